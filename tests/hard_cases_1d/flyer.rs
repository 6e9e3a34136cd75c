//! A flyer plate: the target holds its tension, or spalls at the plane.

use super::*;

/// How the elastic target of scenes/hard/flyer_plate_tension.toml took
/// the reflected tension: each plateau at 8 mm against the elastic wave
/// solution (measured / exact − 1, over the middle 60 % of its exact
/// interval), and the largest free-surface speed once the pulse has left
/// the target (exact: at rest).
#[derive(Debug)]
struct Flyer {
    completed: bool,
    /// Particles failed (a material that can fail).
    failed: usize,
    compression: f64,
    tension: f64,
    rest: f64,
}

fn flyer_tension(scene: &Scene) -> Flyer {
    let mat = material(scene, "steel");
    let c = ((mat.k + 4.0 * mat.g / 3.0) / mat.rho0).sqrt();
    let up = 0.5 * scene.bodies[0].velocity.as_ref().unwrap()[0];
    let sigma = mat.rho0 * c * up;
    let (lf, lt, x) = (0.002, 0.01, probe_at(scene, "stress_8mm"));
    let out = run(scene);
    let t = &out.history.times;
    let (stress, vfs) = (
        column(&out, "stress_8mm"),
        column(&out, "free_surface_velocity"),
    );
    let mean_over = |a: f64, b: f64| {
        let m = 0.2 * (b - a);
        let v: Vec<f64> = (0..t.len())
            .filter(|&k| t[k] > a + m && t[k] < b - m)
            .map(|k| stress[k])
            .collect();
        assert!(v.len() > 10, "{} rows in [{a:e}, {b:e}]", v.len());
        v.iter().sum::<f64>() / v.len() as f64
    };
    let compression = mean_over(x / c, (x + 2.0 * lf) / c);
    let tension = mean_over((2.0 * lt - x) / c, (2.0 * lt - x + 2.0 * lf) / c);
    let left = (lt + 2.0 * lf) / c;
    let rest = (0..t.len())
        .filter(|&k| t[k] > left + 0.15e-6)
        .map(|k| vfs[k].abs())
        .fold(0.0, f64::max);
    let f = Flyer {
        completed: out.summary.status == "completed",
        failed: out
            .summary
            .bodies
            .iter()
            .filter_map(|b| b.failure.as_ref())
            .map(|f| f.failed)
            .sum(),
        compression: compression / -sigma - 1.0,
        tension: tension / sigma - 1.0,
        rest,
    };
    println!(
        "{:?}, {:?}, {} m/s: {f:?}",
        backend(),
        scene.artificial_stress,
        2.0 * up
    );
    f
}

/// The target holds: completed, both plateaus within 2 % of the elastic
/// wave solution (the discretisation's own error, the same on both
/// sides: measured +0.65 % in compression, −0.69 % in tension at 200 m/s)
/// and the free surface at rest (below 5 m/s; measured 1.4).
fn holds(f: &Flyer) {
    assert!(f.completed && f.failed == 0, "{f:?}");
    assert!(f.compression.abs() < 0.02, "{f:?}");
    assert!(f.tension.abs() < 0.02, "{f:?}");
    assert!(f.rest < 5.0, "{f:?}");
}

