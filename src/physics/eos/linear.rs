//! The linear equation of state `p = ρ0 c0² (ρ/ρ0 − 1)`: no Hugoniot
//! curvature and no thermal part, the paper's elastic bodies' (docs/method.md
//! §6). Device twin: `shaders/eos/linear.wgsl`.

use serde::{Deserialize, Serialize};

use super::{PressureLaw, DEVICE_CONSTANTS};
use crate::physics::laws::positive;

/// The constant, as a scene writes it (`eos = { kind = "linear", c0 }`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Eos {
    /// The bulk sound speed, m/s.
    pub c0: f64,
}

impl PressureLaw for Eos {
    fn c0(&self) -> f64 {
        self.c0
    }

    #[inline]
    fn pressure(&self, k: f64, rho0: f64, rho: f64, _e: f64) -> f64 {
        k * (rho / rho0 - 1.0)
    }

    #[inline]
    fn dp_drho(&self, k: f64, rho0: f64, _mu: f64, _e: f64) -> f64 {
        k / rho0
    }

    fn zero_pressure_mu(&self, _k: f64, _rho0: f64, _e: f64) -> f64 {
        0.0
    }

    fn gruneisen(&self) -> f64 {
        0.0
    }

    fn check(&self) -> Result<(), (&'static str, String)> {
        positive("c0", self.c0)
    }

    fn device(&self) -> [f32; DEVICE_CONSTANTS] {
        [0.0; DEVICE_CONSTANTS]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `p = K μ` at any energy; the slope is `K/ρ0`; the pressure
    /// vanishes at ρ0.
    #[test]
    fn pressure_is_linear_in_the_density() {
        let (c0, rho0) = (4580.0, 7850.0);
        let eos = Eos { c0 };
        let k = rho0 * c0 * c0;
        for (mu, e) in [(0.1, 0.0), (-0.05, 1e6), (0.3, -1e5)] {
            let p = eos.pressure(k, rho0, rho0 * (1.0 + mu), e);
            assert!((p - k * mu).abs() <= 1e-12 * k * mu.abs(), "{mu}: {p}");
            assert_eq!(eos.dp_drho(k, rho0, mu, e), k / rho0);
        }
        assert_eq!(eos.zero_pressure_mu(k, rho0, 1e5), 0.0);
    }
}
