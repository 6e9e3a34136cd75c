//! Jittered placement of the paper's bars.

use super::*;

/// Contact plateau over 10–90 % of the contact (mean, least, largest),
/// separation time and the left bar's final mean velocity of a two-bar run.
fn bar_observables(out: &RunOutput) -> ([f64; 3], f64, f64) {
    let t = &out.history.times;
    let p = column(out, "contact_pressure");
    let (_, t_sep) = contact_window(t, &p);
    let plateau = plateau(t, &p, t_sep);
    let mean = plateau.iter().sum::<f64>() / plateau.len() as f64;
    let lo = plateau.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = plateau.iter().cloned().fold(0.0, f64::max);
    let vl = *column(out, "velocity_left").last().unwrap();
    ([mean, lo, hi], t_sep, vl)
}

/// The paper's case 1 with every particle jittered by up to ±10 % of the
/// spacing (scenes/hard/jitter_bars_steel.toml). Exact: −458.1 MPa,
/// separation 1.7136 µs, rebound −10 m/s (`exact::bar_impact`).
///
/// What the method should reach here: the momentum equation's
/// pair-antisymmetric gradient `G_ij = ½(L_i + L_j)∇W_ij` (docs/method.md §5)
/// conserves momentum and energy exactly but is only zeroth-order
/// consistent on an irregular particle set, so the jitter leaves an error
/// that does not shrink with resolution: a noise on the contact plateau of
/// about ±jitter and a softening bias of about jitter² in relative terms.
/// Measured (CPU, 100 and 200 particles per bar, six seeds): plateau mean
/// −5 to −7 %, single rows down to −13 %, separation +1.9 to +2.6 % late,
/// rebound 0.86–0.90 of v0 (regular lattice: +0.2 %, +0.4 %, 0.970); at
/// jitter 0.05 the bias is −1 %, at 0.02 below 0.1 %. Asserted, with room
/// for the seed: plateau mean within 8 %, every row within 15 %, separation
/// within 3.5 %, rebound at least 0.85 v0 and at most v0; clean separation
/// (no tension, zero force after); the freed face's stress below 0.25 of
/// the contact stress from 0.1 µs after the separation; momentum to
/// round-off and the energy balance within 0.5 % (`assert_conserved`).
/// Same on the GPU (f32 noise is far below the jitter's).
fn jittered_bars() {
    let scene = load("scenes/hard/jitter_bars_steel.toml");
    assert!(scene.bodies.iter().all(|b| b.jitter == Some(0.1)));
    let steel = material(&scene, "steel");
    let exact = bar_impact(&steel, 0.005, 10.0, &steel, 0.005, -10.0);
    let out = run(&scene);
    assert_conserved(&scene, &out);
    let ([mean, lo, hi], t_sep, vl) = bar_observables(&out);
    let sigma = -exact.contact_stress;
    let (e_mean, e_lo, e_hi) = (mean / sigma - 1.0, lo / sigma - 1.0, hi / sigma - 1.0);
    let e_sep = t_sep / exact.separation_time - 1.0;
    let rebound = vl / exact.final_velocity_1;
    println!(
        "jittered bars: plateau mean {e_mean:+.4} (rows {e_lo:+.4} .. {e_hi:+.4}), separation {e_sep:+.4}, rebound {rebound:.4}; energy balance {:.2e}",
        out.summary.energy_balance()
    );
    assert!(
        e_mean.abs() < 0.08,
        "plateau mean {mean:e} Pa ({e_mean:+.4})"
    );
    assert!(
        e_lo > -0.15 && e_hi < 0.15,
        "plateau rows {lo:e} .. {hi:e} Pa"
    );
    assert!(e_sep.abs() < 0.035, "separation {t_sep:e} s ({e_sep:+.4})");
    assert!(
        rebound > 0.85 && rebound <= 1.0,
        "rebound {vl} m/s ({rebound:.4} of the exact)"
    );
    let t = &out.history.times;
    let p = column(&out, "contact_pressure");
    assert_never_pulls(&out, 0, "velocity_left");
    for (k, &tk) in t.iter().enumerate() {
        if tk > t_sep {
            assert_eq!(p[k], 0.0, "pressure after separation at {tk:e}");
        }
    }
    // The freed face settles (exact: stress-free). The jitter leaves a
    // noise there, measured 0.17 of the contact stress at most from 0.1 µs
    // after the separation; the close-pair artificial stress must not
    // ring on it (gated on the spacing as placed: with the volume alone
    // the jittered pairs sat inside its gate and the face rang at 1.9).
    let face = column(&out, "stress_a");
    let ring = (0..t.len())
        .filter(|&k| t[k] > t_sep + 1e-7)
        .map(|k| face[k].abs())
        .fold(0.0, f64::max);
    println!(
        "face after separation: {:.3} of the contact stress",
        ring / sigma.abs()
    );
    assert!(ring < 0.25 * sigma.abs(), "the face rings at {ring:e} Pa");
}

#[test]
fn jitter_bars() {
    jittered_bars();
}

#[test]
fn jitter_bars_midpoint() {
    on_midpoint(jitter_bars);
}

#[test]
fn jitter_bars_gpu() {
    on_gpu(jittered_bars);
}

// ---------------------------------------------------------------------------
// 5. Elastic–plastic rod on a rigid wall
// ---------------------------------------------------------------------------
