//! A long run: a free bar ringing, and the integrators' order.

use super::*;

/// A free 5 mm steel bar ringing for 20 wave transits (scenes/hard/
/// long_ringing_bar.toml: two glued halves at ±10 m/s). Exact: each half's
/// mean velocity is a triangle wave between ±v0 crossing zero at
/// (k + ½) transits; energy and momentum constant.
///
/// What the method should keep, and the bounds:
/// * momentum to round-off and the run stable to the end (any instability
///   stops the run and fails it);
/// * total energy (kinetic + internal; the viscosity only moves energy
///   between them): the midpoint rule books its energy compatibly
///   (docs/method.md §9), so the total holds to round-off: measured
///   6.7e-16 over the 20 transits on the CPU path (bound 1e-12; before
///   the compatible energy it crept up 2.1e-3, the rule amplifying the
///   highest modes that the initial velocity jump excites) and 7.3e-7 in
///   the GPU's f32 (bound 5e-6);
/// * still ringing with a bounded amplitude: the largest |mean velocity| of
///   a half over the last two transits between 0.8 v0 and v0 (the viscosity
///   damps the ringing slowly: measured 0.901), exactly one zero crossing
///   per transit, each within 3 % of a transit of the exact (k + ½)
///   transits (measured 1.1 %: the lattice's dispersion is small at these
///   wavelengths).
///
/// The leapfrog's compatible kicks (docs/method.md §9) hold it to
/// round-off as well: −8.9e-16 (before them, its kicks booked at one end
/// of each half step while the step varied, +8.9e-5).
fn long_ringing() {
    let energy_bound = if backend() == sphcontact::scene::Backend::Gpu {
        5e-6
    } else {
        1e-12
    };
    let scene = load("scenes/hard/long_ringing_bar.toml");
    let steel = material(&scene, "steel");
    let v0 = 10.0;
    let transit = 0.005 / steel.c_l;
    let transits = scene.simulation.end_time / transit;
    assert!(transits >= 20.0 - 1e-3, "{transits} transits");
    let out = run(&scene);
    assert_conserved(&scene, &out);
    let t = &out.history.times;
    let e = column(&out, "energy_total");
    let (e0, e_end) = (e[0], *e.last().unwrap());
    println!("energy drift: {:.3e} over 20 transits", e_end / e0 - 1.0);
    assert!(
        (e_end / e0 - 1.0).abs() < energy_bound,
        "energy drift {:e}",
        e_end / e0 - 1.0
    );

    let v = column(&out, "velocity_left");
    let late = v
        .iter()
        .zip(t)
        .filter(|(_, &tk)| tk > t[t.len() - 1] - 2.0 * transit)
        .map(|(x, _)| x.abs())
        .fold(0.0, f64::max);
    println!(
        "ringing amplitude over the last two transits: {:.4} v0",
        late / v0
    );
    assert!(late > 0.8 * v0 && late <= v0, "amplitude {late}");
    let mut worst: f64 = 0.0;
    let mut crossings = 0;
    for k in 1..t.len() {
        if v[k - 1] * v[k] < 0.0 {
            let tc = t[k - 1] + (t[k] - t[k - 1]) * v[k - 1] / (v[k - 1] - v[k]);
            let phase = tc / transit - 0.5;
            worst = worst.max((phase - phase.round()).abs());
            crossings += 1;
        }
    }
    println!("{crossings} zero crossings, worst {worst:.4} of a transit from the exact");
    assert_eq!(crossings, 20, "one zero crossing per transit");
    assert!(worst < 0.03, "crossing off by {worst} of a transit");
}

#[test]
fn long_ringing_free_bar() {
    long_ringing();
}

#[test]
fn long_ringing_free_bar_midpoint() {
    on_midpoint(long_ringing);
}

#[test]
fn long_ringing_free_bar_gpu() {
    on_gpu(long_ringing);
}

// ---------------------------------------------------------------------------
// 5. Order of the time integration
// ---------------------------------------------------------------------------

/// Both integrators are second order in time (docs/method.md §9): the ringing
/// bar of the long run, to two transits, at CFL numbers 0.2, 0.1 and 0.05
/// against a run at 0.0125 on the same particles. Halving the step must
/// cut the largest error of a half's mean velocity about fourfold (at
/// least 3.5×; measured 4.0 and 4.2 for the midpoint rule, 3.7 and 4.0 for
/// the leapfrog, whose viscosity sees the damping-weighted predicted
/// velocity, 4.2 and 4.3 with the plain one). A first-order term fails
/// it: the leapfrog with the viscosity's reconstruction mixing `∇v` at
/// `n+½` with velocities at `n+1` gave 1.9 and 2.2, with its viscosity on
/// `v_{n+½}` 2.7 and 2.7.
fn second_order(integrator: Integrator) {
    let base = load("scenes/hard/long_ringing_bar.toml");
    let at = |cfl: f64| {
        let mut scene = base.clone();
        scene.simulation.end_time = 1.7e-6;
        scene.simulation.cfl = cfl;
        scene.simulation.integrator = integrator;
        let out = run(&scene);
        column(&out, "velocity_left")
    };
    let reference = at(0.0125);
    let err: Vec<f64> = [0.2, 0.1, 0.05]
        .iter()
        .map(|&c| {
            let v = at(c);
            assert_eq!(v.len(), reference.len());
            v.iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
        })
        .collect();
    let ratios = [err[0] / err[1], err[1] / err[2]];
    println!("{integrator}: errors {err:?}, ratios {ratios:?}");
    assert!(err[2] > 0.0 && err[2] < 1e-3, "errors {err:?}");
    for r in ratios {
        assert!(
            r > 3.5,
            "{integrator}: error ratios {ratios:?}, not second order"
        );
    }
}

#[test]
fn midpoint_rule_is_second_order() {
    second_order(Integrator::Midpoint);
}

#[test]
fn leapfrog_is_second_order() {
    second_order(Integrator::Leapfrog);
}
