//! The user's own geometry (docs/scenes.md, "Shapes"): a rectangle drawn
//! as a polygon is the rectangle, bit for bit on both backends; the
//! paper's disk case from particles files and drawn as polygons with holes
//! gives the built-in shapes' answers.

mod common;
use common::*;
use sphcontact::model::Model;
use sphcontact::run::RunOutput;
use sphcontact::scene::Backend;
use sphcontact::validation::exact::{hertz_c_inertia, hertz_disks, HERTZ_C_JOHNSON};
use sphcontact::Scene;

/// Two steel blocks closing at 10 m/s; `$LEFT` and `$RIGHT` are their shapes.
const BLOCKS: &str = r#"
[simulation]
dimension = 2
end_time = 1.0e-6

[materials.steel]
density = 7850.0
shear_modulus = 77.0e9
eos = { kind = "mie_gruneisen", c0 = 4580.0, s = 1.49, gamma0 = 2.02 }

[[bodies]]
name = "left"
material = "steel"
spacing = 1.0e-4
velocity = [5.0, 0.0]
shape = $LEFT

[[bodies]]
name = "right"
material = "steel"
spacing = 1.0e-4
velocity = [-5.0, 0.0]
shape = $RIGHT

[[probes]]
name = "force"
kind = "contact"
bodies = ["left", "right"]
quantity = "force"

[[probes]]
name = "v"
kind = "particle"
body = "left"
at = [-0.0005, 0.0001]
quantity = "velocity_x"
"#;

fn blocks(left: &str, right: &str) -> Scene {
    parse(&BLOCKS.replace("$LEFT", left).replace("$RIGHT", right))
}

/// A rectangle given as a polygon (clockwise, from another corner, with
/// a vertex in the middle of one side) places the rectangle's particles,
/// masses and offsets bit for bit, and runs to the same history bit for
/// bit on the CPU and on the GPU.
#[test]
fn a_rectangle_drawn_as_a_polygon_is_the_rectangle() {
    let rect = blocks(
        r#"{ kind = "rectangle", min = [-0.002, -0.0005], max = [0.0, 0.0007] }"#,
        r#"{ kind = "rectangle", min = [0.0, -0.0004], max = [0.0013, 0.0004] }"#,
    );
    let poly = blocks(
        r#"{ kind = "polygon", vertices = [[0.0, 0.0007], [0.0, -0.0005], [-0.002, -0.0005], [-0.002, 0.0001], [-0.002, 0.0007]] }"#,
        r#"{ kind = "polygon", vertices = [[0.0, -0.0004], [0.0013, -0.0004], [0.0013, 0.0004], [0.0, 0.0004]] }"#,
    );
    let (mr, sr) = Model::new(&rect);
    let (mp, sp) = Model::new(&poly);
    assert_eq!(mr.len(), mp.len());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&mr.mass), bits(&mp.mass), "masses");
    assert_eq!(bits(&mr.offset), bits(&mp.offset), "offsets");
    assert_eq!(bits(&mr.h), bits(&mp.h), "smoothing lengths");
    let xy = |s: &sphcontact::model::State| {
        s.x.iter()
            .flat_map(|p| [p.x.to_bits(), p.y.to_bits()])
            .collect::<Vec<_>>()
    };
    assert_eq!(xy(&sr), xy(&sp), "positions");
    let mut backends = vec![Backend::Cpu];
    if gpu().is_some() {
        backends.push(Backend::Gpu);
    }
    for b in backends {
        let (a, p) = (run_on(&rect, b, None), run_on(&poly, b, None));
        assert_eq!(a.summary.steps, p.summary.steps, "{b}: steps");
        let force = column(&a, "force");
        assert!(force.iter().any(|&f| f > 1e5), "{b}: the blocks touch");
        for name in ["force", "v"] {
            assert_eq!(
                bits(&column(&a, name)),
                bits(&column(&p, name)),
                "{b}: {name}"
            );
        }
    }
}

