//! Checkpoints and restart: a run stopped at a checkpoint (or killed after
//! one) and resumed writes the same history, byte for byte, as the run
//! that was never stopped, on the CPU path and on the GPU path (same
//! adapter); its snapshots too. Bad resumes are refused with a message.

mod common;
use common::*;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use sphcontact::cpu::CpuSolver;
use sphcontact::model::Model;
use sphcontact::run::{resume_run, run_scene, RunOptions};
use sphcontact::scene::{Backend, Integrator, Shape};
use sphcontact::Scene;

const BIN: &str = env!("CARGO_BIN_EXE_sphcontact");

/// The paper's polar-lattice disks, coarse (Δx = 0.5 mm, 630 particles),
/// closing at 80 m/s so that the CPU path rebuilds its neighbour lists
/// several times after the checkpoint, with snapshots every 3 µs, so that
/// the run also stops at snapshot times on both sides of it.
fn disks() -> Scene {
    let mut s = load("scenes/paper/disks_polar.toml");
    for (b, v) in s.bodies.iter_mut().zip([40.0, -40.0]) {
        b.spacing = 5.0e-4;
        b.velocity = Some(vec![v, 0.0]);
    }
    s.output.snapshot_interval = Some(3.0e-6);
    s
}

fn write_opts(dir: &Path, backend: Backend, every: Option<f64>) -> RunOptions {
    RunOptions {
        out_dir: Some(dir.to_path_buf()),
        backend: Some(backend),
        silent: true,
        write: true,
        checkpoint_every: every,
        ..Default::default()
    }
}

