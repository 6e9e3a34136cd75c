//! Exact answers of the paper's validation cases (docs/method.md §10), computed
//! from the material constants so that tests and validation figures compare
//! against computed, not hard-coded, values.
//!
//! * 1-D elastic bar impact (cases 1 and 2): linear acoustics in uniaxial
//!   strain, waves at `c_L` (docs/method.md §6: "1-D is uniaxial strain … waves
//!   therefore travel at `c_L`, not `c0`"), impedance `Z = ρ0 c_L`. Solved
//!   exactly by tracing the piecewise-constant wave fronts ([`bar_impact`],
//!   [`bar_impact_history`]); the equal-bar point history also in closed form
//!   ([`equal_bars_point_velocity`]).
//! * 1-D elastic–perfectly-plastic rod striking a rigid wall: the elastic
//!   precursor at the Hugoniot elastic limit and the plastic wave behind it,
//!   Rankine–Hugoniot jumps with the material's own EOS ([`rod_on_wall`]).
//! * 2-D quasi-static Hertz line contact of two identical disks in plane
//!   strain (case 3), with the two published choices of the approach constant
//!   `C` that bracket the dynamic answer ([`hertz_disks`]).
//!
//! Conventions (docs/method.md §2): SI units, stress tension positive, so contact
//! stresses are negative.

mod bar_tracer;
mod bars;
mod hertz;
mod ring;
mod rod;

pub use bars::*;
pub use hertz::*;
pub use ring::*;
pub use rod::*;

use std::f64::consts::FRAC_PI_2;

/// `∫_a^b f` by tanh–sinh (double-exponential) quadrature, refined by halving
/// the step until two levels agree to `rel_tol`. Nodes never touch the
/// endpoints and cluster there doubly exponentially, so integrable endpoint
/// singularities (here `φ ln φ`) cost nothing extra.
pub(crate) fn tanh_sinh<F: Fn(f64) -> f64>(f: &F, a: f64, b: f64, rel_tol: f64) -> f64 {
    let half = 0.5 * (b - a);
    if half <= 0.0 {
        return 0.0;
    }
    const T_MAX: f64 = 4.0;
    // Contribution of the node pair at ±t (or the centre at t = 0).
    let pair = |t: f64| -> f64 {
        let u = FRAC_PI_2 * t.sinh();
        let cu = u.cosh();
        let w = half * FRAC_PI_2 * t.cosh() / (cu * cu);
        if w.is_nan() || w <= 0.0 {
            return 0.0;
        }
        // Distance of the node from the nearer endpoint, accurate for large u.
        let d = 2.0 * half / (1.0 + (2.0 * u).exp());
        if t == 0.0 {
            return w * f(a + half);
        }
        if d.is_nan() || d <= 0.0 {
            return 0.0;
        }
        w * (f(a + d) + f(b - d))
    };
    let mut h = 1.0;
    let mut sum = pair(0.0);
    let mut k = 1.0;
    while k * h <= T_MAX {
        sum += pair(k * h);
        k += 1.0;
    }
    let mut estimate = h * sum;
    for _ in 0..10 {
        h *= 0.5;
        let mut k = 1.0;
        while k * h <= T_MAX {
            sum += pair(k * h);
            k += 2.0;
        }
        let next = h * sum;
        let done = (next - estimate).abs() <= rel_tol * next.abs();
        estimate = next;
        if done {
            break;
        }
    }
    estimate
}

/// What the tests of the exact answers share: materials and closeness.
#[cfg(test)]
pub(crate) mod test_support {
    use crate::physics::material::MaterialModel;

    /// A linear-EOS material from `(ρ0, c0, G)`, derived constants as in
    /// docs/method.md §6 (K = ρ0 c0², E = 9KG/(3K+G), c_L = sqrt((K + 4G/3)/ρ0)).
    pub fn material(rho0: f64, c0: f64, g: f64) -> MaterialModel {
        let k = rho0 * c0 * c0;
        let e = 9.0 * k * g / (3.0 * k + g);
        let nu = (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g));
        let m = k + 4.0 * g / 3.0;
        let c_l = (m / rho0).sqrt();
        MaterialModel {
            rho0,
            c0,
            eos: crate::physics::eos::Eos::linear(c0),
            g,
            y0: f64::INFINITY,
            k,
            e,
            nu,
            c_l,
            z: rho0 * c_l,
            m,
            strength: None,
            failure: None,
            spall: f64::INFINITY,
            cavitation: f64::INFINITY,
            specific_heat: 0.0,
            taylor_quinney: 0.0,
        }
    }

    pub fn steel() -> MaterialModel {
        material(7850.0, 4580.0, 77e9)
    }

    pub fn aluminium() -> MaterialModel {
        material(2790.0, 5330.0, 25e9)
    }

    /// Relative closeness to a printed figure.
    pub fn close(x: f64, expected: f64, rel: f64) -> bool {
        ((x - expected) / expected).abs() <= rel
    }

    /// Absolute closeness to a printed figure in its last digit.
    pub fn near(x: f64, expected: f64, abs: f64) -> bool {
        (x - expected).abs() <= abs
    }
}
