//! The forces pass: momentum and energy sums (docs/method.md §4) with Monaghan artificial
//! viscosity and, when the scene asks for it, Gray–Monaghan–Swift artificial
//! stress. The pair-antisymmetric `G_ij = ½ (L_i + L_j) ∇_i W_ij` conserves
//! momentum and energy exactly in semi-discrete form.

use glam::DVec2;

use super::neighbours::{Nbr, Neighbours};
use crate::math::{Mat2, Sym};
use crate::model::{Model, State};
use crate::physics::strength;
use crate::scene::ArtPairs;

use super::forces_sweep::sums_into;
use crate::physics::tension::{art_weight, close_gate};
use crate::physics::viscosity::{reconstructed_jump, viscosity_pi};

/// Per-particle inputs of the momentum pass, computed once per evaluation.
#[derive(Debug, Clone, Copy, Default)]
pub struct StressPoint {
    /// `σ_i / ρ_i²`, in plane (tension positive).
    pub sr2: Sym,
    /// Artificial stress `R_i` (zero when off).
    pub r: Sym,
    /// Sound speed for the viscosity.
    pub c: f64,
}

/// What a pair contributes to both of its particles' momentum and energy
/// sums, from particle i's side.
pub(super) struct PairTerms {
    /// `t G_ij`, `t = σ_i/ρ_i² + σ_j/ρ_j² − Π_ij I (+ artificial stress)`.
    pub(super) tg: DVec2,
    /// `G_ij = ½ (L_i + L_j) ∇_i W_ij`.
    pub(super) g: DVec2,
    /// `v_ij = v_i − v_j`.
    pub(super) vij: DVec2,
    /// `½ Π_ij v_ij·G_ij − ½ (R_i + R_j) f^n : (v_ij ⊗ G_ij)`, the part of
    /// either particle's energy term that is the pair's own.
    pub(super) shared: f64,
}

/// The momentum and energy terms of the pair `(i, b.j)`.
///
/// Swapping the particles flips `G`, `v_ij`, `x_ij` and the reconstructed
/// jump and keeps `Π_ij`, `t` and `f`, so particle j's terms are
/// `dv_j −= m_i t G_ij` and `de_j −= m_i (v_ij·(σ_j/ρ_j² G_ij) − shared)`:
/// one evaluation of a pair serves both of its particles.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(super) fn pair_terms(
    model: &Model,
    st: &State,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
    i: usize,
    b: &Nbr,
) -> PairTerms {
    let j = b.j as usize;
    let (pi_, pj) = (&pts[i], &pts[j]);
    let hij = 0.5 * (model.h[i] + model.h[j]);
    let xij = st.x[i] - st.x[j];
    let vij = st.v[i] - st.v[j];
    let g = (l[i] + l[j]).scale(0.5).mul_vec(b.gw);
    // The viscosity sees the reconstructed jump; the energy equation keeps
    // the true v_ij, so the viscous work is still exactly the heat booked
    // (energy conserved). Not at a surface: there ∇v is extrapolated from
    // one side only, and the face is where a contact loads the body
    // impulsively; full viscosity damps that start-up ringing.
    let vis = if model.av_reconstruct && !surface[i] && !surface[j] {
        reconstructed_jump(vij, xij, &gv[i], &gv[j])
    } else {
        vij
    };
    let pi = viscosity_pi(
        model.alpha,
        model.beta,
        hij,
        xij,
        vis,
        0.5 * (pi_.c + pj.c),
        0.5 * (st.rho[i] + st.rho[j]),
    );
    let mut t = pi_.sr2.add_scaled(&pj.sr2, 1.0);
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
    let bonded = || {
        st.damage.is_empty() || !(strength::failed(st.damage[i]) || strength::failed(st.damage[j]))
    };
    if let Some(a) = model.artificial_stress.filter(|_| bonded()) {
        let rs = pi_.r.add_scaled(&pj.r, 1.0);
        let r2 = xij.length_squared();
        let gate = match a.pairs {
            ArtPairs::All => 1.0,
            ArtPairs::Close => {
                let vol = 0.5 * (model.mass[i] / st.rho[i] + model.mass[j] / st.rho[j]);
                let ks = &model.close_scale;
                let k2 = if ks.is_empty() { 1.0 } else { ks[i].min(ks[j]) };
                close_gate(r2, vol, k2, model.dim)
            }
        };
        if rs.xx + rs.yy < 0.0 && gate > 0.0 {
            let dp = 0.5 * (model.spacing_of(i) + model.spacing_of(j));
            let rf = rs.scale(art_weight(r2, dp, hij, a.n) * gate);
            t = t.add_scaled(&rf, 1.0);
            art_work = 0.5 * vij.dot(rf.mul_vec(g));
        }
    }
    PairTerms {
        tg: t.mul_vec(g),
        g,
        vij,
        shared: 0.5 * pi * vij.dot(g) - art_work,
    }
}

