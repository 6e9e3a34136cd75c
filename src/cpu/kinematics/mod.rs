//! Kinematic pass: the correction matrix, the colour gradient, the velocity
//! gradient, continuity and the deviatoric stress rate in one walk over the
//! neighbours (docs/method.md §5, §6, §8.1); the EOS and the stress the momentum
//! pass reads; then the boundary set and area.

use glam::DVec2;
use rayon::prelude::*;
use std::borrow::Cow;

use super::neighbours::Neighbours;
use crate::math::{Mat2, Mirror, Sym};
use crate::model::{Model, State};
use crate::physics::kernel;
use crate::physics::{material, strength, tension};
use crate::scene::Correction;

/// Output of the kinematic pass.
#[derive(Debug, Clone, Default)]
pub struct Kinematics {
    /// Correction matrix `L_i` (docs/method.md §5); identity without correction.
    pub l: Vec<Mat2>,
    /// Particles whose `M_i` could not be inverted and fell back to `L = I`.
    pub fallback: Vec<u32>,
    /// Colour gradient `(∇ψ)_i = −Σ_j V_j ∇_i W_ij` (docs/method.md §8.1, eq. 26).
    pub grad_psi: Vec<DVec2>,
    /// Surface particles, [`surface_measure`] above the boundary threshold
    /// (docs/method.md §8.1): the contact's boundary set, and where the
    /// viscosity keeps the plain velocity jump.
    pub surface: Vec<bool>,
    /// The colour function `ψ_i = Σ_j V_j W_ij`, i included, in a body of
    /// revolution ([`surface_measure`]); empty in plane strain.
    pub psi: Vec<f64>,
    /// Corrected velocity gradient `∇v_i` (zero on rigid particles) of the
    /// velocities the viscosity sees (the state's, or the leapfrog's
    /// predicted ones, [`super::sweep::kinematics_seen`]), kept only when the viscosity
    /// reconstructs velocities with it (`Model::av_reconstruct`) or the
    /// hourglass control is on (`Model::hourglass`); empty otherwise.
    /// Where the correction falls back and the hourglass control is on,
    /// the least-squares fit instead (`kernel::fit_inverse`).
    pub gv: Vec<Mat2>,
    /// The velocities the hourglass control sees and their gradient (the
    /// least-squares fit where the correction falls back), when they are
    /// not those of [`Kinematics::gv`]: in the leapfrog's step the state's
    /// `v_{n+½}` of the kinematic walk, where the viscosity sees the
    /// predicted velocities (docs/method.md, "Hourglass control"). Empty
    /// otherwise: the control then sees the state's velocities and `gv`.
    pub hv: Vec<DVec2>,
    pub hgrad: Vec<Mat2>,
    /// The state's velocity gradient, where supports adapt (they are
    /// carried with it, [`super::advance::carry_supports`]); empty
    /// otherwise.
    pub lv: Vec<Mat2>,
    /// The state's corrected velocity gradient (zero on rigid particles)
    /// when the dispersion correction is on ([`super::dispersion`]);
    /// empty otherwise.
    pub g: Vec<Mat2>,
    /// Continuity `dρ/dt = −ρ tr(∇v)` (the difference form of docs/method.md §4
    /// with the corrected gradient).
    pub drho: Vec<f64>,
    /// Deviatoric stress rate ([`stress_rate`]).
    pub ds: Vec<Sym>,
    /// Equivalent strain rate ([`strength::equivalent_strain_rate`]) when a
    /// material's laws depend on it (`Model::strain_rate`); empty otherwise.
    pub rate: Vec<f64>,
}

