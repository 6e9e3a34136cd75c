//! The CPU reference solver: f64, one function per stage (the oracle the GPU
//! path is checked against), deterministic.
//!
//! One file per stage of the step, each the twin of the shader of the same
//! name ([`crate::stage`]): [`neighbours`], [`kinematics`] (with the EOS and
//! the boundary set), [`forces`], [`contact`], [`reduce`], [`advance`].
//! The kinematic and forces twins are plain gathers, each particle's sums
//! over its own neighbours as the shaders take them. The solver runs the
//! same sums pair by pair ([`sweep`]: each pair evaluated once for both
//! of its particles, the forces four pairs at a time in vector lanes),
//! tested against the gathers to round-off. The leapfrog's step, which
//! keeps each pair's energy vectors for its second half kick, is
//! `leapfrog.rs`; each stage's tests are in `<stage>_tests.rs`.
//!
//! Time integration (docs/method.md §9) is the explicit midpoint rule (RK2, two
//! evaluations a step) or, when the scene asks for it, a kick–drift–kick
//! leapfrog with one evaluation a step ([`CpuSolver::step`]).

pub mod advance;
pub mod axis;
pub mod contact;
#[cfg(test)]
mod contact_tests;
#[cfg(test)]
mod debris_tests;
pub mod dispersion;
pub mod forces;
#[cfg(test)]
mod hourglass_tests;
pub mod kinematics;
mod leapfrog;
pub mod neighbours;
#[cfg(test)]
pub(crate) mod neighbours_tests;
pub mod reduce;
pub mod sweep;

pub use kinematics::{eos_and_stress, eos_and_stress_with};
pub use reduce::cfl_step;
use reduce::support_h;

use advance::{advance, carry_supports, dense, plastic_return, return_with_history, sane};
use kinematics::stress_point;

use glam::DVec2;
use rayon::prelude::*;

use crate::error::Instability;
use crate::math::Sym;
use crate::model::{Diagnostics, Frame, Model, State};
use crate::physics::material;
use crate::scene::Integrator;
use crate::stage::{self, Role, Stage};
use kinematics::StressPoint;

/// Rates of one evaluation. The leapfrog's rates at the end of its step
/// ([`CpuSolver::step`]) carry `dv` and `de` only: it has applied `dρ/dt`
/// and `ds/dt` already, and the next step makes its own.
#[derive(Debug, Clone, Default)]
pub struct Rates {
    pub dv: Vec<DVec2>,
    /// Empty in the leapfrog's carried rates.
    pub drho: Vec<f64>,
    pub de: Vec<f64>,
    /// Empty in the leapfrog's carried rates.
    pub ds: Vec<Sym>,
    /// Equivalent strain rates (`Model::strain_rate`); empty otherwise and
    /// in the leapfrog's carried rates.
    pub rate: Vec<f64>,
    /// Total dashpot heat rate (for the cumulative heat diagnostic).
    pub heat_rate: f64,
    /// Total spring power (for the spring-work ledger).
    pub spring_rate: f64,
    /// Artificial dissipation rate: the power the viscosity, the
    /// artificial stress and the hourglass control book into `de`
    /// (for the ledger's [`State::dissipation`](crate::model::State::dissipation)).
    pub dissipation_rate: f64,
    /// The boundary particles' entry overlaps at the evaluated state
    /// (`(particle, overlap)`, [`contact::write_entries`]); empty without
    /// contact and in the leapfrog's carried rates.
    pub entry: Vec<(u32, f64)>,
    /// The frictional heat rate (part of `heat_rate`).
    pub friction_rate: f64,
    /// The boundary particles' friction at the evaluated state, whose
    /// slip rates advance [`State::slip`] ([`contact::advance_slip`]);
    /// empty without friction.
    pub friction: Vec<(u32, contact::Friction)>,
    /// The velocity gradient the supports are carried with
    /// ([`Kinematics::lv`](kinematics::Kinematics::lv)); empty with round
    /// supports and in the leapfrog's carried rates.
    pub lv: Vec<crate::math::Mat2>,
    /// The debris of the evaluated state (its kinematic pass's fallback
    /// list): the midpoint rule's second evaluation takes the first's, so
    /// that no particle turns to or from debris inside a step (its
    /// acceleration would change between the two evaluations, and the
    /// rule's booking turn that into energy). Empty in the leapfrog's
    /// carried rates.
    pub debris: Vec<u32>,
}

