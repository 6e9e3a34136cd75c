//! Symmetry planes (`[[symmetry]]`, docs/method.md §13): a scene cut along
//! a plane of its symmetry is the whole scene's half, to round-off, when
//! its lattice is symmetric about the plane (a particle on the plane kept
//! with half its mass): the paper's two disks on either lattice cut
//! along their line of centres (contact across the cut), and the
//! penetration cut along its axis of impact. (The GPU path's twin:
//! tests/gpu_stages/parity.rs and tests/gpu_runs/symmetry.rs.)

#[path = "common/mod.rs"]
mod common;
use common::*;

use sphcontact::run::RunOutput;
use sphcontact::scene::{Scene, Symmetry};

/// The shipped half scene at `half`, checked to be the scene at `whole`
/// cut by the plane through the origin with `normal`.
fn shipped(whole: &str, half: &str, normal: [f64; 2]) -> (Scene, Scene) {
    let (w, mut h) = (load(whole), load(half));
    h.title.clone_from(&w.title);
    assert_eq!(h, cut(&w, normal), "{half} is not {whole} cut");
    (w, h)
}

/// `scene` cut by the plane through the origin with `normal`, keeping
/// the half it points to.
fn cut(scene: &Scene, normal: [f64; 2]) -> Scene {
    let mut s = scene.clone();
    s.symmetry.push(Symmetry {
        normal: normal.to_vec(),
        point: vec![0.0, 0.0],
    });
    s
}

/// Asserts that `half` ran the half of `full` on the side `normal`
/// points to: each body half the mass, the ledger's every term (the
/// frictional heat among them) half the whole's, every half particle
/// where a particle of the whole ended, and none beyond the plane.
/// `tol`: relative.
fn is_the_half(full: &RunOutput, half: &RunOutput, normal: glam::DVec2, tol: f64) {
    is_the_part(full, half, &[normal], tol);
}

/// [`is_the_half`] of the part of `full` cut by planes through the origin
/// with `normals`: each body `2^-k` of the mass and the ledger, k planes.
fn is_the_part(full: &RunOutput, half: &RunOutput, normals: &[glam::DVec2], tol: f64) {
    let parts = f64::from(1u32 << normals.len());
    let (f, h) = (&full.summary, &half.summary);
    assert_eq!(h.status, "completed");
    for (bf, bh) in f.bodies.iter().zip(&h.bodies) {
        assert!(
            (parts * bh.mass - bf.mass).abs() <= 1e-12 * bf.mass,
            "{}: mass {} of {}",
            bh.name,
            bh.mass,
            bf.mass
        );
    }
    let (lf, lh) = (&f.energy, &h.energy);
    let e0 = lf.initial;
    for (name, a, b) in [
        ("kinetic", lf.kinetic, lh.kinetic),
        ("internal", lf.internal, lh.internal),
        ("dashpot heat", lf.dashpot_heat, lh.dashpot_heat),
        (
            "artificial dissipation",
            lf.artificial_dissipation,
            lh.artificial_dissipation,
        ),
        ("spring loss", lf.spring_loss, lh.spring_loss),
        (
            "frictional heat",
            lf.friction_heat.unwrap_or(0.0),
            lh.friction_heat.unwrap_or(0.0),
        ),
    ] {
        assert!(
            (parts * b - a).abs() <= tol * e0,
            "{name}: the half's {b:e} against the whole's {a:e}"
        );
    }
    let (xf, xh) = (&full.state.x, &half.state.x);
    let scale = xf.iter().map(|x| x.length()).fold(0.0, f64::max);
    for x in xh {
        // On it at most (a particle placed on it stays there).
        for normal in normals {
            assert!(x.dot(*normal) >= 0.0, "a particle crossed a plane: {x}");
        }
        let nearest = xf
            .iter()
            .map(|y| (*x - *y).length())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest <= tol * scale,
            "the half's particle at {x} is {nearest:e} m from every particle of the whole"
        );
    }
}

