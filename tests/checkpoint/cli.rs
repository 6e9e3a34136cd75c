//! Restarts from the command line: a killed run, a lost device, bad
//! resumes refused, another grid refused, the lists rebuilt.

use super::*;

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
