//! Probes on the device: each probe becomes observation slots (sums or
//! maxima over particles, codes shared with reduce.wgsl) or a particle
//! probe, and a row of the device's ring turns back into probe values.
//!
//! Positions are observed relative to the grid origin (`position_rel` in
//! walk.wgsl) and the origin is added back here, in f64: an absolute f32
//! coordinate near 100 m resolves only 7.6e-6 m, a relative one the f32
//! resolution of the bodies' extent.

use glam::DVec2;

use crate::model::Model;
use crate::probe::Resolved;
use crate::scene::{
    BodyQuantity, ConstraintQuantity, ContactQuantity, EnergyQuantity, ParticleQuantity,
};

const NONE: u32 = u32::MAX;

/// Slot codes of `slot_value` in reduce.wgsl.
mod code {
    pub const MVX: u32 = 0;
    pub const MVY: u32 = 1;
    pub const MX: u32 = 2;
    pub const MY: u32 = 3;
    pub const KINETIC: u32 = 4;
    pub const INTERNAL: u32 = 5;
    pub const PAIR_FORCE: u32 = 6;
    pub const PAIR_PMAX: u32 = 7;
    pub const STORED: u32 = 8;
    pub const HEAT: u32 = 9;
    pub const OWED: u32 = 10;
    pub const DISSIPATION: u32 = 11;
    pub const POTENTIAL: u32 = 12;
    pub const HELD_FX: u32 = 13;
    pub const HELD_FY: u32 = 14;
    /// About a body's centre as placed (`SLOT_C`): `Σ m r × v`, `Σ m |r|²`
    /// and `Σ m r`.
    pub const SPIN: u32 = 15;
    pub const INERTIA: u32 = 16;
    pub const MRX: u32 = 17;
    pub const MRY: u32 = 18;
    /// Coulomb friction: the frictional heat booked; over a pair's
    /// rubbing particles, `Σ f τ A`, `Σ A |slip rate|` and `Σ A`.
    pub const FRICTION_HEAT: u32 = 19;
    pub const TANGENTIAL: u32 = 20;
    pub const SLIP_AREA: u32 = 21;
    pub const RUB_AREA: u32 = 22;
}

/// Where `x` is in `list`, pushed at its end if it is not there.
fn index_of<T: PartialEq>(list: &mut Vec<T>, x: T) -> usize {
    match list.iter().position(|y| *y == x) {
        Some(k) => k,
        None => {
            list.push(x);
            list.len() - 1
        }
    }
}

/// How a probe value is made from a ring row.
#[derive(Debug, Clone)]
enum Expr {
    /// `scale · slot + shift` (the shift: the grid origin's coordinate for
    /// a mean position, else 0).
    Slot(usize, f64, f64),
    /// `value + shift` (the shift as for `Slot`).
    Particle(usize, f64),
    /// Kinetic + internal + stored penalty energy (+ the potential).
    Total(usize, usize, Option<usize>, Option<(usize, f64)>),
    /// The potential energy in the body force: `zero − slot`.
    Potential(usize, f64),
    /// A body's angular velocity about its centre of mass from its sums
    /// about its centre as placed: `Σ m r × v`, `Σ m |r|²`, `Σ m r` (x, y),
    /// `Σ m v` (x, y), and its mass.
    Spin([usize; 6], f64),
    /// `slot / slot` (0 where the second is not positive).
    Ratio(usize, usize),
    /// A value that is zero by construction (the potential without a body
    /// force).
    Zero,
}

/// The device-side form of a scene's probes.
#[derive(Debug, Clone, Default)]
pub struct ProbePlan {
    /// `(code, body or pair a, pair b, op)`; op 1 is a maximum.
    pub slots: Vec<[u32; 4]>,
    /// `(original particle index, quantity code)`.
    pub particles: Vec<[u32; 2]>,
    /// The centres the angular slots take their sums about (their `b`
    /// indexes it), relative to the grid origin.
    centres: Vec<[f32; 2]>,
    exprs: Vec<Expr>,
    /// The slot of the stored penalty energy (always present with contact).
    pub stored: Option<usize>,
    /// The slots of the kinetic and the internal energy the energy guard
    /// reads with the stored one, and of the internal energy held below
    /// zero (present when the run is guarded).
    pub energy: Option<(usize, usize, usize)>,
}

