//! A free circular ring's flexural modes (the colliding rubber rings).

use crate::physics::material::MaterialModel;
use std::f64::consts::PI;

use super::hertz::plane_strain_modulus;

// ---------------------------------------------------------------------------
// A free circular ring's flexural modes (the colliding rubber rings of Gray,
// Monaghan & Swift 2001)
// ---------------------------------------------------------------------------

/// Period (s) of the in-plane flexural mode `n ≥ 2` of a free circular ring
/// of radii `inner` < `outer`, in plane strain (docs/method.md §6: 2-D is plane
/// strain, so the bending modulus is `E' = E/(1 − ν²)`); `n = 2` is the
/// ovalling mode.
///
/// Thin-ring theory (inextensional bending of the mid-line, Hoppe 1871;
/// Love, *Mathematical Theory of Elasticity*, §293): with mean radius
/// `R = (inner + outer)/2`, thickness `t = outer − inner`, bending stiffness
/// per unit depth `D = E' t³/12` and mass per unit length and depth `ρ0 t`,
///
/// ```text
/// ω_n² = D n² (n² − 1)² / (ρ0 t R⁴ (n² + 1))
/// ```
///
/// It neglects shear deformation and rotary inertia, which lower the
/// frequency of a thick ring (by a few per cent for n = 2 at t/R ≈ 0.3), and
/// holds for small amplitude. NaN for `n < 2` (rigid-body modes) or radii
/// that do not make a ring.
pub fn ring_flexural_period(mat: &MaterialModel, inner: f64, outer: f64, n: u32) -> f64 {
    if n < 2 || !(inner > 0.0 && outer > inner && outer.is_finite()) {
        return f64::NAN;
    }
    let r = 0.5 * (inner + outer);
    let t = outer - inner;
    let d = plane_strain_modulus(mat) * t.powi(3) / 12.0;
    let n2 = f64::from(n * n);
    let omega2 = d * n2 * (n2 - 1.0).powi(2) / (mat.rho0 * t * r.powi(4) * (n2 + 1.0));
    2.0 * PI / omega2.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validation::exact::test_support::*;

    /// The rubber ring of Gray, Monaghan & Swift (2001): E = 1e7 Pa,
    /// ν = 0.3975, ρ0 = 1, radii 3 and 4 cm. By hand: E' = 1e7/(1 − 0.3975²)
    /// = 1.18766e7 Pa, D/(ρ0 t) = E' t²/12 = 98.972 m⁴/s², R⁴ = 0.035⁴, so
    /// ω2 = sqrt(98.972/0.035⁴ · 36/5) = 21 791 rad/s, T2 = 288.33 µs. The
    /// period scales as R²/t and as n⁻³ for large n.
    #[test]
    fn ring_ovalling_period() {
        let k: f64 = 1e7 / (3.0 * (1.0 - 2.0 * 0.3975));
        let g = 1e7 / (2.0 * (1.0 + 0.3975));
        let rubber = material(1.0, k.sqrt(), g);
        assert!(close(rubber.e, 1e7, 1e-12) && close(rubber.nu, 0.3975, 1e-12));
        let t2 = ring_flexural_period(&rubber, 0.03, 0.04, 2);
        assert!(close(t2, 288.33e-6, 1e-4), "T2 = {t2:e}");
        // Twice as thick about the same mean radius: half the period.
        let thick = ring_flexural_period(&rubber, 0.025, 0.045, 2);
        assert!(close(thick, 0.5 * t2, 1e-12));
        // ω_n ∝ n(n² − 1)/sqrt(n² + 1): 2·3/√5 for n = 2, 3·8/√10 for n = 3.
        let t3 = ring_flexural_period(&rubber, 0.03, 0.04, 3);
        let ratio = (24.0 / 10f64.sqrt()) / (6.0 / 5f64.sqrt());
        assert!(close(t2 / t3, ratio, 1e-12));
        assert!(ring_flexural_period(&rubber, 0.03, 0.04, 1).is_nan());
        assert!(ring_flexural_period(&rubber, 0.04, 0.03, 2).is_nan());
    }
}
