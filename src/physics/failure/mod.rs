//! Damage laws, one module each, and the registry that makes them a
//! material's `failure = { kind = "…" }` on both backends (docs/method.md,
//! "Strength and failure"; docs/contributing.md, "A damage law").
//!
//! A damage law gives the plastic strain to failure `ε_f` at the stress
//! triaxiality `σ* = −p/σ_vm` (bounded by
//! [`TRIAXIALITY_BOUND`]), the dimensionless rate
//! `ε̇*` and the homologous temperature `T*`; a particle's damage grows by
//! `Δε_p/ε_f` and it fails at 1 ([`crate::physics::strength`]). Each law's
//! module holds its scene keys (the struct), its plain function and its
//! tests; its WGSL file `shaders/failure/<kind>.wgsl` holds
//! `<kind>_failure_strain`; one line of its `law_registry!` registers both.

/// What the stress update asks of a damage law.
pub trait DamageLaw {
    /// The plastic strain to failure at triaxiality `triax`, rate `ε̇*`
    /// (relative to the strength law's reference rate) and `T*`.
    fn failure_strain(&self, triax: f64, rate_star: f64, t_star: f64) -> f64;

    /// Whether the failure strain changes with `T*` (then the strength law
    /// must name a melt temperature).
    fn reads_temperature(&self) -> bool;

    /// The scene's rules for the law's keys: `Err((key, message))`, the key
    /// within `failure` ("" for the table itself). The failure strain must
    /// stay positive at every triaxiality within the solver's bound.
    fn check(&self) -> Result<(), (&'static str, String)>;

    /// The law's constants on the device (`Plastic.d1` … `d5`).
    fn device(&self) -> [f32; DEVICE_CONSTANTS];
}

/// Triaxialities beyond this bound use the bound in the failure strain:
/// past it the material is in near-hydrostatic tension, where the spall
/// pressure governs, and where the exponential term of some published
/// constant sets (Armco iron's) turns the failure strain negative.
pub const TRIAXIALITY_BOUND: f64 = 1.5;

/// How many constants a damage law may keep on the device.
pub const DEVICE_CONSTANTS: usize = 5;

law_registry! {
    /// A material's damage law, as a scene names it
    /// (`failure = { kind = "<module>", … }`). Device number 0 is "no
    /// law".
    enum FailureLaw: dyn DamageLaw, keys Failure, shaders "failure";
    1 => JohnsonCook(johnson_cook),
}

#[cfg(test)]
mod tests {
    /// Every file in shaders/failure/ is a registered law's, and each
    /// defines the function the registry's dispatch calls.
    #[test]
    fn every_failure_file_is_registered_and_defines_its_function() {
        super::super::check_registry(
            "failure",
            super::DEVICE,
            &["failure_strain(p: Plastic, "],
            Some(0),
        );
    }
}
