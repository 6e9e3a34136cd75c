//! Runs: the backend flag without an adapter, the integrator, check and validate.

use super::*;

/// A refusal: exit status 2, no panic, and each of `needles` in the message.
fn refused(out: &Output, needles: &[&str]) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    for n in needles {
        assert!(stderr.contains(n), "no {n:?} in stderr: {stderr}");
    }
    assert!(!stderr.to_lowercase().contains("panicked"), "{stderr}");
}

/// A run that succeeded with exactly one `warning:` line on stderr: that line.
fn the_warning(out: &Output) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "stderr: {stderr}");
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .collect();
    assert_eq!(warnings.len(), 1, "stderr: {stderr}");
    warnings[0].to_string()
}

/// Without an adapter (here: wgpu asked for a backend this platform does not
/// have), `--backend gpu` is bad input with a clear message and `auto` runs
/// the CPU path with one warning line.
#[test]
fn no_adapter_gpu_refuses_and_auto_falls_back() {
    if cfg!(target_os = "macos") {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let scene = write_scene(tmp.path(), "noadapter", BASE_1D);
    let run = |backend: &str| {
        let out_dir = tmp.path().join(backend);
        let args = [
            "run",
            scene.to_str().unwrap(),
            "--backend",
            backend,
            "--out",
            out_dir.to_str().unwrap(),
            "--quiet",
        ];
        let out = sphcontact_env(tmp.path(), &args, &[("WGPU_BACKEND", "metal")]);
        (out, out_dir)
    };
    let (out, _) = run("gpu");
    refused(&out, &["no GPU adapter", "--backend cpu"]);

    let (out, dir) = run("auto");
    let warning = the_warning(&out);
    assert!(warning.contains("CPU path"), "{warning}");
    let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    assert!(summary.contains("\"backend\": \"cpu\""), "{summary}");
}

/// `scene` runs to completion with `--backend cpu` and, on whatever
/// adapter there is, `--backend gpu`, each summary naming its backend.
fn runs_on_both_paths(tmp: &Path, scene: &Path) {
    let backends: &[&str] = if sphcontact::gpu::shared_context().is_ok() {
        &["cpu", "gpu"]
    } else {
        &["cpu"]
    };
    for &b in backends {
        let (out, dir) = run_into(tmp, scene, b, tmp.join(b));
        assert_eq!(
            out.status.code(),
            Some(0),
            "{b}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        assert!(
            summary.contains(&format!("\"backend\": \"{b}\"")),
            "{summary}"
        );
    }
}

/// A scene whose supports adapt runs on either path (`--backend cpu`, and
/// `--backend gpu` on whatever adapter there is), and `check` names the
/// supports.
#[test]
fn adaptive_supports_run_on_both_paths() {
    let tmp = tempfile::tempdir().unwrap();
    let text = BASE_1D.replacen("dimension = 1", "dimension = 1\nsupport = \"adaptive\"", 1);
    let scene = write_scene(tmp.path(), "adaptive", &text);
    runs_on_both_paths(tmp.path(), &scene);
    let out = sphcontact(tmp.path(), &["check", scene.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("support     adaptive"), "{stdout}");
}

/// The dispersion correction runs on either path, with either integrator,
/// and `check` names it.
#[test]
fn dispersion_correction_runs_on_either_path() {
    let tmp = tempfile::tempdir().unwrap();
    let text = BASE_1D.replacen(
        "dimension = 1",
        "dimension = 1\ndispersion_correction = 0.7",
        1,
    );
    for (name, integrator) in [("leapfrog", "leapfrog"), ("midpoint", "midpoint")] {
        let scene = write_scene(
            tmp.path(),
            name,
            &text.replacen(
                "dimension = 1",
                &format!("dimension = 1\nintegrator = \"{integrator}\""),
                1,
            ),
        );
        let both = tmp.path().join(name);
        std::fs::create_dir_all(&both).unwrap();
        runs_on_both_paths(&both, &scene);
        check_says(tmp.path(), &scene, "dispersion  corrected, theta 0.7");
    }
    let plain = write_scene(tmp.path(), "plain", BASE_1D);
    check_says(tmp.path(), &plain, "dispersion  uncorrected");
}

/// `check` names a body force, and a run with one books its potential
/// energy in summary.json's ledger; a run without names none.
#[test]
fn gravity_is_checked_and_booked() {
    let tmp = tempfile::tempdir().unwrap();
    let text = BASE_1D.replacen("dimension = 1", "dimension = 1\ngravity = [-9.81]", 1);
    let scene = write_scene(tmp.path(), "gravity", &text);
    check_says(tmp.path(), &scene, "gravity     [-9.81] m/s²");
    let (_, dir) = run_into(tmp.path(), &scene, "cpu", tmp.path().join("g"));
    let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    assert!(summary.contains("\"potential\":"), "{summary}");
    let plain = write_scene(tmp.path(), "plain", BASE_1D);
    let (_, dir) = run_into(tmp.path(), &plain, "cpu", tmp.path().join("p"));
    let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    assert!(!summary.contains("\"potential\""), "{summary}");
}

/// Constraints run on both paths: `--backend gpu` runs them and books
/// the regions' work in summary.json's ledger, and `check` lists each with
/// its particles.
#[test]
fn constraints_run_on_the_gpu_path() {
    let tmp = tempfile::tempdir().unwrap();
    let text = BASE_1D.replacen(
        "shape = { kind = \"segment\", from = -0.001, to = 0.0 }",
        "shape = { kind = \"segment\", from = -0.001, to = 0.0 }\n\n[[bodies.constraints]]\nname = \"grip\"\nregion = { kind = \"segment\", from = -0.001, to = -0.0008 }\nvelocity = [10.0]",
        1,
    );
    let scene = write_scene(tmp.path(), "held", &text);
    let (o, dir) = run_into(tmp.path(), &scene, "gpu", tmp.path().join("g"));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    assert!(summary.contains("\"backend\": \"gpu\""), "{summary}");
    assert!(summary.contains("\"constraint_work\":"), "{summary}");
    check_says(
        tmp.path(),
        &scene,
        "constraint 'grip': 2 particles held at [10] m/s",
    );
}

/// Friction runs on both paths: `--backend gpu` runs it on either
/// integrator and books the frictional heat in summary.json's ledger, as
/// the CPU path does, and `check` names it; a run without friction names
/// none.
#[test]
fn friction_runs_on_both_paths() {
    let tmp = tempfile::tempdir().unwrap();
    let text = BASE_1D.replacen(
        "[materials.steel]",
        "[contact]\nfriction = 0.2\n\n[materials.steel]",
        1,
    );
    let scene = write_scene(tmp.path(), "rubbing", &text);
    check_says(tmp.path(), &scene, "Coulomb friction μ 0.2 on every pair");
    let midpoint = write_scene(
        tmp.path(),
        "rubbing_midpoint",
        &text.replacen(
            "dimension = 1",
            "dimension = 1\nintegrator = \"midpoint\"",
            1,
        ),
    );
    for (scene, backend, out) in [
        (&scene, "cpu", "c"),
        (&scene, "gpu", "g"),
        (&midpoint, "gpu", "m"),
    ] {
        let (o, dir) = run_into(tmp.path(), scene, backend, tmp.path().join(out));
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        let named = format!("\"backend\": \"{backend}\"");
        assert!(summary.contains(&named), "{summary}");
        assert!(summary.contains("\"friction_heat\":"), "{summary}");
    }
    let plain = write_scene(tmp.path(), "plain", BASE_1D);
    let (_, dir) = run_into(tmp.path(), &plain, "cpu", tmp.path().join("p"));
    let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    assert!(!summary.contains("\"friction_heat\""), "{summary}");
}

/// A symmetry plane runs on either path (`--backend cpu`, and `--backend
/// gpu` on whatever adapter there is), and `check` names the plane and
/// the half.
#[test]
fn symmetry_runs_on_both_paths() {
    let tmp = tempfile::tempdir().unwrap();
    let text = BASE_2D.replacen(
        "[materials.steel]",
        "[[symmetry]]\nnormal = [1.0, 0.0]\npoint = [0.0, 0.0]\n\n[materials.steel]",
        1,
    );
    let scene = write_scene(tmp.path(), "halved", &text);
    runs_on_both_paths(tmp.path(), &scene);
    check_says(
        tmp.path(),
        &scene,
        "symmetry    the plane x = 0 m, modelling x > 0",
    );
}

/// Two symmetry planes (a quadrant) run on either path too, and `check`
/// names both planes.
#[test]
fn two_symmetry_planes_run_on_either_path() {
    let tmp = tempfile::tempdir().unwrap();
    let text = BASE_2D.replacen(
        "[materials.steel]",
        "[[symmetry]]\nnormal = [1.0, 0.0]\npoint = [0.0, 0.0]\n[[symmetry]]\nnormal = [0.0, 1.0]\npoint = [0.0, -0.002]\n\n[materials.steel]",
        1,
    );
    let scene = write_scene(tmp.path(), "quadrant", &text);
    runs_on_both_paths(tmp.path(), &scene);
    for plane in [
        "symmetry    the plane x = 0 m, modelling x > 0",
        "symmetry    the plane y = -0.002 m, modelling y > -0.002 m",
    ] {
        check_says(tmp.path(), &scene, plane);
    }
}

/// `render` on a directory without snapshots exits 2 and says how to get
/// them.
#[test]
fn render_without_snapshots_says_why() {
    let tmp = tempfile::tempdir().unwrap();
    let out = sphcontact(tmp.path(), &["render", tmp.path().to_str().unwrap()]);
    refused(&out, &["snapshot_interval"]);
}

/// The leapfrog runs by default; the midpoint rule (scene key or
/// `--integrator`) runs on both paths, and the summary names it.
#[test]
fn midpoint_by_key_or_flag() {
    let tmp = tempfile::tempdir().unwrap();
    let text = BASE_1D.replacen(
        "dimension = 1",
        "dimension = 1\nintegrator = \"midpoint\"",
        1,
    );
    let scene = write_scene(tmp.path(), "mid", &text);
    let plain = write_scene(tmp.path(), "plain", BASE_1D);
    let run = |scene: &Path, extra: &[&str], dir: &str| {
        let out_dir = tmp.path().join(dir);
        let mut args = vec![
            "run",
            scene.to_str().unwrap(),
            "--out",
            out_dir.to_str().unwrap(),
            "--quiet",
        ];
        args.extend(extra);
        (sphcontact(tmp.path(), &args), out_dir)
    };
    let summary = |dir: &Path| -> serde_json::Value {
        serde_json::from_slice(&std::fs::read(dir.join("summary.json")).unwrap()).unwrap()
    };
    for (scene, extra, dir) in [
        (&scene, &["--backend", "cpu"][..], "key"),
        (
            &plain,
            &["--backend", "cpu", "--integrator", "midpoint"][..],
            "flag",
        ),
    ] {
        let (out, dir) = run(scene, extra, dir);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "stderr: {stderr}");
        let s = summary(&dir);
        assert_eq!(s["integrator"], "midpoint", "{s}");
        assert_eq!(s["backend"], "cpu", "{s}");
    }
    let (out, dir) = run(&plain, &["--backend", "cpu"], "plain");
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(summary(&dir)["integrator"], "leapfrog");

    if common::gpu().is_none() {
        return;
    }
    let (out, dir) = run(&scene, &["--backend", "gpu"], "gpu");
    assert_eq!(out.status.code(), Some(0));
    let s = summary(&dir);
    assert_eq!(
        (&s["integrator"], &s["backend"]),
        (&"midpoint".into(), &"gpu".into())
    );
}

#[test]
fn tiny_scene_runs_on_the_cpu() {
    let tmp = tempfile::tempdir().unwrap();
    let (out, out_dir) = run_base(tmp.path(), "tiny", "cpu");
    assert_eq!(
        out.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out_dir.join("history.csv").is_file());
    assert!(out_dir.join("summary.json").is_file());
    // Quiet: no progress, the closing line alone (stdout empty); without
    // --quiet and without a terminal, plain progress lines too.
    let stderr = String::from_utf8_lossy(&out.stderr);
    let ours: Vec<&str> = stderr.lines().filter(|l| !is_adapter_noise(l)).collect();
    assert_eq!(ours.len(), 1, "{stderr}");
    assert!(ours[0].starts_with("done: "), "{stderr}");
    assert!(out.stdout.is_empty());
    let scene = tmp.path().join("tiny.toml");
    let loud = sphcontact(
        tmp.path(),
        &[
            "run",
            scene.to_str().unwrap(),
            "--backend",
            "cpu",
            "--out",
            tmp.path().join("loud").to_str().unwrap(),
        ],
    );
    let stderr = String::from_utf8_lossy(&loud.stderr);
    assert!(
        stderr.lines().filter(|l| l.starts_with("t = ")).count() >= 2,
        "{stderr}"
    );
}

/// `validate` at small resolutions writes every figure, the CSV behind each,
/// and `validation.json` with the contract's keys; bad arguments exit 2.
#[test]
fn validate_writes_figures_csv_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let out = sphcontact(
        dir.path(),
        &[
            "validate",
            "--backend",
            "cpu",
            "--bar-particles",
            "25",
            "--disk-resolution",
            "8",
            "--out",
            "v",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "validate failed: {stderr}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("| case | observable | exact | measured |"),
        "{stdout}"
    );
    let v = dir.path().join("v");
    let fonts = sphcontact::plot::font_available();
    for stem in [
        "fig4_velocity_b",
        "fig5_stress_a",
        "fig6_mean_velocity",
        "fig7_stress_profiles",
        "fig8_von_mises",
        "fig9_contact_force",
    ] {
        let csv = std::fs::read_to_string(v.join(format!("{stem}.csv"))).unwrap();
        assert!(csv.lines().count() > 10, "{stem}.csv is nearly empty");
        let png = v.join(format!("{stem}.png"));
        if fonts {
            let bytes = std::fs::read(&png).unwrap();
            assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{stem}.png");
        } else if std::env::var_os("SPHCONTACT_REQUIRE_FONT").is_some() {
            panic!("SPHCONTACT_REQUIRE_FONT is set but no TrueType font was found");
        } else {
            eprintln!("SKIP: no TrueType font, {stem}.png not checked");
        }
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(v.join("validation.json")).unwrap()).unwrap();
    let records = json.as_array().unwrap();
    assert!(records.len() >= 20, "{} records", records.len());
    for r in records {
        for key in [
            "case",
            "observable",
            "exact",
            "measured",
            "relative_error",
            "backend",
            "particles",
            "wall_seconds",
        ] {
            assert!(r.get(key).is_some(), "record without {key}: {r}");
        }
        assert_eq!(r["backend"], "cpu");
    }

    let bad = sphcontact(dir.path(), &["validate", "nonsense"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("unknown case 'nonsense'"));
    let bad = sphcontact(dir.path(), &["validate", "--bar-particles", "3"]);
    assert_eq!(bad.status.code(), Some(2));
}

/// `validate --dispersion-correction 0.7 --alpha 0.3` runs the cases with
/// the correction (on the CPU path, where `auto` sends it) and says so:
/// the bars' rebound reaches 0.98 of the exact; values out of range exit 2.
#[test]
fn validate_takes_the_dispersion_correction() {
    let dir = tempfile::tempdir().unwrap();
    let out = sphcontact(
        dir.path(),
        &[
            "validate",
            "bars",
            "--dispersion-correction",
            "0.7",
            "--alpha",
            "0.3",
            "--out",
            "v",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "validate failed: {stderr}");
    assert!(
        stderr.contains("every scene with dispersion correction θ 0.7, viscosity α 0.3"),
        "{stderr}"
    );
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("v/validation.json")).unwrap(),
    )
    .unwrap();
    let rebound = json
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["observable"].as_str().unwrap().starts_with("rebound"))
        .expect("the rebound's record");
    assert_eq!(rebound["backend"], "cpu");
    let ratio = rebound["measured"].as_f64().unwrap() / rebound["exact"].as_f64().unwrap();
    assert!(ratio >= 0.98, "{rebound}");
    for bad in [
        &["validate", "--dispersion-correction", "2"][..],
        &["validate", "--alpha=-1"][..],
    ] {
        let out = sphcontact(dir.path(), bad);
        assert_eq!(out.status.code(), Some(2), "{bad:?}");
    }
}