/// An elastic steel flyer onto an elastic steel target at 200 m/s, 1-D,
/// Δx = 10 µm: the reflected pulse puts the target in 4.6 GPa of tension.
/// The scene asks for no remedy; the default close-pair artificial stress
/// holds it, and at 400 m/s (9.2 GPa) too. With the artificial stress
/// switched off the target does not hold (with Monaghan's viscosity it
/// tears: tension −34 %, the free surface flying on at 166 m/s); the
/// classic form on every pair holds it
/// too, with its bias (+3.3 % at ε = 0.1: docs/method.md, "Tension").
#[test]
fn elastic_target_holds_its_tension() {
    use sphcontact::scene::{ArtPairs, ArtificialStress, ArtificialViscosity, ViscosityForm};
    let scene = load("scenes/hard/flyer_plate_tension.toml");
    assert_eq!(
        scene.artificial_stress, None,
        "the scene asks for no remedy"
    );
    holds(&flyer_tension(&scene));
    let mut fast = scene.clone();
    fast.bodies[0].velocity = Some(vec![400.0]);
    holds(&flyer_tension(&fast));

    let with = |epsilon: f64, pairs: ArtPairs| {
        let mut s = scene.clone();
        s.artificial_stress = Some(ArtificialStress {
            epsilon,
            n: 4.0,
            pairs,
            ..ArtificialStress::DEFAULT
        });
        flyer_tension(&s)
    };
    // Without the term the target does not hold: its free surface never
    // comes to rest. The default viscosity damps receding pairs too and
    // slows the tear (measured: the tension plateau exact, the free
    // surface at 31 m/s); Monaghan's form, which leaves them alone, lets
    // it tear outright.
    let off = with(0.0, ArtPairs::All);
    assert!(off.rest > 10.0, "without: {off:?}");
    let mut monaghan = scene.clone();
    monaghan.artificial_stress = Some(ArtificialStress {
        epsilon: 0.0,
        ..ArtificialStress::DEFAULT
    });
    monaghan.artificial_viscosity = Some(ArtificialViscosity {
        form: ViscosityForm::Monaghan,
        reconstruct_surfaces: false,
        ..Default::default()
    });
    let torn = flyer_tension(&monaghan);
    assert!(
        torn.rest > 50.0 && torn.tension < -0.1,
        "without, Monaghan's form: {torn:?}"
    );
    let classic = with(0.1, ArtPairs::All);
    assert!(classic.completed && classic.rest < 5.0, "{classic:?}");
    assert!(
        classic.tension > 0.0 && classic.tension < 0.05,
        "{classic:?}"
    );
}

#[test]
fn elastic_target_holds_its_tension_midpoint() {
    on_midpoint(|| {
        holds(&flyer_tension(&load(
            "scenes/hard/flyer_plate_tension.toml",
        )))
    });
}

/// A minute and a half on a software adapter; the device's close-pair
/// term is held to the CPU's in the stage tests and over whole runs by
/// the rubber rings' and the spalling target's GPU runs.
#[test]
#[ignore]
fn elastic_target_holds_its_tension_gpu() {
    on_gpu(|| {
        holds(&flyer_tension(&load(
            "scenes/hard/flyer_plate_tension.toml",
        )))
    });
}

/// scenes/hard/flyer_plate_tension.toml with its steel changed by `edit`.
fn with_steel(edit: impl FnOnce(&mut sphcontact::scene::Material)) -> Scene {
    let mut scene = load("scenes/hard/flyer_plate_tension.toml");
    edit(
        scene
            .materials
            .get_mut("steel")
            .expect("the scene's material"),
    );
    scene
}

/// The flyer-plate test of spall: the scene with a spall pressure
/// `p_spall` on the steel.
fn with_spall(p_spall: f64) -> Scene {
    with_steel(|m| m.spall_pressure = Some(p_spall))
}

/// `scene` with both plates' spacing times `coarsen`: the cavitation's GPU
/// run in the default suite takes twice the scene's spacing (a quarter of
/// the work), the scene's own among the long tests.
fn coarsened(mut scene: Scene, coarsen: f64) -> Scene {
    for b in &mut scene.bodies {
        b.spacing *= coarsen;
    }
    scene
}

/// The target's mass-weighted mean velocity at the end of `out` over the
/// particles whose initial position `x0` passes `pick`.
fn target_velocity(out: &RunOutput, x0: &[glam::DVec2], pick: impl Fn(f64) -> bool) -> f64 {
    let ids: Vec<usize> = out.model.bodies[1]
        .range
        .clone()
        .filter(|&i| pick(x0[i].x))
        .collect();
    let m: f64 = ids.iter().map(|&i| out.model.mass[i]).sum();
    ids.iter()
        .map(|&i| out.model.mass[i] * out.state.v[i].x)
        .sum::<f64>()
        / m
}

