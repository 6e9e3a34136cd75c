//! The paper's 1-D cases (docs/method.md §10, cases 1 and 2) against their exact
//! answers, in both interaction modes.

mod common;
use common::*;
use sphcontact::validation::exact::bar_impact;

const L: f64 = 0.005;

/// Case 1 at 100 particles per bar: plateau within 1 %, separation within
/// 1 %, rebound within 5 %, the bars never pulling each other, pressure
/// exactly 0 after.
#[test]
fn equal_steel_bars_penalty() {
    let mut scene = load("scenes/paper/bars_steel.toml");
    scene.output.history_interval = Some(1e-9);
    let steel = material(&scene, "steel");
    let exact = bar_impact(&steel, L, 10.0, &steel, L, -10.0);
    let out = run(&scene);
    assert_conserved(&scene, &out);
    let t = &out.history.times;
    let p = column(&out, "contact_pressure");
    let (t0, t_sep) = contact_window(t, &p);
    assert_eq!(t0, 0.0, "contact from the first step");
    let sep_err = t_sep / exact.separation_time - 1.0;
    assert!(
        sep_err.abs() < 0.01,
        "separation {t_sep:e} s ({sep_err:+.4})"
    );

    assert_never_pulls(&out, 0, "velocity_left");
    let sigma = -exact.contact_stress;
    for (k, &tk) in t.iter().enumerate() {
        if tk > 0.1 * t_sep && tk < 0.9 * t_sep {
            let e = p[k] / sigma - 1.0;
            assert!(
                e.abs() < 0.01,
                "plateau {:e} Pa at {tk:e} s ({e:+.4})",
                p[k]
            );
        }
        if tk > t_sep {
            assert_eq!(p[k], 0.0, "pressure after separation at {tk:e}");
        }
    }
    let vl = column(&out, "velocity_left");
    let vr = column(&out, "velocity_right");
    for (k, &tk) in t.iter().enumerate() {
        if tk > 1.05 * t_sep {
            assert!(
                (vl[k] / exact.final_velocity_1 - 1.0).abs() < 0.05,
                "left {}",
                vl[k]
            );
            assert!(
                (vr[k] / exact.final_velocity_2 - 1.0).abs() < 0.05,
                "right {}",
                vr[k]
            );
        }
    }
}

