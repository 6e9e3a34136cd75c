//! The command line on bad input (docs/scenes.md, "Command line" and "Validation"):
//! every validation rule answers exit status 2 and one line on stderr,
//! `error: <file>: <key>: <what is wrong>`, never a panic or a backtrace.
//!
//! Each case writes a small valid base scene, mutated by plain text edits,
//! into a temporary directory and runs `sphcontact check` on it (which runs
//! nothing); the few `run` cases use tiny scenes and `--out` into the same
//! directory.

#[path = "../common/mod.rs"]
mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_sphcontact");

/// 1-D: two steel bars of 1 mm each, touching at x = 0, 20 particles.
const BASE_1D: &str = r#"title = "two tiny steel bars"

[simulation]
dimension = 1
end_time = 1.0e-7

[materials.steel]
density = 7850.0
shear_modulus = 77.0e9
yield_stress = 600.0e6
eos = { kind = "mie_gruneisen", c0 = 4580.0, s = 1.49, gamma0 = 2.02 }

[[bodies]]
name = "left"
material = "steel"
spacing = 1.0e-4
velocity = [10.0]
shape = { kind = "segment", from = -0.001, to = 0.0 }

[[bodies]]
name = "right"
material = "steel"
spacing = 1.0e-4
velocity = [-10.0]
shape = { kind = "segment", from = 0.0, to = 0.001 }

[[probes]]
name = "v_left"
kind = "particle"
body = "left"
at = [-0.0005]
quantity = "velocity_x"

[[probes]]
name = "energy"
kind = "energy"
quantity = "total"
"#;

/// 2-D: a plate and a disk just above it, for the 2-D shape and point rules.
const BASE_2D: &str = r#"[simulation]
dimension = 2
end_time = 1.0e-7

[materials.steel]
density = 7850.0
shear_modulus = 77.0e9
eos = { kind = "linear", c0 = 4580.0 }

[[bodies]]
name = "plate"
material = "steel"
spacing = 2.0e-4
velocity = [0.0, 10.0]
shape = { kind = "rectangle", min = [-0.001, -0.001], max = [0.001, 0.0] }

[[bodies]]
name = "disk"
material = "steel"
spacing = 2.0e-4
velocity = [0.0, -10.0]
shape = { kind = "disk", center = [0.0, 0.001], radius = 0.001, lattice = "square" }

[[probes]]
name = "v_disk"
kind = "particle"
body = "disk"
at = [0.0, 0.0005]
quantity = "velocity_y"
"#;

// Anchors that occur exactly once in the base scenes.
const RIGHT_SPACING: &str = "name = \"right\"\nmaterial = \"steel\"\nspacing = 1.0e-4";
const RIGHT_VELOCITY: &str = "velocity = [-10.0]";
const RIGHT_SHAPE: &str = "shape = { kind = \"segment\", from = 0.0, to = 0.001 }";
const PROBE0_BODY: &str = "body = \"left\"\nat = [-0.0005]";
const PROBE1_QUANTITY: &str = "quantity = \"total\"";

/// One bad scene: the edits applied to the base, and what the message must name.
struct Case {
    name: &'static str,
    two_d: bool,
    /// (anchor, replacement): each anchor must occur exactly once.
    edits: &'static [(&'static str, &'static str)],
    /// The offending key as the message must name it.
    key: &'static str,
    /// Further fragments the message must contain (a value, a word).
    also: &'static [&'static str],
    /// A serde-level error: the message also gives the line and column.
    located: bool,
    /// Files written beside the scene first: (name, text).
    files: &'static [(&'static str, &'static str)],
}

const fn case(
    name: &'static str,
    edits: &'static [(&'static str, &'static str)],
    key: &'static str,
) -> Case {
    Case {
        name,
        two_d: false,
        edits,
        key,
        also: &[],
        located: false,
        files: &[],
    }
}

impl Case {
    const fn two_d(mut self) -> Self {
        self.two_d = true;
        self
    }
    const fn located(mut self) -> Self {
        self.located = true;
        self
    }
    const fn also(mut self, also: &'static [&'static str]) -> Self {
        self.also = also;
        self
    }
    const fn with_files(mut self, files: &'static [(&'static str, &'static str)]) -> Self {
        self.files = files;
        self
    }
}

