//! The penetration scene's energy ledger in plastic flow: a slow shot, the
//! longest contact per unit of energy, at a coarse spacing.

mod common;

use common::*;
use sphcontact::scene::Backend;

/// The tungsten rod into the 4340 plate at 400 m/s (Δx = 0.2 mm, 30 µs;
/// the rod stays in the plate). The springs' stored energy must not grow
/// without work: when a candidate or a particle joining the surface set
/// entered a pass at full weight, the interpolated partner surface jumped
/// and the springs gave the bodies 0.55 % of the initial energy that no
/// force had put in (the total ended +0.61 %). With the surface ramp
/// (docs/method.md §8.2) the total ends within 0.05 % (leapfrog 0.04 %);
/// asserted within 0.2 %, with the springs' loss above −0.2 %.
///
/// The ledger closes: the midpoint rule's compatible energy (docs/method.md
/// §9) leaves a residual of 4e-15 of the initial energy on the CPU path
/// (asserted 1e-12; before it, the rates' work at the midpoint velocity
/// left some 1e-4), 3e-8 to 3e-7 in the GPU's f32 (asserted 1e-5); the
/// leapfrog's compatible kicks close its ledger as well (asserted 1e-12 on
/// the CPU path; before them, its CFL step shrinking and growing left
/// 5e-6).
///
/// With `hourglass`, no artificial stress and the hourglass control at
/// that coefficient instead (docs/method.md, "Hourglass control"), whose
/// work is heat: besides the above, no particle outside the solid range.
/// Measured at 0.3: +0.045 % (GPU the same, the rod's speed to 4e-6;
/// leapfrog +0.031 %), loss −0.030 %, the rod at 80.53 m/s against 79.40
/// with the default close-pair artificial stress (+0.070 %).
fn slow_shot_keeps_its_energy_with(hourglass: Option<f64>) {
    shot_keeps_its_energy(400.0, hourglass);
}

/// The penetration scene with the rod at `speed` (m/s), Δx = 0.2 mm, to
/// 30 µs, without snapshots.
fn coarse_shot(speed: f64) -> sphcontact::Scene {
    shot_at(speed, 2.0e-4)
}

/// The penetration scene with the rod at `speed` (m/s), spacing `dx`, to
/// 30 µs, without snapshots.
fn shot_at(speed: f64, dx: f64) -> sphcontact::Scene {
    let mut scene = load("scenes/penetration/tungsten_rod_steel_plate.toml");
    for b in &mut scene.bodies {
        b.spacing = dx;
    }
    scene.bodies[0].velocity = Some(vec![0.0, -speed]);
    scene.output.snapshot_interval = None;
    scene
}

/// The rod at `speed` (m/s), Δx = 0.2 mm, to 30 µs: completes, the ledger
/// closes, the total within 0.2 % with the springs' loss above −0.2 %.
fn shot_keeps_its_energy(speed: f64, hourglass: Option<f64>) {
    let mut scene = coarse_shot(speed);
    if let Some(alpha) = hourglass {
        with_hourglass_control(&mut scene, alpha);
    }
    let out = run(&scene);
    assert_eq!(out.summary.status, "completed");
    assert_conserved(&scene, &out);
    let s = &out.summary;
    let total = s.energy_final / s.energy_initial - 1.0;
    let loss = s.energy_spring_loss / s.energy_initial;
    let residual = s.energy.residual / s.energy_initial;
    println!("total {total:+.4e}, spring loss {loss:+.4e}, residual {residual:+.3e}");
    let closes = match backend() {
        Backend::Gpu => 1e-5,
        _ => 1e-12,
    };
    assert!(
        residual.abs() < closes,
        "the ledger's residual {residual:+.3e}"
    );
    assert!(total.abs() < 2e-3, "total energy {total:+.3e}");
    assert!(loss > -2e-3, "the springs made {loss:+.3e} of the energy");
    if hourglass.is_some() {
        assert_eq!(s.out_of_range.count, 0, "particles out of range");
    }
}

