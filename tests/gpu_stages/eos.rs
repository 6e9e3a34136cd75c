//! The equation of state against its formula (docs/method.md §6) at
//! several compressions and energies, on both backends: the shock states
//! of the Hugoniot `U_s = c0 + s u_p` (Rankine–Hugoniot, independent of
//! the solver's form), the Grüneisen term's `Γ0 ρ e` off the Hugoniot, the
//! tension branch, the sound speed as the pressure's slope, and a failed
//! particle's missing tension.

use super::*;
use sphcontact::physics::material::MaterialModel;

/// The paper's steel with a spall pressure, so that the device compiles
/// the failed branch in.
fn steel_scene() -> sphcontact::Scene {
    let mut scene = load("scenes/paper/bars_steel.toml");
    scene
        .materials
        .get_mut("steel")
        .expect("steel")
        .spall_pressure = Some(2e9);
    scene
}

/// A state `(μ, e, damage)` and the pressure the formula gives there with
/// the bound it holds to (the cubic's remainder on the Hugoniot, 0 off it).
struct Case {
    mu: f64,
    e: f64,
    damage: f64,
    p: f64,
    bound: f64,
}

/// The cases: shock states at particle speeds 50–800 m/s (μ up to 0.13),
/// the same densities at other energies, and expansions.
fn cases(m: &MaterialModel) -> Vec<Case> {
    let sphcontact::physics::eos::Eos::MieGruneisen(mg) = m.eos else {
        panic!("the paper's steel is Mie–Grüneisen");
    };
    let (a0, g0) = (m.rho0 * m.c0 * m.c0, mg.gamma0);
    let mut out = Vec::new();
    for up in [50.0, 100.0, 200.0, 400.0, 800.0] {
        // Rankine–Hugoniot: mass, momentum and energy across the shock.
        let us = m.c0 + mg.s * up;
        let rho = m.rho0 * us / (us - up);
        let mu = rho / m.rho0 - 1.0;
        let (p_h, e_h) = (m.rho0 * us * up, 0.5 * up * up);
        // The form's cubic is the Hugoniot's expansion in μ; its remainder
        // starts at a0 (4(s−1)³ + 3(s−1)²) μ⁴, under 2 a0 μ⁴ here.
        out.push(Case {
            mu,
            e: e_h,
            damage: 0.0,
            p: p_h,
            bound: 2.0 * a0 * mu.powi(4),
        });
        // Off the Hugoniot the energy adds Γ0 ρ (e − e_H) exactly.
        for e in [0.0, 1e4, 1e6] {
            out.push(Case {
                mu,
                e,
                damage: 0.0,
                p: p_h + g0 * rho * (e - e_h),
                bound: 2.0 * a0 * mu.powi(4),
            });
        }
    }
    for mu in [-0.001, -0.01, -0.05] {
        let rho = m.rho0 * (1.0 + mu);
        for e in [0.0, 1e5] {
            let p = (1.0 - 0.5 * g0 * mu) * a0 * mu + g0 * rho * e;
            out.push(Case {
                mu,
                e,
                damage: 0.0,
                p,
                bound: 0.0,
            });
            // A failed particle carries no tension.
            out.push(Case {
                mu,
                e,
                damage: 1.0,
                p: p.max(0.0),
                bound: 0.0,
            });
        }
    }
    out
}

/// The sound speed as §6 defines it: `c² = (ρ ∂p/∂ρ|_e + 4G/3)/ρ`, the
/// slope in compression by central differences of the CPU's pressure and
/// taken no smaller than `K/ρ0`, `K/ρ0` in expansion; `g` the shear
/// modulus the particle still has.
fn speed_from_slope(m: &MaterialModel, mu: f64, e: f64, g: f64) -> f64 {
    let rho = m.rho0 * (1.0 + mu);
    let d = 1e-6 * m.rho0;
    let slope = if mu > 0.0 {
        (m.pressure(rho + d, e) - m.pressure(rho - d, e)) / (2.0 * d)
    } else {
        0.0
    };
    ((rho * slope.max(m.k / m.rho0) + 4.0 * g / 3.0) / rho).sqrt()
}

#[test]
fn cpu_eos_meets_its_formula() {
    let m = material(&steel_scene(), "steel");
    for c in cases(&m) {
        let rho = m.rho0 * (1.0 + c.mu);
        let p = m.pressure_of(rho, c.e, c.damage);
        let tol = c.bound + 1e-12 * c.p.abs().max(m.k * c.mu.abs());
        assert!(
            (p - c.p).abs() <= tol,
            "μ {} e {} d {}: {p:e} against {:e}",
            c.mu,
            c.e,
            c.damage,
            c.p
        );
        let g = if c.damage >= 1.0 { 0.0 } else { m.g };
        let speed = m.sound_speed_of(rho, c.e, c.damage);
        let by_slope = speed_from_slope(&m, c.mu, c.e, g);
        // Central differences of a cubic: error (d/ρ0)² of the slope.
        assert!(
            (speed / by_slope - 1.0).abs() < 1e-9,
            "μ {}: c {speed} against {by_slope}",
            c.mu
        );
    }
}

/// The device's pressure and sound speed at the same states: the formula
/// within f32's round-off of the terms (1e-6 of them, measured 1e-7), and
/// the CPU twin likewise.
#[test]
fn gpu_eos_meets_its_formula() {
    let Some(ctx) = gpu() else { return };
    let scene = steel_scene();
    let m = material(&scene, "steel");
    let (model, st) = Model::new(&scene);
    assert!(model.can_fail());
    let g = GpuSolver::new(ctx, model, &st, &[], 1.0).expect("fits");
    let cases = cases(&m);
    let states: Vec<[f32; 3]> = cases
        .iter()
        .map(|c| [c.mu as f32, c.e as f32, c.damage as f32])
        .collect();
    let device = g.equation_of_state(0, &states);
    let mut worst = (0.0f64, 0.0f64);
    for (c, d) in cases.iter().zip(&device) {
        let rho = m.rho0 * (1.0 + c.mu);
        // The terms' size: what f32 rounds.
        let scale = m.k * c.mu.abs() + m.eos.gruneisen() * rho * c.e.abs();
        let (p, speed) = (d[0] as f64, d[1] as f64);
        let e_formula = (p - c.p).abs();
        assert!(
            e_formula <= c.bound + 1e-6 * scale,
            "μ {} e {} d {}: device {p:e} against {:e}",
            c.mu,
            c.e,
            c.damage,
            c.p
        );
        let cpu = m.pressure_of(rho, c.e, c.damage);
        assert!(
            (p - cpu).abs() <= 1e-6 * scale,
            "μ {}: {p:e} against the CPU's {cpu:e}",
            c.mu
        );
        let cpu_speed = m.sound_speed_of(rho, c.e, c.damage);
        let e_speed = (speed / cpu_speed - 1.0).abs();
        assert!(
            e_speed < 1e-6,
            "μ {}: c {speed} against the CPU's {cpu_speed}",
            c.mu
        );
        worst = (worst.0.max((p - cpu).abs() / scale), worst.1.max(e_speed));
    }
    println!(
        "device against the CPU: pressure {:.1e} of the terms, sound speed {:.1e}",
        worst.0, worst.1
    );
}
