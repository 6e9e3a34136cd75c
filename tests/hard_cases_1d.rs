//! Hard cases of issue 6, the one-dimensional half and far-from-origin
//! placement (docs/hard_cases.md): a high impedance mismatch, jittered
//! particles, bodies far from the origin, a long free ring, and an
//! elastic–plastic rod on a rigid wall. Every case loads its scene from
//! `scenes/hard/` (whose header states the exact answer and what is
//! asserted) and runs on the CPU path and, via `on_gpu`, on the GPU path.

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

/// A tungsten-like striker (2 mm, 20 m/s) onto aluminium (6 mm, at rest):
/// density ratio 6.9, impedance ratio 5.7 (scenes/hard/
/// impedance_tungsten_aluminium.toml). Exact: the stepped interface stress
/// of `exact::bar_impact_history` (−301.5, −211.3, −148.2 MPa), separation
/// at 1.889 µs, final mean velocities 8.455 and 26.62 m/s.
///
/// Tolerances, from what the method reaches on the paper's bars (docs/method.md
/// §11, docs/usage.md: plateau +0.2 %, separation +0.4 %, rebound −3 % at 100 per
/// bar): the contact pressure over the middle half of each contact step
/// within 1 %, 1 % and 7 % (the striker is 80 particles long, so each
/// step's front is smeared over a few of them, and the third step is too
/// short to settle, docs/hard_cases.md); separation within 1.5 %; final
/// velocities within 2 %; the
/// waves inside the bars (particle stress, biased near fronts by the
/// kernel) within 3 % of the contact stress on their plateaus. "No
/// oscillation" is: no ringing beyond the plateau band, no chatter (the
/// contact force never drops to zero while the exact contact lasts), the
/// contact faces moving together within 3 % of the closing speed, and no
/// tension. Same tolerances on the GPU: f32 is far below them.
fn impedance_mismatch() {
    let scene = load("scenes/hard/impedance_tungsten_aluminium.toml");
    let (w, al) = (material(&scene, "tungsten"), material(&scene, "aluminium"));
    let (l1, l2, v1, v2) = (0.002, 0.006, 20.0, 0.0);
    let t_end = scene.simulation.end_time;
    let exact = bar_impact_history(&w, l1, v1, &al, l2, v2, t_end).expect("resolved");
    let r = exact.result;
    let out = run(&scene);
    assert_conserved(&scene, &out);
    let t = &out.history.times;
    let p = column(&out, "contact_pressure");
    let f = column(&out, "contact_force");

    // The contact steps.
    assert_eq!(exact.contact_steps.len(), 3, "{:?}", exact.contact_steps);
    for (s, tol) in exact.contact_steps.iter().zip([0.01, 0.01, 0.07]) {
        let margin = 0.25 * (s.t_end - s.t_start);
        let mut worst: f64 = 0.0;
        for (k, &tk) in t.iter().enumerate() {
            if tk > s.t_start + margin && tk < s.t_end - margin {
                worst = worst.max((p[k] / -s.stress - 1.0).abs());
            }
        }
        println!(
            "step {:.3}-{:.3} µs, exact {:.2} MPa: worst {worst:.4}",
            s.t_start * 1e6,
            s.t_end * 1e6,
            s.stress / 1e6
        );
        assert!(worst < tol, "plateau {:e} Pa: off by {worst:.4}", s.stress);
    }
    let (t0, t_sep) = contact_window(t, &f);
    let sep_err = t_sep / r.separation_time - 1.0;
    println!("separation {t_sep:e} s ({sep_err:+.4})");
    assert_eq!(t0, 0.0, "contact from the first step");
    assert!(
        sep_err.abs() < 0.015,
        "separation {t_sep:e} s ({sep_err:+.4})"
    );
    for (k, &tk) in t.iter().enumerate() {
        assert!(p[k] >= 0.0 && f[k] >= 0.0, "tension at {tk:e}");
        if tk > 0.0 && tk < 0.97 * r.separation_time {
            assert!(f[k] > 0.0, "contact lost at {tk:e} s (chatter)");
        }
        if tk > t_sep {
            assert_eq!(f[k], 0.0, "force after separation at {tk:e}");
        }
    }

    // The faces move together over the first step.
    let (fs, ft) = (
        column(&out, "face_velocity_striker"),
        column(&out, "face_velocity_target"),
    );
    let s0 = exact.contact_steps[0];
    let mut worst_gap_rate: f64 = 0.0;
    let mut worst_face: f64 = 0.0;
    for (k, &tk) in t.iter().enumerate() {
        if tk > s0.t_start + 0.15 * (s0.t_end - s0.t_start)
            && tk < s0.t_end - 0.15 * (s0.t_end - s0.t_start)
        {
            worst_gap_rate = worst_gap_rate.max((fs[k] - ft[k]).abs() / (v1 - v2));
            worst_face =
                worst_face.max((0.5 * (fs[k] + ft[k]) - r.interface_velocity).abs() / (v1 - v2));
        }
    }
    println!("faces: worst |Δv| {worst_gap_rate:.4}, worst mean vs interface velocity {worst_face:.4} of the closing speed");
    assert!(
        worst_gap_rate < 0.03,
        "faces move apart/together at {worst_gap_rate} of the closing speed"
    );
    assert!(
        worst_face < 0.03,
        "face velocity off the exact {} m/s by {worst_face}",
        r.interface_velocity
    );

    // Transmitted and reflected waves: the first plateau at each probe,
    // the state behind the first wave from the interface (exact: the
    // contact stress and the interface velocity).
    let sigma = -r.contact_stress;
    for (stress, vel, bar) in [
        ("stress_target_3mm", "velocity_target_3mm", BarId::Two),
        ("stress_striker_1mm", "velocity_striker_1mm", BarId::One),
    ] {
        let d = probe_at(&scene, stress).abs();
        let (es, n_s) = plateau_error(
            &out,
            &column(&out, stress),
            |tt| exact.point_stress(bar, d, tt),
            t_end,
            1..2,
            0.5,
        );
        let (ev, n_v) = plateau_error(
            &out,
            &column(&out, vel),
            |tt| exact.point_velocity(bar, d, tt),
            t_end,
            1..2,
            0.5,
        );
        println!(
            "{stress}: worst {:.4} of the contact stress over {n_s} rows; {vel}: worst {:.4} of the closing speed",
            es / sigma,
            ev / (v1 - v2)
        );
        assert!(n_s > 100 && n_v == n_s);
        assert!(es < 0.05 * sigma, "{stress}: off by {es:e} Pa");
        assert!(ev < 0.02 * (v1 - v2), "{vel}: off by {ev} m/s");
    }

    // Final mean velocities.
    for (name, exact_v) in [
        ("velocity_striker", r.final_velocity_1),
        ("velocity_target", r.final_velocity_2),
    ] {
        let v = *column(&out, name).last().unwrap();
        let e = v / exact_v - 1.0;
        println!("{name}: {v} vs {exact_v} ({e:+.4})");
        assert!(e.abs() < 0.02, "{name} {v} vs exact {exact_v}");
    }
}

