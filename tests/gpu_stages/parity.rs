//! Every stage against its CPU twin on the paper's scenes.

use super::*;
use sphcontact::scene::{
    ArtPairs, ArtPlastic, ArtWork, ArtificialStress, ArtificialViscosity, ViscosityForm,
};

#[test]
fn stages_match_cpu_disks_square() {
    check_stages("scenes/paper/disks_square.toml", 3e-6);
}

#[test]
fn stages_match_cpu_disks_polar() {
    check_stages("scenes/paper/disks_polar.toml", 3e-6);
}

/// The entry overlaps (`State::entry`) on both sides of the rule: body
/// 0's particles joined the surface with a small overlap (their springs
/// push against less, or nothing), body 1's were off the surface at the
/// last step (they join now: no spring of their own).
#[test]
fn stages_match_cpu_with_entry_overlaps() {
    if gpu().is_none() {
        return;
    }
    let (model, mut st) = state_during_contact("scenes/paper/disks_square.toml", 3e-6);
    let dx = model.bodies[0].spacing;
    for i in 0..model.len() {
        st.entry[i] = if model.body[i] == 0 { 2e-3 * dx } else { -1.0 };
    }
    check_state(model, st, true);
}

/// Disks pushed half a spacing further into each other than the run
/// had them: the deepest springs yield (`physics::penalty::yield_overlap`).
#[test]
fn stages_match_cpu_with_yielded_springs() {
    if gpu().is_none() {
        return;
    }
    let (model, mut st) = state_during_contact("scenes/paper/disks_square.toml", 3e-6);
    let dx = model.bodies[1].spacing;
    let shift = DVec2::new(-0.5 * dx, 0.0);
    for i in 0..model.len() {
        if model.body[i] == 1 {
            st.x[i] += shift;
        }
    }
    let nb = neighbours::find(&model, st.frame());
    let k = kinematics::kinematics(&model, &st, &nb);
    let bd = forces::boundary_of(&model, &st.x, &nb, &k);
    let c = contact::penalty(&model, &st, &nb, &bd);
    assert!(c.entry.iter().any(|e| e.1 > 0.0), "some spring yields");
    check_state(model, st, true);
}

#[test]
fn stages_match_cpu_bars_steel_aluminium() {
    check_stages("scenes/paper/bars_steel_aluminium.toml", 0.5e-6);
}

#[test]
fn stages_match_cpu_kernel_mode() {
    check_stages("scenes/paper/disks_square_kernel.toml", 2e-6);
}

/// Two steel spheres as bodies of revolution at the height of their
/// contact: the axis's mirror images in every sum, the hoop terms, the
/// ring areas of the contact.
#[test]
fn stages_match_cpu_spheres_axisymmetric() {
    check_stages("scenes/axisymmetric/spheres_hertz.toml", 8e-6);
}

/// The paper's polar disks cut along their line of centres
/// (scenes/symmetry/disks_polar_half.toml) 3 µs into their contact: each
/// particle near the plane meets its neighbours' images and its own, the
/// particles on the plane weigh half in the contact's sums, and each half
/// disk's contact passes take the other's images across the cut.
#[test]
fn stages_match_cpu_across_a_symmetry_plane() {
    check_stages("scenes/symmetry/disks_polar_half.toml", 3e-6);
}

/// A steel tube swaged onto a rod, bodies of revolution cut at their
/// mid-plane (scenes/symmetry/tube_onto_rod_half.toml), 0.4 µs into the
/// fit: a particle near the axis and the plane meets three images
/// (across the axis, the plane and both), and the contact meets the
/// partner's images across the plane.
#[test]
fn stages_match_cpu_across_a_symmetry_plane_axisymmetric() {
    check_stages("scenes/symmetry/tube_onto_rod_half.toml", 4e-7);
}

/// A steel ring closing onto a steel disk as a quadrant between two
/// planes (scenes/symmetry/ring_onto_disk_quadrant.toml), 0.3 µs into
/// their contact: a
/// particle near both planes meets three images (across either plane and
/// the corner), and the contact meets the partner's images across either
/// plane.
#[test]
fn stages_match_cpu_across_two_symmetry_planes() {
    check_stages("scenes/symmetry/ring_onto_disk_quadrant.toml", 3e-7);
}

