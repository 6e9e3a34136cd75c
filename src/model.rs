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
}

/// How far below the yield stress a von Mises stress still counts as on
/// the yield surface ([`Model::flowing`]): above the f32 round-off of the
/// GPU path's return (about 1e-7), far below any elastic approach to it.
pub const YIELD_TOL: f64 = 1e-5;

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

impl Model {
    /// Whether supports adapt within a band (`Model::band` not none): the
    /// state then carries each particle's ellipse besides its support
    /// ([`State::carried`]).
    #[inline]
    pub fn carries_band(&self) -> bool {
        self.adaptive && !self.band.is_none()
    }

    /// The supports the carried ellipses `carried` give within the band
    /// ([`Metric::banded`]), or none (round supports, [`State::metric`])
    /// while every one of them is round: a scene whose supports stay
    /// inside the band runs the round kernel's code.
    pub fn supports_of(&self, carried: &[Metric], out: &mut Vec<Metric>) {
        use rayon::prelude::*;
        out.clear();
        out.par_extend(
            carried
                .par_iter()
                .enumerate()
                .map(|(i, c)| c.banded(self.h[i], self.band, self.dim)),
        );
        let all_round = out
            .par_iter()
            .enumerate()
            .all(|(i, q)| *q == Metric::round(self.h[i]));
        if all_round {
            out.clear();
        }
    }