impl Rates {
    /// The leapfrog's carried rates: the accelerations `dv` and energy
    /// rates `de`, no totals.
    pub(crate) fn of_motion(dv: Vec<DVec2>, de: Vec<f64>) -> Rates {
        Rates {
            dv,
            drho: Vec::new(),
            de,
            ds: Vec::new(),
            rate: Vec::new(),
            heat_rate: 0.0,
            spring_rate: 0.0,
            dissipation_rate: 0.0,
            entry: Vec::new(),
            friction_rate: 0.0,
            friction: Vec::new(),
            lv: Vec::new(),
            debris: Vec::new(),
        }
    }
}

/// One full evaluation of the rates at `st`, neighbour lists built for it.
pub fn evaluate(model: &Model, st: &State) -> (Rates, Diagnostics) {
    let nb = neighbours::find(model, st.frame());
    evaluate_with(model, st, &nb)
}

/// One full evaluation of the rates at `st` with candidate lists `nb` that
/// are valid there ([`neighbours::Neighbours::still_valid`]).
pub fn evaluate_with(
    model: &Model,
    st: &State,
    nb: &neighbours::Neighbours,
) -> (Rates, Diagnostics) {
    evaluate_at(model, st, nb, Role::Base, None, &mut Default::default())
}

/// [`evaluate_with`] in the role `role` of the step's schedule
/// ([`crate::stage::MIDPOINT`]): at the midpoint the CFL step is not
/// taken (`cfl_dt` is infinite), as the step's own is the base state's.
///
/// `debris`: the particles to treat as debris instead of the evaluation's
/// own fallback list (the midpoint's, [`Rates::debris`]).
fn evaluate_at(
    model: &Model,
    st: &State,
    nb: &neighbours::Neighbours,
    role: Role,
    debris: Option<&[u32]>,
    kept: &mut dispersion::Kept,
) -> (Rates, Diagnostics) {
    stage::enter(Stage::Kinematics, role);
    let mut k = if model.dispersion > 0.0 {
        sweep::kinematics_keeping(model, st, nb, None, kept)
    } else {
        sweep::kinematics(model, st, nb)
    };
    let pts = eos_and_stress_with(model, st, debris.unwrap_or(&k.fallback));
    // The stresses are the state's: the dispersion correction's two sums
    // take one sweep.
    let extra = (model.dispersion > 0.0).then(|| {
        let (c, s) = dispersion::strain_and_stress(model, st, nb, &k, &pts, kept);
        dispersion::correct_rates(model, st, &mut k, &c);
        s
    });
    stage::enter(Stage::Forces, role);
    let (mut dv, mut de, dissipation_rate) = sweep::rates_and_dissipation(model, st, nb, &k, &pts);
    if let Some(s) = extra {
        dispersion::add_forces(model, st, nb, (&k.l, kept), &s, &mut dv);
        dispersion::add_work(model, st, &s, &k.g, &mut de);
    }
    let mut diag = Diagnostics {
        cfl_dt: f64::INFINITY,
        correction_fallback: k.fallback.len(),
        ..Default::default()
    };
    // The contact's normals and areas, as the GPU's forces stage has them.
    let boundary = model.contact.then(|| {
        let measure = forces::contact_measure(model, &k);
        forces::boundary(model, &st.x, nb, std::mem::take(&mut k.surface), measure)
    });
    let kinematics::Kinematics {
        drho,
        ds,
        rate,
        lv,
        fallback,
        ..
    } = k;
    let mut heat_rate = 0.0;
    let mut spring_rate = 0.0;
    let mut entry = Vec::new();
    let mut friction = Vec::new();
    if let Some(bd) = boundary {
        stage::enter(Stage::Contact, role);
        diag.boundary_count = bd.list.len();
        let mut c = contact::penalty(model, st, nb, &bd);
        entry.clone_from(&c.entry);
        friction = std::mem::take(&mut c.friction);
        // Contact terms exist on boundary particles and, through the
        // normals, on their neighbours.
        c.add_forces(model, &bd, &mut dv);
        for (k, &i) in bd.list.iter().enumerate() {
            let i = i as usize;
            if !model.rigid(i) {
                de[i] += c.heat[k] / model.mass[i];
            }
        }
        heat_rate = c.stats.heat_rate;
        spring_rate = c.stats.spring_rate;
        diag.contact = c.stats;
    }
    if role != Role::Mid {
        stage::enter(Stage::Reduce, Role::Step);
        diag.cfl_dt = cfl_step(model, st, &pts);
    }
    if !model.held.is_empty() {
        diag.held_force = model.held_forces(&dv);
    }
    (
        Rates {
            dv,
            drho,
            de,
            ds,
            rate,
            heat_rate,
            spring_rate,
            dissipation_rate,
            entry,
            friction_rate: diag.contact.friction_rate,
            friction,
            lv,
            debris: fallback,
        },
        diag,
    )
}