#[test]
fn high_impedance_mismatch() {
    impedance_mismatch();
}

#[test]
fn high_impedance_mismatch_gpu() {
    on_gpu(impedance_mismatch);
}

// ---------------------------------------------------------------------------
// 2. Jittered particles
// ---------------------------------------------------------------------------

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
    for (k, &tk) in t.iter().enumerate() {
        assert!(p[k] >= 0.0, "tension at {tk:e}");
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
fn jitter_bars_leapfrog() {
    on_leapfrog(jitter_bars);
}

#[test]
fn jitter_bars_gpu() {
    on_gpu(jittered_bars);
}

// ---------------------------------------------------------------------------
// 5. Elastic–plastic rod on a rigid wall
// ---------------------------------------------------------------------------

/// First time `values` crosses `level` (between rows, linearly).
fn crossing(t: &[f64], values: &[f64], level: f64) -> f64 {
    let k = values
        .windows(2)
        .position(|w| (w[0] - level) * (w[1] - level) <= 0.0 && w[0] != w[1])
        .unwrap_or_else(|| panic!("never crosses {level}"));
    let (a, b) = (values[k], values[k + 1]);
    t[k] + (t[k + 1] - t[k]) * (level - a) / (b - a)
}

/// Steel (Table 1, Y0 = 600 MPa, Mie–Grüneisen) at 100 m/s onto a rigid
/// wall (scenes/hard/rod_on_rigid_wall.toml). Exact (`exact::rod_on_wall`):
/// precursor at the HEL, −1.049 GPa and 77.20 m/s, Lagrangian speed
/// 5,863 m/s; plastic wave to rest, −3.934 GPa, 4,759 m/s.
///
/// Probes 4, 6 and 8 mm from the struck face. A front's arrival is where the
/// particle velocity crosses the middle of its jump (a smeared front is
/// centred on the exact one). Tolerances, from what the method reaches and
/// why (measured at 400 and 800 particles, the same to 0.5 %):
/// * arrival times within 2 % (the fronts start from the penalty contact a
///   few steps late: measured +0.1 % precursor, +1.1 % plastic at 6 mm);
///   the speeds between the 4 and 8 mm probes within 1.5 % (measured
///   −0.6 % and −0.7 %: the fronts are still steepening from their smeared
///   start, so where a front's mid-jump lies moves by a fraction of its
///   width); the exact precursor runs 0.5 % faster than `c_L`, and its
///   arrival is within 2 % of `D/c_L` too;
/// * precursor plateau at 6 and 8 mm, where the waves have separated by
///   0.24 and 0.32 µs (at 4 mm the 0.16 µs between them still holds the
///   precursor front's ringing: measured 3.5 %), from 20 % to 60 % of the
///   exact interval between the two waves (the plastic wave's smeared foot
///   arrives early), within 3 %
///   of σ_HEL, velocity within 5 % of the HEL jump: the viscous front
///   overshoots yield a little and the overshoot's plastic strain stays
///   (measured 1.9–2.3 % and 2.4–2.9 %; the same at 800 particles);
/// * plastic plateau (from 0.15 µs after the exact arrival, when the
///   front's ringing has decayed, until the release from the free end
///   could arrive) within 2 % of the exact stress, velocity within 1 % of
///   the impact speed (measured 0.85–0.97 %, ≤ 0.4 %): the ringing behind
///   the plastic front unloads the deviator elastically from 400 to about
///   363 MPa, leaving the settled stress 0.5 % short of the exact;
/// * energy balance within 0.5 %: the wall does no work.
///
/// Same tolerances on the GPU: f32 is far below them.
fn elastic_plastic_rod() {
    rod_two_waves("scenes/hard/rod_on_rigid_wall.toml", [4, 6, 8]);
}

/// [`elastic_plastic_rod`] for the rod of `path`, with probes `mms`
/// millimetres from the struck face.
fn rod_two_waves(path: &str, mms: [u32; 3]) {
    let scene = load(path);
    let steel = material(&scene, "steel");
    let v0 = scene.bodies[0].velocity.as_ref().unwrap()[0];
    let exact = rod_on_wall(&steel, v0).expect("two waves");
    println!(
        "exact: HEL {:.4e} Pa at {:.2} m/s, {:.1} m/s; plastic {:.4e} Pa, {:.1} m/s",
        exact.hel.stress,
        exact.hel.velocity,
        exact.elastic_speed,
        exact.plastic.stress,
        exact.plastic_speed
    );
    let out = run(&scene);
    // The wall takes momentum but, at rest, does no work: the energy
    // balance closes (momentum is not conserved here, by design).
    let balance = out.summary.energy_balance().abs();
    println!("energy balance {balance:.2e}");
    assert!(balance < 5e-3, "energy balance {balance:e}");
    let t = &out.history.times;
    let t_end = scene.simulation.end_time;
    let (h, f) = (exact.hel, exact.plastic);
    let u_hel = v0 - h.velocity;
    // The precursor's release from the free end meets the plastic wave at
    // t_meet = 2L/(W_e + W_p), 8.96 mm from the wall; nothing from that
    // meeting reaches a probe (≤ 8 mm) before t_meet, so the two-wave
    // answer holds at the probes until then.
    let rod_length = match scene.bodies[0].shape {
        sphcontact::scene::Shape::Segment { from, to } => to - from,
        _ => unreachable!("a 1-D rod"),
    };
    let t_meet = 2.0 * rod_length / (exact.elastic_speed + exact.plastic_speed);
    let mut arrivals = Vec::new();
    for mm in mms {
        let (s_name, v_name) = (format!("stress_{mm}mm"), format!("velocity_{mm}mm"));
        let d = -probe_at(&scene, &s_name);
        let s = column(&out, &s_name);
        let v = column(&out, &v_name);
        let t_e = d / exact.elastic_speed;
        let t_p = d / exact.plastic_speed;
        let te = crossing(t, &v, v0 - 0.5 * u_hel);
        let tp = crossing(t, &v, 0.5 * h.velocity);
        println!(
            "{mm} mm: precursor at {:.4} µs ({:+.4}; D/c_L {:+.4}), plastic at {:.4} µs ({:+.4})",
            te * 1e6,
            te / t_e - 1.0,
            te / (d / steel.c_l) - 1.0,
            tp * 1e6,
            tp / t_p - 1.0
        );
        assert!(
            (te / t_e - 1.0).abs() < 0.02,
            "{mm} mm: precursor at {te:e}"
        );
        assert!((te / (d / steel.c_l) - 1.0).abs() < 0.02);
        assert!(
            (tp / t_p - 1.0).abs() < 0.02,
            "{mm} mm: plastic wave at {tp:e}"
        );
        arrivals.push((d, te, tp));

        // Precursor plateau.
        let (a, b) = (t_e + 0.2 * (t_p - t_e), t_p - 0.4 * (t_p - t_e));
        let (mut es, mut ev) = (0.0f64, 0.0f64);
        for (k, &tk) in t.iter().enumerate() {
            if tk > a && tk < b {
                es = es.max((s[k] / h.stress - 1.0).abs());
                ev = ev.max((v[k] - h.velocity).abs() / u_hel);
            }
        }
        // Plastic plateau.
        let (mut fs, mut fv) = (0.0f64, 0.0f64);
        let mut rows = 0;
        for (k, &tk) in t.iter().enumerate() {
            if tk > t_p + 0.15e-6 && tk <= t_end.min(t_meet) {
                fs = fs.max((s[k] / f.stress - 1.0).abs());
                fv = fv.max(v[k].abs() / v0);
                rows += 1;
            }
        }
        println!(
            "{mm} mm: HEL plateau stress {es:.4}, velocity {ev:.4} of u_HEL; plastic plateau stress {fs:.4}, velocity {fv:.4} of v0 ({rows} rows)"
        );
        if mm > mms[0] {
            assert!(es < 0.03, "{mm} mm: precursor stress off σ_HEL by {es:.4}");
            assert!(
                ev < 0.05,
                "{mm} mm: precursor velocity off by {ev:.4} of u_HEL"
            );
        }
        assert!(rows > 20);
        assert!(fs < 0.02, "{mm} mm: plastic stress off by {fs:.4}");
        assert!(
            fv < 0.01,
            "{mm} mm: not at rest behind the plastic wave ({fv:.4} v0)"
        );
    }
    let (d0, te0, tp0) = arrivals[0];
    let (d1, te1, tp1) = arrivals[2];
    let we = (d1 - d0) / (te1 - te0);
    let wp = (d1 - d0) / (tp1 - tp0);
    println!(
        "speeds: precursor {we:.1} m/s ({:+.4}), plastic {wp:.1} m/s ({:+.4})",
        we / exact.elastic_speed - 1.0,
        wp / exact.plastic_speed - 1.0
    );
    assert!((we / exact.elastic_speed - 1.0).abs() < 0.015);
    assert!((wp / exact.plastic_speed - 1.0).abs() < 0.015);
}

#[test]
fn elastic_plastic_rod_on_rigid_wall() {
    elastic_plastic_rod();
}

#[test]
fn elastic_plastic_rod_on_rigid_wall_leapfrog() {
    on_leapfrog(elastic_plastic_rod_on_rigid_wall);
}

#[test]
fn elastic_plastic_rod_on_rigid_wall_gpu() {
    on_gpu(elastic_plastic_rod);
}

/// The rod of [`elastic_plastic_rod`] with linear hardening (a
/// Johnson–Cook strength with n = 1, no rate term, no heating; B = 50 GPa):
/// the same figures against the exact two-wave answer with the hardened
/// deviator behind the plastic wave, which puts the plastic plateau 3.7 %
/// and its speed 5.0 % away from the perfectly plastic rod's.
fn hardening_rod() {
    let path = "scenes/hard/rod_on_rigid_wall_hardening.toml";
    let scene = load(path);
    let v0 = scene.bodies[0].velocity.as_ref().unwrap()[0];
    let hard = rod_on_wall(&material(&scene, "steel"), v0).unwrap();
    let perfect = rod_on_wall(
        &material(&load("scenes/hard/rod_on_rigid_wall.toml"), "steel"),
        v0,
    )
    .unwrap();
    println!(
        "plastic plateau {:.4e} vs {:.4e} Pa, speed {:.1} vs {:.1} m/s",
        hard.plastic.stress, perfect.plastic.stress, hard.plastic_speed, perfect.plastic_speed
    );
    // The test tells the two apart: the hardening moves both answers by
    // more than their tolerances.
    assert!(hard.plastic.stress / perfect.plastic.stress - 1.0 > 0.03);
    assert!(hard.plastic_speed / perfect.plastic_speed - 1.0 > 0.04);
    rod_two_waves(path, [8, 12, 16]);
}

#[test]
fn hardening_rod_on_rigid_wall() {
    hardening_rod();
}

#[test]
fn hardening_rod_on_rigid_wall_leapfrog() {
    on_leapfrog(hardening_rod_on_rigid_wall);
}

#[test]
fn hardening_rod_on_rigid_wall_gpu() {
    on_gpu(hardening_rod);
}

#[test]
fn hardening_rod_on_rigid_wall_gpu_leapfrog() {
    on_leapfrog(|| on_gpu(hardening_rod));
}

/// How the elastic target of scenes/hard/flyer_plate_tension.toml took
/// the reflected tension: each plateau at 8 mm against the elastic wave
/// solution (measured / exact − 1, over the middle 60 % of its exact
/// interval), and the largest free-surface speed once the pulse has left
/// the target (exact: at rest).
#[derive(Debug)]
struct Flyer {
    completed: bool,
    /// Particles failed (a material that can fail).
    failed: usize,
    compression: f64,
    tension: f64,
    rest: f64,
}

fn flyer_tension(scene: &Scene) -> Flyer {
    let mat = material(scene, "steel");
    let c = ((mat.k + 4.0 * mat.g / 3.0) / mat.rho0).sqrt();
    let up = 0.5 * scene.bodies[0].velocity.as_ref().unwrap()[0];
    let sigma = mat.rho0 * c * up;
    let (lf, lt, x) = (0.002, 0.01, probe_at(scene, "stress_8mm"));
    let out = run(scene);
    let t = &out.history.times;
    let (stress, vfs) = (
        column(&out, "stress_8mm"),
        column(&out, "free_surface_velocity"),
    );
    let mean_over = |a: f64, b: f64| {
        let m = 0.2 * (b - a);
        let v: Vec<f64> = (0..t.len())
            .filter(|&k| t[k] > a + m && t[k] < b - m)
            .map(|k| stress[k])
            .collect();
        assert!(v.len() > 10, "{} rows in [{a:e}, {b:e}]", v.len());
        v.iter().sum::<f64>() / v.len() as f64
    };
    let compression = mean_over(x / c, (x + 2.0 * lf) / c);
    let tension = mean_over((2.0 * lt - x) / c, (2.0 * lt - x + 2.0 * lf) / c);
    let left = (lt + 2.0 * lf) / c;
    let rest = (0..t.len())
        .filter(|&k| t[k] > left + 0.15e-6)
        .map(|k| vfs[k].abs())
        .fold(0.0, f64::max);
    let f = Flyer {
        completed: out.summary.status == "completed",
        failed: out
            .summary
            .bodies
            .iter()
            .filter_map(|b| b.failure.as_ref())
            .map(|f| f.failed)
            .sum(),
        compression: compression / -sigma - 1.0,
        tension: tension / sigma - 1.0,
        rest,
    };
    println!(
        "{:?}, {:?}, {} m/s: {f:?}",
        backend(),
        scene.artificial_stress,
        2.0 * up
    );
    f
}

/// The target holds: completed, both plateaus within 2 % of the elastic
/// wave solution (the discretisation's own error, the same on both
/// sides: measured +0.65 % in compression, −0.69 % in tension at 200 m/s)
/// and the free surface at rest (below 5 m/s; measured 1.4).
fn holds(f: &Flyer) {
    assert!(f.completed && f.failed == 0, "{f:?}");
    assert!(f.compression.abs() < 0.02, "{f:?}");
    assert!(f.tension.abs() < 0.02, "{f:?}");
    assert!(f.rest < 5.0, "{f:?}");
}

/// An elastic steel flyer onto an elastic steel target at 200 m/s, 1-D,
/// Δx = 10 µm: the reflected pulse puts the target in 4.6 GPa of tension.
/// The scene asks for no remedy; the default close-pair artificial stress
/// holds it, and at 400 m/s (9.2 GPa) too. With the artificial stress
/// switched off the target tears (measured: tension −34 %, the free
/// surface flying on at 166 m/s); the classic form on every pair holds it
/// too, with its bias (+3.3 % at ε = 0.1: docs/method.md, "Tension").
#[test]
fn elastic_target_holds_its_tension() {
    use sphcontact::scene::{ArtPairs, ArtificialStress};
    let scene = load("scenes/hard/flyer_plate_tension.toml");
    assert_eq!(
        scene.artificial_stress, None,
        "the scene asks for no remedy"
    );
    holds(&flyer_tension(&scene));
    let mut fast = scene.clone();
    fast.bodies[0].velocity = Some(vec![400.0]);
    holds(&flyer_tension(&fast));

    let with = |epsilon: f64, pairs: ArtPairs| {
        let mut s = scene.clone();
        s.artificial_stress = Some(ArtificialStress {
            epsilon,
            n: 4.0,
            pairs,
        });
        flyer_tension(&s)
    };
    let off = with(0.0, ArtPairs::All);
    assert!(off.rest > 50.0 && off.tension < -0.1, "without: {off:?}");
    let classic = with(0.1, ArtPairs::All);
    assert!(classic.completed && classic.rest < 5.0, "{classic:?}");
    assert!(
        classic.tension > 0.0 && classic.tension < 0.05,
        "{classic:?}"
    );
}

#[test]
fn elastic_target_holds_its_tension_leapfrog() {
    on_leapfrog(|| {
        holds(&flyer_tension(&load(
            "scenes/hard/flyer_plate_tension.toml",
        )))
    });
}

#[test]
fn elastic_target_holds_its_tension_gpu() {
    on_gpu(|| {
        holds(&flyer_tension(&load(
            "scenes/hard/flyer_plate_tension.toml",
        )))
    });
}

/// The flyer-plate test of spall: scenes/hard/flyer_plate_tension.toml with
/// a spall pressure `p_spall` on the steel.
fn with_spall(p_spall: f64) -> Scene {
    let mut scene = load("scenes/hard/flyer_plate_tension.toml");
    scene
        .materials
        .get_mut("steel")
        .expect("the scene's material")
        .spall_pressure = Some(p_spall);
    scene
}

/// A spall pressure of 2 GPa, below the 2.82 GPa tensile pressure the
/// reflected pulse brings (0.616 of its 4.58 GPa tensile stress in
/// uniaxial strain): in the elastic wave solution tension first appears
/// one flyer thickness from the free surface (8 mm) at (L_t + L_f)/c_L =
/// 2.056 µs, at full amplitude, and the target spalls there; the scab
/// beyond it carries the superposed pulses' 2 u_p, the flyer's speed, and
/// no stress.
///
/// Measured (CPU midpoint): first failure at +0.04 % of the time; the
/// failed particles, 10, in pairs over 7.93–8.09 mm (the smeared fronts
/// crack the material more than once), centred 0.5 Δx from the plane,
/// the first of them 5.5 Δx right of it, where the ringing behind the
/// reflected front overshoots; the scab at −0.7 % of the flyer's speed.
fn spalls_at_the_plane() {
    let scene = with_spall(2.0e9);
    let mat = material(&scene, "steel");
    let c = ((mat.k + 4.0 * mat.g / 3.0) / mat.rho0).sqrt();
    let v = scene.bodies[0].velocity.as_ref().unwrap()[0];
    let (lf, lt, dx) = (0.002, 0.01, scene.bodies[1].spacing);
    let (plane, t_spall) = (lt - lf, (lt + lf) / c);
    let x0 = sphcontact::model::Model::new(&scene).1.x;
    let out = run(&scene);
    assert_eq!(out.summary.status, "completed");
    let [flyer, target] = [0, 1].map(|b| {
        out.summary.bodies[b]
            .failure
            .clone()
            .expect("a material that can fail")
    });
    assert_eq!(
        (flyer.failed, flyer.first.is_none()),
        (0, true),
        "{flyer:?}"
    );
    let first = target.first.clone().expect("the target spalls");
    let range = out.model.bodies[1].range.clone();
    let failed: Vec<usize> = range
        .clone()
        .filter(|&i| out.state.damage[i] >= 1.0)
        .collect();
    assert_eq!(failed.len(), target.failed);
    let (lo, hi) = failed.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &i| {
        (lo.min(x0[i].x), hi.max(x0[i].x))
    });
    let centre = 0.5 * (lo + hi);
    // The intact pieces on either side of the failed layer.
    let mean_v = |pick: &dyn Fn(f64) -> bool| {
        let ids: Vec<usize> = range.clone().filter(|&i| pick(x0[i].x)).collect();
        let m: f64 = ids.iter().map(|&i| out.model.mass[i]).sum();
        ids.iter()
            .map(|&i| out.model.mass[i] * out.state.v[i].x)
            .sum::<f64>()
            / m
    };
    let scab = mean_v(&|x| x > hi);
    let rest = mean_v(&|x| x < lo);
    println!(
        "{:?}: first failure at {:.4e} s ({:+.2} %), x0 = {:.4e} ({:+.1} Δx); {} failed in [{lo:.4e}, {hi:.4e}], centre {:+.1} Δx; scab {scab:.1} m/s ({:+.2} %), the rest {rest:.2} m/s",
        backend(),
        first.time,
        100.0 * (first.time / t_spall - 1.0),
        first.position_initial[0],
        (first.position_initial[0] - plane) / dx,
        target.failed,
        (centre - plane) / dx,
        100.0 * (scab / v - 1.0),
    );
    assert!((first.time / t_spall - 1.0).abs() < 0.02, "{first:?}");
    assert!((centre - plane).abs() < 2.0 * dx, "centre {centre:e}");
    // Nothing fails away from the plane (the free surface, the contact
    // face): the layer is as wide as the smeared fronts (±8.5 Δx).
    assert!(
        lo > plane - 12.0 * dx && hi < plane + 12.0 * dx,
        "[{lo:e}, {hi:e}]"
    );
    assert!((scab / v - 1.0).abs() < 0.03, "scab {scab}");
    assert!(rest.abs() < 0.05 * v, "the rest {rest}");
}

