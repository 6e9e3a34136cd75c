//! The solver's view of a scene: per-body constants, per-particle constants
//! and the initial state. Shared by every backend.

use glam::DVec2;
use std::ops::Range;

use crate::physics::material::MaterialModel;
use crate::physics::strength::History;
use crate::physics::support::{Band, Metric};
use crate::scene::{
    place_bodies, ArtPairs, ArtPlastic, ArtificialStress, Correction, Integrator, Interaction,
    Scene, ViscosityForm,
};

/// One body: its material, its particles (a contiguous range) and flags.
#[derive(Debug, Clone)]
pub struct BodyInfo {
    pub name: String,
    pub material: MaterialModel,
    pub rigid: bool,
    /// The placed spacing Δx (docs/method.md §8.3's `h0`).
    pub spacing: f64,
    pub range: Range<usize>,
    pub velocity0: DVec2,
    /// Fewest same-body neighbours a particle of the body keeps its
    /// corrected gradient with (docs/method.md, "Debris"): the floor of
    /// [`crate::physics::kernel::debris_neighbours`], lowered to the fewest
    /// any of its particles has as placed (a polygon's acute tip); 0
    /// where the gradient is not corrected, in 1-D and for a rigid body.
    pub debris_neighbours: u32,
    /// Whether the body's particles carry the artificial stress `R_i`
    /// (all do, but a body that can yield takes the hourglass control in
    /// its place under `plastic = "hourglass"`: [`crate::scene::ArtPlastic`]).
    pub art: bool,
    /// The hourglass control's coefficient on the body's families of
    /// pairs (0: none; [`Model::hourglass`] is the largest).
    pub hourglass: f64,
    /// The body's centre of mass as placed: the point the GPU's
    /// reductions take its angular momentum about before the host moves
    /// it to the centre of mass (`gpu::probes`), which keeps the f32 sums
    /// free of the cancellation about a distant origin.
    pub centre0: DVec2,
}

/// How far below the yield stress a von Mises stress still counts as on
/// the yield surface ([`Model::flowing`]): above the f32 round-off of the
/// GPU path's return (about 1e-7), far below any elastic approach to it.
pub const YIELD_TOL: f64 = 1e-5;

/// A pair of bodies' Coulomb coefficients (docs/method.md §8.6): the
/// sliding `μ` and the static `μ_s ≥ μ` a sticking contact holds to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coulomb {
    pub sliding: f64,
    pub sticking: f64,
}