fn slow_shot_keeps_its_energy() {
    slow_shot_keeps_its_energy_with(None);
}

fn slow_shot_keeps_its_energy_with_hourglass_control() {
    slow_shot_keeps_its_energy_with(Some(0.3));
}

#[test]
fn slow_shot_with_hourglass_control_cpu() {
    slow_shot_keeps_its_energy_with_hourglass_control();
}

/// Minutes on a software adapter; the default suite keeps the device's
/// hourglass control in the stage tests and the device's ledger over a
/// shot's first 15 µs in `gpu_runs` (`penetration_gpu_matches_cpu`).
#[test]
#[ignore]
fn slow_shot_with_hourglass_control_gpu() {
    on_gpu(slow_shot_keeps_its_energy_with_hourglass_control);
}

#[test]
fn slow_shot_with_hourglass_control_midpoint() {
    on_midpoint(slow_shot_keeps_its_energy_with_hourglass_control);
}

#[test]
fn slow_shot_keeps_its_energy_cpu() {
    slow_shot_keeps_its_energy();
}

/// With round supports (`slow_shot_keeps_its_energy_cpu` holds the
/// default ones, and `adaptive_penetration_gpu_matches_cpu` the device's
/// twin of them). Two minutes on a software adapter: the default suite
/// holds the device's ledger in plastic flow and failure on the first
/// 15 µs of the fast shot (`gpu_runs`, `penetration_gpu_matches_cpu`).
#[test]
#[ignore]
fn slow_shot_keeps_its_energy_gpu() {
    on_round_supports(|| on_gpu(slow_shot_keeps_its_energy));
}

#[test]
fn slow_shot_keeps_its_energy_midpoint() {
    on_midpoint(slow_shot_keeps_its_energy);
}

/// The rod at 1,200 m/s, through the plate. The crater's wall is made of
/// particles placed inside the plate; with the distance to the plate's
/// faces they were placed at as their surface offsets, the wall's surface
/// points sat up to 5.5 spacings in front of it and the springs gave the
/// bodies 0.47 % of the initial energy (the total ended +0.469 %). With a
/// fresh surface's half spacing (physics::penalty::surface_offset) it ends
/// −0.032 %.
fn fast_shot_keeps_its_energy() {
    shot_keeps_its_energy(1200.0, None);
}

#[test]
fn fast_shot_keeps_its_energy_cpu() {
    fast_shot_keeps_its_energy();
}

/// Minutes on a software adapter.
#[test]
#[ignore]
fn fast_shot_keeps_its_energy_gpu() {
    on_gpu(fast_shot_keeps_its_energy);
}

/// A steel rod into an aluminium plate at 600 m/s, both elastic–perfectly
/// plastic (scenes/large/projectile_plate.toml at Δx = 0.1 mm), to 8 µs,
/// with the close-pair artificial stress and with the scene's classic one.
/// The crater's lip throws off a jet whose tip rings; without the
/// Grüneisen term's floor on the internal energy (docs/method.md §6) the
/// compatible energy booked that motion as internal energies of −1e9 J/kg,
/// whose tension drove it on, and the runs stopped at 4.5 and 7.3 µs.
/// Measured with the floor, to 20 µs: +0.26 % and +0.31 %.
fn jet_tip_holds(classic: bool) {
    let mut scene = load("scenes/large/projectile_plate.toml");
    for b in &mut scene.bodies {
        b.spacing = 1.0e-4;
    }
    scene.bodies[0].velocity = Some(vec![0.0, -600.0]);
    if !classic {
        scene.artificial_stress = None;
    }
    scene.simulation.end_time = 8.0e-6;
    scene.output.snapshot_interval = None;
    let out = run(&scene);
    assert_eq!(out.summary.status, "completed", "{:?}", out.summary.error);
    let s = &out.summary;
    let total = s.energy_final / s.energy_initial - 1.0;
    let residual = s.energy.residual / s.energy_initial;
    println!("classic {classic}: total {total:+.4e}, residual {residual:+.2e}");
    // What the total gains is the springs' (as in every penetration run,
    // docs/hard_cases.md); the rest of the ledger closes to round-off.
    assert!(total.abs() < 5e-3, "total energy {total:+.3e}");
    let closes = if backend() == Backend::Gpu {
        1e-5
    } else {
        1e-12
    };
    assert!(
        residual.abs() < closes,
        "the ledger's residual {residual:+.3e}"
    );
}

