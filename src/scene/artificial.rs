//! The artificial terms (`[artificial_stress]`, `[artificial_viscosity]`) and
//! the contact's settings (`[contact]`).

use super::*;

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
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ContactSettings {
    /// Boundary-particle threshold on `h |∇ψ|` (docs/method.md §8.1).
    #[serde(default = "default_boundary_threshold")]
    pub boundary_threshold: f64,
    /// Coulomb coefficient `μ` of every contact, rigid walls included
    /// (docs/method.md §8.6); 0: frictionless.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub friction: f64,
    /// The static coefficient `μ_s ≥ μ` a sticking contact holds to
    /// before it slides at `friction` (docs/method.md §8.6); none: `μ`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub static_friction: Option<f64>,
    /// Pairs of bodies whose Coulomb coefficient is not `friction`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pairs: Vec<ContactPair>,
}

/// One pair of bodies' own contact settings (`[[contact.pairs]]`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ContactPair {
    /// The two bodies, by name.
    pub bodies: [String; 2],
    /// Their Coulomb coefficient.
    pub friction: f64,
    /// Their static coefficient; none: their `friction`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub static_friction: Option<f64>,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Default for ContactSettings {
    fn default() -> Self {
        Self {
            boundary_threshold: default_boundary_threshold(),
            friction: 0.0,
            static_friction: None,
            pairs: Vec::new(),
        }
    }
}

pub fn default_boundary_threshold() -> f64 {
    0.3
}