/// One particle's sums of the kinematic walk; `S` the sum of the velocity
/// gradient the viscosity sees, when it sees other velocities than the
/// state's ([`Seen`]).
#[derive(Debug, Clone, Copy, Default)]
pub(in crate::cpu) struct Sums<S> {
    /// `M_i = Σ_j V_j ∇_i W_ij ⊗ (x_j − x_i)`.
    pub(in crate::cpu) m: Mat2,
    /// `Σ_j V_j (v_j − v_i) ⊗ ∇_i W_ij`.
    pub(in crate::cpu) gsum: Mat2,
    /// `(∇ψ)_i`.
    pub(in crate::cpu) gpsi: DVec2,
    /// `Σ_j V_j W_ij` over the colour gradient's pairs, the particle itself
    /// left out (bodies of revolution only: [`surface_measure`]).
    pub(in crate::cpu) psi: f64,
    pub(in crate::cpu) seen: S,
    /// Same-body partners in the gradient sums, images included (the
    /// debris floor, [`Model::debris_neighbours`]).
    pub(in crate::cpu) n: u32,
}

impl<S> Sums<S> {
    /// Adds neighbour j's colour terms, of kernel gradient `gw` (`∇_i W`)
    /// and value `w`, volume `vol`: `∇ψ` always, `ψ` in a body of
    /// revolution (`axi`) only.
    #[inline]
    pub(in crate::cpu) fn add_colour(&mut self, gw: DVec2, w: f64, vol: f64, axi: bool) {
        self.gpsi -= gw * vol;
        if axi {
            self.psi += w * vol;
        }
    }
}

/// The kinematic walk's velocities and sum for the velocity gradient of the
/// velocities the viscosity sees: none (`()`, they are the state's; the
/// walk reads the state's velocities `v`), or (`Mat2`) `Σ_j V_j (v*_j −
/// v*_i) ⊗ ∇_i W_ij`, the walk reading `[v, v*]` of a particle together.
pub(in crate::cpu) trait Seen: Copy + Default + Send + Sync {
    /// Whether [`Seen::sum`] gives a gradient.
    const SEES: bool;
    type Vel: Copy + Send + Sync;
    /// Each particle's velocities for the walk, from the state's `v` and
    /// the `seen` ones.
    fn vel<'a>(v: &'a [DVec2], seen: &[DVec2]) -> Cow<'a, [Self::Vel]>;
    fn v(vel: Self::Vel) -> DVec2;
    /// The velocities of a particle's mirror image across `m`.
    fn mirror(vel: Self::Vel, m: &Mirror) -> Self::Vel;
    fn add(&mut self, vj: Self::Vel, vi: Self::Vel, g: DVec2);
    fn sum(self) -> Option<Mat2>;
}

impl Seen for () {
    const SEES: bool = false;
    type Vel = DVec2;
    fn vel<'a>(v: &'a [DVec2], _: &[DVec2]) -> Cow<'a, [DVec2]> {
        Cow::Borrowed(v)
    }
    #[inline]
    fn v(vel: DVec2) -> DVec2 {
        vel
    }
    #[inline]
    fn mirror(vel: DVec2, m: &Mirror) -> DVec2 {
        m.vector(vel)
    }
    #[inline]
    fn add(&mut self, _: DVec2, _: DVec2, _: DVec2) {}
    fn sum(self) -> Option<Mat2> {
        None
    }
}

impl Seen for Mat2 {
    const SEES: bool = true;
    type Vel = [DVec2; 2];
    fn vel<'a>(v: &'a [DVec2], seen: &[DVec2]) -> Cow<'a, [[DVec2; 2]]> {
        Cow::Owned(v.par_iter().zip(seen).map(|(&v, &s)| [v, s]).collect())
    }
    #[inline]
    fn v(vel: [DVec2; 2]) -> DVec2 {
        vel[0]
    }
    #[inline]
    fn mirror(vel: [DVec2; 2], m: &Mirror) -> [DVec2; 2] {
        vel.map(|v| m.vector(v))
    }
    #[inline]
    fn add(&mut self, vj: [DVec2; 2], vi: [DVec2; 2], g: DVec2) {
        *self += Mat2::outer(vj[1] - vi[1], g);
    }
    fn sum(self) -> Option<Mat2> {
        Some(self)
    }
}

