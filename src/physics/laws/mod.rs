//! Strength laws, one module each, and the registry that makes them a
//! scene's `strength = { kind = "…" }` on both backends (docs/method.md,
//! "Strength and failure"; docs/contributing.md, "A strength law").
//!
//! A law is a flow stress `σ_y(ε_p; ε̇, T)`. Over a step the stress update
//! freezes the rate and temperature at the step's start, which every law
//! here sums up in one number, its [`Law::factor`]; the radial return
//! ([`return_increment`]) then solves on the curve [`Law::curve`] of the
//! plastic strain alone. Each law's module holds its scene keys (the
//! struct), its plain functions and their closed-form tests; its WGSL file
//! `shaders/laws/<kind>.wgsl` holds `<kind>_factor` and `<kind>_curve`,
//! the device twins of the two; one line of [`strength_laws!`] below
//! registers both.

use serde::{Deserialize, Serialize};

/// What the stress update asks of a strength law.
pub trait Law {
    /// The rate and temperature part of the flow stress at the equivalent
    /// strain rate `rate` (1/s) and temperature `temperature` (K), frozen
    /// over a step.
    fn factor(&self, rate: f64, temperature: f64) -> f64;

    /// The flow stress at plastic strain `eps_p` under `factor` and its
    /// slope `dσ_y/dε_p` (infinite where the curve starts vertical: the
    /// return brackets its root and never divides by it).
    fn curve(&self, factor: f64, eps_p: f64) -> (f64, f64);

    /// The temperature a particle starts at, K.
    fn room_temperature(&self) -> f64;

    /// The melt temperature, K, that a damage law's homologous temperature
    /// reads; `None` where the law names none (then `T* = 0`).
    fn melt_temperature(&self) -> Option<f64>;

    /// The rate, 1/s, that a damage law's `ε̇*` is relative to.
    fn reference_strain_rate(&self) -> f64;

    /// Whether the flow stress changes with the strain rate: the exact
    /// answers of a hardening rod need it not to
    /// ([`crate::validation::exact::rod`]).
    fn rate_dependent(&self) -> bool;

