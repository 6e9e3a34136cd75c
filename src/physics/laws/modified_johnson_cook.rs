//! Johnson–Cook strength with the multiplicative rate term of Børvik et al.
//! (Eur. J. Mech. A/Solids 20 (2001) 685, eq. 1; Camacho & Ortiz's form),
//! the "modified Johnson–Cook" used for the Weldox steels:
//!
//! `σ_y = (A + B ε_pⁿ)(1 + ε̇*)^C (1 − T*ᵐ)`, `ε̇* = ε̇ / ε̇0`,
//!
//! which stays positive and smooth as the rate falls to zero, where the
//! logarithmic form needs its rates clamped at the reference. The keys are
//! Johnson–Cook's ([`super::johnson_cook::Strength`]); `ε̇` is, as for
//! Johnson–Cook here, the particle's total equivalent strain rate. Device
//! twin: `shaders/laws/modified_johnson_cook.wgsl`.

use serde::{Deserialize, Serialize};

use super::{johnson_cook, Law, DEVICE_CONSTANTS};

/// The constants, as a scene writes them
/// (`strength = { kind = "modified_johnson_cook", a, b, … }`): those of
/// [`johnson_cook::Strength`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Strength(pub johnson_cook::Strength);

impl Strength {
    /// `(1 + ε̇/ε̇0)^C`.
    pub fn rate_factor(&self, strain_rate: f64) -> f64 {
        let jc = &self.0;
        (1.0 + strain_rate.max(0.0) / jc.reference_strain_rate).powf(jc.c)
    }
}

impl Law for Strength {
    /// `(1 + ε̇*)^C (1 − T*ᵐ)`.
    fn factor(&self, rate: f64, temperature: f64) -> f64 {
        self.rate_factor(rate) * self.0.thermal_factor(temperature)
    }

    fn curve(&self, factor: f64, eps_p: f64) -> (f64, f64) {
        self.0.curve(factor, eps_p)
    }

    fn room_temperature(&self) -> f64 {
        self.0.room_temperature
    }

    fn melt_temperature(&self) -> Option<f64> {
        Some(self.0.melt_temperature)
    }

    fn reference_strain_rate(&self) -> f64 {
        self.0.reference_strain_rate
    }

    fn rate_dependent(&self) -> bool {
        self.0.c != 0.0
    }

    fn check(&self) -> Result<(), (&'static str, String)> {
        self.0.check_constants()
    }

    fn device(&self) -> [f32; DEVICE_CONSTANTS] {
        self.0.constants()
    }

    /// `A`: the static yield stress, at rest.
    fn initial_yield(&self) -> f64 {
        self.0.a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Weldox 460 E (Børvik et al. 2001, Table 2).
    pub(crate) fn weldox_460e() -> Strength {
        Strength(johnson_cook::Strength {
            a: 490e6,
            b: 807e6,
            n: 0.73,
            c: 0.0114,
            m: 0.94,
            reference_strain_rate: 5e-4,
            room_temperature: 293.0,
            melt_temperature: 1800.0,
        })
    }

    #[test]
    fn flow_stress_terms_each_alone() {
        let s = weldox_460e();
        let eps: f64 = 0.2;
        let stat = 490e6 + 807e6 * eps.powf(0.73);
        // At rest the rate term is 1 (2^C at the reference rate).
        let y0 = s.flow_stress(eps, 0.0, 293.0);
        assert!((y0 - stat).abs() <= 1e-12 * stat, "{y0} vs {stat}");
        let y = s.flow_stress(eps, 5e-4, 293.0);
        assert!((y / stat - 2f64.powf(0.0114)).abs() < 1e-14);
        // 1000/s: (1 + 2e6)^C, about 18 % above the static curve.
        let r = s.flow_stress(eps, 1e3, 293.0) / stat;
        assert!((r - (1.0 + 1e3 / 5e-4f64).powf(0.0114)).abs() < 1e-14);
        assert!((r - 1.18).abs() < 0.01, "{r}");
        // T* = 0.4: (1 − 0.4^0.94).
        let t = 293.0 + 0.4 * (1800.0 - 293.0);
        let r = s.flow_stress(eps, 0.0, t) / stat;
        assert!((r - (1.0 - 0.4f64.powf(0.94))).abs() < 1e-14);
        assert_eq!(s.flow_stress(eps, 1e3, 1800.0), 0.0);
        // Slower rates soften smoothly, unlike the logarithmic form's
        // clamp: at a tenth of the reference, (1.1)^C.
        let r = s.flow_stress(eps, 5e-5, 293.0) / stat;
        assert!((r - 1.1f64.powf(0.0114)).abs() < 1e-14);
    }

    #[test]
    fn the_return_lands_on_the_surface_at_the_rate() {
        let s = weldox_460e();
        let g = 80.77e9;
        let f = s.factor(2e3, 400.0);
        for (eps_p, q) in [(0.0, 1.0e9), (0.1, 1.5e9), (0.5, 2.5e9)] {
            let d = crate::physics::laws::return_increment(|e| s.curve(f, e), q, g, eps_p);
            let y = s.flow_stress(eps_p + d, 2e3, 400.0);
            assert!(d > 0.0);
            assert!(((q - 3.0 * g * d) - y).abs() <= 1e-12 * y, "{eps_p} {q}");
        }
        assert_eq!(s.initial_yield(), 490e6);
    }
}
