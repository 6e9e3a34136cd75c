//! Zerilli–Armstrong strength (Zerilli & Armstrong, J. Appl. Phys. 61
//! (1987) 1816), from the thermal activation of dislocation motion: in a
//! face-centred cubic metal (copper) the activation area falls with the
//! plastic strain, so the thermal term multiplies the hardening; in a
//! body-centred cubic one (iron, tantalum) it does not, and the hardening
//! adds. Both forms in one:
//!
//! `σ_y = C0 + (C1 + C2 ε_p^½) exp(−C3 T + C4 T ln ε̇) + C5 ε_pⁿ`
//!
//! (FCC: C1 = C5 = 0; BCC: C2 = 0), with `T` the absolute temperature in K
//! and `ε̇` in 1/s, floored at `minimum_strain_rate` so that the logarithm
//! stays finite at rest. `C0` gathers the athermal stress and the grain
//! size's `k l^−½`. The law names no melt; a damage law's homologous
//! temperature reads `melt_temperature` where one is given. Device twin:
//! `shaders/laws/zerilli_armstrong.wgsl`.

use serde::{Deserialize, Serialize};

use super::{non_negative, positive, temperatures, Law, DEVICE_CONSTANTS};

/// The constants, as a scene writes them
/// (`strength = { kind = "zerilli_armstrong", c0, c2, c3, c4, … }`):
/// stresses in Pa, `C3` and `C4` in 1/K, temperatures in K.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Strength {
    /// Athermal stress and grain-size term, Pa.
    pub c0: f64,
    /// Thermal stress of the BCC form, Pa (default 0).
    #[serde(default)]
    pub c1: f64,
    /// Thermal hardening of the FCC form, Pa (default 0).
    #[serde(default)]
    pub c2: f64,
    /// Thermal softening, 1/K.
    pub c3: f64,
    /// Rate sensitivity, 1/K.
    pub c4: f64,
    /// Athermal hardening of the BCC form, Pa (default 0).
    #[serde(default)]
    pub c5: f64,
    /// Exponent of the BCC hardening (required with `c5`).
    #[serde(default)]
    pub n: f64,
    /// The temperature a particle starts at, K.
    pub room_temperature: f64,
    /// The melt temperature, K, for a damage law's `T*` only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub melt_temperature: Option<f64>,
    /// The rate below which the rate term is held, 1/s.
    #[serde(default = "default_minimum_strain_rate")]
    pub minimum_strain_rate: f64,
}

/// A quasi-static test's rate, 1/s.
pub const DEFAULT_MINIMUM_STRAIN_RATE: f64 = 1e-3;

fn default_minimum_strain_rate() -> f64 {
    DEFAULT_MINIMUM_STRAIN_RATE
}

impl Law for Strength {
    /// `exp(−C3 T + C4 T ln ε̇)`.
    fn factor(&self, rate: f64, temperature: f64) -> f64 {
        let ln_rate = rate.max(self.minimum_strain_rate).ln();
        (temperature * (self.c4 * ln_rate - self.c3)).exp()
    }

    /// `C0 + (C1 + C2 ε_p^½) factor + C5 ε_pⁿ`.
    fn curve(&self, factor: f64, eps_p: f64) -> (f64, f64) {
        let base = self.c0 + self.c1 * factor;
        if eps_p <= 0.0 {
            let slope = if self.c2 * factor > 0.0 || (self.c5 > 0.0 && self.n < 1.0) {
                f64::INFINITY
            } else if self.n == 1.0 {
                self.c5
            } else {
                0.0
            };
            return (base, slope);
        }
        let root = eps_p.sqrt();
        let mut s = base + self.c2 * factor * root;
        let mut slope = 0.5 * self.c2 * factor / root;
        if self.c5 != 0.0 {
            let pow = eps_p.powf(self.n);
            s += self.c5 * pow;
            slope += self.c5 * self.n * pow / eps_p;
        }
        (s, slope)
    }

    fn room_temperature(&self) -> f64 {
        self.room_temperature
    }

    fn melt_temperature(&self) -> Option<f64> {
        self.melt_temperature
    }

    /// The law's `ε̇` is in 1/s.
    fn reference_strain_rate(&self) -> f64 {
        1.0
    }

    fn rate_dependent(&self) -> bool {
        self.c4 != 0.0 && (self.c1 != 0.0 || self.c2 != 0.0)
    }

    fn check(&self) -> Result<(), (&'static str, String)> {
        for (key, v) in [
            ("c0", self.c0),
            ("c1", self.c1),
            ("c2", self.c2),
            ("c3", self.c3),
            ("c4", self.c4),
            ("c5", self.c5),
            ("n", self.n),
        ] {
            non_negative(key, v)?;
        }
        if self.c0 + self.c1 <= 0.0 {
            return Err((
                "c0",
                "c0 + c1 must be > 0: the virgin material needs a yield stress".into(),
            ));
        }
        if self.c5 > 0.0 {
            positive("n", self.n)?;
        }
        positive("minimum_strain_rate", self.minimum_strain_rate)?;
        temperatures(self.room_temperature, self.melt_temperature)
    }

