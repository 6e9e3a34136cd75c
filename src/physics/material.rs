//! Material model (docs/method.md §6): the equation of state
//! ([`crate::physics::eos`]), derived elastic constants, sound speeds and
//! impedances. A scene's material
//! becomes one through `MaterialModel::new` (src/scene/model.rs), so that
//! this module knows nothing of the scene format.

use crate::math::Sym;
use crate::physics::eos::Eos;
use crate::physics::failure::FailureLaw;
use crate::physics::laws::StrengthLaw;

/// A material with every derived constant the solver needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialModel {
    pub rho0: f64,
    /// The bulk sound speed at ρ0 (the equation of state's `c0`).
    pub c0: f64,
    /// The equation of state.
    pub eos: Eos,
    /// Shear modulus G (0: no deviatoric stress).
    pub g: f64,
    /// Yield stress Y0 (infinite: elastic).
    pub y0: f64,
    /// Bulk modulus `K = ρ0 c0²`.
    pub k: f64,
    /// Young's modulus `E = 9KG/(3K+G)`; for a strengthless material, `K`.
    pub e: f64,
    /// Poisson's ratio.
    pub nu: f64,
    /// Longitudinal (P-wave) speed at ρ0, `sqrt((K + 4G/3)/ρ0)`.
    pub c_l: f64,
    /// Acoustic impedance `Z = ρ0 c_L` (docs/method.md §8.3, eq. 24).
    pub z: f64,
    /// Constrained modulus `M = K + 4G/3 = ρ0 c_L²`.
    pub m: f64,
    /// A strength law (then `y0` is its initial yield stress,
    /// [`crate::physics::laws::Law::initial_yield`]); `None`: perfect
    /// plasticity at `y0`, or elastic.
    pub strength: Option<StrengthLaw>,
    /// A damage law ([`crate::physics::failure`]).
    pub failure: Option<FailureLaw>,
    /// The tensile pressure at which a particle fails, Pa (infinite: none).
    pub spall: f64,
    /// The tensile pressure past which a particle opens a void without
    /// failing ([`crate::physics::strength::void_state`]), Pa (infinite:
    /// none).
    pub cavitation: f64,
    /// Specific heat, J/(kg K) (0 when no strength law needs it).
    pub specific_heat: f64,
    /// Taylor–Quinney fraction of the plastic work that heats.
    pub taylor_quinney: f64,
}

impl MaterialModel {
    /// Whether a particle of this material carries a plastic history
    /// ([`crate::physics::strength::History`]): a strength law with
    /// hardening, or a failure model.
    pub fn has_history(&self) -> bool {
        self.strength.is_some() || self.can_fail() || self.cavitation.is_finite()
    }

    /// Whether a particle of the material can fail: it has a damage law or
    /// a spall pressure. Both read the pressure (the damage law through
    /// the triaxiality), so the stress update asks for it only then.
    #[inline]
    pub fn can_fail(&self) -> bool {
        self.failure.is_some() || self.spall.is_finite()
    }

    /// The room temperature a particle starts at (0 without a strength law,
    /// which has no use for it).
    pub fn initial_temperature(&self) -> f64 {
        self.strength.map_or(0.0, |law| law.room_temperature())
    }

    /// The sound speed of a particle with damage `damage`: a failed one has
    /// no shear stiffness, so its speed is the bulk one (which stays bounded
    /// as an opening crack takes its density towards zero).
    #[inline]
    pub fn sound_speed_of(&self, rho: f64, e: f64, damage: f64) -> f64 {
        let g = if failed(damage) { 0.0 } else { self.g };
        self.speed_with_shear(rho, e, g)
    }

    /// The pressure of a particle with damage `damage`: a failed one
    /// ([`crate::physics::strength::FAILED`]) carries no tension.
    #[inline]
    pub fn pressure_of(&self, rho: f64, e: f64, damage: f64) -> f64 {
        let p = self.pressure(rho, e);
        if failed(damage) {
            p.max(0.0)
        } else {
            p
        }
    }

    /// The density at or above which a failed particle with specific
    /// internal energy `e` stays: the density at which its pressure
    /// vanishes ([`crate::physics::eos::PressureLaw::zero_pressure_mu`]:
    /// ρ0 for the linear EOS, never above ρ0). A failed particle
    /// carries no tension, so below it the material would do nothing but
    /// dilate, and its volume `m/ρ` would grow in its neighbours' sums
    /// without bound: an opening crack is void, not stretched metal.
    pub fn failed_density_floor(&self, e: f64) -> f64 {
        self.rho0 * (1.0 + self.eos.zero_pressure_mu(self.k, self.rho0, e))
    }

