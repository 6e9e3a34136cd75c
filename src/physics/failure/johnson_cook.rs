//! Johnson–Cook damage (Johnson & Cook, Eng. Fract. Mech. 21 (1985) 31):
//! the failure strain
//!
//! `ε_f = (D1 + D2 exp(D3 σ*))(1 + D4 ln ε̇*)(1 + D5 T*)`
//!
//! with the stress triaxiality `σ* = −p / σ_vm`, `ε̇*` the rate over the
//! strength law's reference (rates below it give no change: `ln` of at
//! least 1) and `T*` the homologous temperature. Device twin:
//! `shaders/failure/johnson_cook.wgsl`.

use serde::{Deserialize, Serialize};

use super::{DamageLaw, DEVICE_CONSTANTS, TRIAXIALITY_BOUND};

/// The failure constants of one material, as a scene writes them
/// (`failure = { kind = "johnson_cook", d1, … }`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Failure {
    pub d1: f64,
    pub d2: f64,
    pub d3: f64,
    pub d4: f64,
    pub d5: f64,
}

impl DamageLaw for Failure {
    fn failure_strain(&self, triax: f64, rate_star: f64, t_star: f64) -> f64 {
        let rate = if rate_star > 1.0 {
            1.0 + self.d4 * rate_star.ln()
        } else {
            1.0
        };
        (self.d1 + self.d2 * (self.d3 * triax).exp()) * rate * (1.0 + self.d5 * t_star)
    }

    fn reads_temperature(&self) -> bool {
        self.d5 != 0.0
    }

    fn check(&self) -> Result<(), (&'static str, String)> {
        let Failure { d1, d2, d3, d4, d5 } = *self;
        if let Some(x) = [d1, d2, d3, d4, d5].into_iter().find(|x| !x.is_finite()) {
            return Err(("", format!("must be finite (got {x})")));
        }
        // ε_f is monotonic in the triaxiality, which the solver bounds:
        // positive at both bounds, positive everywhere.
        for t in [-TRIAXIALITY_BOUND, TRIAXIALITY_BOUND] {
            let base = d1 + d2 * (d3 * t).exp();
            if base.is_nan() || base <= 0.0 {
                return Err((
                    "d1",
                    format!(
                        "the failure strain D1 + D2 exp(D3 σ*) is {base} at the triaxiality σ* = {t} (the solver's bound); it must be > 0"
                    ),
                ));
            }
        }
        if d4 < 0.0 {
            return Err((
                "d4",
                format!("must be >= 0 (got {d4}): a negative D4 makes the failure strain non-positive at high rates"),
            ));
        }
        if d5 <= -1.0 {
            return Err((
                "d5",
                format!("must be > -1 (got {d5}): the failure strain would be non-positive at the melt"),
            ));
        }
        Ok(())
    }

    fn device(&self) -> [f32; DEVICE_CONSTANTS] {
        [self.d1, self.d2, self.d3, self.d4, self.d5].map(|d| d as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failure_strain_terms() {
        // 4340 steel (Johnson & Cook 1985, Table 2).
        let f = Failure {
            d1: 0.05,
            d2: 3.44,
            d3: -2.12,
            d4: 0.002,
            d5: 0.61,
        };
        let base = 0.05 + 3.44 * (-2.12f64 / 3.0).exp();
        assert!((f.failure_strain(1.0 / 3.0, 1.0, 0.0) - base).abs() < 1e-15);
        let r = f.failure_strain(1.0 / 3.0, 1e4, 0.0) / base;
        assert!((r - (1.0 + 0.002 * 1e4f64.ln())).abs() < 1e-14);
        let r = f.failure_strain(1.0 / 3.0, 1.0, 0.5) / base;
        assert!((r - 1.305).abs() < 1e-14);
        assert!(f.check().is_ok() && f.reads_temperature());
    }

    /// Constants that make the failure strain non-positive somewhere in the
    /// solver's range are refused, by key.
    #[test]
    fn checks_refuse_a_non_positive_failure_strain() {
        let ok = Failure {
            d1: 0.05,
            d2: 3.44,
            d3: -2.12,
            d4: 0.002,
            d5: 0.0,
        };
        assert!(ok.check().is_ok() && !ok.reads_temperature());
        let key = |f: Failure| f.check().unwrap_err().0;
        assert_eq!(key(Failure { d1: -1.0, ..ok }), "d1");
        assert_eq!(key(Failure { d4: -0.01, ..ok }), "d4");
        assert_eq!(key(Failure { d5: -1.0, ..ok }), "d5");
        assert_eq!(key(Failure { d2: f64::NAN, ..ok }), "");
    }
}