/// The half's own books: in plane strain the momentum along the plane
/// kept (the plane takes the momentum normal to it, as the image's
/// contact and stress would; `speed`, the fastest body's, sets the
/// scale), and the energy ledger closed as a whole scene's
/// ([`assert_conserved`]'s CPU bound). (A body of revolution cut normal
/// to its axis keeps no momentum: its radial momentum is no conserved
/// quantity, and the plane takes the axial.)
fn books(half: &RunOutput, normal: glam::DVec2, speed: Option<f64>) {
    let s = &half.summary;
    if let Some(speed) = speed {
        let t = normal.perp();
        let along = |m: &[f64]| glam::DVec2::new(m[0], m[1]).dot(t);
        let (p0, p1) = (along(&s.momentum_initial), along(&s.momentum_final));
        let scale: f64 = s.bodies.iter().map(|b| b.mass).sum::<f64>() * speed;
        assert!(
            (p1 - p0).abs() <= 1e-12 * scale,
            "momentum along the plane drifted: {p0} -> {p1}"
        );
    }
    let drift = s.energy_balance().abs();
    assert!(drift < 1e-10, "energy drift {drift:e}");
    assert!(s.energy.dashpot_heat >= 0.0 && s.energy.artificial_dissipation >= 0.0);
}

/// The largest difference of two history columns, the part's times `k`
/// (the whole over the part, for an extensive column; else 1), over the
/// whole's largest magnitude.
fn column_gap(full: &RunOutput, half: &RunOutput, name: &str, k: f64) -> f64 {
    let (a, b) = (column(full, name), column(half, name));
    assert_eq!(a.len(), b.len());
    let peak = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(&b)
        .map(|(x, y)| (k * y - x).abs())
        .fold(0.0, f64::max)
        / peak
}

/// The paper's disks on `lattice` ("square" or "polar") cut along their
/// line of centres (scenes/symmetry/disks_{lattice}_half.toml): the
/// contact point lies on the plane, and each half disk meets the other's
/// image across it. On the polar lattice the disks' centres and their
/// rings' particles on the diameter lie on the plane, each with half its
/// mass. Measured: the contact force 3e-14 of its peak from the whole's
/// (either lattice), the contact time the same row for row.
fn half_disks(lattice: &str) {
    half_disks_with(lattice, 0.0);
}

/// [`half_disks`] with the dispersion correction at `theta` (0: off).
fn half_disks_with(lattice: &str, theta: f64) {
    let (mut full, mut half) = shipped(
        &format!("scenes/paper/disks_{lattice}.toml"),
        &format!("scenes/symmetry/disks_{lattice}_half.toml"),
        [0.0, 1.0],
    );
    for s in [&mut full, &mut half] {
        s.simulation.dispersion_correction = theta;
    }
    let (a, b) = (run(&full), run(&half));
    books(&b, glam::DVec2::Y, Some(5.0));
    is_the_half(&a, &b, glam::DVec2::Y, 1e-9);
    let force = column_gap(&a, &b, "contact_force", 2.0);
    println!("{lattice}, θ {theta}: the contact force {force:.2e} of its peak from the whole's");
    assert!(force <= 1e-9, "contact force off by {force:e} of its peak");
    let touching = |o: &RunOutput| -> Vec<bool> {
        column(o, "contact_force")
            .iter()
            .map(|&f| f > 0.0)
            .collect()
    };
    assert_eq!(touching(&a), touching(&b), "the contact times differ");
    for v in ["velocity_left", "velocity_right"] {
        let gap = column_gap(&a, &b, v, 1.0);
        assert!(gap <= 1e-9, "{v} off by {gap:e}");
    }
}

#[test]
fn half_disks_give_the_whole_pairs_contact() {
    half_disks("square");
}

#[test]
fn half_disks_give_the_whole_pairs_contact_midpoint() {
    on_midpoint(|| half_disks("square"));
}

#[test]
fn half_polar_disks_give_the_whole_pairs_contact() {
    half_disks("polar");
}

/// The dispersion correction across the plane (docs/method.md §13): its
/// sums meet the neighbours' images, with their velocity gradients,
/// correction matrices, stresses and extra stresses mirrored, and on the
/// polar lattice the particles on the plane with half their volume.
#[test]
fn half_disks_with_the_dispersion_correction_give_the_whole_pairs_contact() {
    half_disks_with("square", 0.7);
}

#[test]
fn half_polar_disks_with_the_dispersion_correction_give_the_whole_pairs_contact() {
    half_disks_with("polar", 0.7);
}

