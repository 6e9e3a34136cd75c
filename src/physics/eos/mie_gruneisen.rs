//! The Mie–Grüneisen equation of state of SPH codes for solids (Libersky
//! et al. 1993; docs/method.md §6): with `μ = ρ/ρ0 − 1` and the linear
//! shock Hugoniot `U_s = c0 + s u_p`,
//!
//! `p = (1 − Γ0 μ/2) p_H(μ) + Γ0 ρ e`, `p_H = a0 μ + b0 μ² + c0' μ³`
//! in compression (`a0 = ρ0 c0²`, `b0 = a0 (1 + 2(s − 1))`,
//! `c0' = a0 (2(s − 1) + 3(s − 1)²)`), `p_H = a0 μ` in tension.
//!
//! Device twin: `shaders/eos/mie_gruneisen.wgsl`.

use serde::{Deserialize, Serialize};

use super::{PressureLaw, DEVICE_CONSTANTS};
use crate::physics::laws::{non_negative, positive};

/// The constants, as a scene writes them
/// (`eos = { kind = "mie_gruneisen", c0, s, gamma0 }`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Eos {
    /// The bulk sound speed, m/s.
    pub c0: f64,
    /// The Hugoniot slope `s`.
    pub s: f64,
    /// The Grüneisen coefficient Γ0.
    pub gamma0: f64,
}

impl Eos {
    /// The Hugoniot's cubic in compression (`p_H` above) and its slope
    /// `dp_H/dμ`.
    #[inline]
    fn hugoniot(&self, a0: f64, mu: f64) -> (f64, f64) {
        let sm = self.s - 1.0;
        let b0 = a0 * (1.0 + 2.0 * sm);
        let c0p = a0 * (2.0 * sm + 3.0 * sm * sm);
        (
            mu * (a0 + mu * (b0 + mu * c0p)),
            a0 + mu * (2.0 * b0 + 3.0 * mu * c0p),
        )
    }
}

impl PressureLaw for Eos {
    fn c0(&self) -> f64 {
        self.c0
    }

    #[inline]
    fn pressure(&self, k: f64, rho0: f64, rho: f64, e: f64) -> f64 {
        let mu = rho / rho0 - 1.0;
        let ph = if mu > 0.0 {
            self.hugoniot(k, mu).0
        } else {
            k * mu
        };
        (1.0 - 0.5 * self.gamma0 * mu) * ph + self.gamma0 * rho * e.max(0.0)
    }

    #[inline]
    fn dp_drho(&self, k: f64, rho0: f64, mu: f64, e: f64) -> f64 {
        let dpdrho = k / rho0;
        if mu <= 0.0 {
            return dpdrho;
        }
        let (ph, dph) = self.hugoniot(k, mu);
        let d = ((1.0 - 0.5 * self.gamma0 * mu) * dph - 0.5 * self.gamma0 * ph) / rho0
            + self.gamma0 * e.max(0.0);
        dpdrho.max(d)
    }

    /// The root near 0 of `(1 − Γμ/2) K μ + Γ ρ0 (1 + μ) e = 0` (the
    /// tension branch), with `e` taken as at least 0 so that it is never
    /// above 0: `−½ΓK μ² + (K + Γρ0e) μ + Γρ0e = 0`, written to keep its
    /// digits, `μ = −2c / (b + sqrt(b² − 4ac))`.
    fn zero_pressure_mu(&self, k: f64, rho0: f64, e: f64) -> f64 {
        let g = self.gamma0;
        if g == 0.0 {
            return 0.0;
        }
        let ge = g * rho0 * e.max(0.0);
        let b = k + ge;
        -2.0 * ge / (b + (b * b + 2.0 * g * k * ge).sqrt())
    }

    fn gruneisen(&self) -> f64 {
        self.gamma0
    }

    fn check(&self) -> Result<(), (&'static str, String)> {
        positive("c0", self.c0)?;
        if !self.s.is_finite() {
            return Err(("s", format!("must be finite (got {})", self.s)));
        }
        non_negative("gamma0", self.gamma0)
    }

    fn device(&self) -> [f32; DEVICE_CONSTANTS] {
        [self.s as f32, self.gamma0 as f32]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Steel as docs/method.md §6 lists it.
    const STEEL: Eos = Eos {
        c0: 4580.0,
        s: 1.49,
        gamma0: 2.02,
    };
    const RHO0: f64 = 7850.0;

    /// The formula above, written out once more at hand-picked states.
    #[test]
    fn pressure_is_the_formula() {
        let k = RHO0 * STEEL.c0 * STEEL.c0;
        for (mu, e) in [(0.05, 2e4), (0.2, 3e5), (-0.03, 1e4), (0.1, -5e5)] {
            let rho = RHO0 * (1.0 + mu);
            let sm: f64 = 0.49;
            let ph = if mu > 0.0 {
                k * mu + k * (1.0 + 2.0 * sm) * mu * mu + k * (2.0 * sm + 3.0 * sm * sm) * mu.powi(3)
            } else {
                k * mu
            };
            let want = (1.0 - 1.01 * mu) * ph + 2.02 * rho * f64::max(e, 0.0);
            let got = STEEL.pressure(k, RHO0, rho, e);
            assert!((got - want).abs() <= 1e-12 * want.abs(), "{mu} {e}: {got} against {want}");
        }
    }

    /// `dp/dρ` is the pressure's slope (central differences) in
    /// compression, and `K/ρ0` in tension.
    #[test]
    fn dp_drho_is_the_slope() {
        let k = RHO0 * STEEL.c0 * STEEL.c0;
        for (mu, e) in [(0.02, 1e5), (0.15, 4e5)] {
            let rho = RHO0 * (1.0 + mu);
            let d = 1e-6 * RHO0;
            let fd = (STEEL.pressure(k, RHO0, rho + d, e) - STEEL.pressure(k, RHO0, rho - d, e))
                / (2.0 * d);
            // The thermal part Γ ρ e adds Γ e to the slope.
            let got = STEEL.dp_drho(k, RHO0, mu, e);
            assert!((got / fd - 1.0).abs() < 1e-6, "{mu}: {got} against {fd}");
        }
        assert_eq!(STEEL.dp_drho(k, RHO0, -0.05, 1e5), k / RHO0);
    }

    /// The pressure vanishes at the zero-pressure compression.
    #[test]
    fn zero_pressure_mu_is_a_root() {
        let k = RHO0 * STEEL.c0 * STEEL.c0;
        assert_eq!(STEEL.zero_pressure_mu(k, RHO0, 0.0), 0.0);
        for e in [1e3, 1e5, 2e6] {
            let mu = STEEL.zero_pressure_mu(k, RHO0, e);
            assert!(mu < 0.0);
            let p = STEEL.pressure(k, RHO0, RHO0 * (1.0 + mu), e);
            assert!(p.abs() < 1e-9 * k, "{e}: p = {p}");
        }
    }
}
