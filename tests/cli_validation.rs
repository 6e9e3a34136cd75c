//! The command line on bad input (docs/scenes.md, "Command line" and "Validation"):
//! every validation rule answers exit status 2 and one line on stderr,
//! `error: <file>: <key>: <what is wrong>`, never a panic or a backtrace.
//!
//! Each case writes a small valid base scene, mutated by plain text edits,
//! into a temporary directory and runs `sphcontact check` on it (which runs
//! nothing); the few `run` cases use tiny scenes and `--out` into the same
//! directory.

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

#[test]
fn base_scenes_are_valid() {
    let tmp = tempfile::tempdir().unwrap();
    for (name, text) in [("base_1d", BASE_1D), ("base_2d", BASE_2D)] {
        let path = write_scene(tmp.path(), name, text);
        let out = sphcontact(tmp.path(), &["check", path.to_str().unwrap()]);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// Unknown keys, missing required keys, wrong types: serde's rules, with the
/// key and its line and column.
#[test]
fn unknown_missing_and_mistyped_keys() {
    check_cases(&[
        case(
            "unknown_key_top_level",
            &[("title = ", "colour = \"red\"\ntitle = ")],
            "colour",
        )
        .also(&["line 1, column 1"])
        .located(),
        case(
            "unknown_key_in_simulation",
            &[("end_time = 1.0e-7", "end_time = 1.0e-7\nend_tme = 2.0e-7")],
            "simulation.end_tme",
        )
        .located(),
        case(
            "unknown_key_in_body",
            &[(RIGHT_VELOCITY, "velocity = [-10.0]\ncolour = \"red\"")],
            "bodies[1].colour",
        )
        .located(),
        case(
            "unknown_key_in_eos",
            &[("gamma0 = 2.02 }", "gamma0 = 2.02, alpha = 1.0 }")],
            "materials.steel.eos.alpha",
        )
        .located(),
        case(
            "unknown_key_in_probe",
            &[(PROBE1_QUANTITY, "quantity = \"total\"\ncolour = \"red\"")],
            "probes[1].colour",
        )
        .located(),
        case(
            "unknown_key_in_shape",
            &[(
                RIGHT_SHAPE,
                "shape = { kind = \"segment\", from = 0.0, to = 0.001, width = 1.0 }",
            )],
            "bodies[1].shape.width",
        )
        .located(),
        case(
            "unknown_key_in_output",
            &[(
                PROBE1_QUANTITY,
                "quantity = \"total\"\n\n[output]\nhistory_every = 1.0e-9",
            )],
            "output.history_every",
        )
        .located(),
        case(
            "missing_simulation_end_time",
            &[("end_time = 1.0e-7\n", "")],
            "simulation.end_time",
        )
        .located(),
        case(
            "missing_body_spacing",
            &[(RIGHT_SPACING, "name = \"right\"\nmaterial = \"steel\"")],
            "bodies[1].spacing",
        )
        .located(),
        case(
            "missing_material_density",
            &[("density = 7850.0\n", "")],
            "materials.steel.density",
        )
        .located(),
        case(
            "missing_eos_c0",
            &[("c0 = 4580.0, ", "")],
            "materials.steel.eos.c0",
        )
        .located(),
        case(
            "missing_probe_body",
            &[(PROBE0_BODY, "at = [-0.0005]")],
            "probes[0].body",
        )
        .located(),
        case(
            "missing_probe_quantity",
            &[(PROBE1_QUANTITY, "")],
            "probes[1].quantity",
        )
        .located(),
        case(
            "missing_simulation_table",
            &[("[simulation]\ndimension = 1\nend_time = 1.0e-7\n", "")],
            "simulation",
        )
        .located(),
        case(
            "wrong_type_string_for_density",
            &[("density = 7850.0", "density = \"heavy\"")],
            "materials.steel.density",
        )
        .also(&["heavy"])
        .located(),
        case(
            "wrong_type_string_for_end_time",
            &[("end_time = 1.0e-7", "end_time = \"soon\"")],
            "simulation.end_time",
        )
        .located(),
        case(
            "wrong_type_string_for_spacing",
            &[(
                RIGHT_SPACING,
                "name = \"right\"\nmaterial = \"steel\"\nspacing = \"fine\"",
            )],
            "bodies[1].spacing",
        )
        .located(),
        case(
            "wrong_type_number_for_velocity",
            &[(RIGHT_VELOCITY, "velocity = -10.0")],
            "bodies[1].velocity",
        )
        .located(),
        case(
            "wrong_type_string_for_probe_at",
            &[("at = [-0.0005]", "at = \"middle\"")],
            "probes[0]",
        )
        .also(&["middle"])
        .located(),
        case(
            "bad_enum_interaction",
            &[("dimension = 1", "dimension = 1\ninteraction = \"glue\"")],
            "simulation.interaction",
        )
        .also(&["glue"])
        .located(),
        case(
            "bad_enum_backend",
            &[("dimension = 1", "dimension = 1\nbackend = \"tpu\"")],
            "simulation.backend",
        )
        .also(&["tpu"])
        .located(),
        case(
            "bad_enum_integrator",
            &[("dimension = 1", "dimension = 1\nintegrator = \"euler\"")],
            "simulation.integrator",
        )
        .also(&["euler"])
        .located(),
        case(
            "bad_enum_eos_kind",
            &[("kind = \"mie_gruneisen\"", "kind = \"ideal_gas\"")],
            "materials.steel.eos.kind",
        )
        .also(&["ideal_gas"])
        .located(),
        case(
            "bad_enum_shape_kind",
            &[(
                RIGHT_SHAPE,
                "shape = { kind = \"line\", from = 0.0, to = 0.001 }",
            )],
            "bodies[1].shape.kind",
        )
        .also(&["line"])
        .located(),
        case(
            "bad_enum_probe_quantity",
            &[(PROBE1_QUANTITY, "quantity = \"temperature\"")],
            "probes[1].quantity",
        )
        .also(&["temperature"])
        .located(),
        case(
            "toml_syntax_error",
            &[("end_time = 1.0e-7", "end_time = 1.0e-7 s")],
            "simulation.end_time",
        )
        .located(),
    ]);
}

/// Non-positive density, spacing, c0, end time, CFL (zero and negative);
/// negative G and Y0.
#[test]
fn non_positive_and_negative_values() {
    check_cases(&[
        case(
            "density_zero",
            &[("density = 7850.0", "density = 0.0")],
            "materials.steel.density",
        ),
        case(
            "density_negative",
            &[("density = 7850.0", "density = -7850.0")],
            "materials.steel.density",
        ),
        case(
            "spacing_zero",
            &[(
                RIGHT_SPACING,
                "name = \"right\"\nmaterial = \"steel\"\nspacing = 0.0",
            )],
            "bodies[1].spacing",
        ),
        case(
            "spacing_negative",
            &[(
                RIGHT_SPACING,
                "name = \"right\"\nmaterial = \"steel\"\nspacing = -1.0e-4",
            )],
            "bodies[1].spacing",
        ),
        case(
            "c0_zero",
            &[("c0 = 4580.0", "c0 = 0.0")],
            "materials.steel.eos.c0",
        ),
        case(
            "c0_negative",
            &[("c0 = 4580.0", "c0 = -4580.0")],
            "materials.steel.eos.c0",
        ),
        case(
            "end_time_zero",
            &[("end_time = 1.0e-7", "end_time = 0.0")],
            "simulation.end_time",
        ),
        case(
            "end_time_negative",
            &[("end_time = 1.0e-7", "end_time = -1.0e-7")],
            "simulation.end_time",
        ),
        case(
            "cfl_zero",
            &[("dimension = 1", "dimension = 1\ncfl = 0.0")],
            "simulation.cfl",
        ),
        case(
            "cfl_negative",
            &[("dimension = 1", "dimension = 1\ncfl = -0.3")],
            "simulation.cfl",
        ),
        case(
            "shear_modulus_negative",
            &[("shear_modulus = 77.0e9", "shear_modulus = -77.0e9")],
            "materials.steel.shear_modulus",
        ),
        case(
            "yield_stress_negative",
            &[("yield_stress = 600.0e6", "yield_stress = -600.0e6")],
            "materials.steel.yield_stress",
        ),
        case(
            "dt_zero",
            &[("dimension = 1", "dimension = 1\ndt = 0.0")],
            "simulation.dt",
        ),
        case(
            "dimension_three",
            &[("dimension = 1", "dimension = 3")],
            "simulation.dimension",
        ),
    ]);
}

/// Velocities and points of the wrong dimension; shapes of the wrong dimension.
const YIELD: &str = "yield_stress = 600.0e6";
const JC: &str = "strength = { kind = \"johnson_cook\", a = 792e6, b = 510e6, n = 0.26, c = 0.014, m = 1.03, reference_strain_rate = 1.0, room_temperature = 294.0, melt_temperature = 1793.0 }\nspecific_heat = 477.0";

/// The strength, failure and library keys: unknown model keys, negative or
/// missing constants, damage constants whose failure strain is not
/// positive, an unknown library material.
#[test]
fn strength_failure_and_library() {
    check_cases(&[
        case("specific_heat_negative", &[(YIELD, JC), ("specific_heat = 477.0", "specific_heat = -1.0")], "materials.steel.specific_heat"),
        case(
            "jc_unknown_kind",
            &[(YIELD, "strength = { kind = \"zerilli_armstrong\", a = 1.0 }")],
            "materials.steel.strength.kind",
        )
        .located()
        .also(&["zerilli_armstrong", "johnson_cook"]),
        case("jc_unknown_key", &[(YIELD, JC), ("melt_temperature = 1793.0", "melt_temperature = 1793.0, d = 1.0")], "materials.steel.strength.d")
            .located(),
        case("jc_missing_constant", &[(YIELD, JC), ("n = 0.26, ", "")], "materials.steel.strength.n")
            .located()
            .also(&["missing"]),
        case("jc_negative_a", &[(YIELD, JC), ("a = 792e6", "a = -792e6")], "materials.steel.strength.a"),
        case("jc_negative_c", &[(YIELD, JC), ("c = 0.014", "c = -0.014")], "materials.steel.strength.c"),
        case("jc_zero_rate", &[(YIELD, JC), ("reference_strain_rate = 1.0", "reference_strain_rate = 0.0")], "materials.steel.strength.reference_strain_rate"),
        case("jc_melt_below_room", &[(YIELD, JC), ("melt_temperature = 1793.0", "melt_temperature = 200.0")], "materials.steel.strength.melt_temperature"),
        case("jc_no_specific_heat", &[(YIELD, JC), ("\nspecific_heat = 477.0", "")], "materials.steel.specific_heat"),
        case("jc_and_yield", &[(YIELD, "yield_stress = 600.0e6\nstrength = { kind = \"johnson_cook\", a = 792e6, b = 510e6, n = 0.26, c = 0.014, m = 1.03, reference_strain_rate = 1.0, room_temperature = 294.0, melt_temperature = 1793.0 }\nspecific_heat = 477.0")], "materials.steel.strength"),
        case("taylor_quinney_above_one", &[(YIELD, "yield_stress = 600.0e6\ntaylor_quinney = 1.5")], "materials.steel.taylor_quinney"),
        case(
            "failure_strain_not_positive",
            &[(YIELD, "yield_stress = 600.0e6\nfailure = { kind = \"johnson_cook\", d1 = -2.2, d2 = 0.4, d3 = -0.47, d4 = 0.016, d5 = 0.63 }")],
            "materials.steel.failure.d1",
        ),
        case("failure_negative_d4", &[(YIELD, "yield_stress = 600.0e6\nfailure = { kind = \"johnson_cook\", d1 = 0.05, d2 = 3.44, d3 = -2.12, d4 = -0.1, d5 = 0.61 }")], "materials.steel.failure.d4"),
        case("failure_d5_melts_to_zero", &[(YIELD, "yield_stress = 600.0e6\nfailure = { kind = \"johnson_cook\", d1 = 0.05, d2 = 3.44, d3 = -2.12, d4 = 0.002, d5 = -1.0 }")], "materials.steel.failure.d5"),
        case("failure_missing_d", &[(YIELD, "yield_stress = 600.0e6\nfailure = { kind = \"johnson_cook\", d1 = 0.05, d2 = 3.44, d3 = -2.12, d4 = 0.002 }")], "materials.steel.failure.d5").located(),
        case("failure_without_plasticity", &[(YIELD, "failure = { kind = \"johnson_cook\", d1 = 0.05, d2 = 3.44, d3 = -2.12, d4 = 0.002, d5 = 0.61 }")], "materials.steel.failure"),
        case("spall_negative", &[(YIELD, "spall_pressure = -1.0e9")], "materials.steel.spall_pressure"),
        case(
            "unknown_library_material",
            &[("density = 7850.0\nshear_modulus = 77.0e9\nyield_stress = 600.0e6\neos = { kind = \"mie_gruneisen\", c0 = 4580.0, s = 1.49, gamma0 = 2.02 }", "library = \"steel_4341\"")],
            "materials.steel",
        )
        .located()
        .also(&["steel_4341", "steel_4340"]),
    ]);
}

#[test]
fn wrong_dimensions() {
    check_cases(&[
        case(
            "velocity_2d_in_1d",
            &[(RIGHT_VELOCITY, "velocity = [-10.0, 0.0]")],
            "bodies[1].velocity",
        ),
        case(
            "velocity_1d_in_2d",
            &[("velocity = [0.0, -10.0]", "velocity = [-10.0]")],
            "bodies[1].velocity",
        )
        .two_d(),
        case(
            "probe_at_2d_in_1d",
            &[("at = [-0.0005]", "at = [-0.0005, 0.0]")],
            "probes[0].at",
        ),
        case(
            "probe_at_1d_in_2d",
            &[("at = [0.0, 0.0005]", "at = [0.0005]")],
            "probes[0].at",
        )
        .two_d(),
        case(
            "disk_center_1d_in_2d",
            &[("center = [0.0, 0.001]", "center = [0.001]")],
            "bodies[1].shape.center",
        )
        .two_d(),
        case(
            "rectangle_min_3d_in_2d",
            &[("min = [-0.001, -0.001]", "min = [-0.001, -0.001, 0.0]")],
            "bodies[0].shape.min",
        )
        .two_d(),
        case(
            "rectangle_max_1d_in_2d",
            &[("max = [0.001, 0.0]", "max = [0.001]")],
            "bodies[0].shape.max",
        )
        .two_d(),
        case(
            "segment_in_2d_scene",
            &[(
                "shape = { kind = \"disk\", center = [0.0, 0.001], radius = 0.001, lattice = \"square\" }",
                "shape = { kind = \"segment\", from = 0.0, to = 0.001 }",
            )],
            "bodies[1].shape.kind",
        )
        .also(&["segment"])
        .two_d(),
        case(
            "rectangle_in_1d_scene",
            &[(RIGHT_SHAPE, "shape = { kind = \"rectangle\", min = [0.0, 0.0], max = [0.001, 0.001] }")],
            "bodies[1].shape.kind",
        )
        .also(&["rectangle"]),
    ]);
}

/// Names: unknown materials and bodies, duplicate body and probe names.
#[test]
fn names() {
    check_cases(&[
        case(
            "body_unknown_material",
            &[(RIGHT_SPACING, "name = \"right\"\nmaterial = \"iron\"\nspacing = 1.0e-4")],
            "bodies[1].material",
        )
        .also(&["iron"]),
        case(
            "particle_probe_unknown_body",
            &[(PROBE0_BODY, "body = \"middle\"\nat = [-0.0005]")],
            "probes[0].body",
        )
        .also(&["middle"]),
        case(
            "contact_probe_unknown_body",
            &[(
                PROBE1_QUANTITY,
                "quantity = \"total\"\n\n[[probes]]\nname = \"force\"\nkind = \"contact\"\nbodies = [\"left\", \"centre\"]\nquantity = \"force\"",
            )],
            "probes[2].bodies",
        )
        .also(&["centre"]),
        case(
            "duplicate_body_name",
            &[(RIGHT_SPACING, "name = \"left\"\nmaterial = \"steel\"\nspacing = 1.0e-4")],
            "bodies[1].name",
        )
        .also(&["left"]),
        case(
            "duplicate_probe_name",
            &[("name = \"energy\"", "name = \"v_left\"")],
            "probes[1].name",
        )
        .also(&["v_left"]),
    ]);
}

/// The rules that need the particles: empty shapes, overlapping bodies, a
/// fixed `dt` above the CFL step at t = 0.
#[test]
fn placement() {
    check_cases(&[
        case(
            "empty_segment",
            // 4e-5 m is less than half the 1e-4 m spacing: no particle.
            &[(
                RIGHT_SHAPE,
                "shape = { kind = \"segment\", from = 0.0, to = 4.0e-5 }",
            )],
            "bodies[1].shape",
        )
        .also(&["right"]),
        case(
            "too_many_particles",
            // A spacing absurdly small for its shape is refused before any
            // particle is allocated.
            &[(
                "spacing = 1.0e-4\nvelocity = [10.0]",
                "spacing = 1.0e-300\nvelocity = [10.0]",
            )],
            "bodies[0].spacing",
        )
        .also(&["particles"]),
        case(
            "empty_disk",
            &[("radius = 0.001", "radius = 5.0e-5")],
            "bodies[1].shape",
        )
        .also(&["disk"])
        .two_d(),
        case(
            "overlapping_segments",
            &[(
                RIGHT_SHAPE,
                "shape = { kind = \"segment\", from = -0.0005, to = 0.0005 }",
            )],
            "bodies[1].shape",
        )
        .also(&["overlap", "left"]),
        case(
            "overlapping_rectangle_and_disk",
            &[("center = [0.0, 0.001]", "center = [0.0, 0.0]")],
            "bodies[1].shape",
        )
        .also(&["overlap"])
        .two_d(),
        case(
            "dt_above_cfl",
            &[("dimension = 1", "dimension = 1\ndt = 1.0e-6")],
            "simulation.dt",
        )
        .also(&["CFL"]),
    ]);
}

/// The optional placement jitter (`jitter`, a fraction of the spacing in
/// [0, 0.5), and its `seed`): out-of-range and mistyped values.
#[test]
fn jitter_and_seed() {
    check_cases(&[
        case(
            "jitter_negative",
            &[(RIGHT_VELOCITY, "velocity = [-10.0]\njitter = -0.1")],
            "bodies[1].jitter",
        )
        .also(&["-0.1", "0.5"]),
        case(
            "jitter_half_a_spacing",
            &[(RIGHT_VELOCITY, "velocity = [-10.0]\njitter = 0.5")],
            "bodies[1].jitter",
        )
        .also(&["< 0.5", "got 0.5"]),
        case(
            "jitter_not_a_number",
            &[(RIGHT_VELOCITY, "velocity = [-10.0]\njitter = nan")],
            "bodies[1].jitter",
        )
        .also(&["NaN"]),
        case(
            "jitter_mistyped",
            &[(RIGHT_VELOCITY, "velocity = [-10.0]\njitter = \"some\"")],
            "bodies[1].jitter",
        )
        .located(),
        case(
            "seed_negative",
            &[(
                RIGHT_VELOCITY,
                "velocity = [-10.0]\njitter = 0.1\nseed = -3",
            )],
            "bodies[1].seed",
        )
        .located(),
        case(
            "seed_fractional",
            &[(
                RIGHT_VELOCITY,
                "velocity = [-10.0]\njitter = 0.1\nseed = 1.5",
            )],
            "bodies[1].seed",
        )
        .located(),
    ]);
    // In range, the scene is valid and `check` reports the jitter.
    let tmp = tempfile::tempdir().unwrap();
    let text = edit(
        BASE_1D,
        &[(
            RIGHT_VELOCITY,
            "velocity = [-10.0]\njitter = 0.2\nseed = 42",
        )],
    )
    .unwrap();
    let path = write_scene(tmp.path(), "jitter_ok", &text);
    let out = sphcontact(tmp.path(), &["check", path.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("jitter ±0.2 Δx") && stdout.contains("seed 42"),
        "{stdout}"
    );
}

#[test]
fn dt_below_the_cfl_step_is_accepted() {
    let tmp = tempfile::tempdir().unwrap();
    let text = edit(BASE_1D, &[("dimension = 1", "dimension = 1\ndt = 1.0e-9")]).unwrap();
    let path = write_scene(tmp.path(), "dt_ok", &text);
    let out = sphcontact(tmp.path(), &["check", path.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("fixed"), "{stdout}");
}

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
    let out_dir = tmp.join("out");
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

/// The leapfrog (scene key or `--integrator`) runs on both paths, and the
/// summary names it.
#[test]
fn leapfrog_by_key_or_flag() {
    let tmp = tempfile::tempdir().unwrap();
    let text = BASE_1D.replacen(
        "dimension = 1",
        "dimension = 1\nintegrator = \"leapfrog\"",
        1,
    );
    let scene = write_scene(tmp.path(), "leap", &text);
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
            &["--backend", "cpu", "--integrator", "leapfrog"][..],
            "flag",
        ),
    ] {
        let (out, dir) = run(scene, extra, dir);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "stderr: {stderr}");
        let s = summary(&dir);
        assert_eq!(s["integrator"], "leapfrog", "{s}");
        assert_eq!(s["backend"], "cpu", "{s}");
    }
    let (out, dir) = run(&plain, &["--backend", "cpu"], "plain");
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(summary(&dir)["integrator"], "midpoint");

    if common::gpu().is_none() {
        return;
    }
    let (out, dir) = run(&scene, &["--backend", "gpu"], "gpu");
    assert_eq!(out.status.code(), Some(0));
    let s = summary(&dir);
    assert_eq!(
        (&s["integrator"], &s["backend"]),
        (&"leapfrog".into(), &"gpu".into())
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
    assert!(stdout.contains("midpoint rule"), "{stdout}");
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
