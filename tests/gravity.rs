//! The body force (`[simulation] gravity`): a free fall exact to
//! round-off, and an elastic bar set on a rigid wall as the force comes on
//! (scenes/boundaries/bar_under_gravity.toml) against the fixed–free
//! bar's exact answer; the energy ledger, with the potential energy,
//! closed; on both backends and both integrators.

#[path = "common/mod.rs"]
mod common;
use common::*;
use glam::DVec2;
use sphcontact::scene::Backend;
use sphcontact::Scene;

/// What `steps` steps of two kicks each may round away, relative to a
/// velocity: `2 N ε` (ε = 2⁻⁵³ on the CPU, 2⁻²⁴ in the GPU's f32).
fn rounding(steps: u64) -> f64 {
    let eps = if backend() == Backend::Gpu {
        f32::EPSILON as f64
    } else {
        f64::EPSILON
    };
    steps as f64 * eps
}

/// A 4340 steel disk (716 particles) thrown at 10 m/s across a body force
/// of (3, −4)·10⁵ m/s², nothing else in the scene.
fn free_fall() -> Scene {
    parse(
        r#"
title = "free fall"
[simulation]
dimension = 2
end_time = 2.0e-5
gravity = [3.0e5, -4.0e5]
[materials.steel]
library = "steel_4340"
[[bodies]]
name = "disk"
material = "steel"
spacing = 2.0e-4
velocity = [10.0, 0.0]
shape = { kind = "disk", center = [0.0, 0.0], radius = 0.003 }
[[probes]]
name = "y"
kind = "body"
body = "disk"
quantity = "position_y"
[[probes]]
name = "potential"
kind = "energy"
quantity = "potential"
[output]
history_interval = 5.0e-6
"#,
    )
}

/// Every particle falls as a point: its velocity `v0 + g t`, the disk's
/// mean height `½ g_y t²`, no stress and no internal energy; the ledger
/// closed with the potential `−M g·Δx̄`; each within [`rounding`]'s bound
/// (1,638 steps: 3.6e-13 on the CPU, measured 2e-16; 2.0e-4 on the GPU,
/// measured 9.8e-6 in the leapfrog's velocity and 1.9e-5 of the potential
/// in its ledger, 2.4e-7 and 8e-8 in the midpoint rule's).
fn falls_freely() {
    let scene = free_fall();
    let out = run(&scene);
    let (g, v0, t) = (DVec2::new(3.0e5, -4.0e5), DVec2::new(10.0, 0.0), 2.0e-5);
    let tol = rounding(out.summary.steps);
    assert_eq!(out.summary.status, "completed");
    let v = v0 + g * t;
    let worst = out
        .state
        .v
        .iter()
        .map(|vi| (*vi - v).length())
        .fold(0.0, f64::max);
    assert!(worst <= tol * v.length(), "velocity off by {worst:e}");
    let y = column(&out, "y");
    let fall = 0.5 * g.y * t * t;
    assert!(
        (y[y.len() - 1] - y[0] - fall).abs() <= tol * fall.abs(),
        "height {:e} against {fall:e}",
        y[y.len() - 1] - y[0]
    );
    let l = &out.summary.energy;
    let mass = out.summary.bodies[0].mass;
    let drop = -mass * g.dot((v0 + g * (0.5 * t)) * t);
    let potential = l.potential.expect("the ledger names the potential");
    println!(
        "{:?}: velocity {worst:e}, potential {potential:e} against {drop:e}, residual {:e}",
        backend(),
        l.residual
    );
    assert!((potential - drop).abs() <= tol * drop.abs(), "{l:?}");
    assert!(l.internal.abs() <= tol * l.kinetic, "{l:?}");
    assert!(l.residual.abs() <= tol * drop.abs(), "{l:?}");
    // The probe reads what the ledger holds.
    let u = column(&out, "potential");
    assert!((u[u.len() - 1] - potential).abs() <= tol * drop.abs());
}

/// A steel cylinder of revolution (radius 1 mm, 2 mm long) thrown along
/// its axis at 10 m/s against a body force of 4·10⁵ m/s² along it.
fn free_fall_of_revolution() -> Scene {
    parse(
        r#"
title = "free fall of a body of revolution"
[simulation]
dimension = 2
geometry = "axisymmetric"
end_time = 1.0e-5
gravity = [0.0, -4.0e5]
[materials.steel]
library = "steel_4340"
[[bodies]]
name = "cylinder"
material = "steel"
spacing = 1.0e-4
velocity = [0.0, 10.0]
shape = { kind = "rectangle", min = [0.0, 0.0], max = [0.001, 0.002] }
"#,
    )
}

/// The cylinder falls as a point: every particle at `v0 + g t` within
/// [`rounding`]'s bound and twice the motion it makes in the same run
/// without the force (the body of revolution's placed state is in
/// equilibrium only to round-off, which moves its particles by up to
/// 5e-12 m/s on the CPU, with or without gravity); the ledger closed as
/// in [`falls_freely`].
fn falls_freely_of_revolution() {
    let scene = free_fall_of_revolution();
    let out = run(&scene);
    let mut still = scene.clone();
    still.simulation.gravity = None;
    let base = run(&still);
    assert_eq!(out.summary.status, "completed");
    let off = |o: &sphcontact::run::RunOutput, v: DVec2| {
        o.state
            .v
            .iter()
            .map(|vi| (*vi - v).length())
            .fold(0.0, f64::max)
    };
    let v0 = DVec2::new(0.0, 10.0);
    let own = off(&base, v0);
    let worst = off(&out, v0 + DVec2::new(0.0, -4.0e5 * 1.0e-5));
    let tol = rounding(out.summary.steps);
    println!(
        "{:?}: velocity {worst:e} (without the force {own:e}), ledger {:?}",
        backend(),
        out.summary.energy
    );
    assert!(worst <= tol * 10.0 + 2.0 * own, "velocity off by {worst:e}");
    let l = &out.summary.energy;
    assert!(
        l.residual.abs() <= tol * l.potential.unwrap().abs(),
        "{l:?}"
    );
}

