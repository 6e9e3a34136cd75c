//! `sphcontact bench` from the command line: the JSON records and their
//! sanity, the table, and bad arguments (exit status 2, one message, no
//! panic). Speed itself is not asserted anywhere: that is what the benches
//! are for.

mod common;

use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_sphcontact");

fn bench(args: &[&str], env: &[(&str, &str)]) -> Output {
    Command::new(BIN)
        .arg("bench")
        .args(args)
        .env_remove("RUST_BACKTRACE")
        .envs(env.iter().copied())
        .output()
        .expect("the sphcontact binary runs")
}

/// stdout parsed as the JSON list of records (nothing else may be there).
fn records(out: &Output) -> Vec<serde_json::Value> {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "stderr: {stderr}");
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "stdout is not a JSON list of records ({e}):\n{}",
            String::from_utf8_lossy(&out.stdout)
        )
    })
}

/// The CPU rows of a successful run's table, and the whole of stdout.
fn cpu_rows(out: &Output) -> (Vec<String>, String) {
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    let rows = stdout
        .lines()
        .filter(|l| l.starts_with("| cpu |"))
        .map(str::to_string)
        .collect();
    (rows, stdout)
}

fn num(r: &serde_json::Value, key: &str) -> f64 {
    r[key]
        .as_f64()
        .unwrap_or_else(|| panic!("'{key}' is not a number in {r}"))
}

/// The fields every record has, with sane values for the 1,000-particle
/// disk impact.
fn check_record(r: &serde_json::Value, backend: &str, steps: f64) {
    assert_eq!(r["backend"], backend, "{r}");
    assert!(!r["adapter"].as_str().unwrap_or("").is_empty(), "{r}");
    let n = num(r, "particles");
    assert!((n / 1000.0 - 1.0).abs() <= 0.05, "particles {n}");
    assert_eq!(num(r, "requested_particles"), 1000.0);
    assert_eq!(num(r, "steps"), steps);
    assert!(num(r, "wall_seconds") > 0.0, "{r}");
    let rate = num(r, "particle_steps_per_second");
    assert!(rate > 0.0 && rate.is_finite(), "{r}");
    let rel = rate * num(r, "wall_seconds") / (n * steps) - 1.0;
    assert!(rel.abs() < 1e-9, "rate is particles × steps / wall: {r}");
    let nb = num(r, "mean_neighbours");
    assert!((10.0..=40.0).contains(&nb), "mean neighbours {nb}");
    assert!(num(r, "bytes_per_particle") > 0.0, "{r}");
    assert_eq!(r["in_contact"], true, "the timed steps end in contact: {r}");
    // The rate is the median measurement's (of an even count, the slower
    // of the middle two), and every measurement's rate is listed.
    let mut rates: Vec<f64> = r["rates"]
        .as_array()
        .unwrap_or_else(|| panic!("'rates' is not a list in {r}"))
        .iter()
        .map(|x| x.as_f64().expect("a rate"))
        .collect();
    let k = rates.len();
    assert!(k >= 1, "{r}");
    rates.sort_by(f64::total_cmp);
    assert_eq!(rate, rates[k - 1 - k / 2], "the median rate: {r}");
}

#[test]
fn cpu_records_as_json() {
    let out = bench(
        &[
            "--backend",
            "cpu",
            "--particles",
            "1000",
            "--steps",
            "3",
            "--json",
        ],
        &[],
    );
    let recs = records(&out);
    assert_eq!(recs.len(), 1, "{recs:?}");
    let r = &recs[0];
    check_record(r, "cpu", 3.0);
    assert_eq!(r["memory_kind"], "host");
    assert_eq!(r["hourglass"], 0.0, "the control is off by default");
    assert_eq!(r["dispersion"], 0.0, "the correction is off by default");
    assert_eq!(r["support"], "adaptive", "adaptive supports by default");
    let threads = num(r, "threads");
    assert!(threads >= 1.0);
    assert!(r["adapter"].as_str().unwrap().starts_with("cpu: "), "{r}");
    let per_core = num(r, "particle_steps_per_second_per_core");
    assert!((per_core * threads / num(r, "particle_steps_per_second") - 1.0).abs() < 1e-9);
}