/// The bilinear Taylor bar (16 across) spread on its wall at 40 µs: in a
/// body of revolution the surface test is taken relative to the colour
/// function (docs/method.md §8.1), and here that decides particles the
/// plain test would not.
#[test]
fn stages_match_cpu_on_a_spread_taylor_bar_axisymmetric() {
    if gpu().is_none() {
        return;
    }
    let mut scene = load("scenes/axisymmetric/taylor_bar_bilinear.toml");
    for b in &mut scene.bodies {
        b.spacing *= 2.0;
    }
    // Round supports: the surface set is decided on them either way, and
    // the bar's adaptive ones are held by the banded test below.
    scene.simulation.support = Some(sphcontact::scene::Support::Fixed);
    let (model, st) = state_of(&scene, 40e-6);
    let nb = neighbours::find(&model, st.frame());
    let a = kinematics::kinematics(&model, &st, &nb);
    let decided = (0..model.len())
        .filter(|&i| {
            a.surface[i] != (model.h[i] * a.grad_psi[i].length() > model.boundary_threshold)
        })
        .count();
    println!("{decided} particles decided by the colour function");
    assert!(decided > 0, "the plain test gives the same set");
    check_state(model, st, true);
}

/// A sphere of revolution on a rigid wall at the height of the impact: the
/// rigid body's boundary and areas on the axis.
#[test]
fn stages_match_cpu_sphere_on_wall_axisymmetric() {
    check_stages("scenes/axisymmetric/sphere_on_wall.toml", 8e-6);
}

/// The stages against the CPU at `t` of `path` with supports that adapt at
/// Δx = 0.2 mm within the band `band`, after checking that more than 20
/// supports are drawn out (and, with a band, that more than 20 deformable
/// ones are still round).
fn adaptive_parity(path: &str, t: f64, band: sphcontact::physics::support::Band) {
    if gpu().is_none() {
        return;
    }
    let mut scene = load(path);
    scene.simulation.support = Some(sphcontact::scene::Support::Adaptive);
    scene.simulation.support_band = Some(sphcontact::scene::SupportBand::Apart([
        band.drawn,
        band.squeezed,
    ]));
    for b in scene.bodies.iter_mut() {
        b.spacing = 2.0e-4;
    }
    let (model, st) = state_of(&scene, t);
    let stretched = st
        .metric
        .iter()
        .filter(|q| q.axes().1 > 1.2 * model.h[0])
        .count();
    let round = (0..st.metric.len())
        .filter(|&i| {
            !model.rigid(i)
                && st.metric[i] == sphcontact::physics::support::Metric::round(model.h[i])
        })
        .count();
    println!(
        "step {}: {stretched} supports drawn out, {round} round",
        st.step
    );
    assert!(stretched > 20, "{stretched} supports drawn out");
    if !band.is_none() {
        assert_eq!(st.carried.len(), st.metric.len());
        assert!(round > 20, "{round} supports round");
    }
    check_state(model, st, true);
}

/// Supports that adapt (docs/method.md, "Supports that follow the
/// deformation"), following from the start (`support_band = 1`): a
/// tungsten rod 1 µs into a 4340 plate at 1,200 m/s (Δx = 0.2 mm), its
/// supports drawn out and turned by the impact: the pairs in their mean
/// metric, the surface set and contact on round supports, the CFL step on
/// the minor semi-axes.
#[test]
fn stages_match_cpu_with_adaptive_supports() {
    adaptive_parity(
        "scenes/penetration/tungsten_rod_steel_plate.toml",
        1.0e-6,
        sphcontact::physics::support::Band::NONE,
    );
}

/// The same in a body of revolution: the computational Taylor bar 5 µs
/// onto its wall (16 particles across), its foot's supports drawn out
/// radially and mirrored across the axis.
#[test]
fn stages_match_cpu_with_adaptive_supports_axisymmetric() {
    adaptive_parity(
        "scenes/axisymmetric/taylor_bar_bilinear.toml",
        5.0e-6,
        sphcontact::physics::support::Band::NONE,
    );
}

