//! The forces pass: momentum and energy sums (docs/method.md §4) with Monaghan artificial
//! viscosity and, when the scene asks for it, Gray–Monaghan–Swift artificial
//! stress. The stress terms are the variation of the particles' stress
//! power (each its own corrected gradient `L_i ∇_i W_ij`) or the paper's
//! on `G_ij = ½ (L_i + L_j) ∇_i W_ij`, the artificial terms on `G_ij`:
//! both conserve momentum and energy exactly in semi-discrete form.

mod boundary;
#[cfg(test)]
mod tests;

pub use boundary::*;

use glam::DVec2;

use super::kinematics::{Kinematics, StressPoint};
use super::neighbours::{Nbr, Neighbours};
use crate::math::{Mat2, Mirror, Sym};
use crate::model::{Model, State};
use crate::physics::strength;
use crate::scene::ArtPairs;

use crate::physics::tension::{art_weight, close_gate, heat_share, HEAT_SPEED};
use crate::physics::viscosity::{reconstructed_jump, viscosity_pi};

/// What a pair contributes to both of its particles' momentum and energy
/// sums, from particle i's side.
pub(in crate::cpu) struct PairTerms {
    /// The pair's force per unit `m_i m_j`: `S_i + S_j + t G_ij`, `t =
    /// −Π_ij I (+ artificial stress)` (and the hourglass control's terms).
    pub(in crate::cpu) tg: DVec2,
    /// Each side's stress vector `[S_i, S_j]`, whose work `−m_j v_ij·S_i`
    /// is i's stress power in the pair: variational, `S_i = σ_i/(ρ_i ρ_j)
    /// L_i ∇_i W_ij` (in a body of revolution `σ_i/(η_i ρ_i) L_i ∇_i
    /// W_ij`); the paper's form, `S_i = σ_i/ρ_i² G_ij`.
    pub(in crate::cpu) s: [DVec2; 2],
    /// `v_ij = v_i − v_j`.
    pub(in crate::cpu) vij: DVec2,
    /// `½ Π_ij v_ij·G_ij − ½ (R_i + R_j) f^n : (v_ij ⊗ G_ij)`, the part of
    /// either particle's energy term that is the pair's own.
    pub(in crate::cpu) shared: f64,
    /// `½ ((R_i + R_j) f^n − Π_ij I) G_ij`: the artificial terms' part of
    /// either side's energy vector, whose work `−m_j v_ij·(a + X_i)` (with
    /// the hourglass control's `X_i`) is the pair's artificial
    /// dissipation booked to i (docs/method.md, "The energy ledger").
    pub(in crate::cpu) a: DVec2,
    /// The hourglass control's terms per unit of both masses: `[X_i, X_j]`,
    /// its force on i being `m_i m_j (X_i + X_j)` (in `tg`) and its heat
    /// `−m_j v_ij·X_i` on i and `−m_i v_ij·X_j` on j; zero when off.
    pub(in crate::cpu) hg: [DVec2; 2],
}

/// The momentum and energy terms of the pair `(i, b.j)`.
///
/// Swapping the particles flips `G`, `v_ij`, `x_ij` and the reconstructed
/// jump and keeps `Π_ij`, `t` and `f`, so particle j's terms are
/// `dv_j −= m_i t G_ij` and `de_j −= m_i (v_ij·(σ_j/ρ_j² G_ij) − shared)`:
/// one evaluation of a pair serves both of its particles.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(in crate::cpu) fn pair_terms(
    model: &Model,
    st: &State,
    kin: &Kinematics,
    pts: &[StressPoint],
    i: usize,
    b: &Nbr,
) -> PairTerms {
    let j = b.j as usize;
    let side = |k| Side::of(st, kin, pts, k);
    pair_terms_of(model, st, &kin.surface, (i, &side(i)), (j, &side(j)), b)
}

