//! The scene file: the format of docs/scenes.md.
//!
//! A scene is one TOML document. This module holds its data types exactly as
//! the contract names them (unknown keys are rejected by serde), the loader,
//! and re-exports the semantic validation and the particle placement.

pub mod library;
mod material;
mod model;
pub mod outline;
pub mod particles_file;
mod place;
mod surface;
mod toml_errors;
pub mod validate;

pub use material::{Eos, FailureLaw, Material, MaterialSpec, StrengthLaw};
pub use place::{place_bodies, PlacedBody};
pub use validate::validate;

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::error::SceneError;
use crate::physics::support::Band;

/// A whole scene: geometry, materials, physics switches and what to record.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    #[serde(default)]
    pub title: Option<String>,
    pub simulation: Simulation,
    #[serde(default)]
    pub artificial_stress: Option<ArtificialStress>,
    #[serde(default)]
    pub artificial_viscosity: Option<ArtificialViscosity>,
    /// Optional contact settings (an addition to the contract; absent: defaults).
    #[serde(default)]
    pub contact: Option<ContactSettings>,
    pub materials: BTreeMap<String, Material>,
    pub bodies: Vec<Body>,
    #[serde(default)]
    pub probes: Vec<Probe>,
    #[serde(default)]
    pub output: Output,
}

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

/// Gray, Monaghan & Swift artificial stress (docs/method.md, "Tension").
///
/// A scene without the section gets [`ArtificialStress::DEFAULT`], the
/// close-pair form; a section without `pairs` is the classic form on
/// every pair; `epsilon = 0` switches the term off; `work` says where its
/// work may only be heat ([`ArtWork`]); `plastic` what a body whose
/// material can yield takes ([`ArtPlastic`]).
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ArtificialStress {
    #[serde(default = "default_as_epsilon")]
    pub epsilon: f64,
    #[serde(default = "default_as_n")]
    pub n: f64,
    #[serde(default)]
    pub pairs: ArtPairs,
    #[serde(default)]
    pub work: ArtWork,
    #[serde(default)]
    pub plastic: ArtPlastic,
    /// The hourglass control's coefficient in a body that takes it in
    /// place of the term ([`ArtPlastic::Hourglass`]).
    #[serde(default = "default_as_plastic_hourglass")]
    pub plastic_hourglass: f64,
}
fn default_as_epsilon() -> f64 {
    0.3
}
fn default_as_n() -> f64 {
    4.0
}
fn default_as_plastic_hourglass() -> f64 {
    ArtificialStress::DEFAULT.plastic_hourglass
}

impl ArtificialStress {
    /// What a scene without `[artificial_stress]` runs with: the
    /// close-pair form at Gray, Monaghan & Swift's `ε = 0.3`, `n = 4`.
    pub const DEFAULT: ArtificialStress = ArtificialStress {
        epsilon: 0.3,
        n: 4.0,
        pairs: ArtPairs::Close,
        work: ArtWork::Yielding,
        plastic: ArtPlastic::Stress,
        plastic_hourglass: 0.3,
    };
}

/// What the particles of a deformable body whose material can yield (a
/// yield stress or a strength law) take against the tensile instability
/// (docs/method.md, "Hourglass control in place of the term").
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum ArtPlastic {
    /// The artificial stress, as every other body.
    #[default]
    Stress,
    /// No artificial stress of their own (`R_i = 0`), and the hourglass
    /// control at `plastic_hourglass` on their families of pairs, whose
    /// work is heat: plastic flow has no tension to hold, and the term's
    /// one-signed work there drains internal energy into motion.
    Hourglass,
}

