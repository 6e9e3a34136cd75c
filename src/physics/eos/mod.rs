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
//! [`PressureLaw::zero_pressure_mu`]; one line of [`eos_laws!`] below
//! registers both.

use serde::{Deserialize, Serialize};

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

/// An equation of state as the device knows it: its number (`Body.eos`),
/// its kind and its WGSL.
pub struct DeviceEos {
    pub id: u32,
    pub kind: &'static str,
    pub wgsl: &'static str,
}

/// The registry: one line per law, `id => Variant(module)`. The module's
/// `Eos` is the law's scene keys; its name is the scene's `kind` and the
/// stem of its WGSL file. Ids are the device's.
macro_rules! eos_laws {
    ($($id:literal => $variant:ident($module:ident)),* $(,)?) => {
        $(pub mod $module;)*

        /// A material's equation of state, as a scene names it
        /// (`eos = { kind = "<module>", … }`).
        #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
        #[serde(tag = "kind", rename_all = "snake_case")]
        pub enum Eos {
            $($variant($module::Eos)),*
        }

        /// The law's functions: `eos.pressure(…)`.
        impl std::ops::Deref for Eos {
            type Target = dyn PressureLaw;

            fn deref(&self) -> &Self::Target {
                match self {
                    $(Self::$variant(l) => l),*
                }
            }
        }

        impl Eos {
            /// The law's number on the device.
            pub fn device_id(&self) -> u32 {
                match self {
                    $(Self::$variant(_) => $id),*
                }
            }
        }

        /// Every law's device side, in the registry's order.
        pub const DEVICE: &[DeviceEos] = &[$(DeviceEos {
            id: $id,
            kind: stringify!($module),
            wgsl: include_str!(concat!("../../../shaders/eos/", stringify!($module), ".wgsl")),
        }),*];
    };
}

eos_laws! {
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
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders/eos");
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
            for f in [
                "pressure(b: Body, mu: f32, e: f32)",
                "dpdrho(b: Body, mu: f32, e: f32)",
                "zero_mu(b: Body, e: f32)",
            ] {
                let sig = format!("fn {}_{f}", l.kind);
                assert!(l.wgsl.contains(&sig), "{}.wgsl: no `{sig}`", l.kind);
            }
        }
        let mut ids: Vec<u32> = super::DEVICE.iter().map(|l| l.id).collect();
        ids.sort();
        ids.dedup();
        assert_eq!(ids.len(), super::DEVICE.len(), "ids are distinct");
        assert!(ids.iter().all(|&i| i < 32), "an id is a bit of EOS_LAWS");
    }
}
