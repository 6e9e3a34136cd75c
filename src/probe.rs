//! Probes: the observables a scene records into `history.csv` (SCENES.md,
//! "Probes"), resolved once against the model and evaluated on a state.

use glam::DVec2;

use crate::cpu::Diagnostics;
use crate::model::{Model, State};
use crate::scene::{BodyQuantity, ContactQuantity, EnergyQuantity, ParticleQuantity, Probe, Scene};

/// A probe with its body and particle resolved to indices.
#[derive(Debug, Clone)]
pub enum Resolved {
    Particle(usize, ParticleQuantity),
    Body(usize, BodyQuantity),
    Contact(u32, u32, ContactQuantity),
    Energy(EnergyQuantity),
}

/// Resolve the scene's probes (a `particle` probe picks the particle of its
/// body nearest to `at` at t = 0 and keeps it for the whole run).
pub fn resolve(scene: &Scene, model: &Model, st0: &State) -> Vec<Resolved> {
    let body_index = |name: &str| {
        model
            .bodies
            .iter()
            .position(|b| b.name == name)
            .expect("validated: probes name known bodies")
    };
    scene
        .probes
        .iter()
        .map(|p| match p {
            Probe::Particle {
                body, at, quantity, ..
            } => {
                let b = &model.bodies[body_index(body)];
                let target = DVec2::new(at[0], at.get(1).copied().unwrap_or(0.0));
                let i = b
                    .range
                    .clone()
                    .min_by(|&i, &j| {
                        st0.x[i]
                            .distance_squared(target)
                            .total_cmp(&st0.x[j].distance_squared(target))
                    })
                    .expect("validated: bodies are not empty");
                Resolved::Particle(i, *quantity)
            }
            Probe::Body { body, quantity, .. } => Resolved::Body(body_index(body), *quantity),
            Probe::Contact {
                bodies, quantity, ..
            } => Resolved::Contact(
                body_index(&bodies[0]) as u32,
                body_index(&bodies[1]) as u32,
                *quantity,
            ),
            Probe::Energy { quantity, .. } => Resolved::Energy(*quantity),
        })
        .collect()
}

/// Value of a particle quantity.
pub fn particle_value(model: &Model, st: &State, i: usize, q: ParticleQuantity) -> f64 {
    let p = || model.material(i).pressure(st.rho[i], st.e[i]);
    match q {
        ParticleQuantity::PositionX => st.x[i].x,
        ParticleQuantity::PositionY => st.x[i].y,
        ParticleQuantity::VelocityX => st.v[i].x,
        ParticleQuantity::VelocityY => st.v[i].y,
        ParticleQuantity::Density => st.rho[i],
        ParticleQuantity::Pressure => p(),
        ParticleQuantity::StressXx => st.s[i].xx - p(),
        ParticleQuantity::StressYy => st.s[i].yy - p(),
        ParticleQuantity::StressXy => st.s[i].xy,
        ParticleQuantity::VonMises => st.s[i].von_mises(),
        ParticleQuantity::InternalEnergy => st.e[i],
    }
}

/// Energies of the whole system (SCENES.md `energy` probe): kinetic,
/// internal (dashpot heat included: it is booked into `e`), cumulative
/// dashpot heat, and total = kinetic + internal + stored penalty energy.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Energies {
    pub kinetic: f64,
    pub internal: f64,
    pub contact_heat: f64,
    pub stored: f64,
}

impl Energies {
    pub fn total(&self) -> f64 {
        self.kinetic + self.internal + self.stored
    }
}

pub fn energies(model: &Model, st: &State, diag: &Diagnostics) -> Energies {
    let mut e = Energies {
        contact_heat: st.heat,
        stored: diag.contact.stored,
        ..Default::default()
    };
    for i in 0..model.len() {
        e.kinetic += 0.5 * model.mass[i] * st.v[i].length_squared();
        if !model.rigid(i) {
            e.internal += model.mass[i] * st.e[i];
        }
    }
    e
}

/// Total momentum of the deformable bodies.
pub fn momentum(model: &Model, st: &State) -> DVec2 {
    (0..model.len())
        .filter(|&i| !model.rigid(i))
        .map(|i| st.v[i] * model.mass[i])
        .sum()
}

/// Mass, momentum and mass-weighted mean position and velocity of a body.
pub fn body_means(model: &Model, st: &State, b: usize) -> (f64, DVec2, DVec2, f64) {
    let mut m = 0.0;
    let mut mv = DVec2::ZERO;
    let mut mx = DVec2::ZERO;
    let mut ke = 0.0;
    for i in model.bodies[b].range.clone() {
        m += model.mass[i];
        mv += st.v[i] * model.mass[i];
        mx += st.x[i] * model.mass[i];
        ke += 0.5 * model.mass[i] * st.v[i].length_squared();
    }
    (m, mv, mx / m, ke)
}

/// Evaluate every probe.
pub fn evaluate(probes: &[Resolved], model: &Model, st: &State, diag: &Diagnostics) -> Vec<f64> {
    // Each body's sums and the energies are computed once, however many
    // probes read them.
    let mut en: Option<Energies> = None;
    let mut bodies: Vec<Option<(f64, DVec2, DVec2, f64)>> = vec![None; model.bodies.len()];
    probes
        .iter()
        .map(|p| match *p {
            Resolved::Particle(i, q) => particle_value(model, st, i, q),
            Resolved::Body(b, q) => {
                let (m, mv, mx, ke) = *bodies[b].get_or_insert_with(|| body_means(model, st, b));
                match q {
                    BodyQuantity::VelocityX => mv.x / m,
                    BodyQuantity::VelocityY => mv.y / m,
                    BodyQuantity::PositionX => mx.x,
                    BodyQuantity::PositionY => mx.y,
                    BodyQuantity::KineticEnergy => ke,
                    BodyQuantity::MomentumX => mv.x,
                    BodyQuantity::MomentumY => mv.y,
                }
            }
            Resolved::Contact(a, b, q) => {
                let (force, pmax) = diag.contact.pair(a, b);
                match q {
                    ContactQuantity::Force => force,
                    ContactQuantity::PressureMax => pmax,
                }
            }
            Resolved::Energy(q) => {
                let e = *en.get_or_insert_with(|| energies(model, st, diag));
                match q {
                    EnergyQuantity::Kinetic => e.kinetic,
                    EnergyQuantity::Internal => e.internal,
                    EnergyQuantity::ContactHeat => e.contact_heat,
                    EnergyQuantity::Total => e.total(),
                }
            }
        })
        .collect()
}