/// Verney's imploding shell (scenes/hard/verney_{geometry}.toml), here
/// at 10 particles through the wall over its first 20 µs, cut through
/// its centre by the plane normal to y: the cylinder (plane strain) on a
/// diameter, the sphere (a body of revolution, its shell on §12's polar
/// half rings) at its equator. The particles of the polar rings on the
/// plane are halved, and the half is the whole shell's. Measured: the
/// ledger half the whole's to 3e-14 (cylinder) and 5e-15 (sphere) of the
/// initial energy, the inner radius's probe to 2e-16 and exactly.
fn half_shell(geometry: &str, probe: &str) {
    let mut whole = load(&format!("scenes/hard/verney_{geometry}.toml"));
    whole.bodies[0].spacing = 2.0e-3;
    whole.simulation.end_time = 2.0e-5;
    let half = cut(&whole, [0.0, 1.0]);
    let (a, b) = (run(&whole), run(&half));
    assert!(
        b.state.x.iter().any(|x| x.y == 0.0),
        "no particle on the plane"
    );
    let speed = (geometry == "cylinder").then_some(490.30);
    books(&b, glam::DVec2::Y, speed);
    is_the_half(&a, &b, glam::DVec2::Y, 1e-9);
    let gap = column_gap(&a, &b, probe, 1.0);
    assert!(gap <= 1e-9, "{probe} off by {gap:e}");
}

/// Verney's cylinder, on the square lattice (symmetric about both planes,
/// where the polar rings' particle counts need not be multiples of four),
/// as a quadrant between two planes (Spheral's model of the shell): each
/// particle near both planes meets the images across either and across
/// the corner: each term of the ledger a quarter of the whole's and the
/// inner radii the whole's, within 1e-9.
#[test]
fn quarter_cylinder_gives_the_whole_shell() {
    let mut whole = load("scenes/hard/verney_cylinder.toml");
    whole.bodies[0].spacing = 2.0e-3;
    whole.simulation.end_time = 2.0e-5;
    if let sphcontact::scene::Shape::Ring { lattice, .. } = &mut whole.bodies[0].shape {
        *lattice = sphcontact::scene::Lattice::Square;
    }
    let quarter = cut(&cut(&whole, [0.0, 1.0]), [1.0, 0.0]);
    let (a, b) = (run(&whole), run(&quarter));
    books(&b, glam::DVec2::Y, None);
    is_the_part(&a, &b, &[glam::DVec2::Y, glam::DVec2::X], 1e-9);
    for probe in ["inner_x", "inner_y"] {
        let gap = column_gap(&a, &b, probe, 1.0);
        assert!(gap <= 1e-9, "{probe} off by {gap:e}");
    }
}

#[test]
fn half_cylinder_gives_the_whole_shell() {
    half_shell("cylinder", "inner_x");
}

#[test]
fn half_sphere_of_revolution_gives_the_whole_shell() {
    half_shell("sphere", "inner_r");
}

/// The whole penetration and its half (the shipped scenes at Δx 0.2 mm)
/// run to `end` with Coulomb friction `mu` between rod and plate.
fn half_penetration(end: f64, mu: f64) -> (RunOutput, RunOutput) {
    let (mut full, mut half) = shipped(
        "scenes/penetration/tungsten_rod_steel_plate.toml",
        "scenes/symmetry/tungsten_rod_steel_plate_half.toml",
        [1.0, 0.0],
    );
    for s in [&mut full, &mut half] {
        for b in &mut s.bodies {
            b.spacing = 2e-4;
        }
        s.simulation.end_time = end;
        if mu > 0.0 {
            s.contact.get_or_insert_with(Default::default).friction = mu;
        }
    }
    (run(&full), run(&half))
}

/// The tungsten rod into the steel plate cut along its axis of impact
/// (scenes/symmetry/tungsten_rod_steel_plate_half.toml, here at Δx 0.2
/// mm and to 15 µs, through the plate's first half): plastic flow,
/// erosion by failure and contact all meet across the plane. Measured
/// at 30 µs: the residual velocity 1e-13 from the whole's.
#[test]
fn half_penetration_gives_the_whole_residual_velocity() {
    let (a, b) = half_penetration(1.5e-5, 0.0);
    books(&b, glam::DVec2::X, Some(1200.0));
    is_the_half(&a, &b, glam::DVec2::X, 1e-9);
    for v in ["velocity_rod", "velocity_plate"] {
        let gap = column_gap(&a, &b, v, 1.0);
        assert!(gap <= 1e-9, "{v} off by {gap:e}");
    }
}