/// Which way the artificial stress's work on a pair may go (docs/method.md,
/// "Only heat").
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum ArtWork {
    /// Every pair the form selects takes it; its work, of either sign, is
    /// booked as heat.
    Either,
    /// A pair with a particle of a body whose material can yield (a yield
    /// stress or a strength law) takes it as with [`ArtWork::Heat`], every
    /// other pair as with [`ArtWork::Either`]: plastic flow has no elastic
    /// tension to hold, and the term's push there drains internal energy
    /// into motion; elastic bodies keep the push their tension needs. In a
    /// scene where nothing can yield, the term is `Either`'s to the bit.
    #[default]
    Yielding,
    /// The pair takes the term only while its work there is heat (`≥ 0`),
    /// fully once the pair closes along the term's force at
    /// [`crate::physics::tension::HEAT_SPEED`] of its sound speed.
    Heat,
    /// A pair with a particle that flows plastically
    /// ([`crate::model::Model::flowing`]) takes it as with
    /// [`ArtWork::Heat`], every other pair as with [`ArtWork::Either`]:
    /// where nothing yields, the term is `Either`'s to the bit.
    Plastic,
}

/// Which pairs the artificial stress acts on.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum ArtPairs {
    /// Every pair with a particle in tension (Gray, Monaghan & Swift).
    #[default]
    All,
    /// Only pairs closer than their local spacing `(V̄)^(1/d)`, at full
    /// strength from [`crate::physics::tension::CLOSE_FULL`] of it: zero on a
    /// smoothly strained lattice, on at the clumping the tensile
    /// instability starts with.
    Close,
}

/// The pairs the artificial viscosity acts on.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ViscosityForm {
    /// Monaghan's: approaching pairs only.
    Monaghan,
    /// The acoustic Riemann solver's dissipation: approaching and
    /// receding pairs alike, so release fronts are damped as compression
    /// fronts are (the quadratic term still on approach only).
    #[default]
    Riemann,
}

/// The artificial viscosity (docs/method.md §4, "The Riemann form").
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ArtificialViscosity {
    #[serde(default = "default_av_alpha")]
    pub alpha: f64,
    #[serde(default = "default_av_beta")]
    pub beta: f64,
    /// Limited linear reconstruction of the velocity jump to the pair
    /// midpoint (`physics::viscosity::reconstructed_jump`): the viscosity acts at
    /// fronts, not on smooth compression. Default on.
    #[serde(default = "default_true")]
    pub reconstruct: bool,
    /// Which pairs it acts on (docs/method.md, "Viscosity on the
    /// reconstructed velocity jump").
    #[serde(default)]
    pub form: ViscosityForm,
    /// With `reconstruct`, pairs with a surface particle see the
    /// reconstructed jump too (the default; `false`: the plain one).
    #[serde(default = "default_true")]
    pub reconstruct_surfaces: bool,
    /// Hourglass control's coefficient (docs/method.md, "Hourglass
    /// control"): a viscosity on the part of each neighbour's velocity
    /// that the particle's velocity gradient does not explain. 0 (the
    /// default) is off.
    #[serde(default)]
    pub hourglass: f64,
}
fn default_true() -> bool {
    true
}
/// Documented defaults: see `docs/method.md` ("Defaults").
pub fn default_av_alpha() -> f64 {
    0.75
}
pub fn default_av_beta() -> f64 {
    0.75
}
impl Default for ArtificialViscosity {
    fn default() -> Self {
        Self {
            alpha: default_av_alpha(),
            beta: default_av_beta(),
            reconstruct: true,
            form: ViscosityForm::default(),
            reconstruct_surfaces: true,
            hourglass: 0.0,
        }
    }
}

