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
//! `<kind>_failure_strain`; one line of [`failure_laws!`] registers both.

use serde::{Deserialize, Serialize};

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

/// A damage law as the device knows it: its number (`Plastic.damage`; 0
/// is none), its kind and its WGSL.
pub struct DeviceFailure {
    pub id: u32,
    pub kind: &'static str,
    pub wgsl: &'static str,
}

/// The registry: one line per law, `id => Variant(module)`. The module's
/// `Failure` is the law's scene keys; its name is the scene's `kind` and
/// the stem of its WGSL file. Ids are the device's: 0 is "no law".
macro_rules! failure_laws {
    ($($id:literal => $variant:ident($module:ident)),* $(,)?) => {
        $(pub mod $module;)*

        /// A material's damage law, as a scene names it
        /// (`failure = { kind = "<module>", … }`).
        #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
        #[serde(tag = "kind", rename_all = "snake_case")]
        pub enum FailureLaw {
            $($variant($module::Failure)),*
        }

        /// The law's functions: `law.failure_strain(…)`.
        impl std::ops::Deref for FailureLaw {
            type Target = dyn DamageLaw;

            fn deref(&self) -> &Self::Target {
                match self {
                    $(Self::$variant(l) => l),*
                }
            }
        }

        impl FailureLaw {
            /// The law's number on the device.
            pub fn device_id(&self) -> u32 {
                match self {
                    $(Self::$variant(_) => $id),*
                }
            }
        }

        /// Every law's device side, in the registry's order.
        pub const DEVICE: &[DeviceFailure] = &[$(DeviceFailure {
            id: $id,
            kind: stringify!($module),
            wgsl: include_str!(concat!("../../../shaders/failure/", stringify!($module), ".wgsl")),
        }),*];
    };
}

failure_laws! {
    1 => JohnsonCook(johnson_cook),
}

#[cfg(test)]
mod tests {
    /// Every file in shaders/failure/ is a registered law's, and each
    /// defines the function the registry's dispatch calls.
    #[test]
    fn every_failure_file_is_registered_and_defines_its_function() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders/failure");
        let mut on_disk: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        on_disk.sort();
        let mut listed: Vec<String> = super::DEVICE
            .iter()
            .map(|l| format!("{}.wgsl", l.kind))
            .collect();
        listed.sort();
        assert_eq!(on_disk, listed);
        for l in super::DEVICE {
            let sig = format!("fn {}_failure_strain(p: Plastic, ", l.kind);
            assert!(l.wgsl.contains(&sig), "{}.wgsl: no `{sig}…`", l.kind);
            assert!(l.id > 0 && l.id < 32, "0 is no law; an id is a bit");
        }
        let mut ids: Vec<u32> = super::DEVICE.iter().map(|l| l.id).collect();
        ids.sort();
        ids.dedup();
        assert_eq!(ids.len(), super::DEVICE.len(), "ids are distinct");
    }
}