/// Outward unit normals and the boundary set at `st`, for output
/// (snapshots): the contact's normals ([`forces::boundary`]) on the
/// surface particles, zero elsewhere. The step never calls this: it costs one
/// neighbour search and one kinematic pass, paid only when a snapshot is written.
/// In kernel mode the SPH sums run across bodies, so faces in contact with
/// another body are not surface there.
pub fn surface(model: &Model, st: &State) -> (Vec<DVec2>, Vec<bool>) {
    let nb = neighbours::find(model, st.frame());
    let a = sweep::kinematics(model, st, &nb);
    let bd = forces::boundary_of(model, &st.x, &nb, &a);
    (bd.normal, bd.is_boundary)
}

/// The CPU solver: the state and the evaluation made at it.
pub struct CpuSolver {
    pub model: Model,
    pub state: State,
    /// Rates and diagnostics at `state` (the first stage of the next step).
    current: Option<(Rates, Diagnostics)>,
    /// Reused buffers: the midpoint state and the next state.
    scratch: State,
    spare: State,
    initial_dt: Option<f64>,
    /// The energy guard's limit ([`Model::guards_energy`]), set at the
    /// first state's evaluation.
    energy_limit: Option<f64>,
    /// Candidate neighbour lists with a skin, rebuilt only when a particle
    /// has moved more than half the skin since the last build.
    nb: neighbours::Neighbours,
    /// List builds so far (a diagnostic of the skin's economy).
    pub list_builds: u64,
    /// The leapfrog's pair vectors of the step's momentum pass
    /// ([`sweep::PairVectors`]), kept between steps for their memory only.
    kept: Vec<sweep::PairVectors>,
    /// The dispersion correction's pairs of the step's evaluation
    /// ([`dispersion::Kept`]), kept between steps for their memory only.
    disp_kept: dispersion::Kept,
}

/// The skin of the CPU neighbour lists as a fraction of the support `2 h`.
/// The candidates grow as `(1 + f)²` (0.15: a third more, each rejected by
/// one distance test per pass) and the lists last while no particle has
/// moved `f h`: at 10 m/s and the CFL step that is some hundreds of steps,
/// at 500 m/s about six, so a rebuild (about half an evaluation) stays a
/// small share either way.
pub const SKIN_FRACTION: f64 = 0.15;

impl CpuSolver {
    pub fn new(model: Model, state: State) -> Self {
        let scratch = state.clone();
        let spare = state.clone();
        Self {
            model,
            state,
            current: None,
            scratch,
            spare,
            initial_dt: None,
            energy_limit: None,
            nb: neighbours::Neighbours::default(),
            list_builds: 0,
            kept: Vec::new(),
            disp_kept: Default::default(),
        }
    }