#[test]
fn target_spalls_at_the_plane() {
    spalls_at_the_plane();
}

#[test]
fn target_spalls_at_the_plane_leapfrog() {
    on_leapfrog(spalls_at_the_plane);
}

#[test]
fn target_spalls_at_the_plane_gpu() {
    on_gpu(spalls_at_the_plane);
}

#[test]
fn target_spalls_at_the_plane_gpu_leapfrog() {
    on_leapfrog(|| on_gpu(spalls_at_the_plane));
}

/// With a spall pressure above the incident stress (4.6 GPa against
/// 4.58) nothing breaks, and the target holds as without one. Between the
/// exact tensile pressure (2.82 GPa) and the discretised one the target
/// still spalls: where the incident pulse's tail crosses the reflected
/// front their ringing adds up, and the tensile pressure near 8 mm peaks
/// at 3.97 GPa, 1.41 times the plateau, for a few ns (docs/hard_cases.md).
#[test]
fn target_holds_below_its_spall_pressure() {
    holds(&flyer_tension(&with_spall(4.6e9)));
}

// ---------------------------------------------------------------------------
// 3. Far from the origin
// ---------------------------------------------------------------------------

/// The scene with every coordinate (shapes and probe points, both axes in
/// 2-D) moved by `-delta`.
fn shifted(scene: &Scene, delta: f64) -> Scene {
    use sphcontact::scene::Shape;
    let mut s = scene.clone();
    let dim = s.dim();
    let shift = |v: &mut Vec<f64>| v.iter_mut().take(dim).for_each(|x| *x -= delta);
    for b in &mut s.bodies {
        match &mut b.shape {
            Shape::Segment { from, to } => {
                *from -= delta;
                *to -= delta;
            }
            Shape::Rectangle { min, max } => {
                shift(min);
                shift(max);
            }
            Shape::Disk { center, .. } | Shape::Ring { center, .. } => shift(center),
        }
    }
    for p in &mut s.probes {
        if let Probe::Particle { at, .. } = p {
            shift(at);
        }
    }
    s
}