/// Peak force and contact time of a disk-case run.
fn impact(out: &RunOutput) -> (f64, f64) {
    let f = column(out, "contact_force");
    let peak = f.iter().cloned().fold(0.0, f64::max);
    let (t0, t1) = contact_window(&out.history.times, &f);
    (peak, t1 - t0)
}

/// Run the built-in scene and the user's shapes' one, and hold the
/// latter's peak force and contact time within `tol` of the former's;
/// returns the second run.
fn same_impact(builtin: (&str, &Scene), shapes: (&str, &Scene), tol: f64) -> RunOutput {
    let (a, b) = (run(builtin.1), run(shapes.1));
    let ((pa, ta), (pb, tb)) = (impact(&a), impact(&b));
    println!(
        "{}: peak {:.4} MN/m, contact {:.3} µs; {}: {:.4} MN/m, {:.3} µs",
        builtin.0,
        pa / 1e6,
        ta * 1e6,
        shapes.0,
        pb / 1e6,
        tb * 1e6
    );
    assert!((pb / pa - 1.0).abs() < tol, "peak force");
    assert!((tb / ta - 1.0).abs() < tol, "contact time");
    b
}

/// The paper's disk case (polar lattice, R/Δx = 25) with each disk read
/// from a particles file holding the built-in disk's particles and
/// volumes but no surface offsets: the solver finds the outer ring's
/// offsets within 5 % of the built-in Δr/2, and the impact's peak force
/// and contact time come within 1 % of the built-in disks' and inside the
/// Hertz bracket.
#[test]
fn particles_files_run_the_paper_disks() {
    let builtin = load("scenes/paper/disks_polar.toml");
    let files = load("scenes/shapes/particles_disks.toml");
    let (mb, sb) = Model::new(&builtin);
    let (mf, sf) = Model::new(&files);
    assert_eq!(mb.len(), mf.len(), "particle count");
    for (a, b) in sb.x.iter().zip(&sf.x) {
        assert!(a.distance(*b) < 1e-15, "{a} against {b}");
    }
    for (a, b) in mb.mass.iter().zip(&mf.mass) {
        assert!((a / b - 1.0).abs() < 1e-14, "mass {a} against {b}");
    }
    // The outer ring: built-in offset Δr/2 = 0.1 mm.
    let (mut outer, mut worst) = (0, 0.0f64);
    for i in 0..mb.len() {
        if mb.offset[i] < 0.15e-3 {
            outer += 1;
            let e = mf.offset[i] / mb.offset[i] - 1.0;
            worst = worst.max(e.abs());
            assert!(
                e.abs() < 0.05,
                "offset of {i}: {} against {}",
                mf.offset[i],
                mb.offset[i]
            );
        }
    }
    assert!(outer > 300, "{outer} outer particles");
    println!(
        "outer ring: {outer} particles, offsets within {:.2} % of Δr/2",
        100.0 * worst
    );
    let b = same_impact(("built-in disks", &builtin), ("from files", &files), 0.01);
    let steel = material(&files, "steel");
    let soft = hertz_disks(&steel, 0.005, 10.0, HERTZ_C_JOHNSON);
    let stiff = hertz_disks(&steel, 0.005, 10.0, hertz_c_inertia(steel.nu));
    let (pb, tb) = impact(&b);
    assert_in_hertz_bracket(pb, tb, &soft, &stiff, 0.1);
    assert_conserved(&files, &b);
}