/// `--repeat`: that many measurements of the same steps, each listed,
/// the median reported; the table gives their range.
#[test]
fn repeated_measurements() {
    let args = ["--backend", "cpu", "--particles", "1000", "--steps", "2"];
    for k in [1usize, 2, 3] {
        let n = k.to_string();
        let out = bench(&[&args[..], &["--repeat", &n, "--json"]].concat(), &[]);
        let recs = records(&out);
        assert_eq!(recs.len(), 1, "{recs:?}");
        check_record(&recs[0], "cpu", 2.0);
        assert_eq!(recs[0]["rates"].as_array().map(Vec::len), Some(k));
    }
    let out = bench(&[&args[..], &["--repeat", "3"]].concat(), &[]);
    let (rows, _) = cpu_rows(&out);
    assert_eq!(rows.len(), 1, "{rows:?}");
    let row = &rows[0];
    // The particle-steps/s cell: `median (min–max)`.
    let cell = row.split('|').nth(9).unwrap_or_default().trim();
    let (median, range) = cell
        .split_once(" (")
        .unwrap_or_else(|| panic!("no range in '{cell}': {row}"));
    let (lo, hi) = range
        .trim_end_matches(')')
        .split_once('–')
        .unwrap_or_else(|| panic!("no min–max in '{cell}'"));
    let [median, lo, hi] = [median, lo, hi].map(|x| x.parse::<f64>().expect("a rate"));
    assert!(lo <= median && median <= hi, "{cell}");
}

/// Each integrator's records say so, on both backends; with `--stages` the
/// GPU leapfrog's work counts its three walks a step.
#[test]
fn leapfrog_records_on_both_backends() {
    let args = ["--particles", "1000", "--steps", "2", "--integrator"];
    let out = bench(
        &[&["--backend", "cpu"][..], &args, &["leapfrog", "--json"]].concat(),
        &[],
    );
    let recs = records(&out);
    assert_eq!(recs.len(), 1, "{recs:?}");
    check_record(&recs[0], "cpu", 2.0);
    assert_eq!(recs[0]["integrator"], "leapfrog");
    let out = bench(
        &[&["--backend", "cpu"][..], &args, &["midpoint", "--json"]].concat(),
        &[],
    );
    assert_eq!(records(&out)[0]["integrator"], "midpoint");

    if common::gpu().is_none() {
        return;
    }
    let out = bench(
        &[
            &["--backend", "gpu"][..],
            &args,
            &["leapfrog", "--stages", "--json"],
        ]
        .concat(),
        &[],
    );
    let recs = records(&out);
    check_record(&recs[0], "gpu", 2.0);
    assert_eq!(recs[0]["integrator"], "leapfrog");
    assert_eq!(recs[0]["work"]["walks"], 3, "{}", recs[0]);
    // The midpoint rule's two evaluations: kinematics and forces twice.
    let out = bench(
        &[
            &["--backend", "gpu"][..],
            &args,
            &["midpoint", "--stages", "--json"],
        ]
        .concat(),
        &[],
    );
    let recs = records(&out);
    assert_eq!(recs[0]["integrator"], "midpoint");
    assert_eq!(recs[0]["work"]["walks"], 4, "{}", recs[0]);
}

/// `--support fixed` times the disks with round supports of fixed `h`:
/// the record and the table say so, on the CPU and the GPU.
#[test]
fn fixed_supports_records_say_so() {
    let args = ["--particles", "1000", "--steps", "2", "--support", "fixed"];
    for backend in ["cpu", "gpu"] {
        if backend == "gpu" && common::gpu().is_none() {
            return;
        }
        let out = bench(
            &[&["--backend", backend][..], &args, &["--json"]].concat(),
            &[],
        );
        let recs = records(&out);
        check_record(&recs[0], backend, 2.0);
        assert_eq!(recs[0]["support"], "fixed");
    }
    let (rows, _) = cpu_rows(&bench(&[&["--backend", "cpu"][..], &args].concat(), &[]));
    assert!(rows[0].contains("leapfrog, fixed supports"), "{}", rows[0]);
}

/// `--hourglass` times the disks with the control on: the record and the
/// table say so (the GPU runs it too).
#[test]
fn hourglass_records_say_so() {
    option_records_say_so(("--hourglass", "hourglass"), "leapfrog, hourglass 0.7");
}

/// `--dispersion-correction` times the disks with the correction's sweeps:
/// the record and the table say so (the GPU runs it too).
#[test]
fn dispersion_correction_records_say_so() {
    option_records_say_so(
        ("--dispersion-correction", "dispersion"),
        "leapfrog, dispersion correction 0.7",
    );
}

/// The disks timed with `flag` at 0.7: the record's `key` holds it and the
/// table's row shows `cell`, on the CPU and on a GPU where there is one.
fn option_records_say_so((flag, key): (&str, &str), cell: &str) {
    let args = ["--particles", "1000", "--steps", "2", flag, "0.7"];
    let out = bench(
        &[&["--backend", "cpu"][..], &args, &["--json"]].concat(),
        &[],
    );
    let recs = records(&out);
    check_record(&recs[0], "cpu", 2.0);
    assert_eq!(recs[0][key], 0.7);
    let (rows, _) = cpu_rows(&bench(&[&["--backend", "cpu"][..], &args].concat(), &[]));
    assert!(rows[0].contains(cell), "{}", rows[0]);
    if common::gpu().is_none() {
        return;
    }
    let out = bench(
        &[&["--backend", "gpu"][..], &args, &["--json"]].concat(),
        &[],
    );
    let recs = records(&out);
    check_record(&recs[0], "gpu", 2.0);
    assert_eq!(recs[0][key], 0.7);
}

