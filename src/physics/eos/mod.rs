//! Equations of state, one module each, and the registry that makes them
//! a material's `eos = { kind = "…" }` on both backends (docs/method.md
//! §6; docs/contributing.md, "An equation of state").
//!
//! An equation of state gives the pressure `p(ρ, e)` from the density and
//! the specific internal energy, compression positive. Each law's module
//! holds its scene keys (the struct), its plain functions and their
//! closed-form tests; its WGSL file `shaders/eos/<kind>.wgsl` holds
//! `<kind>_pressure`, `<kind>_dpdrho` and `<kind>_zero_mu`, the device
//! twins of [`PressureLaw::pressure`], [`PressureLaw::dp_drho`] and
//! [`PressureLaw::zero_pressure_mu`]; one line of its `law_registry!` below
//! registers both.

/// What the solver asks of an equation of state. `k = ρ0 c0²` is the bulk
/// modulus at the reference density `rho0`.
pub trait PressureLaw {
    /// The bulk sound speed at the reference state, m/s.
    fn c0(&self) -> f64;

    /// The pressure at density `rho` and specific internal energy `e`.
    /// A thermal part takes `e` at least 0: no adiabatic path from the
    /// reference state lowers the internal energy below it, so a negative
    /// `e` is a numerical deficit, and as a tension it would feed the
    /// motion that drew it.
    fn pressure(&self, k: f64, rho0: f64, rho: f64, e: f64) -> f64;

    /// `∂p/∂ρ` at `μ = ρ/ρ0 − 1` and `e`, never below its reference value
    /// `k/ρ0`: the bulk part of the sound speed.
    fn dp_drho(&self, k: f64, rho0: f64, mu: f64, e: f64) -> f64;

    /// The compression `μ` at which the pressure vanishes at specific
    /// energy `e` (at most 0): where a failed particle, which carries no
    /// tension, stops dilating.
    fn zero_pressure_mu(&self, k: f64, rho0: f64, e: f64) -> f64;

    /// The Grüneisen coefficient `Γ0` of a law of the form
    /// `p = p(ρ, 0) + Γ0 ρ e` (0 for a law with no thermal part).
    fn gruneisen(&self) -> f64;

    /// The scene's rules for the law's keys: `Err((key, message))`, the key
    /// within `eos`.
    fn check(&self) -> Result<(), (&'static str, String)>;

    /// The law's constants on the device (`Body.eos0`, `Body.eos1`).
    fn device(&self) -> [f32; DEVICE_CONSTANTS];
}

/// How many constants an equation of state may keep on the device.
pub const DEVICE_CONSTANTS: usize = 2;

law_registry! {
    /// A material's equation of state, as a scene names it
    /// (`eos = { kind = "<module>", … }`).
    enum Eos: dyn PressureLaw, keys Eos, shaders "eos";
    0 => MieGruneisen(mie_gruneisen),
    1 => Linear(linear),
}

impl Eos {
    /// Mie–Grüneisen with bulk sound speed `c0` (m/s), Hugoniot slope `s`
    /// and Grüneisen coefficient `gamma0`.
    pub fn mie_gruneisen(c0: f64, s: f64, gamma0: f64) -> Eos {
        Eos::MieGruneisen(mie_gruneisen::Eos { c0, s, gamma0 })
    }

    /// The linear law with bulk sound speed `c0` (m/s).
    pub fn linear(c0: f64) -> Eos {
        Eos::Linear(linear::Eos { c0 })
    }
}

#[cfg(test)]
mod tests {
    /// Every file in shaders/eos/ is a registered law's, and each defines
    /// the functions the registry's dispatch calls.
    #[test]
    fn every_eos_file_is_registered_and_defines_its_functions() {
        super::super::check_registry(
            "eos",
            super::DEVICE,
            &[
                "pressure(b: Body, mu: f32, e: f32)",
                "dpdrho(b: Body, mu: f32, e: f32)",
                "zero_mu(b: Body, e: f32)",
            ],
            None,
        );
    }
}