/// A spall pressure of 2 GPa, below the 2.82 GPa tensile pressure the
/// reflected pulse brings (0.616 of its 4.58 GPa tensile stress in
/// uniaxial strain): in the elastic wave solution tension first appears
/// one flyer thickness from the free surface (8 mm) at (L_t + L_f)/c_L =
/// 2.056 µs, at full amplitude, and the target spalls there; the scab
/// beyond it carries the superposed pulses' 2 u_p, the flyer's speed, and
/// no stress.
///
/// Measured (CPU, leapfrog): first failure at +0.04 % of the time; the
/// failed particles, 10, in pairs over 7.925–8.085 mm (the smeared
/// fronts crack the material more than once), centred 0.5 Δx from the
/// plane, the first of them 7.5 Δx right of it, where the ringing behind
/// the reflected front overshoots; the scab at −0.68 % of the flyer's
/// speed (midpoint rule: +0.05 %, 7.945–8.085 mm, −0.76 %). The device
/// the same, particle for particle.
fn spalls_at_the_plane() {
    let scene = with_spall(2.0e9);
    let mat = material(&scene, "steel");
    let c = ((mat.k + 4.0 * mat.g / 3.0) / mat.rho0).sqrt();
    let v = scene.bodies[0].velocity.as_ref().unwrap()[0];
    let (lf, lt, dx) = (0.002, 0.01, scene.bodies[1].spacing);
    let (plane, t_spall) = (lt - lf, (lt + lf) / c);
    let x0 = sphcontact::model::Model::new(&scene).1.x;
    let out = run(&scene);
    assert_eq!(out.summary.status, "completed");
    let [flyer, target] = [0, 1].map(|b| {
        out.summary.bodies[b]
            .failure
            .clone()
            .expect("a material that can fail")
    });
    assert_eq!(
        (flyer.failed, flyer.first.is_none()),
        (0, true),
        "{flyer:?}"
    );
    let first = target.first.clone().expect("the target spalls");
    let failed: Vec<usize> = out.model.bodies[1]
        .range
        .clone()
        .filter(|&i| out.state.damage[i] >= 1.0)
        .collect();
    assert_eq!(failed.len(), target.failed);
    let (lo, hi) = failed.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &i| {
        (lo.min(x0[i].x), hi.max(x0[i].x))
    });
    let centre = 0.5 * (lo + hi);
    // The intact pieces on either side of the failed layer.
    let scab = target_velocity(&out, &x0, |x| x > hi);
    let rest = target_velocity(&out, &x0, |x| x < lo);
    println!(
        "{:?}: first failure at {:.4e} s ({:+.2} %), x0 = {:.4e} ({:+.1} Δx); {} failed in [{lo:.4e}, {hi:.4e}], centre {:+.1} Δx; scab {scab:.1} m/s ({:+.2} %), the rest {rest:.2} m/s",
        backend(),
        first.time,
        100.0 * (first.time / t_spall - 1.0),
        first.position_initial[0],
        (first.position_initial[0] - plane) / dx,
        target.failed,
        (centre - plane) / dx,
        100.0 * (scab / v - 1.0),
    );
    assert!((first.time / t_spall - 1.0).abs() < 0.02, "{first:?}");
    assert!((centre - plane).abs() < 2.0 * dx, "centre {centre:e}");
    // Nothing fails away from the plane (the free surface, the contact
    // face): the layer is as wide as the smeared fronts (±8.5 Δx).
    assert!(
        lo > plane - 12.0 * dx && hi < plane + 12.0 * dx,
        "[{lo:e}, {hi:e}]"
    );
    assert!((scab / v - 1.0).abs() < 0.03, "scab {scab}");
    assert!(rest.abs() < 0.05 * v, "the rest {rest}");
}

#[test]
fn target_spalls_at_the_plane() {
    spalls_at_the_plane();
}

#[test]
fn target_spalls_at_the_plane_midpoint() {
    on_midpoint(spalls_at_the_plane);
}

/// At the CPU test's spacing, where its bounds were set: at twice it
/// the failed layer is eight to ten particles and its centre moves by
/// whole particles with the step's details (from −0.5 to +2.0 Δx; the CPU
/// the same).
#[test]
fn target_spalls_at_the_plane_gpu() {
    on_gpu(spalls_at_the_plane);
}

/// Among the long tests: the device's midpoint rule keeps its spall in
/// the leapfrog run above and its step in the stage tests.
#[test]
#[ignore]
fn target_spalls_at_the_plane_gpu_midpoint() {
    on_midpoint(|| on_gpu(spalls_at_the_plane));
}

/// The flyer plate with a cavitation pressure `p_cav` (`inf`: none) on the
/// steel in place of a spall pressure (docs/method.md, "Cavitation").
fn with_cavitation(p_cav: f64) -> Scene {
    with_steel(|m| m.cavitation_pressure = Some(p_cav))
}

/// The target's mean velocities beyond 12 Δx on either side of the
/// spall plane (the scab's and the rest's) at the end of `out`.
fn scab_and_rest(scene: &Scene, out: &RunOutput) -> (f64, f64) {
    let (plane, dx) = (0.01 - 0.002, scene.bodies[1].spacing);
    let x0 = sphcontact::model::Model::new(scene).1.x;
    (
        target_velocity(out, &x0, |x| x > plane + 12.0 * dx),
        target_velocity(out, &x0, |x| x < plane - 12.0 * dx),
    )
}