/// Penalty contact settings (docs/method.md §8.3); an optional addition to the contract.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ContactSettings {
    /// Boundary-particle threshold on `h |∇ψ|` (docs/method.md §8.1).
    #[serde(default = "default_boundary_threshold")]
    pub boundary_threshold: f64,
}
impl Default for ContactSettings {
    fn default() -> Self {
        Self {
            boundary_threshold: default_boundary_threshold(),
        }
    }
}
pub fn default_boundary_threshold() -> f64 {
    0.3
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Body {
    pub name: String,
    pub material: String,
    /// Particle spacing Δx, m.
    pub spacing: f64,
    /// Initial velocity, one component per dimension.
    #[serde(default)]
    pub velocity: Option<Vec<f64>>,
    /// Moves at its initial velocity and is an infinitely stiff contact partner.
    #[serde(default)]
    pub rigid: bool,
    pub shape: Shape,
    /// Optional placement jitter (an addition to the contract), a fraction
    /// of the spacing in `[0, 0.5)`: each coordinate of each particle is
    /// displaced uniformly in `[−jitter, +jitter]·Δx` after placement (see
    /// [`place_bodies`]). Absent or 0: the regular lattice.
    #[serde(default)]
    pub jitter: Option<f64>,
    /// Seed of the jitter's generator (absent: the body's index in the
    /// file), so a jittered scene places the same particles on every run
    /// and every backend.
    #[serde(default)]
    pub seed: Option<u64>,
    /// A velocity field added to `velocity` particle by particle (an
    /// imploding or expanding shell, say).
    #[serde(default)]
    pub velocity_field: Option<VelocityField>,
}

/// An initial velocity that varies over a body.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum VelocityField {
    /// Along the direction from `center`, `speed (radius/r)^exponent` at
    /// distance `r` (negative: inward). Exponent 1 is the incompressible
    /// flow of a cylinder in the plane; 2 that of a sphere, drawn as a body
    /// of revolution centred on the axis.
    Radial {
        center: Vec<f64>,
        speed: f64,
        radius: f64,
        #[serde(default)]
        exponent: f64,
    },
}

impl VelocityField {
    /// The field's velocity at `x`; `None` at the centre, where a radial
    /// field has no direction.
    pub fn at(&self, x: glam::DVec2) -> Option<glam::DVec2> {
        match self {
            VelocityField::Radial {
                center,
                speed,
                radius,
                exponent,
            } => {
                let c = glam::DVec2::new(center[0], center.get(1).copied().unwrap_or(0.0));
                let d = x - c;
                let r = d.length();
                (r > 0.0).then(|| d / r * (*speed * (radius / r).powf(*exponent)))
            }
        }
    }
}

#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Lattice {
    #[default]
    Square,
    Polar,
}

/// How a polygon is filled.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum PolygonLattice {
    /// The square lattice fitted to the outline's bounding box.
    #[default]
    Square,
    /// Layers at depths `(k + ½) Δx` along the boundary
    /// ([`outline::boundary_lattice`]).
    Boundary,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    Segment {
        from: f64,
        to: f64,
    },
    Rectangle {
        min: Vec<f64>,
        max: Vec<f64>,
    },
    Disk {
        center: Vec<f64>,
        radius: f64,
        #[serde(default)]
        lattice: Lattice,
    },
    Ring {
        center: Vec<f64>,
        inner_radius: f64,
        outer_radius: f64,
        #[serde(default)]
        lattice: Lattice,
    },
    /// A closed outline (`[[x, y], ...]`, the last vertex joined to the
    /// first, either orientation) with optional holes, filled on the square
    /// lattice fitted to the outline's bounding box or in layers that
    /// follow the boundary ([`PolygonLattice`]).
    Polygon {
        vertices: Vec<Vec<f64>>,
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        holes: Vec<Vec<Vec<f64>>>,
        #[serde(default)]
        lattice: PolygonLattice,
    },
    /// Particles read from a CSV file ([`particles_file`]); a relative path
    /// is taken from the scene file's folder.
    Particles {
        file: PathBuf,
    },
}

impl Shape {
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Segment { .. } => "segment",
            Shape::Rectangle { .. } => "rectangle",
            Shape::Disk { .. } => "disk",
            Shape::Ring { .. } => "ring",
            Shape::Polygon { .. } => "polygon",
            Shape::Particles { .. } => "particles",
        }
    }
}

/// Per-particle quantities a `particle` probe can record.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ParticleQuantity {
    PositionX,
    PositionY,
    VelocityX,
    VelocityY,
    Density,
    Pressure,
    StressXx,
    StressYy,
    StressXy,
    /// The normal stress across the plane: `σ_zz` of plane strain, the
    /// hoop stress `σ_θθ` of a body of revolution.
    StressZz,
    VonMises,
    InternalEnergy,
    /// Equivalent plastic strain (a body whose material has a strength law
    /// or a failure model).
    PlasticStrain,
    /// Temperature, K (as `plastic_strain`).
    Temperature,
    /// Damage, 0 to 1 (1: failed; as `plastic_strain`).
    Damage,
    /// The time the particle failed, s; −1 while it holds (as
    /// `plastic_strain`).
    FailureTime,
}