    /// C0, C1, C2, C3, C4, C5, n, the rate floor
    /// (shaders/laws/zerilli_armstrong.wgsl).
    fn device(&self) -> [f32; DEVICE_CONSTANTS] {
        [
            self.c0,
            self.c1,
            self.c2,
            self.c3,
            self.c4,
            self.c5,
            self.n,
            self.minimum_strain_rate,
        ]
        .map(|k| k as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// OFHC copper, the FCC form (Zerilli & Armstrong 1987).
    fn copper() -> Strength {
        Strength {
            c0: 65e6,
            c1: 0.0,
            c2: 890e6,
            c3: 0.0028,
            c4: 0.000115,
            c5: 0.0,
            n: 0.0,
            room_temperature: 294.0,
            melt_temperature: None,
            minimum_strain_rate: DEFAULT_MINIMUM_STRAIN_RATE,
        }
    }

    /// Armco iron, the BCC form (Zerilli & Armstrong 1987).
    fn iron() -> Strength {
        Strength {
            c0: 70e6,
            c1: 1033e6,
            c2: 0.0,
            c3: 0.00698,
            c4: 0.000415,
            c5: 266e6,
            n: 0.289,
            ..copper()
        }
    }

    /// The two forms against the formula written out, at strains, rates
    /// and temperatures across a Taylor test's.
    #[test]
    fn flow_stress_is_the_formula() {
        for (law, fcc) in [(copper(), true), (iron(), false)] {
            for eps in [0.0, 0.01, 0.1, 0.5, 2.0] {
                for rate in [1e-2, 1.0, 1e3, 1e5] {
                    for t in [77.0, 294.0, 600.0] {
                        let th = (-law.c3 * t + law.c4 * t * f64::ln(rate)).exp();
                        let want = if fcc {
                            65e6 + 890e6 * f64::sqrt(eps) * th
                        } else {
                            70e6 + 1033e6 * th + 266e6 * f64::powf(eps, 0.289)
                        };
                        let got = law.flow_stress(eps, rate, t);
                        assert!(
                            (got - want).abs() <= 1e-14 * want,
                            "{fcc} {eps} {rate} {t}: {got} vs {want}"
                        );
                    }
                }
            }
        }
    }

    /// Copper's thermal term multiplies its hardening: the stress above
    /// C0 scales with ε̇^(C4 T); iron's hardening is athermal: its yield
    /// at zero strain carries all the rate sensitivity.
    #[test]
    fn the_rate_acts_where_each_form_puts_it() {
        let cu = copper();
        let ratio = (cu.flow_stress(0.3, 1e4, 294.0) - 65e6) / (cu.flow_stress(0.3, 1.0, 294.0) - 65e6);
        assert!((ratio - 1e4f64.powf(0.000115 * 294.0)).abs() < 1e-13);
        assert_eq!(cu.flow_stress(0.0, 1e4, 294.0), 65e6);
        let fe = iron();
        let hard = |law: &Strength, rate| law.flow_stress(0.3, rate, 294.0) - law.flow_stress(0.0, rate, 294.0);
        assert!((hard(&fe, 1e4) - hard(&fe, 1.0)).abs() < 1e-6);
        // Below the floor, the floor's rate.
        assert_eq!(cu.factor(1e-9, 294.0), cu.factor(1e-3, 294.0));
        assert_eq!(cu.factor(0.0, 294.0), cu.factor(1e-3, 294.0));
    }

    /// The slope is the curve's derivative (central differences), and the
    /// return lands on the surface.
    #[test]
    fn slope_and_return() {
        let g = 46e9;
        for law in [copper(), iron()] {
            let f = law.factor(2e3, 350.0);
            for eps in [0.01, 0.2, 1.0] {
                let h = 1e-6 * eps;
                let fd = (law.curve(f, eps + h).0 - law.curve(f, eps - h).0) / (2.0 * h);
                let (_, slope) = law.curve(f, eps);
                assert!((fd - slope).abs() <= 1e-6 * slope, "{eps}: {fd} vs {slope}");
            }
            for (eps, q) in [(0.0, 0.6e9), (0.2, 0.9e9), (1.0, 1.5e9)] {
                let d = crate::physics::laws::return_increment(|e| law.curve(f, e), q, g, eps);
                let y = law.curve(f, eps + d).0;
                assert!(d > 0.0);
                assert!(((q - 3.0 * g * d) - y).abs() <= 1e-12 * y, "{eps} {q}");
            }
            assert_eq!(
                crate::physics::laws::return_increment(|e| law.curve(f, e), 50e6, g, 0.0),
                0.0
            );
        }
    }

    #[test]
    fn checks_name_the_key() {
        assert!(copper().check().is_ok() && iron().check().is_ok());
        let bad = Strength { c2: -1.0, ..copper() };
        assert_eq!(bad.check().unwrap_err().0, "c2");
        let bad = Strength { n: 0.0, ..iron() };
        assert_eq!(bad.check().unwrap_err().0, "n");
        let bad = Strength { c0: 0.0, ..copper() };
        assert_eq!(bad.check().unwrap_err().0, "c0");
        let bad = Strength { melt_temperature: Some(200.0), ..copper() };
        assert_eq!(bad.check().unwrap_err().0, "melt_temperature");
        let bad = Strength { minimum_strain_rate: 0.0, ..copper() };
        assert_eq!(bad.check().unwrap_err().0, "minimum_strain_rate");
    }
}