    /// A solver continuing from a checkpoint: its state, its first step
    /// (the time-step collapse test's reference), the candidate lists it
    /// had, so that every sum keeps its order, and the leapfrog's carried
    /// rates ([`CpuSolver::carried`]).
    pub fn restored(
        model: Model,
        state: State,
        initial_dt: Option<f64>,
        energy_limit: Option<f64>,
        lists: neighbours::Neighbours,
        carried: Option<(Rates, Diagnostics)>,
    ) -> Self {
        let mut s = Self::new(model, state);
        s.initial_dt = initial_dt;
        s.energy_limit = energy_limit;
        s.nb = lists;
        // The rows come back in the order they were indexed in, so this
        // only restores the segment ends (the partition is stable).
        s.nb.index_rows();
        s.nb.index_images(&s.model);
        s.current = carried;
        s
    }

    /// What a checkpoint needs beyond the state: the first step, the
    /// energy guard's limit and the candidate lists.
    pub fn resume_parts(&self) -> (Option<f64>, Option<f64>, &neighbours::Neighbours) {
        (self.initial_dt, self.energy_limit, &self.nb)
    }

    /// The rates a checkpoint must carry: the leapfrog's, which its step
    /// made at the predicted velocity and energy and which an evaluation
    /// of the stored state would not give again. The midpoint rule's are
    /// an evaluation of the state, redone on resume.
    pub fn carried(&self) -> Option<&(Rates, Diagnostics)> {
        match self.model.integrator {
            Integrator::Leapfrog => self.current.as_ref(),
            Integrator::Midpoint => None,
        }
    }

    /// The energy guard's limit, once the first state has been evaluated
    /// (`None` before, or when the run is not guarded).
    pub fn energy_limit(&self) -> Option<f64> {
        self.energy_limit
    }

    /// Make the candidate lists valid for the positions and supports `f`.
    fn refresh_lists(
        model: &Model,
        nb: &mut neighbours::Neighbours,
        builds: &mut u64,
        f: Frame,
        role: Role,
    ) {
        stage::enter(Stage::Neighbours, role);
        if !nb.still_valid(model, f) {
            let h_max = model.h.iter().cloned().fold(0.0, f64::max);
            *nb = neighbours::find_with_skin(model, f, SKIN_FRACTION * 2.0 * h_max);
            *builds += 1;
        }
    }

    /// Rates and diagnostics at the current state (computed once per state).
    pub fn current(&mut self) -> &(Rates, Diagnostics) {
        if self.current.is_none() {
            Self::refresh_lists(
                &self.model,
                &mut self.nb,
                &mut self.list_builds,
                self.state.frame(),
                Role::Base,
            );
            let (r, mut d) = evaluate_at(
                &self.model,
                &self.state,
                &self.nb,
                Role::Base,
                None,
                &mut self.disp_kept,
            );
            if self.model.contact {
                // The base state's entries (the rule is applied anew at
                // the midpoint, and stored only here).
                contact::write_entries(&r.entry, &mut self.state.entry);
            }
            if self.model.rubs {
                d.contact.stored += contact::slip_stored(&self.state);
            }
            self.current = Some((r, d));
        }
        self.current.as_ref().expect("just set")
    }

    pub fn diagnostics(&mut self) -> &Diagnostics {
        &self.current().1
    }

    /// The model, the state and the diagnostics at it, borrowed together.
    pub fn observe(&mut self) -> (&Model, &State, &Diagnostics) {
        self.current();
        let diag = &self.current.as_ref().expect("evaluated above").1;
        (&self.model, &self.state, diag)
    }

    /// The step the next `step` call would take, before clipping.
    pub fn next_dt(&mut self) -> f64 {
        match self.model.fixed_dt {
            Some(dt) => dt,
            None => self.diagnostics().cfl_dt.min(self.model.contact_dt),
        }
    }