/// The same across a symmetry plane: the rod and plate cut along the axis
/// of impact (scenes/symmetry/tungsten_rod_steel_plate_half.toml), the
/// images' supports the particles' mirrored.
#[test]
fn stages_match_cpu_with_adaptive_supports_across_a_symmetry_plane() {
    adaptive_parity(
        "scenes/symmetry/tungsten_rod_steel_plate_half.toml",
        1.0e-6,
        sphcontact::physics::support::Band::NONE,
    );
}

/// Within the default band: the rod 3 µs into the plate, where the crater's
/// supports have left the band and the rest are still round (the carried
/// ellipses on the GPU, their supports formed where they are read). The
/// state is at an odd step, and the device counts its steps from 0: the
/// first walks read the largest semi-axis from the slot of the device's
/// parity.
#[test]
fn stages_match_cpu_with_banded_supports() {
    adaptive_parity(
        "scenes/penetration/tungsten_rod_steel_plate.toml",
        3.0e-6,
        sphcontact::physics::support::DEFAULT_BAND,
    );
}

/// The same in a body of revolution: the Taylor bar 30 µs onto its wall.
#[test]
fn stages_match_cpu_with_banded_supports_axisymmetric() {
    adaptive_parity(
        "scenes/axisymmetric/taylor_bar_bilinear.toml",
        3.0e-5,
        sphcontact::physics::support::DEFAULT_BAND,
    );
}

/// The stages against the CPU at `t` of `path` with its viscosity
/// `edit`ed (and checked by `edited` on the model), on a velocity field
/// stirred particle by particle.
fn stirred_parity(
    path: &str,
    t: f64,
    edit: impl FnOnce(&mut ArtificialViscosity),
    edited: impl Fn(&Model) -> bool,
) {
    if gpu().is_none() {
        return;
    }
    let mut scene = load(path);
    edit(
        scene
            .artificial_viscosity
            .get_or_insert_with(Default::default),
    );
    let (model, mut st) = state_of(&scene, t);
    assert!(edited(&model));
    stir(&mut st);
    check_state(model, st, true);
}

/// The hourglass control (docs/method.md, "Hourglass control") with the
/// viscosity's reconstruction, in plane strain and in a body of
/// revolution (mirror images), where its terms are a large part of the
/// forces. 0.7: with the default (Riemann) viscosity the midpoint rule is
/// stable with the control to about 0.85 (docs/method.md, "The Riemann
/// form").
fn hourglass_parity(path: &str, t: f64) {
    stirred_parity(
        path,
        t,
        |av| av.hourglass = 0.7,
        |m| m.hourglass == 0.7 && m.av_reconstruct,
    );
}

#[test]
fn stages_match_cpu_with_hourglass_control() {
    hourglass_parity("scenes/paper/disks_polar.toml", 3e-6);
}

#[test]
fn stages_match_cpu_with_hourglass_control_axisymmetric() {
    hourglass_parity("scenes/axisymmetric/spheres_hertz.toml", 8e-6);
}

/// The Riemann form of the viscosity (receding pairs damped too)
/// reconstructed at surfaces as well (docs/method.md, "The Riemann
/// form"), in plane strain and in a body of revolution: half the stirred
/// field's pairs recede, and the minmod of the seen and the true jump
/// decides at some.
fn riemann_parity(path: &str, t: f64) {
    stirred_parity(
        path,
        t,
        |av| {
            av.form = ViscosityForm::Riemann;
            av.reconstruct_surfaces = true;
        },
        |m| m.av_release && m.av_recon_surface && m.av_reconstruct,
    );
}

#[test]
fn stages_match_cpu_with_riemann_viscosity() {
    riemann_parity("scenes/paper/disks_polar.toml", 3e-6);
}

#[test]
fn stages_match_cpu_with_riemann_viscosity_axisymmetric() {
    riemann_parity("scenes/axisymmetric/spheres_hertz.toml", 8e-6);
}

