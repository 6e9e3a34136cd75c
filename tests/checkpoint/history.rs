//! Restarts that carry a plastic history and failed particles.

use super::*;

/// A scene whose target spalls (scenes/hard/flyer_plate_tension.toml at
/// twice its spacing, 20 µm, with a 2 GPa spall pressure: 9 failures from
/// 2.066 µs), checkpointed at 2.3 µs with the crack open and resumed: the
/// same history, the same final state (damage and failure times included)
/// and the same failures in the summary.
fn resume_keeps_the_failures(backend: Backend, integrator: Integrator, reference: Uninterrupted) {
    let mut scene = load("scenes/hard/flyer_plate_tension.toml");
    scene.materials.get_mut("steel").unwrap().spall_pressure = Some(2.0e9);
    for b in &mut scene.bodies {
        b.spacing *= 2.0;
    }
    scene.output.snapshot_interval = None;
    scene.simulation.integrator = integrator;
    resume_keeps_the_history(scene, 2.3e-6..2.31e-6, backend, reference);
}

/// A copper Taylor rod on its rigid wall (scenes/axisymmetric/
/// taylor_copper.toml at 5 particles across the radius, to 30 µs) with a
/// 1 GPa spall pressure: Johnson–Cook flow with heating, a rigid body, and
/// rim particles failing in the release from 0.5 µs on (38 of 165 at
/// 0.6 GPa); checkpointed at 15 µs, mid-flow, and resumed.
fn rod_with_failures(integrator: Integrator) -> Scene {
    let mut scene = load("scenes/axisymmetric/taylor_copper.toml");
    scene.materials.get_mut("copper").unwrap().spall_pressure = Some(1.0e9);
    for b in &mut scene.bodies {
        b.spacing = 7.62e-4;
    }
    if let Some(Shape::Rectangle { min, .. }) = scene.bodies.get_mut(1).map(|b| &mut b.shape) {
        min[1] = -3.0 * 7.62e-4;
    }
    scene.simulation.end_time = 3.0e-5;
    scene.simulation.integrator = integrator;
    scene
}

/// The run in `ck`, killed after its checkpoint (its summary gone),
/// resumed.
fn resume_killed(ck: &Path) -> sphcontact::run::RunOutput {
    std::fs::remove_file(ck.join("summary.json")).unwrap();
    let opts = RunOptions {
        silent: true,
        ..Default::default()
    };
    resume_run(ck, &opts).expect("resumes")
}

/// Run `scene` whole and with a checkpoint at a time in `at`, resume the
/// latter from it: the same history, final state (plastic strain,
/// temperature, damage and failure times included) and summary, with
/// failures before the checkpoint.
fn resume_keeps_the_history(
    scene: Scene,
    at: std::ops::Range<f64>,
    backend: Backend,
    reference: Uninterrupted,
) {
    let tmp = tempfile::tempdir().unwrap();
    let (full, ck) = (tmp.path().join("full"), tmp.path().join("ck"));
    let whole = (reference == Uninterrupted::Run)
        .then(|| run_scene(&scene, None, &write_opts(&full, backend, None)).expect("runs"));
    let with_checkpoint =
        run_scene(&scene, None, &write_opts(&ck, backend, Some(at.start))).expect("runs");
    let whole = whole.unwrap_or_else(|| {
        copy_outputs(&ck, &full);
        with_checkpoint
    });
    let saved = sphcontact::checkpoint::Checkpoint::read(&ck).expect("a checkpoint");
    assert!(
        at.contains(&saved.time()),
        "checkpoint at {:e} s",
        saved.time()
    );
    let resumed = resume_killed(&ck);
    assert!(read(full.join("history.csv")) == read(ck.join("history.csv")));
    assert!(whole
        .state
        .failed_at
        .iter()
        .any(|&t| t > 0.0 && t < at.start));
    assert!(whole.state == resumed.state, "final states differ");
    let bodies = |d: &Path| {
        serde_json::from_slice::<serde_json::Value>(&read(d.join("summary.json"))).unwrap()
            ["bodies"]
            .clone()
    };
    let b = bodies(&full);
    let failed = b
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|body| body["failure"]["failed"].as_u64())
        .sum::<u64>();
    assert!(failed > 0, "{b}");
    assert_eq!(b, bodies(&ck));
}

#[test]
fn cpu_resume_keeps_the_failures() {
    resume_keeps_the_failures(Backend::Cpu, Integrator::Midpoint, Uninterrupted::Run);
}