/// The same penetration with Coulomb friction 0.1 between rod and plate
/// (docs/method.md §8.6), to 10 µs: the rod's nose rubs on the crater's
/// particles and their images across the plane, and the gathers of the
/// normal force and of the rub's reaction take the images' share. The
/// frictional heat, as every other term of the ledger, half the whole's.
#[test]
fn half_penetration_with_friction_gives_the_whole() {
    let (a, b) = half_penetration(1e-5, 0.1);
    books(&b, glam::DVec2::X, Some(1200.0));
    is_the_half(&a, &b, glam::DVec2::X, 1e-9);
    let heat = a.summary.energy.friction_heat.expect("friction");
    assert!(
        heat > 1e-3 * a.summary.energy_initial,
        "the rod rubs: {heat:e}"
    );
    for v in ["velocity_rod", "velocity_plate"] {
        let gap = column_gap(&a, &b, v, 1.0);
        assert!(gap <= 1e-9, "{v} off by {gap:e}");
    }
}

/// A steel tube swaged onto a steel rod, bodies of revolution cut at
/// their mid-plane (scenes/symmetry/tube_onto_rod_half.toml): the images
/// across the axis, the plane and both, and the contact across the
/// plane. The whole is the same scene without its plane.
#[test]
fn half_tube_on_a_rod_gives_the_whole() {
    let half = load("scenes/symmetry/tube_onto_rod_half.toml");
    let mut full = half.clone();
    full.symmetry.clear();
    let (a, b) = (run(&full), run(&half));
    books(&b, glam::DVec2::Y, None);
    is_the_half(&a, &b, glam::DVec2::Y, 1e-9);
    let force = column_gap(&a, &b, "contact_force", 2.0);
    assert!(force <= 1e-9, "contact force off by {force:e} of its peak");
    let gap = column_gap(&a, &b, "velocity_tube", 1.0);
    assert!(gap <= 1e-9, "the tube's speed off by {gap:e}");
    assert!(column(&b, "contact_force").iter().any(|&f| f > 0.0));
}

/// A steel ring closing onto a steel disk in plane strain, as a quadrant
/// (scenes/symmetry/ring_onto_disk_quadrant.toml): the images across
/// either plane and the corner in the sums, and the contact across either
/// plane. The whole is the same scene without its planes: every term of
/// the ledger and the contact force a quarter of the whole's, the ring's
/// place the whole's, within 1e-9 (measured: 2.5e-14 of the peak force).
#[test]
fn quarter_ring_on_a_disk_gives_the_whole() {
    let quarter = load("scenes/symmetry/ring_onto_disk_quadrant.toml");
    let mut full = quarter.clone();
    full.symmetry.clear();
    let (a, b) = (run(&full), run(&quarter));
    books(&b, glam::DVec2::Y, None);
    is_the_part(&a, &b, &[glam::DVec2::X, glam::DVec2::Y], 1e-9);
    let force = column_gap(&a, &b, "contact_force", 4.0);
    assert!(force <= 1e-9, "contact force off by {force:e} of its peak");
    let gap = column_gap(&a, &b, "ring_x", 1.0);
    assert!(gap <= 1e-9, "the ring's place off by {gap:e}");
    assert!(column(&b, "contact_force").iter().any(|&f| f > 0.0));
}

/// [`quarter_ring_on_a_disk_gives_the_whole`] with Coulomb friction 0.3
/// between ring and disk: the square lattices slip a little where the
/// ring's bore meets the disk, across either plane as well, and the
/// quadrant's frictional heat is a quarter of the whole's, as every other
/// term of its ledger.
#[test]
fn quarter_ring_on_a_disk_with_friction_gives_the_whole() {
    let mut quarter = load("scenes/symmetry/ring_onto_disk_quadrant.toml");
    quarter
        .contact
        .get_or_insert_with(Default::default)
        .friction = 0.3;
    let mut full = quarter.clone();
    full.symmetry.clear();
    let (a, b) = (run(&full), run(&quarter));
    books(&b, glam::DVec2::Y, None);
    is_the_part(&a, &b, &[glam::DVec2::X, glam::DVec2::Y], 1e-9);
    let heat = a.summary.energy.friction_heat.expect("friction");
    assert!(heat > 0.0, "the ring rubs");
    let force = column_gap(&a, &b, "contact_force", 4.0);
    assert!(force <= 1e-9, "contact force off by {force:e} of its peak");
}