    /// Advance one step of at most `max_dt` with the scene's integrator.
    pub fn step(&mut self, max_dt: f64) -> Result<f64, Instability> {
        let dt = self.next_dt().min(max_dt);
        let initial = *self.initial_dt.get_or_insert(dt);
        if !(dt.is_finite() && dt > 1e-6 * initial) && max_dt > 1e-6 * initial {
            return Err(self.instability(0, "time step", dt));
        }
        self.current();
        if self.model.energy_guard {
            // The total the summary and the energy probes report.
            let diag = &self.current.as_ref().expect("evaluated above").1;
            let e = crate::probe::energies(&self.model, &self.state, diag).total();
            let limit = *self.energy_limit.get_or_insert(self.model.energy_limit(e));
            let owed = self.model.energy_owed(&self.state);
            if self.model.energy_outside(limit, e, owed) {
                let i = self.model.guarded_particle(&self.state, limit, e);
                let (q, value) = self.model.energy_quantity(limit, e, owed);
                return Err(self.instability(i, &q, value));
            }
        }
        let (k1, _) = self.current.take().expect("evaluated above");
        if self.model.integrator == Integrator::Leapfrog {
            if !self.leapfrog(k1, dt) {
                // The walk that found it does not say which particle.
                self.check()?;
            }
            return Ok(dt);
        }
        let mut half = std::mem::take(&mut self.scratch);
        stage::enter(Stage::Advance, Role::HalfStep);
        advance(
            &self.model,
            &self.state,
            &self.state.v,
            &k1,
            0.5 * dt,
            false,
            &mut half,
        );
        // The midpoint's sums take the step's supports.
        half.metric.clone_from(&self.state.metric);
        let lists = (&mut self.nb, &mut self.list_builds);
        Self::refresh_lists(&self.model, lists.0, lists.1, half.frame(), Role::Mid);
        let debris = Some(&k1.debris[..]);
        let (k2, _) = evaluate_at(
            &self.model,
            &half,
            &self.nb,
            Role::Mid,
            debris,
            &mut self.disp_kept,
        );
        let mut next = std::mem::take(&mut self.spare);
        stage::enter(Stage::Advance, Role::FullStep);
        advance(&self.model, &self.state, &half.v, &k2, dt, true, &mut next);
        if self.model.rubs {
            // Onto the limit the step's evaluation found.
            contact::return_slip(&self.model, &k2.friction, &mut next);
        }
        // The midpoint evaluation's gradient, carried as it is: it lies
        // half a step ahead, and mapping it back moves no run measurably
        // (docs/hard_cases.md, "Where the shot converges in the step").
        carry_supports(
            &self.model,
            &self.state,
            (&k2.lv, 0.0),
            dt,
            &mut next.metric,
            &mut next.carried,
        );
        next.t = self.state.t + dt;
        next.step = self.state.step + 1;
        self.scratch = half;
        self.spare = std::mem::replace(&mut self.state, next);
        self.check()?;
        Ok(dt)
    }

    /// Bytes of host memory the solver holds for its particles: the model's
    /// per-particle constants, the three states (current, midpoint, next,
    /// with the contact entries and plastic histories a scene carries),
    /// the rates of the current evaluation, the neighbour lists and the
    /// leapfrog's pair vectors (32 B a visited candidate). The
    /// transient arrays of an evaluation are not counted.
    pub fn memory_bytes(&self) -> u64 {
        use std::mem::size_of_val;
        let m = &self.model;
        let model = size_of_val(&m.mass[..])
            + size_of_val(&m.h[..])
            + size_of_val(&m.body[..])
            + size_of_val(&m.offset[..])
            + size_of_val(&m.close_scale[..]);
        let state = |s: &State| {
            size_of_val(&s.x[..])
                + size_of_val(&s.v[..])
                + size_of_val(&s.rho[..])
                + size_of_val(&s.e[..])
                + size_of_val(&s.s[..])
                + size_of_val(&s.entry[..])
                + size_of_val(&s.eps_p[..])
                + size_of_val(&s.temperature[..])
                + size_of_val(&s.damage[..])
                + size_of_val(&s.failed_at[..])
        };
        let states = state(&self.state) + state(&self.scratch) + state(&self.spare);
        let rates = self.current.as_ref().map_or(0, |(r, _)| {
            size_of_val(&r.dv[..])
                + size_of_val(&r.drho[..])
                + size_of_val(&r.de[..])
                + size_of_val(&r.ds[..])
                + size_of_val(&r.rate[..])
        });
        (model
            + states
            + rates
            + self.nb.bytes()
            + size_of_val(&self.kept[..])
            + self.disp_kept.bytes()) as u64
    }