// The two forms' tests, with round supports: the default adaptive ones
// take twice the steps in the crater and hold the jet as well
// (docs/hard_cases.md).
///
/// The leapfrog holds the jet at CFL 0.3 because its viscosity sees the
/// damping-weighted predicted velocity (physics::viscosity::
/// predictor_weight): with the plain predicted velocity `v_n + Δt a_n`
/// it stopped at 3.7 µs, internal energy held below zero in the crater
/// (docs/method.md §9, "Stability where the damping is strong").
#[test]
fn jet_tip_holds_with_the_close_pair_stress() {
    on_round_supports(|| jet_tip_holds(false));
}

#[test]
fn jet_tip_holds_with_the_classic_stress() {
    on_round_supports(|| jet_tip_holds(true));
}

/// The midpoint rule.
#[test]
fn jet_tip_holds_with_the_close_pair_stress_midpoint() {
    on_midpoint(|| on_round_supports(|| jet_tip_holds(false)));
}

#[test]
#[ignore]
fn jet_tip_holds_gpu() {
    on_gpu(|| jet_tip_holds(false));
}

/// The artificial stress that only heats (`work = "heat"`) through the
/// coarse penetration (Δx = 0.2 mm, 1,200 m/s, 15 µs). A pair's share of
/// the term is a continuous function of its velocity (docs/method.md,
/// "Only heat"), so round-off stays round-off: the scene's mirror symmetry
/// holds (the rod's sideways speed measured 1e-8 m/s, asserted 1e-6) and
/// an impact speed changed by 1e-6 of itself moves the rod's mean plastic
/// strain by less than 1e-6 of itself (1e-8: 6e-6; asserted 1e-4). With
/// the share read from the direction of `v_ij` alone the rod left sideways
/// at 0.1–0.2 m/s and the strain moved by 3e-3. (`work = "plastic"` keys
/// the share on whether a particle flows, a switch: 1.2e-4 for a change
/// of 1e-6, 1e-7 or 1e-8.)
///
/// With round supports: a test of the term, not of the supports.
#[test]
fn artificial_stress_that_only_heats_keeps_round_off_small() {
    on_round_supports(only_heats_keeps_round_off_small);
}

fn only_heats_keeps_round_off_small() {
    let shot = |speed: f64| {
        let mut scene = coarse_shot(speed);
        scene.simulation.end_time = 1.5e-5;
        scene.artificial_stress = Some(sphcontact::scene::ArtificialStress {
            pairs: sphcontact::scene::ArtPairs::Close,
            work: sphcontact::scene::ArtWork::Heat,
            ..sphcontact::scene::ArtificialStress::DEFAULT
        });
        let out = run(&scene);
        assert_eq!(out.summary.status, "completed", "{:?}", out.summary.error);
        let rod = out.model.bodies[0].range.clone();
        let m: f64 = rod.clone().map(|i| out.model.mass[i]).sum();
        let mean = |f: &dyn Fn(usize) -> f64| {
            rod.clone().map(|i| out.model.mass[i] * f(i)).sum::<f64>() / m
        };
        let vx = mean(&|i| out.state.v[i].x);
        let eps = mean(&|i| out.state.eps_p[i]);
        (vx, eps)
    };
    let (vx, eps) = shot(1200.0);
    let (vx2, eps2) = shot(1200.0 * (1.0 + 1e-6));
    println!("rod sideways {vx:+.2e} / {vx2:+.2e} m/s, mean plastic strain {eps:.6} / {eps2:.6}");
    assert!(eps > 0.3, "the rod flows: {eps}");
    for v in [vx, vx2] {
        assert!(v.abs() < 1e-6, "the rod leaves sideways at {v:+e} m/s");
    }
    assert!(
        (eps2 / eps - 1.0).abs() < 1e-4,
        "plastic strain {eps} against {eps2}"
    );
}

