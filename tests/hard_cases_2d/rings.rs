//! The rubber rings, with and without the artificial stress.

use super::*;
use sphcontact::scene::{StressForm, ViscosityForm};

/// Positions and body indices of the particles in a snapshot file (the
/// `Points` and `body` arrays of the VTK output of docs/scenes.md).
fn snapshot_particles(path: &Path) -> (f64, Vec<(usize, glam::DVec2)>) {
    let v = vtu::read_vtu(path);
    let particles = v
        .ints("body")
        .into_iter()
        .zip(v.xy("Points"))
        .map(|(b, [x, y])| (b as usize, glam::DVec2::new(x, y)))
        .collect();
    (v.time, particles)
}

/// The lowest internal energy in any snapshot of `dir` after the start
/// (where every particle holds zero), J/kg.
fn lowest_internal_energy(dir: &Path) -> f64 {
    std::fs::read_dir(dir.join("snapshots"))
        .expect("the snapshots")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "vtu"))
        .map(|p| vtu::read_vtu(&p))
        .filter(|v| v.time > 0.0)
        .flat_map(|v| v.f64s("internal_energy", 1))
        .fold(f64::INFINITY, f64::min)
}

/// What a ring's particle cloud looks like: the sizes of its connected
/// clusters (union–find over pairs closer than `link`), largest first, and
/// its smallest pair distance.
fn cloud_shape(points: &[glam::DVec2], link: f64) -> (Vec<usize>, f64) {
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut parent: Vec<usize> = (0..points.len()).collect();
    let mut closest = f64::INFINITY;
    for i in 0..points.len() {
        for j in i + 1..points.len() {
            let d = points[i].distance(points[j]);
            closest = closest.min(d);
            if d < link {
                let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                parent[a] = b;
            }
        }
    }
    let mut sizes = std::collections::HashMap::new();
    for i in 0..points.len() {
        *sizes.entry(root(&mut parent, i)).or_insert(0usize) += 1;
    }
    let mut sizes: Vec<usize> = sizes.into_values().collect();
    sizes.sort_unstable_by(|a, b| b.cmp(a));
    (sizes, closest)
}

/// The shape of both rings in every snapshot of `dir` and in the final
/// state: `(time, ring, cluster sizes, smallest distance / Δx)`.
fn ring_shapes(dir: &Path, out: &RunOutput, dx: f64) -> Vec<(f64, usize, Vec<usize>, f64)> {
    let mut files: Vec<_> = std::fs::read_dir(dir.join("snapshots"))
        .expect("the snapshots")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "vtu"))
        .collect();
    files.sort();
    let mut states: Vec<(f64, Vec<(usize, glam::DVec2)>)> =
        files.iter().map(|p| snapshot_particles(p)).collect();
    let last = (0..out.model.len())
        .map(|i| (out.model.body[i] as usize, out.state.x[i]))
        .collect();
    states.push((out.state.t, last));
    let mut shapes = Vec::new();
    for (t, particles) in states {
        for ring in 0..2 {
            let points: Vec<glam::DVec2> = particles
                .iter()
                .filter(|p| p.0 == ring)
                .map(|p| p.1)
                .collect();
            let (sizes, closest) = cloud_shape(&points, LINK * dx);
            shapes.push((t, ring, sizes, closest / dx));
        }
    }
    shapes
}

/// Particles of one ring closer than this many spacings are linked into one
/// cluster: a ring's neighbours sit at about 1 Δx, a crack opens wider.
const LINK: f64 = 1.5;
/// No two particles of a ring closer than this many spacings: the tensile
/// instability pairs particles up well inside it (measured 0.13 Δx).
const CLUMP: f64 = 0.5;

/// The impact speed of the rings: 0.059 c0 with c0 = sqrt(K/ρ0), the bulk
/// sound speed of the linear EOS (the scene's stated choice).
fn ring_speed(scene: &sphcontact::Scene) -> f64 {
    let rubber = material(scene, "rubber");
    let v0 = 0.059 * (rubber.k / rubber.rho0).sqrt();
    for (b, sign) in scene.bodies.iter().zip([1.0, -1.0]) {
        let v = b.velocity.as_ref().unwrap()[0];
        assert!((v / (sign * v0) - 1.0).abs() < 1e-12, "{}: {v} m/s", b.name);
    }
    v0
}