/// The device's plastic histories travel in its checkpoint, under both
/// integrators (the leapfrog's run minutes on a software adapter; its
/// carried rates are resumed in the default suite by
/// `gpu_leapfrog_resume_gives_the_same_bytes`).
#[test]
fn gpu_resume_keeps_the_failures() {
    on_gpu(|| resume_keeps_the_failures(Backend::Gpu, Integrator::Midpoint, Uninterrupted::Kept));
}

#[test]
#[ignore]
fn gpu_leapfrog_resume_keeps_the_failures() {
    on_gpu(|| resume_keeps_the_failures(Backend::Gpu, Integrator::Leapfrog, Uninterrupted::Kept));
}

/// The rod with a plastic history, a rigid wall and failures
/// ([`rod_with_failures`]) on both backends and both integrators.
#[test]
fn cpu_resume_keeps_a_plastic_rod_on_its_wall() {
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        let scene = rod_with_failures(integrator);
        resume_keeps_the_history(scene, 1.5e-5..1.51e-5, Backend::Cpu, Uninterrupted::Run);
    }
}

#[test]
fn gpu_resume_keeps_a_plastic_rod_on_its_wall() {
    on_gpu(|| {
        for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
            let scene = rod_with_failures(integrator);
            // The device checkpoints at the end of a batch of steps.
            resume_keeps_the_history(scene, 1.5e-5..2.5e-5, Backend::Gpu, Uninterrupted::Kept);
        }
    })
}

/// The disk sliding on its wall with friction
/// (scenes/friction/disk_wall_oblique.toml), checkpointed at 7 µs with
/// every contact particle's slip and the leapfrog's carried friction in
/// flight (with a static coefficient, the particles' sliding flags too),
/// and resumed: the history the run wrote and its final state (slips and
/// frictional heat included) again, on both integrators.
#[test]
fn cpu_resume_keeps_a_disk_sliding() {
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        resume_keeps_a_disk_sliding(Backend::Cpu, integrator, 1.0, 7.0e-6..7.1e-6);
    }
}

/// The same on the GPU path, at twice the spacing (a software adapter's
/// time is the step count's), checkpointed at the end of the batch past
/// 7 µs: the slips, springs, sliding flags and frictional heat ride in the
/// device's part of the checkpoint (`slip`), and the leapfrog's carried
/// friction too (`frub`).
#[test]
fn gpu_resume_keeps_a_disk_sliding() {
    on_gpu(|| {
        for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
            resume_keeps_a_disk_sliding(Backend::Gpu, integrator, 2.0, 7.0e-6..1.0e-5);
        }
    })
}

/// The sliding disk at `coarsen` times the scene's spacing, checkpointed
/// at a time in `at` on `backend` and resumed ([`Uninterrupted::Kept`]:
/// that the checkpoint leaves the steps alone is the other tests').
fn resume_keeps_a_disk_sliding(
    backend: Backend,
    integrator: Integrator,
    coarsen: f64,
    at: std::ops::Range<f64>,
) {
    let mut scene = load("scenes/friction/disk_wall_oblique.toml");
    scene.simulation.integrator = integrator;
    // Each particle's sliding flag rides through the checkpoint too.
    scene.contact.as_mut().unwrap().static_friction = Some(0.3);
    for b in &mut scene.bodies {
        b.spacing *= coarsen;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (full, ck) = (tmp.path().join("full"), tmp.path().join("ck"));
    let whole = run_scene(&scene, None, &write_opts(&ck, backend, Some(at.start))).expect("runs");
    copy_outputs(&ck, &full);
    let saved = sphcontact::checkpoint::Checkpoint::read(&ck).expect("a checkpoint");
    assert!(at.contains(&saved.time()), "{:e}", saved.time());
    let resumed = resume_killed(&ck);
    assert!(
        read(full.join("history.csv")) == read(ck.join("history.csv")),
        "{integrator:?}"
    );
    assert!(
        whole.state == resumed.state,
        "{integrator:?}: final states differ"
    );
    assert!(whole.state.friction_heat > 0.0);
    // The run slid through its checkpoint.
    let (names, rows) = read_history(&full.join("history.csv"));
    let col = names.iter().position(|n| n == "friction_force").unwrap();
    let at = rows.iter().position(|r| r[0] >= saved.time()).unwrap();
    assert!(rows[at][col] > 0.0, "{:?}", rows[at]);
}
