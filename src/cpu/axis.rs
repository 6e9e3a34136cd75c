//! Bodies of revolution on the CPU (docs/method.md §12): the axis as a
//! mirror, the stress point of a ring, and the hoop terms.
//!
//! The kernel sums run in the r–z plane with each particle's area
//! `V = m / η` (`η = 2π r ρ`, [`crate::model::State::rho`]). Near the axis
//! a particle's support reaches across it; what lies there is the mirror
//! image of the body, `(r, z) → (−r, z)`, with the radial velocity and the
//! `rz` shear reversed. Each particle within reach of the axis adds the
//! terms of the mirror images of its neighbours (and of itself) to its
//! sums, so the axis is neither a free surface nor a hole in the kernel's
//! support, and no particle sits on it.

use glam::DVec2;
use rayon::prelude::*;
use std::f64::consts::PI;

use super::forces::{pair_terms_of, Side, StressPoint};
use super::kinematics::{Seen, Sums};
use super::neighbours::{pair_inv_h, Nbr, Neighbours};
use super::sweep::forces::pair_vectors;
use crate::math::{Mat2, Sym};
use crate::model::{Model, State};
use crate::physics::{kernel, material, tension};

/// The mirror image of a point or a velocity: `(r, z) → (−r, z)`.
#[inline]
pub fn mirror(x: DVec2) -> DVec2 {
    DVec2::new(-x.x, x.y)
}

/// The mirror image of a tensor `T`: `P T P` with `P = diag(−1, 1)`.
#[inline]
pub fn mirror_mat(m: &Mat2) -> Mat2 {
    Mat2 {
        xx: m.xx,
        xy: -m.xy,
        yx: -m.yx,
        yy: m.yy,
    }
}

/// The mirror image of a symmetric tensor (the `rz` entry reversed).
#[inline]
pub fn mirror_sym(s: &Sym) -> Sym {
    Sym { xy: -s.xy, ..*s }
}

/// Every particle's mirror partners: for each particle `i` within reach of
/// the axis, the particles `j` (itself included) whose image `x̄_j` lies
/// within `2 h_ij` of it, with `W` and `∇_i W` at `x_i − x̄_j`.
#[derive(Debug, Clone, Default)]
pub struct Mirrors {
    /// `(i, partners)`, in ascending `i`.
    pub rows: Vec<(u32, Vec<Nbr>)>,
}

impl Mirrors {
    /// The mirror partners at positions `x`. An image is never nearer than
    /// its particle (`|x_i − x̄_j| ≥ |x_i − x_j|` for `r_i, r_j ≥ 0`), so
    /// they are found among the candidate lists `nb`.
    pub fn find(model: &Model, x: &[DVec2], nb: &Neighbours) -> Mirrors {
        let h_max = model.h.iter().cloned().fold(0.0, f64::max);
        let rows = (0..model.len() as u32)
            .into_par_iter()
            .filter(|&i| x[i as usize].x < model.h[i as usize] + h_max)
            .map(|i| {
                let iu = i as usize;
                let inv_hi = 1.0 / model.h[iu];
                let list =
                    std::iter::once(i)
                        .chain(nb.candidates(iu).iter().copied())
                        .filter_map(|j| {
                            let inv_h = pair_inv_h(model.h[iu], model.h[j as usize], inv_hi);
                            let d = x[iu] - mirror(x[j as usize]);
                            kernel::w_grad(model.dim, d, d.length_squared(), inv_h)
                                .map(|(w, gw)| Nbr { j, w, gw })
                        })
                        .collect();
                (i, list)
            })
            .collect();
        Mirrors { rows }
    }

    /// Particle i's mirror partners, if it is within reach of the axis.
    pub fn of(&self, i: usize) -> Option<&[Nbr]> {
        self.rows
            .binary_search_by_key(&(i as u32), |r| r.0)
            .ok()
            .map(|k| &self.rows[k].1[..])
    }
}

/// Particle i's [`StressPoint`] in a body of revolution at `η` (its
/// [`State::rho`]) and position `x`: the EOS at the density `ρ = η / 2π r`,
/// `σ/(η ρ)` in the momentum sums (the divergence of `2π r σ` per unit
/// `η`), the artificial stress in the same measure, and the hoop
/// acceleration `σ_θθ / (r ρ)`.
pub(super) fn stress_point(
    model: &Model,
    i: usize,
    eta: f64,
    x: DVec2,
    e: f64,
    s: &Sym,
    damage: f64,
) -> StressPoint {
    let mat = model.material(i);
    let rho = eta / (2.0 * PI * x.x);
    let p = mat.pressure_of(rho, e, damage);
    let c = mat.sound_speed_of(rho, e, damage);
    let sigma = material::cauchy(p, s);
    let r = match model.artificial_stress {
        Some(a) => tension::artificial_stress(a.epsilon, &sigma, rho).scale(rho / eta),
        None => Sym::default(),
    };
    StressPoint {
        sr2: sigma.scale(1.0 / (eta * rho)),
        r,
        c,
        hoop: sigma.zz / (x.x * rho),
    }
}

/// What the mirror partners give each particle within reach of the axis:
/// `(i, Σ m_j t G, [(j, X_i)])`, `X_i` the pair's energy vector of i's
/// side ([`crate::cpu::sweep::PairVectors`]), so that its energy rate at
/// velocities `w` is `−Σ m_j (w_i − w̄_j)·X_i`.
type MirrorTerms = Vec<(usize, DVec2, Vec<(usize, DVec2)>)>;