/// What a pair's terms read of one of its particles that its mirror
/// image across the axis of a body of revolution has otherwise
/// ([`super::axis`]); the rest is read by index.
#[derive(Debug, Clone, Copy)]
pub(in crate::cpu) struct Side {
    pub(in crate::cpu) x: DVec2,
    pub(in crate::cpu) v: DVec2,
    pub(in crate::cpu) l: Mat2,
    /// `∇v`, read only when the viscosity is reconstructed.
    pub(in crate::cpu) gv: Mat2,
    /// The velocity and `∇v` the hourglass control sees
    /// ([`Kinematics::hv`]).
    pub(in crate::cpu) vh: DVec2,
    pub(in crate::cpu) gh: Mat2,
    pub(in crate::cpu) pt: StressPoint,
}

impl Side {
    /// Particle k's side at `st`, with its `L`, `∇v` (none kept: zero) and
    /// stress point.
    #[inline]
    pub(in crate::cpu) fn of(st: &State, kin: &Kinematics, pts: &[StressPoint], k: usize) -> Side {
        let gv = kin.gv.get(k).copied().unwrap_or(Mat2::ZERO);
        Side {
            x: st.x[k],
            v: st.v[k],
            l: kin.l[k],
            gv,
            vh: kin.hv.get(k).copied().unwrap_or(st.v[k]),
            gh: kin.hgrad.get(k).copied().unwrap_or(gv),
            pt: pts[k],
        }
    }

    /// The side of this particle's mirror image across `m` (the axis of
    /// a body of revolution, a symmetry plane): its position, velocities
    /// and gradients mirrored, its stress's shear entries reversed.
    #[inline]
    pub(in crate::cpu) fn mirrored(&self, m: &Mirror) -> Side {
        Side {
            x: m.point(self.x),
            v: m.vector(self.v),
            l: m.mat(&self.l),
            gv: m.mat(&self.gv),
            vh: m.vector(self.vh),
            gh: m.mat(&self.gh),
            pt: StressPoint {
                sr2: m.sym(&self.pt.sr2),
                r: m.sym(&self.pt.r),
                ..self.pt
            },
        }
    }
}

