//! The user's own geometry: polygons and particles files.

use super::*;

const DISK_SHAPE: &str =
    "shape = { kind = \"disk\", center = [0.0, 0.001], radius = 0.001, lattice = \"square\" }";

/// A valid particles file of four particles above the plate.
const GOOD_CSV: &str =
    "x,y,volume\n0.0,0.0004,4e-8\n0.0002,0.0004,4e-8\n0.0,0.0006,4e-8\n0.0002,0.0006,4e-8\n";

#[test]
fn polygons_and_particles_files() {
    check_cases(&[
        case(
            "self_intersecting_polygon",
            &[(
                DISK_SHAPE,
                "shape = { kind = \"polygon\", vertices = [[0.0, 0.0002], [0.001, 0.001], [0.001, 0.0002], [0.0, 0.001]] }",
            )],
            "bodies[1].shape.vertices",
        )
        .also(&["intersects itself", "edge 0", "edge 2"])
        .two_d(),
        case(
            "polygon_repeating_a_vertex",
            &[(
                DISK_SHAPE,
                "shape = { kind = \"polygon\", lattice = \"boundary\", vertices = [[0.0, 0.0002], [0.001, 0.0002], [0.001, 0.0002], [0.0, 0.001]] }",
            )],
            "bodies[1].shape.vertices[2]",
        )
        .also(&["repeats vertex 1"])
        .two_d(),
        case(
            "polygon_of_two_vertices",
            &[(
                DISK_SHAPE,
                "shape = { kind = \"polygon\", vertices = [[0.0, 0.0002], [0.001, 0.001]] }",
            )],
            "bodies[1].shape.vertices",
        )
        .also(&["at least 3"])
        .two_d(),
        case(
            "polygon_vertex_of_three_numbers",
            &[(
                DISK_SHAPE,
                "shape = { kind = \"polygon\", vertices = [[0.0, 0.0002], [0.001, 0.0002, 0.0], [0.0, 0.001]] }",
            )],
            "bodies[1].shape.vertices[1]",
        )
        .two_d(),
        case(
            "hole_outside_its_outline",
            &[(
                DISK_SHAPE,
                "shape = { kind = \"polygon\", vertices = [[0.0, 0.0002], [0.001, 0.0002], [0.001, 0.001], [0.0, 0.001]], holes = [[[0.0002, 0.0004], [0.0004, 0.0004], [0.0004, 0.002]]] }",
            )],
            "bodies[1].shape.holes[0]",
        )
        .also(&["not inside the outline"])
        .two_d(),
        case(
            "overlapping_holes",
            &[(
                DISK_SHAPE,
                "shape = { kind = \"polygon\", vertices = [[0.0, 0.0002], [0.001, 0.0002], [0.001, 0.001], [0.0, 0.001]], holes = [[[0.0002, 0.0004], [0.0006, 0.0004], [0.0006, 0.0008]], [[0.0003, 0.0005], [0.0005, 0.0005], [0.0005, 0.0007]]] }",
            )],
            "bodies[1].shape.holes[1]",
        )
        .also(&["overlaps holes[0]"])
        .two_d(),
        case(
            "polygon_in_1d",
            &[(
                RIGHT_SHAPE,
                "shape = { kind = \"polygon\", vertices = [[0.0, 0.0], [0.001, 0.0], [0.0, 0.001]] }",
            )],
            "bodies[1].shape.kind",
        )
        .also(&["2-D"]),
        case(
            "particles_file_missing",
            &[(DISK_SHAPE, "shape = { kind = \"particles\", file = \"none.csv\" }")],
            "bodies[1].shape.file",
        )
        .also(&["cannot read", "none.csv"])
        .two_d(),
        case(
            "particles_file_not_a_number",
            &[(DISK_SHAPE, "shape = { kind = \"particles\", file = \"bad.csv\" }")],
            "bodies[1].shape.file",
        )
        .also(&["bad.csv", "'0.0o04'", "column 'y'"])
        .located()
        .with_files(&[("bad.csv", "x,y,volume\n0.0,0.0004,4e-8\n0.0002,0.0o04,4e-8\n")])
        .two_d(),
        case(
            "particles_file_short_line",
            &[(DISK_SHAPE, "shape = { kind = \"particles\", file = \"short.csv\" }")],
            "bodies[1].shape.file",
        )
        .also(&["line 3", "2 fields"])
        .with_files(&[("short.csv", "x,y,mass\n0.0,0.0004,0.1\n0.0002,0.0004\n")])
        .two_d(),
        case(
            "particles_file_without_volume",
            &[(DISK_SHAPE, "shape = { kind = \"particles\", file = \"novol.csv\" }")],
            "bodies[1].shape.file",
        )
        .also(&["'volume' or 'mass'"])
        .with_files(&[("novol.csv", "x,y\n0.0,0.0004\n")])
        .two_d(),
        case(
            "particles_far_from_the_spacing",
            &[(
                "name = \"disk\"\nmaterial = \"steel\"\nspacing = 2.0e-4",
                "name = \"disk\"\nmaterial = \"steel\"\nspacing = 5.0e-4",
            ), (DISK_SHAPE, "shape = { kind = \"particles\", file = \"good.csv\" }")],
            "bodies[1].spacing",
        )
        .also(&["25 %"])
        .with_files(&[("good.csv", GOOD_CSV)])
        .two_d(),
        case(
            "particles_velocity_twice",
            &[(DISK_SHAPE, "shape = { kind = \"particles\", file = \"moving.csv\" }")],
            "bodies[1].velocity",
        )
        .with_files(&[("moving.csv", "x,y,volume,vx,vy\n0.0,0.0004,4e-8,0,-10\n")])
        .two_d(),
        case(
            "particles_jittered",
            &[(
                DISK_SHAPE,
                "shape = { kind = \"particles\", file = \"good.csv\" }\njitter = 0.1",
            )],
            "bodies[1].jitter",
        )
        .with_files(&[("good.csv", GOOD_CSV)])
        .two_d(),
    ]);
}