fn particle_code(q: ParticleQuantity) -> u32 {
    match q {
        ParticleQuantity::PositionX => 0,
        ParticleQuantity::PositionY => 1,
        ParticleQuantity::VelocityX => 2,
        ParticleQuantity::VelocityY => 3,
        ParticleQuantity::Density => 4,
        ParticleQuantity::Pressure => 5,
        ParticleQuantity::StressXx => 6,
        ParticleQuantity::StressYy => 7,
        ParticleQuantity::StressXy => 8,
        ParticleQuantity::VonMises => 9,
        ParticleQuantity::InternalEnergy => 10,
        ParticleQuantity::PlasticStrain => 11,
        // The rise above room temperature (strength.wgsl): the plan adds
        // the room temperature.
        ParticleQuantity::Temperature => 12,
        ParticleQuantity::Damage => 13,
        ParticleQuantity::FailureTime => 14,
        ParticleQuantity::StressZz => 15,
    }
}

impl ProbePlan {
    /// `origin`: the grid origin that device positions are relative to.
    pub fn new(probes: &[Resolved], model: &Model, origin: DVec2) -> Self {
        let mut plan = ProbePlan::default();
        if model.contact {
            plan.stored = Some(plan.slot([code::STORED, NONE, NONE, 0]));
        }
        if model.energy_guard {
            plan.energy = Some((
                plan.slot([code::KINETIC, NONE, NONE, 0]),
                plan.slot([code::INTERNAL, NONE, NONE, 0]),
                plan.slot([code::OWED, NONE, NONE, 0]),
            ));
        }
        for p in probes {
            let e = match *p {
                Resolved::Particle(i, q) => {
                    plan.particles.push([i as u32, particle_code(q)]);
                    let shift = match q {
                        ParticleQuantity::PositionX => origin.x,
                        ParticleQuantity::PositionY => origin.y,
                        ParticleQuantity::Temperature => model.material(i).initial_temperature(),
                        _ => 0.0,
                    };
                    Expr::Particle(plan.particles.len() - 1, shift)
                }
                Resolved::Body(b, q) => {
                    let mass: f64 = model.bodies[b].range.clone().map(|i| model.mass[i]).sum();
                    let b = b as u32;
                    let (c, scale, shift) = match q {
                        BodyQuantity::VelocityX => (code::MVX, 1.0 / mass, 0.0),
                        BodyQuantity::VelocityY => (code::MVY, 1.0 / mass, 0.0),
                        BodyQuantity::PositionX => (code::MX, 1.0 / mass, origin.x),
                        BodyQuantity::PositionY => (code::MY, 1.0 / mass, origin.y),
                        BodyQuantity::KineticEnergy => (code::KINETIC, 1.0, 0.0),
                        BodyQuantity::MomentumX => (code::MVX, 1.0, 0.0),
                        BodyQuantity::MomentumY => (code::MVY, 1.0, 0.0),
                        BodyQuantity::AngularVelocity => {
                            let e = plan.spin(model, b as usize, origin, mass);
                            plan.exprs.push(e);
                            continue;
                        }
                    };
                    Expr::Slot(plan.slot([c, b, NONE, 0]), scale, shift)
                }
                Resolved::Contact(a, b, q) => {
                    let (a, b) = (a.min(b), a.max(b));
                    match q {
                        ContactQuantity::Force => {
                            Expr::Slot(plan.slot([code::PAIR_FORCE, a, b, 0]), 1.0, 0.0)
                        }
                        ContactQuantity::PressureMax => {
                            Expr::Slot(plan.slot([code::PAIR_PMAX, a, b, 1]), 1.0, 0.0)
                        }
                        // Without friction, none of either.
                        _ if !model.rubs => Expr::Zero,
                        ContactQuantity::TangentialForce => {
                            Expr::Slot(plan.slot([code::TANGENTIAL, a, b, 0]), 1.0, 0.0)
                        }
                        ContactQuantity::SlipRate => Expr::Ratio(
                            plan.slot([code::SLIP_AREA, a, b, 0]),
                            plan.slot([code::RUB_AREA, a, b, 0]),
                        ),
                    }
                }
                // The force that holds region k against the rates of the
                // state's evaluation (Model::held_forces).
                Resolved::Constraint(k, q) => {
                    let c = match q {
                        ConstraintQuantity::ForceX => code::HELD_FX,
                        ConstraintQuantity::ForceY => code::HELD_FY,
                    };
                    Expr::Slot(plan.slot([c, k as u32, NONE, 0]), 1.0, 0.0)
                }
                Resolved::Energy(q) => match q {
                    EnergyQuantity::Kinetic => {
                        Expr::Slot(plan.slot([code::KINETIC, NONE, NONE, 0]), 1.0, 0.0)
                    }
                    EnergyQuantity::Internal => {
                        Expr::Slot(plan.slot([code::INTERNAL, NONE, NONE, 0]), 1.0, 0.0)
                    }
                    EnergyQuantity::ContactHeat => {
                        Expr::Slot(plan.slot([code::HEAT, NONE, NONE, 0]), 1.0, 0.0)
                    }
                    EnergyQuantity::FrictionHeat if model.rubs => {
                        Expr::Slot(plan.slot([code::FRICTION_HEAT, NONE, NONE, 0]), 1.0, 0.0)
                    }
                    EnergyQuantity::FrictionHeat => Expr::Zero,
                    EnergyQuantity::ArtificialDissipation => {
                        Expr::Slot(plan.slot([code::DISSIPATION, NONE, NONE, 0]), 1.0, 0.0)
                    }
                    EnergyQuantity::Potential => match plan.potential(model, origin) {
                        Some((k, zero)) => Expr::Potential(k, zero),
                        None => Expr::Zero,
                    },
                    EnergyQuantity::Total => Expr::Total(
                        plan.slot([code::KINETIC, NONE, NONE, 0]),
                        plan.slot([code::INTERNAL, NONE, NONE, 0]),
                        plan.stored,
                        plan.potential(model, origin),
                    ),
                },
            };
            plan.exprs.push(e);
        }
        plan
    }