/// [`pair_terms`] of particles `(i, a)` and `(j, b)`, each with its
/// [`Side`], and their kernel `nb` (`∇_i W_ij` and `q²` at their
/// positions).
#[inline]
pub(in crate::cpu) fn pair_terms_of(
    model: &Model,
    st: &State,
    surface: &[bool],
    (i, a): (usize, &Side),
    (j, b): (usize, &Side),
    nb: &Nbr,
) -> PairTerms {
    let (pi_, pj) = (&a.pt, &b.pt);
    let gw = nb.gw;
    let h0 = 0.5 * (model.h[i] + model.h[j]);
    let xij = a.x - b.x;
    // The pair's smoothing length along x_ij: h_ij, or where supports
    // adapt `r/q` (docs/method.md, "Supports that follow the
    // deformation").
    let hij = if !st.round_supports() {
        along(xij.length_squared(), nb.q2, h0)
    } else {
        h0
    };
    let vij = a.v - b.v;
    let g = (a.l + b.l).scale(0.5).mul_vec(gw);
    // The viscosity sees the reconstructed jump; the energy equation keeps
    // the true v_ij, so the viscous work is still exactly the heat booked
    // (energy conserved). At a surface only where the scene asks for it:
    // there ∇v is extrapolated from one side, and the face is where a
    // contact loads the body impulsively.
    let vis = if model.av_reconstruct && (model.av_recon_surface || !(surface[i] || surface[j])) {
        reconstructed_jump(vij, xij, &a.gv, &b.gv)
    } else {
        vij
    };
    let pi = viscosity_pi(
        model.alpha,
        model.beta,
        hij,
        xij,
        vis,
        vij,
        0.5 * (pi_.c + pj.c),
        0.5 * (st.rho[i] + st.rho[j]),
        model.av_release,
        bonded(st, i, j),
    );
    // The stress terms (docs/method.md §4): the paper's form keeps them in
    // `t` on G; the variational one gives each side its own gradient.
    let s = if model.variational {
        // V_j / ρ_i against ρ_i²: ρ_i/ρ_j; a body of revolution's
        // gradient weighs j by m_j/η_i, whose ratio is 1.
        let (fi, fj) = if model.axisymmetric {
            (1.0, 1.0)
        } else {
            (st.rho[i] / st.rho[j], st.rho[j] / st.rho[i])
        };
        [
            pi_.sr2.mul_vec(a.l.mul_vec(gw)) * fi,
            pj.sr2.mul_vec(b.l.mul_vec(gw)) * fj,
        ]
    } else {
        [pi_.sr2.mul_vec(g), pj.sr2.mul_vec(g)]
    };
    let mut t = if model.variational {
        Sym::default()
    } else {
        pi_.sr2.add_scaled(&pj.sr2, 1.0)
    };
    t.xx -= pi;
    t.yy -= pi;
    // The artificial stress's work on the pair, half to each particle, is
    // booked as heat: ½ (R_i + R_j) f^n : (v_ij ⊗ G_ij). docs/method.md §4 puts
    // R in the momentum bracket only, which leaves its work in no energy
    // (the rubber rings' total swung by 8 %); booked, the ledger closes as
    // for the viscosity.
    //
    // A pair acts only where one of its particles is in tension, which
    // both codes test alike on the trace of `R_i + R_j` (R is negative
    // semi-definite, so the trace is zero only with R): the lane code
    // skips whole rows of four untouched by tension on that test.
    //
    // It holds intact material together against the tensile instability;
    // a failed particle is bonded to nothing and takes no part in it.
    let mut art_work = 0.0;
    let mut rfg = DVec2::ZERO;
    if let Some(rf) = art_stress(model, st, (i, pi_), (j, pj), nb, (xij, vij, g), (hij, h0)) {
        t = t.add_scaled(&rf, 1.0);
        rfg = rf.mul_vec(g);
        art_work = 0.5 * vij.dot(rfg);
    }
    let hg = if model.hourglass > 0.0 {
        hourglass(model, st, (i, a), (j, b), gw)
    } else {
        [DVec2::ZERO; 2]
    };
    let tg = if model.variational {
        t.mul_vec(g) + (s[0] + s[1])
    } else {
        t.mul_vec(g)
    };
    PairTerms {
        tg: tg + hg[0] + hg[1],
        s,
        vij,
        shared: 0.5 * pi * vij.dot(g) - art_work,
        a: (rfg - g * pi) * 0.5,
        hg,
    }
}

/// Whether neither particle of the pair `(i, j)` has failed or has a void
/// open ([`State::damage_of`]): only then is the pair material, bonded
/// across.
#[inline]
fn bonded(st: &State, i: usize, j: usize) -> bool {
    st.damage.is_empty()
        || !(strength::failed(st.damage_of(i)) || strength::failed(st.damage_of(j)))
}

/// The artificial stress of the pair `(i, j)` (stress points `pi_`,
/// `pj`), scaled by its weight and gate, and to its heat share where its
/// work may only be heat: `None` where neither particle is in tension,
/// the gate is shut, or a failed particle is in the pair (it is bonded to
/// nothing and takes no part in it).
#[inline]
#[allow(clippy::too_many_arguments)]
fn art_stress(
    model: &Model,
    st: &State,
    (i, pi_): (usize, &StressPoint),
    (j, pj): (usize, &StressPoint),
    nb: &Nbr,
    (xij, vij, g): (DVec2, DVec2, DVec2),
    (hij, h0): (f64, f64),
) -> Option<Sym> {
    let a = model.artificial_stress.filter(|_| bonded(st, i, j))?;
    let rs = pi_.r.add_scaled(&pj.r, 1.0);
    let r2 = xij.length_squared();
    let gate = match a.pairs {
        ArtPairs::All => 1.0,
        ArtPairs::Close => {
            // The whole particles' volumes, on a symmetry plane too.
            let vol = 0.5
                * (model.mass[i] / (st.rho[i] * model.share(i))
                    + model.mass[j] / (st.rho[j] * model.share(j)));
            let ks = &model.close_scale;
            let k2 = if ks.is_empty() { 1.0 } else { ks[i].min(ks[j]) };
            if !st.round_supports() {
                // In the pair's metric: its distance q against the
                // spacing its volume has there.
                close_gate(nb.q2, vol * nb.scale, k2, model.dim)
            } else {
                close_gate(r2, vol, k2, model.dim)
            }
        }
    };
    if rs.xx + rs.yy < 0.0 && gate > 0.0 {
        let dp = 0.5 * (model.spacing_of(i) + model.spacing_of(j));
        let w = if !st.round_supports() {
            art_weight(nb.q2, dp / h0, 1.0, a.n)
        } else {
            art_weight(r2, dp, hij, a.n)
        };
        let mut rf = rs.scale(w * gate);
        // Where its work may only be heat (everywhere, in a body that
        // can yield, or at a pair that flows plastically), the share of
        // it that is (docs/method.md, "Only heat").
        if model.art_heats(st, i) || model.art_heats(st, j) {
            let rg = rf.mul_vec(g);
            let scale = HEAT_SPEED * (0.5 * (pi_.c + pj.c)) * rg.length();
            rf = rf.scale(heat_share(vij.dot(rg), scale));
        }
        return Some(rf);
    }
    None
}

