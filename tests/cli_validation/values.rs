//! Values out of range, the strength and failure keys, dimensions and names.

use super::*;

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
        case(
            "support_band_with_fixed_supports",
            &[(
                "dimension = 1",
                "dimension = 1\nsupport = \"fixed\"\nsupport_band = 1.5",
            )],
            "simulation.support_band",
        ),
        case(
            "support_band_squeezed_beyond_four",
            &[(
                "dimension = 1",
                "dimension = 1\nsupport = \"adaptive\"\nsupport_band = [1.5, 5.0]",
            )],
            "simulation.support_band",
        ),
        case(
            "support_band_below_one",
            &[(
                "dimension = 1",
                "dimension = 1\nsupport = \"adaptive\"\nsupport_band = 0.5",
            )],
            "simulation.support_band",
        ),
        case(
            "dispersion_correction_beyond_its_range",
            &[(
                "dimension = 1",
                "dimension = 1\ndispersion_correction = 2.0",
            )],
            "simulation.dispersion_correction",
        ),
        case(
            "dispersion_correction_negative",
            &[(
                "dimension = 1",
                "dimension = 1\ndispersion_correction = -0.7",
            )],
            "simulation.dispersion_correction",
        ),
        case(
            "negative_friction",
            &[(
                "[materials.steel]",
                "[contact]\nfriction = -0.1\n\n[materials.steel]",
            )],
            "contact.friction",
        ),
        case(
            "snapshot_png_without_snapshots",
            &[(
                "[materials.steel]",
                "[output]\nsnapshot_png = true\n\n[materials.steel]",
            )],
            "output.snapshot_png",
        ),
        case(
            "static_friction_below_friction",
            &[(
                "[materials.steel]",
                "[contact]\nfriction = 0.3\nstatic_friction = 0.2\n\n[materials.steel]",
            )],
            "contact.static_friction",
        ),
        case(
            "pair_static_friction_below_its_friction",
            &[(
                "[materials.steel]",
                "[contact]\n[[contact.pairs]]\nbodies = [\"left\", \"right\"]\nfriction = 0.1\nstatic_friction = 0.05\n\n[materials.steel]",
            )],
            "contact.pairs[0].static_friction",
        ),
        case(
            "friction_pair_with_an_unknown_body",
            &[(
                "[materials.steel]",
                "[contact]\n[[contact.pairs]]\nbodies = [\"left\", \"middle\"]\nfriction = 0.1\n\n[materials.steel]",
            )],
            "contact.pairs[0].bodies",
        ),
        case(
            "friction_pair_of_one_body",
            &[(
                "[materials.steel]",
                "[contact]\n[[contact.pairs]]\nbodies = [\"left\", \"left\"]\nfriction = 0.1\n\n[materials.steel]",
            )],
            "contact.pairs[0].bodies",
        ),
        case(
            "friction_pair_named_twice",
            &[(
                "[materials.steel]",
                "[contact]\n[[contact.pairs]]\nbodies = [\"left\", \"right\"]\nfriction = 0.1\n[[contact.pairs]]\nbodies = [\"right\", \"left\"]\nfriction = 0.2\n\n[materials.steel]",
            )],
            "contact.pairs[1].bodies",
        ),
        case(
            "negative_pair_friction",
            &[(
                "[materials.steel]",
                "[contact]\n[[contact.pairs]]\nbodies = [\"left\", \"right\"]\nfriction = -0.5\n\n[materials.steel]",
            )],
            "contact.pairs[0].friction",
        ),
        case(
            "constraint_without_velocity",
            &[("shape = { kind = \"segment\", from = -0.001, to = 0.0 }", concat!("shape = { kind = \"segment\", from = -0.001, to = 0.0 }", "\n\n[[bodies.constraints]]\nregion = { kind = \"segment\", from = -0.001, to = -0.0008 }\n"))],
            "bodies[0].constraints[0].velocity",
        ),
        case(
            "constraint_with_velocity_and_fixed",
            &[("shape = { kind = \"segment\", from = -0.001, to = 0.0 }", concat!("shape = { kind = \"segment\", from = -0.001, to = 0.0 }", "\n\n[[bodies.constraints]]\nregion = { kind = \"segment\", from = -0.001, to = -0.0008 }\nvelocity = [1.0]\nfixed = true\n"))],
            "bodies[0].constraints[0].fixed",
        ),
        case(
            "constraint_leaving_everything_free",
            &[("shape = { kind = \"segment\", from = -0.001, to = 0.0 }", concat!("shape = { kind = \"segment\", from = -0.001, to = 0.0 }", "\n\n[[bodies.constraints]]\nregion = { kind = \"segment\", from = -0.001, to = -0.0008 }\nfixed = true\nfree = [\"x\"]\n"))],
            "bodies[0].constraints[0].free",
        ),
        case(
            "constraint_region_of_the_wrong_dimension",
            &[("shape = { kind = \"segment\", from = -0.001, to = 0.0 }", concat!("shape = { kind = \"segment\", from = -0.001, to = 0.0 }", "\n\n[[bodies.constraints]]\nregion = { kind = \"disk\", center = [0.0, 0.0], radius = 0.001 }\nfixed = true\n"))],
            "bodies[0].constraints[0].region",
        ),
        case(
            "constraint_region_holding_no_particle",
            &[("shape = { kind = \"segment\", from = -0.001, to = 0.0 }", concat!("shape = { kind = \"segment\", from = -0.001, to = 0.0 }", "\n\n[[bodies.constraints]]\nregion = { kind = \"segment\", from = 0.5, to = 0.6 }\nfixed = true\n"))],
            "bodies[0].constraints[0].region",
        ),
        case(
            "constraints_overlapping",
            &[("shape = { kind = \"segment\", from = -0.001, to = 0.0 }", concat!("shape = { kind = \"segment\", from = -0.001, to = 0.0 }", "\n\n[[bodies.constraints]]\nregion = { kind = \"segment\", from = -0.001, to = -0.0007 }\nfixed = true\n", "\n\n[[bodies.constraints]]\nregion = { kind = \"segment\", from = -0.0008, to = -0.0005 }\nfixed = true\n"))],
            "bodies[0].constraints[1].region",
        ),
        case(
            "constraint_probe_of_an_unknown_constraint",
            &[("quantity = \"total\"", "quantity = \"total\"\n\n[[probes]]\nname = \"f\"\nkind = \"constraint\"\nconstraint = \"clamp\"\nquantity = \"force_x\"")],
            "probes[2].constraint",
        ),
        case(
            "gravity_of_the_wrong_dimension",
            &[("dimension = 1", "dimension = 1\ngravity = [0.0, -9.81]")],
            "simulation.gravity",
        ),
        case(
            "gravity_not_finite",
            &[("dimension = 1", "dimension = 1\ngravity = [nan]")],
            "simulation.gravity",
        ),
        case(
            "gravity_across_the_axis_of_a_body_of_revolution",
            &[(
                "dimension = 2",
                "dimension = 2\ngeometry = \"axisymmetric\"\ngravity = [9.81, 0.0]",
            )],
            "simulation.gravity",
        )
        .two_d(),
    ]);
}