    /// The slot table as the WGSL constants reduce.wgsl is compiled with
    /// (`NSLOTS`, and each slot's code, bodies and operation): the
    /// reductions evaluate this scene's observations and no other.
    pub fn wgsl(&self) -> String {
        let n = self.slots.len();
        let column = |k: usize| -> String {
            if n == 0 {
                // WGSL has no empty arrays; NSLOTS = 0 never reads it.
                return "array<u32, 1>(0u)".to_string();
            }
            let items: Vec<String> = self.slots.iter().map(|s| format!("{}u", s[k])).collect();
            format!("array<u32, {n}>({})", items.join(", "))
        };
        // One line a slot rather than a loop over them: each line's slot
        // is a constant, so the compiler folds its code's branches and
        // keeps the values in registers.
        let fold: String = (0..n)
            .map(|k| {
                let v = k + 1;
                format!("    (*acc)[{v}] = combine({v}u, (*acc)[{v}], slot_value({k}u, i, o));\n")
            })
            .collect();
        let centres = if self.centres.is_empty() {
            "array<vec2<f32>, 1>(vec2<f32>(0.0))".to_string()
        } else {
            let items: Vec<String> = self
                .centres
                .iter()
                .map(|c| format!("vec2<f32>({:?}, {:?})", c[0], c[1]))
                .collect();
            format!(
                "array<vec2<f32>, {}>({})",
                self.centres.len(),
                items.join(", ")
            )
        };
        format!(
            "// The scene's observation slots (gpu::probes::ProbePlan::wgsl).\n\
             const NSLOTS: u32 = {n}u;\n\
             const SLOT_CODE = {};\n\
             const SLOT_A = {};\n\
             const SLOT_B = {};\n\
             const SLOT_OP = {};\n\
             // The centres of the angular slots (SLOT_B indexes them).\n\
             const SLOT_C = {centres};\n\
             // Particle i's value of every slot folded into `acc`.\n\
             fn fold_slots(acc: ptr<function, array<f32, NVALS>>, i: u32, o: Obs) {{\n{fold}}}\n",
            column(0),
            column(1),
            column(2),
            column(3)
        )
    }

    /// A plan with one slot of every code, to check reduce.wgsl alone.
    pub fn sample() -> Self {
        let mut plan = ProbePlan::default();
        for c in code::MVX..=code::MRY {
            let op = (c == code::PAIR_PMAX) as u32;
            let (a, b) = match c {
                code::PAIR_FORCE | code::PAIR_PMAX => (0, 1),
                code::HELD_FX | code::HELD_FY => (0, NONE),
                code::SPIN..=code::MRY => (0, 0),
                _ => (NONE, NONE),
            };
            plan.slot([c, a, b, op]);
        }
        plan.centres.push([0.0, 0.0]);
        plan
    }