/// The artificial stress keyed on plastic flow (`work = "plastic"`): the
/// disks' steel given a yield stress that a tenth of the
/// elastic run's particles exceed, so that the contact zone flows and the
/// rest does not; every pair in tension takes the term (the
/// classic form) and the velocities are stirred, so that the flowing
/// pairs' heat shares are a large part of it.
#[test]
fn stages_match_cpu_with_plastic_flow() {
    if gpu().is_none() {
        return;
    }
    let path = "scenes/paper/disks_square.toml";
    let (_, elastic) = state_during_contact(path, 3e-6);
    let mut vm: Vec<f64> = elastic.s.iter().map(|s| s.von_mises()).collect();
    vm.sort_by(f64::total_cmp);
    let mut scene = load(path);
    scene.materials.get_mut("steel").unwrap().yield_stress = Some(vm[vm.len() * 9 / 10]);
    scene.artificial_stress = Some(ArtificialStress {
        pairs: ArtPairs::All,
        work: ArtWork::Plastic,
        ..ArtificialStress::DEFAULT
    });
    let (model, mut st) = state_of(&scene, 3e-6);
    let flowing = (0..model.len()).filter(|&i| model.flowing(&st, i)).count();
    assert!(
        flowing > 20 && flowing < model.len() / 2,
        "{flowing} of {} particles flow",
        model.len()
    );
    stir(&mut st);
    check_state(model, st, true);
}

/// The artificial stress keyed on the body (`work = "yielding"`, the
/// default): the paper's disks meeting through the SPH sums (kernel mode,
/// so pairs cross between them), the right one given a yield stress that
/// nothing reaches; its pairs, those across included, take only the heat
/// share, the left disk's the whole classic term; velocities stirred.
#[test]
fn stages_match_cpu_with_the_term_keyed_on_the_body() {
    if gpu().is_none() {
        return;
    }
    let mut scene = load("scenes/paper/disks_square_kernel.toml");
    let mut yielding = scene.materials["steel"].clone();
    yielding.yield_stress = Some(1.0e10);
    scene.materials.insert("yielding".into(), yielding);
    scene.bodies[1].material = "yielding".into();
    scene.artificial_stress = Some(ArtificialStress {
        pairs: ArtPairs::All,
        ..ArtificialStress::DEFAULT
    });
    let (model, mut st) = state_of(&scene, 3e-6);
    assert_eq!(model.artificial_stress.unwrap().work, ArtWork::Yielding);
    assert!(!model.yields(0) && model.yields(model.bodies[1].range.start));
    assert!(model.art_keyed_on_flow());
    stir(&mut st);
    check_state(model, st, true);
}

/// The hourglass control in place of the artificial stress in a body that
/// can yield (`plastic = "hourglass"`): the paper's disks meeting through
/// the SPH sums (kernel mode, so pairs cross between them), the right one
/// given a yield stress; its particles carry no artificial stress and
/// its families the control at 0.7, the left disk's the classic term and
/// the control at 0.2; velocities stirred.
#[test]
fn stages_match_cpu_with_hourglass_in_place_of_the_term() {
    if gpu().is_none() {
        return;
    }
    let mut scene = load("scenes/paper/disks_square_kernel.toml");
    let mut yielding = scene.materials["steel"].clone();
    yielding.yield_stress = Some(1.0e9);
    scene.materials.insert("yielding".into(), yielding);
    scene.bodies[1].material = "yielding".into();
    scene.artificial_stress = Some(ArtificialStress {
        pairs: ArtPairs::All,
        plastic: ArtPlastic::Hourglass,
        plastic_hourglass: 0.7,
        ..ArtificialStress::DEFAULT
    });
    scene
        .artificial_viscosity
        .get_or_insert_with(Default::default)
        .hourglass = 0.2;
    let (model, mut st) = state_of(&scene, 3e-6);
    assert!(model.bodies[0].art && !model.bodies[1].art);
    assert_eq!(
        (model.bodies[0].hourglass, model.bodies[1].hourglass),
        (0.2, 0.7)
    );
    stir(&mut st);
    check_state(model, st, true);
}

