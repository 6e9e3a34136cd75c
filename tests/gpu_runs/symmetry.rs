//! Symmetry planes on the GPU path (docs/method.md §13): a half scene
//! against its CPU twin, and against the whole scene on the device.

use super::*;

/// The paper's polar disks cut along their line of centres
/// (scenes/symmetry/disks_polar_half.toml), GPU against CPU to 10 µs on
/// the leapfrog: the peak force, the contact time and the final
/// velocities as the whole disks' (`compare_disks_with`), the same steps,
/// and no particle across the plane (the 72 placed on it stay there).
#[test]
fn half_polar_disks_gpu_match_cpu() {
    let path = "scenes/symmetry/disks_polar_half.toml";
    let Some(out) = compare_disks_with(path, Integrator::Leapfrog) else {
        return;
    };
    // The device's positions are its grid's, to f32 within their cell.
    let tol = 1e-6 * out.model.bodies[0].spacing;
    let on = out.state.x.iter().filter(|x| x.y.abs() <= tol).count();
    assert!(on >= 72, "{on} particles on the plane at the end");
    for x in &out.state.x {
        assert!(x.y >= -tol, "a particle crossed the plane: {x}");
    }
}

/// Two runs' history column `name` (`b`'s doubled where `double`, a half
/// against its whole): the largest gap over `a`'s peak.
fn gap_on_gpu(a: &RunOutput, b: &RunOutput, name: &str, double: bool) -> f64 {
    let (a, b) = (column(a, name), column(b, name));
    assert_eq!(a.len(), b.len(), "{name}: rows");
    let k = if double { 2.0 } else { 1.0 };
    let peak = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let gap = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (k * y - x).abs())
        .fold(0.0, f64::max)
        / peak;
    println!("{name}: {gap:.3e} of the peak {peak:.6e}");
    gap
}

/// `half` within `tol` of `whole`, relative.
fn near(what: &str, half: f64, whole: f64, tol: f64) {
    let e = half / whole - 1.0;
    println!("{what}: half {half:.6e} whole {whole:.6e} ({e:+.3e})");
    assert!(
        e.abs() < tol,
        "{what}: the half's {half:e} against the whole's {whole:e}"
    );
}

/// Issue 50's must-show 7 on the device: the paper's square disks cut
/// along their line of centres give the whole pair's contact force and
/// contact time within 0.5 % (measured on lavapipe: the force to 1.0e-5
/// of its peak, the same contact rows).
#[test]
#[ignore]
fn half_disks_on_the_gpu_give_the_whole_pairs_contact() {
    if gpu().is_none() {
        return;
    }
    let whole = run_on(&load("scenes/paper/disks_square.toml"), Backend::Gpu, None);
    let half = run_on(
        &load("scenes/symmetry/disks_square_half.toml"),
        Backend::Gpu,
        None,
    );
    assert!(gap_on_gpu(&whole, &half, "contact_force", true) < 5e-3);
    near(
        "contact time",
        contact_time(&half),
        contact_time(&whole),
        5e-3,
    );
    for v in ["velocity_left", "velocity_right"] {
        assert!(gap_on_gpu(&whole, &half, v, false) < 5e-3);
    }
}

/// The penetration cut along its axis of impact, on the device, at Δx
/// 0.2 mm to 15 µs: the half's residual velocity (the rod's at the end)
/// within 1 % of the whole's.
#[test]
#[ignore]
fn half_penetration_on_the_gpu_gives_the_whole_residual_velocity() {
    if gpu().is_none() {
        return;
    }
    let mut whole = load("scenes/penetration/tungsten_rod_steel_plate.toml");
    let mut half = load("scenes/symmetry/tungsten_rod_steel_plate_half.toml");
    for s in [&mut whole, &mut half] {
        for b in &mut s.bodies {
            b.spacing = 2e-4;
        }
        s.simulation.end_time = 1.5e-5;
    }
    let (a, b) = (
        run_on(&whole, Backend::Gpu, None),
        run_on(&half, Backend::Gpu, None),
    );
    near(
        "residual velocity",
        last(&b, "velocity_rod"),
        last(&a, "velocity_rod"),
        1e-2,
    );
}