/// How far the runs at 1 m and 100 m stray from the run at the origin:
/// the largest difference of the contact force over the history (relative
/// to its peak), of the contact window's end (relative), of the final body
/// velocities (relative to the impact speed `v_scale`) and of the
/// position probes less the shift (m).
struct Stray {
    force: f64,
    window: f64,
    velocity: f64,
    position: f64,
}

/// Tolerances for a run at `offset` (m) against the origin run, as
/// [`Stray`]'s fields. CPU (f64): a coordinate near X is rounded to
/// `ε X` (ε = 2.2e-16), and the penalty spring (stiffness `M/Δx` over two
/// half-spacing layers) turns a gap error `ε X` into a pressure error
/// `M ε X/Δx`, that is `(c_L/v) (ε X/Δx)` of the contact stress `Z v`: with
/// four roundings in a gap (two coordinates, their shift, the difference)
/// and a factor 2 of margin, `8 (c_L/v) ε X/Δx` for the force history, the
/// contact end and the velocities; a mean position sums `n` coordinates, so
/// `n ε X`. GPU (f32): positions are relative to a grid origin held in f64
/// on the host, so the offset changes only the rounding of each particle's
/// f32 offset inside its cell (1e-7 Δx, 1 unit in the last place); one
/// flipped rounding on a contact face moves the pressure by
/// `(c_L/v)·1e-7·(a few)` ≈ 1e-4 of it (measured 4e-5 at 100 m): force
/// history and contact end within 1e-3, velocities within 1e-5 of the
/// impact speed, positions within 1e-8 m (f32 resolution of a
/// centimetre-size body, 2e-4 Δx; an absolute f32 coordinate near 100 m
/// would be off by up to 3.8e-6 m).
fn tolerances(offset: f64, c_over_v: f64, spacing: f64, n: usize) -> Stray {
    if backend() == sphcontact::scene::Backend::Gpu {
        return Stray {
            force: 1e-3,
            window: 1e-3,
            velocity: 1e-5,
            position: 1e-8,
        };
    }
    let round = f64::EPSILON * offset.max(0.01);
    let rel = 8.0 * c_over_v * round / spacing;
    Stray {
        force: rel,
        window: rel,
        velocity: rel,
        position: n as f64 * round,
    }
}