impl Kinematics {
    /// Whether each particle is debris ([`debris_point`]): on the
    /// fallback list and not rigid; empty when none is.
    pub fn debris_flags(&self, model: &Model) -> Vec<bool> {
        let mut flags = Vec::new();
        if let Some(&last) = self.fallback.iter().max() {
            flags.resize(last as usize + 1, false);
            for &i in &self.fallback {
                flags[i as usize] = !model.rigid(i as usize);
            }
        }
        flags
    }
}

/// The kinematic pass at `st`.
///
/// `L_i = [Σ_j V_j ∇_i W_ij ⊗ (x_j − x_i)]⁻¹`, `(∇ψ)_i`, and the velocity
/// gradient `∇v_i = Σ_j V_j (v_j − v_i) ⊗ ∇̃_i W_ij` with `∇̃ = L_i ∇`.
/// Because `L_i` is particle i's own, `∇v_i = [Σ_j V_j (v_j − v_i) ⊗
/// ∇_i W_ij] L_iᵀ`: the uncorrected sum is gathered in the same walk as
/// `M_i` and corrected once at the end, so one pass over the neighbours
/// serves what would otherwise take two.
///
///
/// Each particle's sums are gathered over its own neighbours, as the
/// shader does; the solver runs the same sums pair by pair
/// ([`super::sweep::kinematics()`], equal to round-off).
pub fn kinematics(model: &Model, st: &State, nb: &Neighbours) -> Kinematics {
    let vol = volumes(model, st);
    let mut sums: Vec<Sums<()>> = (0..model.len())
        .map(|i| {
            let mut sum = Sums::<()>::default();
            for b in nb.of(model, st.frame(), i) {
                let j = b.j as usize;
                let gm = b.gw * gradient_weight(model, st, &vol, i, j);
                sum.m += Mat2::outer(gm, st.x[j] - st.x[i]);
                sum.gsum += Mat2::outer(st.v[j] - st.v[i], gm);
                sum.add_colour(b.gw, b.w, vol[j], model.axisymmetric);
                sum.n += u32::from(b.q2 > 0.0);
            }
            // The mirror images across the axis of a body of revolution
            // or a symmetry plane (none without), as more neighbours;
            // `round_colour` redoes the colour where supports adapt.
            for (b, _, m) in nb.images_of(model, st.frame(), i) {
                let j = b.j as usize;
                let gm = b.gw * gradient_weight(model, st, &vol, i, j);
                sum.m += Mat2::outer(gm, m.point(st.x[j]) - st.x[i]);
                sum.gsum += Mat2::outer(m.vector(st.v[j]) - st.v[i], gm);
                sum.add_colour(b.gw, b.w, vol[j], model.axisymmetric);
                sum.n += u32::from(b.q2 > 0.0);
            }
            sum
        })
        .collect();
    round_colour(model, st, nb, &vol, &mut sums);
    finish(model, st, sums)
}

/// Where supports adapt, each particle's colour gradient with the round
/// supports of the bodies' `h` instead of its own, images included: the
/// surface set it decides is then a function of the positions alone, as
/// the contact's normals are, and does not switch as the supports turn
/// (docs/method.md, "Supports that follow the deformation"). Nothing with
/// round supports.
pub(in crate::cpu) fn round_colour<S: Seen>(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    vol: &[f64],
    sums: &mut [Sums<S>],
) {
    if st.round_supports() {
        return;
    }
    sums.par_iter_mut().enumerate().for_each(|(i, sum)| {
        (sum.gpsi, sum.psi) = (DVec2::ZERO, 0.0);
        for (b, _) in nb.round_with_images(model, &st.x, i) {
            sum.add_colour(b.gw, b.w, vol[b.j as usize], model.axisymmetric);
        }
    });
}

/// Neighbour j's weight in particle i's gradient sums (`M_i`, `∇v_i`):
/// its volume `vol[j]`, in a body of revolution its mass over `η_i`
/// (docs/method.md §12; the colour gradient keeps the volumes).
#[inline]
pub(in crate::cpu) fn gradient_weight(
    model: &Model,
    st: &State,
    vol: &[f64],
    i: usize,
    j: usize,
) -> f64 {
    if model.axisymmetric {
        model.mass[j] / st.rho[i]
    } else {
        vol[j]
    }
}