/// Everything constant during a run.
#[derive(Debug, Clone)]
pub struct Model {
    pub dim: usize,
    pub interaction: Interaction,
    pub correction: Correction,
    pub cfl: f64,
    pub fixed_dt: Option<f64>,
    pub integrator: Integrator,
    pub alpha: f64,
    pub beta: f64,
    /// Limited reconstruction of the velocity jump in the viscosity.
    pub av_reconstruct: bool,
    /// The viscosity acts on receding pairs too (`form = "riemann"`).
    pub av_release: bool,
    /// Pairs with a surface particle see the reconstructed jump too
    /// (`reconstruct_surfaces`).
    pub av_recon_surface: bool,
    /// The hourglass control's largest coefficient over the bodies (0:
    /// off; docs/method.md, "Hourglass control"); each body's is
    /// [`BodyInfo::hourglass`].
    pub hourglass: f64,
    /// The dispersion correction's `θ` (0: off; docs/method.md §4).
    pub dispersion: f64,
    /// The artificial stress, unless the scene switches it off
    /// (`epsilon = 0`); a scene without the section gets
    /// [`ArtificialStress::DEFAULT`].
    pub artificial_stress: Option<ArtificialStress>,
    /// Each particle's squared spacing scale `κ²` for the close-pair
    /// artificial stress ([`Model::close_scales`]); empty unless the run
    /// uses that form and some `κ²` is below 1 (empty reads as all 1).
    pub close_scale: Vec<f64>,
    pub boundary_threshold: f64,
    pub bodies: Vec<BodyInfo>,
    pub mass: Vec<f64>,
    pub h: Vec<f64>,
    pub body: Vec<u32>,
    /// Surface offset `o` of each particle (docs/method.md §8.3): as
    /// placed, half a spacing where that is deeper than a body's outer
    /// layer can be ([`surface_offset`](crate::physics::penalty::surface_offset)).
    pub offset: Vec<f64>,
    /// `true` when the penalty contact runs: penalty mode and two or more bodies.
    pub contact: bool,
    /// The Coulomb coefficients of every contact (`[contact] friction`
    /// and `static_friction`; 0: frictionless) but the pairs of
    /// [`Model::friction_pairs`].
    pub friction: Coulomb,
    /// `(a, b, coefficients)` with `a < b`: the pairs of bodies with their
    /// own (`[[contact.pairs]]`).
    pub friction_pairs: Vec<(u32, u32, Coulomb)>,
    /// Whether any pair of bodies rubs: the state then carries the slips
    /// and the contact's friction pass runs.
    pub rubs: bool,
    /// The longest step the penalty spring allows
    /// ([`contact_step`](crate::physics::penalty::contact_step), over every
    /// pair of bodies and both sides); infinite without contact. Both
    /// backends take the CFL step or this, the shorter, unless the scene
    /// fixes the step.
    pub contact_dt: f64,
    /// `true` when some material has a yield stress.
    pub plastic: bool,
    /// `true` when some deformable body's material carries a plastic
    /// history (a strength law with hardening, a failure model:
    /// [`MaterialModel::has_history`]): the state then holds
    /// [`State::eps_p`], [`State::temperature`] and [`State::damage`].
    pub history: bool,
    /// `true` when some material's laws depend on the strain rate: the
    /// kinematic pass then keeps each particle's equivalent strain rate.
    pub strain_rate: bool,
    /// `true` when some body is rigid. Without one, [`Model::rigid`]
    /// answers at once instead of looking through the particle's body (the
    /// pair loops ask it for both particles of every pair).
    pub any_rigid: bool,
    /// The box a particle may not leave (`[lower, upper]` corners): see
    /// [`Model::domain_of`].
    pub domain: [DVec2; 2],
    /// Whether the energy guard watches this run, and the energy its limit
    /// adds to the growth of the first state's: see [`Model::guards_energy`].
    pub energy_guard: bool,
    pub energy_floor: f64,
    /// Bodies of revolution (docs/method.md §12): `x` is the radius, masses
    /// are rings', and [`State::rho`] holds `η = 2π r ρ`.
    pub axisymmetric: bool,
    /// The mirror images the kernel sums see (docs/method.md §12, §13):
    /// across the axis of a body of revolution, across the scene's
    /// symmetry plane, and with both across the corner they make (in that
    /// order, the lists' image kinds); none otherwise.
    pub images: Vec<crate::math::Mirror>,
    /// The scene's symmetry planes (at most one per coordinate), each
    /// reversing its own coordinate.
    pub planes: Vec<crate::math::Mirror>,
    /// The images across the symmetry planes alone, across which the
    /// contact also meets the partners' images: each plane's, and with two
    /// the corner's (both reversed).
    pub contact_images: Vec<crate::math::Mirror>,
    /// Each particle's symmetry planes it lies on, a bit per coordinate
    /// the plane reverses (bit 0: x); empty where no particle lies on one
    /// ([`Model::along_plane`]).
    pub on_plane: Vec<u8>,
    /// Each particle's share of itself on the modelled side of the
    /// symmetry planes: ½ for one on a plane, whose mirror image is its
    /// other half (docs/method.md §13, "Particles on the plane"), ¼ for
    /// one on two, 1 elsewhere; empty where no particle lies on one
    /// ([`Model::share`]).
    pub share: Vec<f64>,
    /// Each particle's area in the r–z plane as placed, `m / (2π r₀ ρ₀)`:
    /// its reference volume in the kernel sums of a body of revolution
    /// ([`Model::reference_volume`]). Empty in plane strain.
    pub area0: Vec<f64>,
    /// Supports that follow the deformation (docs/method.md, "Supports
    /// that follow the deformation"): [`State::metric`] holds each
    /// particle's.
    pub adaptive: bool,
    /// The band within which supports stay round ([`Metric::banded`]):
    /// none ([`Band::NONE`]: they follow the deformation from the start,
    /// and wherever supports are fixed) or wider, when [`State::carried`]
    /// holds each particle's carried ellipse.
    pub band: Band,
    /// The variational stress terms (docs/method.md §4,
    /// [`crate::scene::StressForm`]); `false`: the paper's eq. 6.
    pub variational: bool,
    /// The body force per unit mass on the deformable particles
    /// (`[simulation] gravity`), `None` without one.
    pub gravity: Option<DVec2>,
    /// `Σ m x` of the deformable particles as placed: the potential
    /// energy's zero ([`Model::potential_energy`]).
    pub gravity_ref: DVec2,
    /// The clamped and driven regions (`[[bodies.constraints]]`), in the
    /// scene's order.
    pub held: Vec<Held>,
    /// Each particle's constraint, `k + 1` (0: free); empty without any.
    pub held_of: Vec<u32>,
}

