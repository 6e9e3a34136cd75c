//! The dispersion correction on the GPU path (docs/method.md, "The
//! dispersion correction"): the midpoint rule's two extra walks an
//! evaluation and the leapfrog's four a step against the CPU's sweeps.

use super::*;

/// The paper's steel bars at θ 0.7 with the viscosity at α 0.3 on both
/// integrators: the rebound reaches 0.98 of the exact on the device as on
/// the host (measured on lavapipe: 0.98116 midpoint, 0.98107 leapfrog),
/// and the histories and the ledger follow the CPU's within the elastic
/// contacts' bound (measured: the rebound speed within 5.2e-6 and 1.6e-6
/// of its peak, the total energy within 6.4e-7 and 4.2e-7), the same
/// steps.
#[test]
fn dispersion_correction_bars_gpu_match_cpu() {
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        let path = "scenes/paper/bars_steel.toml";
        let mut scene = load(path);
        with_dispersion_correction(&mut scene, 0.7, 0.3);
        scene.simulation.integrator = integrator;
        let Some((cpu, gpu)) = both_scene(path, &scene) else {
            return;
        };
        assert_eq!(gpu.summary.steps, cpu.summary.steps, "step counts");
        let rebound = -last(&gpu, "velocity_left") / 10.0;
        println!("{integrator:?}: rebound on the device {rebound:.5}");
        assert!(rebound >= 0.98, "rebound {rebound}");
        close_at_end(&gpu, &cpu, ["velocity_left", "velocity_right"], ELASTIC);
        for name in ["velocity_left", "energy_total", "contact_pressure"] {
            let gap = history_gap(&cpu, &gpu, name);
            assert!(gap < ELASTIC, "{name} off by {gap:e} of its peak");
        }
        let e0 = cpu.summary.energy.initial;
        let residual = gpu.summary.energy.residual.abs() / e0;
        assert!(residual < 1e-5, "the device's ledger residual {residual:e}");
    }
}

/// The paper's square disks with the correction, supports following the
/// deformation from the start (`support_band = 1`: the walks in the
/// pairs' mean metric), 2 µs into their contact on both integrators: the
/// contact force's history within 1e-4 of its peak (measured on lavapipe
/// 1.1e-5 on either), the total energy within 1e-5 (5.3e-7 and 8.3e-7),
/// the same steps.
#[test]
fn dispersion_correction_disks_gpu_match_cpu() {
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        let path = "scenes/paper/disks_square.toml";
        let mut scene = load(path);
        with_dispersion_correction(&mut scene, 0.7, 0.3);
        scene.simulation.integrator = integrator;
        scene.simulation.end_time = 2.0e-6;
        scene.simulation.support = Some(sphcontact::scene::Support::Adaptive);
        scene.simulation.support_band = Some(sphcontact::scene::SupportBand::Both(1.0));
        if !disks_follow_the_cpu(path, &scene) {
            return;
        }
    }
}

/// The paper's polar disks cut along their line of centres
/// (scenes/symmetry/disks_polar_half.toml) with the correction, 2 µs into
/// their contact: the walks meet the neighbours' images and their own
/// across the plane, the particles on it with half their volume; round
/// supports on both integrators, and supports following the deformation
/// from the start on the leapfrog (the images' metrics mirrored). The
/// contact force's history within 1e-4 of its peak, the total energy
/// within 1e-5, the same steps.
#[test]
fn dispersion_correction_across_a_symmetry_plane_gpu_matches_cpu() {
    with_images_follows_the_cpu("scenes/symmetry/disks_polar_half.toml");
}

/// Two steel spheres of revolution (scenes/axisymmetric/spheres_hertz.toml)
/// with the correction, 2 µs into their contact: the walks weigh the
/// power by the rings' volumes, the gradient's pairs by mass and the
/// correction's by area, meet the images across the axis and leave the
/// hoop rate uncorrected. Round supports on both integrators, supports
/// following the deformation from the start on the leapfrog. The contact
/// force's history within 1e-4 of its peak, the total energy within 1e-5,
/// the same steps.
#[test]
fn dispersion_correction_in_bodies_of_revolution_gpu_matches_cpu() {
    with_images_follows_the_cpu("scenes/axisymmetric/spheres_hertz.toml");
}

/// The scene at `path` with the correction (θ 0.7, α 0.3), 2 µs in: round
/// supports on both integrators and supports following the deformation
/// from the start on the leapfrog, each following the CPU
/// ([`disks_follow_the_cpu`]).
fn with_images_follows_the_cpu(path: &str) {
    let cases = [
        (Integrator::Midpoint, false),
        (Integrator::Leapfrog, false),
        (Integrator::Leapfrog, true),
    ];
    for (integrator, adapt) in cases {
        let mut scene = load(path);
        with_dispersion_correction(&mut scene, 0.7, 0.3);
        scene.simulation.integrator = integrator;
        scene.simulation.end_time = 2.0e-6;
        if adapt {
            scene.simulation.support = Some(sphcontact::scene::Support::Adaptive);
            scene.simulation.support_band = Some(sphcontact::scene::SupportBand::Both(1.0));
        }
        println!("{integrator:?}, adaptive supports {adapt}");
        if !disks_follow_the_cpu(path, &scene) {
            return;
        }
    }
}

/// Runs `scene` on both paths: the same steps, the contact force's history
/// within 1e-4 of its peak and the total energy within 1e-5. False
/// without an adapter.
fn disks_follow_the_cpu(path: &str, scene: &Scene) -> bool {
    let Some((cpu, gpu)) = both_scene(path, scene) else {
        return false;
    };
    assert_eq!(gpu.summary.steps, cpu.summary.steps, "step counts");
    let force = history_gap(&cpu, &gpu, "contact_force");
    assert!(force < 1e-4, "contact force off by {force:e} of its peak");
    let energy = history_gap(&cpu, &gpu, "energy_total");
    assert!(energy < 1e-5, "total energy off by {energy:e}");
    true
}

/// The largest gap between two runs' history column `name` over the
/// CPU's peak.
fn history_gap(cpu: &RunOutput, gpu: &RunOutput, name: &str) -> f64 {
    let (a, b) = (column(cpu, name), column(gpu, name));
    assert_eq!(a.len(), b.len(), "{name}: rows");
    let peak = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let gap = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (y - x).abs())
        .fold(0.0, f64::max)
        / peak;
    println!("{name}: {gap:.3e} of the peak {peak:.6e}");
    gap
}