/// Limits lowered on what the solver requests (a smaller device's, on any
/// device): a scene past the largest buffer or past the device memory the
/// solver may take stops before its first step with exit status 2, naming
/// the limit and the particle count that fits; a bad limit is refused.
#[test]
fn gpu_limits_refuse_a_scene_that_does_not_fit() {
    if sphcontact::gpu::shared_context().is_err() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/disks_polar.toml");
    let out_dir = tmp.path().join("out");
    let run = |env: &[(&str, &str)]| {
        let args = [
            "run",
            scene.to_str().unwrap(),
            "--backend",
            "gpu",
            "--quiet",
            "--out",
            out_dir.to_str().unwrap(),
        ];
        sphcontact_env(tmp.path(), &args, env)
    };
    // 16,000 bytes hold a vec4 for each of 1,000 particles.
    let out = run(&[("SPHCONTACT_GPU_MAX_BUFFER", "16000")]);
    refused(
        &out,
        &[
            "does not fit this adapter",
            "16000 bytes a storage binding (max_storage_buffer_binding_size)",
            "at most 1000 particles fit",
        ],
    );
    let history = std::fs::read_to_string(out_dir.join("history.csv")).unwrap_or_default();
    assert!(history.lines().count() <= 1, "rows written: {history}");
    let out = run(&[("SPHCONTACT_GPU_MEMORY", "100000")]);
    refused(
        &out,
        &[
            "does not fit the device memory the solver may take",
            "SPHCONTACT_GPU_MEMORY allows 100000",
            "particles fit",
        ],
    );
    for (var, value) in [
        ("SPHCONTACT_GPU_MEMORY", "lots"),
        ("SPHCONTACT_GPU_MAX_BUFFER", "0"),
        ("SPHCONTACT_GPU_LOSE_AT", "soon"),
    ] {
        refused(&run(&[(var, value)]), &[var]);
    }
}