/// A clamped or driven region as the solvers apply it
/// (docs/method.md, "Constraints").
#[derive(Debug, Clone, PartialEq)]
pub struct Held {
    pub name: String,
    /// 1 in each component it holds, 0 in a free one.
    pub mask: DVec2,
    /// Its velocity in the held components.
    pub velocity: DVec2,
    /// The particles it holds.
    pub particles: Vec<usize>,
}

impl Held {
    /// `v` with the held components at the region's velocity.
    #[inline]
    pub fn hold(&self, v: DVec2) -> DVec2 {
        DVec2::new(
            if self.mask.x > 0.0 {
                self.velocity.x
            } else {
                v.x
            },
            if self.mask.y > 0.0 {
                self.velocity.y
            } else {
                v.y
            },
        )
    }
}

/// The energy guard's factor ([`Model::guards_energy`]).
pub const ENERGY_GROWTH: f64 = 1.5;

/// The energy guard's floor as a fraction of `Σ m c_L²`
/// ([`Model::guards_energy`]).
pub const ENERGY_FLOOR: f64 = 1e-10;

/// The evolving state: what an integrator advances and a checkpoint saves.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct State {
    pub t: f64,
    pub step: u64,
    pub x: Vec<DVec2>,
    pub v: Vec<DVec2>,
    /// The density the kernel sums weigh particles by, `V = m / rho`: the
    /// density itself in plane strain, the mass per unit area of the r–z
    /// plane `η = 2π r ρ` in a body of revolution ([`Model::density`]
    /// gives the density).
    pub rho: Vec<f64>,
    /// Specific internal energy, J/kg.
    pub e: Vec<f64>,
    /// Deviatoric stress.
    pub s: Vec<crate::math::Sym>,
    /// Cumulative dashpot heat (already booked into `e`), J (per unit area
    /// in 1-D, per unit thickness in 2-D).
    pub heat: f64,
    /// Cumulative artificial dissipation (already booked into `e`): the
    /// work of the viscosity, the artificial stress and the hourglass
    /// control, J (per unit area in 1-D, per unit thickness in 2-D).
    pub dissipation: f64,
    /// Cumulative work the contact forces' spring part absorbed,
    /// `∫ Σ ½ k δ A w dt` (docs/method.md §8.3). On a conservative spring it
    /// equals the stored energy `Σ ¼ k δ² A`; the difference is the energy
    /// the discrete spring lost (`energy_spring_loss` in the summary).
    pub spring_work: f64,
    /// Overlap each boundary particle had when it joined the surface (m),
    /// which its spring does not push against; negative: not a boundary
    /// particle at the last step's start. Empty without contact.
    pub entry: Vec<f64>,
    /// Whether each boundary particle's friction slid at the last return
    /// (it then holds to the sliding coefficient until it sticks again,
    /// docs/method.md §8.6); empty without friction.
    pub sliding: Vec<bool>,
    /// Each boundary particle's elastic tangential slip against the
    /// partner it presses on, m, along `t = ẑ × n` of its pass
    /// (docs/method.md §8.6); empty without friction.
    pub slip: Vec<f64>,
    /// The tangential spring each slip was stored in at the last return,
    /// `f A k_t` (N/m per unit thickness): the stored energy is
    /// `Σ ½ f A k_t u²`; empty without friction.
    pub slip_stiffness: Vec<f64>,
    /// Cumulative frictional heat (already booked into `e` and counted in
    /// [`State::heat`]), J (per unit thickness in 2-D).
    pub friction_heat: f64,
    /// Equivalent plastic strain; empty unless [`Model::history`].
    pub eps_p: Vec<f64>,
    /// Temperature, K (0 for materials without a strength law); empty
    /// unless [`Model::history`].
    pub temperature: Vec<f64>,
    /// Damage in [0, 1] (1: failed); empty unless [`Model::history`].
    pub damage: Vec<f64>,
    /// The time at which each particle failed (the end of the step that
    /// failed it), negative while it holds: −1, or −2 with a void open
    /// ([`crate::physics::strength::VOID_OPEN`]); empty unless
    /// [`Model::history`].
    pub failed_at: Vec<f64>,
    /// Each constraint's impulse on its region so far, N·s (per unit area
    /// in 1-D, per unit thickness in 2-D); empty without constraints.
    pub held_impulse: Vec<DVec2>,
    /// The work the constraints have done on the bodies so far, J (per
    /// unit area in 1-D, per unit thickness in 2-D).
    pub held_work: f64,
    /// Each particle's support metric ([`Metric`]) where supports adapt
    /// ([`Model::adaptive`]) and one of them is not round; empty otherwise
    /// (the bodies' round supports of `h`). Within a band every support
    /// starts round, and the state keeps none until one leaves it
    /// ([`Model::supports_of`]).
    pub metric: Vec<Metric>,
    /// Where supports adapt within a band ([`Model::band`] wider than none): each
    /// particle's carried ellipse, whose banded form is [`State::metric`];
    /// empty otherwise.
    pub carried: Vec<Metric>,
}