/// `far` (placed near 100 m) run moved to the origin, to 1 m and as it is.
fn runs_at_offsets(far: &Scene) -> Vec<(f64, RunOutput)> {
    [0.0, 1.0, 100.0]
        .iter()
        .map(|&o| (o, run(&shifted(far, 100.0 - o))))
        .collect()
}

/// The runs of [`runs_at_offsets`] away from the origin conserve and give
/// the origin run's answers within [`tolerances`] (impact speed 10 m/s,
/// `n` particles in a mean position).
fn assert_offsets_match(
    what: &str,
    far: &Scene,
    runs: &[(f64, RunOutput)],
    spacing: f64,
    n: usize,
) {
    let steel = material(far, "steel");
    let origin = &runs[0].1;
    for (o, out) in &runs[1..] {
        assert_conserved(far, out);
        let s = stray(origin, out, *o, 10.0);
        // The contact stress is Z v0 with v0 = 10 m/s per body.
        let tol = tolerances(*o, steel.c_l / 10.0, spacing, n);
        println!(
            "{what} at {o} m: force {:.2e} (tolerance {:.1e}), contact end {:.2e}, velocity {:.2e}, position {:.2e} m (tolerance {:.1e})",
            s.force, tol.force, s.window, s.velocity, s.position, tol.position
        );
        assert!(
            s.force < tol.force,
            "{o} m: force history off by {:e} of the peak",
            s.force
        );
        assert!(
            s.window < tol.window,
            "{o} m: end of contact off by {:e}",
            s.window
        );
        assert!(
            s.velocity < tol.velocity,
            "{o} m: rebound off by {:e} of v0",
            s.velocity
        );
        assert!(
            s.position < tol.position,
            "{o} m: positions off by {:e} m",
            s.position
        );
    }
}