/// The disk case with each disk drawn as a polygon of 64 vertices with a
/// hole of 32 (scenes/shapes/polygon_rings.toml) against the built-in
/// square-lattice rings of the same radii: the particle counts differ only
/// by the cells between the chords and the arcs, and the impact's peak
/// force and contact time agree within 1 % (the square and polar lattices'
/// disks differ by 4 % and 3 %).
#[test]
fn polygons_with_holes_run_as_the_builtin_rings() {
    let poly = load("scenes/shapes/polygon_rings.toml");
    let mut rings = load("scenes/paper/disks_square.toml");
    for b in &mut rings.bodies {
        let sphcontact::scene::Shape::Disk { center, .. } = &b.shape else {
            panic!("the paper's disks");
        };
        b.shape = sphcontact::scene::Shape::Ring {
            center: center.clone(),
            inner_radius: 0.002,
            outer_radius: 0.005,
            lattice: sphcontact::scene::Lattice::Square,
        };
    }
    let (mp, _) = Model::new(&poly);
    let (mr, _) = Model::new(&rings);
    let differ = mp.len().abs_diff(mr.len());
    println!("polygons {} particles, rings {}", mp.len(), mr.len());
    // The chords of 64 and 32 vertices cut off slivers of at most
    // R (1 − cos(π/N)) ≈ 6 and 10 µm, against the 0.2 mm lattice: the
    // cells whose centres fall in them, under 1 % of the particles
    // (measured: 16 of 3,320, all outside the outer chords).
    assert!(differ * 100 < mr.len(), "{differ} particles apart");
    let b = same_impact(("built-in rings", &rings), ("polygons", &poly), 0.01);
    assert_conserved(&poly, &b);
}

/// The paper's polar disks, coarse (Δx = 0.5 mm, 630 particles, closing at
/// 80 m/s), written to particles files with each particle's velocity and
/// run from them: the CPU and GPU runs agree within 0.5 % in peak force
/// and contact time, and a run stopped at a checkpoint and resumed writes
/// the uninterrupted run's history byte for byte.
#[test]
fn particles_files_with_velocities_on_both_backends_and_resumed() {
    let mut builtin = load("scenes/paper/disks_polar.toml");
    for (b, v) in builtin.bodies.iter_mut().zip([40.0, -40.0]) {
        b.spacing = 5.0e-4;
        b.velocity = Some(vec![v, 0.0]);
    }
    let (model, state) = Model::new(&builtin);
    let tmp = tempfile::tempdir().expect("a temporary directory");
    let mut scene = builtin.clone();
    for (k, b) in scene.bodies.iter_mut().enumerate() {
        let rho0 = builtin.materials[&b.material].density;
        let mut csv = String::from("x,y,volume,vx,vy\n");
        for i in model.bodies[k].range.clone() {
            let (x, v) = (state.x[i], state.v[i]);
            csv += &format!(
                "{:e},{:e},{:e},{:e},{:e}\n",
                x.x,
                x.y,
                model.mass[i] / rho0,
                v.x,
                v.y
            );
        }
        let file = tmp.path().join(format!("{}.csv", b.name));
        std::fs::write(&file, csv).expect("write the particles");
        b.shape = sphcontact::scene::Shape::Particles { file };
        b.velocity = None;
    }
    let scene = parse(&scene.to_toml());
    let (mf, sf) = Model::new(&scene);
    assert_eq!(mf.len(), model.len());
    assert!(sf.v.iter().zip(&state.v).all(|(a, b)| a == b), "velocities");

    let cpu = run_on(&scene, Backend::Cpu, None);
    let (pc, tc) = impact(&cpu);
    assert!(pc > 1e6, "the disks collide: peak {pc:e} N/m");
    if gpu().is_some() {
        let g = run_on(&scene, Backend::Gpu, None);
        let (pg, tg) = impact(&g);
        println!(
            "cpu: peak {:.4} MN/m, contact {:.3} µs; gpu: {:.4} MN/m, {:.3} µs",
            pc / 1e6,
            tc * 1e6,
            pg / 1e6,
            tg * 1e6
        );
        assert!((pg / pc - 1.0).abs() < 5e-3, "peak force");
        assert!((tg / tc - 1.0).abs() < 5e-3, "contact time");
    }

    let opts = |dir: &std::path::Path, every: Option<f64>| sphcontact::run::RunOptions {
        out_dir: Some(dir.to_path_buf()),
        backend: Some(Backend::Cpu),
        silent: true,
        write: true,
        checkpoint_every: every,
        ..Default::default()
    };
    let (full, ck) = (tmp.path().join("full"), tmp.path().join("ck"));
    sphcontact::run::run_scene(&scene, None, &opts(&full, None)).expect("runs");
    sphcontact::run::run_scene(&scene, None, &opts(&ck, Some(5.0e-6))).expect("runs");
    let resume = sphcontact::run::RunOptions {
        backend: Some(Backend::Cpu),
        silent: true,
        ..Default::default()
    };
    sphcontact::run::resume_run(&ck, &resume).expect("resumes");
    let read = |d: &std::path::Path| std::fs::read(d.join("history.csv")).expect("a history");
    assert_eq!(read(&full), read(&ck), "the resumed history");
}