/// Velocities and points of the wrong dimension; shapes of the wrong dimension.
const YIELD: &str = "yield_stress = 600.0e6";
const ZA: &str = "strength = { kind = \"zerilli_armstrong\", c0 = 65e6, c2 = 890e6, c3 = 0.0028, c4 = 0.000115, room_temperature = 294.0 }\nspecific_heat = 383.0";
const MJC: &str = "strength = { kind = \"modified_johnson_cook\", a = 490e6, b = 807e6, n = 0.73, c = 0.0114, m = 0.94, reference_strain_rate = 5e-4, room_temperature = 293.0, melt_temperature = 1800.0 }\nspecific_heat = 452.0";
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
            &[(YIELD, "strength = { kind = \"steinberg_guinan\", a = 1.0 }")],
            "materials.steel.strength.kind",
        )
        .located()
        .also(&["zerilli_armstrong", "johnson_cook", "modified_johnson_cook"]),
        case("za_unknown_key", &[(YIELD, ZA), ("c4 = 0.000115", "c4 = 0.000115, a = 1.0")], "materials.steel.strength.a").located(),
        case("za_negative_c2", &[(YIELD, ZA), ("c2 = 890e6", "c2 = -890e6")], "materials.steel.strength.c2"),
        case("za_no_yield", &[(YIELD, ZA), ("c0 = 65e6", "c0 = 0.0")], "materials.steel.strength.c0"),
        case("za_hardening_without_n", &[(YIELD, ZA), ("c2 = 890e6", "c5 = 266e6")], "materials.steel.strength.n"),
        case("za_zero_rate_floor", &[(YIELD, ZA), ("c4 = 0.000115", "c4 = 0.000115, minimum_strain_rate = 0.0")], "materials.steel.strength.minimum_strain_rate"),
        case(
            "za_damage_temperature_without_melt",
            &[(YIELD, ZA), ("specific_heat = 383.0", "specific_heat = 383.0\nfailure = { kind = \"johnson_cook\", d1 = 0.54, d2 = 4.89, d3 = -3.03, d4 = 0.014, d5 = 1.12 }")],
            "materials.steel.failure.d5",
        ),
        case("mjc_negative_m", &[(YIELD, MJC), ("m = 0.94", "m = -0.94")], "materials.steel.strength.m"),
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
        case("cavitation_zero", &[(YIELD, "yield_stress = 600.0e6\ncavitation_pressure = 0.0")], "materials.steel.cavitation_pressure")
            .also(&["inf"]),
        case("cavitation_nan", &[(YIELD, "yield_stress = 600.0e6\ncavitation_pressure = nan")], "materials.steel.cavitation_pressure"),
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