/// Kernel mode (the paper's "kerneling") never separates cleanly: the bars
/// stick in imaginary tension and their mean velocity swings back and forth,
/// where penalty mode leaves them at a steady rebound.
#[test]
fn equal_steel_bars_kernel_mode_does_not_separate() {
    let window = |out: &sphcontact::run::RunOutput| {
        let t = &out.history.times;
        let v = column(out, "velocity_left");
        let w: Vec<f64> = t
            .iter()
            .zip(&v)
            .filter(|(&tk, _)| tk > 2.0e-6)
            .map(|(_, &x)| x)
            .collect();
        let lo = w.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = w.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let kernel = load("scenes/paper/bars_steel_kernel.toml");
    let out_k = run(&kernel);
    assert_conserved(&kernel, &out_k);
    let (lo, hi) = window(&out_k);
    assert!(hi - lo > 10.0, "kernel mode swings: {lo} .. {hi}");
    assert!(hi > 0.0, "the left bar moves forward again: {hi}");
    // Tension appears at the interface particle (imaginary tension).
    let s = column(&out_k, "stress_a");
    assert!(s.iter().cloned().fold(f64::MIN, f64::max) > 2e8);

    let penalty = load("scenes/paper/bars_steel.toml");
    let out_p = run(&penalty);
    let (lo, hi) = window(&out_p);
    assert!(hi - lo < 0.01, "penalty mode is settled: {lo} .. {hi}");
}

fn steel_aluminium(v_steel: f64, v_al: f64) -> (sphcontact::Scene, sphcontact::run::RunOutput) {
    let mut scene = load("scenes/paper/bars_steel_aluminium.toml");
    scene.output.history_interval = Some(1e-9);
    scene.bodies[0].velocity = Some(vec![v_steel]);
    scene.bodies[1].velocity = Some(vec![v_al]);
    let out = run(&scene);
    assert_conserved(&scene, &out);
    (scene, out)
}

/// Case 2: interface stress within 2 %, separation within 3 %, final
/// aluminium velocity within 4 %; the Galilean shift (steel at 20 m/s onto
/// aluminium at rest) gives the same pressure and timing within 0.5 %.
#[test]
fn steel_against_aluminium() {
    let (scene, out) = steel_aluminium(10.0, -10.0);
    let exact = bar_impact(
        &material(&scene, "steel"),
        L,
        10.0,
        &material(&scene, "aluminium"),
        L,
        -10.0,
    );
    let t = &out.history.times;
    let p = column(&out, "contact_pressure");
    let (_, t_sep) = contact_window(t, &p);
    let sep_err = t_sep / exact.separation_time - 1.0;
    assert!(sep_err.abs() < 0.03, "separation {t_sep:e} ({sep_err:+.4})");
    let steady = plateau(t, &p, t_sep);
    let mean = steady.iter().sum::<f64>() / steady.len() as f64;
    for x in &steady {
        let e = x / -exact.contact_stress - 1.0;
        assert!(e.abs() < 0.02, "interface stress {x:e} ({e:+.4})");
    }
    assert_never_pulls(&out, 0, "velocity_left");
    let v_al = *column(&out, "velocity_right").last().unwrap();
    let e_al = v_al / exact.final_velocity_2 - 1.0;
    assert!(e_al.abs() < 0.04, "aluminium leaves at {v_al} ({e_al:+.4})");

    let (_, out_g) = steel_aluminium(20.0, 0.0);
    let pg = column(&out_g, "contact_pressure");
    let (_, t_sep_g) = contact_window(&out_g.history.times, &pg);
    let steady_g = plateau(&out_g.history.times, &pg, t_sep);
    let mean_g = steady_g.iter().sum::<f64>() / steady_g.len() as f64;
    assert!(
        (mean_g / mean - 1.0).abs() < 0.005,
        "Galilean pressure {mean_g:e} vs {mean:e}"
    );
    assert!(
        (t_sep_g / t_sep - 1.0).abs() < 0.005,
        "Galilean separation {t_sep_g:e} vs {t_sep:e}"
    );
}

/// A single bar translating at 10 m/s stays stress-free and keeps its speed;
/// two bars touching at rest stay at rest with no contact force.
#[test]
fn translation_and_rest() {
    let scene = parse(
        r#"
[simulation]
dimension = 1
end_time = 2e-6
[materials.steel]
density = 7850.0
shear_modulus = 77e9
eos = { kind = "mie_gruneisen", c0 = 4580.0, s = 1.49, gamma0 = 2.02 }
[[bodies]]
name = "bar"
material = "steel"
spacing = 5e-5
velocity = [10.0]
shape = { kind = "segment", from = -0.005, to = 0.0 }
[[probes]]
name = "s_end"
kind = "particle"
body = "bar"
at = [0.0]
quantity = "stress_xx"
[[probes]]
name = "s_mid"
kind = "particle"
body = "bar"
at = [-0.0025]
quantity = "stress_xx"
[[probes]]
name = "v"
kind = "body"
body = "bar"
quantity = "velocity_x"
"#,
    );
    let out = run(&scene);
    assert_conserved(&scene, &out);
    for name in ["s_end", "s_mid"] {
        let worst = column(&out, name)
            .iter()
            .fold(0.0f64, |a, &b| a.max(b.abs()));
        assert!(worst < 1e-3, "{name}: {worst} Pa in a translating bar");
    }
    assert!(column(&out, "v").iter().all(|&v| (v - 10.0).abs() < 1e-12));

    let mut rest = load("scenes/paper/bars_steel.toml");
    rest.bodies[0].velocity = Some(vec![0.0]);
    rest.bodies[1].velocity = Some(vec![0.0]);
    rest.simulation.end_time = 2e-6;
    let out = run(&rest);
    // Exactly at rest in f64. In f32 the touching faces' gap is known to
    // about 1e-7 Δx (a few units in the last place of a cell size), and the
    // penalty spring (M/Δx) turns that into up to ~1e5 Pa (2e-4 of the impact's
    // contact stress): body velocities of order 1e-6 m/s and a wave of
    // particle velocity σ/Z of order 1e-5 m/s (1e-6 of the impact speed).
    let gpu = backend() == sphcontact::scene::Backend::Gpu;
    for (name, tol) in [
        ("velocity_left", if gpu { 1e-5 } else { 1e-9 }),
        ("velocity_right", if gpu { 1e-5 } else { 1e-9 }),
        ("velocity_b", if gpu { 1e-4 } else { 1e-9 }),
        ("contact_force", if gpu { 1e5 } else { 1e-9 }),
    ] {
        let worst = column(&out, name)
            .iter()
            .fold(0.0f64, |a, &b| a.max(b.abs()));
        println!("{name}: worst {worst:e}");
        assert!(worst < tol, "{name}: {worst} for bodies at rest");
    }
}

/// A rigid partner has infinite impedance and modulus (docs/method.md §8.5): a
/// steel bar at 10 m/s onto a rigid wall sees the stress of two equal bars
/// closing at 20 m/s, separates at 2L/c_L and rebounds at −10 m/s; the wall
/// does not move.
#[test]
fn bar_onto_rigid_wall() {
    let mut scene = load("scenes/paper/bars_steel.toml");
    scene.output.history_interval = Some(1e-9);
    scene.bodies[1].rigid = true;
    scene.bodies[1].velocity = Some(vec![0.0]);
    let steel = material(&scene, "steel");
    let exact = bar_impact(&steel, L, 10.0, &steel, L, -10.0);
    let out = run(&scene);
    let t = &out.history.times;
    let p = column(&out, "contact_pressure");
    let (_, t_sep) = contact_window(t, &p);
    assert!(
        (t_sep / exact.separation_time - 1.0).abs() < 0.01,
        "separation {t_sep:e}"
    );
    let k = t.iter().position(|&x| x > 0.5 * t_sep).unwrap();
    assert!(
        (p[k] / -exact.contact_stress - 1.0).abs() < 0.01,
        "pressure {:e}",
        p[k]
    );
    let vl = *column(&out, "velocity_left").last().unwrap();
    assert!((vl / -10.0 - 1.0).abs() < 0.05, "rebound {vl}");
    assert_never_pulls(&out, 0, "velocity_left");
    assert!(column(&out, "velocity_right").iter().all(|&v| v == 0.0));
    // Energy: the wall does no work, so the bar's energy balance still closes.
    let drift = (out.summary.energy_final / out.summary.energy_initial - 1.0).abs();
    assert!(drift < 5e-3, "energy drift {drift:e}");
}

/// The lateral stress of uniaxial strain: in the steel bars' impact the
/// `stress_zz` probe reads the other lateral stress, `stress_yy`, to
/// round-off, and differs from the axial stress by the deviator's exact
/// `σ_zz − σ_xx = 2G ln(ρ/ρ0)` (the hypoelastic law in uniaxial strain,
/// whatever the EOS) at every row the wave has reached: to 1e-5 in f64,
/// 1e-3 in f32 (whose density carries 1e-7 of itself, 1e-4 of the strain
/// here). On the backend of the thread.
fn lateral_stress_of_uniaxial_strain() {
    let mut scene = load("scenes/paper/bars_steel.toml");
    scene.simulation.end_time = 1.0e-6;
    let probe = |name: &str, quantity: &str| {
        format!("\n[[probes]]\nname = \"{name}\"\nkind = \"particle\"\nbody = \"left\"\nat = [-0.0025]\nquantity = \"{quantity}\"\n")
    };
    let text = scene.to_toml()
        + &probe("sxx", "stress_xx")
        + &probe("syy", "stress_yy")
        + &probe("szz", "stress_zz")
        + &probe("rho", "density");
    let scene = parse(&text);
    let steel = material(&scene, "steel");
    let out = run(&scene);
    let (sxx, syy, szz, rho) = (
        column(&out, "sxx"),
        column(&out, "syy"),
        column(&out, "szz"),
        column(&out, "rho"),
    );
    let gpu = backend() == sphcontact::scene::Backend::Gpu;
    let (round_off, tol) = if gpu { (1e-5, 1e-3) } else { (1e-12, 1e-5) };
    let peak = sxx.iter().map(|s| s.abs()).fold(0.0, f64::max);
    assert!(peak > 4e8, "the bar is compressed: {peak:e}");
    let mut reached = 0;
    for k in 0..sxx.len() {
        assert!(
            (szz[k] - syy[k]).abs() <= round_off * peak,
            "{} against {}",
            szz[k],
            syy[k]
        );
        if sxx[k].abs() > 0.2 * peak {
            reached += 1;
            let exact = 2.0 * steel.g * (rho[k] / steel.rho0).ln();
            let e = ((szz[k] - sxx[k]) - exact).abs() / exact.abs();
            assert!(e < tol, "row {k}: {} against {exact}", szz[k] - sxx[k]);
        }
    }
    assert!(reached > 10, "{reached} rows behind the wave");
}

#[test]
fn lateral_stress_of_uniaxial_strain_cpu() {
    lateral_stress_of_uniaxial_strain();
}

#[test]
fn lateral_stress_of_uniaxial_strain_gpu() {
    on_gpu(lateral_stress_of_uniaxial_strain);
}

/// The midpoint rule. (The leapfrog, the default above, takes the step's
/// strain rate exactly in its density, `ρ exp(−Δt tr ∇v)`; with the
/// forward step `ρ + Δt ρ̇` the identity held to 1.5e-5 only.)
#[test]
fn lateral_stress_of_uniaxial_strain_midpoint() {
    on_midpoint(lateral_stress_of_uniaxial_strain);
}

#[test]
fn lateral_stress_of_uniaxial_strain_midpoint_gpu() {
    on_midpoint(|| on_gpu(lateral_stress_of_uniaxial_strain));
}

/// The paper's steel bars meeting at `v` each for 1.5 µs, with the yield
/// stress `yield_stress` (`None`: elastic). The artificial stress's work
/// keeps either sign in both (`work = "either"`): by default a body that
/// can yield takes only its share that is heat, which moves even the
/// bars that never yield (their rebound speed at 4 µs by 2e-5 of itself),
/// and this compares the material alone.
fn steel_bars(yield_stress: Option<f64>, v: f64) -> sphcontact::Scene {
    let mut scene = load("scenes/paper/bars_steel.toml");
    assert_eq!(scene.artificial_stress, None);
    scene.artificial_stress = Some(sphcontact::scene::ArtificialStress {
        work: sphcontact::scene::ArtWork::Either,
        ..sphcontact::scene::ArtificialStress::DEFAULT
    });
    scene.simulation.end_time = 1.5e-6;
    scene.materials.get_mut("steel").unwrap().yield_stress = yield_stress;
    scene.bodies[0].velocity = Some(vec![v]);
    scene.bodies[1].velocity = Some(vec![-v]);
    scene
}

/// Perfect plasticity (docs/method.md §6): below yield the run is identical to the
/// elastic one; above it the radial return holds von Mises at Y0 exactly.
#[test]
fn plasticity_caps_von_mises() {
    let with_vm = |yield_stress: Option<f64>, v: f64| {
        let text = steel_bars(yield_stress, v).to_toml()
            + "\n[[probes]]\nname = \"vm_a\"\nkind = \"particle\"\nbody = \"left\"\nat = [-0.0001]\nquantity = \"von_mises\"\n"
            + "\n[[probes]]\nname = \"vm_b\"\nkind = \"particle\"\nbody = \"left\"\nat = [-0.0025]\nquantity = \"von_mises\"\n";
        let scene = parse(&text);
        let out = run(&scene);
        assert_conserved(&scene, &out);
        out
    };
    let elastic = with_vm(None, 10.0);
    let below = with_vm(Some(600e6), 10.0);
    assert_eq!(
        elastic.history.rows, below.history.rows,
        "below yield nothing changes"
    );
    let peak_elastic = column(&elastic, "vm_b").iter().cloned().fold(0.0, f64::max);
    assert!(
        peak_elastic > 2e8 && peak_elastic < 6e8,
        "elastic von Mises {peak_elastic:e}"
    );

    let y0 = 600e6;
    let plastic = with_vm(Some(y0), 50.0);
    // "Exactly" is to the arithmetic's round-off: f64 on the CPU, f32 on
    // the GPU (the returned stress is rescaled and its norm recomputed).
    let round_off = if backend() == sphcontact::scene::Backend::Gpu {
        1e-6
    } else {
        1e-12
    };
    for name in ["vm_a", "vm_b"] {
        let peak = column(&plastic, name).iter().cloned().fold(0.0, f64::max);
        assert!(peak <= y0 * (1.0 + round_off), "{name}: {peak:e} above Y0");
        assert!(peak > 0.999 * y0, "{name}: {peak:e} never yields at 50 m/s");
    }
}

/// The artificial stress keyed on plastic flow (`work = "plastic"`) keys
/// nothing below yield: the bars with a yield stress they never reach run
/// as the elastic bars do with the term's work of either sign, to the bit.
#[test]
fn below_yield_the_plastic_key_changes_nothing() {
    use sphcontact::scene::{ArtWork, ArtificialStress};
    let bars = |yield_stress: Option<f64>, work: ArtWork| {
        let mut scene = steel_bars(yield_stress, 10.0);
        scene.artificial_stress = Some(ArtificialStress {
            work,
            ..ArtificialStress::DEFAULT
        });
        run(&scene).history.rows
    };
    assert_eq!(
        bars(Some(600e6), ArtWork::Plastic),
        bars(None, ArtWork::Either),
        "below yield nothing changes"
    );
}

// The same physics on the GPU backend (f32 on the device).

#[test]
fn equal_steel_bars_penalty_gpu() {
    on_gpu(equal_steel_bars_penalty);
}

#[test]
fn equal_steel_bars_kernel_mode_does_not_separate_gpu() {
    on_gpu(equal_steel_bars_kernel_mode_does_not_separate);
}

/// Held to the CPU's run (which meets the targets) to 0.5 % in
/// tests/gpu_runs/; this run of the targets on the device is nearly a
/// minute on a software adapter.
#[test]
#[ignore]
fn steel_against_aluminium_gpu() {
    on_gpu(steel_against_aluminium);
}

#[test]
fn translation_and_rest_gpu() {
    on_gpu(translation_and_rest);
}

#[test]
fn bar_onto_rigid_wall_gpu() {
    on_gpu(bar_onto_rigid_wall);
}

#[test]
fn plasticity_caps_von_mises_gpu() {
    on_gpu(plasticity_caps_von_mises);
}

// The same exact answers with the midpoint rule, two evaluations a step
// (CPU path; the default is the leapfrog).

#[test]
fn equal_steel_bars_penalty_midpoint() {
    on_midpoint(equal_steel_bars_penalty);
}

#[test]
fn steel_against_aluminium_midpoint() {
    on_midpoint(steel_against_aluminium);
}

#[test]
fn translation_and_rest_midpoint() {
    on_midpoint(translation_and_rest);
}

#[test]
fn bar_onto_rigid_wall_midpoint() {
    on_midpoint(bar_onto_rigid_wall);
}

#[test]
fn plasticity_caps_von_mises_midpoint() {
    on_midpoint(plasticity_caps_von_mises);
}

/// Case 1's rebound and contact plateau at 100 particles a bar with the
/// dispersion correction at `theta` and the viscosity at α = 0.3, at CFL
/// `cfl` with `integrator`; the ledger closes.
fn rebound_with_the_correction(
    theta: f64,
    cfl: f64,
    integrator: sphcontact::scene::Integrator,
) -> (f64, f64) {
    let mut scene = load("scenes/paper/bars_steel.toml");
    let steel = material(&scene, "steel");
    let exact = bar_impact(&steel, L, 10.0, &steel, L, -10.0);
    with_dispersion_correction(&mut scene, theta, 0.3);
    scene.simulation.cfl = cfl;
    scene.simulation.integrator = integrator;
    let out = run(&scene);
    assert_conserved(&scene, &out);
    let ledger = &out.summary.energy;
    assert!(ledger.residual.abs() < 1e-10 * ledger.initial, "{ledger:?}");
    let rebound = column(&out, "velocity_left").last().copied().unwrap() / exact.final_velocity_1;
    let t = &out.history.times;
    let p = column(&out, "contact_pressure");
    let (_, t_sep) = contact_window(t, &p);
    let sigma = -exact.contact_stress;
    let ring = plateau(t, &p, t_sep)
        .iter()
        .map(|&x| (x / sigma - 1.0).abs())
        .fold(0.0, f64::max);
    println!(
        "θ {theta}, CFL {cfl}, {integrator:?}: rebound {rebound:.5}, plateau within {ring:.4}"
    );
    (rebound, ring)
}

/// The dispersion correction (docs/method.md §4) at θ = 0.7 with the
/// viscosity at α = 0.3 brings case 1's rebound at 100 particles a bar
/// to 0.98 of the exact with both integrators (measured 0.9812 and
/// 0.9811), its contact plateau within 1 %, where the same viscosity
/// without it stops at 0.9725 and rings 1.4 %: the rebound is lost to
/// the release front's dispersion, not to its damping.
#[test]
fn dispersion_correction_lifts_the_rebound() {
    use sphcontact::scene::Integrator;
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        let (rebound, ring) = rebound_with_the_correction(0.7, 0.3, integrator);
        assert!(rebound >= 0.98, "rebound {rebound}");
        assert!(ring < 0.01, "plateau off by {ring}");
    }
    let (rebound, _) = rebound_with_the_correction(0.0, 0.3, Integrator::Midpoint);
    assert!(rebound < 0.975, "rebound {rebound} without the correction");
}

/// The same at CFL 0.05 (measured 0.9810 with both): the rebound is the
/// operator's, not the step's.
#[test]
#[ignore = "long: six times the steps; run with --ignored"]
fn dispersion_correction_lifts_the_rebound_at_small_steps() {
    use sphcontact::scene::Integrator;
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        let (rebound, ring) = rebound_with_the_correction(0.7, 0.05, integrator);
        assert!(rebound >= 0.98, "rebound {rebound}");
        assert!(ring < 0.01, "plateau off by {ring}");
    }
}