    /// Pressure `p(ρ, e)` (docs/method.md §6), compression positive.
    #[inline]
    pub fn pressure(&self, rho: f64, e: f64) -> f64 {
        self.eos.pressure(self.k, self.rho0, rho, e)
    }

    /// Longitudinal sound speed at the current state, for the time step and
    /// the artificial viscosity: `sqrt((ρ ∂p/∂ρ + 4G/3)/ρ)` with the bulk part
    /// never below its reference value `K`, so it equals `c_L` at ρ0.
    #[inline]
    pub fn sound_speed(&self, rho: f64, e: f64) -> f64 {
        self.speed_with_shear(rho, e, self.g)
    }

    /// [`MaterialModel::sound_speed`] with shear modulus `g`.
    #[inline]
    fn speed_with_shear(&self, rho: f64, e: f64, g: f64) -> f64 {
        let mu = rho / self.rho0 - 1.0;
        let dpdrho = self.eos.dp_drho(self.k, self.rho0, mu, e);
        ((rho * dpdrho + 4.0 * g / 3.0) / rho).sqrt()
    }
}

/// The CFL step of one particle (docs/method.md §9): `C h / (c + |v|)`.
#[inline]
pub fn cfl_step(cfl: f64, h: f64, c: f64, speed: f64) -> f64 {
    cfl * h / (c + speed)
}

/// Interface impedance `Z* = Z_i Z_j/(Z_i + Z_j)` (eq. 24); a rigid partner
/// (infinite impedance) gives `Z_i`.
#[inline]
pub fn series(a: f64, b: f64) -> f64 {
    if a.is_infinite() {
        return b;
    }
    if b.is_infinite() {
        return a;
    }
    a * b / (a + b)
}

/// The Cauchy stress `σ = −p I + s` (in plane; `zz` = `−p + s_zz`).
#[inline]
pub fn cauchy(p: f64, s: &Sym) -> Sym {
    Sym {
        xx: s.xx - p,
        yy: s.yy - p,
        xy: s.xy,
        zz: s.zz - p,
    }
}

/// A failed particle's damage.
pub const FAILED: f64 = 1.0;

