//! The paper's cases at the edge of stability: a clear stop or a good answer.

use super::*;
use sphcontact::scene::Integrator;
use std::process::Output;

const BIN: &str = env!("CARGO_BIN_EXE_sphcontact");

/// How a run through the command line ended.
#[derive(Debug, PartialEq)]
enum Outcome {
    /// Exit status 0: the stable contract was checked.
    Completed,
    /// Exit status 1 with the instability message: that contract was checked.
    Unstable,
}

/// Run `scene` through the command line on `backend` and check the contract
/// of whichever way it ended: completed (status 0: every history value
/// finite, momentum to round-off, energy balance within 1 %, and the main
/// answers by `answers`) or stopped (status 1: one instability message
/// naming step, time, body, particle and quantity; summary.json parses,
/// marked failed, with that message and the time reached; history.csv
/// parses, finite, up to the failure). Anything else fails.
fn run_at_the_edge(
    scene: &sphcontact::Scene,
    backend: &str,
    answers: impl Fn(&[String], &[Vec<f64>]),
) -> Outcome {
    let tmp = tempfile::tempdir().unwrap();
    let out_dir = tmp.path().join("out");
    let (out, stderr) = run_cli(scene, backend, &out_dir);
    assert!(!stderr.contains("panicked"), "a panic:\n{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap())
            .expect("summary.json parses");
    let (names, rows) = read_history(&out_dir.join("history.csv"));
    assert!(!rows.is_empty(), "no history rows");
    assert!(
        rows.iter().flatten().all(|x| x.is_finite()),
        "a non-finite value in the history"
    );
    let round_off = if backend == "gpu" { 1e-6 } else { 1e-12 };
    match out.status.code() {
        Some(0) => {
            assert_eq!(summary["status"], "completed");
            let end = scene.simulation.end_time;
            assert!(
                (rows.last().unwrap()[0] / end - 1.0).abs() < 1e-9,
                "rows to the end"
            );
            let scale: f64 = summary["bodies"]
                .as_array()
                .unwrap()
                .iter()
                .zip(&scene.bodies)
                .map(|(b, sb)| {
                    let v = sb.velocity.clone().unwrap_or_default();
                    b["mass"].as_f64().unwrap() * v.iter().map(|x| x * x).sum::<f64>().sqrt()
                })
                .sum();
            let p0 = summary["momentum_initial"].as_array().unwrap();
            let p1 = summary["momentum_final"].as_array().unwrap();
            for (a, b) in p0.iter().zip(p1) {
                let (a, b) = (a.as_f64().unwrap(), b.as_f64().unwrap());
                assert!((a - b).abs() <= round_off * scale, "momentum {a} -> {b}");
            }
            let e0 = summary["energy_initial"].as_f64().unwrap();
            let e1 = summary["energy_final"].as_f64().unwrap();
            let loss = summary["energy_spring_loss"].as_f64().unwrap();
            let balance = (e1 + loss) / e0 - 1.0;
            println!("{backend}: completed, energy balance {balance:+.3e}");
            assert!(balance.abs() < 1e-2, "energy balance {balance:e}");
            answers(&names, &rows);
            Outcome::Completed
        }
        Some(1) => {
            let (line, msg, _) = failed_run(&out_dir, &stderr);
            println!("{backend}: {line}");
            let Message {
                step,
                time,
                body,
                particle,
                ..
            } = msg;
            assert!(step >= 1, "step {step}");
            assert!(
                time > 0.0 && time < scene.simulation.end_time,
                "time {time:e}"
            );
            let (model, _) = sphcontact::model::Model::new(scene);
            let b = model
                .bodies
                .iter()
                .find(|b| b.name == body)
                .unwrap_or_else(|| panic!("no body '{body}'"));
            assert!(particle < b.range.len(), "particle {particle} of '{body}'");
            Outcome::Unstable
        }
        other => panic!("exit status {other:?}:\n{stderr}"),
    }
}

/// `sphcontact run --quiet` of `scene` on `backend` into `out_dir` (its
/// scene file beside it), with its stderr.
fn run_cli(scene: &sphcontact::Scene, backend: &str, out_dir: &Path) -> (Output, String) {
    std::fs::create_dir_all(out_dir).unwrap();
    let path = out_dir.with_extension("toml");
    std::fs::write(&path, scene.to_toml()).unwrap();
    let out = Command::new(BIN)
        .args(["run", "--quiet", "--backend", backend, "--out"])
        .arg(out_dir)
        .arg(&path)
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    (out, stderr)
}

/// The bars' main answers (docs/method.md §10, case 1) if the run holds: the
/// contact pressure's mean over the middle 60 % of the contact within 2 % of
/// −σ = ρ0 c_L v0, separation within 2 % of 2L/c_L, rebound within 10 % of
/// −10 m/s (docs/method.md §11: 0.94–0.97 at 100 particles per bar).
fn bars_answers(scene: &sphcontact::Scene) -> impl Fn(&[String], &[Vec<f64>]) {
    let steel = material(scene, "steel");
    let exact =
        sphcontact::validation::exact::bar_impact(&steel, 0.005, 10.0, &steel, 0.005, -10.0);
    move |names, rows| {
        let col = |n: &str| -> Vec<f64> {
            let k = names.iter().position(|x| x == n).unwrap();
            rows.iter().map(|r| r[k]).collect()
        };
        let t = col("time");
        let p = col("contact_pressure");
        let (_, t_sep) = contact_window(&t, &p);
        let mid: Vec<f64> = (0..t.len())
            .filter(|&k| t[k] > 0.2 * t_sep && t[k] < 0.8 * t_sep)
            .map(|k| p[k])
            .collect();
        let plateau = mid.iter().sum::<f64>() / mid.len() as f64;
        let v = *col("velocity_left").last().unwrap();
        println!("bars: plateau {plateau:.4e} Pa, separation {t_sep:.4e} s, rebound {v:.3} m/s");
        assert!(
            (plateau / -exact.contact_stress - 1.0).abs() < 0.02,
            "plateau {plateau:e}"
        );
        assert!(
            (t_sep / exact.separation_time - 1.0).abs() < 0.02,
            "separation {t_sep:e}"
        );
        assert!(
            (v / exact.final_velocity_1 - 1.0).abs() < 0.1,
            "rebound {v}"
        );
    }
}

/// The coarse disks' main answers (docs/method.md §10, case 3) if the run holds:
/// peak force and contact time within 15 % of the Hertz bracket (R/Δx = 10
/// is coarse: docs/method.md §8.4 finds the polar lattice 6 % low at 20),
/// restitution in [0.8, 1].
fn disks_answers(scene: &sphcontact::Scene) -> impl Fn(&[String], &[Vec<f64>]) {
    use sphcontact::validation::exact::hertz_disks;
    let steel = material(scene, "steel");
    let soft = hertz_disks(&steel, 0.005, 10.0, HERTZ_C_JOHNSON);
    let stiff = hertz_disks(&steel, 0.005, 10.0, hertz_c_inertia(steel.nu));
    move |names, rows| {
        let col = |n: &str| -> Vec<f64> {
            let k = names.iter().position(|x| x == n).unwrap();
            rows.iter().map(|r| r[k]).collect()
        };
        let t = col("time");
        let f = col("contact_force");
        let peak = f.iter().cloned().fold(0.0, f64::max);
        let (t0, t1) = contact_window(&t, &f);
        let e =
            (col("velocity_right").last().unwrap() - col("velocity_left").last().unwrap()) / 10.0;
        println!(
            "disks: peak {peak:.4e} N/m, contact {:.4e} s, restitution {e:.4}",
            t1 - t0
        );
        assert_in_hertz_bracket(peak, t1 - t0, &soft, &stiff, 0.15);
        assert!((0.8..=1.0).contains(&e), "restitution {e}");
    }
}

fn edge_backends() -> Vec<&'static str> {
    let mut b = vec!["cpu"];
    if gpu().is_some() {
        b.push("gpu");
    }
    b
}