/// The paper's disk case with each disk drawn as a polygon of 256
/// vertices filled on the boundary-following lattice, against the
/// built-in polar-lattice disks: the body's mass is the polygon's, the
/// particle counts agree within 2 %, and the impact's peak force and
/// contact time within 1 %.
#[test]
fn a_circle_on_the_boundary_lattice_runs_as_the_polar_disk() {
    let polar = load("scenes/paper/disks_polar.toml");
    let mut poly = polar.clone();
    let n = 256;
    for b in &mut poly.bodies {
        let sphcontact::scene::Shape::Disk { center, radius, .. } = &b.shape else {
            panic!("the paper's disks");
        };
        let vertices = (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                vec![center[0] + radius * a.cos(), center[1] + radius * a.sin()]
            })
            .collect();
        b.shape = sphcontact::scene::Shape::polygon(
            vertices,
            Vec::new(),
            sphcontact::scene::PolygonLattice::Boundary,
        );
    }
    let poly = parse(&poly.to_toml());
    let (mp, _) = Model::new(&poly);
    let (mr, _) = Model::new(&polar);
    let rho0 = polar.materials["steel"].density;
    let r = 0.005;
    let area = 0.5 * n as f64 * r * r * (std::f64::consts::TAU / n as f64).sin();
    let mass: f64 = mp.bodies[0].range.clone().map(|i| mp.mass[i]).sum();
    assert!((mass / (rho0 * area) - 1.0).abs() < 1e-12, "mass {mass}");
    println!(
        "boundary lattice {} particles, polar {}",
        mp.len(),
        mr.len()
    );
    assert!(
        mp.len().abs_diff(mr.len()) * 50 < mr.len(),
        "particle counts"
    );
    let b = same_impact(
        ("polar disks", &polar),
        ("boundary-lattice polygons", &poly),
        0.01,
    );
    assert_conserved(&poly, &b);
}