/// Whether a particle with damage `damage` has failed.
#[inline]
pub fn failed(damage: f64) -> bool {
    damage >= FAILED
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Eos, Material};

    /// The Hugoniot slope of [`steel`].
    const STEEL_S: f64 = 1.49;

    pub fn steel() -> Material {
        Material {
            shear_modulus: Some(77e9),
            yield_stress: Some(600e6),
            ..Material::basic(7850.0, Eos::mie_gruneisen(4580.0, STEEL_S, 2.02))
        }
    }

    /// A failed particle's density floor is where its pressure vanishes:
    /// ρ0 cold, below it as heat adds thermal pressure, ρ0 for the linear
    /// EOS.
    #[test]
    fn failed_density_floor_is_the_zero_pressure_density() {
        let s = MaterialModel::new(&steel());
        assert_eq!(s.failed_density_floor(0.0), s.rho0);
        assert_eq!(s.failed_density_floor(-1e4), s.rho0);
        let mut last = s.rho0;
        for e in [1e3, 1e5, 5e5, 2e6] {
            let rho = s.failed_density_floor(e);
            assert!(rho < last, "{e}: {rho}");
            assert!(
                s.pressure(rho, e).abs() < 1e-9 * s.k,
                "{e}: p = {}",
                s.pressure(rho, e)
            );
            last = rho;
        }
        let lin = MaterialModel::new(&Material::basic(7850.0, Eos::linear(4580.0)));
        assert_eq!(lin.failed_density_floor(1e5), 7850.0);
    }

    /// The derived constants docs/method.md §6 lists for steel and aluminium.
    #[test]
    fn derived_constants() {
        let s = MaterialModel::new(&steel());
        assert!((s.k / 164.66e9 - 1.0).abs() < 1e-4);
        assert!((s.e / 199.8e9 - 1.0).abs() < 1e-3);
        assert!((s.nu - 0.298).abs() < 1e-3);
        assert!((s.c_l / 5835.7 - 1.0).abs() < 1e-4);
        assert!((s.z / 4.581e7 - 1.0).abs() < 1e-3);
        let a = MaterialModel::new(&Material {
            shear_modulus: Some(25e9),
            yield_stress: Some(550e6),
            ..Material::basic(2790.0, Eos::mie_gruneisen(5330.0, 1.34, 2.0))
        });
        assert!((a.k / 79.26e9 - 1.0).abs() < 1e-3);
        assert!((a.e / 67.9e9 - 1.0).abs() < 1e-3);
        assert!((a.nu - 0.357).abs() < 1e-3);
        assert!((a.c_l / 6352.7 - 1.0).abs() < 1e-4);
        assert!((a.z / 1.772e7 - 1.0).abs() < 1e-3);
    }

    /// A failed particle carries no tension and has the bulk sound speed;
    /// an intact one is unchanged.
    #[test]
    fn a_failed_particle_has_no_tension_and_no_shear_stiffness() {
        let s = MaterialModel::new(&steel());
        let stretched = 0.9 * s.rho0;
        assert!(s.pressure_of(stretched, 0.0, 0.0) < 0.0);
        assert_eq!(
            s.pressure_of(stretched, 0.0, 0.0),
            s.pressure(stretched, 0.0)
        );
        assert_eq!(s.pressure_of(stretched, 0.0, 1.0), 0.0);
        let squeezed = 1.1 * s.rho0;
        assert_eq!(s.pressure_of(squeezed, 0.0, 1.0), s.pressure(squeezed, 0.0));
        assert_eq!(s.sound_speed_of(s.rho0, 0.0, 0.5), s.c_l);
        assert!((s.sound_speed_of(s.rho0, 0.0, 1.0) / s.c0 - 1.0).abs() < 1e-12);
    }

    /// p(ρ0, 0) = 0; the slope at ρ0 is c0²; the sound speed at ρ0 is c_L.
    #[test]
    fn eos_reference_state() {
        let s = MaterialModel::new(&steel());
        assert_eq!(s.pressure(s.rho0, 0.0), 0.0);
        let d = 1e-3 * s.rho0;
        let slope = (s.pressure(s.rho0 + d, 0.0) - s.pressure(s.rho0 - d, 0.0)) / (2.0 * d);
        assert!((slope / (s.c0 * s.c0) - 1.0).abs() < 1e-3);
        assert!((s.sound_speed(s.rho0, 0.0) / s.c_l - 1.0).abs() < 1e-12);
        assert!(
            s.pressure(1.1 * s.rho0, 0.0) > s.k * 0.1,
            "Hugoniot stiffens"
        );
    }

    /// On the shock Hugoniot of `U_s = c0 + s u_p` the pressure is
    /// `ρ0 c0² μ(1 + μ)/(1 − (s − 1)μ)²` at the Rankine–Hugoniot energy
    /// `e_H = p_H μ / (2ρ0(1 + μ))`; the SPH form's cubic is that
    /// expansion to third order in μ, so the two differ by `O(μ⁴)`.
    #[test]
    fn eos_lies_on_the_hugoniot() {
        let s = MaterialModel::new(&steel());
        for mu in [0.005, 0.02, 0.05, 0.1] {
            let exact =
                s.rho0 * s.c0 * s.c0 * mu * (1.0 + mu) / (1.0 - (STEEL_S - 1.0) * mu).powi(2);
            let e_h = exact * mu / (2.0 * s.rho0 * (1.0 + mu));
            let p = s.pressure(s.rho0 * (1.0 + mu), e_h);
            // The remainder starts at a0 (4(s−1)³ + 3(s−1)²) μ⁴: under
            // 2 a0 μ⁴ for s − 1 < 0.5 and μ ≤ 0.1.
            let bound = 2.0 * s.k * mu.powi(4) + 1e-12 * exact;
            assert!((p - exact).abs() < bound, "mu {mu}: {p} against {exact}");
        }
    }

    /// A negative internal energy (a numerical deficit: no adiabatic path
    /// from the reference lowers it) adds no tension and no softening.
    #[test]
    fn negative_energy_adds_no_thermal_tension() {
        let s = MaterialModel::new(&steel());
        for rho in [0.8 * s.rho0, s.rho0, 1.3 * s.rho0] {
            assert_eq!(s.pressure(rho, -4e8), s.pressure(rho, 0.0));
            assert_eq!(s.sound_speed(rho, -4e8), s.sound_speed(rho, 0.0));
            assert!(s.pressure(rho, 1e5) > s.pressure(rho, 0.0));
        }
    }
}