/// `scene` stepped by `integrator`.
fn stepped_by(scene: &sphcontact::Scene, integrator: Integrator) -> sphcontact::Scene {
    let mut scene = scene.clone();
    scene.simulation.integrator = integrator;
    scene
}

/// The paper's bars at CFL 0.9 with α = β = 0.01 (scenes/hard/bars_stiff.toml).
/// Either contract may hold (see `run_at_the_edge`); what each integrator
/// does is asserted so that a change is noticed. The step is the contact's
/// limit (`Model::contact_dt`), an effective CFL number of 0.59. The
/// leapfrog completes them within the checks on both backends. The
/// midpoint rule, which amplifies an undamped mode by sqrt(1 + (ωΔt)⁴/4)
/// a step, stops on the energy guard (CPU: step 260, 1.58 µs, left bar
/// particle 1, internal energy held below zero); at the full CFL 0.9
/// step it stopped at step 7.
#[test]
fn stiff_bars_hold_on_the_leapfrog_and_stop_on_the_midpoint_rule() {
    let scene = load("scenes/hard/bars_stiff.toml");
    hold_on_the_leapfrog_stop_on_the_midpoint_rule(&scene, || bars_answers(&scene));
}

/// `scene` completes within `answers` on the leapfrog and stops with the
/// instability message on the midpoint rule, on every backend.
fn hold_on_the_leapfrog_stop_on_the_midpoint_rule<A: Fn(&[String], &[Vec<f64>])>(
    scene: &sphcontact::Scene,
    answers: impl Fn() -> A,
) {
    for backend in edge_backends() {
        for (integrator, expect) in [
            (Integrator::Leapfrog, Outcome::Completed),
            (Integrator::Midpoint, Outcome::Unstable),
        ] {
            let outcome = run_at_the_edge(&stepped_by(scene, integrator), backend, answers());
            assert_eq!(outcome, expect, "{backend}, {integrator}");
        }
    }
}