/// What the kernel of a pair is made of: the positions, and each
/// particle's support metric where supports adapt (empty: the bodies'
/// round supports of radius `2h`).
#[derive(Debug, Clone, Copy)]
pub struct Frame<'a> {
    pub x: &'a [DVec2],
    pub metric: &'a [Metric],
}

impl<'a> Frame<'a> {
    /// Round supports at positions `x`.
    pub fn round(x: &'a [DVec2]) -> Frame<'a> {
        Frame { x, metric: &[] }
    }
}

impl State {
    /// The state at time 0 with room for `n` particles, none placed.
    fn blank(n: usize) -> State {
        State {
            t: 0.0,
            step: 0,
            x: Vec::with_capacity(n),
            v: Vec::with_capacity(n),
            rho: Vec::with_capacity(n),
            e: vec![0.0; n],
            s: vec![Default::default(); n],
            heat: 0.0,
            dissipation: 0.0,
            spring_work: 0.0,
            entry: Vec::new(),
            slip: Vec::new(),
            sliding: Vec::new(),
            slip_stiffness: Vec::new(),
            friction_heat: 0.0,
            eps_p: Vec::new(),
            temperature: Vec::new(),
            damage: Vec::new(),
            failed_at: Vec::new(),
            metric: Vec::new(),
            carried: Vec::new(),
            held_impulse: Vec::new(),
            held_work: 0.0,
        }
    }

    /// Whether the supports are the bodies' round ones of `h` ([`State::metric`]
    /// empty): the pair sums then take the round kernel's code.
    #[inline]
    pub fn round_supports(&self) -> bool {
        self.metric.is_empty()
    }

    /// The state's positions and supports.
    #[inline]
    pub fn frame(&self) -> Frame<'_> {
        Frame {
            x: &self.x,
            metric: &self.metric,
        }
    }

    /// Particle i's plastic history (the state must carry one).
    #[inline]
    pub fn history(&self, i: usize) -> History {
        History {
            eps_p: self.eps_p[i],
            temperature: self.temperature[i],
            damage: self.damage[i],
        }
    }