/// A steel tube swaged onto a rod, bodies of revolution cut at their
/// mid-plane (scenes/symmetry/tube_onto_rod_half.toml), on the device:
/// the contact force (doubled) and the tube's speed as the whole's,
/// within 0.5 % of their peaks.
#[test]
#[ignore]
fn half_tube_on_the_gpu_gives_the_whole() {
    if gpu().is_none() {
        return;
    }
    let half = load("scenes/symmetry/tube_onto_rod_half.toml");
    let mut whole = half.clone();
    whole.symmetry.clear();
    let (a, b) = (
        run_on(&whole, Backend::Gpu, None),
        run_on(&half, Backend::Gpu, None),
    );
    assert!(gap_on_gpu(&a, &b, "contact_force", true) < 5e-3);
    assert!(gap_on_gpu(&a, &b, "velocity_tube", false) < 5e-3);
}

/// Verney's imploding sphere (scenes/hard/verney_sphere.toml, a body of
/// revolution) at 10 particles through the wall, cut at its equator, over
/// its first 20 µs on both paths: the half rings' particles on the plane
/// (half their mass) with the three images of a particle near the axis
/// and the plane. The inner radius's history and the total energy within
/// 1e-4 of the CPU's (measured on lavapipe: 5.1e-6 and 7.0e-8), the same
/// steps.
#[test]
fn half_sphere_of_revolution_gpu_matches_cpu() {
    let mut scene = load("scenes/hard/verney_sphere.toml");
    scene.bodies[0].spacing = 2.0e-3;
    scene.simulation.end_time = 2.0e-5;
    scene.symmetry.push(sphcontact::scene::Symmetry {
        normal: vec![0.0, 1.0],
        point: vec![0.0, 0.0],
    });
    let Some((cpu, gpu)) = both_scene("Verney's sphere, half", &scene) else {
        return;
    };
    assert_eq!(gpu.summary.steps, cpu.summary.steps, "step counts");
    for name in ["inner_r", "energy_total"] {
        let gap = gap_on_gpu(&cpu, &gpu, name, false);
        assert!(gap < 1e-4, "{name} off by {gap:e}");
    }
}

/// A steel ring closing onto a steel disk as a quadrant
/// (scenes/symmetry/ring_onto_disk_quadrant.toml) on both paths: the
/// images across either plane and the corner, the particles on a plane
/// (half their mass) and at the corner (a quarter), and the contact
/// across either plane. The contact force's and the ring's histories and
/// the total energy within 1e-4 of the CPU's (measured on lavapipe: the
/// force 1.9e-6 of its peak, the ring's place 1.2e-7), the same steps.
#[test]
fn quarter_ring_on_a_disk_gpu_matches_cpu() {
    let path = "scenes/symmetry/ring_onto_disk_quadrant.toml";
    let Some((cpu, gpu)) = both_scene(path, &load(path)) else {
        return;
    };
    assert_eq!(gpu.summary.steps, cpu.summary.steps, "step counts");
    for name in ["contact_force", "ring_x", "energy_total"] {
        let gap = gap_on_gpu(&cpu, &gpu, name, false);
        assert!(gap < 1e-4, "{name} off by {gap:e}");
    }
    let tol = 1e-6 * gpu.model.bodies[0].spacing;
    for x in &gpu.state.x {
        assert!(
            x.x >= -tol && x.y >= -tol,
            "a particle crossed a plane: {x}"
        );
    }
}

/// The penetration cut along its axis of impact with Coulomb friction
/// 0.1 between rod and plate (Δx 0.2 mm, to 10 µs), GPU against CPU: the
/// rod's nose rubs on the crater's particles and their images across the
/// plane (`rubbing_rod_follows_the_cpu`: measured on lavapipe, the same
/// steps, the rod's speed within 1.8e-5, the frictional heat within
/// 3.0e-5, the device's residual 5.7e-8).
#[test]
fn half_penetration_with_friction_gpu_matches_cpu() {
    let mut scene = load("scenes/symmetry/tungsten_rod_steel_plate_half.toml");
    for b in &mut scene.bodies {
        b.spacing = 2e-4;
    }
    scene.simulation.end_time = 1e-5;
    scene.contact.get_or_insert_with(Default::default).friction = 0.1;
    penetration::rubbing_rod_follows_the_cpu("half penetration, μ 0.1", &scene);
}