    /// The scene's rules for the law's keys: `Err((key, message))`, the key
    /// within `strength`.
    fn check(&self) -> Result<(), (&'static str, String)>;

    /// The law's constants on the device, in the order its WGSL file reads
    /// them (`Plastic.k`).
    fn device(&self) -> [f32; DEVICE_CONSTANTS];

    /// The flow stress at plastic strain, rate and temperature.
    fn flow_stress(&self, eps_p: f64, rate: f64, temperature: f64) -> f64 {
        self.curve(self.factor(rate, temperature), eps_p).0
    }

    /// The yield stress of the virgin material at room temperature and the
    /// reference rate: the material's `Y0` where a scalar is asked for
    /// ([`crate::physics::material::MaterialModel::y0`]).
    fn initial_yield(&self) -> f64 {
        self.flow_stress(0.0, self.reference_strain_rate(), self.room_temperature())
    }
}

/// How many constants a law may keep on the device.
pub const DEVICE_CONSTANTS: usize = 8;

/// A law as the device knows it: its number (`Plastic.law`), its kind and
/// its WGSL.
pub struct DeviceLaw {
    pub id: u32,
    pub kind: &'static str,
    pub wgsl: &'static str,
}

/// The registry: one line per law, `id => Variant(module)`. The module's
/// `Strength` is the law's scene keys; its name is the scene's `kind` and
/// the stem of its WGSL file. Ids are the device's: 0 is "no law".
macro_rules! strength_laws {
    ($($id:literal => $variant:ident($module:ident)),* $(,)?) => {
        $(pub mod $module;)*

        /// A material's strength law, as a scene names it
        /// (`strength = { kind = "<module>", … }`).
        #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
        #[serde(tag = "kind", rename_all = "snake_case")]
        pub enum StrengthLaw {
            $($variant($module::Strength)),*
        }

        /// The law's functions: `law.factor(…)`.
        impl std::ops::Deref for StrengthLaw {
            type Target = dyn Law;

            fn deref(&self) -> &Self::Target {
                match self {
                    $(Self::$variant(l) => l),*
                }
            }
        }

        impl StrengthLaw {
            /// The law's number on the device.
            pub fn device_id(&self) -> u32 {
                match self {
                    $(Self::$variant(_) => $id),*
                }
            }
        }

        /// Every law's device side, in the registry's order.
        pub const DEVICE: &[DeviceLaw] = &[$(DeviceLaw {
            id: $id,
            kind: stringify!($module),
            wgsl: include_str!(concat!("../../../shaders/laws/", stringify!($module), ".wgsl")),
        }),*];
    };
}

strength_laws! {
    1 => JohnsonCook(johnson_cook),
    2 => ModifiedJohnsonCook(modified_johnson_cook),
    3 => ZerilliArmstrong(zerilli_armstrong),
}

/// A particle's homologous temperature `T* = (T − T_room)/(T_melt − T_room)`,
/// clamped to [0, 1]; 0 without a melt temperature.
pub fn homologous(room: f64, melt: Option<f64>, temperature: f64) -> f64 {
    match melt {
        Some(melt) => ((temperature - room) / (melt - room)).clamp(0.0, 1.0),
        None => 0.0,
    }
}

/// The plastic strain increment `Δε_p` of a radial return from a trial von
/// Mises stress `q_trial` with shear modulus `g` at plastic strain `eps_p`
/// onto the flow curve `curve` (value and slope at a plastic strain):
/// the root of `q_trial − 3 G Δε_p = σ_y(ε_p + Δε_p)` (von Mises,
/// associated flow), 0 where the trial state is inside the surface.
/// Safeguarded Newton on a bracket (the residual falls monotonically in
/// Δε_p for a hardening or perfectly plastic curve), to round-off.
pub fn return_increment(
    curve: impl Fn(f64) -> (f64, f64),
    q_trial: f64,
    g: f64,
    eps_p: f64,
) -> f64 {
    let resid = |d: f64| {
        let (s, slope) = curve(eps_p + d);
        (q_trial - 3.0 * g * d - s, -3.0 * g - slope)
    };
    if resid(0.0).0 <= 0.0 {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, q_trial / (3.0 * g));
    let mut d = 0.5 * (lo + hi);
    for _ in 0..200 {
        let (f, df) = resid(d);
        if f > 0.0 {
            lo = d;
        } else {
            hi = d;
        }
        let newton = d - f / df;
        if newton.is_finite() && newton >= lo && newton <= hi {
            // Converged where Newton no longer moves.
            let done = (newton - d).abs() <= 1e-15 * d;
            d = newton;
            if done {
                break;
            }
        } else {
            d = 0.5 * (lo + hi);
        }
        if f == 0.0 || hi - lo <= 1e-15 * hi {
            break;
        }
    }
    d
}

/// `Err((key, "must be > 0"))` unless `v` is finite and positive.
pub(crate) fn positive(key: &'static str, v: f64) -> Result<(), (&'static str, String)> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err((key, format!("must be > 0 (got {v})")))
    }
}

/// `Err((key, "must be >= 0"))` unless `v` is finite and not negative.
pub(crate) fn non_negative(key: &'static str, v: f64) -> Result<(), (&'static str, String)> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err((key, format!("must be >= 0 (got {v})")))
    }
}

/// A room and a melt temperature, the melt above the room.
pub(crate) fn temperatures(room: f64, melt: Option<f64>) -> Result<(), (&'static str, String)> {
    positive("room_temperature", room)?;
    if let Some(melt) = melt {
        positive("melt_temperature", melt)?;
        if melt <= room {
            return Err((
                "melt_temperature",
                format!("must be above room_temperature ({room} K)"),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    /// Every file in shaders/laws/ is a registered law's, and each defines
    /// the two functions the registry's dispatch calls.
    #[test]
    fn every_law_file_is_registered_and_defines_its_functions() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders/laws");
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
            for f in ["factor", "curve"] {
                let sig = format!("fn {}_{f}(p: Plastic, ", l.kind);
                assert!(l.wgsl.contains(&sig), "{}.wgsl: no `{sig}…`", l.kind);
            }
            assert!(l.id > 0, "0 is no law");
        }
        let mut ids: Vec<u32> = super::DEVICE.iter().map(|l| l.id).collect();
        ids.sort();
        ids.dedup();
        assert_eq!(ids.len(), super::DEVICE.len(), "ids are distinct");
    }
}
