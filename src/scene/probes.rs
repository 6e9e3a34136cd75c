//! What a run records (`[[probes]]`) and writes (`[output]`).

use super::*;

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
    /// The angular momentum about the centre of mass over the moment of
    /// inertia about it, rad/s (counter-clockwise positive; CPU path).
    AngularVelocity,
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ContactQuantity {
    Force,
    PressureMax,
    /// The friction force ([`crate::model::ContactStats::tangential`]).
    TangentialForce,
    /// The area-weighted mean slip rate of the frictional passes.
    SlipRate,
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum EnergyQuantity {
    Kinetic,
    Internal,
    ContactHeat,
    /// The frictional part of `ContactHeat` ([`crate::model::State::friction_heat`]).
    FrictionHeat,
    /// The artificial terms' work so far ([`crate::model::State::dissipation`]).
    ArtificialDissipation,
    /// The deformable bodies' potential energy in the body force
    /// (`[simulation] gravity`), zero as placed.
    Potential,
    Total,
}

/// What a `constraint` probe records of a held region.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ConstraintQuantity {
    /// The force the constraint puts on its region.
    ForceX,
    ForceY,
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
    /// A clamped or driven region (`[[bodies.constraints]]`), by its name.
    Constraint {
        name: String,
        constraint: String,
        quantity: ConstraintQuantity,
    },
}

impl Probe {
    pub fn name(&self) -> &str {
        match self {
            Probe::Particle { name, .. }
            | Probe::Body { name, .. }
            | Probe::Contact { name, .. }
            | Probe::Energy { name, .. }
            | Probe::Constraint { name, .. } => name,
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
    /// Draw each snapshot as a PNG of the von Mises stress when the run
    /// ends (`sphcontact render`'s frames).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub snapshot_png: bool,
}
