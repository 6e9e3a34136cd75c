//! Sections drawn in CAD (docs/scenes.md, "Drawn sections"): the polygon
//! scenes of scenes/shapes/ read from SVG and DXF drawings in millimetres
//! place the typed polygons' particles bit for bit, curves are cut within
//! the tolerance, and a bad drawing is refused naming the element at
//! fault.

mod common;
use common::*;
use sphcontact::scene::{place_bodies, Shape};
use sphcontact::Scene;
use std::path::{Path, PathBuf};

fn shapes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/shapes")
}

/// Every placed particle's position, mass and boundary offset, as bits.
fn particles(scene: &Scene) -> Vec<(u64, u64, u64, u64)> {
    place_bodies(scene)
        .iter()
        .flat_map(|b| {
            (0..b.positions.len()).map(|i| {
                (
                    b.positions[i].x.to_bits(),
                    b.positions[i].y.to_bits(),
                    b.masses[i].to_bits(),
                    b.offsets[i].to_bits(),
                )
            })
        })
        .collect()
}

/// A shipped scene with its drawn file swapped for `file`.
fn drawn(scene: &str, from: &str, to: &str) -> Scene {
    let path = shapes().join(scene);
    let text = std::fs::read_to_string(&path).unwrap().replace(from, to);
    Scene::from_toml_in(&text, scene, &shapes()).expect("a valid scene")
}

#[test]
fn drawn_sections_place_the_typed_polygons_particles_bit_for_bit() {
    for (typed, scene, svg, dxf) in [
        (
            "polygon_rings.toml",
            "rings_drawn.toml",
            "rings.svg",
            "rings.dxf",
        ),
        (
            "wedge_on_plate.toml",
            "wedge_drawn.toml",
            "wedge.svg",
            "wedge.dxf",
        ),
    ] {
        let typed = load(&format!("scenes/shapes/{typed}"));
        let want = particles(&typed);
        assert!(want.len() > 1000, "{}", want.len());
        for file in [svg, dxf] {
            let [from, to] = if scene.starts_with("rings") {
                ["rings.svg", file]
            } else {
                ["wedge.dxf", file]
            };
            let got = drawn(scene, from, to);
            // The vertices themselves, then every particle.
            for (a, b) in typed.bodies.iter().zip(&got.bodies) {
                let (
                    Shape::Polygon {
                        vertices: va,
                        holes: ha,
                        ..
                    },
                    Shape::Polygon {
                        vertices: vb,
                        holes: hb,
                        ..
                    },
                ) = (&a.shape, &b.shape)
                else {
                    assert_eq!(a.shape, b.shape);
                    continue;
                };
                let bits = |v: &Vec<Vec<f64>>| {
                    v.iter()
                        .map(|p| (p[0].to_bits(), p[1].to_bits()))
                        .collect::<Vec<_>>()
                };
                assert_eq!(bits(va), bits(vb), "{file}: {}", a.name);
                assert_eq!(ha.len(), hb.len(), "{file}: {}", a.name);
                for (x, y) in ha.iter().zip(hb) {
                    assert_eq!(bits(x), bits(y), "{file}: a hole of {}", a.name);
                }
            }
            assert!(particles(&got) == want, "{file}: the particles differ");
        }
    }
}

/// A scene of one steel body drawn in `file` (written to `dir` with
/// `content`), and the extra shape keys `keys`.
fn scene_with(dir: &Path, file: &str, content: &str, keys: &str) -> Result<Scene, String> {
    std::fs::write(dir.join(file), content).unwrap();
    let text = format!(
        r#"
[simulation]
dimension = 2
end_time = 1.0e-6

[materials.steel]
density = 7850.0
shear_modulus = 77.0e9
eos = {{ kind = "mie_gruneisen", c0 = 4580.0, s = 1.49, gamma0 = 2.02 }}

[[bodies]]
name = "part"
material = "steel"
spacing = 2.0e-4
[bodies.shape]
kind = "polygon"
file = "{file}"
{keys}
"#
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    Scene::from_file(&path).map_err(|e| e.to_string())
}

fn svg(width: &str, body: &str) -> String {
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="10mm" viewBox="0 0 10 10">{body}</svg>"#
    )
}

/// A DXF drawing in `units` ($INSUNITS) of the given entities (code,
/// value pairs).
fn dxf(units: u32, entities: &[&[(u32, &str)]]) -> String {
    let mut s = format!(
        "0\nSECTION\n2\nHEADER\n9\n$ACADVER\n1\nAC1015\n9\n$INSUNITS\n70\n{units}\n0\nENDSEC\n0\nSECTION\n2\nENTITIES\n"
    );
    for e in entities {
        for (code, value) in *e {
            s.push_str(&format!("{code}\n{value}\n"));
        }
    }
    s + "0\nENDSEC\n0\nEOF\n"
}