/// A symmetry plane: its keys, and what it does not run with.
#[test]
fn symmetry_planes() {
    const PLANE: &str =
        "[[symmetry]]\nnormal = [1.0, 0.0]\npoint = [0.0, 0.0]\n\n[materials.steel]";
    check_cases(&[
        case(
            "symmetry_in_1d",
            &[(
                "[materials.steel]",
                "[[symmetry]]\nnormal = [1.0]\npoint = [0.0]\n\n[materials.steel]",
            )],
            "symmetry[0]",
        ),
        case(
            "symmetry_twice_on_one_axis",
            &[(
                "[materials.steel]",
                "[[symmetry]]\nnormal = [1.0, 0.0]\npoint = [0.0, 0.0]\n[[symmetry]]\nnormal = [-1.0, 0.0]\npoint = [0.01, 0.0]\n\n[materials.steel]",
            )],
            "symmetry[1].normal",
        )
        .two_d(),
        case(
            "symmetry_oblique_normal",
            &[(
                "[materials.steel]",
                "[[symmetry]]\nnormal = [0.6, 0.8]\npoint = [0.0, 0.0]\n\n[materials.steel]",
            )],
            "symmetry[0].normal",
        )
        .two_d(),
        case(
            "symmetry_normal_1d_in_2d",
            &[(
                "[materials.steel]",
                "[[symmetry]]\nnormal = [1.0]\npoint = [0.0, 0.0]\n\n[materials.steel]",
            )],
            "symmetry[0].normal",
        )
        .two_d(),
        case(
            "symmetry_point_not_finite",
            &[(
                "[materials.steel]",
                "[[symmetry]]\nnormal = [1.0, 0.0]\npoint = [nan, 0.0]\n\n[materials.steel]",
            )],
            "symmetry[0].point",
        )
        .two_d(),
        case(
            "symmetry_along_the_axis",
            &[
                ("dimension = 2", "dimension = 2\ngeometry = \"axisymmetric\""),
                ("min = [-0.001, -0.001]", "min = [0.0, -0.001]"),
                (
                    "[materials.steel]",
                    "[[symmetry]]\nnormal = [1.0, 0.0]\npoint = [0.0, 0.0]\n\n[materials.steel]",
                ),
            ],
            "symmetry[0].normal",
        )
        .also(&["already a mirror"])
        .two_d(),
        case(
            "symmetry_with_gravity_across_it",
            &[
                ("dimension = 2", "dimension = 2\ngravity = [1.0, -9.81]"),
                ("[materials.steel]", PLANE),
            ],
            "simulation.gravity",
        )
        .two_d(),
        case(
            "symmetry_beyond_a_body",
            &[(
                "[materials.steel]",
                "[[symmetry]]\nnormal = [0.0, -1.0]\npoint = [0.0, -0.0011]\n\n[materials.steel]",
            )],
            "bodies[0].shape",
        )
        .also(&["beyond the symmetry plane"])
        .two_d(),
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
        .also(&["iron", "(the scene defines: steel)"]),
        case(
            "particle_probe_unknown_body",
            &[(PROBE0_BODY, "body = \"middle\"\nat = [-0.0005]")],
            "probes[0].body",
        )
        .also(&["middle", "(the scene defines: left, right)"]),
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