/// What the boundary threshold is held against (docs/method.md §8.1):
/// `h |∇ψ|`, in a body of revolution `h |∇ψ| / ψ` with `ψ` the colour
/// function itself ([`Kinematics::psi`]). The areas `m/(2π r ρ)` of the
/// particles nearest the axis do not tile the r–z plane once it spreads
/// (ψ from 0.4 to 1.5 in a Taylor bar's face): unnormalised, the face's
/// axis particle left the surface set while pressed on a wall, and
/// interior particles by the axis joined it.
#[inline]
pub fn surface_measure(model: &Model, i: usize, gpsi: DVec2, psi: Option<f64>) -> f64 {
    model.h[i] * gpsi.length() / psi.unwrap_or(1.0)
}

/// Each particle's volume `V_j = m_j / ρ_j`.
pub(in crate::cpu) fn volumes(model: &Model, st: &State) -> Vec<f64> {
    (0..model.len())
        .into_par_iter()
        .map(|j| model.mass[j] / st.rho[j])
        .collect()
}

/// The kinematic pass's results from each particle's sums: `L_i`, `∇v_i`,
/// continuity, the stress rate, the surface set.
pub(in crate::cpu) fn finish<S: Seen>(model: &Model, st: &State, sums: Vec<Sums<S>>) -> Kinematics {
    let n = sums.len();
    let hg = model.hourglass > 0.0 && S::SEES;
    let mut out = Kinematics::sized(model, n, hg);
    // Each particle's results go straight to their arrays, a run of
    // particles a task; the fallback lists join in order.
    let mut runs = Vec::with_capacity(n.div_ceil(FINISH_RUN));
    let (mut rest, mut base) = (out.rows(), 0);
    while base < n {
        let (run, tail) = rest.split_at(FINISH_RUN.min(n - base));
        runs.push((base, run));
        (rest, base) = (tail, base + FINISH_RUN);
    }
    let fallback: Vec<Vec<u32>> = runs
        .into_par_iter()
        .map(|(base, mut run)| {
            let mut fallback = Vec::new();
            for (r, sums) in sums[base..base + run.l.len()].iter().enumerate() {
                let i = base + r;
                let p = point_of_sums(model, st, i, *sums);
                if !run.put(model, st, (r, i), p) {
                    fallback.push(i as u32);
                }
            }
            fallback
        })
        .collect();
    out.fallback = fallback.concat();
    if hg {
        out.hv.clone_from(&st.v);
    }
    out
}

/// Particles a task of [`finish`].
const FINISH_RUN: usize = 4096;

/// Particle i's [`Point`] from its sums: `L_i` (or the fallback), the
/// velocity gradients, the hourglass control's fit, the colour function.
fn point_of_sums<S: Seen>(model: &Model, st: &State, i: usize, sums: Sums<S>) -> Point {
    let corrected = model.correction == Correction::Gradient;
    let Sums {
        mut m,
        gsum,
        gpsi,
        psi,
        seen,
        n,
    } = sums;
    let (l, ok) = if !corrected {
        (Mat2::IDENTITY, true)
    } else {
        if model.dim == 1 {
            // 1-D: L is the scalar 1/M_xx; keep the unused yy entry neutral.
            m.yy = 1.0;
        }
        // Too few neighbours is debris however well M looks: a
        // compact cluster of a few particles passes the
        // conditioning test (docs/method.md, "Debris").
        match kernel::correction_inverse(&m) {
            Some(l) if n >= model.bodies[model.body[i] as usize].debris_neighbours => (l, true),
            _ => (Mat2::IDENTITY, false),
        }
    };
    let (gv, gv_seen) = if model.rigid(i) {
        (Mat2::ZERO, seen.sum().map(|_| Mat2::ZERO))
    } else {
        (
            gsum.mul_transpose(&l),
            seen.sum().map(|g| g.mul_transpose(&l)),
        )
    };
    // Where the correction falls back, the hourglass control
    // still needs the least-squares fit (kernel::fit_inverse).
    // It sees the state's velocities; with others seen (the
    // leapfrog) the viscosity keeps their plain gradient.
    let hg = model.hourglass > 0.0;
    let fit_of =
        |g: Mat2| (!ok && !model.rigid(i)).then(|| g.mul_transpose(&kernel::fit_inverse(&m)));
    let (fit, hgrad) = match seen.sum() {
        Some(_) if hg => (None, Some(fit_of(gsum).unwrap_or(gv))),
        None if hg => (fit_of(gsum), None),
        _ => (None, None),
    };
    Point {
        l,
        ok,
        psi: model
            .axisymmetric
            .then(|| psi + model.mass[i] / st.rho[i] * kernel::w(2, 0.0, model.h[i])),
        gpsi,
        gv,
        gv_seen,
        fit,
        hgrad,
    }
}