/// The paper's two steel bars (1-D) with the right bar read from a file
/// holding the segment's positions, lengths and surface offsets: the
/// same model bit for bit, and the same history bit for bit. Without the
/// offset column the ends' offsets are found within 2 % of Δx/2.
#[test]
fn a_segment_from_a_file_with_offsets_is_the_segment() {
    let bars = load("scenes/paper/bars_steel.toml");
    let (model, state) = Model::new(&bars);
    let tmp = tempfile::tempdir().expect("a temporary directory");
    let right = &model.bodies[1];
    let rho0 = bars.materials[&bars.bodies[1].material].density;
    let write = |name: &str, offsets: bool| {
        let mut csv = String::from(if offsets {
            "x,volume,offset\n"
        } else {
            "x,volume\n"
        });
        for i in right.range.clone() {
            // The segment's cell length, as placement computes it.
            let len = model.mass[i] / rho0;
            csv += &format!("{:e},{:e}", state.x[i].x, len);
            if offsets {
                csv += &format!(",{:e}", model.offset[i]);
            }
            csv += "\n";
        }
        let file = tmp.path().join(name);
        std::fs::write(&file, csv).expect("write the particles");
        let mut scene = bars.clone();
        scene.bodies[1].shape = sphcontact::scene::Shape::Particles { file };
        scene.bodies[1].spacing = right.spacing;
        parse(&scene.to_toml())
    };
    let with = write("with.csv", true);
    let (mw, sw) = Model::new(&with);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&mw.mass), bits(&model.mass), "masses");
    assert_eq!(bits(&mw.offset), bits(&model.offset), "offsets");
    assert_eq!(bits(&mw.h), bits(&model.h), "smoothing lengths");
    assert!(sw.x.iter().zip(&state.x).all(|(a, b)| a == b), "positions");
    let (a, b) = (run(&bars), run(&with));
    assert_eq!(a.summary.steps, b.summary.steps);
    for name in &a.history.names {
        assert_eq!(bits(&column(&a, name)), bits(&column(&b, name)), "{name}");
    }
    let found = write("without.csv", false);
    let (mf, _) = Model::new(&found);
    let ends = [right.range.start, right.range.end - 1];
    for i in ends {
        let e = mf.offset[i] / model.offset[i] - 1.0;
        assert!(
            e.abs() < 0.02,
            "end {i}: {} against {}",
            mf.offset[i],
            model.offset[i]
        );
    }
}

/// A radial velocity field (docs/scenes.md, "Bodies"): every particle of
/// an imploding shell, in the plane and as a body of revolution, moves at
/// the body's velocity plus `speed (radius/r)^exponent` along the
/// direction from the centre; bad keys are refused naming them.
#[test]
fn a_radial_velocity_field_is_the_incompressible_flow() {
    let shell = |geometry: &str, exponent: u32, extra: &str| {
        format!(
            r#"
[simulation]
dimension = 2
{geometry}
end_time = 1.0e-6
[materials.be]
density = 1845.0
shear_modulus = 151.0e9
eos = {{ kind = "linear", c0 = 7998.0 }}
[[bodies]]
name = "shell"
material = "be"
spacing = 2.0e-3
velocity = [0.0, 3.0]
shape = {{ kind = "ring", center = [0.0, 0.01], inner_radius = 0.08, outer_radius = 0.1, lattice = "polar" }}
velocity_field = {{ kind = "radial", center = [0.0, 0.01], speed = -490.3, radius = 0.08, exponent = {exponent}{extra} }}
"#
        )
    };
    for (geometry, exponent) in [("", 1), ("geometry = \"axisymmetric\"", 2)] {
        let scene = parse(&shell(geometry, exponent, ""));
        let (_, state) = Model::new(&scene);
        for (x, v) in state.x.iter().zip(&state.v) {
            let d = *x - glam::DVec2::new(0.0, 0.01);
            let r = d.length();
            let want =
                glam::DVec2::new(0.0, 3.0) + d / r * (-490.3 * (0.08 / r).powi(exponent as i32));
            assert!((*v - want).length() < 1e-12, "{geometry}: {v} at {x}");
        }
    }
    let refused = |text: String, key: &str| {
        let e = Scene::from_toml_str(&text, "s.toml").expect_err("refused");
        assert!(e.to_string().contains(key), "{e}");
    };
    refused(
        shell("", 1, "").replace("exponent = 1", "exponent = -1"),
        "velocity_field.exponent",
    );
    refused(
        shell("", 1, "").replace("radius = 0.08, exponent", "radius = 0.0, exponent"),
        "velocity_field.radius",
    );
    refused(
        shell("", 1, "").replace("center = [0.0, 0.01], speed", "center = [0.0], speed"),
        "velocity_field.center",
    );
    refused(shell("", 1, ", swirl = 1.0"), "swirl");
    refused(
        shell("", 1, "").replace("velocity = [0.0, 3.0]", "rigid = true"),
        "velocity_field",
    );
}