#[test]
fn table_lists_every_size() {
    let out = bench(
        &[
            "--backend",
            "cpu",
            "--particles",
            "300",
            "1000",
            "--steps",
            "2",
        ],
        &[],
    );
    let (rows, stdout) = cpu_rows(&out);
    assert_eq!(rows.len(), 2, "{stdout}");
    assert!(stdout.contains("(host)"), "{stdout}");
}

#[test]
fn bad_arguments_exit_2() {
    for (args, needle) in [
        (vec!["--particles", "0"], "--particles"),
        (vec!["--particles", "99"], "--particles"),
        (vec!["--particles", "1000", "--steps", "0"], "--steps"),
        (vec!["--particles", "1000", "--repeat", "0"], "--repeat"),
        (vec!["--particles", "1000", "--hourglass=-1"], "--hourglass"),
        (
            vec!["--particles", "1000", "--hourglass", "NaN"],
            "--hourglass",
        ),
        (
            vec!["--particles", "1000", "--dispersion-correction=-0.5"],
            "--dispersion-correction",
        ),
        (vec!["--particles", "many"], "--particles"),
        (vec!["--backend", "tpu"], "--backend"),
    ] {
        let mut all = vec!["--backend", "cpu"];
        if args[0] == "--backend" {
            all.clear();
        }
        all.extend(&args);
        let out = bench(&all, &[]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(out.stdout.is_empty(), "{args:?}: nothing on stdout");
    }
}

/// Without an adapter (wgpu asked for a backend this platform does not
/// have): `--backend gpu` is an error with a clear message, `all` times the
/// CPU alone.
#[test]
fn no_adapter_gpu_fails_and_all_runs_the_cpu() {
    if cfg!(target_os = "macos") {
        return;
    }
    let none = [("WGPU_BACKEND", "metal")];
    let out = bench(
        &["--backend", "gpu", "--particles", "1000", "--steps", "2"],
        &none,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no GPU adapter"), "{stderr}");
    assert!(stderr.contains("--backend cpu"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");

    let out = bench(
        &[
            "--backend",
            "all",
            "--particles",
            "1000",
            "--steps",
            "2",
            "--json",
        ],
        &none,
    );
    let recs = records(&out);
    assert_eq!(recs.len(), 1, "{recs:?}");
    check_record(&recs[0], "cpu", 2.0);
}

/// On an adapter: the GPU record, its stage times, and the ratio line.
#[test]
fn gpu_records_and_stages() {
    if common::gpu().is_none() {
        return;
    }
    let out = bench(
        &[
            "--backend",
            "gpu",
            "--particles",
            "1000",
            "--steps",
            "3",
            "--stages",
            "--json",
        ],
        &[],
    );
    let recs = records(&out);
    assert_eq!(recs.len(), 1, "{recs:?}");
    let r = &recs[0];
    check_record(r, "gpu", 3.0);
    assert_eq!(r["memory_kind"], "device");
    assert!(r["threads"].is_null(), "{r}");
    assert!(r["particle_steps_per_second_per_core"].is_null(), "{r}");
    let stages = r["stages"].as_array().expect("stage times with --stages");
    let names: Vec<&str> = stages.iter().map(|s| s["name"].as_str().unwrap()).collect();
    let expected: Vec<&str> = sphcontact::stage::STAGES.iter().map(|s| s.name).collect();
    assert_eq!(names, expected);
    for s in stages {
        assert!(num(s, "seconds_per_call") > 0.0, "{s}");
        let per_step = num(s, "calls_per_step") * num(s, "seconds_per_call");
        assert!(
            (num(s, "seconds_per_step") / per_step - 1.0).abs() < 1e-9,
            "{s}"
        );
    }
    // The work of a step, counted from the cell list.
    let w = &r["work"];
    assert!(
        num(w, "dispatches") >= 10.0 && num(w, "walks") >= 1.0,
        "{w}"
    );
    let walks = w["per_walk"].as_array().expect("the walks");
    // The default leapfrog's kinematic pass.
    assert!(walks.iter().any(|k| k["name"] == "kinematics_leap"), "{w}");
    for k in walks {
        assert!(num(k, "candidates") > 0.0, "{k}");
        assert!((0.0..=1.0).contains(&num(k, "lane_use")), "{k}");
        // Every particle walks the kinematics pass: a group's trips are at least its
        // lanes' mean.
        if k["name"] == "kinematics_leap" {
            assert!(num(k, "group_trips") >= num(k, "candidates"), "{k}");
        }
    }

    let out = bench(
        &["--backend", "all", "--particles", "1000", "--steps", "2"],
        &[],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(
        stdout.contains("GPU/CPU throughput at 1000 particles:"),
        "{stdout}"
    );
}