fn read(p: impl AsRef<Path>) -> Vec<u8> {
    let p = p.as_ref();
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Every file of the two runs' outputs that must match: the history, the
/// snapshot collection and each snapshot.
fn assert_same_outputs(a: &Path, b: &Path) {
    let ha = read(a.join("history.csv"));
    let hb = read(b.join("history.csv"));
    let rows = ha.iter().filter(|&&c| c == b'\n').count();
    assert!(rows > 100, "a history of {rows} lines");
    if ha != hb {
        let (la, lb) = (String::from_utf8_lossy(&ha), String::from_utf8_lossy(&hb));
        let k = la.lines().zip(lb.lines()).position(|(x, y)| x != y);
        panic!(
            "histories differ ({} and {} bytes), first at line {k:?}",
            ha.len(),
            hb.len()
        );
    }
    let pvd = read(a.join("snapshots.pvd"));
    assert_eq!(pvd, read(b.join("snapshots.pvd")), "snapshot collections");
    let list = |d: &Path| -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = std::fs::read_dir(d.join("snapshots"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        v.sort();
        v
    };
    let (fa, fb) = (list(a), list(b));
    assert_eq!(fa.len(), 5, "snapshots at 0, 3, 6, 9, 12 µs");
    assert_eq!(fa.len(), fb.len());
    for (x, y) in fa.iter().zip(&fb) {
        assert_eq!(x.file_name(), y.file_name());
        assert!(read(x) == read(y), "{} differs", x.display());
    }
}

/// One backend's case: the uninterrupted run; a run with checkpoints
/// (which must not change the steps: same bytes); then that run's
/// directory damaged as a kill after the checkpoint would leave it (a
/// history cut mid-row, no summary, a snapshot written after the
/// checkpoint and a stray one) and resumed.
fn resume_matches(backend: Backend) {
    resume_matches_of(disks(), backend);
}

fn resume_matches_of(scene: Scene, backend: Backend) {
    resume_matches_within(scene, backend, latest(backend), Uninterrupted::Run);
}

/// The latest time a checkpoint asked for at 7 µs may be taken: the GPU
/// checkpoints at the end of the batch that passes 7 µs, sized from the
/// last batch's mean step and its wall time: anywhere before the
/// snapshot at 9 µs, by the machine's speed.
fn latest(backend: Backend) -> f64 {
    match backend {
        Backend::Gpu => 9.0e-6,
        _ => 7.2e-6,
    }
}

/// What a resumed run is held to.
#[derive(Clone, Copy, PartialEq)]
enum Uninterrupted {
    /// A run without checkpoints: it must write what the run with one
    /// wrote, and the resumed run the same.
    Run,
    /// The outputs of the run with the checkpoint, kept before the kill
    /// is staged: the resumed run must write them again. The checkpoint's
    /// writing leaving the steps alone is then another test's (one run
    /// fewer: the GPU tests on a software adapter).
    Kept,
}

/// A copy of the output directory `from` (history, summary, snapshots
/// where it has them).
fn copy_outputs(from: &Path, to: &Path) {
    for sub in ["", "snapshots"] {
        let Ok(files) = std::fs::read_dir(from.join(sub)) else {
            continue;
        };
        std::fs::create_dir_all(to.join(sub)).unwrap();
        for e in files {
            let p = e.unwrap().path();
            if p.is_file() {
                std::fs::copy(&p, to.join(sub).join(p.file_name().unwrap())).unwrap();
            }
        }
    }
}

/// [`resume_matches_of`] with the checkpoint taken no later than
/// `latest` (the GPU checkpoints at the end of a batch of steps, which a
/// slower step makes shorter in time).
fn resume_matches_within(scene: Scene, backend: Backend, latest: f64, reference: Uninterrupted) {
    let tmp = tempfile::tempdir().unwrap();
    let (full, ck) = (tmp.path().join("full"), tmp.path().join("ck"));
    if reference == Uninterrupted::Run {
        run_scene(&scene, None, &write_opts(&full, backend, None)).expect("runs");
    }
    // One checkpoint, at the first state after 7 µs (mid-contact, between
    // the snapshots at 6 and 9 µs).
    run_scene(&scene, None, &write_opts(&ck, backend, Some(7.0e-6))).expect("runs");
    match reference {
        Uninterrupted::Run => assert_same_outputs(&full, &ck),
        Uninterrupted::Kept => copy_outputs(&ck, &full),
    }

    let saved = sphcontact::checkpoint::Checkpoint::read(&ck).expect("a checkpoint");
    let t = saved.time();
    assert!((7.0e-6..latest).contains(&t), "checkpoint at {t:e} s");
    let history = read(ck.join("history.csv"));
    std::fs::write(
        ck.join("history.csv"),
        &history[..history.len() * 4 / 5 - 7],
    )
    .unwrap();
    std::fs::remove_file(ck.join("summary.json")).unwrap();
    std::fs::write(ck.join("snapshots/snapshot_000099.vtu"), b"stray").unwrap();

    let opts = RunOptions {
        backend: Some(backend),
        silent: true,
        ..Default::default()
    };
    let out = resume_run(&ck, &opts).expect("resumes");
    assert_same_outputs(&full, &ck);
    assert_eq!(out.summary.status, "completed");
    let whole: serde_json::Value =
        serde_json::from_slice(&read(full.join("summary.json"))).unwrap();
    let resumed: serde_json::Value =
        serde_json::from_slice(&read(ck.join("summary.json"))).unwrap();
    for key in [
        "steps",
        "particles",
        "energy_initial",
        "energy_final",
        "energy",
        "momentum_initial",
        "momentum_final",
        "bodies",
        "backend",
    ] {
        assert_eq!(whole[key], resumed[key], "summary key {key}");
    }
}

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
    std::fs::remove_file(ck.join("summary.json")).unwrap();
    let opts = RunOptions {
        silent: true,
        ..Default::default()
    };
    let resumed = resume_run(&ck, &opts).expect("resumes");
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
            resume_keeps_the_history(scene, 1.5e-5..2.5e-5, Backend::Gpu, Uninterrupted::Run);
        }
    })
}

#[test]
fn cpu_resume_gives_the_same_bytes() {
    resume_matches(Backend::Cpu);
}

/// The leapfrog's rates at a state are made at predicted velocities and
/// cannot be evaluated again from it: the checkpoint carries them.
#[test]
fn cpu_leapfrog_resume_gives_the_same_bytes() {
    let mut scene = disks();
    scene.simulation.integrator = Integrator::Leapfrog;
    resume_matches_of(scene, Backend::Cpu);
}

/// With the dispersion correction (the coarse disks, both integrators):
/// the leapfrog's carried rates hold the correction's forces and work.
#[test]
fn cpu_resume_with_the_dispersion_correction_gives_the_same_bytes() {
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        let mut scene = disks();
        scene.simulation.dispersion_correction = 0.7;
        scene.simulation.integrator = integrator;
        resume_matches_of(scene, Backend::Cpu);
    }
}

/// Two coarse spheres as bodies of revolution (R/Δx = 10, closing at
/// 80 m/s), on both integrators: the state's `η = 2π r ρ` and the
/// leapfrog's carried rates, mirror terms included, resume to the same
/// bytes.
#[test]
fn cpu_resume_of_bodies_of_revolution_gives_the_same_bytes() {
    let scene = coarse_spheres();
    resume_matches_of(scene.clone(), Backend::Cpu);
    resume_matches_of(leapfrog(scene), Backend::Cpu);
}