    fn instability(&self, i: usize, quantity: &str, value: f64) -> Instability {
        let (body, particle) = self.model.locate(i);
        Instability {
            step: self.state.step,
            time: self.state.t,
            body: body.to_string(),
            particle,
            quantity: quantity.to_string(),
            value,
        }
    }

    /// Stop on a non-finite value, a particle outside the domain
    /// ([`Model::domain_of`]) or a density outside `[0.1, 10] ρ0` (the
    /// energy guard runs at the start of a step, [`CpuSolver::step`]).
    fn check(&self) -> Result<(), Instability> {
        let st = &self.state;
        let m = &self.model;
        let density = |i: usize| m.density(st.rho[i], st.x[i]);
        let dense = |i: usize| dense(m, i, density(i), st.damage_of(i));
        let bad = (0..m.len())
            .into_par_iter()
            .find_first(|&i| !sane(m, i, st.x[i], st.v[i], st.e[i], st.rho[i], st.damage_of(i)));
        match bad {
            None => Ok(()),
            Some(i) => {
                // The GPU's order (advance.wgsl): the density band before
                // the domain.
                let (q, v) = if !st.x[i].is_finite() {
                    ("position".to_string(), st.x[i].x + st.x[i].y)
                } else if !st.v[i].is_finite() {
                    ("velocity".to_string(), st.v[i].x + st.v[i].y)
                } else if !st.e[i].is_finite() {
                    ("internal energy".to_string(), st.e[i])
                } else if !dense(i) {
                    ("density".to_string(), density(i))
                } else {
                    m.outside_domain(st.x[i])
                };
                Err(self.instability(i, &q, v))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stage::{trace, Scheduled, LEAPFROG, MIDPOINT};

    /// The paper's two steel bars (40 particles each), closing at 20 m/s,
    /// touching from the start.
    fn bars(integrator: Integrator) -> (Model, State) {
        let mut scene = crate::validation::bar_scene(crate::validation::BARS, 40, 1e-8);
        scene.simulation.integrator = integrator;
        Model::new(&scene)
    }

    /// The CPU's step runs the stages of its integrator's schedule
    /// (crate::stage) in the schedule's order; it keeps the scene's
    /// particle order, so it has no reorder, and the leapfrog takes the
    /// next step's CFL step in its finishing walk.
    #[test]
    fn a_step_runs_the_schedule() {
        let integrators = [
            (Integrator::Midpoint, MIDPOINT),
            (Integrator::Leapfrog, LEAPFROG),
        ];
        for (integrator, schedule) in integrators {
            let (model, state) = bars(integrator);
            assert!(model.contact);
            let mut solver = CpuSolver::new(model, state);
            solver.step(f64::INFINITY).expect("a first step");
            let ran = trace::record(|| {
                solver.step(f64::INFINITY).expect("a second step");
            });
            let mut want: Vec<Scheduled> = schedule
                .iter()
                .filter(|e| e.stage != Stage::Reorder)
                .copied()
                .collect();
            if integrator == Integrator::Leapfrog {
                want.rotate_left(1);
            }
            assert_eq!(ran, want, "{integrator:?}");
        }
    }
}
