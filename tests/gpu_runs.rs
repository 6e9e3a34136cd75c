//! Whole runs of the paper's scenes, GPU against the CPU oracle: the
//! observables the paper reports agree within 0.5 %, and two GPU runs of one
//! scene write byte-identical histories.

mod common;
use common::*;
use sphcontact::run::{run_scene, RunOptions, RunOutput};
use sphcontact::scene::Backend;
use sphcontact::Scene;

fn run_with(scene: &Scene, backend: Backend, out_dir: Option<&std::path::Path>) -> RunOutput {
    run_scene(
        scene,
        None,
        &RunOptions {
            silent: true,
            backend: Some(backend),
            write: out_dir.is_some(),
            out_dir: out_dir.map(|d| d.to_path_buf()),
            ..Default::default()
        },
    )
    .expect("the run completes")
}

fn close(what: &str, gpu: f64, cpu: f64, tol: f64) {
    let e = (gpu / cpu - 1.0).abs();
    println!(
        "{what}: gpu {gpu:.6e} cpu {cpu:.6e} ({:+.3} %)",
        100.0 * (gpu / cpu - 1.0)
    );
    assert!(
        e < tol,
        "{what}: gpu {gpu:e} vs cpu {cpu:e} differ by {e:.2e}"
    );
}

fn last(out: &RunOutput, name: &str) -> f64 {
    *column(out, name).last().expect("a history")
}

fn mean_over(out: &RunOutput, name: &str, t0: f64, t1: f64) -> f64 {
    let t = &out.history.times;
    let v = column(out, name);
    let sel: Vec<f64> = (0..t.len())
        .filter(|&k| t[k] >= t0 && t[k] <= t1)
        .map(|k| v[k])
        .collect();
    sel.iter().sum::<f64>() / sel.len() as f64
}

/// Bars: the contact-pressure plateau, the separation time, the final mean
/// velocities.
fn compare_bars(path: &str, plateau: (f64, f64), bodies: [&str; 2]) {
    if gpu().is_none() {
        return;
    }
    let scene = load(path);
    let cpu = run_with(&scene, Backend::Cpu, None);
    let gpu_out = run_with(&scene, Backend::Gpu, None);
    println!(
        "{path}: cpu {:.2} s, gpu {:.2} s",
        cpu.summary.wall_seconds, gpu_out.summary.wall_seconds
    );
    close(
        "pressure plateau",
        mean_over(&gpu_out, "contact_pressure", plateau.0, plateau.1),
        mean_over(&cpu, "contact_pressure", plateau.0, plateau.1),
        5e-3,
    );
    let sep = |o: &RunOutput| contact_window(&o.history.times, &column(o, "contact_pressure")).1;
    close("separation time", sep(&gpu_out), sep(&cpu), 5e-3);
    for b in bodies {
        close(b, last(&gpu_out, b), last(&cpu, b), 5e-3);
    }
}

#[test]
fn bars_steel_gpu_matches_cpu() {
    compare_bars(
        "scenes/paper/bars_steel.toml",
        (0.3e-6, 1.4e-6),
        ["velocity_left", "velocity_right"],
    );
}

#[test]
fn bars_steel_aluminium_gpu_matches_cpu() {
    compare_bars(
        "scenes/paper/bars_steel_aluminium.toml",
        (0.3e-6, 1.3e-6),
        ["velocity_left", "velocity_right"],
    );
}

/// Disks: peak contact force, contact time, final velocities.
fn compare_disks(path: &str) {
    if gpu().is_none() {
        return;
    }
    let scene = load(path);
    let cpu = run_with(&scene, Backend::Cpu, None);
    let gpu_out = run_with(&scene, Backend::Gpu, None);
    println!(
        "{path}: cpu {:.2} s, gpu {:.2} s",
        cpu.summary.wall_seconds, gpu_out.summary.wall_seconds
    );
    let peak = |o: &RunOutput| {
        column(o, "contact_force")
            .iter()
            .cloned()
            .fold(0.0, f64::max)
    };
    close("peak force", peak(&gpu_out), peak(&cpu), 5e-3);
    let dur = |o: &RunOutput| {
        let (a, b) = contact_window(&o.history.times, &column(o, "contact_force"));
        b - a
    };
    close("contact time", dur(&gpu_out), dur(&cpu), 5e-3);
    close(
        "velocity_left",
        last(&gpu_out, "velocity_left"),
        last(&cpu, "velocity_left"),
        5e-3,
    );
    close(
        "velocity_right",
        last(&gpu_out, "velocity_right"),
        last(&cpu, "velocity_right"),
        5e-3,
    );
}

#[test]
fn disks_square_gpu_matches_cpu() {
    compare_disks("scenes/paper/disks_square.toml");
}

#[test]
fn disks_polar_gpu_matches_cpu() {
    compare_disks("scenes/paper/disks_polar.toml");
}

/// Same scene, same adapter: byte-identical `history.csv`. The disks run
/// through first contact and several reorderings of the particles.
#[test]
fn gpu_histories_are_bitwise_repeatable() {
    if gpu().is_none() {
        return;
    }
    let dir = tempfile::tempdir().expect("a temp dir");
    for (path, end) in [
        ("scenes/paper/bars_steel_aluminium.toml", None),
        ("scenes/paper/disks_polar.toml", Some(1.5e-6)),
    ] {
        let mut scene = load(path);
        if let Some(t) = end {
            scene.simulation.end_time = t;
        }
        let mut files = Vec::new();
        for k in 0..2 {
            let d = dir.path().join(format!("{k}"));
            let out = run_with(&scene, Backend::Gpu, Some(&d));
            assert!(out.summary.steps > 100, "a real run");
            files.push(std::fs::read(d.join("history.csv")).expect("history written"));
        }
        assert!(files[0].len() > 1000);
        assert!(files[0] == files[1], "{path}: the two GPU histories differ");
    }
}
