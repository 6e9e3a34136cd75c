//! The base scenes, and unknown, missing and mistyped keys.

use super::*;

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