/// Pairs of particles of the same body closer than half a spacing in the
/// final state, with the closest distance the material's own deformation
/// allows them: a plastic strain `ε_p` (von Mises' equivalent) in plane
/// strain compresses a line of the material by `exp(−(√3/2) ε_p)` at most,
/// the larger of the pair's. Returns, per body, the pairs found and the
/// smallest ratio of a pair's distance to that bound.
fn close_pairs(out: &sphcontact::run::RunOutput, dx: f64) -> Vec<(usize, f64)> {
    let st = &out.state;
    out.model
        .bodies
        .iter()
        .map(|b| {
            let idx: Vec<usize> = b.range.clone().collect();
            let key = |p: glam::DVec2| ((p.x / dx).floor() as i64, (p.y / dx).floor() as i64);
            let mut cells: std::collections::HashMap<(i64, i64), Vec<usize>> =
                std::collections::HashMap::new();
            for &i in &idx {
                cells.entry(key(st.x[i])).or_default().push(i);
            }
            let (mut found, mut lowest) = (0, f64::INFINITY);
            for &i in &idx {
                let (cx, cy) = key(st.x[i]);
                for (ox, oy) in (-1..=1).flat_map(|a| (-1..=1).map(move |b| (a, b))) {
                    for &j in cells.get(&(cx + ox, cy + oy)).into_iter().flatten() {
                        let d = st.x[i].distance(st.x[j]);
                        if j > i && d < 0.5 * dx {
                            let strain = st.eps_p[i].max(st.eps_p[j]);
                            let bound = dx * (-(3f64.sqrt() / 2.0) * strain).exp();
                            found += 1;
                            lowest = lowest.min(d / bound);
                        }
                    }
                }
            }
            (found, lowest)
        })
        .collect()
}

/// The rod at 1,500 m/s at Δx = 0.1 mm (the fastest of the penetration
/// table, docs/hard_cases.md), to 30 µs: completes, its energy within
/// 0.5 % of the start, the ledger closed to 1e-12, at most 2 particles out
/// of range. Measured (CPU, leapfrog, 335 s on two cores): −0.117 %,
/// residual 6e-15, none out of range. It also prints the pairs closer
/// than half a spacing and how close they come against what their plastic
/// strain explains (`close_pairs`): 217 in the rod, none below 0.78 of it,
/// and 274 in the plate, of which two mirrored pairs in the plate's ejecta
/// at 0.45 (docs/hard_cases.md, "Penetration": not asserted, a clump the
/// solver does not yet prevent).
#[test]
#[ignore]
fn fastest_shot_at_a_tenth_of_a_millimetre_keeps_its_energy() {
    let dx = 1.0e-4;
    let scene = shot_at(1500.0, dx);
    let out = run(&scene);
    assert_eq!(out.summary.status, "completed", "{:?}", out.summary.error);
    assert_conserved(&scene, &out);
    let s = &out.summary;
    let total = s.energy_final / s.energy_initial - 1.0;
    let residual = s.energy.residual / s.energy_initial;
    let pairs = close_pairs(&out, dx);
    println!(
        "total {total:+.4e}, residual {residual:+.2e}, out of range {}, pairs below Δx/2 and their least ratio to the strain's bound {pairs:?}",
        s.out_of_range.count
    );
    assert!(total.abs() < 5e-3, "total energy {total:+.3e}");
    assert!(
        residual.abs() < 1e-12,
        "the ledger's residual {residual:+.3e}"
    );
    assert!(
        s.out_of_range.count <= 2,
        "{} out of range",
        s.out_of_range.count
    );
}
