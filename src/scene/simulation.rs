//! The run's settings: the `[simulation]` table and its choices.

use super::*;

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Simulation {
    /// 1 (uniaxial strain) or 2 (plane strain).
    pub dimension: u32,
    /// Simulated time to reach, s.
    pub end_time: f64,
    #[serde(default = "default_cfl")]
    pub cfl: f64,
    /// Optional fixed time step, s.
    #[serde(default)]
    pub dt: Option<f64>,
    #[serde(default)]
    pub interaction: Interaction,
    #[serde(default = "default_smoothing_ratio")]
    pub smoothing_ratio: f64,
    #[serde(default)]
    pub correction: Correction,
    /// The momentum and energy sums' stress terms (docs/method.md §4).
    #[serde(default)]
    pub stress_form: StressForm,
    #[serde(default)]
    pub backend: Backend,
    /// Time integration (docs/method.md §9; an addition to the contract).
    #[serde(default)]
    pub integrator: Integrator,
    /// Plane strain or bodies of revolution (docs/method.md §12).
    #[serde(default)]
    pub geometry: Geometry,
    /// Round supports of fixed `h`, or supports that follow the
    /// deformation (docs/method.md, "Supports that follow the
    /// deformation"); absent: adaptive.
    #[serde(default)]
    pub support: Option<Support>,
    /// How far adaptive supports stay round: a factor on the semi-axes,
    /// or two (drawn out, squeezed) (docs/method.md, "Supports that follow
    /// the deformation"); absent:
    /// [`crate::physics::support::DEFAULT_BAND`].
    #[serde(default)]
    pub support_band: Option<SupportBand>,
    /// The dispersion correction's `θ` (docs/method.md §4, "The
    /// dispersion correction"): 0 (the default) is off.
    #[serde(default)]
    pub dispersion_correction: f64,
    /// A uniform body force per unit mass on every deformable particle,
    /// m/s², one component per dimension (in a body of revolution along
    /// the axis only); absent: none.
    #[serde(default)]
    pub gravity: Option<Vec<f64>>,
}

pub fn default_cfl() -> f64 {
    0.3
}

pub fn default_smoothing_ratio() -> f64 {
    1.2
}

/// How bodies interact (docs/method.md §7).
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Interaction {
    /// The paper's contact algorithm: SPH sums within one body only.
    #[default]
    Penalty,
    /// Plain SPH across bodies (the paper's "kerneling" baseline).
    Kernel,
}

/// What a 2-D scene's plane stands for (docs/method.md §12).
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Geometry {
    /// Plane strain: every quantity per unit thickness.
    #[default]
    Planar,
    /// Bodies of revolution about the second axis: the first coordinate is
    /// the radius `r >= 0`, the second the axis `z`; masses are rings'.
    Axisymmetric,
}

/// The shape of each particle's kernel support (docs/method.md,
/// "Supports that follow the deformation").
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Support {
    /// A disk of radius `2h`, `h = smoothing_ratio × Δx`, for the whole run.
    Fixed,
    /// An ellipse carried with the material's deformation, within bounds.
    Adaptive,
}

impl Simulation {
    /// Whether supports adapt (as the scene says; adaptive where it says
    /// nothing).
    pub fn adaptive(&self) -> bool {
        self.support != Some(Support::Fixed)
    }

    /// The band within which adaptive supports stay round; none where
    /// supports are fixed.
    pub fn band(&self) -> Band {
        if self.adaptive() {
            self.support_band
                .map_or(crate::physics::support::DEFAULT_BAND, SupportBand::band)
        } else {
            Band::NONE
        }
    }
}

/// `simulation.support_band`: one factor for drawn-out and squeezed
/// supports alike, or `[drawn out, squeezed]`.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum SupportBand {
    Both(f64),
    Apart([f64; 2]),
}

impl SupportBand {
    pub fn band(self) -> Band {
        match self {
            SupportBand::Both(b) => Band::uniform(b),
            SupportBand::Apart([drawn, squeezed]) => Band { drawn, squeezed },
        }
    }
}

impl From<f64> for SupportBand {
    fn from(b: f64) -> SupportBand {
        SupportBand::Both(b)
    }
}

/// Time integration (docs/method.md §9), both second order.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Integrator {
    /// The explicit midpoint rule: two evaluations a step.
    Midpoint,
    /// Kick–drift–kick leapfrog: one evaluation a step (the default).
    #[default]
    Leapfrog,
}

impl std::fmt::Display for Integrator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Integrator::Midpoint => "midpoint",
            Integrator::Leapfrog => "leapfrog",
        })
    }
}

/// Kernel gradient correction (docs/method.md §5).
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Correction {
    #[default]
    Gradient,
    None,
}

/// The stress terms of the momentum and energy sums (docs/method.md §4).
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum StressForm {
    /// The variation of the discrete internal power (Bonet & Lok 1999):
    /// each particle's stress on its own corrected gradient, and each
    /// particle's energy its own stress power `σ_i : (∇v)_i / ρ_i`.
    #[default]
    Variational,
    /// The paper's eq. 6: `σ_i/ρ_i² + σ_j/ρ_j²` on the pair's mean
    /// corrected gradient, the energy on that gradient too.
    Paper,
}

#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Backend {
    #[default]
    Auto,
    Gpu,
    Cpu,
}

impl std::fmt::Display for Backend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Backend::Auto => "auto",
            Backend::Gpu => "gpu",
            Backend::Cpu => "cpu",
        })
    }
}