/// The mirror partners' momentum terms and energy vectors at `st`.
#[allow(clippy::too_many_arguments)]
fn mirror_terms(
    model: &Model,
    st: &State,
    mirrors: &Mirrors,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
) -> MirrorTerms {
    let side = |k| Side::of(st, l, gv, pts, k);
    let image = |k: usize| {
        let s = side(k);
        Side {
            x: mirror(s.x),
            v: mirror(s.v),
            l: mirror_mat(&s.l),
            gv: mirror_mat(&s.gv),
            pt: StressPoint {
                sr2: mirror_sym(&s.pt.sr2),
                r: mirror_sym(&s.pt.r),
                ..s.pt
            },
        }
    };
    mirrors
        .rows
        .par_iter()
        .filter(|(i, _)| !model.rigid(*i as usize))
        .map(|(i, list)| {
            let i = *i as usize;
            let a = side(i);
            let mut dv = DVec2::ZERO;
            let xs = list
                .iter()
                .map(|b| {
                    let j = b.j as usize;
                    let im = image(j);
                    let p = pair_terms_of(model, st, surface, (i, &a), (j, &im), b.gw);
                    dv += p.tg * model.mass[j];
                    let x = pair_vectors(p.tg, a.pt.sr2.mul_vec(p.g), im.pt.sr2.mul_vec(p.g));
                    (j, x[0])
                })
                .collect();
            (i, dv, xs)
        })
        .collect()
}

/// The mirror partners' energy vectors, kept by [`add_momentum`] for the
/// energy rates at the velocities the leapfrog books its work at.
pub(super) struct KeptMirrors(MirrorTerms);

/// Adds the mirror partners' and the hoop's accelerations to `dv` and
/// keeps what their energy rates need ([`KeptMirrors::add_energy`]): the
/// hoop acceleration `−σ_θθ / (r ρ)` along r, whose work the hoop heat
/// `σ_θθ v_r / (r ρ)` books, so that they exchange no energy with the
/// total.
#[allow(clippy::too_many_arguments)]
pub(super) fn add_momentum(
    model: &Model,
    st: &State,
    mirrors: &Mirrors,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
    dv: &mut [DVec2],
) -> KeptMirrors {
    let terms = mirror_terms(model, st, mirrors, l, gv, surface, pts);
    for (i, dvi, _) in &terms {
        dv[*i] += *dvi;
    }
    dv.par_iter_mut().enumerate().for_each(|(i, dv)| {
        if !model.rigid(i) {
            dv.x -= pts[i].hoop;
        }
    });
    KeptMirrors(terms)
}

impl KeptMirrors {
    /// Adds the mirror partners' and the hoop's energy rates at the
    /// velocities `w` to `de`.
    pub(super) fn add_energy(
        &self,
        model: &Model,
        pts: &[StressPoint],
        w: &[DVec2],
        de: &mut [f64],
    ) {
        for (i, _, xs) in &self.0 {
            let mut sum = 0.0;
            for &(j, x) in xs {
                sum -= model.mass[j] * (w[*i] - mirror(w[j])).dot(x);
            }
            de[*i] += sum;
        }
        de.par_iter_mut().enumerate().for_each(|(i, de)| {
            if !model.rigid(i) {
                *de += pts[i].hoop * w[i].x;
            }
        });
    }
}

/// The hoop rate of strain `v_r / r` of particle i.
#[inline]
pub fn hoop_rate(st: &State, i: usize) -> f64 {
    st.v[i].x / st.x[i].x
}

/// The deviatoric stress rate with the hoop strain rate `d_θθ` added to
/// the plane's ([`super::kinematics::stress_rate`] with `d_θθ = 0`): the
/// trace takes it, and `s_θθ` (kept as `zz`) follows it.
#[inline]
pub fn with_hoop(g_mod: f64, ds: Sym, d_tt: f64) -> Sym {
    let third = d_tt / 3.0;
    Sym {
        xx: ds.xx - 2.0 * g_mod * third,
        yy: ds.yy - 2.0 * g_mod * third,
        xy: ds.xy,
        zz: ds.zz + 4.0 * g_mod * third,
    }
}

/// Adds the mirror partners' terms to each particle's kinematic sums
/// ([`super::kinematics::Sums`]): the images' masses, offsets and
/// velocities (`vel`, as the walk reads them), and their areas `vol` in
/// the colour gradient.
pub(super) fn add_kinematics<S: Seen>(
    model: &Model,
    st: &State,
    mirrors: &Mirrors,
    vol: &[f64],
    vel: &[S::Vel],
    sums: &mut [Sums<S>],
) {
    for (i, list) in &mirrors.rows {
        let i = *i as usize;
        let sum = &mut sums[i];
        for b in list {
            let j = b.j as usize;
            let vj = S::mirror(vel[j]);
            let gi = b.gw * (model.mass[j] / st.rho[i]);
            sum.m += Mat2::outer(gi, mirror(st.x[j]) - st.x[i]);
            sum.gsum += Mat2::outer(S::v(vj) - S::v(vel[i]), gi);
            sum.gpsi -= b.gw * vol[j];
            sum.seen.add(vj, vel[i], gi);
        }
    }
}