impl Kinematics {
    /// Every array the scene keeps at `n` particles (the hourglass
    /// control's own gradient where `hgrad`), to be filled by [`Rows::put`].
    fn sized(model: &Model, n: usize, hgrad: bool) -> Kinematics {
        let keep = |on: bool| if on { n } else { 0 };
        Kinematics {
            l: vec![Mat2::ZERO; n],
            fallback: Vec::new(),
            grad_psi: vec![DVec2::ZERO; n],
            surface: vec![false; n],
            psi: vec![0.0; keep(model.axisymmetric)],
            gv: vec![Mat2::ZERO; keep(model.keeps_gradient())],
            hv: Vec::new(),
            hgrad: vec![Mat2::ZERO; keep(hgrad)],
            lv: vec![Mat2::ZERO; keep(model.adaptive)],
            g: vec![Mat2::ZERO; keep(model.dispersion > 0.0)],
            drho: vec![0.0; n],
            ds: vec![Sym::default(); n],
            rate: vec![0.0; keep(model.strain_rate)],
        }
    }

    /// The per-particle arrays as one [`Rows`].
    fn rows(&mut self) -> Rows<'_> {
        Rows {
            l: &mut self.l,
            grad_psi: &mut self.grad_psi,
            surface: &mut self.surface,
            psi: &mut self.psi,
            gv: &mut self.gv,
            hgrad: &mut self.hgrad,
            lv: &mut self.lv,
            g: &mut self.g,
            drho: &mut self.drho,
            ds: &mut self.ds,
            rate: &mut self.rate,
        }
    }
}

/// A run of particles' slots in [`Kinematics`]' per-particle arrays; an
/// array the scene does not keep is empty in every run.
struct Rows<'a> {
    l: &'a mut [Mat2],
    grad_psi: &'a mut [DVec2],
    surface: &'a mut [bool],
    psi: &'a mut [f64],
    gv: &'a mut [Mat2],
    hgrad: &'a mut [Mat2],
    lv: &'a mut [Mat2],
    g: &'a mut [Mat2],
    drho: &'a mut [f64],
    ds: &'a mut [Sym],
    rate: &'a mut [f64],
}

/// `s` cut at `k`, or two empty slices where `s` is empty.
fn cut<T>(s: &mut [T], k: usize) -> (&mut [T], &mut [T]) {
    if s.is_empty() {
        (&mut [], &mut [])
    } else {
        s.split_at_mut(k)
    }
}

impl<'a> Rows<'a> {
    /// The first `k` particles' slots and the rest's.
    fn split_at(self, k: usize) -> (Rows<'a>, Rows<'a>) {
        let (l, l2) = self.l.split_at_mut(k);
        let (grad_psi, grad_psi2) = self.grad_psi.split_at_mut(k);
        let (surface, surface2) = self.surface.split_at_mut(k);
        let (psi, psi2) = cut(self.psi, k);
        let (gv, gv2) = cut(self.gv, k);
        let (hgrad, hgrad2) = cut(self.hgrad, k);
        let (lv, lv2) = cut(self.lv, k);
        let (g, g2) = cut(self.g, k);
        let (drho, drho2) = self.drho.split_at_mut(k);
        let (ds, ds2) = self.ds.split_at_mut(k);
        let (rate, rate2) = cut(self.rate, k);
        (
            Rows {
                l,
                grad_psi,
                surface,
                psi,
                gv,
                hgrad,
                lv,
                g,
                drho,
                ds,
                rate,
            },
            Rows {
                l: l2,
                grad_psi: grad_psi2,
                surface: surface2,
                psi: psi2,
                gv: gv2,
                hgrad: hgrad2,
                lv: lv2,
                g: g2,
                drho: drho2,
                ds: ds2,
                rate: rate2,
            },
        )
    }