/// The coarse spheres of revolution on the GPU path: its state keeps the
/// density itself, converted to and from the host's `η` only at upload
/// and download, so the saved buffers resume to the same bytes (the
/// leapfrog's run below, minutes on a software adapter).
#[test]
fn gpu_resume_of_bodies_of_revolution_gives_the_same_bytes() {
    on_gpu(|| {
        resume_matches_within(
            coarse_spheres(),
            Backend::Gpu,
            latest(Backend::Gpu),
            Uninterrupted::Kept,
        )
    });
}

#[test]
#[ignore]
fn gpu_leapfrog_resume_of_bodies_of_revolution_gives_the_same_bytes() {
    on_gpu(|| resume_matches_of(leapfrog(coarse_spheres()), Backend::Gpu));
}

/// The computational Taylor bar at 10 across with supports that adapt, to
/// 12 µs, its history every 0.1 µs and snapshots every 3 µs.
fn coarse_adaptive_taylor() -> Scene {
    let mut scene = load("scenes/axisymmetric/taylor_bar_bilinear.toml");
    scene.simulation.support = Some(sphcontact::scene::Support::Adaptive);
    for b in scene.bodies.iter_mut() {
        b.spacing = 3.2e-4;
    }
    scene.simulation.end_time = 1.2e-5;
    scene.output.history_interval = Some(1.0e-7);
    scene.output.snapshot_interval = Some(3.0e-6);
    scene
}

/// Supports that adapt (docs/method.md, "Supports that follow the
/// deformation"): the coarse computational Taylor bar (10 across, its
/// face spreading on the wall from the start), on both integrators: the
/// supports' metrics and the lists' reference supports resume to the
/// same bytes.
#[test]
fn cpu_resume_with_adaptive_supports_gives_the_same_bytes() {
    let scene = coarse_adaptive_taylor();
    resume_matches_of(scene.clone(), Backend::Cpu);
    resume_matches_of(leapfrog(scene), Backend::Cpu);
}

/// The coarse Taylor bar with supports that adapt on the GPU path: the
/// device's metrics and the control block's largest semi-axis resume to
/// the same bytes.
#[test]
fn gpu_resume_with_adaptive_supports_gives_the_same_bytes() {
    on_gpu(|| {
        let scene = coarse_adaptive_taylor();
        resume_matches_within(scene.clone(), Backend::Gpu, 1.0e-5, Uninterrupted::Kept);
        resume_matches_within(leapfrog(scene), Backend::Gpu, 1.0e-5, Uninterrupted::Kept);
    });
}

/// Two spheres as bodies of revolution, R/Δx = 10, closing at 80 m/s.
fn coarse_spheres() -> Scene {
    let mut scene = load("scenes/axisymmetric/spheres_hertz.toml");
    for (b, v) in scene.bodies.iter_mut().zip([40.0, -40.0]) {
        b.spacing = 5.0e-4;
        b.velocity = Some(vec![0.0, v]);
    }
    scene.simulation.end_time = 1.2e-5;
    scene.output.snapshot_interval = Some(3.0e-6);
    scene
}

fn leapfrog(mut scene: Scene) -> Scene {
    scene.simulation.integrator = Integrator::Leapfrog;
    scene
}

#[test]
fn gpu_resume_gives_the_same_bytes() {
    on_gpu(|| resume_matches(Backend::Gpu));
}

/// The GPU leapfrog's checkpoint carries its rates and what its next
/// step's reductions read, so the resumed run is the uninterrupted one.
#[test]
fn gpu_leapfrog_resume_gives_the_same_bytes() {
    on_gpu(|| {
        let mut scene = disks();
        scene.simulation.integrator = Integrator::Leapfrog;
        resume_matches_of(scene, Backend::Gpu);
    });
}