/// The hourglass control of a pair (docs/method.md): each particle's
/// neighbourhood resists the part of its neighbours' velocities that its
/// own velocity gradient does not explain. Particle i's family puts
/// `c_ij δ_i` on i and `−c_ij δ_i` on j, with `δ_i = v_j − v_i − ∇v_i x_ji`
/// and `c_ij = α_i m_i c_i h_i V_j w_ij` (`α_i` the coefficient of i's
/// body), `w_ij = ∇_i W_ij·x_ji / r²` the
/// weight the corrected gradient fits `∇v_i` with by least squares. The
/// fit's residuals are orthogonal to every linear field, so the family
/// exerts no net force or torque and its power is `−Σ_j c_ij |δ_i|²`:
/// heat, never negative, booked to i. Returned per unit `m_i m_j`:
/// `[c_ij δ_i, −c_ji δ_j] / (m_i m_j)`.
#[inline]
fn hourglass(
    model: &Model,
    st: &State,
    (i, a): (usize, &Side),
    (j, b): (usize, &Side),
    gw: DVec2,
) -> [DVec2; 2] {
    let xji = b.x - a.x;
    let r2 = xji.length_squared();
    if r2 <= 0.0 {
        return [DVec2::ZERO; 2];
    }
    let w = gw.dot(xji) / r2;
    let vji = b.vh - a.vh;
    let di = vji - a.gh.mul_vec(xji);
    let dj = -vji + b.gh.mul_vec(xji);
    let (ki, kj) = (model.hourglass_of(i) * w, model.hourglass_of(j) * w);
    // V_j / m_j: 1/ρ_j; in a body of revolution j's weight in i's fit is
    // m_j / η_i (kinematics::gradient_weight), so 1/η_i.
    let (vi, vj) = if model.axisymmetric {
        (st.rho[i], st.rho[j])
    } else {
        (st.rho[j], st.rho[i])
    };
    [
        di * (ki * a.pt.c * model.h[i] / vi),
        dj * (-kj * b.pt.c * model.h[j] / vj),
    ]
}

/// The smoothing length along a pair at squared distance `r2` and
/// squared metric distance `q2` (`r/q`), `h0` for coincident particles.
#[inline]
pub(in crate::cpu) fn along(r2: f64, q2: f64, h0: f64) -> f64 {
    if q2 > 0.0 {
        (r2 / q2).sqrt()
    } else {
        h0
    }
}