fn stray(origin: &RunOutput, far: &RunOutput, offset: f64, v_scale: f64) -> Stray {
    let f0 = column(origin, "contact_force");
    let f1 = column(far, "contact_force");
    let peak = f0.iter().cloned().fold(0.0, f64::max);
    let force = f0
        .iter()
        .zip(&f1)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / peak;
    let t = &origin.history.times;
    let (_, e0) = contact_window(t, &f0);
    let (_, e1) = contact_window(&far.history.times, &f1);
    let velocity = ["velocity_left", "velocity_right"]
        .iter()
        .map(|n| {
            (column(origin, n).last().unwrap() - column(far, n).last().unwrap()).abs() / v_scale
        })
        .fold(0.0, f64::max);
    let position = origin
        .history
        .names
        .iter()
        .filter(|n| n.starts_with("position"))
        .flat_map(|n| {
            column(origin, n)
                .into_iter()
                .zip(column(far, n))
                .map(|(a, b)| (b - offset - a).abs())
        })
        .fold(0.0, f64::max);
    Stray {
        force,
        window: (e1 / e0 - 1.0).abs(),
        velocity,
        position,
    }
}

/// The paper's bars with the contact face at 100 m (scenes/hard/
/// far_bars_steel.toml), moved back to the origin and to 1 m: the runs at
/// 1 m and 100 m must give the origin run's answers to round-off
/// ([`tolerances`]: at 100 m on the CPU 2e-6 of the contact force and 2e-12 m
/// of position; on the GPU 1e-3 and 1e-8 m). The origin run itself meets
/// the paper's case 1 (plateau and separation within 1 %, rebound within
/// 5 %: tests/paper_bars.rs).
fn far_bars() {
    let far = load("scenes/hard/far_bars_steel.toml");
    let steel = material(&far, "steel");
    let exact = bar_impact(&steel, 0.005, 10.0, &steel, 0.005, -10.0);
    let runs = runs_at_offsets(&far);
    let origin = &runs[0].1;
    assert_conserved(&far, origin);
    let f = column(origin, "contact_force");
    let (_, t_sep) = contact_window(&origin.history.times, &f);
    assert!((t_sep / exact.separation_time - 1.0).abs() < 0.01);
    let k = origin
        .history
        .times
        .iter()
        .position(|&x| x > 0.5 * t_sep)
        .unwrap();
    assert!((f[k] / -exact.contact_stress - 1.0).abs() < 0.01);
    let vl = *column(origin, "velocity_left").last().unwrap();
    assert!((vl / exact.final_velocity_1 - 1.0).abs() < 0.05);

    assert_offsets_match("bars", &far, &runs, 5e-5, 100);
}

