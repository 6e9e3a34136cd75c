//! The same bytes twice, round supports bit for bit, and the backend
//! flag.

use super::penetration::coarse_penetration;
use super::*;

/// Adaptive supports that stay inside their band run the round kernel's
/// code: the paper's square disks through their first 1 µs of contact
/// with `support = "adaptive"` (the default band) end bit for bit as with
/// round supports, on the CPU and (where there is an adapter) the GPU,
/// under both integrators, while their carried ellipses have turned and
/// stretched (none round at the end) and the state keeps no supports.
#[test]
fn supports_inside_the_band_run_the_round_kernel_bit_for_bit() {
    let mut backends = vec![Backend::Cpu];
    if gpu().is_some() {
        backends.push(Backend::Gpu);
    }
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        for &backend in &backends {
            let mut round = load("scenes/paper/disks_square.toml");
            round.simulation.end_time = 1.0e-6;
            round.simulation.integrator = integrator;
            let mut banded = round.clone();
            round.simulation.support = Some(sphcontact::scene::Support::Fixed);
            banded.simulation.support = Some(sphcontact::scene::Support::Adaptive);
            let (a, b) = (
                run_on(&round, backend, None),
                run_on(&banded, backend, None),
            );
            let what = format!("{backend:?}, {integrator:?}");
            assert!(b.state.metric.is_empty(), "{what}: supports left the band");
            let turned = b
                .state
                .carried
                .iter()
                .filter(|c| c.xy != 0.0 || c.xx != c.yy)
                .count();
            println!(
                "{what}: {turned} of {} ellipses not round",
                b.state.carried.len()
            );
            assert!(
                turned > b.state.carried.len() / 2,
                "{what}: {turned} carried ellipses turned"
            );
            assert_eq!(a.summary.steps, b.summary.steps, "{what}: steps");
            assert!(a.state.x == b.state.x, "{what}: positions differ");
            assert!(a.state.v == b.state.v, "{what}: velocities differ");
            assert!(a.state.e == b.state.e, "{what}: energies differ");
            assert!(a.history.rows == b.history.rows, "{what}: histories differ");
        }
    }
}

/// Same scene, same adapter: byte-identical `history.csv`. The disks run
/// through first contact and several reorderings of the particles; the
/// coarse penetration through plastic flow and failure, with the default
/// supports, which leave their band in the crater (the largest semi-axis
/// and the out-of-band flag are raised with integer atomics); the bars
/// (1-D) on the leapfrog through contact and separation. The scenes but
/// the penetration run on round supports. (The leapfrog with supports
/// out of their band writes the same bytes twice in the checkpoint tests:
/// `gpu_resume_with_adaptive_supports_gives_the_same_bytes` runs the
/// coarse Taylor bar, its face spreading, on both integrators.)
#[test]
fn gpu_histories_are_bitwise_repeatable() {
    if gpu().is_none() {
        return;
    }
    let dir = tempfile::tempdir().expect("a temp dir");
    for (path, end, integrator) in [
        (
            "scenes/paper/bars_steel_aluminium.toml",
            None,
            Integrator::Leapfrog,
        ),
        (
            "scenes/paper/disks_polar.toml",
            Some(1.5e-6),
            Integrator::Leapfrog,
        ),
        // Plastic histories, permuted with the particles, and failures.
        (
            "scenes/penetration/tungsten_rod_steel_plate.toml",
            None,
            Integrator::Midpoint,
        ),
        // Bodies of revolution: the mirror images across the axis (in
        // contact from the start; the ball dents the plate at once).
        (
            "scenes/axisymmetric/spheres_hertz.toml",
            Some(2.0e-6),
            Integrator::Leapfrog,
        ),
        (
            "scenes/axisymmetric/ball_on_plate.toml",
            Some(2.0e-6),
            Integrator::Midpoint,
        ),
        // A body force.
        (
            "scenes/boundaries/bar_under_gravity.toml",
            Some(1.0e-6),
            Integrator::Leapfrog,
        ),
    ] {
        let mut scene = load(path);
        scene.simulation.integrator = integrator;
        if let Some(t) = end {
            scene.simulation.end_time = t;
        }
        if path.contains("penetration") {
            // Its first 1.5 µs: plastic flow, failures (the first at
            // 0.55 µs) and the crater's supports out of their band (from
            // 0.47 µs).
            scene = coarse_penetration(integrator);
            scene.simulation.end_time = 1.5e-6;
            scene.simulation.support = None;
        } else {
            scene.simulation.support = Some(sphcontact::scene::Support::Fixed);
        }
        let mut files = Vec::new();
        for k in 0..2 {
            let d = dir.path().join(format!("{k}"));
            let out = run_on(&scene, Backend::Gpu, Some(&d));
            assert!(out.summary.steps > 100, "a real run");
            files.push(std::fs::read(d.join("history.csv")).expect("history written"));
        }
        assert!(files[0].len() > 1000);
        assert!(
            files[0] == files[1],
            "{path} ({integrator}): the two GPU histories differ"
        );
    }
}

