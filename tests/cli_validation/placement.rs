//! Placement, jitter and the time step.

use super::*;

/// The rules that need the particles: empty shapes, overlapping bodies, a
/// fixed `dt` above the CFL step at t = 0.
#[test]
fn placement() {
    check_cases(&[
        case(
            "empty_segment",
            // 4e-5 m is less than half the 1e-4 m spacing: no particle.
            &[(
                RIGHT_SHAPE,
                "shape = { kind = \"segment\", from = 0.0, to = 4.0e-5 }",
            )],
            "bodies[1].shape",
        )
        .also(&["right"]),
        case(
            "too_many_particles",
            // A spacing absurdly small for its shape is refused before any
            // particle is allocated.
            &[(
                "spacing = 1.0e-4\nvelocity = [10.0]",
                "spacing = 1.0e-300\nvelocity = [10.0]",
            )],
            "bodies[0].spacing",
        )
        .also(&["particles"]),
        case(
            "empty_disk",
            &[("radius = 0.001", "radius = 5.0e-5")],
            "bodies[1].shape",
        )
        .also(&["disk"])
        .two_d(),
        case(
            "overlapping_segments",
            &[(
                RIGHT_SHAPE,
                "shape = { kind = \"segment\", from = -0.0005, to = 0.0005 }",
            )],
            "bodies[1].shape",
        )
        .also(&["overlap", "left"]),
        case(
            "overlapping_rectangle_and_disk",
            &[("center = [0.0, 0.001]", "center = [0.0, 0.0]")],
            "bodies[1].shape",
        )
        .also(&["overlap"])
        .two_d(),
        case(
            "dt_above_cfl",
            &[("dimension = 1", "dimension = 1\ndt = 1.0e-6")],
            "simulation.dt",
        )
        .also(&["CFL"]),
    ]);
}

/// The optional placement jitter (`jitter`, a fraction of the spacing in
/// [0, 0.5), and its `seed`): out-of-range and mistyped values.
#[test]
fn jitter_and_seed() {
    check_cases(&[
        case(
            "jitter_negative",
            &[(RIGHT_VELOCITY, "velocity = [-10.0]\njitter = -0.1")],
            "bodies[1].jitter",
        )
        .also(&["-0.1", "0.5"]),
        case(
            "jitter_half_a_spacing",
            &[(RIGHT_VELOCITY, "velocity = [-10.0]\njitter = 0.5")],
            "bodies[1].jitter",
        )
        .also(&["< 0.5", "got 0.5"]),
        case(
            "jitter_not_a_number",
            &[(RIGHT_VELOCITY, "velocity = [-10.0]\njitter = nan")],
            "bodies[1].jitter",
        )
        .also(&["NaN"]),
        case(
            "jitter_mistyped",
            &[(RIGHT_VELOCITY, "velocity = [-10.0]\njitter = \"some\"")],
            "bodies[1].jitter",
        )
        .located(),
        case(
            "seed_negative",
            &[(
                RIGHT_VELOCITY,
                "velocity = [-10.0]\njitter = 0.1\nseed = -3",
            )],
            "bodies[1].seed",
        )
        .located(),
        case(
            "seed_fractional",
            &[(
                RIGHT_VELOCITY,
                "velocity = [-10.0]\njitter = 0.1\nseed = 1.5",
            )],
            "bodies[1].seed",
        )
        .located(),
    ]);
    // In range, the scene is valid and `check` reports the jitter.
    let tmp = tempfile::tempdir().unwrap();
    let text = edit(
        BASE_1D,
        &[(
            RIGHT_VELOCITY,
            "velocity = [-10.0]\njitter = 0.2\nseed = 42",
        )],
    )
    .unwrap();
    let path = write_scene(tmp.path(), "jitter_ok", &text);
    let out = sphcontact(tmp.path(), &["check", path.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("jitter ±0.2 Δx") && stdout.contains("seed 42"),
        "{stdout}"
    );
}

#[test]
fn dt_below_the_cfl_step_is_accepted() {
    let tmp = tempfile::tempdir().unwrap();
    let text = edit(BASE_1D, &[("dimension = 1", "dimension = 1\ndt = 1.0e-9")]).unwrap();
    let path = write_scene(tmp.path(), "dt_ok", &text);
    let out = sphcontact(tmp.path(), &["check", path.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("fixed"), "{stdout}");
}