#[test]
fn far_from_origin_bars() {
    far_bars();
}

#[test]
fn far_from_origin_bars_gpu() {
    on_gpu(far_bars);
}

/// Two coarse polar-lattice steel disks touching at (100 m, 100 m)
/// (scenes/hard/far_disks_polar.toml), moved back to the origin and to
/// (1 m, 1 m): the runs there and here must give the origin run's answers
/// to round-off ([`tolerances`], the 2-D contact's partner interpolation
/// in the chain). The origin run makes contact and the disks separate
/// (restitution between 0.8 and 1 at this coarse resolution; the converged
/// answer is tests/paper_disks.rs's).
fn far_disks() {
    let far = load("scenes/hard/far_disks_polar.toml");
    let runs = runs_at_offsets(&far);
    let origin = &runs[0].1;
    assert_conserved(&far, origin);
    let (t0, t1) = contact_window(&origin.history.times, &column(origin, "contact_force"));
    assert!(
        t1 > t0 && t1 < far.simulation.end_time,
        "the disks separate"
    );
    let restitution = (column(origin, "velocity_right").last().unwrap()
        - column(origin, "velocity_left").last().unwrap())
        / 10.0;
    assert!(
        restitution > 0.8 && restitution <= 1.0,
        "restitution {restitution}"
    );

    let n = origin.summary.bodies[0].particles;
    assert_offsets_match("disks", &far, &runs, 5e-4, n);
}

#[test]
fn far_from_origin_disks() {
    far_disks();
}

#[test]
fn far_from_origin_disks_gpu() {
    on_gpu(far_disks);
}

// ---------------------------------------------------------------------------
// 4. Long run
// ---------------------------------------------------------------------------