const AXISYMMETRIC: (&str, &str) = (
    "dimension = 2\nend_time",
    "dimension = 2\ngeometry = \"axisymmetric\"\nend_time",
);
const PLATE_FROM_AXIS: (&str, &str) = (
    "min = [-0.001, -0.001], max = [0.001, 0.0]",
    "min = [0.0, -0.001], max = [0.001, 0.0]",
);

#[test]
fn bodies_of_revolution() {
    check_cases(&[
        case(
            "axisymmetric_body_at_negative_r",
            &[AXISYMMETRIC],
            "bodies[0].shape",
        )
        .also(&["r = -0.001", "radius"])
        .two_d(),
        case(
            "axisymmetric_disk_across_the_axis_off_centre",
            &[
                AXISYMMETRIC,
                PLATE_FROM_AXIS,
                ("center = [0.0, 0.001]", "center = [0.0005, 0.001]"),
            ],
            "bodies[1].shape",
        )
        .also(&["without being centred on the axis"])
        .two_d(),
        case(
            "axisymmetric_polygon_at_negative_r",
            &[
                AXISYMMETRIC,
                PLATE_FROM_AXIS,
                (
                    DISK_SHAPE,
                    "shape = { kind = \"polygon\", vertices = [[-0.0002, 0.0002], [0.001, 0.0002], [0.0, 0.001]] }",
                ),
            ],
            "bodies[1].shape",
        )
        .also(&["vertex at r = -0.0002"])
        .two_d(),
        case(
            "axisymmetric_particle_on_the_axis",
            &[
                AXISYMMETRIC,
                PLATE_FROM_AXIS,
                (DISK_SHAPE, "shape = { kind = \"particles\", file = \"axis.csv\" }"),
            ],
            "bodies[1].shape.file",
        )
        .also(&["particle 0", "data line 1", "r = 0"])
        .with_files(&[("axis.csv", "x,y,volume\n0.0,0.0004,4e-8\n0.0002,0.0004,4e-8\n")])
        .two_d(),
        case("axisymmetric_in_1d", &[("dimension = 1", "dimension = 1\ngeometry = \"axisymmetric\"")], "simulation.geometry")
            .also(&["dimension = 2"]),
    ]);
}
