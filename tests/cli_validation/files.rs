//! Scene files that are missing or unreadable, and bad arguments.

use super::*;

#[test]
fn nonexistent_scene_file() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("no_such_scene.toml");
    let file = path.display().to_string();
    for cmd in ["check", "run"] {
        let out = sphcontact(tmp.path(), &[cmd, &file]);
        if let Err(e) = bad_input(&out, &file) {
            panic!("{cmd}: {e}");
        }
    }
}

#[test]
fn unreadable_scene_file() {
    let tmp = tempfile::tempdir().unwrap();
    // A directory cannot be read as a scene.
    let dir = tmp.path().join("a_directory.toml");
    std::fs::create_dir(&dir).unwrap();
    // Nor can a file that is not UTF-8.
    let binary = tmp.path().join("binary.toml");
    std::fs::write(&binary, [0xff, 0xfe, 0x00, 0x9f, b'\n']).unwrap();
    for path in [dir, binary] {
        let file = path.display().to_string();
        let out = sphcontact(tmp.path(), &["check", &file]);
        if let Err(e) = bad_input(&out, &file) {
            panic!("{file}: {e}");
        }
    }
}

/// `run` validates exactly as `check` does, and writes nothing for a bad scene.
#[test]
fn run_rejects_an_invalid_scene() {
    let tmp = tempfile::tempdir().unwrap();
    let text = edit(BASE_1D, &[("density = 7850.0", "density = 0.0")]).unwrap();
    let path = write_scene(tmp.path(), "run_density_zero", &text);
    let file = path.display().to_string();
    let out_dir = tmp.path().join("out");
    let out = sphcontact(
        tmp.path(),
        &["run", &file, "--out", out_dir.to_str().unwrap(), "--quiet"],
    );
    let msg = bad_input(&out, &file).unwrap_or_else(|e| panic!("{e}"));
    assert!(msg.contains("materials.steel.density"), "{msg}");
    assert!(!out_dir.join("history.csv").exists());
}

/// Clap's own errors: exit 2, an `error: ` first line naming the argument.
fn bad_argument(out: &Output, names: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert!(stderr.starts_with("error: "), "stderr: {stderr}");
    assert!(
        stderr.contains(names),
        "stderr does not name {names}: {stderr}"
    );
    let lower = stderr.to_lowercase();
    assert!(
        !lower.contains("panicked") && !lower.contains("backtrace"),
        "{stderr}"
    );
}

#[test]
fn bad_command_line_arguments() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = write_scene(tmp.path(), "good", BASE_1D);
    let file = scene.to_str().unwrap();
    let out_dir = tmp.path().join("out");
    let out_dir = out_dir.to_str().unwrap();

    bad_argument(&sphcontact(tmp.path(), &["simulate", file]), "simulate");
    bad_argument(
        &sphcontact(tmp.path(), &["check", file, "--fast"]),
        "--fast",
    );
    bad_argument(
        &sphcontact(tmp.path(), &["run", file, "--speed", "2"]),
        "--speed",
    );
    bad_argument(&sphcontact(tmp.path(), &["check"]), "SCENE");
    // No subcommand at all: clap prints the help (no `error: ` line), exit 2.
    let out = sphcontact(tmp.path(), &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert!(stderr.contains("Usage"), "stderr: {stderr}");
    assert!(!stderr.to_lowercase().contains("panicked"), "{stderr}");
    bad_argument(
        &sphcontact(tmp.path(), &["run", file, "--backend", "quantum"]),
        "quantum",
    );
    bad_argument(
        &sphcontact(tmp.path(), &["run", file, "--end-time", "soon"]),
        "soon",
    );
    // `-1` and `=-1` and `=0` all reach the range check.
    for arg in [
        vec!["--end-time", "-1"],
        vec!["--end-time=-1"],
        vec!["--end-time=0"],
    ] {
        let mut args = vec!["run", file, "--out", out_dir];
        args.extend(arg);
        let out = sphcontact(tmp.path(), &args);
        bad_argument(&out, "--end-time");
        assert_eq!(
            String::from_utf8_lossy(&out.stderr)
                .trim_end()
                .lines()
                .count(),
            1
        );
    }
    assert!(!Path::new(out_dir).join("history.csv").exists());
}