/// A coarse disk pair at CFL 0.9 with α = β = 0.01
/// (scenes/hard/disks_stiff.toml), at the contact's step limit as above:
/// the leapfrog completes within the Hertz bracket on both backends
/// (CPU: peak 1.128e6 N/m), the midpoint rule stops on the energy guard
/// (CPU: step 56, 3.39 µs, left disk particle 311 by the contact).
#[test]
fn stiff_disks_hold_on_the_leapfrog_and_stop_on_the_midpoint_rule() {
    let scene = load("scenes/hard/disks_stiff.toml");
    hold_on_the_leapfrog_stop_on_the_midpoint_rule(&scene, || disks_answers(&scene));
}

/// The rubber rings with the hourglass control at α_hg = 1.2 on the
/// leapfrog, past the leapfrog's stability with the control (docs/method.md,
/// "Hourglass control"; it holds them at 1.0 since its viscosity sees the
/// damping-weighted predicted velocity, and stopped at 1.0 with the plain
/// one): a local blow-up drives particles to negative internal energies.
/// The ledger closes (the leapfrog's compatible kicks, §9), so the total
/// holds; what shows is the internal energy those particles hold below
/// zero, which passes half the initial energy. The energy guard stops the
/// run on both backends at the same step (measured: step 63, 8.9 µs,
/// particle 201, on both; step 62 before the contact's step limit,
/// `Model::contact_dt`).
#[test]
fn rings_past_the_leapfrogs_hourglass_limit_stop_on_energy_held_below_zero() {
    let mut scene = load("scenes/hard/rubber_rings.toml");
    with_hourglass_control(&mut scene, 1.2);
    scene.simulation.integrator = Integrator::Leapfrog;
    scene.simulation.end_time = 2.0e-4;
    let tmp = tempfile::tempdir().unwrap();
    let mut steps = Vec::new();
    for backend in edge_backends() {
        let out_dir = tmp.path().join(backend);
        let (out, stderr) = run_cli(&scene, backend, &out_dir);
        assert_eq!(out.status.code(), Some(1), "{backend}:\n{stderr}");
        let (line, msg, _) = failed_run(&out_dir, &stderr);
        println!("{backend}: {line}");
        assert!(
            msg.quantity
                .starts_with("internal energy held below zero (over 0.5 times"),
            "{backend}: {line}"
        );
        steps.push(msg.step);
    }
    assert!(steps.iter().all(|&s| s == steps[0]), "steps {steps:?}");
}

