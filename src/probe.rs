//! Probes: the observables a scene records into `history.csv` (docs/scenes.md,
//! "Probes"), resolved once against the model and evaluated on a state.

use glam::DVec2;

use crate::model::Diagnostics;
use crate::model::{Model, State};
use crate::scene::{
    BodyQuantity, ConstraintQuantity, ContactQuantity, EnergyQuantity, ParticleQuantity, Probe,
    Scene,
};

/// A probe with its body and particle resolved to indices.
#[derive(Debug, Clone)]
pub enum Resolved {
    Particle(usize, ParticleQuantity),
    Body(usize, BodyQuantity),
    Contact(u32, u32, ContactQuantity),
    Energy(EnergyQuantity),
    /// A constraint by its index in [`Model::held`].
    Constraint(usize, ConstraintQuantity),
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
            Probe::Constraint {
                constraint,
                quantity,
                ..
            } => Resolved::Constraint(
                model
                    .held
                    .iter()
                    .position(|c| &c.name == constraint)
                    .expect("validated: probes name known constraints"),
                *quantity,
            ),
        })
        .collect()
}

/// Value of a particle quantity.
pub fn particle_value(model: &Model, st: &State, i: usize, q: ParticleQuantity) -> f64 {
    let rho = model.density(st.rho[i], st.x[i]);
    let p = || model.material(i).pressure_of(rho, st.e[i], st.damage_of(i));
    let history = |a: &[f64]| a.get(i).copied().unwrap_or(0.0);
    match q {
        ParticleQuantity::PositionX => st.x[i].x,
        ParticleQuantity::PositionY => st.x[i].y,
        ParticleQuantity::VelocityX => st.v[i].x,
        ParticleQuantity::VelocityY => st.v[i].y,
        ParticleQuantity::Density => rho,
        ParticleQuantity::Pressure => p(),
        ParticleQuantity::StressXx => st.s[i].xx - p(),
        ParticleQuantity::StressYy => st.s[i].yy - p(),
        ParticleQuantity::StressXy => st.s[i].xy,
        ParticleQuantity::StressZz => st.s[i].zz - p(),
        ParticleQuantity::VonMises => st.s[i].von_mises(),
        ParticleQuantity::InternalEnergy => st.e[i],
        ParticleQuantity::PlasticStrain => history(&st.eps_p),
        ParticleQuantity::Temperature => history(&st.temperature),
        ParticleQuantity::Damage => history(&st.damage),
        ParticleQuantity::FailureTime => st.failed_at.get(i).copied().unwrap_or(-1.0),
    }
}

/// Energies of the whole system (docs/scenes.md, "Probes": `energy`): kinetic,
/// internal (dashpot heat included: it is booked into `e`), cumulative
/// dashpot heat, and total = kinetic + internal + stored penalty energy
/// (+ the potential energy in the body force, with one).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Energies {
    pub kinetic: f64,
    pub internal: f64,
    pub contact_heat: f64,
    /// The frictional part of `contact_heat`.
    pub friction_heat: f64,
    /// Cumulative artificial dissipation (booked into `e`, part of
    /// `internal`): the work of the viscosity, the artificial stress and
    /// the hourglass control ([`State::dissipation`]).
    pub dissipation: f64,
    pub stored: f64,
    /// [`Model::potential_energy`] (0 without gravity).
    pub potential: f64,
}

impl Energies {
    pub fn total(&self) -> f64 {
        self.kinetic + self.internal + self.stored + self.potential
    }
}

pub fn energies(model: &Model, st: &State, diag: &Diagnostics) -> Energies {
    let mut e = Energies {
        contact_heat: st.heat,
        friction_heat: st.friction_heat,
        dissipation: st.dissipation,
        stored: diag.contact.stored,
        potential: model.potential_energy(st),
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

/// Body `b`'s angular momentum about its centre of mass over its moment
/// of inertia about it, rad/s (0 for a body that is one point), from its
/// mass, momentum and centre ([`body_means`]).
pub fn angular_velocity(
    model: &Model,
    st: &State,
    b: usize,
    (m, mv, xc): (f64, DVec2, DVec2),
) -> f64 {
    let vc = mv / m;
    let (mut l, mut inertia) = (0.0, 0.0);
    for i in model.bodies[b].range.clone() {
        let (r, v) = (st.x[i] - xc, st.v[i] - vc);
        l += model.mass[i] * r.perp_dot(v);
        inertia += model.mass[i] * r.length_squared();
    }
    if inertia > 0.0 {
        l / inertia
    } else {
        0.0
    }
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
                    BodyQuantity::AngularVelocity => angular_velocity(model, st, b, (m, mv, mx)),
                }
            }
            Resolved::Contact(a, b, q) => {
                let (force, pmax) = diag.contact.pair(a, b);
                match q {
                    ContactQuantity::Force => force,
                    ContactQuantity::PressureMax => pmax,
                    ContactQuantity::TangentialForce => diag.contact.tangential(a, b).0,
                    ContactQuantity::SlipRate => diag.contact.tangential(a, b).1,
                }
            }
            Resolved::Constraint(k, q) => {
                let f = diag.held_force.get(k).copied().unwrap_or_default();
                match q {
                    ConstraintQuantity::ForceX => f.x,
                    ConstraintQuantity::ForceY => f.y,
                }
            }
            Resolved::Energy(q) => {
                let e = *en.get_or_insert_with(|| energies(model, st, diag));
                match q {
                    EnergyQuantity::Kinetic => e.kinetic,
                    EnergyQuantity::Internal => e.internal,
                    EnergyQuantity::ContactHeat => e.contact_heat,
                    EnergyQuantity::FrictionHeat => e.friction_heat,
                    EnergyQuantity::ArtificialDissipation => e.dissipation,
                    EnergyQuantity::Potential => e.potential,
                    EnergyQuantity::Total => e.total(),
                }
            }
        })
        .collect()
}