/// Three particles of the right disk torn off into a straight chain in
/// the empty corner above the contact, and five into a compact cross
/// below it (arms 0.8 Δx: an `M` the conditioning test accepts, four
/// neighbours each), in tension (1 % below their reference density) and
/// with a deviatoric stress: the chain's correction falls back and the
/// cross has too few neighbours, so on both backends they are debris
/// (docs/method.md, "Debris") and carry neither.
#[test]
fn stages_match_cpu_with_debris() {
    if gpu().is_none() {
        return;
    }
    let (model, mut st) = state_during_contact("scenes/paper/disks_square.toml", 3e-6);
    let dx = model.bodies[1].spacing;
    let top = st.x.iter().map(|x| x.y).fold(f64::MIN, f64::max);
    let right = st.x.iter().map(|x| x.x).fold(f64::MIN, f64::max);
    let torn: Vec<usize> = (0..model.len())
        .filter(|&i| model.body[i] == 1)
        .take(8)
        .collect();
    let cross = [(0.0, 0.0), (0.8, 0.0), (-0.8, 0.0), (0.0, 0.8), (0.0, -0.8)];
    for (k, &i) in torn.iter().enumerate() {
        st.x[i] = match cross.get(k.wrapping_sub(3)) {
            Some(&(a, b)) => DVec2::new(right + (a - 3.0) * dx, top + (b - 6.0) * dx),
            None => DVec2::new(right - (3.0 + k as f64) * dx, top - 2.0 * dx),
        };
        st.rho[i] *= 0.99;
        st.s[i] = Sym {
            xx: 1e8,
            yy: -1e8,
            xy: 5e7,
            zz: 0.0,
        };
    }
    let nb = neighbours::find(&model, st.frame());
    let k = kinematics::kinematics(&model, &st, &nb);
    let pts = cpu::eos_and_stress_with(&model, &st, &k.fallback);
    for &i in &torn {
        assert!(k.fallback.contains(&(i as u32)), "{i} is debris");
        assert_eq!(pts[i].sr2, Sym::default(), "debris {i} carries no stress");
    }
    check_state(model, st, true);
}

/// Coulomb friction (contact.wgsl, RUB): the oblique disk of
/// scenes/friction/disk_wall_oblique.toml part-way through its contact,
/// sliding (μ = 0.1 at 45°, its slips at the limit) and sticking (μ = 1
/// at 20°, its slips inside it): the rub pass and its gather against
/// cpu::contact's friction, in the contact's forces and the full rates.
#[test]
fn stages_match_cpu_with_friction() {
    if gpu().is_none() {
        return;
    }
    for (mu, degrees) in [(0.1, 45.0), (1.0, 20.0)] {
        let (model, st) = oblique_disk_at_3_us(mu, degrees);
        let nb = neighbours::find(&model, st.frame());
        let k = kinematics::kinematics(&model, &st, &nb);
        let bd = forces::boundary_of(&model, &st.x, &nb, &k);
        let c = contact::penalty(&model, &st, &nb, &bd);
        let (normal, _) = c.stats.pair(0, 1);
        let (tangential, _) = c.stats.tangential(0, 1);
        println!("μ {mu}: normal {normal:e}, tangential {tangential:e}");
        assert!(tangential.abs() > 0.05 * mu * normal, "the disk rubs");
        assert!(st.slip.iter().any(|&u| u != 0.0), "slips carried");
        check_state(model, st, true);
    }
}

/// Coulomb friction across a symmetry plane: the rod and plate cut along
/// the axis of impact (scenes/symmetry/tungsten_rod_steel_plate_half.toml,
/// Δx 0.2 mm, μ = 0.1) 6 µs into the plate, where the rod's nose rubs on
/// the crater's particles and their images: the rub's normal force and
/// its gather take what the passes that met a particle's image handed it.
#[test]
fn stages_match_cpu_with_friction_across_a_symmetry_plane() {
    if gpu().is_none() {
        return;
    }
    let mut scene = load("scenes/symmetry/tungsten_rod_steel_plate_half.toml");
    for b in &mut scene.bodies {
        b.spacing = 2e-4;
    }
    scene.contact.get_or_insert_with(Default::default).friction = 0.1;
    let (model, st) = state_of(&scene, 6e-6);
    // Rubbing within a support of the plane, where the images take part.
    let near = (0..model.len())
        .filter(|&i| st.slip[i] != 0.0 && st.x[i].x < 2.0 * model.h[i])
        .count();
    println!("{near} rubbing particles within 2h of the plane");
    assert!(near > 0, "the rod rubs near the plane");
    check_state(model, st, true);
}