/// The forces pass: `dv_i/dt` and `de_i/dt` from the SPH sums, each pair evaluated
/// once ([`Neighbours::sweep`]); rigid particles get zero rates.
///
/// `dv_i/dt = Σ_j m_j t G_ij` and `de_i/dt = −Σ_j m_j (σ_i/ρ_i² − ½Π I +
/// ½ (R_i + R_j) f^n) : (v_ij ⊗ G_ij)` (docs/method.md §4).
///
/// Scenes with no rigid body (the common case: impacts between deforming
/// bodies) take the lane code, four pairs of a row at a time
/// (`lane_terms`); the others take the one-pair code (`pair_terms`). Both
/// give the same bits.
pub fn momentum_energy(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
) -> (Vec<DVec2>, Vec<f64>) {
    sums(model, st, nb, l, gv, surface, pts, lanes_serve(model), None)
}

/// A pair's energy vectors, kept by [`momentum_keeping`] in the pair's
/// slot of the sweep: particle i's `X_i = (σ_i/ρ_i² − ½Π_ij I + ½ (R_i +
/// R_j) f^n) G_ij` and particle j's `X_j = t G_ij − X_i`, so that the
/// energy sums at any velocities `w` are `de_i/dt = −Σ_j m_j w_ij·X_i`
/// and `de_j/dt = −Σ_i m_i w_ij·X_j` ([`energy_replay`]).
pub type PairVectors = [DVec2; 2];

/// The forces pass's momentum sums (`dv/dt`, as [`momentum_energy`], the same bits)
/// with the energy sums left for later: each pair's [`PairVectors`] go to
/// `keep` instead. The leapfrog (`CpuSolver::step`) books the work of the
/// forces on the velocity at the end of the step, which the momentum sums
/// themselves give.
#[allow(clippy::too_many_arguments)]
pub fn momentum_keeping(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
    keep: &mut Vec<PairVectors>,
) -> Vec<DVec2> {
    keep.resize(nb.store_len(), [DVec2::ZERO; 2]);
    let lanes = lanes_serve(model);
    sums(model, st, nb, l, gv, surface, pts, lanes, Some(keep)).0
}

/// `de/dt` from the pairs kept by [`momentum_keeping`] with the work done
/// on the velocities `w` (rigid particles: zero), in the sweep's order.
pub fn energy_replay(
    model: &Model,
    nb: &Neighbours,
    kept: &[PairVectors],
    w: &[DVec2],
) -> Vec<f64> {
    let mut acc = vec![0.0f64; model.len()];
    nb.replay(&mut acc, kept, |i, j, x, ai, aj| {
        let wij = w[i] - w[j];
        if !model.rigid(i) {
            *ai -= model.mass[j] * wij.dot(x[0]);
        }
        if let Some(aj) = aj.filter(|_| !model.rigid(j)) {
            *aj -= model.mass[i] * wij.dot(x[1]);
        }
    });
    acc
}

/// Particle i's energy vector `X_i = ½ (t G + (σ_i/ρ_i² − σ_j/ρ_j²) G)`
/// and j's `t G − X_i` ([`PairVectors`]).
#[inline]
pub(super) fn pair_vectors(tg: DVec2, sig: DVec2, sjg: DVec2) -> PairVectors {
    let xi = (tg + (sig - sjg)) * 0.5;
    [xi, tg - xi]
}

/// Whether the lane code serves the scene: it does not do the rigid
/// bodies' zero rates.
pub(super) fn lanes_serve(model: &Model) -> bool {
    !model.any_rigid
}

/// [`momentum_energy`] by the lane code (`lanes`, [`lanes_serve`]) or by
/// the one-pair code; with `keep`, the energy terms' vectors go there
/// instead of into the sums ([`momentum_keeping`]).
#[allow(clippy::too_many_arguments)]
pub(super) fn sums(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
    lanes: bool,
    keep: Option<&mut Vec<PairVectors>>,
) -> (Vec<DVec2>, Vec<f64>) {
    let args = (model, st, nb, l, gv, surface, pts);
    match keep {
        Some(keep) => sums_into(args, lanes, keep),
        // Zero-sized slots: the energy terms go into the sums.
        None => sums_into(args, lanes, &mut vec![(); nb.store_len()]),
    }
}