impl ParticleQuantity {
    /// Whether the quantity is part of the plastic history, which only
    /// bodies of materials with a strength law or failure model carry.
    pub fn needs_history(self) -> bool {
        matches!(
            self,
            ParticleQuantity::PlasticStrain
                | ParticleQuantity::Temperature
                | ParticleQuantity::Damage
                | ParticleQuantity::FailureTime
        )
    }
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BodyQuantity {
    VelocityX,
    VelocityY,
    PositionX,
    PositionY,
    KineticEnergy,
    MomentumX,
    MomentumY,
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ContactQuantity {
    Force,
    PressureMax,
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum EnergyQuantity {
    Kinetic,
    Internal,
    ContactHeat,
    /// The artificial terms' work so far ([`crate::model::State::dissipation`]).
    ArtificialDissipation,
    Total,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Probe {
    Particle {
        name: String,
        body: String,
        at: Vec<f64>,
        quantity: ParticleQuantity,
    },
    Body {
        name: String,
        body: String,
        quantity: BodyQuantity,
    },
    Contact {
        name: String,
        bodies: [String; 2],
        quantity: ContactQuantity,
    },
    Energy {
        name: String,
        quantity: EnergyQuantity,
    },
}

impl Probe {
    pub fn name(&self) -> &str {
        match self {
            Probe::Particle { name, .. }
            | Probe::Body { name, .. }
            | Probe::Contact { name, .. }
            | Probe::Energy { name, .. } => name,
        }
    }
}

#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// Output directory (default `out/<scene file stem>`).
    #[serde(default)]
    pub dir: Option<PathBuf>,
    /// s; default `end_time / 1000`.
    #[serde(default)]
    pub history_interval: Option<f64>,
    /// s; optional.
    #[serde(default)]
    pub snapshot_interval: Option<f64>,
}

impl Scene {
    /// Parse a scene from TOML text and validate it. `origin` names the source
    /// in error messages (usually the file path).
    /// Relative particle files are taken from the working folder.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Scene, SceneError> {
        Self::from_toml_in(text, origin, Path::new(""))
    }

    /// Read, parse and validate a scene file.
    pub fn from_file(path: &Path) -> Result<Scene, SceneError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SceneError {
            file: origin.clone(),
            key: None,
            message: format!("cannot read the scene file: {e}"),
        })?;
        let base = path.parent().unwrap_or(Path::new(""));
        Self::from_toml_in(&text, &origin, base)
    }

    /// [`Scene::from_toml_str`] with the relative paths inside the scene
    /// (particle files) taken from `base`. They are kept absolute, so a
    /// run resumed from its checkpoint finds them from any folder.
    pub fn from_toml_in(text: &str, origin: &str, base: &Path) -> Result<Scene, SceneError> {
        let mut scene: Scene =
            toml::from_str(text).map_err(|e| SceneError::parse(origin, text, &e))?;
        for b in &mut scene.bodies {
            if let Shape::Particles { file } = &mut b.shape {
                let joined = base.join(&*file);
                *file = std::path::absolute(&joined).unwrap_or(joined);
            }
        }
        validate(&scene).map_err(|e| e.in_file(origin))?;
        Ok(scene)
    }

    /// Serialise back to TOML (used by examples that build scenes in code).
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).expect("a Scene always serialises")
    }

    pub fn dim(&self) -> usize {
        self.simulation.dimension as usize
    }

    /// Whether the scene's bodies are bodies of revolution.
    pub fn axisymmetric(&self) -> bool {
        self.simulation.geometry == Geometry::Axisymmetric
    }

    pub fn viscosity(&self) -> ArtificialViscosity {
        self.artificial_viscosity.unwrap_or_default()
    }

    pub fn contact_settings(&self) -> ContactSettings {
        self.contact.unwrap_or_default()
    }

    pub fn history_interval(&self) -> f64 {
        self.output
            .history_interval
            .unwrap_or(self.simulation.end_time / 1000.0)
    }
}