    /// With gravity, the slot of `Σ m g·(x − origin)` over the deformable
    /// particles and its value as placed, in f64
    /// ([`Model::gravity_ref`]): the potential is their difference.
    fn potential(&mut self, model: &Model, origin: DVec2) -> Option<(usize, f64)> {
        let g = model.gravity?;
        let mass: f64 = (0..model.len())
            .filter(|&i| !model.rigid(i))
            .map(|i| model.mass[i])
            .sum();
        let zero = g.dot(model.gravity_ref - origin * mass);
        Some((self.slot([code::POTENTIAL, NONE, NONE, 0]), zero))
    }

    /// Body `b`'s angular velocity (of mass `mass`; CPU twin:
    /// `probe::angular_velocity`): its sums about its centre as placed,
    /// where `r` stays of the body's size, moved to its centre of mass in
    /// f64 by the host.
    fn spin(&mut self, model: &Model, b: usize, origin: DVec2, mass: f64) -> Expr {
        let c = model.bodies[b].centre0 - origin;
        let k = index_of(&mut self.centres, [c.x as f32, c.y as f32]) as u32;
        let b = b as u32;
        let slots = [
            self.slot([code::SPIN, b, k, 0]),
            self.slot([code::INERTIA, b, k, 0]),
            self.slot([code::MRX, b, k, 0]),
            self.slot([code::MRY, b, k, 0]),
            self.slot([code::MVX, b, NONE, 0]),
            self.slot([code::MVY, b, NONE, 0]),
        ];
        Expr::Spin(slots, mass)
    }

    fn slot(&mut self, s: [u32; 4]) -> usize {
        index_of(&mut self.slots, s)
    }

    /// Floats per ring row: time (hi, lo), dt, slots, particle probes.
    pub fn row_width(&self) -> usize {
        3 + self.slots.len() + self.particles.len()
    }

    /// Probe values from one ring row (header included).
    pub fn values(&self, row: &[f32]) -> Vec<f64> {
        self.exprs.iter().map(|e| self.value(e, row)).collect()
    }

    /// One probe value from a ring row.
    fn value(&self, e: &Expr, row: &[f32]) -> f64 {
        let slot = |k: usize| row[3 + k] as f64;
        match *e {
            Expr::Slot(k, scale, shift) => slot(k) * scale + shift,
            Expr::Particle(k, shift) => row[3 + self.slots.len() + k] as f64 + shift,
            Expr::Total(k, i, s, u) => {
                slot(k) + slot(i) + s.map_or(0.0, slot) + u.map_or(0.0, |(k, zero)| zero - slot(k))
            }
            Expr::Potential(k, zero) => zero - slot(k),
            Expr::Spin([l, i, rx, ry, px, py], m) => {
                // About the centre of mass: L − M c × V, I − M |c|², c the
                // centre of mass from the centre as placed.
                let c = DVec2::new(slot(rx), slot(ry)) / m;
                let p = DVec2::new(slot(px), slot(py));
                let inertia = slot(i) - m * c.length_squared();
                if inertia > 0.0 {
                    (slot(l) - c.perp_dot(p)) / inertia
                } else {
                    0.0
                }
            }
            Expr::Ratio(a, b) => {
                let d = slot(b);
                if d > 0.0 {
                    slot(a) / d
                } else {
                    0.0
                }
            }
            Expr::Zero => 0.0,
        }
    }

    /// The total energy in a row (the energy guard's value, as an `energy`
    /// probe of quantity `total` reads it; 0 without the guard).
    pub fn guarded_energy(&self, row: &[f32]) -> f64 {
        self.energy.map_or(0.0, |(k, i, _)| {
            self.value(&Expr::Total(k, i, self.stored, None), row)
        })
    }

    /// The internal energy held below zero in a row (the energy guard's;
    /// 0 without the guard).
    pub fn guarded_owed(&self, row: &[f32]) -> f64 {
        self.energy.map_or(0.0, |(_, _, o)| row[3 + o] as f64)
    }

    /// The stored penalty energy in a row (0 without contact).
    pub fn stored_energy(&self, row: &[f32]) -> f64 {
        self.stored.map_or(0.0, |k| row[3 + k] as f64)
    }
}
