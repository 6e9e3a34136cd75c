//! A run that goes unstable stops with exit status 1 and one message naming
//! the step, time, body, particle and quantity, and keeps what it had
//! written: the history and a summary marked failed, both still parseable
//! (docs/scenes.md, "Command line"). On both backends.

mod common;

use std::path::Path;
use std::process::Command;

use glam::DVec2;
use sphcontact::cpu::CpuSolver;
use sphcontact::model::Model;
use sphcontact::scene::Integrator;

const BIN: &str = env!("CARGO_BIN_EXE_sphcontact");

/// The paper's steel bars at a fixed step of 2.9e-8 s, ten times the stable
/// one (just below the CFL step at 3, which the scene's `cfl` allows; a
/// step the solver chose would be held to the contact's limit,
/// `Model::contact_dt`):
/// the first steps overshoot and the run blows up within a few steps.
fn unstable_bars(dir: &Path) -> std::path::PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("scenes/paper/bars_steel.toml")).unwrap();
    let text = text.replacen(
        "interaction = \"penalty\"",
        "interaction = \"penalty\"\ncfl = 3.0\ndt = 2.9e-8",
        1,
    );
    assert!(text.contains("dt = 2.9e-8"), "the base scene changed");
    let path = dir.join("unstable.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn stops_and_keeps_outputs(backend: &str) {
    stops_and_keeps_outputs_with(&["--backend", backend]);
}

fn stops_and_keeps_outputs_with(args: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let scene = unstable_bars(tmp.path());
    let out_dir = tmp.path().join("out");
    let out = Command::new(BIN)
        .arg("run")
        .args(args)
        .arg("--out")
        .arg(&out_dir)
        .arg(&scene)
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "exit status; stderr:\n{stderr}");
    assert!(!stderr.contains("panicked"), "a panic:\n{stderr}");
    let (_, msg, rows) = common::failed_run(&out_dir, &stderr);
    assert!(msg.step >= 1 && msg.step < 100, "step {}", msg.step);
    assert!(msg.time > 0.0 && msg.time < 4e-6, "time {:e}", msg.time);
    assert!(["left", "right"].contains(&msg.body.as_str()));
    assert!(msg.particle < 100, "particle {}", msg.particle);
    assert!(rows.len() >= 2, "rows before the failure");
}

#[test]
fn unstable_run_stops_with_a_message_and_keeps_its_outputs() {
    stops_and_keeps_outputs("cpu");
}

/// The leapfrog finds the bad state in its last walk and names the
/// particle as the midpoint rule's check does.
#[test]
fn unstable_leapfrog_run_stops_with_a_message_and_keeps_its_outputs() {
    stops_and_keeps_outputs_with(&["--backend", "cpu", "--integrator", "leapfrog"]);
}

#[test]
fn unstable_run_stops_with_a_message_and_keeps_its_outputs_gpu() {
    if common::gpu().is_some() {
        stops_and_keeps_outputs("gpu");
        stops_and_keeps_outputs_with(&["--backend", "gpu", "--integrator", "leapfrog"]);
    }
}

/// A 6 × 6 steel block, at rest, for the domain cases.
fn block() -> (Model, sphcontact::model::State) {
    let scene = common::parse(
        r#"[simulation]
dimension = 2
end_time = 2.0e-6

[materials.steel]
density = 7850.0
shear_modulus = 77.0e9
eos = { kind = "mie_gruneisen", c0 = 4580.0, s = 1.49, gamma0 = 2.02 }

[[bodies]]
name = "block"
material = "steel"
spacing = 1.0e-3
shape = { kind = "rectangle", min = [0.0, 0.0], max = [0.006, 0.006] }
"#,
    );
    Model::new(&scene)
}

/// The block flung at 20 c_L in +x (a uniform motion, so no rate changes
/// and nothing but the domain can stop it): it must leave the domain long
/// before the end time, and the run must say so.
fn flung() -> (Model, sphcontact::model::State) {
    let (model, mut state) = block();
    let c = model.bodies[0].material.c_l;
    for v in &mut state.v {
        *v = DVec2::new(20.0 * c, 0.0);
    }
    (model, state)
}

#[test]
fn domain_is_the_box_grown_by_the_fastest_wave_over_the_run() {
    let (model, state) = block();
    let c = model.bodies[0].material.c_l;
    // Margin T c_L = 2e-6 × ~5900 m/s ≈ 12 mm, larger than the 5 mm box.
    let margin = 2.0e-6 * c;
    assert!(margin > 0.005);
    let [lo, hi] = model.domain;
    let (blo, bhi) = sphcontact::math::bounds(&state.x);
    assert!((blo - lo - DVec2::splat(margin)).abs().max_element() < 1e-12);
    assert!((hi - bhi - DVec2::splat(margin)).abs().max_element() < 1e-12);
    assert!(model.in_domain(hi) && !model.in_domain(hi + DVec2::new(1e-9, 0.0)));
}

fn cpu_leaves_domain_with(integrator: Integrator) -> sphcontact::error::Instability {
    let (mut model, state) = flung();
    model.integrator = integrator;
    let upper = model.domain[1].x;
    let mut solver = CpuSolver::new(model, state);
    loop {
        let t = solver.state.t;
        assert!(t < 2.0e-6, "the block never left the domain");
        if let Err(e) = solver.step(2.0e-6 - t) {
            let x = solver.state.x.iter().map(|p| p.x).fold(f64::MIN, f64::max);
            assert!(x > upper, "stopped at max x {x} inside {upper}");
            return e;
        }
    }
}