fn edit(base: &str, edits: &[(&str, &str)]) -> Result<String, String> {
    let mut text = base.to_string();
    for (from, to) in edits {
        match text.matches(from).count() {
            1 => text = text.replacen(from, to, 1),
            n => return Err(format!("anchor {from:?} occurs {n} times (test bug)")),
        }
    }
    Ok(text)
}

fn sphcontact(dir: &Path, args: &[&str]) -> Output {
    sphcontact_env(dir, args, &[])
}

/// As [`sphcontact`] with extra environment variables.
fn sphcontact_env(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .env_remove("RUST_BACKTRACE")
        .envs(env.iter().copied())
        .output()
        .expect("the sphcontact binary runs")
}

fn write_scene(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).expect("write the scene");
    path
}

/// Exit status 2, one `error: ` line naming the file, no panic, no backtrace.
/// Returns the message, or what is wrong with the output.
fn bad_input(out: &Output, file: &str) -> Result<String, String> {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let mut problems = Vec::new();
    if out.status.code() != Some(2) {
        problems.push(format!("exit status {:?}, expected 2", out.status.code()));
    }
    let lower = stderr.to_lowercase();
    if lower.contains("panicked") || lower.contains("backtrace") {
        problems.push("stderr shows a panic or a backtrace".into());
    }
    let lines: Vec<&str> = stderr.trim_end().lines().collect();
    if lines.len() != 1 {
        problems.push(format!("{} lines on stderr, expected 1", lines.len()));
    }
    if !stderr.starts_with("error: ") {
        problems.push("stderr does not start with 'error: '".into());
    }
    if !stderr.contains(file) {
        problems.push(format!("the message does not name the file {file}"));
    }
    if problems.is_empty() {
        Ok(stderr.trim_end().to_string())
    } else {
        Err(format!("{}; stderr: {stderr:?}", problems.join("; ")))
    }
}

/// Run `sphcontact check` on every case; report all failures at once.
fn check_cases(cases: &[Case]) {
    let tmp = tempfile::tempdir().expect("a temporary directory");
    let mut failures = Vec::new();
    for c in cases {
        let base = if c.two_d { BASE_2D } else { BASE_1D };
        let text = match edit(base, c.edits) {
            Ok(t) => t,
            Err(e) => {
                failures.push(format!("{}: {e}", c.name));
                continue;
            }
        };
        for (name, text) in c.files {
            std::fs::write(tmp.path().join(name), text).expect("write a file beside the scene");
        }
        let path = write_scene(tmp.path(), c.name, &text);
        let file = path.display().to_string();
        let out = sphcontact(tmp.path(), &["check", &file]);
        let msg = match bad_input(&out, &file) {
            Ok(m) => m,
            Err(e) => {
                failures.push(format!("{}: {e}", c.name));
                continue;
            }
        };
        // The key comes after the file name; match it as a whole path element.
        let after_file = &msg[msg.find(&file).unwrap() + file.len()..];
        let key_named = after_file.match_indices(c.key).any(|(i, _)| {
            let before = after_file[..i].chars().next_back();
            let after = after_file[i + c.key.len()..].chars().next();
            !matches!(before, Some(ch) if ch.is_alphanumeric() || ch == '_' || ch == '.')
                && !matches!(after, Some(ch) if ch.is_alphanumeric() || ch == '_' || ch == '.' || ch == '[')
        });
        if !key_named {
            failures.push(format!(
                "{}: the message does not name {}: {msg}",
                c.name, c.key
            ));
        }
        for a in c.also {
            if !after_file.contains(a) {
                failures.push(format!("{}: the message lacks {a:?}: {msg}", c.name));
            }
        }
        if c.located && !(after_file.contains("line ") && after_file.contains("column ")) {
            failures.push(format!("{}: no line and column: {msg}", c.name));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

mod check;
mod files;
mod keys;
mod placement;
mod runs;
mod shapes;
mod values;

/// `sphcontact check` on `scene` succeeds and prints `line`.
fn check_says(dir: &Path, scene: &Path, line: &str) {
    let out = sphcontact(dir, &["check", scene.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains(line), "{stdout}");
}

/// A line the graphics stack may print on its own (Mesa without a
/// display's runtime directory), not the solver's.
fn is_adapter_noise(line: &str) -> bool {
    line.contains("XDG_RUNTIME_DIR")
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