/// Period of the ovalling signal `s` after `from`: twice the mean spacing of
/// its crossings of its own mean there; `None` with fewer than three.
fn ovalling_period(t: &[f64], s: &[f64], from: f64) -> Option<f64> {
    let k0 = t.iter().position(|&x| x >= from)?;
    let mean = s[k0..].iter().sum::<f64>() / (s.len() - k0) as f64;
    let crossings: Vec<f64> = (k0..s.len() - 1)
        .filter_map(|k| {
            let (a, b) = (s[k] - mean, s[k + 1] - mean);
            (a * b < 0.0).then(|| t[k] + (t[k + 1] - t[k]) * a / (a - b))
        })
        .collect();
    (crossings.len() >= 3).then(|| {
        2.0 * (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
    })
}

/// Momentum to round-off (1e-12 of Σ m |v0| in f64, 1e-6 in f32).
fn assert_momentum(out: &RunOutput, scale: f64) {
    let round_off = if backend() == Backend::Gpu {
        1e-6
    } else {
        1e-12
    };
    let s = &out.summary;
    for (a, b) in s.momentum_initial.iter().zip(&s.momentum_final) {
        assert!(
            (a - b).abs() <= round_off * scale,
            "momentum drifted: {a} -> {b} (scale {scale})"
        );
    }
}

/// The rings with artificial stress (scenes/hard/rubber_rings.toml; `end`
/// shortens it). Asserted, at Δx = 2 mm (five particles through the wall):
///
/// * they rebound: mean velocities reversed, restitution
///   `(v_right − v_left)/(2 v0)` in [0.5, 0.9], and no contact in the last
///   10 µs. Not an exact answer: elastic rings rebound (a ring that breaks
///   or clumps does not, see below), but at 0.059 c0 their ovalling mode
///   keeps a large share of the impact energy. Measured: CPU 0.762,
///   separation at 300 µs; GPU 0.704 at 304 µs (CPU and GPU agree to 1e-5
///   for the first 100 µs; the rings in tension then amplify f32 round-off);
///   at Δx = 1 mm (CPU, not in the test: 350 s) 0.607 at 338 µs: the
///   restitution is not converged at these resolutions.
/// * momentum to round-off.
/// * total energy within 1 % of its initial value at every history row
///   (the artificial stress's work is booked as heat, half to each
///   particle of a pair, as the viscosity's is; without that booking the
///   total swung by up to +7.8 %, and ended 17 % high at 1 mm). Measured:
///   −0.52 % worst, −0.45 % at the end (CPU), −0.51 % (GPU); the rings
///   without artificial stress hold 0.36 % (below).
/// * each ring stays one connected cluster (pairs closer than 1.5 Δx) with
///   no clumps (no pair closer than 0.5 Δx) in every snapshot (every
///   100 µs) and at the end. Measured: one cluster each throughout,
///   smallest distance 0.81 Δx (at 1 mm one cluster each, but pairs down to
///   0.26 Δx).
/// * (full run only) the run spans two periods of the ovalling mode after
///   the separation, the period measured from the left ring's diameters
///   (`D_y − D_x` crossing its mean). Thin-ring theory (plane strain) gives
///   288.3 µs, a lower bound (shear, rotary inertia and a stretching
///   mid-line only lower the frequency): the measured period must lie in
///   [0.95, 1.5] times it, the upper end failing a ring left with less than
///   half its bending stiffness. Measured 384 µs (1.33×; 339 µs, 1.18×, at
///   1 mm: the coarse ring is soft in bending).
///
/// `default`: the scene's `[artificial_stress]` (the classic form on every
/// pair, ε = 0.3) removed, so that the run takes the default close-pair
/// form. Measured (CPU, full run): restitution 0.767, apart at 295 µs,
/// energy +0.02 %, one cluster each, smallest distance 0.60 Δx, period
/// 367 µs (1.27×).
///
/// [`Hold::Hourglass`]: no artificial stress at all, the hourglass control
/// (`artificial_viscosity.hourglass`, 1 here, docs/method.md "Hourglass
/// control") instead, whose work is heat: besides the above, no particle
/// ever below `−1e-3 c_L²` of internal energy (the classic form leaves some
/// there at finer spacings). Measured (CPU, full run): restitution 0.718,
/// energy ledger residual 7.5e-5 of the initial, one cluster each,
/// smallest distance 0.83 Δx; GPU (lavapipe) the same restitution to 2e-6.
fn rings_with_artificial_stress(end: Option<f64>, hold: Hold) {
    let mut scene = load(if hold == Hold::Fine {
        "scenes/hard/rubber_rings_fine.toml"
    } else {
        "scenes/hard/rubber_rings.toml"
    });
    assert_eq!(scene.artificial_stress.is_some(), hold != Hold::Fine);
    match hold {
        Hold::Classic | Hold::Fine => {}
        Hold::Default => scene.artificial_stress = None,
        Hold::Hourglass(alpha) => with_hourglass_control(&mut scene, alpha),
        Hold::Adaptive(dx) => {
            scene.artificial_stress = None;
            scene.simulation.support = Some(sphcontact::scene::Support::Adaptive);
            // Following the deformation from the start: supports round
            // within the default band let the rings clump as round ones do
            // (docs/method.md, "Round within a band").
            scene.simulation.support_band = Some(1.0.into());
            for b in &mut scene.bodies {
                b.spacing = dx;
            }
        }
    }
    if let Some(end) = end {
        scene.simulation.end_time = end;
    }
    let v0 = ring_speed(&scene);
    let dx = scene.bodies[0].spacing;
    let tmp = tempfile::tempdir().unwrap();
    let out = run_on(&scene, backend(), Some(tmp.path()));
    let t = &out.history.times;
    let f = column(&out, "contact_force");
    let (_, t_sep) = contact_window(t, &f);
    let vl = *column(&out, "velocity_left").last().unwrap();
    let vr = *column(&out, "velocity_right").last().unwrap();
    let restitution = (vr - vl) / (2.0 * v0);
    println!(
        "rings with artificial stress ({}): separate at {:.1} µs, velocities {vl:.2} / {vr:.2} m/s, restitution {restitution:.4}",
        out.summary.backend,
        t_sep * 1e6
    );
    assert!(
        t_sep <= scene.simulation.end_time - 1e-5,
        "in contact within 10 µs of the end"
    );
    assert!(vl < 0.0 && vr > 0.0, "not reversed: {vl} / {vr}");
    assert!(
        (0.5..=0.9).contains(&restitution),
        "restitution {restitution}"
    );

    let mass: f64 = out.summary.bodies.iter().map(|b| b.mass).sum();
    assert_momentum(&out, mass * v0);
    let e = column(&out, "energy_total");
    let worst =
        e.iter()
            .map(|x| x / e[0] - 1.0)
            .fold(0.0f64, |a, b| if b.abs() > a.abs() { b } else { a });
    println!(
        "energy: worst {:+.2} %, at the end {:+.2} %",
        worst * 100.0,
        (e[e.len() - 1] / e[0] - 1.0) * 100.0
    );
    assert!(worst.abs() < 0.01, "energy off by {worst:e}");

    let shapes = ring_shapes(tmp.path(), &out, dx);
    let closest = shapes.iter().map(|s| s.3).fold(f64::INFINITY, f64::min);
    println!(
        "{} ring states checked: one cluster each: {}, smallest distance {closest:.3} Δx",
        shapes.len(),
        shapes.iter().all(|s| s.2.len() == 1)
    );
    if let Hold::Hourglass(_) | Hold::Adaptive(_) | Hold::Fine = hold {
        let c_l2 = material(&scene, "rubber").c_l.powi(2);
        let lowest = lowest_internal_energy(tmp.path());
        println!("lowest internal energy {:.2e} c_L²", lowest / c_l2);
        if let Hold::Hourglass(_) = hold {
            assert!(lowest > -1e-3 * c_l2, "internal energy {lowest:e} J/kg");
        } else {
            // The rubber's elastic energy is never negative, and nothing
            // here may take it below zero.
            assert!(lowest >= 0.0, "internal energy {lowest:e} J/kg");
        }
    }
    for (time, ring, sizes, closest) in &shapes {
        assert_eq!(
            sizes.len(),
            1,
            "ring {ring} at {time:e} s broke into clusters of {sizes:?}"
        );
        assert!(
            *closest > CLUMP,
            "ring {ring} at {time:e} s: particles {closest:.3} Δx apart"
        );
    }

    if end.is_none() {
        let rubber = material(&scene, "rubber");
        let Shape::Ring {
            inner_radius,
            outer_radius,
            ..
        } = scene.bodies[0].shape
        else {
            panic!("a ring");
        };
        let thin = ring_flexural_period(&rubber, inner_radius, outer_radius, 2);
        let dy: Vec<f64> = column(&out, "top_y")
            .iter()
            .zip(column(&out, "bottom_y"))
            .map(|(a, b)| a - b)
            .collect();
        let dxs: Vec<f64> = column(&out, "front_x")
            .iter()
            .zip(column(&out, "back_x"))
            .map(|(a, b)| a - b)
            .collect();
        let oval: Vec<f64> = dy.iter().zip(&dxs).map(|(a, b)| a - b).collect();
        let period = ovalling_period(t, &oval, t_sep).expect("the rings ring");
        println!(
            "ovalling period {:.1} µs (thin-ring theory {:.1} µs, ratio {:.3}); {:.2} periods after the separation",
            period * 1e6,
            thin * 1e6,
            period / thin,
            (scene.simulation.end_time - t_sep) / period
        );
        assert!(
            period > 0.95 * thin && period < 1.5 * thin,
            "ovalling period {period:e} s against thin-ring {thin:e} s"
        );
        assert!(
            scene.simulation.end_time - t_sep >= 2.0 * period,
            "the run spans fewer than two periods after the separation"
        );
    }
}

/// The same rings without artificial stress, shortened to `end`, with the
/// default viscosity or (`former`) Monaghan's form plain at surfaces. At Δx = 2 mm updated-Lagrangian SPH fails them in
/// tension, as Gray, Monaghan & Swift describe (measured with Monaghan's
/// form): particles pair up (clumps from about 100 µs, pairs
/// 0.13 Δx apart at 150 µs), the left ring cracks into pieces by 200 µs,
/// the rings do not rebound (at 250 µs they still close at 45 m/s each,
/// where the rings with artificial stress have reversed by 180 µs), and run
/// on, the CPU path stops at 484 µs with the instability message
/// (density < 0). Asserted, in some snapshot or at the end: clumps (a pair
/// of one ring closer than 0.5 Δx); with the paper's stress terms
/// (`paper`), a ring broken into more than one cluster (1.5 Δx links) and
/// the rings not yet reversed; with the variational ones (the default),
/// each ring one cluster.
/// Energy holds to 0.5 % (no artificial stress outside the energy
/// equation; measured −0.27 %) and momentum to round-off, so the failure
/// is the tensile instability, not a leak.
fn rings_without_artificial_stress(end: f64, paper: bool, former: bool) {
    let mut scene = load("scenes/hard/rubber_rings.toml");
    if paper {
        scene.simulation.stress_form = StressForm::Paper;
    }
    scene.artificial_stress = Some(sphcontact::scene::ArtificialStress {
        epsilon: 0.0,
        ..sphcontact::scene::ArtificialStress::DEFAULT
    });
    if former {
        // The former default: Monaghan's form, plain at surfaces.
        scene.artificial_viscosity = Some(sphcontact::scene::ArtificialViscosity {
            form: ViscosityForm::Monaghan,
            reconstruct_surfaces: false,
            ..Default::default()
        });
    }
    scene.simulation.end_time = end;
    scene.output.snapshot_interval = Some(5e-5);
    let v0 = ring_speed(&scene);
    let dx = scene.bodies[0].spacing;
    let tmp = tempfile::tempdir().unwrap();
    let out = run_on(&scene, backend(), Some(tmp.path()));
    let shapes = ring_shapes(tmp.path(), &out, dx);
    for (time, ring, sizes, closest) in &shapes {
        println!(
            "no artificial stress ({}): t = {:5.1} µs, ring {ring}: clusters {sizes:?}, smallest distance {closest:.3} Δx",
            out.summary.backend,
            time * 1e6
        );
    }
    let closest = shapes.iter().map(|s| s.3).fold(f64::INFINITY, f64::min);
    assert!(
        closest < CLUMP,
        "no clumps without artificial stress: the smallest distance is {closest:.3} Δx"
    );
    let mass: f64 = out.summary.bodies.iter().map(|b| b.mass).sum();
    assert_momentum(&out, mass * v0);
    let e = column(&out, "energy_total");
    let worst = e.iter().map(|x| (x / e[0] - 1.0).abs()).fold(0.0, f64::max);
    println!("energy: worst {:.3} %", worst * 100.0);
    assert!(worst < 5e-3, "energy off by {worst:e}");
    if !paper {
        assert!(
            shapes.iter().all(|s| s.2.len() == 1),
            "a ring broke with the variational stress terms"
        );
    }
    if paper {
        assert!(
            shapes.iter().any(|s| s.2.len() > 1),
            "no ring fragmented without artificial stress"
        );
        let vl = *column(&out, "velocity_left").last().unwrap();
        assert!(vl > 0.0, "the plain rings rebounded ({vl} m/s)");
    }
}

/// How the rings are held together against the tensile instability.
#[derive(Clone, Copy, PartialEq)]
enum Hold {
    /// The scene's classic artificial stress.
    Classic,
    /// The default close-pair artificial stress.
    Default,
    /// The hourglass control at this α_hg, no artificial stress.
    Hourglass(f64),
    /// The default close-pair artificial stress with supports that follow
    /// the deformation from the start (`support_band = 1`), at this
    /// spacing.
    Adaptive(f64),
    /// `rubber_rings_fine.toml` as shipped: the same at Δx = 0.5 mm.
    Fine,
}

#[test]
fn rubber_rings_rebound_intact_with_artificial_stress() {
    rings_with_artificial_stress(None, Hold::Classic);
}

#[test]
fn rubber_rings_rebound_intact_with_hourglass_control() {
    rings_with_artificial_stress(None, Hold::Hourglass(1.0));
}

/// Two minutes on a software adapter: the device's hourglass control is
/// held to the CPU's in the stage tests (`gpu_stages`,
/// `stages_match_cpu_with_hourglass_control` and the leapfrog's steps),
/// and the rings' whole GPU run by `rubber_rings_rebound_intact_by_default_gpu`.
#[test]
#[ignore]
fn rubber_rings_rebound_intact_with_hourglass_control_gpu() {
    on_gpu(|| rings_with_artificial_stress(Some(3.3e-4), Hold::Hourglass(1.0)));
}

/// The midpoint rule at the same α_hg. (The leapfrog, the default, holds
/// the rings at 1.0 because its control's viscosity sees the
/// damping-weighted predicted velocity; with the plain one it was stable
/// to 0.7 only, docs/method.md, "Hourglass control".)
#[test]
fn rubber_rings_rebound_intact_with_hourglass_control_midpoint() {
    on_midpoint(|| rings_with_artificial_stress(None, Hold::Hourglass(1.0)));
}

/// The rings at Δx = 1 mm (4,398 particles), where round supports no
/// longer hold them: with the default close-pair stress (leapfrog, to
/// 600 µs) 11 particles end below zero, 6 of them below −1e-3 c_L² (down
/// to −0.079 c_L²), and the restitution falls to 0.636; the default band
/// (1.5) leaves the supports round here, to the bit. With
/// supports that follow the deformation from the start (the close-pair
/// gate then reads each pair in its own metric) they hold: besides the
/// checks above, no particle at a negative internal energy in any
/// snapshot. Measured (CPU, leapfrog, to 600 µs): the lowest +4.3e-5 c_L²,
/// restitution 0.809, energy −0.036 % at the end; to 300 µs here.
#[test]
fn rubber_rings_at_1_mm_hold_with_adaptive_supports() {
    rings_with_artificial_stress(Some(3.0e-4), Hold::Adaptive(1.0e-3));
}

/// The same on the GPU path (some minutes on a software adapter).
#[test]
#[ignore]
fn rubber_rings_at_1_mm_hold_with_adaptive_supports_gpu() {
    on_gpu(|| rings_with_artificial_stress(Some(3.0e-4), Hold::Adaptive(1.0e-3)));
}

/// `rubber_rings_fine.toml`, the same at Δx = 0.5 mm (17,594 particles)
/// to 400 µs: no particle ever at a negative internal energy (with the
/// default band of 1.5, 214 end below zero, 28 of them below −1e-3 c_L²).
/// Measured (CPU, leapfrog; 214 s on two cores): the lowest +1.9e-5 c_L²,
/// restitution 0.800, energy −0.020 % at the end; the midpoint rule
/// alike (lowest +2.0e-5 c_L², 351 s).
#[test]
#[ignore]
fn rubber_rings_at_half_mm_never_below_zero_internal_energy() {
    rings_with_artificial_stress(Some(4.0e-4), Hold::Fine);
}

/// The scene without its `[artificial_stress]`: the default holds the
/// rings as the classic form does.
#[test]
fn rubber_rings_rebound_intact_by_default() {
    rings_with_artificial_stress(None, Hold::Default);
}

#[test]
fn rubber_rings_rebound_intact_by_default_gpu() {
    on_gpu(|| rings_with_artificial_stress(Some(3.3e-4), Hold::Default));
}

/// GPU: to 330 µs, just past the separation (300 µs), without the period.
/// The classic form differs from the default only in the gate, which the
/// default's GPU run above and the stage tests take on the device
/// (a minute and a half on a software adapter).
#[test]
#[ignore]
fn rubber_rings_rebound_intact_with_artificial_stress_gpu() {
    on_gpu(|| rings_with_artificial_stress(Some(3.3e-4), Hold::Classic));
}

/// The midpoint rule to the same point.
#[test]
fn rubber_rings_rebound_intact_with_artificial_stress_midpoint() {
    on_midpoint(|| rings_with_artificial_stress(Some(3.3e-4), Hold::Classic));
}

/// With the former default viscosity (Monaghan's form, which leaves
/// receding pairs alone) and the paper's stress terms, the rings clump and
/// break by 250 µs. With the variational terms (docs/method.md §4) they
/// clump as much (pairs 0.04 Δx apart by 250 µs) and each ring stays one
/// cluster (measured to 400 µs).
/// On the midpoint rule, whose figures `rings_without_artificial_stress`
/// gives. (On the leapfrog, which lacks the midpoint rule's own damping,
/// these rings stop with the instability message before 250 µs, internal
/// energy held below zero: CPU, the paper's terms at 216 µs, the
/// variational ones at 224 µs.)
#[test]
fn rubber_rings_clump_and_break_without_artificial_stress() {
    on_midpoint(|| {
        rings_without_artificial_stress(2.5e-4, true, true);
        rings_without_artificial_stress(2.5e-4, false, true);
    });
}

/// With the default viscosity they clump by 160 µs; continued, the CPU
/// run stops at 190 µs with the instability message (a particle's
/// internal energy held below zero).
#[test]
fn rubber_rings_clump_without_artificial_stress() {
    rings_without_artificial_stress(1.6e-4, false, false);
}

/// GPU: to 160 µs, where the rings have clumped but not yet cracked.
#[test]
fn rubber_rings_clump_without_artificial_stress_gpu() {
    on_gpu(|| rings_without_artificial_stress(1.6e-4, false, false));
}

// ---------------------------------------------------------------------------
// 3. Stiff settings on the edge of stability
// ---------------------------------------------------------------------------