/// A free 5 mm steel bar ringing for 20 wave transits (scenes/hard/
/// long_ringing_bar.toml: two glued halves at ±10 m/s). Exact: each half's
/// mean velocity is a triangle wave between ±v0 crossing zero at
/// (k + ½) transits; energy and momentum constant.
///
/// What the method should keep, and the bounds:
/// * momentum to round-off and the run stable to the end (any instability
///   stops the run and fails it);
/// * total energy (kinetic + internal; the viscosity only moves energy
///   between them): the midpoint rule is not exactly conservative and
///   slightly amplifies the highest modes, which the initial velocity jump
///   excites, so the energy creeps up, most while the jump is sharp:
///   measured +1.66e-3 over the first 10 transits and +0.43e-3 over the
///   next 10, +2.09e-3 in all (both backends). Bound: below 4e-3 over the 20 transits, and
///   the second half drifting less than the first (the drift does not
///   accelerate, as it would in an instability);
/// * still ringing with a bounded amplitude: the largest |mean velocity| of
///   a half over the last two transits between 0.8 v0 and v0 (the viscosity
///   damps the ringing slowly: measured 0.901), exactly one zero crossing
///   per transit, each within 3 % of a transit of the exact (k + ½)
///   transits (measured 1.1 %: the lattice's dispersion is small at these
///   wavelengths).
///
/// The leapfrog neither amplifies nor damps an undamped oscillation, so its
/// energy holds far better: measured +8.6e-5 over the 20 transits, the
/// bound `energy_bound` it is held to is 2e-4.
fn long_ringing() {
    long_ringing_within(4e-3);
}

fn long_ringing_within(energy_bound: f64) {
    let scene = load("scenes/hard/long_ringing_bar.toml");
    let steel = material(&scene, "steel");
    let v0 = 10.0;
    let transit = 0.005 / steel.c_l;
    let transits = scene.simulation.end_time / transit;
    assert!(transits >= 20.0 - 1e-3, "{transits} transits");
    let out = run(&scene);
    assert_conserved(&scene, &out);
    let t = &out.history.times;
    let e = column(&out, "energy_total");
    let half = t.iter().position(|&x| x >= 0.5 * t[t.len() - 1]).unwrap();
    let (e0, e_half, e_end) = (e[0], e[half], *e.last().unwrap());
    let (d1, d2) = (e_half / e0 - 1.0, e_end / e_half - 1.0);
    println!(
        "energy drift: {:.3e} over 20 transits ({d1:.3e} first half, {d2:.3e} second)",
        e_end / e0 - 1.0
    );
    assert!(
        (e_end / e0 - 1.0).abs() < energy_bound,
        "energy drift {:e}",
        e_end / e0 - 1.0
    );
    assert!(
        d2.abs() < d1.abs(),
        "the energy drift accelerates: {d1:e} then {d2:e}"
    );

    let v = column(&out, "velocity_left");
    let late = v
        .iter()
        .zip(t)
        .filter(|(_, &tk)| tk > t[t.len() - 1] - 2.0 * transit)
        .map(|(x, _)| x.abs())
        .fold(0.0, f64::max);
    println!(
        "ringing amplitude over the last two transits: {:.4} v0",
        late / v0
    );
    assert!(late > 0.8 * v0 && late <= v0, "amplitude {late}");
    let mut worst: f64 = 0.0;
    let mut crossings = 0;
    for k in 1..t.len() {
        if v[k - 1] * v[k] < 0.0 {
            let tc = t[k - 1] + (t[k] - t[k - 1]) * v[k - 1] / (v[k - 1] - v[k]);
            let phase = tc / transit - 0.5;
            worst = worst.max((phase - phase.round()).abs());
            crossings += 1;
        }
    }
    println!("{crossings} zero crossings, worst {worst:.4} of a transit from the exact");
    assert_eq!(crossings, 20, "one zero crossing per transit");
    assert!(worst < 0.03, "crossing off by {worst} of a transit");
}

#[test]
fn long_ringing_free_bar() {
    long_ringing();
}

#[test]
fn long_ringing_free_bar_leapfrog() {
    on_leapfrog(|| long_ringing_within(2e-4));
}

#[test]
fn long_ringing_free_bar_gpu() {
    on_gpu(long_ringing);
}

// ---------------------------------------------------------------------------
// 5. Order of the time integration
// ---------------------------------------------------------------------------

/// Both integrators are second order in time (docs/method.md §9): the ringing
/// bar of the long run, to two transits, at CFL numbers 0.2, 0.1 and 0.05
/// against a run at 0.0125 on the same particles. Halving the step must
/// cut the largest error of a half's mean velocity about fourfold (at
/// least 3.5×; measured 4.1 and 4.2 for the midpoint rule, 4.2 and 4.2 for
/// the leapfrog). A first-order term fails it: the leapfrog with the
/// viscosity's reconstruction mixing `∇v` at `n+½` with velocities at
/// `n+1` gave 1.9 and 2.2.
fn second_order(integrator: Integrator) {
    let base = load("scenes/hard/long_ringing_bar.toml");
    let at = |cfl: f64| {
        let mut scene = base.clone();
        scene.simulation.end_time = 1.7e-6;
        scene.simulation.cfl = cfl;
        scene.simulation.integrator = integrator;
        let out = run(&scene);
        column(&out, "velocity_left")
    };
    let reference = at(0.0125);
    let err: Vec<f64> = [0.2, 0.1, 0.05]
        .iter()
        .map(|&c| {
            let v = at(c);
            assert_eq!(v.len(), reference.len());
            v.iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
        })
        .collect();
    let ratios = [err[0] / err[1], err[1] / err[2]];
    println!("{integrator}: errors {err:?}, ratios {ratios:?}");
    assert!(err[2] > 0.0 && err[2] < 1e-3, "errors {err:?}");
    for r in ratios {
        assert!(
            r > 3.5,
            "{integrator}: error ratios {ratios:?}, not second order"
        );
    }
}

#[test]
fn midpoint_rule_is_second_order() {
    second_order(Integrator::Midpoint);
}

#[test]
fn leapfrog_is_second_order() {
    second_order(Integrator::Leapfrog);
}
