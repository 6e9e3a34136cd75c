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

/// `run` of the tiny base scene on `backend`, writing into `<tmp>/out`.
fn run_base(tmp: &Path, name: &str, backend: &str) -> (Output, PathBuf) {
    let scene = write_scene(tmp, name, BASE_1D);
    run_into(tmp, &scene, backend, tmp.join("out"))
}

/// `run` of `scene` on `backend`, quiet, writing into `out_dir`.
fn run_into(tmp: &Path, scene: &Path, backend: &str, out_dir: PathBuf) -> (Output, PathBuf) {
    let args = [
        "run",
        scene.to_str().unwrap(),
        "--backend",
        backend,
        "--out",
        out_dir.to_str().unwrap(),
        "--quiet",
    ];
    (sphcontact(tmp, &args), out_dir)
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

/// A scene whose supports adapt runs on either path (`--backend cpu`, and
/// `--backend gpu` on whatever adapter there is), and `check` names the
/// supports.
#[test]
fn adaptive_supports_run_on_both_paths() {
    let tmp = tempfile::tempdir().unwrap();
    let text = BASE_1D.replacen("dimension = 1", "dimension = 1\nsupport = \"adaptive\"", 1);
    let scene = write_scene(tmp.path(), "adaptive", &text);
    let run = |backend: &str| run_into(tmp.path(), &scene, backend, tmp.path().join(backend));
    let backends: &[&str] = if sphcontact::gpu::shared_context().is_ok() {
        &["cpu", "gpu"]
    } else {
        &["cpu"]
    };
    for &b in backends {
        let (out, dir) = run(b);
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
    let out = sphcontact(tmp.path(), &["check", scene.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("support     adaptive"), "{stdout}");
}

/// The dispersion correction runs on the CPU path alone so far: `--backend
/// gpu` refuses it (exit 2, naming the key and the way out) before any
/// adapter is asked for, `auto` runs it on the CPU path with one warning
/// line, and `check` names it.
#[test]
fn dispersion_correction_runs_on_the_cpu_path() {
    let tmp = tempfile::tempdir().unwrap();
    let text = BASE_1D.replacen(
        "dimension = 1",
        "dimension = 1\ndispersion_correction = 0.7",
        1,
    );
    let scene = write_scene(tmp.path(), "dispersion", &text);
    let run = |backend: &str| run_into(tmp.path(), &scene, backend, tmp.path().join(backend));
    let (out, _) = run("gpu");
    refused(&out, &["dispersion_correction", "--backend cpu"]);
    let (out, dir) = run("auto");
    let warning = the_warning(&out);
    assert!(warning.contains("CPU path only"), "{warning}");
    let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    assert!(summary.contains("\"backend\": \"cpu\""), "{summary}");
    check_says(tmp.path(), &scene, "dispersion  corrected, theta 0.7");
    let plain = write_scene(tmp.path(), "plain", BASE_1D);
    check_says(tmp.path(), &plain, "dispersion  uncorrected");
}

/// `sphcontact check` on `scene` succeeds and prints `line`.
fn check_says(dir: &Path, scene: &Path, line: &str) {
    let out = sphcontact(dir, &["check", scene.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains(line), "{stdout}");
}

/// `check` gives the contact's step limit, and says when it sets the step:
/// not at the paper's CFL 0.3, at the stiff scenes' 0.9.
#[test]
fn check_names_the_contacts_step_limit() {
    let tmp = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (scene, sets) in [
        ("scenes/paper/bars_steel.toml", false),
        ("scenes/hard/bars_stiff.toml", true),
    ] {
        let out = sphcontact(tmp.path(), &["check", root.join(scene).to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(0));
        let stdout = String::from_utf8_lossy(&out.stdout);
        // Δx / (√2 c_L) for the bars' steel at 50 µm.
        assert!(
            stdout.contains("step limit of the stiffest spring 6.0585e-9 s"),
            "{stdout}"
        );
        assert_eq!(stdout.contains("it sets the step"), sets, "{stdout}");
        // Under the contact's lines, which it belongs to.
        let lines: Vec<&str> = stdout.lines().collect();
        let k = lines
            .iter()
            .position(|l| l.contains("step limit of the stiffest spring"))
            .unwrap();
        assert!(lines[k - 1].starts_with("contact"), "{stdout}");
        assert_eq!(stdout.contains("(the contact's limit)"), sets, "{stdout}");
    }
}

/// `check` says whether the hourglass control runs and at what coefficient.
#[test]
fn check_names_the_hourglass_control() {
    let tmp = tempfile::tempdir().unwrap();
    let off = write_scene(tmp.path(), "off", BASE_1D);
    let text = format!("{BASE_1D}\n[artificial_viscosity]\nhourglass = 0.5\n");
    let on = write_scene(tmp.path(), "on", &text);
    for (scene, line) in [
        (off, "hourglass control off"),
        (on, "hourglass control 0.5"),
    ] {
        check_says(tmp.path(), &scene, line);
    }
}

/// `check` says which form of the viscosity runs and on which jump; a
/// bad `form` is a clear error naming the key.
#[test]
fn check_names_the_viscosity_form() {
    let tmp = tempfile::tempdir().unwrap();
    let default = write_scene(tmp.path(), "default", BASE_1D);
    let text = format!("{BASE_1D}\n[artificial_viscosity]\nform = \"monaghan\"\n");
    let monaghan = write_scene(tmp.path(), "monaghan", &text);
    let text = format!("{BASE_1D}\n[artificial_viscosity]\nreconstruct_surfaces = false\n");
    let plain = write_scene(tmp.path(), "plain", &text);
    for (scene, line) in [
        (
            default,
            "viscosity   Riemann (approaching and receding pairs), alpha 0.75, beta 0.75, on the reconstructed velocity jump;",
        ),
        (
            monaghan,
            "viscosity   Monaghan (approaching pairs), alpha 0.75, beta 0.75, on the reconstructed velocity jump;",
        ),
        (
            plain,
            "viscosity   Riemann (approaching and receding pairs), alpha 0.75, beta 0.75, on the reconstructed velocity jump (plain at surfaces);",
        ),
    ] {
        check_says(tmp.path(), &scene, line);
    }
    let bad = format!("{BASE_1D}\n[artificial_viscosity]\nform = \"godunov\"\n");
    let bad = write_scene(tmp.path(), "bad", &bad);
    let out = sphcontact(tmp.path(), &["check", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("artificial_viscosity.form") && stderr.contains("riemann"),
        "{stderr}"
    );
}

/// `check` says which artificial stress runs, where its work may only be
/// heat and which bodies take the hourglass control in its place; a bad
/// `work` is a clear error.
#[test]
fn check_names_the_artificial_stress() {
    let tmp = tempfile::tempdir().unwrap();
    let default = write_scene(tmp.path(), "default", BASE_1D);
    let heat = format!("{BASE_1D}\n[artificial_stress]\nwork = \"heat\"\n");
    let heat = write_scene(tmp.path(), "heat", &heat);
    let off = format!("{BASE_1D}\n[artificial_stress]\nepsilon = 0\n");
    let off = write_scene(tmp.path(), "off", &off);
    let plastic =
        format!("{BASE_1D}\n[artificial_stress]\npairs = \"close\"\nwork = \"plastic\"\n");
    let yielding = write_scene(tmp.path(), "yielding", &plastic);
    let elastic = plastic.replacen("yield_stress = 600.0e6\n", "", 1);
    assert_ne!(elastic, plastic);
    let elastic = write_scene(tmp.path(), "elastic", &elastic);
    let default_elastic = BASE_1D.replacen("yield_stress = 600.0e6\n", "", 1);
    assert_ne!(default_elastic, BASE_1D);
    let default_elastic = write_scene(tmp.path(), "default_elastic", &default_elastic);
    let either = format!("{BASE_1D}\n[artificial_stress]\npairs = \"close\"\nwork = \"either\"\n");
    let either = write_scene(tmp.path(), "either", &either);
    for (scene, line) in [
        (
            default,
            "artificial stress epsilon 0.3, n 4, close pairs; only heat in bodies that can yield, of either sign elsewhere",
        ),
        (
            default_elastic,
            "close pairs; its work of either sign (nothing can yield)",
        ),
        (
            either,
            "artificial stress epsilon 0.3, n 4, close pairs; its work of either sign",
        ),
        (
            heat,
            "artificial stress epsilon 0.3, n 4, every pair in tension; only heat",
        ),
        (off, "no artificial stress"),
        (
            elastic,
            "close pairs; its work of either sign (nothing yields)",
        ),
        (
            yielding,
            "close pairs; only heat where it flows plastically",
        ),
    ] {
        check_says(tmp.path(), &scene, line);
    }
    // The hourglass control in place of the term where a body can yield:
    // both bars can, so no artificial stress runs; without a yield
    // stress the key changes nothing.
    let keyed = format!(
        "{BASE_1D}\n[artificial_stress]\nplastic = \"hourglass\"\nplastic_hourglass = 0.5\n"
    );
    let keyed_elastic = keyed.replacen("yield_stress = 600.0e6\n", "", 1);
    let keyed = write_scene(tmp.path(), "keyed", &keyed);
    check_says(
        tmp.path(),
        &keyed,
        "plastic     left, right: the hourglass control 0.5 in place of the artificial stress",
    );
    check_says(tmp.path(), &keyed, "no artificial stress");
    let keyed_elastic = write_scene(tmp.path(), "keyed_elastic", &keyed_elastic);
    let out = sphcontact(tmp.path(), &["check", keyed_elastic.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(
        stdout.contains("every pair in tension; its work of either sign")
            && !stdout.contains("in place of"),
        "{stdout}"
    );
    let bad = format!("{BASE_1D}\n[artificial_stress]\nwork = \"cold\"\n");
    let bad = write_scene(tmp.path(), "bad", &bad);
    let out = sphcontact(tmp.path(), &["check", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("work"), "{stderr}");
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

/// A line the graphics stack may print on its own (Mesa without a
/// display's runtime directory), not the solver's.
fn is_adapter_noise(line: &str) -> bool {
    line.contains("XDG_RUNTIME_DIR")
}

#[test]
fn check_prints_the_derived_set_up() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/bars_steel.toml");
    let out = sphcontact(tmp.path(), &["check", scene.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let particles = stdout
        .lines()
        .find(|l| l.starts_with("particles"))
        .unwrap_or_else(|| panic!("no particle count: {stdout}"));
    assert_eq!(
        particles.split_whitespace().nth(1),
        Some("200"),
        "{particles}"
    );
    // c_L = sqrt((K + 4G/3) / ρ0) with K = ρ0 c0²: 5835.66 m/s for this steel.
    assert!(stdout.contains("c_L 5835."), "{stdout}");
    // The geometry, and each body's mass and velocity with their units.
    assert!(
        stdout
            .contains("set-up      1-D, uniaxial strain, interaction penalty, correction gradient"),
        "{stdout}"
    );
    assert!(stdout.contains(" kg/m2, velocity (10, 0) m/s"), "{stdout}");
    let axi =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/axisymmetric/taylor_bar_bilinear.toml");
    let out = sphcontact(tmp.path(), &["check", axi.to_str().unwrap()]);
    let axi = String::from_utf8_lossy(&out.stdout);
    assert!(
        axi.contains("set-up      2-D, bodies of revolution (r–z)"),
        "{axi}"
    );
    assert!(axi.contains(" kg, velocity (0, -227) m/s"), "{axi}");
    assert!(
        stdout.contains("leapfrog (one evaluation a step)"),
        "{stdout}"
    );
    // check runs nothing and writes nothing.
    assert!(std::fs::read_dir(tmp.path()).unwrap().next().is_none());
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