/// A GPU checkpoint names the cell grid its reference positions count in;
/// one without it (an older build's, whose cells were twice as large) or
/// with another is refused with a message, not resumed on the wrong grid.
#[test]
fn gpu_resume_on_another_grid_is_refused() {
    on_gpu(|| {
        let tmp = tempfile::tempdir().unwrap();
        let ck = tmp.path().join("ck");
        run_scene(&disks(), None, &write_opts(&ck, Backend::Gpu, Some(2.0e-6))).expect("runs");
        let opts = RunOptions {
            backend: Some(Backend::Gpu),
            silent: true,
            ..Default::default()
        };
        let saved = sphcontact::checkpoint::Checkpoint::read(&ck).expect("a checkpoint");
        for change in [0, 1] {
            let mut c = saved.clone();
            let sphcontact::checkpoint::SolverState::Gpu(g) = &mut c.solver else {
                panic!("a GPU checkpoint")
            };
            let k = g
                .device
                .buffers
                .iter()
                .position(|b| b.0 == "frame")
                .expect("a frame");
            if change == 0 {
                g.device.buffers.remove(k);
            } else {
                // The cell size, twice as large.
                let cell = f64::from_le_bytes(g.device.buffers[k].1[16..24].try_into().unwrap());
                g.device.buffers[k].1[16..24].copy_from_slice(&(2.0 * cell).to_le_bytes());
            }
            c.write(&ck).unwrap();
            let Err(err) = resume_run(&ck, &opts) else {
                panic!("resumed on another grid")
            };
            assert_eq!(err.exit_code(), 2);
            assert!(err.to_string().contains("another cell grid"), "{err}");
        }
    });
}

/// The case above is a real test of the CPU path's saved neighbour lists:
/// the run rebuilds them after the checkpoint, so a resume that rebuilt
/// them at its own first step would sum in another order.
#[test]
fn the_disks_rebuild_their_lists_after_the_checkpoint() {
    let scene = disks();
    let (model, state) = Model::new(&scene);
    let mut solver = CpuSolver::new(model, state);
    let mut at_checkpoint = None;
    while solver.state.t < scene.simulation.end_time {
        if solver.state.t >= 7.0e-6 && at_checkpoint.is_none() {
            at_checkpoint = Some(solver.list_builds);
        }
        solver
            .step(scene.simulation.end_time - solver.state.t)
            .expect("stable");
    }
    let after = solver.list_builds - at_checkpoint.expect("reached 7 µs");
    assert!(after >= 2, "{after} list builds after the checkpoint");
}

/// The binary, killed: a run with a checkpoint every 0.5 µs is killed
/// (SIGKILL) as soon as its first checkpoint is on disk, leaving a history
/// of whole rows, then resumed with `run --resume`; its history is the
/// uninterrupted run's, byte for byte, and it goes on checkpointing.
/// (Should the machine finish the run before the kill lands, the resume
/// still starts from the last checkpoint and the comparison still holds.)
#[test]
fn killed_run_resumes_to_the_same_history() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/disks_polar.toml");
    let run = |out: &Path, extra: &[&str]| {
        let mut c = Command::new(BIN);
        c.arg("run")
            .arg(&scene)
            .args(["--backend", "cpu", "--quiet", "--end-time", "6e-6", "--out"])
            .arg(out)
            .args(extra)
            .stdout(Stdio::null())
            .stderr(Stdio::null());
        c
    };
    let (full, killed) = (tmp.path().join("full"), tmp.path().join("killed"));
    let st = run(&full, &[]).status().unwrap();
    assert!(st.success());

    let mut child = run(&killed, &["--checkpoint-every", "5e-7"])
        .spawn()
        .unwrap();
    let started = Instant::now();
    while !killed.join("checkpoint.bin").exists() && started.elapsed() < Duration::from_secs(120) {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().ok();
    let status = child.wait().unwrap();
    eprintln!(
        "killed run: {status} after {:.2} s",
        started.elapsed().as_secs_f64()
    );
    // What the kill left: whole files only (every output is replaced by a
    // rename, never appended to).
    read_history(&killed.join("history.csv"));
    let ck = sphcontact::checkpoint::Checkpoint::read(&killed).expect("a whole checkpoint");
    eprintln!("resuming from t = {:e} s", ck.time());

    let out = Command::new(BIN)
        .args(["run", "--quiet", "--resume"])
        .arg(&killed)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        read(full.join("history.csv")) == read(killed.join("history.csv")),
        "the resumed history differs"
    );
    // The resumed run went on writing checkpoints at the interval it was
    // started with (the last multiple of 0.5 µs before the 6 µs end).
    let last = sphcontact::checkpoint::Checkpoint::read(&killed).expect("a checkpoint");
    assert!(
        (5.5e-6..5.7e-6).contains(&last.time()),
        "last checkpoint at {:e} s",
        last.time()
    );
}