#[test]
fn free_fall_is_exact() {
    falls_freely();
}

#[test]
fn free_fall_of_a_body_of_revolution_is_exact() {
    falls_freely_of_revolution();
}

#[test]
fn free_fall_of_a_body_of_revolution_is_exact_gpu() {
    on_gpu(falls_freely_of_revolution);
}

#[test]
fn free_fall_is_exact_midpoint() {
    on_midpoint(falls_freely);
}

#[test]
fn free_fall_is_exact_gpu() {
    on_gpu(falls_freely);
}

#[test]
fn free_fall_is_exact_gpu_midpoint() {
    on_midpoint(|| on_gpu(falls_freely));
}

/// What the bar of scenes/boundaries/bar_under_gravity.toml did, against
/// the exact answer.
#[derive(Debug)]
struct Bar {
    /// The wall's largest force over 2 M g (at T/2), less 1.
    peak: f64,
    /// The wall's impulse over [0, T] over M g T, less 1.
    impulse: f64,
    /// The bar's mean displacement at T/2 over the exact, less 1.
    sag: f64,
    /// Its mean velocity and displacement at T over their largest in [0, T].
    back: (f64, f64),
    /// The ledger's residual over the largest |potential|.
    residual: f64,
}

fn bar_under_gravity() -> Bar {
    let scene = load("scenes/boundaries/bar_under_gravity.toml");
    let mat = material(&scene, "steel");
    let m_l = mat.k + 4.0 * mat.g / 3.0;
    let c = (m_l / mat.rho0).sqrt();
    let (l, g) = (0.01, scene.simulation.gravity.as_ref().unwrap()[0]);
    let (mass, period) = (mat.rho0 * l, 4.0 * l / c);
    let out = run(&scene);
    assert_eq!(out.summary.status, "completed");
    let t = &out.history.times;
    let (f, v, x, u) = (
        column(&out, "wall_force"),
        column(&out, "bar_velocity"),
        column(&out, "bar_position"),
        column(&out, "energy_potential"),
    );
    let impulse: f64 = (1..t.len())
        .map(|k| 0.5 * (f[k] + f[k - 1]) * (t[k] - t[k - 1]))
        .sum();
    let half = (0..t.len())
        .min_by(|&a, &b| {
            (t[a] - 0.5 * period)
                .abs()
                .total_cmp(&(t[b] - 0.5 * period).abs())
        })
        .unwrap();
    let sag = 2.0 * mat.rho0 * g * l * l / (3.0 * m_l);
    let largest = |s: &[f64]| s.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    let dx: Vec<f64> = x.iter().map(|xi| xi - x[0]).collect();
    let end = t.len() - 1;
    assert!((t[end] / period - 1.0).abs() < 1e-3, "the scene ends at T");
    let bar = Bar {
        peak: largest(&f) / (2.0 * mass * g) - 1.0,
        impulse: impulse / (mass * g * period) - 1.0,
        sag: dx[half] / sag - 1.0,
        back: (v[end].abs() / largest(&v), dx[end].abs() / largest(&dx)),
        residual: out.summary.energy.residual / largest(&u),
    };
    println!("{:?}: {bar:?}", backend());
    bar
}

/// The wall's peak force within 2 % of 2 M g and its impulse over a period
/// within 1 % of M g T; the sag at T/2 within 2 % of twice the static; at
/// T the bar back at rest where it started (its mean velocity below 3 % of
/// its largest, its displacement below 1 %); the ledger closed to 1e-9 of
/// the largest potential (1e-4 in f32).
///
/// Measured (CPU, leapfrog): peak −0.82 %, impulse −0.16 %, sag −0.59 %,
/// back 1.2 % and 0.02 %, residual 6e-13.
fn holds(b: &Bar) {
    let tol = if backend() == Backend::Gpu {
        1e-4
    } else {
        1e-9
    };
    assert!(b.peak.abs() < 0.02, "{b:?}");
    assert!(b.impulse.abs() < 0.01, "{b:?}");
    assert!(b.sag.abs() < 0.02, "{b:?}");
    assert!(b.back.0 < 0.03 && b.back.1 < 0.01, "{b:?}");
    assert!(b.residual.abs() < tol, "{b:?}");
}

#[test]
fn bar_on_a_wall_rings_about_its_static_sag() {
    holds(&bar_under_gravity());
}

#[test]
fn bar_on_a_wall_rings_about_its_static_sag_midpoint() {
    on_midpoint(|| holds(&bar_under_gravity()));
}

#[test]
fn bar_on_a_wall_rings_about_its_static_sag_gpu() {
    on_gpu(|| holds(&bar_under_gravity()));
}