fn cli(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_sphcontact"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the binary runs")
}

fn summary(dir: &std::path::Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary written");
    serde_json::from_str(&text).expect("valid JSON")
}

/// `--backend gpu` runs on the device and `summary.json` names the adapter;
/// `auto` runs on a hardware GPU, or on the CPU path with exactly one
/// warning line when the only adapter is a software one; the scene key
/// `simulation.backend` chooses when the flag is absent.
#[test]
fn backend_flag_auto_and_scene_key() {
    let Some(ctx) = gpu() else { return };
    let dir = tempfile::tempdir().expect("a temp dir");
    let scene = "scenes/paper/bars_steel.toml";
    let g = dir.path().join("gpu");
    let out = cli(&[
        "run",
        scene,
        "--backend",
        "gpu",
        "--end-time",
        "3e-7",
        "--quiet",
        "--out",
        g.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s = summary(&g);
    assert_eq!(s["backend"], "gpu");
    assert_eq!(s["adapter"], ctx.adapter_name());

    let a = dir.path().join("auto");
    let out = cli(&[
        "run",
        scene,
        "--backend",
        "auto",
        "--end-time",
        "3e-7",
        "--quiet",
        "--out",
        a.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    let warnings = stderr
        .lines()
        .filter(|l| l.starts_with("warning: backend auto"))
        .count();
    if ctx.is_software() {
        assert_eq!(summary(&a)["backend"], "cpu");
        assert_eq!(warnings, 1, "one fallback warning: {stderr}");
    } else {
        assert_eq!(summary(&a)["backend"], "gpu");
        assert_eq!(warnings, 0, "{stderr}");
    }

    let mut sc = load(scene);
    sc.simulation.end_time = 3e-7;
    sc.simulation.backend = Backend::Gpu;
    let out = run_scene(
        &sc,
        None,
        &RunOptions {
            silent: true,
            ..Default::default()
        },
    )
    .expect("runs");
    assert_eq!(out.summary.backend, "gpu");
    assert!(out.summary.adapter.is_some());
}

/// A machine without a desktop session (no `XDG_RUNTIME_DIR`): listing the
/// adapters prints no line beginning with `error:` when the run works
/// (Mesa's drivers would, twice, without the binary's private directory).
#[test]
fn no_error_lines_without_a_display() {
    let tmp = tempfile::tempdir().expect("a temp dir");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_sphcontact"))
        .args([
            "run",
            "scenes/paper/bars_steel.toml",
            "--quiet",
            "--end-time",
            "1e-7",
        ])
        .arg("--out")
        .arg(tmp.path())
        .env_remove("XDG_RUNTIME_DIR")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        !stderr.lines().any(|l| l.starts_with("error:")),
        "error lines on a working run:\n{stderr}"
    );
}