/// Bad resumes: exit status 2 and one message saying what is wrong.
#[test]
fn bad_resumes_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("bars");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/bars_steel.toml");
    let st = Command::new(BIN)
        .arg("run")
        .arg(&scene)
        .args([
            "--backend",
            "cpu",
            "--quiet",
            "--checkpoint-every",
            "2e-6",
            "--out",
        ])
        .arg(&dir)
        .status()
        .unwrap();
    assert!(st.success());
    let refused = |args: &[&str], says: &str| {
        let out = Command::new(BIN).args(args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    };
    let d = dir.to_str().unwrap();
    let s = scene.to_str().unwrap();
    let empty = tmp.path().to_str().unwrap();
    refused(&["run", "--resume", empty], "cannot read the checkpoint");
    refused(
        &["run", "--resume", d, "--backend", "gpu"],
        "written by the cpu backend",
    );
    refused(&["run", "--resume", d, "--end-time", "1e-6"], "--end-time");
    refused(&["run", s, "--resume", d], "cannot be used with");
    refused(&["run", s, "--checkpoint-every", "0"], "--checkpoint-every");
    refused(
        &["run", s, "--checkpoint-every", "-1"],
        "--checkpoint-every",
    );

    let ck = dir.join("checkpoint.bin");
    let mut bytes = read(&ck);
    let k = bytes.len() / 2;
    bytes[k] ^= 1;
    std::fs::write(&ck, &bytes).unwrap();
    refused(&["run", "--resume", d], "damaged");
    std::fs::write(&ck, &bytes[..k]).unwrap();
    refused(&["run", "--resume", d], "damaged");
}

/// A device lost mid-run (destroyed after the first checkpoint, as a
/// driver reset would lose it: `SPHCONTACT_GPU_LOSE_AT`) stops the run
/// with exit status 1 and a message that names the loss and the kept
/// checkpoint; the history written so far and the checkpoint stay, no
/// summary claims the run, and the run resumed from that checkpoint on a
/// fresh device writes the uninterrupted run's history, byte for byte.
#[test]
fn gpu_lost_mid_run_exits_1_and_resumes_from_the_checkpoint() {
    if gpu().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/bars_steel.toml");
    let run = |out: &Path, extra: &[&str], env: &[(&str, &str)]| {
        Command::new(BIN)
            .arg("run")
            .arg(&scene)
            .args(["--backend", "gpu", "--end-time", "2e-6", "--quiet", "--out"])
            .arg(out)
            .args(extra)
            .env_remove("RUST_BACKTRACE")
            .envs(env.iter().copied())
            .output()
            .expect("the sphcontact binary runs")
    };
    let whole = tmp.path().join("whole");
    let out = run(&whole, &[], &[]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    // To 2 us (the bars in contact), a checkpoint from 0.5 us, the device
    // lost at the first state past it.
    let lost = tmp.path().join("lost");
    let out = run(
        &lost,
        &["--checkpoint-every", "5e-7"],
        &[("SPHCONTACT_GPU_LOSE_AT", "5e-7")],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.contains("the GPU failed after t = "), "{stderr}");
    assert!(stderr.contains("lost"), "{stderr}");
    assert!(stderr.contains("the last checkpoint is kept"), "{stderr}");
    assert!(stderr.contains("--resume"), "{stderr}");
    assert!(
        !lost.join("summary.json").exists(),
        "a summary of a lost run"
    );
    let saved = sphcontact::checkpoint::Checkpoint::read(&lost).expect("the checkpoint kept");
    let t = saved.time();
    assert!((5.0e-7..2.0e-6).contains(&t), "checkpoint at {t:e} s");
    // The history up to the last state the device delivered: at least to
    // the checkpoint, and a prefix of the whole run's.
    let (h, hw) = (
        read(lost.join("history.csv")),
        read(whole.join("history.csv")),
    );
    let rows = String::from_utf8_lossy(&h).lines().count();
    assert!(rows as f64 > t / 1.0e-8, "{rows} history rows kept");
    assert!(
        hw.starts_with(&h),
        "the kept history is the whole run's start"
    );

    let out = Command::new(BIN)
        .args(["run", "--quiet", "--resume"])
        .arg(&lost)
        .env_remove("RUST_BACKTRACE")
        .output()
        .expect("the sphcontact binary runs");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        read(lost.join("history.csv")) == hw,
        "the resumed history differs from the uninterrupted run's"
    );
}
