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
//! the device twins of the two; one line of its `law_registry!` below
//! registers both.

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

pub use super::DeviceLaw;

law_registry! {
    /// A material's strength law, as a scene names it
    /// (`strength = { kind = "<module>", … }`). Device number 0 is "no
    /// law".
    enum StrengthLaw: dyn Law, keys Strength, shaders "laws";
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
        super::super::check_registry(
            "laws",
            super::DEVICE,
            &["factor(p: Plastic, ", "curve(p: Plastic, "],
            Some(0),
        );
    }
}
