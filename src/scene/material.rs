//! A scene's materials: as written (each key optional, a library entry
//! supplying the rest) and as the solver uses them, with their strength,
//! failure and EOS laws.

use serde::{Deserialize, Serialize};

use super::library;

/// A material as the solver uses it: every constant given, whether written
/// out in the scene or taken from the library (`library = "name"`, see
/// [`library`]) with the scene's own keys overriding the entry's.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(try_from = "MaterialSpec")]
pub struct Material {
    /// The library entry this material was taken from, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub library: Option<String>,
    /// Where the constants come from (a citation; the library's entries
    /// carry one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// Reference density ρ0, kg/m³.
    pub density: f64,
    /// Shear modulus G, Pa (absent: no deviatoric stress).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shear_modulus: Option<f64>,
    /// Yield stress Y0, Pa, of perfect plasticity (absent: elastic, unless
    /// `strength` is given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub yield_stress: Option<f64>,
    pub eos: Eos,
    /// A strength law with hardening, rate and temperature terms (instead of
    /// `yield_stress`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub strength: Option<StrengthLaw>,
    /// Specific heat c_p, J/(kg K): the plastic work's heating. Required by
    /// a `strength` law.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub specific_heat: Option<f64>,
    /// The fraction of plastic work that heats the material (default 0.9).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub taylor_quinney: Option<f64>,
    /// A ductile damage law; a particle whose damage reaches 1 fails.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failure: Option<FailureLaw>,
    /// The tensile pressure, Pa (a positive number), at which a particle
    /// fails (spall).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spall_pressure: Option<f64>,
    /// The tension, Pa (a positive number; `inf`: none), past which the
    /// solid opens a void without failing (docs/method.md,
    /// "Cavitation"). Default: a tenth of Young's modulus for a material
    /// with a strength law, none otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cavitation_pressure: Option<f64>,
}

/// The default Taylor–Quinney fraction (Taylor & Quinney, 1934).
pub const DEFAULT_TAYLOR_QUINNEY: f64 = 0.9;

impl Material {
    /// An elastic material with nothing else given.
    pub fn basic(density: f64, eos: Eos) -> Self {
        Self {
            library: None,
            source: None,
            density,
            shear_modulus: None,
            yield_stress: None,
            eos,
            strength: None,
            specific_heat: None,
            taylor_quinney: None,
            failure: None,
            spall_pressure: None,
            cavitation_pressure: None,
        }
    }

    pub fn taylor_quinney(&self) -> f64 {
        self.taylor_quinney.unwrap_or(DEFAULT_TAYLOR_QUINNEY)
    }

    /// Whether a deformable body of this material carries a plastic history
    /// (equivalent plastic strain, temperature, damage): a strength law, a
    /// failure model, a spall pressure or a cavitation pressure. The
    /// scene-level twin of
    /// [`crate::physics::material::MaterialModel::has_history`].
    pub fn has_history(&self) -> bool {
        self.strength.is_some()
            || self.failure.is_some()
            || self.spall_pressure.is_some()
            || self.cavitation_pressure.is_some_and(f64::is_finite)
    }
}

/// A material as written in a scene: each key optional, so that an entry
/// of the library can supply the rest.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    #[serde(default)]
    pub library: Option<String>,
    #[serde(default)]
    pub source: Option<String>,
    #[serde(default)]
    pub density: Option<f64>,
    #[serde(default)]
    pub shear_modulus: Option<f64>,
    #[serde(default)]
    pub yield_stress: Option<f64>,
    #[serde(default)]
    pub eos: Option<Eos>,
    #[serde(default)]
    pub strength: Option<StrengthLaw>,
    #[serde(default)]
    pub specific_heat: Option<f64>,
    #[serde(default)]
    pub taylor_quinney: Option<f64>,
    #[serde(default)]
    pub failure: Option<FailureLaw>,
    #[serde(default)]
    pub spall_pressure: Option<f64>,
    #[serde(default)]
    pub cavitation_pressure: Option<f64>,
}

impl TryFrom<MaterialSpec> for Material {
    type Error = String;

    /// The library entry, if named, with the spec's own keys over it.
    fn try_from(spec: MaterialSpec) -> Result<Material, String> {
        let base = match &spec.library {
            Some(name) => Some(library::entry(name)?),
            None => None,
        };
        // The spec's own value, else the entry's.
        fn or_base<T>(
            own: Option<T>,
            base: &Option<Material>,
            of: impl Fn(&Material) -> Option<T>,
        ) -> Option<T> {
            own.or_else(|| base.as_ref().and_then(of))
        }
        let density =
            or_base(spec.density, &base, |b| Some(b.density)).ok_or("missing field `density`")?;
        let eos = or_base(spec.eos, &base, |b| Some(b.eos)).ok_or("missing field `eos`")?;
        Ok(Material {
            shear_modulus: or_base(spec.shear_modulus, &base, |b| b.shear_modulus),
            yield_stress: or_base(spec.yield_stress, &base, |b| b.yield_stress),
            strength: or_base(spec.strength, &base, |b| b.strength),
            specific_heat: or_base(spec.specific_heat, &base, |b| b.specific_heat),
            taylor_quinney: or_base(spec.taylor_quinney, &base, |b| b.taylor_quinney),
            failure: or_base(spec.failure, &base, |b| b.failure),
            spall_pressure: or_base(spec.spall_pressure, &base, |b| b.spall_pressure),
            cavitation_pressure: or_base(spec.cavitation_pressure, &base, |b| {
                b.cavitation_pressure
            }),
            source: or_base(spec.source, &base, |b| b.source.clone()),
            library: spec.library,
            density,
            eos,
        })
    }
}

/// Strength laws beyond perfect plasticity: one module each in
/// [`crate::physics::laws`], registered there.
pub use crate::physics::laws::StrengthLaw;

/// Damage laws (one module each in [`crate::physics::failure`]).
pub use crate::physics::failure::FailureLaw;

/// Equation of state (docs/method.md §6; one module each in
/// [`crate::physics::eos`]).
pub use crate::physics::eos::Eos;