/// The forces pass: `dv_i/dt` and `de_i/dt` from the SPH sums; rigid
/// particles get zero rates.
///
/// `dv_i/dt = Σ_j m_j (S_i + S_j + t G_ij)` and `de_i/dt = −Σ_j m_j v_ij ·
/// (S_i + ½ t G_ij)`, `S` each side's stress vector (`PairTerms::s`)
/// and `t = −Π I + (R_i + R_j) f^n` (docs/method.md §4).
///
/// Each particle's sums are gathered over its own neighbours, as the
/// shader does; the solver evaluates each pair once for both of its
/// particles ([`super::sweep::momentum_energy`], equal to round-off).
pub fn momentum_energy(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    kin: &Kinematics,
    pts: &[StressPoint],
) -> (Vec<DVec2>, Vec<f64>) {
    let (dv, de, _) = rates_and_dissipation(model, st, nb, kin, pts);
    (dv, de)
}

/// [`momentum_energy`] and the artificial dissipation rate: the power the
/// viscosity, the artificial stress and the hourglass control book into
/// the particles' internal energy, `Σ_i m_i Σ_j −m_j v_ij·(a_ij + X_i)`
/// ([`PairTerms::a`], docs/method.md, "The energy ledger").
pub fn rates_and_dissipation(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    kin: &Kinematics,
    pts: &[StressPoint],
) -> (Vec<DVec2>, Vec<f64>, f64) {
    let sums: Vec<(DVec2, f64, f64)> = (0..model.len())
        .map(|i| {
            let (mut dv, mut de, mut dd) = (DVec2::ZERO, 0.0, 0.0);
            if model.rigid(i) {
                return (dv, de, dd);
            }
            for b in nb.of(model, st.frame(), i) {
                let p = pair_terms(model, st, kin, pts, i, &b);
                let mj = model.mass[b.j as usize];
                dv += p.tg * mj;
                de -= mj * (p.vij.dot(p.s[0] + p.hg[0]) - p.shared);
                dd -= mj * p.vij.dot(p.a + p.hg[0]);
            }
            // The mirror images across the axis of a body of revolution
            // or a symmetry plane (none without) as more neighbours, and
            // the hoop stress's acceleration and its work.
            let side_i = Side::of(st, kin, pts, i);
            for (b, _, m) in nb.images_of(model, st.frame(), i) {
                let j = b.j as usize;
                let image = Side::of(st, kin, pts, j).mirrored(&m);
                let p = pair_terms_of(model, st, &kin.surface, (i, &side_i), (j, &image), &b);
                let mj = model.mass[j];
                dv += p.tg * mj;
                de -= mj * (p.vij.dot(p.s[0] + p.hg[0]) - p.shared);
                dd -= mj * p.vij.dot(p.a + p.hg[0]);
            }
            if model.axisymmetric {
                dv.x -= pts[i].hoop;
                de += pts[i].hoop * st.v[i].x;
            }
            (dv, de, dd * model.mass[i])
        })
        .collect();
    let d = sums.iter().map(|s| s.2).sum::<f64>();
    let (dv, de): (Vec<DVec2>, Vec<f64>) = sums.into_iter().map(|s| (s.0, s.1)).unzip();
    (dv, de, d)
}

/// A pair's energy vectors, kept by [`momentum_keeping`] in the pair's
/// slot of the sweep: particle i's `X_i = (σ_i/ρ_i² − ½Π_ij I + ½ (R_i +
/// R_j) f^n) G_ij` and particle j's `X_j = t G_ij − X_i`, so that the
/// energy sums at any velocities `w` are `de_i/dt = −Σ_j m_j w_ij·X_i`
/// and `de_j/dt = −Σ_i m_i w_ij·X_j` ([`energy_replay`]).
pub type PairVectors = [DVec2; 2];

/// The one-pair terms `p`'s [`PairVectors`] (the hourglass control's
/// parts included): `X_i = ½ (t G + (S_i − S_j))` with each side's
/// stress vector and hourglass term `S` ([`PairTerms::s`]), and `X_j = t
/// G − X_i`.
///
/// [`PairTerms::s`]: crate::cpu::forces::PairTerms
#[inline]
pub(in crate::cpu) fn vectors_of(p: &PairTerms) -> PairVectors {
    let [hi, hj] = p.hg;
    let (sig, sjg) = (p.s[0] + hi, p.s[1] + hj);
    let xi = (p.tg + (sig - sjg)) * 0.5;
    [xi, p.tg - xi]
}