    /// Particle i's damage (0 when the state carries no history), taken
    /// as failed while it has a void open
    /// ([`crate::physics::strength::VOID_OPEN`]): it carries the stress of
    /// a failed particle.
    #[inline]
    pub fn damage_of(&self, i: usize) -> f64 {
        if self.failed_at.get(i) == Some(&crate::physics::strength::VOID_OPEN) {
            return crate::physics::strength::FAILED;
        }
        self.damage.get(i).copied().unwrap_or(0.0)
    }
}

mod build;
mod energy;
mod held;
#[cfg(test)]
mod tests;

impl Model {
    /// The Coulomb coefficients between bodies a and b.
    pub fn friction_between(&self, a: u32, b: u32) -> Coulomb {
        let (a, b) = (a.min(b), a.max(b));
        self.friction_pairs
            .iter()
            .find(|p| p.0 == a && p.1 == b)
            .map_or(self.friction, |p| p.2)
    }

    /// The density of particle i at position `x` from its state's
    /// [`State::rho`]: itself in plane strain, `η / 2π r` in a body of
    /// revolution.
    #[inline]
    pub fn density(&self, rho: f64, x: DVec2) -> f64 {
        if self.axisymmetric {
            rho / crate::math::circumference(x.x)
        } else {
            rho
        }
    }

    /// What [`State::rho`] holds for density `rho` at position `x` (the
    /// inverse of [`Model::density`]): `rho` in plane strain, `η = 2π r ρ`
    /// in a body of revolution.
    #[inline]
    pub fn state_rho(&self, rho: f64, x: DVec2) -> f64 {
        if self.axisymmetric {
            rho * crate::math::circumference(x.x)
        } else {
            rho
        }
    }

    /// `V⁰_j`, the volume particle j was made with, in the measure of the
    /// kernel sums: `m_j / ρ₀` in plane strain, its area in the r–z plane
    /// as placed in a body of revolution.
    #[inline]
    pub fn reference_volume(&self, j: usize) -> f64 {
        if self.axisymmetric {
            self.area0[j]
        } else {
            self.mass[j] / self.material(j).rho0
        }
    }

    /// Particle i's share of itself on the modelled side of the symmetry
    /// plane ([`Model::share`]): what its mass, volume and contact area
    /// are of the whole particle's, and what weighs it in the sums that
    /// count particles rather than their volumes.
    #[inline]
    pub fn share(&self, i: usize) -> f64 {
        self.share.get(i).copied().unwrap_or(1.0)
    }

    pub fn len(&self) -> usize {
        self.mass.len()
    }

    pub fn is_empty(&self) -> bool {
        self.mass.is_empty()
    }

    #[inline]
    pub fn rigid(&self, i: usize) -> bool {
        self.any_rigid && self.bodies[self.body[i] as usize].rigid
    }

    #[inline]
    /// Whether the kinematics pass keeps each particle's velocity
    /// gradient for the forces pass: the viscosity's reconstruction or
    /// the hourglass control reads it.
    pub fn keeps_gradient(&self) -> bool {
        self.av_reconstruct || self.hourglass > 0.0
    }

    /// Whether the gradient kept for the viscosity is the step's own
    /// velocity gradient, bit for bit, so that adaptive supports are
    /// carried with it and the GPU keeps no second copy: in the midpoint
    /// rule (the leapfrog's is of the predicted velocities) without the
    /// hourglass control (whose fit replaces the correction where it
    /// falls back).
    pub fn kept_gradient_is_the_steps(&self) -> bool {
        self.av_reconstruct && self.hourglass == 0.0 && self.integrator == Integrator::Midpoint
    }

    /// Whether some artificial term books heat: the viscosity, the
    /// artificial stress or the hourglass control ([`State::dissipation`];
    /// the GPU's `DISS`, which keeps the ledger's sums only then).
    pub fn dissipates(&self) -> bool {
        self.alpha > 0.0
            || self.beta > 0.0
            || self.artificial_stress.is_some()
            || self.hourglass > 0.0
    }

    /// Every body's hourglass coefficient set to `alpha` (as a scene's
    /// `[artificial_viscosity] hourglass` does).
    pub fn set_hourglass(&mut self, alpha: f64) {
        for b in &mut self.bodies {
            b.hourglass = alpha;
        }
        self.hourglass = alpha;
    }