/// The same two scenes at the default CFL number (0.3) and viscosity, on
/// the CPU path: the completed branch of `run_at_the_edge` holds, so its
/// checks are live (measured: bars energy balance 1e-3, disks within the
/// bracket).
#[test]
fn edge_check_accepts_the_stable_settings() {
    for (path, bars) in [
        ("scenes/hard/bars_stiff.toml", true),
        ("scenes/hard/disks_stiff.toml", false),
    ] {
        let mut scene = load(path);
        scene.simulation.cfl = 0.3;
        scene.artificial_viscosity = None;
        let outcome = if bars {
            run_at_the_edge(&scene, "cpu", bars_answers(&scene))
        } else {
            run_at_the_edge(&scene, "cpu", disks_answers(&scene))
        };
        assert_eq!(outcome, Outcome::Completed, "{path} at CFL 0.3");
    }
}

/// CFL 0.9 with the default viscosity's α = β = 0.75. Before the energy
/// guard (`Model::guards_energy`) both scenes completed with exit status 0
/// and silently wrong energy (the bars with 28 times their initial energy,
/// the disks with 135 times, restitution 1.29). At the full CFL 0.9 step
/// the midpoint rule stopped both, and the leapfrog completed the disks
/// with the contact chattering, opening and closing every 15 steps at
/// twice the Hertz force (the spring at `ω Δt ≈ 1.5` on particles the
/// disk's stresses load too). At the contact's step limit
/// (`Model::contact_dt`, here an effective CFL number of 0.59) both
/// integrators complete both scenes within every check of the completed
/// branch, with the default viscosity (the Riemann form) and with the
/// former one (Monaghan's form, plain at surfaces). At CFL 0.75 (the
/// limit binds too) the default completes the disks on both backends.
/// All asserted.
#[test]
fn stiff_settings_with_default_viscosity_are_never_silent_garbage() {
    use sphcontact::scene::{ArtificialViscosity, ViscosityForm};
    for (path, bars) in [
        ("scenes/hard/bars_stiff.toml", true),
        ("scenes/hard/disks_stiff.toml", false),
    ] {
        for former in [false, true] {
            let mut scene = load(path);
            scene.artificial_viscosity = former.then(|| ArtificialViscosity {
                form: ViscosityForm::Monaghan,
                reconstruct_surfaces: false,
                ..Default::default()
            });
            for integrator in [Integrator::Leapfrog, Integrator::Midpoint] {
                let scene = stepped_by(&scene, integrator);
                for backend in edge_backends() {
                    let outcome = if bars {
                        run_at_the_edge(&scene, backend, bars_answers(&scene))
                    } else {
                        run_at_the_edge(&scene, backend, disks_answers(&scene))
                    };
                    assert_eq!(
                        outcome,
                        Outcome::Completed,
                        "{path}, former default {former}, {integrator} on {backend}"
                    );
                }
            }
        }
    }
    let mut scene = load("scenes/hard/disks_stiff.toml");
    scene.simulation.cfl = 0.75;
    scene.artificial_viscosity = None;
    for backend in edge_backends() {
        let outcome = run_at_the_edge(&scene, backend, disks_answers(&scene));
        assert_eq!(
            outcome,
            Outcome::Completed,
            "disks at CFL 0.75 on {backend}"
        );
    }
}