    /// Build the model and the initial state of a validated scene.
    pub fn new(scene: &Scene) -> (Model, State) {
        let placed = place_bodies(scene);
        let sim = &scene.simulation;
        let av = scene.viscosity();
        let cs = scene.contact_settings();
        let n: usize = placed.iter().map(|p| p.positions.len()).sum();
        let art = scene.artificial_stress.unwrap_or(ArtificialStress::DEFAULT);
        let mut model = Model {
            dim: scene.dim(),
            interaction: sim.interaction,
            correction: sim.correction,
            cfl: sim.cfl,
            fixed_dt: sim.dt,
            integrator: sim.integrator,
            alpha: av.alpha,
            beta: av.beta,
            av_reconstruct: av.reconstruct,
            av_release: av.form == ViscosityForm::Riemann,
            av_recon_surface: av.reconstruct_surfaces,
            // The bodies' largest, once they are known.
            hourglass: 0.0,
            dispersion: sim.dispersion_correction,
            artificial_stress: Some(art).filter(|a| a.epsilon > 0.0),
            close_scale: Vec::new(),
            boundary_threshold: cs.boundary_threshold,
            bodies: Vec::with_capacity(placed.len()),
            mass: Vec::with_capacity(n),
            h: Vec::with_capacity(n),
            body: Vec::with_capacity(n),
            offset: Vec::with_capacity(n),
            contact: sim.interaction == Interaction::Penalty && scene.bodies.len() > 1,
            contact_dt: f64::INFINITY,
            plastic: false,
            history: false,
            strain_rate: false,
            any_rigid: false,
            domain: [DVec2::ZERO; 2],
            energy_guard: false,
            energy_floor: 0.0,
            axisymmetric: scene.axisymmetric(),
            adaptive: sim.adaptive(),
            band: sim.band(),
            variational: sim.stress_form == crate::scene::StressForm::Variational,
            area0: Vec::new(),
        };
        let mut state = State {
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
            eps_p: Vec::new(),
            temperature: Vec::new(),
            damage: Vec::new(),
            failed_at: Vec::new(),
            metric: Vec::new(),
            carried: Vec::new(),
        };
        for (bi, (b, p)) in scene.bodies.iter().zip(&placed).enumerate() {
            let material = MaterialModel::new(&scene.materials[&b.material]);
            let mut v0 = DVec2::ZERO;
            if let Some(v) = &b.velocity {
                v0.x = v[0];
                if v.len() > 1 {
                    v0.y = v[1];
                }
            }
            let start = model.mass.len();
            let h = sim.smoothing_ratio * p.spacing;
            for k in 0..p.positions.len() {
                model.mass.push(p.masses[k]);
                model.h.push(h);
                model.body.push(bi as u32);
                // As placed; deep particles off the boundary get a fresh
                // surface's below, once the boundary is known.
                model.offset.push(p.offsets[k]);
                state.x.push(p.positions[k]);
                state.v.push(p.velocities.get(k).copied().unwrap_or(v0));
                state
                    .rho
                    .push(model.state_rho(material.rho0, p.positions[k]));
                if model.axisymmetric {
                    model
                        .area0
                        .push(p.masses[k] / state.rho[state.rho.len() - 1]);
                }
            }
            let yields = !b.rigid && material.y0.is_finite();
            model.plastic |= yields;
            model.history |= !b.rigid && material.has_history();
            model.strain_rate |=
                !b.rigid && (material.strength.is_some() || material.failure.is_some());
            model.any_rigid |= b.rigid;
            // A body that can yield takes the hourglass control in place of
            // the artificial stress where the scene says so.
            let keyed = yields && art.plastic == ArtPlastic::Hourglass;
            model.bodies.push(BodyInfo {
                name: b.name.clone(),
                material,
                rigid: b.rigid,
                spacing: p.spacing,
                range: start..model.mass.len(),
                velocity0: v0,
                debris_neighbours: 0,
                art: !keyed,
                hourglass: if keyed {
                    art.plastic_hourglass
                } else {
                    av.hourglass
                },
            });
        }
        model.hourglass = model.bodies.iter().map(|b| b.hourglass).fold(0.0, f64::max);
        if model.bodies.iter().all(|b| !b.art) {
            model.artificial_stress = None;
        }
        if model.carries_band() {
            state.carried = model.h.iter().map(|&h| Metric::round(h)).collect();
        } else if model.adaptive {
            state.metric = model.h.iter().map(|&h| Metric::round(h)).collect();
        }
        let floor = match sim.correction {
            Correction::Gradient => {
                crate::physics::kernel::debris_neighbours(model.dim, sim.smoothing_ratio)
            }
            _ => 0,
        };
        let close = model
            .artificial_stress
            .is_some_and(|a| a.pairs == ArtPairs::Close);
        // One walk of the placed particles serves the debris floor, the
        // close-pair gate's scales and the contact's surface offsets.
        let hoods = if floor > 0 || close || model.contact {
            model.placed_neighbourhoods(&state.x)
        } else {
            Vec::new()
        };
        if model.contact {
            model.contact_dt = model.contact_step();
            for (i, n) in hoods.iter().enumerate() {
                let b = model.body[i] as usize;
                model.offset[i] = crate::physics::penalty::surface_offset(
                    model.offset[i],
                    model.bodies[b].spacing,
                    scene.bodies[b].jitter.unwrap_or(0.0),
                    model.dim,
                    n.hg > model.boundary_threshold,
                );
            }
        }
        if floor > 0 {
            let fewest = model.fewest_neighbours(&hoods);
            for (b, n) in model.bodies.iter_mut().zip(fewest) {
                b.debris_neighbours = if b.rigid { 0 } else { floor.min(n) };
            }
        }
        model.domain = Model::domain_of(&model, &state, sim.end_time);
        model.energy_guard = Model::guards_energy(&model);
        model.energy_floor = ENERGY_FLOOR
            * (0..model.len())
                .filter(|&i| !model.rigid(i))
                .map(|i| model.mass[i] * model.material(i).c_l.powi(2))
                .sum::<f64>();
        if close {
            let k2 = model.close_scales_of(&hoods);
            // All 1 (a square lattice): the gate needs none of them.
            if k2.iter().any(|&k| k < 1.0) {
                model.close_scale = k2;
            }
        }
        if model.history {
            state.eps_p = vec![0.0; model.len()];
            state.damage = vec![0.0; model.len()];
            state.failed_at = vec![-1.0; model.len()];
            state.temperature = (0..model.len())
                .map(|i| model.material(i).initial_temperature())
                .collect();
        }
        if model.contact {
            // Bodies that start overlapping are pushed apart (entry 0).
            state.entry = vec![0.0; model.len()];
        }
        (model, state)
    }