#[test]
fn a_particle_leaving_the_domain_stops_the_run() {
    a_particle_leaving_the_domain_stops(Integrator::Midpoint);
}

#[test]
fn a_particle_leaving_the_domain_stops_the_leapfrog_run() {
    a_particle_leaving_the_domain_stops(Integrator::Leapfrog);
}

fn a_particle_leaving_the_domain_stops(integrator: Integrator) {
    let e = cpu_leaves_domain_with(integrator);
    assert_eq!(e.body, "block");
    assert!(
        e.quantity.starts_with("position x (outside the domain ["),
        "{}",
        e.quantity
    );
    // The lowest-numbered particle of the leading column.
    let (model, state) = flung();
    let right = state.x.iter().map(|p| p.x).fold(f64::MIN, f64::max);
    let first = (0..model.len())
        .find(|&i| state.x[i].x == right)
        .expect("a leading particle");
    assert_eq!(e.particle, first);
    assert!(e.value > model.domain[1].x);
    assert!(e.to_string().contains("body 'block'"));
}

#[test]
fn a_particle_leaving_the_domain_stops_the_run_gpu() {
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        leaves_domain_on_the_gpu(integrator);
    }
}

fn leaves_domain_on_the_gpu(integrator: Integrator) {
    let Some(ctx) = common::gpu() else { return };
    let cpu = cpu_leaves_domain_with(integrator);
    let (mut model, state) = flung();
    model.integrator = integrator;
    let mut solver = sphcontact::gpu::GpuSolver::new(ctx, model, &state, &[], 2.0e-6)
        .expect("the device takes the block");
    let failure = loop {
        let batch = solver.run_batch(64);
        if let Some(f) = batch.failure {
            break f;
        }
        assert!(!batch.done, "the block never left the domain on the GPU");
    };
    assert_eq!(failure.body, cpu.body);
    assert_eq!(failure.particle, cpu.particle);
    assert_eq!(failure.quantity, cpu.quantity);
    // f32 positions may cross the boundary a step apart from f64 ones.
    assert!(
        failure.step.abs_diff(cpu.step) <= 1,
        "GPU step {} against CPU step {}",
        failure.step,
        cpu.step
    );
}

/// `check` states the domain: for the paper's bars, the particle centres
/// span ±4.975 mm and the margin is `T (|v|max + c_L)` = 4 µs × (10 +
/// 5835.66) m/s = 23.383 mm.
#[test]
fn check_prints_the_domain() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Command::new(BIN)
        .arg("check")
        .arg(root.join("scenes/paper/bars_steel.toml"))
        .output()
        .expect("the binary runs");
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find(|l| l.starts_with("domain"))
        .expect("a domain line");
    let steel = common::material(&common::load("scenes/paper/bars_steel.toml"), "steel");
    let c_l = steel.c_l;
    assert!((c_l - 5835.66).abs() < 0.01, "c_L {c_l}");
    let half = 0.004975 + 4.0e-6 * (10.0 + c_l);
    let want = format!("x in [{:.4e}, {:.4e}] m", -half, half);
    assert!(line.contains(&want), "{line:?} against {want:?}");
}

/// The energy guard's rule (`Model::guards_energy`): a band from 0.5 to 1.5 times the total
/// energy of the first state, exactly ½ m v² for the paper's bars
/// (7850 kg/m³ × 10 mm × (10 m/s)² / 2 = 3925 J/m², no penalty energy
/// stored at the touching start), give or take the floor 1e-10 Σ m c_L² (0.267 J/m²
/// for the bars: 78.5 kg/m² × (5835.7 m/s)²), set when that state is
/// evaluated; not watched when a rigid body moves (it does work on what it
/// pushes); the floor alone for bodies at rest.
#[test]
fn energy_guard_is_one_and_a_half_times_the_initial_energy() {
    let limit_after_a_step = |scene: &sphcontact::Scene| {
        let (model, state) = Model::new(scene);
        let mut solver = CpuSolver::new(model, state);
        assert_eq!(solver.energy_limit(), None, "set at the first state");
        solver.step(f64::MAX).expect("stable");
        solver.energy_limit()
    };
    let floor = 1e-10 * 78.5 * 5835.7f64.powi(2);
    let mut scene = common::load("scenes/paper/bars_steel.toml");
    assert!((Model::new(&scene).0.energy_floor / floor - 1.0).abs() < 1e-4);
    let limit = limit_after_a_step(&scene).expect("guarded");
    assert!(
        (limit / (1.5 * 3925.0 + floor) - 1.0).abs() < 1e-6,
        "{limit}"
    );
    // The band's lower bound: half the initial, less the floor.
    let lower = Model::new(&scene).0.energy_lower(limit);
    assert!(
        (lower / (0.5 * 3925.0 - floor) - 1.0).abs() < 1e-6,
        "{lower}"
    );

    scene.bodies[1].rigid = true;
    assert!(!Model::new(&scene).0.energy_guard, "a moving rigid body");
    assert_eq!(limit_after_a_step(&scene), None);
    scene.bodies[1].velocity = Some(vec![0.0]);
    let limit = limit_after_a_step(&scene).expect("a resting wall");
    // (Only the left bar is deformable: half the floor.)
    assert!(
        (limit / (1.5 * 0.5 * 3925.0 + 0.5 * floor) - 1.0).abs() < 1e-6,
        "{limit}"
    );
    for b in &mut scene.bodies {
        b.velocity = Some(vec![0.0]);
        b.rigid = false;
    }
    let limit = limit_after_a_step(&scene).expect("guarded at rest");
    assert!((limit / floor - 1.0).abs() < 1e-4, "{limit}");
}
