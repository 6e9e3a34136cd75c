//! Johnson–Cook strength (Johnson & Cook, 1983): the flow stress
//! `σ_y = (A + B ε_pⁿ)(1 + C ln ε̇*)(1 − T*ᵐ)`, with `ε̇* = ε̇_p / ε̇_0`
//! (rates below the reference give no softening: `ln` of at least 1) and
//! the homologous temperature `T* = (T − T_room)/(T_melt − T_room)`,
//! clamped to [0, 1].
//!
//! The law is registered in [`super`] as `kind = "johnson_cook"`; its
//! device twin is `shaders/laws/johnson_cook.wgsl`. Johnson and Cook's
//! damage law is [`crate::physics::failure::johnson_cook`].

use serde::{Deserialize, Serialize};

use super::{non_negative, positive, temperatures, Law, DEVICE_CONSTANTS};

/// The strength constants of one material, as a scene writes them
/// (`strength = { kind = "johnson_cook", a, b, … }`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Strength {
    /// Yield stress at zero plastic strain, Pa.
    pub a: f64,
    /// Hardening modulus, Pa.
    pub b: f64,
    /// Hardening exponent.
    pub n: f64,
    /// Strain-rate coefficient.
    pub c: f64,
    /// Thermal softening exponent.
    pub m: f64,
    /// Reference plastic strain rate ε̇_0, 1/s.
    pub reference_strain_rate: f64,
    /// Room and melt temperatures, K.
    pub room_temperature: f64,
    pub melt_temperature: f64,
}

impl Strength {
    /// `(1 + C ln ε̇*)`, rates below the reference counting as the reference.
    pub fn rate_factor(&self, strain_rate: f64) -> f64 {
        let star = strain_rate / self.reference_strain_rate;
        if star > 1.0 {
            1.0 + self.c * star.ln()
        } else {
            1.0
        }
    }

    /// The homologous temperature `T*`, clamped to [0, 1].
    pub fn homologous(&self, temperature: f64) -> f64 {
        super::homologous(
            self.room_temperature,
            Some(self.melt_temperature),
            temperature,
        )
    }

    /// `(1 − T*ᵐ)`: 1 at or below room temperature, 0 at the melt.
    pub fn thermal_factor(&self, temperature: f64) -> f64 {
        let t = self.homologous(temperature);
        if t <= 0.0 {
            1.0
        } else {
            1.0 - t.powf(self.m)
        }
    }

    /// The static hardening curve `A + B ε_pⁿ` and its slope.
    pub(crate) fn hardening(&self, eps_p: f64) -> (f64, f64) {
        if eps_p <= 0.0 {
            // The slope is infinite at zero strain for n < 1; the return
            // brackets its root, so it never divides by it.
            let slope = if self.n < 1.0 {
                f64::INFINITY
            } else if self.n == 1.0 {
                self.b
            } else {
                0.0
            };
            return (self.a, slope);
        }
        let pow = eps_p.powf(self.n);
        (self.a + self.b * pow, self.b * self.n * pow / eps_p)
    }

    /// The rules shared with the multiplicative form
    /// ([`super::modified_johnson_cook`]).
    pub(crate) fn check_constants(&self) -> Result<(), (&'static str, String)> {
        positive("a", self.a)?;
        non_negative("b", self.b)?;
        positive("n", self.n)?;
        non_negative("c", self.c)?;
        positive("m", self.m)?;
        positive("reference_strain_rate", self.reference_strain_rate)?;
        temperatures(self.room_temperature, Some(self.melt_temperature))
    }

    /// A, B, n, C, m, ε̇0 (shaders/laws/johnson_cook.wgsl).
    pub(crate) fn constants(&self) -> [f32; DEVICE_CONSTANTS] {
        let k = [self.a, self.b, self.n, self.c, self.m, self.reference_strain_rate];
        let mut out = [0.0; DEVICE_CONSTANTS];
        for (o, k) in out.iter_mut().zip(k) {
            *o = k as f32;
        }
        out
    }
}

impl Law for Strength {
    /// `(1 + C ln ε̇*)(1 − T*ᵐ)`.
    fn factor(&self, rate: f64, temperature: f64) -> f64 {
        self.rate_factor(rate) * self.thermal_factor(temperature)
    }

    /// `factor (A + B ε_pⁿ)`.
    fn curve(&self, factor: f64, eps_p: f64) -> (f64, f64) {
        let (s, slope) = self.hardening(eps_p);
        (factor * s, factor * slope)
    }

    fn room_temperature(&self) -> f64 {
        self.room_temperature
    }

    fn melt_temperature(&self) -> Option<f64> {
        Some(self.melt_temperature)
    }

    fn reference_strain_rate(&self) -> f64 {
        self.reference_strain_rate
    }

    fn rate_dependent(&self) -> bool {
        self.c != 0.0
    }

    fn check(&self) -> Result<(), (&'static str, String)> {
        self.check_constants()
    }

    fn device(&self) -> [f32; DEVICE_CONSTANTS] {
        self.constants()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 4340 steel (Johnson & Cook 1985, Table 1).
    fn steel_4340() -> Strength {
        Strength {
            a: 792e6,
            b: 510e6,
            n: 0.26,
            c: 0.014,
            m: 1.03,
            reference_strain_rate: 1.0,
            room_temperature: 294.0,
            melt_temperature: 1793.0,
        }
    }

    #[test]
    fn flow_stress_terms_each_alone() {
        let s = steel_4340();
        // Static, at room temperature: A + B eps^n.
        let eps: f64 = 0.1;
        let want = 792e6 + 510e6 * eps.powf(0.26);
        assert!((s.flow_stress(eps, 1.0, 294.0) - want).abs() <= 1e-12 * want);
        // The rate term alone: 1 + C ln(1e3).
        let r = s.flow_stress(eps, 1e3, 294.0) / want;
        assert!((r - (1.0 + 0.014 * 1e3f64.ln())).abs() < 1e-14);
        // Slower than the reference: no softening.
        assert_eq!(
            s.flow_stress(eps, 1e-3, 294.0),
            s.flow_stress(eps, 1.0, 294.0)
        );
        // The temperature term alone: T* = 0.5.
        let t = 294.0 + 0.5 * (1793.0 - 294.0);
        let r = s.flow_stress(eps, 1.0, t) / want;
        assert!((r - (1.0 - 0.5f64.powf(1.03))).abs() < 1e-14);
        // Melted: no strength; below room temperature: none gained.
        assert_eq!(s.flow_stress(eps, 1.0, 2000.0), 0.0);
        assert_eq!(
            s.flow_stress(eps, 1.0, 200.0),
            s.flow_stress(eps, 1.0, 294.0)
        );
    }

    #[test]
    fn the_return_lands_on_the_hardened_surface() {
        let s = steel_4340();
        let g = 77.5e9;
        let ret = |q, eps| crate::physics::laws::return_increment(|e| s.curve(1.0, e), q, g, eps);
        for (eps_p, q_trial) in [(0.0, 1.2e9), (0.0, 792.5e6), (0.05, 2.0e9), (0.3, 1.5e9)] {
            let d = ret(q_trial, eps_p);
            let q = q_trial - 3.0 * g * d;
            let y = s.flow_stress(eps_p + d, 1.0, 294.0);
            assert!(d > 0.0, "{eps_p} {q_trial}: yields");
            assert!((q - y).abs() <= 1e-12 * y, "{eps_p} {q_trial}: {q} vs {y}");
        }
        // Inside the surface: elastic.
        assert_eq!(ret(700e6, 0.0), 0.0);
        assert_eq!(ret(0.9e9, 0.2), 0.0);
    }
}