    /// Whether particle i carries the artificial stress ([`BodyInfo::art`]).
    #[inline]
    pub fn takes_art(&self, i: usize) -> bool {
        self.artificial_stress.is_some() && self.bodies[self.body[i] as usize].art
    }

    /// The hourglass control's coefficient on particle i's family of
    /// pairs ([`BodyInfo::hourglass`]).
    #[inline]
    pub fn hourglass_of(&self, i: usize) -> f64 {
        self.bodies[self.body[i] as usize].hourglass
    }

    pub fn material(&self, i: usize) -> &MaterialModel {
        &self.bodies[self.body[i] as usize].material
    }

    /// Whether some pair's artificial stress is keyed on a particle's
    /// plastic flow or its body's yield: `work = "plastic"` or
    /// `"yielding"` in a scene with a yield stress ([`Model::art_heats`];
    /// the GPU's `ART_FLOW`).
    pub fn art_keyed_on_flow(&self) -> bool {
        use crate::scene::ArtWork;
        self.plastic
            && self
                .artificial_stress
                .is_some_and(|a| matches!(a.work, ArtWork::Plastic | ArtWork::Yielding))
    }

    /// Whether particle i's body can yield: deformable, with a finite
    /// yield stress (`work = "yielding"`; the GPU's `ART_BY_BODY`).
    #[inline]
    pub fn yields(&self, i: usize) -> bool {
        let b = &self.bodies[self.body[i] as usize];
        !b.rigid && b.material.y0.is_finite()
    }

    /// Whether the pairs of particle i take only the share of the
    /// artificial stress whose work is heat (docs/method.md, "Only heat"):
    /// everywhere with `work = "heat"`, in a body that can yield with
    /// `"yielding"`, where it flows with `"plastic"`.
    #[inline]
    pub fn art_heats(&self, st: &State, i: usize) -> bool {
        use crate::scene::ArtWork;
        match self.artificial_stress.map(|a| a.work) {
            Some(ArtWork::Heat) => true,
            Some(ArtWork::Yielding) => self.yields(i),
            Some(ArtWork::Plastic) => self.flowing(st, i),
            Some(ArtWork::Either) | None => false,
        }
    }

    /// Whether particle i flows plastically in `st`, for the artificial
    /// stress's `work = "plastic"` (docs/method.md, "Only heat"): it has
    /// plastic strain where the state carries it ([`Model::history`]), or
    /// else its deviatoric stress is on the yield surface (von Mises within
    /// [`YIELD_TOL`] of `y0`: the radial return leaves it there to
    /// round-off). A particle below yield never flows.
    #[inline]
    pub fn flowing(&self, st: &State, i: usize) -> bool {
        if !self.plastic {
            return false;
        }
        if self.history {
            return st.eps_p[i] > 0.0;
        }
        st.s[i].von_mises() >= (1.0 - YIELD_TOL) * self.material(i).y0
    }

    /// The initial spacing `Δp` of particle i's body.
    #[inline]
    pub fn spacing_of(&self, i: usize) -> f64 {
        self.bodies[self.body[i] as usize].spacing
    }

    /// Whether some deformable body's material can fail
    /// ([`MaterialModel::can_fail`]).
    pub fn can_fail(&self) -> bool {
        self.bodies
            .iter()
            .any(|b| !b.rigid && b.material.can_fail())
    }

    /// Whether a deformable body's material has a cavitation pressure
    /// ([`crate::physics::strength::void_state`]).
    pub fn cavitates(&self) -> bool {
        self.bodies
            .iter()
            .any(|b| !b.rigid && b.material.cavitation.is_finite())
    }

    /// The strength laws the deformable bodies use, a bit `1 << id` each
    /// ([`crate::physics::laws::StrengthLaw::device_id`]): the device
    /// compiles the others out.
    pub fn strength_laws(&self) -> u32 {
        self.bodies
            .iter()
            .filter(|b| !b.rigid)
            .filter_map(|b| b.material.strength.as_ref())
            .fold(0, |bits, law| bits | 1 << law.device_id())
    }

