//! Hard cases of issue 6, the one-dimensional half and far-from-origin
//! placement (docs/hard_cases.md): a high impedance mismatch, jittered
//! particles, bodies far from the origin, a long free ring, and an
//! elastic–plastic rod on a rigid wall. Every case loads its scene from
//! `scenes/hard/` (whose header states the exact answer and what is
//! asserted) and runs on the CPU path and, via `on_gpu`, on the GPU path.

#[path = "../common/mod.rs"]
mod common;
use common::*;
use sphcontact::run::RunOutput;
use sphcontact::scene::{Integrator, Probe};
use sphcontact::validation::exact::{bar_impact, bar_impact_history, rod_on_wall, BarId};
use sphcontact::Scene;

/// The initial coordinate `at[0]` of the particle probe `name`.
fn probe_at(scene: &Scene, name: &str) -> f64 {
    scene
        .probes
        .iter()
        .find_map(|p| match p {
            Probe::Particle { name: n, at, .. } if n == name => Some(at[0]),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no particle probe '{name}'"))
}

/// The maximal intervals on which `f` is constant, sampled every `dt` over
/// `[0, t_end]` (the exact histories here are piecewise constant): `(start,
/// end, value)` with start and end located to `dt`.
fn plateaus(f: impl Fn(f64) -> f64, t_end: f64, dt: f64) -> Vec<(f64, f64, f64)> {
    let n = (t_end / dt).ceil() as usize;
    let mut out = Vec::new();
    let mut start = 0.0;
    let mut value = f(0.0);
    for k in 1..=n {
        let t = k as f64 * dt;
        let v = f(t);
        if v != value || k == n {
            out.push((start, t, value));
            start = t;
            value = v;
        }
    }
    out
}

/// The largest deviation of `values` from the exact piecewise-constant
/// history `exact` over the middle `keep` fraction of the exact plateaus
/// numbered `which` (0: the state before anything arrives), and how many
/// rows were compared.
fn plateau_error(
    out: &RunOutput,
    values: &[f64],
    exact: impl Fn(f64) -> f64,
    t_end: f64,
    which: std::ops::Range<usize>,
    keep: f64,
) -> (f64, usize) {
    let t = &out.history.times;
    let mut worst: f64 = 0.0;
    let mut rows = 0;
    let all = plateaus(&exact, t_end, 1e-10);
    for &(a, b, v) in &all[which] {
        let margin = 0.5 * (1.0 - keep) * (b - a);
        for (k, &tk) in t.iter().enumerate() {
            if tk > a + margin && tk < b - margin {
                worst = worst.max((values[k] - v).abs());
                rows += 1;
            }
        }
    }
    (worst, rows)
}

// ---------------------------------------------------------------------------
// 1. High impedance mismatch
// ---------------------------------------------------------------------------

mod far;
mod flyer;
mod impedance;
mod jitter;
mod ringing;
mod rod;
mod spall;