/// A cavitation pressure of 2 GPa, below the 2.82 GPa tensile pressure the
/// reflected pulse brings: the target opens at the plane as it spalls
/// (above), the scab flying off at the flyer's speed and the rest at
/// rest, but nothing fails, and the energy the opened layer held in
/// tension stays with it as heat (the total is held to round-off). With
/// none (`inf`) the plane holds its tension and the far part of the target
/// does not fly free.
///
/// Measured at the scene's spacing (CPU): the scab at −0.80 % of the
/// flyer's speed, the rest at 0.58 m/s (midpoint rule −0.97 %, 0.68 m/s);
/// without cavitation the far part at rest at the end. The
/// run without cavitation, which holds no device code of its own, is the
/// CPU's only where `contrast` is false.
fn cavitates_at_the_plane(coarsen: f64, contrast: bool) {
    let scene = coarsened(with_cavitation(2.0e9), coarsen);
    let v = scene.bodies[0].velocity.as_ref().unwrap()[0];
    let (scab, rest) = cavitation_run(&scene);
    assert!((scab / v - 1.0).abs() < 0.03, "scab {scab}");
    assert!(rest.abs() < 0.05 * v, "the rest {rest}");
    if contrast {
        let holding = coarsened(with_cavitation(f64::INFINITY), coarsen);
        let (far, _) = scab_and_rest(&holding, &run(&holding));
        println!("without cavitation the far part {far:.1} m/s");
        assert!((far / v - 1.0).abs() > 0.2, "without cavitation {far}");
    }
}

/// The cavitating flyer plate `scene` run on this thread's backend:
/// completed, nothing failed, conserved; the scab's and the rest's speeds.
fn cavitation_run(scene: &Scene) -> (f64, f64) {
    let v = scene.bodies[0].velocity.as_ref().unwrap()[0];
    let out = run(scene);
    assert_eq!(out.summary.status, "completed");
    assert!(
        out.summary.bodies.iter().all(|b| b.failure.is_none()),
        "nothing can fail"
    );
    assert!(out.state.damage.iter().all(|&d| d < 1.0));
    assert_conserved(scene, &out);
    let (scab, rest) = scab_and_rest(scene, &out);
    println!(
        "{:?}: scab {scab:.1} m/s ({:+.2} %), the rest {rest:.2} m/s",
        backend(),
        100.0 * (scab / v - 1.0),
    );
    (scab, rest)
}

#[test]
fn target_cavitates_at_the_plane() {
    cavitates_at_the_plane(1.0, true);
}

#[test]
fn target_cavitates_at_the_plane_midpoint() {
    on_midpoint(|| cavitates_at_the_plane(1.0, false));
}

/// The device at twice the spacing (the scene's own takes minutes on a
/// software adapter: `_gpu_fine`), held to its CPU twin there: the scab
/// and the rest within 0.5 % of the flyer's speed of the CPU's (measured
/// on both backends at that spacing: the scab at −1.66 %, the rest at
/// 0.96 m/s).
#[test]
fn target_cavitates_at_the_plane_gpu() {
    let scene = coarsened(with_cavitation(2.0e9), 2.0);
    let v = scene.bodies[0].velocity.as_ref().unwrap()[0];
    let (scab, rest) = cavitation_run(&scene);
    on_gpu(|| {
        let (gs, gr) = cavitation_run(&scene);
        assert!((gs - scab).abs() < 5e-3 * v, "scab {gs} against {scab}");
        assert!((gr - rest).abs() < 5e-3 * v, "the rest {gr} against {rest}");
    });
}

/// Minutes on a software adapter.
#[test]
#[ignore]
fn target_cavitates_at_the_plane_gpu_fine() {
    on_gpu(|| cavitates_at_the_plane(1.0, true));
}

/// With a spall pressure above the incident stress (4.6 GPa against
/// 4.58) nothing breaks, and the target holds as without one. Between the
/// exact tensile pressure (2.82 GPa) and the discretised one the target
/// still spalls: where the incident pulse's tail crosses the reflected
/// front their ringing adds up, and the tensile pressure near 8 mm peaks
/// at 3.97 GPa, 1.41 times the plateau, for a few ns (docs/hard_cases.md).
#[test]
fn target_holds_below_its_spall_pressure() {
    holds(&flyer_tension(&with_spall(4.6e9)));
}

// ---------------------------------------------------------------------------
// 3. Far from the origin
// ---------------------------------------------------------------------------