    /// The damage laws the deformable bodies use, a bit `1 << id` each (the
    /// device's `FAILURE_LAWS`).
    pub fn failure_laws(&self) -> u32 {
        self.bodies
            .iter()
            .filter(|b| !b.rigid)
            .filter_map(|b| b.material.failure.as_ref())
            .fold(0, |bits, law| bits | 1 << law.device_id())
    }

    /// The equations of state the bodies use, a bit `1 << id` each (the
    /// device's `EOS_LAWS`).
    pub fn eos_laws(&self) -> u32 {
        self.bodies
            .iter()
            .fold(0, |bits, b| bits | 1 << b.material.eos.device_id())
    }

    /// Body name and index within the body of global particle `i`.
    pub fn locate(&self, i: usize) -> (&str, usize) {
        let b = &self.bodies[self.body[i] as usize];
        (&b.name, i - b.range.start)
    }
}

/// What an evaluation tells about the state it was made at, beyond the rates.
#[derive(Debug, Clone, Default)]
pub struct Diagnostics {
    /// The CFL step at this state (docs/method.md §9), from the sound speeds the
    /// evaluation computed anyway.
    pub cfl_dt: f64,
    pub contact: ContactStats,
    /// Particles whose correction matrix fell back to the identity.
    pub correction_fallback: usize,
    /// Boundary particles, when the contact runs.
    pub boundary_count: usize,
    /// Each constraint's force on its region at this state
    /// ([`Model::held_forces`]); empty without constraints.
    pub held_force: Vec<DVec2>,
}

/// Totals per pair of bodies (`a < b`), and the energies of the contact.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContactStats {
    /// `(a, b, total normal force, largest pressure)`.
    pub pairs: Vec<(u32, u32, f64, f64)>,
    /// Stored penalty-spring energy.
    pub stored: f64,
    /// Total dashpot heat rate.
    pub heat_rate: f64,
    /// Rate of change of the stored energy, `Σ dΦ/dt` over the passes at
    /// the booking velocities: the springs' absorbed power.
    pub spring_rate: f64,
    /// The frictional heat rate (part of `heat_rate`; docs/method.md §8.6).
    pub friction_rate: f64,
    /// With friction, `(a, b, [tangential force, Σ A |slip rate|, Σ A])`
    /// over the frictional passes of each pair: the first the friction
    /// force (`Σ f τ A`, positive against the slide of a on b along the
    /// passes' tangents), the other two the contact area's mean slip rate.
    pub tangential: Vec<(u32, u32, [f64; 3])>,
}

impl ContactStats {
    pub fn pair(&self, a: u32, b: u32) -> (f64, f64) {
        let (a, b) = (a.min(b), a.max(b));
        self.pairs
            .iter()
            .find(|p| p.0 == a && p.1 == b)
            .map_or((0.0, 0.0), |p| (p.2, p.3))
    }

    /// The friction force of the pair of bodies a, b and the mean slip rate
    /// of its frictional passes (zeros where it has none).
    pub fn tangential(&self, a: u32, b: u32) -> (f64, f64) {
        let (a, b) = (a.min(b), a.max(b));
        self.tangential
            .iter()
            .find(|p| p.0 == a && p.1 == b)
            .map_or((0.0, 0.0), |p| {
                let [f, slip, area] = p.2;
                (f, if area > 0.0 { slip / area } else { 0.0 })
            })
    }

    pub(crate) fn add_tangential(&mut self, a: u32, b: u32, t: [f64; 3]) {
        let (a, b) = (a.min(b), a.max(b));
        match self.tangential.iter_mut().find(|x| x.0 == a && x.1 == b) {
            Some(x) => (0..3).for_each(|k| x.2[k] += t[k]),
            None => self.tangential.push((a, b, t)),
        }
    }

    pub(crate) fn add(&mut self, a: u32, b: u32, force: f64, p: f64) {
        let (a, b) = (a.min(b), a.max(b));
        match self.pairs.iter_mut().find(|x| x.0 == a && x.1 == b) {
            Some(x) => {
                x.2 += force;
                x.3 = x.3.max(p);
            }
            None => self.pairs.push((a, b, force, p)),
        }
    }
}
