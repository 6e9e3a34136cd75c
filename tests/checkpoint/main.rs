//! Checkpoints and restart: a run stopped at a checkpoint (or killed after
//! one) and resumed writes the same history, byte for byte, as the run
//! that was never stopped, on the CPU path and on the GPU path (same
//! adapter); its snapshots too. Bad resumes are refused with a message.

#[path = "../common/mod.rs"]
mod common;

mod cli;
mod history;
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

/// A bar driven at one end and clamped at the other under a body force,
/// on both integrators: the constraints' impulses and work and the
/// leapfrog's carried forces on the regions ride in the checkpoint.
#[test]
fn cpu_resume_with_constraints_and_gravity_gives_the_same_bytes() {
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        let scene = held_bar(integrator);
        resume_matches_within(
            scene,
            Backend::Cpu,
            latest(Backend::Cpu),
            Uninterrupted::Kept,
        );
    }
}

/// The driven and clamped bar to 10 µs under a body force of 1e6 m/s²,
/// snapshots every 3 µs.
fn held_bar(integrator: Integrator) -> Scene {
    let mut scene = load("scenes/boundaries/bar_driven_clamped.toml");
    scene.simulation.end_time = 1.0e-5;
    scene.simulation.gravity = Some(vec![1.0e6]);
    scene.simulation.integrator = integrator;
    scene.output.snapshot_interval = Some(3.0e-6);
    scene
}

/// The same on the GPU path, at 2.5 times the spacing (a software
/// adapter's time is the step count's): the regions' impulses
/// (`held_w`) ride in the device's part of the checkpoint.
#[test]
fn gpu_resume_with_constraints_and_gravity_gives_the_same_bytes() {
    on_gpu(|| {
        for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
            let mut scene = held_bar(integrator);
            scene.bodies[0].spacing = 5.0e-5;
            resume_matches_within(
                scene,
                Backend::Gpu,
                latest(Backend::Gpu),
                Uninterrupted::Kept,
            );
        }
    });
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