/// Which bound of the solid range a particle's state has left
/// ([`out_of_range`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutOfRange {
    /// Specific internal energy below `−10⁻³ c_L²`: heat only adds to it
    /// and the elastic energy it carries is positive.
    NegativeEnergy,
    /// Specific internal energy above `0.1 c_L²` (for metals above the
    /// energy that melts them from room temperature): no solid law applies.
    Energy,
    /// Density outside `[½, 2] ρ₀`: compressed or torn beyond what a solid
    /// at these pressures does (a failed particle may go below ½ρ₀: it
    /// lies in an opening crack).
    Density,
}

impl OutOfRange {
    pub fn name(self) -> &'static str {
        match self {
            OutOfRange::NegativeEnergy => "internal energy below -1e-3 c_L^2",
            OutOfRange::Energy => "internal energy above 0.1 c_L^2",
            OutOfRange::Density => "density outside [0.5, 2] rho0",
        }
    }
}

/// Particle i's state against the solid range, and how far outside it is
/// (the value over its bound, ≥ 1): `None` inside. Rigid particles keep
/// their reference state and are never outside.
pub fn out_of_range(model: &Model, st: &State, i: usize) -> Option<(OutOfRange, f64)> {
    if model.rigid(i) {
        return None;
    }
    let mat = model.material(i);
    let c2 = mat.c_l * mat.c_l;
    let (e, rho) = (st.e[i], model.density(st.rho[i], st.x[i]) / mat.rho0);
    if e < -1e-3 * c2 {
        Some((OutOfRange::NegativeEnergy, -e / (1e-3 * c2)))
    } else if e > 0.1 * c2 {
        Some((OutOfRange::Energy, e / (0.1 * c2)))
    } else if rho > 2.0 || (rho < 0.5 && !crate::physics::strength::failed(st.damage_of(i))) {
        // A failed particle below ½ρ₀ is an opening crack, not a torn solid.
        Some((OutOfRange::Density, (rho / 2.0).max(0.5 / rho)))
    } else {
        None
    }
}

/// The particles outside the solid range: how many in each body, and the
/// one furthest outside `(particle, what, value)` (the value in SI units:
/// J/kg or kg/m³).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OutOfRangeCount {
    pub per_body: Vec<usize>,
    /// Their internal energy, `Σ m e` (J, per unit thickness in 2-D).
    pub internal_energy: f64,
    pub worst: Option<(usize, OutOfRange, f64)>,
}

impl OutOfRangeCount {
    pub fn total(&self) -> usize {
        self.per_body.iter().sum()
    }
}

/// Counts the particles of `st` outside the solid range.
pub fn count_out_of_range(model: &Model, st: &State) -> OutOfRangeCount {
    let mut out = OutOfRangeCount {
        per_body: vec![0; model.bodies.len()],
        internal_energy: 0.0,
        worst: None,
    };
    let mut worst = 0.0;
    for i in 0..model.len() {
        if let Some((what, by)) = out_of_range(model, st, i) {
            out.per_body[model.body[i] as usize] += 1;
            out.internal_energy += model.mass[i] * st.e[i];
            if by > worst {
                worst = by;
                let value = match what {
                    OutOfRange::Density => model.density(st.rho[i], st.x[i]),
                    _ => st.e[i],
                };
                out.worst = Some((i, what, value));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validation::disk_scene;

    /// A state inside the solid range counts nothing; each bound, crossed
    /// by one particle, is counted in its body, and the furthest outside
    /// is named with its value.
    #[test]
    fn states_outside_the_solid_range_are_counted() {
        let (model, mut st) = Model::new(&disk_scene("square", 8.0));
        assert_eq!(count_out_of_range(&model, &st).total(), 0);
        let c2 = model.material(0).c_l.powi(2);
        let last = model.len() - 1;
        st.e[3] = -2e-3 * c2;
        st.e[last] = 0.3 * c2;
        st.rho[5] = 0.4 * model.material(5).rho0;
        // Just inside each bound: not counted.
        st.e[7] = -0.99e-3 * c2;
        st.rho[9] = 1.99 * model.material(9).rho0;
        let c = count_out_of_range(&model, &st);
        assert_eq!(c.total(), 3);
        assert_eq!(c.per_body, vec![2, 1]);
        let held = model.mass[3] * st.e[3] + model.mass[last] * st.e[last];
        assert!((c.internal_energy - held).abs() < 1e-12 * held.abs());
        assert_eq!(c.worst, Some((last, OutOfRange::Energy, 0.3 * c2)));
        assert_eq!(
            out_of_range(&model, &st, 3).map(|o| o.0),
            Some(OutOfRange::NegativeEnergy)
        );
        assert_eq!(
            out_of_range(&model, &st, 5).map(|o| o.0),
            Some(OutOfRange::Density)
        );
    }
}