#[test]
fn curves_are_cut_within_the_tolerance_and_units_are_read() {
    let dir = tempfile::tempdir().unwrap();
    // A disk of radius 4 mm with a hole of 1 mm, as an SVG circle pair in
    // a path of arcs (evenodd), as DXF circles in centimetres, and as a
    // DXF LWPOLYLINE of two half-circle bulges: every vertex on the circle
    // and every chord's middle within the tolerance of it.
    let tol = 1e-5;
    let keys = format!("tolerance = {tol}");
    let arcs = r#"<path fill-rule="evenodd" d="M 1,5 A 4,4 0 0 1 9,5 A 4,4 0 0 1 1,5 Z M 4,5 A 1,1 0 0 0 6,5 A 1,1 0 0 0 4,5 Z"/>"#;
    let circle = |r: &'static str, h: &'static str| -> Vec<(u32, &'static str)> {
        vec![
            (0, "CIRCLE"),
            (5, h),
            (8, "0"),
            (10, "0.5"),
            (20, "0.5"),
            (30, "0"),
            (40, r),
        ]
    };
    let bulged: Vec<(u32, &str)> = vec![
        (0, "LWPOLYLINE"),
        (5, "30"),
        (8, "0"),
        (90, "2"),
        (70, "1"),
        (10, "0.1"),
        (20, "0.5"),
        (42, "-1"),
        (10, "0.9"),
        (20, "0.5"),
        (42, "-1"),
    ];
    let cases = [
        ("arcs.svg", svg("10mm", arcs), (0.005, -0.005), Some(1e-3)),
        (
            "circles.dxf",
            dxf(5, &[&circle("0.4", "2A"), &circle("0.1", "2B")]),
            (0.005, 0.005),
            Some(1e-3),
        ),
        ("bulged.dxf", dxf(5, &[&bulged]), (0.005, 0.005), None),
    ];
    for (file, content, (cx, cy), hole) in cases {
        let scene = scene_with(dir.path(), file, &content, &keys).unwrap();
        let Shape::Polygon {
            vertices, holes, ..
        } = &scene.bodies[0].shape
        else {
            panic!("a polygon");
        };
        assert_eq!(holes.len(), usize::from(hole.is_some()), "{file}");
        let rings = std::iter::once((vertices, 0.004)).chain(holes.iter().zip(hole));
        for (ring, r) in rings {
            // Cubic arcs stray 2.7e-4 r from the circle on their own.
            let slack = if file.ends_with("svg") {
                2.8e-4 * r
            } else {
                1e-12
            };
            let n = ring.len();
            assert!(n >= 8, "{file}: {n} vertices");
            for k in 0..n {
                let (a, b) = (&ring[k], &ring[(k + 1) % n]);
                let d = |x: f64, y: f64| ((x - cx).powi(2) + (y - cy).powi(2)).sqrt() - r;
                assert!(d(a[0], a[1]).abs() <= slack, "{file}: vertex {k}");
                let mid = d(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]));
                assert!(
                    mid <= 0.0 && -mid <= tol + slack,
                    "{file}: chord {k}: {mid}"
                );
            }
            // Not needlessly fine: within 1.5 times the fewest chords.
            let fewest = std::f64::consts::PI / (1.0 - tol / r).acos();
            assert!((n as f64) < 1.5 * fewest + 8.0, "{file}: {n} vs {fewest}");
        }
    }
    // A rounded rectangle, ry taking rx: its area w h − (4 − π) r², less
    // what the chords cut off (at most the perimeter times the tolerance).
    let rounded = svg("10mm", r#"<rect x="1" y="1" width="4" height="2" rx="1"/>"#);
    let s = scene_with(dir.path(), "rounded.svg", &rounded, &keys).unwrap();
    let Shape::Polygon { vertices, .. } = &s.bodies[0].shape else {
        panic!("a polygon");
    };
    let n = vertices.len();
    let area = 0.5
        * (0..n)
            .map(|k| {
                let (a, b) = (&vertices[k], &vertices[(k + 1) % n]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
            .abs();
    let want = (8.0 - (4.0 - std::f64::consts::PI)) * 1e-6;
    let perimeter = (4.0 + 2.0 * std::f64::consts::PI) * 1e-3;
    assert!(
        area <= want && want - area <= perimeter * tol,
        "{area} vs {want}"
    );
    // An inch drawing, a scale that overrides the stated unit, and an
    // offset.
    let square = r#"<polygon points="0,0 1,0 1,1 0,1"/>"#;
    let page = |w: &str| {
        format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" viewBox="0 0 2 2">{square}</svg>"#
        )
    };
    for (w, keys, side) in [
        ("2in", "", 0.0254),
        ("20mm", "", 0.01),
        ("20mm", "scale = 0.5", 0.5),
        ("2in", "scale = 1e-3", 1e-3),
    ] {
        let s = scene_with(dir.path(), "square.svg", &page(w), keys).unwrap();
        let Shape::Polygon { vertices, .. } = &s.bodies[0].shape else {
            panic!("a polygon");
        };
        assert!(
            (vertices[1][0] - side).abs() < 1e-15 * side,
            "{w} {keys}: {vertices:?}"
        );
        // Down the page is down the scene.
        assert!(
            (vertices[2][1] + side).abs() < 1e-15 * side,
            "{w} {keys}: {vertices:?}"
        );
    }
    let s = scene_with(
        dir.path(),
        "square.svg",
        &page("20mm"),
        "offset = [0.25, 0.5]",
    )
    .unwrap();
    let Shape::Polygon { vertices, .. } = &s.bodies[0].shape else {
        panic!("a polygon");
    };
    assert_eq!(vertices[0], vec![0.25, 0.5]);
    assert!((vertices[2][0] - 0.26).abs() < 1e-15 && (vertices[2][1] - 0.49).abs() < 1e-15);
}

#[test]
fn bad_drawings_are_refused_naming_the_element() {
    let dir = tempfile::tempdir().unwrap();
    let lines = |end: &'static str| -> Vec<Vec<(u32, &'static str)>> {
        [
            ("0", "0", "10", "0", "21"),
            ("10", "0", "10", "10", "22"),
            ("10", "10", "0", end, "23"),
        ]
        .into_iter()
        .map(|(x1, y1, x2, y2, h)| {
            vec![
                (0, "LINE"),
                (5, h),
                (8, "part"),
                (10, x1),
                (20, y1),
                (11, x2),
                (21, y2),
            ]
        })
        .collect()
    };
    let bow: Vec<(u32, &str)> = vec![
        (0, "LWPOLYLINE"),
        (5, "2A"),
        (8, "part"),
        (90, "4"),
        (70, "1"),
        (10, "0"),
        (20, "0"),
        (10, "10"),
        (20, "10"),
        (10, "10"),
        (20, "0"),
        (10, "0"),
        (20, "10"),
    ];
    let spline: Vec<(u32, &str)> = vec![(0, "SPLINE"), (5, "3C"), (8, "part")];
    let open = lines("1");
    let closed = lines("0");
    let refs = |v: &[Vec<(u32, &'static str)>]| -> String {
        dxf(4, &v.iter().map(Vec::as_slice).collect::<Vec<_>>())
    };
    let cases: Vec<(&str, String, &str, &str)> = vec![
        (
            "open.svg",
            svg("10mm", r#"<path id="lip" d="M 0,0 L 5,0 L 5,5"/>"#),
            "",
            r#"<path id="lip">: the outline is open: it ends at (5, 5), not where it starts, (0, 0)"#,
        ),
        (
            "open.dxf",
            refs(&open),
            "",
            "LINE (handle 21, layer 'part') and 2 more joined to it: the outline is open",
        ),
        (
            "bow.dxf",
            dxf(4, &[&bow]),
            "",
            "LWPOLYLINE (handle 2A, layer 'part'): the outline crosses itself",
        ),
        (
            "em.svg",
            svg("10em", r#"<rect width="5" height="5"/>"#),
            "",
            "unknown unit in the <svg> width '10em': give `scale`",
        ),
        (
            "unitless.dxf",
            refs(&closed).replace("$INSUNITS\n70\n4", "$INSUNITS\n70\n0"),
            "",
            "the drawing states no unit ($INSUNITS is 0, unitless): give `scale`",
        ),
        (
            "spline.dxf",
            dxf(4, &[&spline]),
            "",
            "SPLINE (handle 3C, layer 'part') is not read as an outline",
        ),
        (
            "layer.dxf",
            refs(&closed),
            r#"layer = "plate""#,
            "no layer 'plate' in",
        ),
        (
            "crossing.svg",
            svg(
                "10mm",
                r#"<path id="plate" fill-rule="evenodd" d="M 0,0 H 5 V 5 H 0 Z M 4,1 H 6 V 2 H 4 Z"/>"#,
            ),
            "",
            r#"<path id="plate"> and <path id="plate"> (subpath 2) cross or touch"#,
        ),
        (
            "two.svg",
            svg(
                "10mm",
                r#"<rect id="a" width="2" height="2"/><circle id="b" cx="6" cy="6" r="1"/>"#,
            ),
            "",
            r#"holds 2 separate outlines (<rect id="a">, <circle id="b">)"#,
        ),
        (
            "text.svg",
            "this is not a drawing".to_string(),
            "",
            "is not readable XML",
        ),
        (
            "both.svg",
            svg("10mm", r#"<rect width="5" height="5"/>"#),
            "vertices = [[0, 0], [1, 0], [0, 1]]",
            "either as `vertices` (and `holes`) or as a drawn `file`, not both",
        ),
    ];
    for (file, content, keys, want) in cases {
        let e = scene_with(dir.path(), file, &content, keys).unwrap_err();
        assert!(e.contains(want), "{file}: {e}");
        assert!(e.contains("bodies[0].shape"), "{file}: {e}");
    }
    // The layer's error lists the drawing's layers; the CLI exits 2.
    let e = scene_with(
        dir.path(),
        "layer.dxf",
        &refs(&closed),
        r#"layer = "plate""#,
    )
    .unwrap_err();
    assert!(e.contains("(it has 'part')"), "{e}");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_sphcontact"))
        .arg("check")
        .arg(dir.path().join("scene.toml"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("no layer 'plate'"), "{stderr}");
    // The closed chain itself is read.
    assert!(scene_with(dir.path(), "closed.dxf", &refs(&closed), "").is_ok());
}