    /// The longest step the penalty spring allows over every pair of
    /// bodies and both sides ([`Model::contact_dt`]).
    fn contact_step(&self) -> f64 {
        let m = |b: &BodyInfo| {
            if b.rigid {
                f64::INFINITY
            } else {
                b.material.m
            }
        };
        let mut dt = f64::INFINITY;
        for (i, a) in self.bodies.iter().enumerate() {
            for (j, b) in self.bodies.iter().enumerate() {
                if i != j {
                    dt = dt.min(crate::physics::penalty::contact_step(
                        a.spacing,
                        a.material.rho0,
                        m(a),
                        b.spacing,
                        m(b),
                    ));
                }
            }
        }
        dt
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

    /// For each particle at positions `x`, from one walk of its own body's
    /// neighbours: the squared distance to the nearest one and how many lie
    /// within `2h` (coincident ones and mirror images excluded), and
    /// `h |∇ψ⁰|`, the colour gradient with the reference volumes that the
    /// boundary test reads (docs/method.md §8.1; in a body of revolution
    /// with the images across the axis, as the solver's test has them, so
    /// that the axis reads as no surface).
    fn placed_neighbourhoods(&self, x: &[DVec2]) -> Vec<Neighbourhood> {
        use rayon::prelude::*;
        let reach = 2.0 * self.h.iter().cloned().fold(0.0, f64::max);
        let cells = crate::math::cells::CellList::build(x, reach);
        (0..self.len())
            .into_par_iter()
            .map(|i| {
                let (mut nearest, mut n) = (f64::INFINITY, 0);
                let mut g = DVec2::ZERO;
                let r2 = 4.0 * self.h[i] * self.h[i];
                cells.for_each_near(x[i], self.dim, |j| {
                    if self.body[j] != self.body[i] {
                        return;
                    }
                    let inv_h = 2.0 / (self.h[i] + self.h[j]);
                    let mut add = |d: DVec2| {
                        let d2 = d.length_squared();
                        if let Some((_, gw)) =
                            crate::physics::kernel::w_grad(self.dim, d, d2, inv_h)
                        {
                            g -= gw * self.reference_volume(j);
                        }
                    };
                    // A body of revolution's images across the axis `r = 0`
                    // fill the neighbourhood as they do in the solver's
                    // boundary test (an image is never nearer than its
                    // particle, so the cells around x_i hold every one
                    // within reach).
                    if self.axisymmetric {
                        add(x[i] - DVec2::new(-x[j].x, x[j].y));
                    }
                    if j != i {
                        let d = x[i] - x[j];
                        let d2 = d.length_squared();
                        nearest = nearest.min(d2);
                        n += u32::from(d2 > 0.0 && d2 < r2);
                        add(d);
                    }
                });
                Neighbourhood {
                    nearest2: nearest,
                    count: n,
                    hg: self.h[i] * g.length(),
                }
            })
            .collect()
    }

    /// The fewest same-body neighbours (within `2h`, no mirror images) any
    /// particle of each body has in the walk's `hoods` (0 for an empty
    /// body).
    fn fewest_neighbours(&self, hoods: &[Neighbourhood]) -> Vec<u32> {
        self.bodies
            .iter()
            .map(|b| {
                hoods[b.range.clone()]
                    .iter()
                    .map(|n| n.count)
                    .min()
                    .unwrap_or(0)
            })
            .collect()
    }

    /// The close-pair gate's spacing scale of each particle, squared:
    /// `κ_i² = (d_i / V0_i^(1/d))²`, `d_i` the distance to its nearest
    /// neighbour of its own body as placed and `V0_i = m_i/ρ0` its volume.
    /// 1 on the square lattice; below 1 where placement (a polar lattice,
    /// jitter) puts a neighbour closer than the volume says, so that the
    /// gate, whose spacing is `κ V̄^(1/d)` with the smaller `κ` of a pair,
    /// stays shut on the lattice as placed. Within 1e-9 of 1 or above it
    /// (and alone in its body) is 1.
    pub fn close_scales(&self, x: &[DVec2]) -> Vec<f64> {
        self.close_scales_of(&self.placed_neighbourhoods(x))
    }

    /// [`Model::close_scales`] from the walk's `hoods`.
    fn close_scales_of(&self, hoods: &[Neighbourhood]) -> Vec<f64> {
        hoods
            .iter()
            .enumerate()
            .map(|(i, &Neighbourhood { nearest2: d2, .. })| {
                let v0 = self.reference_volume(i);
                let s2 = if self.dim == 1 { v0 * v0 } else { v0 };
                // Within round-off of the volume's side is the lattice
                // spacing itself.
                let k2 = d2 / s2;
                if k2 < 1.0 - 1e-9 {
                    k2
                } else {
                    1.0
                }
            })
            .collect()
    }

    /// The energy guard: the total energy (kinetic + internal, dashpot heat
    /// included, + stored penalty energy) may not exceed [`ENERGY_GROWTH`]
    /// times its value at the first state (where bodies built overlapping
    /// on a coarse lattice already hold penalty energy), plus a floor of
    /// [`ENERGY_FLOOR`] `Σ m c_L²`: the energy of a motion at 1e-5 c_L, far
    /// above the round-off energy of bodies at rest (1e-17 of it in f32)
    /// and far below any impact's. The method conserves the total
    /// (docs/method.md §4; the discrete spring loses a little), so energy grown
    /// by half was made by the time integration going unstable: the run
    /// stops instead of finishing with answers that look right and energy
    /// many times the start's. Energy lost by half is as sure a sign: a
    /// blow-up that drives particles to large negative internal energies
    /// (an unstable damping, for one) can leave the total far below the
    /// start while the motion looks tame, so the guard is a band,
    /// [`Model::energy_lower`] below. Both solvers check each state at the start
    /// of the step that leaves it, with the evaluation they make there
    /// anyway. Not watched when a rigid body moves (it does work on what it
    /// pushes).
    pub fn guards_energy(model: &Model) -> bool {
        !model
            .bodies
            .iter()
            .any(|b| b.rigid && b.velocity0 != DVec2::ZERO)
    }

    /// The guard's limit from the total energy `e0` of the first state.
    pub fn energy_limit(&self, e0: f64) -> f64 {
        ENERGY_GROWTH * e0 + self.energy_floor
    }

    /// The initial total energy the upper `limit` was set from
    /// ([`Model::energy_limit`] inverted).
    fn energy_initial(&self, limit: f64) -> f64 {
        (limit - self.energy_floor) / ENERGY_GROWTH
    }

    /// The guard's lower bound for the upper `limit`: the initial total
    /// less as much as the upper bound allows it to grow, `(2 − G) e0 −
    /// floor` (half the initial, less the floor).
    pub fn energy_lower(&self, limit: f64) -> f64 {
        (2.0 - ENERGY_GROWTH) * self.energy_initial(limit) - self.energy_floor
    }

    /// The guard's bound on the internal energy the deformable particles
    /// hold below zero, `owed = Σ m min(e_i, 0)`: as much as the lower
    /// band lets the total lose, `−((G − 1) e0 + floor)`.
    ///
    /// Where the ledger closes (both integrators book their energy
    /// compatibly, docs/method.md §9) a blow-up leaves the total where it
    /// was and shows here instead: the motion a local instability makes is
    /// paid from the internal energy of the particles it drives, which
    /// then hold far below zero what no solid holds (the rubber rings
    /// past the leapfrog's limit for the hourglass control: 2.9 times the
    /// initial energy; rings that rebound intact hold 0.09 of it there,
    /// the penetration runs at most 0.011).
    pub fn energy_owed_bound(&self, limit: f64) -> f64 {
        -((ENERGY_GROWTH - 1.0) * self.energy_initial(limit) + self.energy_floor)
    }

    /// Whether the state has left the guard's band under the upper
    /// `limit`: its total energy `e`, or the internal energy `owed` its
    /// particles hold below zero ([`Model::energy_owed_bound`]).
    pub fn energy_outside(&self, limit: f64, e: f64, owed: f64) -> bool {
        e > limit || e < self.energy_lower(limit) || owed < self.energy_owed_bound(limit)
    }

    /// The quantity of an energy-guard message (both backends) under
    /// `limit`, for the total energy `e` and the energy below zero `owed`
    /// of a state outside the band, and the value it names.
    pub fn energy_quantity(&self, limit: f64, e: f64, owed: f64) -> (String, f64) {
        let e0 = self.energy_initial(limit);
        if e > limit {
            let q = format!("total energy (over {ENERGY_GROWTH} times the initial {e0:.4e})");
            (q, e)
        } else if e < self.energy_lower(limit) {
            let low = 2.0 - ENERGY_GROWTH;
            (
                format!("total energy (below {low} times the initial {e0:.4e})"),
                e,
            )
        } else {
            let share = ENERGY_GROWTH - 1.0;
            let q = format!(
                "internal energy held below zero (over {share} times the initial energy {e0:.4e})"
            );
            (q, owed)
        }
    }

    /// The internal energy the deformable particles of `state` hold below
    /// zero, `Σ m min(e_i, 0)` ([`Model::energy_owed_bound`]).
    pub fn energy_owed(&self, state: &State) -> f64 {
        (0..self.len())
            .filter(|&i| !self.rigid(i))
            .map(|i| self.mass[i] * state.e[i].min(0.0))
            .sum()
    }

    /// The particle an energy-guard message names for the total `e` under
    /// `limit`: the deformable one with the most specific energy `½ v² +
    /// e` (where a growth shows first), or the least where energy was lost
    /// or is held below zero.
    pub fn guarded_particle(&self, state: &State, limit: f64, e: f64) -> usize {
        let sign = if e <= limit { -1.0 } else { 1.0 };
        (0..self.len())
            .filter(|&i| !self.rigid(i))
            .map(|i| (i, sign * (0.5 * state.v[i].length_squared() + state.e[i])))
            .fold((0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a })
            .0
    }

    /// The domain: the bodies' initial bounding box grown on every side by
    /// the larger of its largest side and `T (|v|max + c_L,max)`, with `T`
    /// the end time, `|v|max` the largest initial speed and `c_L,max` the
    /// largest longitudinal wave speed at rest. Nothing in a sound run gets
    /// there: a particle must outrun the fastest wave for the whole run to
    /// leave, so one that does was flung out by an instability. Stopping
    /// then beats computing a particle alone in space, where the GPU's f32
    /// positions lose their precision too.
    pub fn domain_of(model: &Model, state: &State, end_time: f64) -> [DVec2; 2] {
        let (lo, hi) = crate::math::bounds(&state.x);
        let v_max = state.v.iter().map(|v| v.length()).fold(0.0, f64::max);
        let c_max = model
            .bodies
            .iter()
            .map(|b| b.material.c_l)
            .fold(0.0, f64::max);
        let extent = (hi - lo).max_element();
        let margin = extent.max(end_time * (v_max + c_max));
        [lo - DVec2::splat(margin), hi + DVec2::splat(margin)]
    }

    /// Whether `x` lies in the domain ([`Model::domain_of`]).
    #[inline]
    pub fn in_domain(&self, x: DVec2) -> bool {
        let [lo, hi] = self.domain;
        x.cmpge(lo).all() && x.cmple(hi).all()
    }

    /// The quantity and value that name a particle at `x` outside the
    /// domain in an instability message: the coordinate that is out and
    /// the interval it left (both backends).
    pub fn outside_domain(&self, x: DVec2) -> (String, f64) {
        let [lo, hi] = self.domain;
        let (axis, value, a, b) = if x.x < lo.x || x.x > hi.x {
            ("x", x.x, lo.x, hi.x)
        } else {
            ("y", x.y, lo.y, hi.y)
        };
        (
            format!("position {axis} (outside the domain [{a:e}, {b:e}] m)"),
            value,
        )
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

    /// Body name and index within the body of global particle `i`.
    pub fn locate(&self, i: usize) -> (&str, usize) {
        let b = &self.bodies[self.body[i] as usize];
        (&b.name, i - b.range.start)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(lattice: &str, jitter: f64) -> Scene {
        Scene::from_toml_str(
            &format!(
                r#"
                [simulation]
                dimension = 2
                end_time = 1.0e-6
                interaction = "penalty"
                [materials.steel]
                density = 7850.0
                shear_modulus = 77.0e9
                eos = {{ kind = "linear", c0 = 4580.0 }}
                [[bodies]]
                name = "a"
                material = "steel"
                spacing = 1.0e-4
                jitter = {jitter}
                seed = 7
                shape = {{ kind = "disk", center = [0.0, 0.0], radius = 2.0e-3, lattice = "{lattice}" }}
                [[bodies]]
                name = "b"
                material = "steel"
                spacing = 1.0e-4
                shape = {{ kind = "rectangle", min = [3.0e-3, -2.0e-3], max = [5.0e-3, 2.0e-3] }}
                "#
            ),
            "the test scene",
        )
        .expect("a valid scene")
    }

    /// The model keeps the contact's step limit over its pairs of bodies
    /// (two steel bodies of one spacing: `Δx / (√2 c_L)`), infinite
    /// without contact; the CPU solver's step is the shorter of it and the
    /// CFL step, and a fixed step is left as the scene gives it.
    #[test]
    fn contact_step_limit_holds_the_solvers_step() {
        let mut sc = scene("square", 0.0);
        let (m, _) = Model::new(&sc);
        let c = m.bodies[0].material.c_l;
        let limit = 1.0e-4 / (2f64.sqrt() * c);
        assert!(
            (m.contact_dt / limit - 1.0).abs() < 1e-14,
            "{}",
            m.contact_dt
        );
        let next_dt = |sc: &Scene| {
            let (m, st) = Model::new(sc);
            crate::cpu::CpuSolver::new(m, st).next_dt()
        };
        sc.simulation.cfl = 0.9;
        assert_eq!(next_dt(&sc), m.contact_dt);
        sc.simulation.cfl = 0.3;
        assert!(next_dt(&sc) < 0.6 * m.contact_dt);
        sc.simulation.cfl = 0.9;
        sc.simulation.dt = Some(1.2 * m.contact_dt);
        assert_eq!(next_dt(&sc), 1.2 * m.contact_dt);
        sc.simulation.interaction = Interaction::Kernel;
        assert_eq!(Model::new(&sc).0.contact_dt, f64::INFINITY);
    }

    /// Each particle's surface offset as placed, the model and state the
    /// scene builds, and which particles the solver's test puts on the
    /// boundary.
    fn placed_offsets(sc: &Scene) -> (Vec<f64>, Model, State, Vec<bool>) {
        let placed = place_bodies(sc)
            .iter()
            .flat_map(|p| p.offsets.iter().copied())
            .collect();
        let (m, st) = Model::new(sc);
        let (_, boundary) = crate::cpu::surface(&m, &st);
        (placed, m, st, boundary)
    }

    /// Every particle the solver finds on the boundary as placed keeps the
    /// surface offset its placement gave it, on the square and polar
    /// lattices, jittered or not: the fresh surfaces' half spacing goes
    /// only to particles deeper than any outer layer, and to some of them
    /// in each body.
    #[test]
    fn boundary_particles_keep_their_placed_offsets() {
        for (lattice, jitter) in [
            ("square", 0.0),
            ("polar", 0.0),
            ("square", 0.3),
            ("square", 0.45),
        ] {
            let (placed, m, _, boundary) = placed_offsets(&scene(lattice, jitter));
            let mut fresh = vec![0; m.bodies.len()];
            for i in 0..m.len() {
                if boundary[i] {
                    assert_eq!(
                        m.offset[i],
                        placed[i],
                        "{lattice} {jitter}: particle {i} placed {}",
                        placed[i] / m.spacing_of(i)
                    );
                } else if m.offset[i] != placed[i] {
                    assert_eq!(m.offset[i], 0.5 * m.spacing_of(i));
                    fresh[m.body[i] as usize] += 1;
                }
            }
            assert!(
                fresh.iter().all(|&n| n > 100),
                "{lattice} {jitter}: {fresh:?}"
            );
        }
    }

    /// In a body of revolution the axis is no surface: a rod's and a
    /// sphere's particles along it, placed as deep as their distance to
    /// the face or the pole, are off the solver's boundary (which counts
    /// the images across the axis) and carry a fresh surface's half
    /// spacing, while every boundary particle keeps its placed offset.
    /// Kept at their depth, the axis particles of a Taylor rod entered the
    /// contact with surface points spacings in front of them as the face
    /// spread (the face's centre pressed through the wall).
    #[test]
    fn the_axis_of_a_body_of_revolution_is_no_surface() {
        let sc = Scene::from_toml_str(
            r#"
            [simulation]
            dimension = 2
            geometry = "axisymmetric"
            end_time = 1.0e-6
            interaction = "penalty"
            [materials.steel]
            density = 7850.0
            shear_modulus = 77.0e9
            eos = { kind = "linear", c0 = 4580.0 }
            [[bodies]]
            name = "rod"
            material = "steel"
            spacing = 1.0e-4
            shape = { kind = "rectangle", min = [0.0, 0.0], max = [1.6e-3, 3.0e-3] }
            [[bodies]]
            name = "ball"
            material = "steel"
            spacing = 1.0e-4
            shape = { kind = "disk", center = [0.0, 5.0e-3], radius = 1.5e-3, lattice = "polar" }
            "#,
            "the test scene",
        )
        .expect("a valid scene");
        let (placed, m, st, boundary) = placed_offsets(&sc);
        let mut fresh_on_axis = vec![0; m.bodies.len()];
        for i in 0..m.len() {
            let dx = m.spacing_of(i);
            if boundary[i] {
                assert_eq!(m.offset[i], placed[i], "particle {i}");
            } else if placed[i] > crate::physics::penalty::FRESH_DEPTH * dx {
                assert_eq!(m.offset[i], 0.5 * dx, "particle {i} at {}", st.x[i]);
                fresh_on_axis[m.body[i] as usize] += usize::from(st.x[i].x < dx);
            }
        }
        // The rod's axis column below its top's outer layers, the ball's
        // inside its poles'.
        assert!(fresh_on_axis.iter().all(|&n| n >= 10), "{fresh_on_axis:?}");
    }

    /// The close-pair scales: 1 on the square lattice; on a jittered one
    /// the brute-force nearest neighbour of the particle's own body over
    /// its volume's side, capped at 1; the default form computes them and
    /// a scene that switches the term off carries none.
    #[test]
    fn close_scales_are_the_placed_nearest_neighbour() {
        let (m, st) = Model::new(&scene("square", 0.0));
        assert!(m.close_scales(&st.x).iter().all(|&k| k == 1.0));
        assert!(m.close_scale.is_empty(), "all 1: none kept");

        let (m, st2) = Model::new(&scene("square", 0.1));
        let mut below = 0;
        for i in 0..m.len() {
            let d2 = (0..m.len())
                .filter(|&j| j != i && m.body[j] == m.body[i])
                .map(|j| (st2.x[j] - st2.x[i]).length_squared())
                .fold(f64::INFINITY, f64::min);
            let want = (d2 / (m.mass[i] / 7850.0)).min(1.0);
            assert_eq!(m.close_scale.len(), m.len());
            assert!((m.close_scale[i] - want).abs() < 1e-12, "particle {i}");
            below += (want < 0.99) as usize;
        }
        assert!(below > m.bodies[0].range.len() / 2, "{below} below 0.99");
        // The rectangle is not jittered: its scales stay 1.
        let b = m.bodies[1].range.clone();
        assert!(m.close_scale[b].iter().all(|&k| k == 1.0));

        let mut off = scene("square", 0.0);
        off.artificial_stress = Some(ArtificialStress {
            epsilon: 0.0,
            ..ArtificialStress::DEFAULT
        });
        let (m, _) = Model::new(&off);
        assert!(m.artificial_stress.is_none() && m.close_scale.is_empty());
    }
}

/// A particle's own-body neighbourhood as placed ([`Model::placed_neighbourhoods`]).
#[derive(Debug, Clone, Copy)]
struct Neighbourhood {
    /// Squared distance to the nearest neighbour.
    nearest2: f64,
    /// Neighbours within `2h`, coincident ones excluded.
    count: u32,
    /// `h |∇ψ⁰|`, what the boundary test reads.
    hg: f64,
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
}

impl ContactStats {
    pub fn pair(&self, a: u32, b: u32) -> (f64, f64) {
        let (a, b) = (a.min(b), a.max(b));
        self.pairs
            .iter()
            .find(|p| p.0 == a && p.1 == b)
            .map_or((0.0, 0.0), |p| (p.2, p.3))
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