    /// Particle i's results from its point `p` into slot `r`: the surface
    /// test, the continuity and stress rates, the gradients kept. Returns
    /// whether its correction held (`p.ok`).
    fn put(&mut self, model: &Model, st: &State, (r, i): (usize, usize), p: Point) -> bool {
        self.l[r] = p.l;
        self.surface[r] = surface_measure(model, i, p.gpsi, p.psi) > model.boundary_threshold;
        if let Some(psi) = p.psi {
            self.psi[r] = psi;
        }
        self.grad_psi[r] = p.gpsi;
        if !model.rigid(i) {
            // η = 2π r ρ obeys the plane's continuity equation: the hoop
            // strain rate is in ρ alone (docs/method.md §12).
            self.drho[r] = -st.rho[i] * p.gv.trace();
            // Debris keeps its deviatoric stress, frozen (docs/method.md,
            // "Debris").
            let g = if p.ok { model.material(i).g } else { 0.0 };
            let ds = stress_rate(g, &st.s[i], &p.gv);
            self.ds[r] = if model.axisymmetric {
                with_hoop(g, ds, hoop_rate(st, i))
            } else {
                ds
            };
        }
        if !self.gv.is_empty() {
            self.gv[r] = p.fit.or(p.gv_seen).unwrap_or(p.gv);
        }
        if let Some(g) = p.hgrad {
            self.hgrad[r] = g;
        }
        if !self.lv.is_empty() {
            self.lv[r] = p.gv;
        }
        if !self.g.is_empty() {
            self.g[r] = p.gv;
        }
        if !self.rate.is_empty() {
            self.rate[r] = if model.axisymmetric && !model.rigid(i) {
                strength::equivalent_strain_rate_3(&p.gv, hoop_rate(st, i))
            } else {
                strength::equivalent_strain_rate(&p.gv)
            };
        }
        p.ok
    }
}

/// One particle's result of the kinematic pass.
struct Point {
    l: Mat2,
    ok: bool,
    /// The colour function, i included, in a body of revolution.
    psi: Option<f64>,
    gpsi: DVec2,
    gv: Mat2,
    /// `∇v` of the velocities the viscosity sees, when not the state's.
    gv_seen: Option<Mat2>,
    /// The least-squares `∇v` (of the seen velocities) where the
    /// correction fell back and the hourglass control is on.
    fit: Option<Mat2>,
    /// The hourglass control's `∇v` of the state's velocities, where the
    /// viscosity sees others (the leapfrog).
    hgrad: Option<Mat2>,
}

/// The [`StressPoint`] of pressure `p`, sound speed `c` and deviatoric
/// stress `s` at `η`, `x` and density `rho`, with its artificial stress if
/// `art`.
#[inline]
fn point_of(
    model: &Model,
    art: bool,
    (eta, x): (f64, DVec2),
    rho: f64,
    (p, c): (f64, f64),
    s: &Sym,
) -> StressPoint {
    let sigma = material::cauchy(p, s);
    let r = match model.artificial_stress.filter(|_| art) {
        Some(a) if model.axisymmetric => {
            tension::artificial_stress(a.epsilon, &sigma, rho).scale(rho / eta)
        }
        Some(a) => tension::artificial_stress(a.epsilon, &sigma, rho),
        None => Sym::default(),
    };
    StressPoint {
        sr2: sigma.scale(1.0 / (eta * rho)),
        r,
        c,
        hoop: if model.axisymmetric {
            sigma.zz / (x.x * rho)
        } else {
            0.0
        },
    }
}

mod stress;

pub use stress::*;
