//! The forces stage as the solver runs it: every pair once
//! ([`Neighbours::sweep`]), four pairs of a row at a time in vector lanes
//! where the scene has no rigid body (`forces_lanes.rs`); and, for the
//! leapfrog, the momentum sums alone with each pair's energy vectors kept
//! for the energy sums at the step's end.

use glam::DVec2;

use super::forces_lanes::{lanes_serve, sums_into, Inputs, SumsOut};
use crate::cpu::forces::PairVectors;
use crate::cpu::kinematics::Kinematics;
use crate::cpu::kinematics::StressPoint;
use crate::cpu::neighbours::Neighbours;
use crate::model::{Model, State};
/// The forces pass: `dv_i/dt` and `de_i/dt` from the SPH sums, each pair evaluated
/// once ([`Neighbours::sweep`]); rigid particles get zero rates.
///
/// `dv_i/dt = Σ_j m_j (S_i + S_j + t G_ij)` and `de_i/dt = −Σ_j m_j v_ij ·
/// (S_i + ½ t G_ij)`, `S` each side's stress vector (`cpu::forces::PairTerms::s`)
/// and `t = −Π I + (R_i + R_j) f^n` (docs/method.md §4).
///
/// Scenes with no rigid body (the common case: impacts between deforming
/// bodies) take the lane code, four pairs of a row at a time
/// (`lane_terms`); the others take the one-pair code (`pair_terms`). Both
/// give the same bits.
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

/// [`momentum_energy`] and the artificial dissipation rate, the power the
/// viscosity, the artificial stress and the hourglass control book into
/// the particles' internal energy (twin of
/// [`crate::cpu::forces::rates_and_dissipation`]).
pub fn rates_and_dissipation(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    kin: &Kinematics,
    pts: &[StressPoint],
) -> (Vec<DVec2>, Vec<f64>, f64) {
    let (mut dv, mut de, mut d, _) = sums((model, st, nb, kin, pts), lanes_serve(model), None);
    if !model.images.is_empty() {
        d += crate::cpu::axis::add_rates(model, st, nb, kin, pts, (&mut dv, &mut de));
    }
    (dv, de, d)
}

/// The artificial dissipation of the pairs [`momentum_keeping`] kept, as
/// a function of the velocities it is booked at: a pair's is `−m_i m_j
/// w_ij·Y_ij`, `Y_ij` the artificial parts of its booked sides' energy
/// vectors (`X` less `σ/ρ² G`), which is `−Σ_k w_k·C_k` with `C_k` summed
/// per particle as the momentum is (no store of its own), plus the part
/// of rigid particles, whose velocity the step does not change.
#[derive(Debug, Clone, Default)]
pub struct KeptWork {
    c: Vec<DVec2>,
    fixed: f64,
}

impl KeptWork {
    /// The artificial dissipation rate at the velocities `w`.
    pub fn at(&self, w: &[DVec2]) -> f64 {
        self.fixed - self.c.iter().zip(w).map(|(c, w)| c.dot(*w)).sum::<f64>()
    }
}

/// The forces pass's momentum sums (`dv/dt`, as [`momentum_energy`], the same bits)
/// with the energy sums left for later: each pair's [`PairVectors`] go to
/// `keep` instead. The leapfrog (`CpuSolver::step`) books the work of the
/// forces on the velocity at the end of the step, which the momentum sums
/// themselves give.
pub fn momentum_keeping(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    kin: &Kinematics,
    pts: &[StressPoint],
    keep: &mut Vec<PairVectors>,
) -> (Vec<DVec2>, KeptWork) {
    keep.resize(nb.store_len(), [DVec2::ZERO; 2]);
    let lanes = lanes_serve(model);
    let (dv, _, fixed, c) = sums((model, st, nb, kin, pts), lanes, Some(keep));
    (dv, KeptWork { c, fixed })
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
    let mass = &model.mass[..];
    // Rigid particles book nothing; a far pair's j side is its own row's.
    nb.replay_rows(&mut acc, kept, |i, ai, near, far, piece, base| {
        let (wi, mi, ri) = (w[i], mass[i], model.rigid(i));
        for (&j, x) in near.0.iter().zip(near.1) {
            let j = j as usize;
            let wij = wi - w[j];
            if !ri {
                *ai -= mass[j] * wij.dot(x[0]);
            }
            if !model.rigid(j) {
                piece[j - base] -= mi * wij.dot(x[1]);
            }
        }
        if !ri {
            for (&j, x) in far.0.iter().zip(far.1) {
                *ai -= mass[j as usize] * (wi - w[j as usize]).dot(x[0]);
            }
        }
    });
    acc
}

/// [`momentum_energy`] by the lane code (`lanes`, [`lanes_serve`]) or by
/// the one-pair code; with `keep`, the energy terms' vectors go there
/// instead of into the sums ([`momentum_keeping`]).
pub(in crate::cpu) fn sums(
    args: Inputs<'_>,
    lanes: bool,
    keep: Option<&mut Vec<PairVectors>>,
) -> SumsOut {
    let nb = args.2;
    match keep {
        Some(keep) => sums_into(args, lanes, keep),
        // Zero-sized slots: the energy terms go into the sums.
        None => sums_into(args, lanes, &mut vec![(); nb.store_len()]),
    }
}
