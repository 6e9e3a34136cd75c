//! The paper's 2-D case (docs/method.md §10, case 3): two steel disks, R = 5 mm,
//! closing at 10 m/s, on the square and on the polar lattice (R/Δx = 25),
//! against the quasi-static Hertz bracket computed by `validation::exact`.

mod common;
use common::*;
use sphcontact::validation::exact::{hertz_c_inertia, hertz_disks, HERTZ_C_JOHNSON};

fn check_lattice(path: &str) {
    let scene = load(path);
    let steel = material(&scene, "steel");
    // The bracket: C = 1 is the softer, longer bound; the inertia C the stiffer.
    let soft = hertz_disks(&steel, 0.005, 10.0, HERTZ_C_JOHNSON);
    let stiff = hertz_disks(&steel, 0.005, 10.0, hertz_c_inertia(steel.nu));
    let out = run(&scene);
    assert_conserved(&scene, &out);
    let t = &out.history.times;
    let f = column(&out, "contact_force");
    let peak = f.iter().cloned().fold(0.0, f64::max);
    let (t0, t1) = contact_window(t, &f);
    let duration = t1 - t0;
    println!(
        "{path}: peak {:.4} MN/m (bracket {:.4}–{:.4}), contact {:.3} µs (bracket {:.3}–{:.3}), from {:.3} µs",
        peak / 1e6,
        soft.peak_force / 1e6,
        stiff.peak_force / 1e6,
        duration * 1e6,
        stiff.contact_time * 1e6,
        soft.contact_time * 1e6,
        t0 * 1e6
    );
    assert_in_hertz_bracket(peak, duration, &soft, &stiff, 0.1);
    // The disks separate and fly apart: restitution just below 1 (some
    // energy stays in vibration), never above.
    let vl = *column(&out, "velocity_left").last().unwrap();
    let vr = *column(&out, "velocity_right").last().unwrap();
    let restitution = (vr - vl) / 10.0;
    assert!(
        restitution > 0.9 && restitution <= 1.0,
        "restitution {restitution}"
    );
    assert_never_pulls(&out, 0, "velocity_left");
    // The discrete spring is not exactly conservative (its gap is not the
    // time integral of the relative normal velocity on a curved face): at
    // R/Δx = 25 it loses 0.7 % of the impact energy (polar lattice,
    // measured), and 0.08 % at R/Δx = 50 (tests/validation.rs).
    let s = &out.summary;
    let loss = s.energy_spring_loss / s.energy_initial;
    println!("{path}: spring loss {loss:.3e} of the impact energy");
    assert!(
        loss < 1e-2,
        "the penalty spring lost {loss:e} of the energy"
    );
}

#[test]
fn disks_square_lattice() {
    check_lattice("scenes/paper/disks_square.toml");
}

#[test]
fn disks_polar_lattice() {
    check_lattice("scenes/paper/disks_polar.toml");
}

/// Disks touching at rest stay at rest, and a translating disk stays
/// stress-free. On the square lattice the facet gap is positive and nothing
/// moves at all; on the polar lattice the interpolated partner surface is
/// exact to second order in the angle it spans, and the residual overlap
/// (≈ 1e-9 m, 5e-6 Δx) gives a drift of about 2e-4 m/s over 2 µs (2e-5 of
/// the paper's impact speed). The force it makes is bounded by an overlap
/// of 1e-5 Δx on the spring of two Δx/2 layers (`k = M/Δx`) over a width of
/// 2Δx: `2 M · 1e-5 Δx` ≈ 1.1 kN/m, 1e-3 of the impact's peak (measured:
/// 460 N/m).
#[test]
fn disks_at_rest_and_translating() {
    let polar = load("scenes/paper/disks_polar.toml");
    let m = material(&polar, "steel").m;
    let f_polar = 2.0 * m * 1e-5 * polar.bodies[0].spacing;
    for (path, v_tol, f_tol) in [
        ("scenes/paper/disks_square.toml", 1e-9, 1e-9),
        ("scenes/paper/disks_polar.toml", 5e-4, f_polar),
    ] {
        let mut scene = load(path);
        scene.bodies[0].velocity = Some(vec![0.0, 0.0]);
        scene.bodies[1].velocity = Some(vec![0.0, 0.0]);
        scene.simulation.end_time = 2e-6;
        let out = run(&scene);
        for (name, tol) in [
            ("velocity_left", v_tol),
            ("velocity_right", v_tol),
            ("contact_force", f_tol),
        ] {
            let worst = column(&out, name)
                .iter()
                .fold(0.0f64, |a, &b| a.max(b.abs()));
            println!("{path}: at rest, worst |{name}| = {worst:e}");
            assert!(worst < tol, "{path}: {name} = {worst} for disks at rest");
        }
    }
    let mut scene = load("scenes/paper/disks_polar.toml");
    scene.bodies.truncate(1);
    scene
        .probes
        .retain(|p| p.name() == "von_mises_a" || p.name() == "velocity_left");
    scene.bodies[0].velocity = Some(vec![10.0, -3.0]);
    scene.simulation.end_time = 2e-6;
    let out = run(&scene);
    assert_conserved(&scene, &out);
    let worst = column(&out, "von_mises_a")
        .iter()
        .fold(0.0f64, |a, &b| a.max(b.abs()));
    assert!(worst < 1e-3, "translating disk: von Mises {worst} Pa");
}

// The same physics on the GPU backend (f32 on the device).

#[test]
fn disks_square_lattice_gpu() {
    on_gpu(disks_square_lattice);
}

/// The polar disks' GPU run is held to the CPU's (which meets the
/// bracket) in tests/gpu_runs/, to 0.5 %; this run of the bracket on the
/// device is a minute and more on a software adapter.
#[test]
#[ignore]
fn disks_polar_lattice_gpu() {
    on_gpu(disks_polar_lattice);
}

#[test]
fn disks_at_rest_and_translating_gpu() {
    on_gpu(disks_at_rest_and_translating);
}

// The same bracket with the midpoint rule, two evaluations a step (CPU
// path; the default is the leapfrog).

#[test]
fn disks_square_lattice_midpoint() {
    on_midpoint(disks_square_lattice);
}

#[test]
fn disks_polar_lattice_midpoint() {
    on_midpoint(disks_polar_lattice);
}

#[test]
fn disks_at_rest_and_translating_midpoint() {
    on_midpoint(disks_at_rest_and_translating);
}
