//! `sphcontact bench`: particle throughput of the two-disk impact (the
//! paper's case 3, square lattice) at chosen particle counts, on the CPU
//! path and on the GPU path.
//!
//! What is timed: whole steps of the impact while the disks are in contact,
//! so that every timed step runs the contact pass on live contact pairs. The
//! paper's disks touch at the origin at t = 0 in the continuum, but on the
//! square lattice the particles nearest the origin sit on flat facets a
//! sagitta short of the circle (about 0.01–0.02 Δx each side), and the
//! contact force only turns positive once the 10 m/s closing speed has taken
//! up that gap: some tens of steps (about 20–30 from 1,000 to 10,000
//! particles). On the coarsest lattices the first touch also chatters (a
//! spike at the first step, then a few steps of zero force). So each run
//! first steps, untimed, until the contact force has stayed positive for
//! [`SETTLE_STEPS`] consecutive steps, and only then times. The impact lasts
//! about 8.4 µs, a few hundred to a few thousand steps depending on the
//! resolution; timed steps stop 60 % of that duration after the approach
//! (which leaves a margin for the late start and short contact of the
//! coarsest lattices), and a longer measurement restarts the impact (rebuild and approach untimed), so no timed step
//! belongs to the rebound after separation. Each record says whether the
//! contact force was still positive at the end (`in_contact`).
//!
//! Not timed: building the scene, the approach to contact (which is also
//! the warm-up: on the GPU, the first batches, after the pipelines are
//! compiled).
//! On the GPU the timed steps run in batches of up to [`RING_LEN`]` − 2`
//! steps, one submission and one readback of the per-step observations each
//! (as in a run): no host round trip per step, and each batch ends with the
//! device idle.

use serde::Serialize;
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::cpu::{neighbours, CpuSolver};
use crate::gpu::profile::StepProfile;
use crate::gpu::work::StepWork;
use crate::gpu::{GpuContext, GpuSolver, RING_LEN};
use crate::model::{Model, State};
use crate::probe::{self, Resolved};
use crate::run::{choose_backend, RunOptions};
use crate::scene::{Backend, Integrator, Scene};
use crate::validation::{disk_scene, DISKS_CONTACT_TIME};

/// Fewer particles than this make too small a disk to say anything about
/// throughput (R/Δx ≈ 4).
pub const MIN_PARTICLES: usize = 100;
/// Beyond this the host memory of the set-up alone is tens of GB.
pub const MAX_PARTICLES: usize = 100_000_000;
/// Timed steps when `--steps` is not given: at least this many, more until
/// the measurement lasts [`TARGET_SECONDS`].
pub const DEFAULT_STEPS: u64 = 20;
pub const TARGET_SECONDS: f64 = 1.0;
/// Consecutive steps of positive contact force that end the untimed
/// approach of each (re)start.
pub const SETTLE_STEPS: u64 = 10;
/// More steps than any approach to contact takes (the lattice gap is at
/// most about Δx/2, closed at 10 m/s in a few hundred CFL steps).
const MAX_APPROACH_STEPS: u64 = 20_000;

/// Real steps profiled with timestamp queries (`--stages`): two periodic
/// reorders' worth.
pub const PROFILE_STEPS: u64 = 2 * crate::gpu::REORDER_EVERY;
/// Timed steps stay within this fraction of the impact's duration, counted
/// from the end of the approach.
const CONTACT_WINDOW: f64 = 0.6;
/// Far beyond any benchmark: the device never reaches its end time.
const END_TIME: f64 = 1.0;

/// Which backends to benchmark.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BenchBackend {
    Cpu,
    Gpu,
    /// What `run --backend auto` would use.
    Auto,
    /// The CPU, and the GPU when there is an adapter.
    All,
}

/// Why a benchmark did not run.
#[derive(Debug, Clone, PartialEq)]
pub enum BenchError {
    /// A bad argument, or a size the adapter cannot hold (exit status 2).
    Input(String),
    /// The GPU was asked for and there is none, or a run failed (exit 1).
    Failed(String),
}

impl BenchError {
    pub fn exit_code(&self) -> i32 {
        match self {
            BenchError::Input(_) => 2,
            BenchError::Failed(_) => 1,
        }
    }
}

impl std::fmt::Display for BenchError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BenchError::Input(m) | BenchError::Failed(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for BenchError {}

/// The bench command's settings.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    pub backend: BenchBackend,
    /// Requested total particle counts.
    pub particles: Vec<usize>,
    /// Timed steps per measurement; `None`: at least [`DEFAULT_STEPS`],
    /// more until the measurement lasts [`TARGET_SECONDS`].
    pub steps: Option<u64>,
    /// Measurements per backend and size (at least 1): the first sets the
    /// steps, the rest repeat them ([`Record::rates`]).
    pub repeat: u32,
    /// Also time each GPU stage alone.
    pub stages: bool,
    /// Time integration of the timed steps.
    pub integrator: Integrator,
    /// Progress lines on stderr.
    pub verbose: bool,
}

/// One GPU stage timed alone.
#[derive(Debug, Clone, Serialize)]
pub struct StageTime {
    pub name: String,
    /// Runs per step (2 for the evaluation stages: base state and midpoint).
    pub calls_per_step: f64,
    pub seconds_per_call: f64,
    /// `calls_per_step × seconds_per_call`.
    pub seconds_per_step: f64,
}

/// One measurement: a backend at one size.
#[derive(Debug, Clone, Serialize)]
pub struct Record {
    /// `cpu` or `gpu`.
    pub backend: String,
    /// GPU: the adapter's name and backend; CPU: the processor's model name
    /// and the worker threads.
    pub adapter: String,
    /// Worker threads of the CPU path; `None` on the GPU.
    pub threads: Option<usize>,
    /// `midpoint` (two evaluations a step) or `leapfrog` (one).
    pub integrator: String,
    pub requested_particles: usize,
    pub particles: usize,
    /// Disk radius over particle spacing that gives `particles`.
    pub r_over_dx: f64,
    /// Timed steps of one measurement.
    pub steps: u64,
    /// Wall time of the median measurement.
    pub wall_seconds: f64,
    /// `particles × steps / wall_seconds`: the median measurement's rate
    /// (of an even count, the slower of the middle two).
    pub particle_steps_per_second: f64,
    /// Every measurement's particle-steps per second, in the order taken
    /// (as many as `--repeat` asked): the spread of this machine's speed.
    pub rates: Vec<f64>,
    /// CPU: divided by the worker threads; `None` on the GPU.
    pub particle_steps_per_second_per_core: Option<f64>,
    /// Neighbours within `2 h` per particle at t = 0 (SPH partners and
    /// contact candidates), the work behind one particle-step.
    pub mean_neighbours: f64,
    /// GPU: device memory of the run; CPU: host memory of the solver.
    pub bytes_per_particle: f64,
    /// `device` or `host`.
    pub memory_kind: String,
    /// The contact force was positive at the last timed state.
    pub in_contact: bool,
    /// GPU stages timed alone (with `--stages`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stages: Option<Vec<StageTime>>,
    /// GPU work per step (with `--stages`): dispatches, walks, and each
    /// walk's candidates and group trips counted from the cell list.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub work: Option<StepWork>,
    /// Each GPU dispatch's time inside real steps (with `--stages`, where
    /// the adapter has timestamp queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step_profile: Option<StepProfile>,
}

/// R/Δx whose square-lattice disks (two of them) hold the total particle
/// count closest to `particles`, and that count.
///
/// A lattice point `((i + ½)Δx, (j + ½)Δx)` is inside the disk when
/// `(i + ½)² + (j + ½)² < (R/Δx)²`, i.e. when the integer `q = i² + i + j² + j`
/// is below `(R/Δx)² − ½`. Sorting the q of the points near the expected
/// radius gives every achievable count; `(R/Δx)² = q + 1` sits half-way
/// between two achievable thresholds, so round-off in the placement cannot
/// move a point across the circle.
pub fn lattice_radius(particles: usize) -> (f64, usize) {
    let per_disk = particles as f64 / 2.0;
    let r = (per_disk / std::f64::consts::PI).sqrt();
    let n = (1.2 * r).ceil() as i64 + 2;
    // One quadrant: i ↦ −1 − i leaves q unchanged, so each point of the
    // quadrant i, j ≥ 0 stands for four.
    let mut q: Vec<i64> = Vec::with_capacity((n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            q.push(i * i + i + j * j + j);
        }
    }
    q.sort_unstable();
    // Points up to each distinct q: (total count, that q).
    let mut best = (usize::MAX, 0i64);
    let mut k = 0;
    while k < q.len() {
        let v = q[k];
        while k < q.len() && q[k] == v {
            k += 1;
        }
        let total = 2 * 4 * k;
        if total.abs_diff(particles) < best.0.abs_diff(particles) {
            best = (total, v);
        }
        if total > particles {
            break;
        }
    }
    (((best.1 + 1) as f64).sqrt(), best.0)
}

/// `Err` (bad input) outside [`MIN_PARTICLES`]..=[`MAX_PARTICLES`].
pub fn check_particles(particles: usize) -> Result<(), BenchError> {
    if particles < MIN_PARTICLES {
        return Err(BenchError::Input(format!(
            "--particles must be at least {MIN_PARTICLES} (got {particles})"
        )));
    }
    if particles > MAX_PARTICLES {
        return Err(BenchError::Input(format!(
            "--particles must be at most {MAX_PARTICLES} (got {particles})"
        )));
    }
    Ok(())
}

/// The disk impact at one size, with everything the backends start from.
#[derive(Clone)]
pub struct DiskCase {
    pub requested: usize,
    pub r_over_dx: f64,
    pub scene: Scene,
    pub model: Model,
    pub state: State,
    pub probes: Vec<Resolved>,
}

impl DiskCase {
    /// The case closest to `particles` in all (see [`lattice_radius`]).
    pub fn new(particles: usize) -> Result<Self, BenchError> {
        check_particles(particles)?;
        let (r_over_dx, _) = lattice_radius(particles);
        let mut scene = disk_scene("square", r_over_dx);
        scene.simulation.end_time = END_TIME;
        let (model, state) = Model::new(&scene);
        let probes = probe::resolve(&scene, &model, &state);
        Ok(Self {
            requested: particles,
            r_over_dx,
            scene,
            model,
            state,
            probes,
        })
    }

    pub fn particles(&self) -> usize {
        self.model.len()
    }

    /// The same case stepped by integrator `i`.
    pub fn with_integrator(mut self, i: Integrator) -> Self {
        self.scene.simulation.integrator = i;
        self.model.integrator = i;
        self
    }

    /// The step a timed run stops at, from the step `onset` that ended
    /// the approach and the step size `dt` there.
    fn window_end(dt: f64, onset: u64) -> u64 {
        onset + ((CONTACT_WINDOW * DISKS_CONTACT_TIME / dt).floor() as u64).max(1)
    }
}

/// The CPU path stepping the disk impact, restarting it when a timed run
/// would leave the contact phase.
pub struct CpuBench {
    model: Model,
    initial: State,
    solver: CpuSolver,
    /// The step index a timed run stops at (the end of the contact window).
    cap: u64,
    /// The step at which the approach to contact ended.
    pub onset: u64,
}

impl CpuBench {
    /// Build the solver and step it, untimed, into contact.
    pub fn new(case: &DiskCase) -> Result<Self, BenchError> {
        let mut b = Self {
            model: case.model.clone(),
            initial: case.state.clone(),
            solver: CpuSolver::new(case.model.clone(), case.state.clone()),
            cap: 0,
            onset: 0,
        };
        b.start()?;
        Ok(b)
    }

    /// From t = 0: steps until the contact force has been positive for
    /// [`SETTLE_STEPS`] consecutive states.
    fn start(&mut self) -> Result<(), BenchError> {
        self.solver = CpuSolver::new(self.model.clone(), self.initial.clone());
        let mut dt = 0.0;
        let mut run = 0;
        while run < SETTLE_STEPS {
            if self.solver.state.step >= MAX_APPROACH_STEPS {
                return Err(BenchError::Failed(format!(
                    "the CPU benchmark's disks did not settle into contact in {MAX_APPROACH_STEPS} steps"
                )));
            }
            // (The evaluation this needs is the step's first stage, reused.)
            run = if self.in_contact() { run + 1 } else { 0 };
            dt = self.step()?;
        }
        self.onset = self.solver.state.step;
        self.cap = DiskCase::window_end(dt, self.onset);
        Ok(())
    }

    fn step(&mut self) -> Result<f64, BenchError> {
        self.solver
            .step(f64::MAX)
            .map_err(|e| BenchError::Failed(format!("the CPU benchmark run failed: {e}")))
    }

    /// Wall time of `steps` steps. Call the observers (`memory_bytes`,
    /// `in_contact`) only after timing: they evaluate the current state,
    /// which the next step would then reuse untimed.
    pub fn time_steps(&mut self, steps: u64) -> Result<Duration, BenchError> {
        let mut wall = Duration::ZERO;
        let mut left = steps;
        while left > 0 {
            if self.solver.state.step >= self.cap {
                self.start()?;
            }
            let chunk = left.min(self.cap - self.solver.state.step);
            let start = Instant::now();
            for _ in 0..chunk {
                self.step()?;
            }
            wall += start.elapsed();
            left -= chunk;
        }
        Ok(wall)
    }

    /// The particles' constants.
    pub fn model(&self) -> &Model {
        &self.solver.model
    }

    /// The current state (in contact once `new` has returned).
    pub fn state(&self) -> &State {
        &self.solver.state
    }

    /// Host bytes of the solver, its current evaluation included.
    pub fn memory_bytes(&mut self) -> u64 {
        self.solver.current();
        self.solver.memory_bytes()
    }

    /// The contact force is positive at the current state.
    pub fn in_contact(&mut self) -> bool {
        self.solver.diagnostics().contact.pair(0, 1).0 > 0.0
    }
}

/// The GPU path stepping the disk impact in batches, restarting it when a
/// timed run would leave the contact phase.
pub struct GpuBench {
    ctx: Arc<GpuContext>,
    case: DiskCase,
    solver: GpuSolver,
    /// Steps taken since the last (re)start.
    steps: u64,
    /// The step a timed run stops at (the end of the contact window).
    cap: u64,
    force_probe: usize,
    last_force: f64,
    /// Consecutive observed states with a positive contact force.
    contact_run: u64,
    /// The step at which the approach to contact ended.
    pub onset: u64,
}

impl GpuBench {
    /// Upload the case and step it, untimed, into contact. `Err` (bad
    /// input) when the adapter cannot hold it.
    pub fn new(ctx: Arc<GpuContext>, case: &DiskCase) -> Result<Self, BenchError> {
        let force_probe = case
            .scene
            .probes
            .iter()
            .position(|p| p.name() == "contact_force")
            .ok_or_else(|| {
                BenchError::Failed("the disk scene has no contact_force probe".into())
            })?;
        let solver = Self::upload(&ctx, case)?;
        let mut b = Self {
            ctx,
            case: case.clone(),
            solver,
            steps: 0,
            cap: 0,
            force_probe,
            last_force: 0.0,
            contact_run: 0,
            onset: 0,
        };
        b.approach()?;
        Ok(b)
    }

    /// A fresh solver; a device out of memory is an error, not wgpu's
    /// default panic.
    fn upload(ctx: &Arc<GpuContext>, case: &DiskCase) -> Result<GpuSolver, BenchError> {
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let solver = GpuSolver::new(
            ctx.clone(),
            case.model.clone(),
            &case.state,
            &case.probes,
            END_TIME,
        );
        let oom = pollster::block_on(scope.pop());
        if let Some(e) = oom {
            return Err(BenchError::Input(format!(
                "the GPU ran out of memory for {} particles ({e}); use fewer particles",
                case.particles()
            )));
        }
        solver.map_err(BenchError::Input)
    }

    /// From the solver's start: batches of [`SETTLE_STEPS`] steps until
    /// the contact force has been positive for that many consecutive
    /// states.
    fn approach(&mut self) -> Result<(), BenchError> {
        self.contact_run = 0;
        while self.contact_run < SETTLE_STEPS {
            if self.steps >= MAX_APPROACH_STEPS {
                return Err(BenchError::Failed(format!(
                    "the GPU benchmark's disks did not settle into contact in {MAX_APPROACH_STEPS} steps"
                )));
            }
            self.batch(SETTLE_STEPS)?;
        }
        self.onset = self.steps;
        self.cap = DiskCase::window_end(self.solver.last_dt(), self.onset);
        Ok(())
    }

    fn batch(&mut self, steps: u64) -> Result<(), BenchError> {
        let batch = self.solver.run_batch(steps as u32);
        self.observe(batch, steps)
    }

    /// The contact force of a batch's states, which should be `steps`.
    fn observe(&mut self, batch: crate::gpu::Batch, steps: u64) -> Result<(), BenchError> {
        if let Some(f) = batch.failure {
            return Err(BenchError::Failed(format!(
                "the GPU benchmark run failed: {f}"
            )));
        }
        if batch.done || batch.states.len() as u64 != steps {
            return Err(BenchError::Failed(format!(
                "the GPU benchmark batch of {steps} steps delivered {} states",
                batch.states.len()
            )));
        }
        for (_, obs, _) in &batch.states {
            self.last_force = obs[self.force_probe];
            self.contact_run = if self.last_force > 0.0 {
                self.contact_run + 1
            } else {
                0
            };
        }
        self.steps += steps;
        Ok(())
    }

    /// The impact restarted (and stepped into contact again) where fewer
    /// than `steps` steps of its contact window are left.
    fn room_for(&mut self, steps: u64) -> Result<(), BenchError> {
        if self.steps + steps > self.cap {
            self.solver = Self::upload(&self.ctx, &self.case)?;
            self.steps = 0;
            self.approach()?;
        }
        Ok(())
    }

    /// Wall time of `steps` steps, batch by batch, each ending with the
    /// device idle.
    pub fn time_steps(&mut self, steps: u64) -> Result<Duration, BenchError> {
        let mut wall = Duration::ZERO;
        let mut left = steps;
        while left > 0 {
            self.room_for(1)?;
            let chunk = left.min(self.cap - self.steps).min(RING_LEN as u64 - 2);
            let start = Instant::now();
            self.batch(chunk)?;
            wall += start.elapsed();
            left -= chunk;
        }
        Ok(wall)
    }

    /// Each dispatch's time inside [`PROFILE_STEPS`] real steps of the
    /// contact, from timestamp queries; `None` where the adapter has none.
    pub fn profile_steps(&mut self) -> Result<Option<StepProfile>, BenchError> {
        if !self.ctx.timestamps {
            return Ok(None);
        }
        self.room_for(PROFILE_STEPS)?;
        let (batch, profile) = self
            .solver
            .run_batch_profiled(PROFILE_STEPS as u32)
            .map_err(BenchError::Failed)?;
        self.observe(batch, profile.steps as u64)?;
        Ok(Some(profile))
    }

    /// The solver (for timing its stages alone).
    pub fn solver(&mut self) -> &mut GpuSolver {
        &mut self.solver
    }

    /// The contact force was positive at the last state a batch observed
    /// (the state the last step started from).
    pub fn in_contact(&self) -> bool {
        self.last_force > 0.0
    }

    /// Each stage of [`GpuSolver::stage_names`] timed alone at the current
    /// state: one untimed repetition, then enough to last about
    /// `seconds` (at most 256).
    pub fn time_stages(&mut self, seconds: f64) -> Result<Vec<StageTime>, BenchError> {
        let mut out = Vec::new();
        for name in self.solver.stage_names() {
            let fail = |e: String| BenchError::Failed(format!("timing GPU stage {name}: {e}"));
            let once = self.solver.time_stage(name, 1).map_err(fail)?;
            let reps = (seconds / once.as_secs_f64().max(1e-9))
                .ceil()
                .clamp(1.0, 256.0) as u32;
            let t = self.solver.time_stage(name, reps).map_err(fail)?;
            let per_call = t.as_secs_f64() / reps as f64;
            let calls = self.solver.stage_per_step(name);
            out.push(StageTime {
                name: name.to_string(),
                calls_per_step: calls,
                seconds_per_call: per_call,
                seconds_per_step: calls * per_call,
            });
        }
        Ok(out)
    }
}

/// The processor's model name (from /proc/cpuinfo where there is one).
pub fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

/// Steps, then the wall time of each of `repeat` measurements: the first
/// of exactly `fixed` steps, or of [`DEFAULT_STEPS`] and then more until
/// it lasts [`TARGET_SECONDS`]; the others of the first's steps.
fn measure(
    fixed: Option<u64>,
    repeat: u32,
    mut time: impl FnMut(u64) -> Result<Duration, BenchError>,
) -> Result<(u64, Vec<f64>), BenchError> {
    let (steps, first) = measure_once(fixed, &mut time)?;
    let mut walls = vec![first];
    for _ in 1..repeat {
        walls.push(time(steps)?.as_secs_f64());
    }
    Ok((steps, walls))
}

/// The first measurement of [`measure`].
fn measure_once(
    fixed: Option<u64>,
    mut time: impl FnMut(u64) -> Result<Duration, BenchError>,
) -> Result<(u64, f64), BenchError> {
    if let Some(k) = fixed {
        return Ok((k, time(k)?.as_secs_f64()));
    }
    let mut steps = DEFAULT_STEPS;
    let mut wall = time(steps)?.as_secs_f64();
    if wall < TARGET_SECONDS {
        let per_step = (wall / steps as f64).max(1e-9);
        let more = (((TARGET_SECONDS - wall) / per_step).ceil() as u64).clamp(1, 1_000_000);
        wall += time(more)?.as_secs_f64();
        steps += more;
    }
    Ok((steps, wall))
}

/// The backends to run: the CPU flag and the GPU context.
fn backends(
    which: BenchBackend,
    verbose: bool,
) -> Result<(bool, Option<Arc<GpuContext>>), BenchError> {
    match which {
        BenchBackend::Cpu => Ok((true, None)),
        BenchBackend::Gpu => match crate::gpu::shared_context() {
            Ok(ctx) => Ok((false, Some(ctx))),
            Err(e) => Err(BenchError::Failed(format!(
                "bench --backend gpu: {e}; use --backend cpu (or all)"
            ))),
        },
        BenchBackend::Auto => {
            // The choice `run --backend auto` makes (it needs a scene only
            // for its own backend key, overridden here).
            let scene = disk_scene("square", 5.0);
            let opts = RunOptions {
                backend: Some(Backend::Auto),
                ..Default::default()
            };
            let choice =
                choose_backend(&scene, &opts).map_err(|e| BenchError::Failed(e.to_string()))?;
            if let (Some(w), true) = (&choice.warning, verbose) {
                eprintln!("warning: {w}");
            }
            Ok((choice.gpu.is_none(), choice.gpu))
        }
        BenchBackend::All => match crate::gpu::shared_context() {
            Ok(ctx) => Ok((true, Some(ctx))),
            Err(e) => {
                if verbose {
                    eprintln!("bench: {e}; CPU only");
                }
                Ok((true, None))
            }
        },
    }
}

/// Run the benchmark: one record per backend and size.
pub fn bench(opts: &BenchOptions) -> Result<Vec<Record>, BenchError> {
    if opts.particles.is_empty() {
        return Err(BenchError::Input(
            "--particles needs at least one count".into(),
        ));
    }
    // Every size is checked before anything runs.
    for &n in &opts.particles {
        check_particles(n)?;
    }
    if opts.steps == Some(0) {
        return Err(BenchError::Input(
            "--steps must be at least 1 (got 0)".into(),
        ));
    }
    if opts.repeat == 0 {
        return Err(BenchError::Input(
            "--repeat must be at least 1 (got 0)".into(),
        ));
    }
    let (cpu, gpu) = backends(opts.backend, opts.verbose)?;
    let threads = rayon::current_num_threads();
    let cpu_adapter = format!("cpu: {} ({threads} threads)", cpu_name());
    let mut records = Vec::new();
    for &n in &opts.particles {
        let case = DiskCase::new(n)?.with_integrator(opts.integrator);
        let particles = case.particles();
        let record = |backend: &str, adapter: &str, steps: u64, walls: Vec<f64>| {
            let rate = |wall: f64| (steps * particles as u64) as f64 / wall.max(1e-12);
            let mut sorted = walls.clone();
            sorted.sort_by(f64::total_cmp);
            let wall = sorted[sorted.len() / 2];
            Record {
                backend: backend.into(),
                adapter: adapter.into(),
                threads: None,
                integrator: opts.integrator.to_string(),
                requested_particles: n,
                particles,
                r_over_dx: case.r_over_dx,
                steps,
                wall_seconds: wall,
                particle_steps_per_second: rate(wall),
                rates: walls.iter().map(|&w| rate(w)).collect(),
                particle_steps_per_second_per_core: None,
                mean_neighbours: 0.0,
                bytes_per_particle: 0.0,
                memory_kind: String::new(),
                in_contact: false,
                stages: None,
                work: None,
                step_profile: None,
            }
        };
        // The GPU solver is built first: a size the adapter cannot hold
        // fails in a moment, before minutes of CPU work.
        let mut gpu_bench = None;
        if let Some(ctx) = &gpu {
            if opts.verbose {
                eprintln!(
                    "bench: gpu, {particles} particles (R/Δx = {:.2})",
                    case.r_over_dx
                );
            }
            match GpuBench::new(ctx.clone(), &case) {
                Ok(b) => {
                    if opts.verbose {
                        eprintln!("bench: gpu, in contact by step {}", b.onset);
                    }
                    gpu_bench = Some(b);
                }
                // With every backend asked for, a size the adapter cannot
                // hold leaves the CPU figures standing.
                Err(BenchError::Input(e)) if opts.backend == BenchBackend::All => {
                    eprintln!("warning: GPU skipped at {particles} particles: {e}");
                }
                Err(e) => return Err(e),
            }
        }
        let mut here = Vec::new();
        if cpu {
            if opts.verbose {
                eprintln!(
                    "bench: cpu, {particles} particles (R/Δx = {:.2})",
                    case.r_over_dx
                );
            }
            let mut b = CpuBench::new(&case)?;
            if opts.verbose {
                eprintln!("bench: cpu, in contact by step {}", b.onset);
            }
            let (steps, walls) = measure(opts.steps, opts.repeat, |k| b.time_steps(k))?;
            let mut r = record("cpu", &cpu_adapter, steps, walls);
            r.threads = Some(threads);
            r.particle_steps_per_second_per_core =
                Some(r.particle_steps_per_second / threads as f64);
            r.bytes_per_particle = b.memory_bytes() as f64 / particles as f64;
            r.memory_kind = "host".into();
            r.in_contact = b.in_contact();
            here.push(r);
        }
        if let (Some(ctx), Some(mut b)) = (&gpu, gpu_bench) {
            let (steps, walls) = measure(opts.steps, opts.repeat, |k| b.time_steps(k))?;
            let mut r = record("gpu", &ctx.adapter_name(), steps, walls);
            r.bytes_per_particle = b.solver.device_bytes() as f64 / particles as f64;
            r.memory_kind = "device".into();
            r.in_contact = b.in_contact();
            if opts.stages {
                r.stages = Some(b.time_stages(0.25)?);
                r.work = Some(b.solver().step_work());
                r.step_profile = b.profile_steps()?;
            }
            here.push(r);
        }
        let mean_nb = neighbours::mean_neighbours(&case.model, &case.state.x);
        for r in &mut here {
            r.mean_neighbours = mean_nb;
        }
        records.extend(here);
    }
    Ok(records)
}

/// The work of a GPU step as a table: one row a neighbour walk.
fn work_table(w: &StepWork) -> String {
    let mut s = format!(
        "A step: {} dispatches (the reorder every {} steps aside), {} neighbour walks over every \
         particle and {} over the boundary particles, {:.1} device bytes a particle.\n\n",
        w.dispatches,
        crate::gpu::REORDER_EVERY,
        w.walks,
        w.contact_walks,
        w.device_bytes_per_particle
    );
    s.push_str(&table_head(&[
        "walk",
        "per step",
        "walking particles",
        "candidates a particle",
        &format!("trips of a {}-thread group", crate::gpu::work::WARP),
        "lanes used",
    ]));
    for k in &w.per_walk {
        s.push_str(&format!(
            "| {} | {} | {} | {:.1} | {:.1} | {:.0} % |\n",
            k.name,
            k.per_step,
            k.walkers,
            k.candidates,
            k.group_trips,
            100.0 * k.lane_use
        ));
    }
    s.push('\n');
    s
}

/// A Markdown table's header row and the rule under it.
fn table_head(columns: &[&str]) -> String {
    format!(
        "| {} |\n{}|\n",
        columns.join(" | "),
        "|---".repeat(columns.len())
    )
}

/// `1.23e6`-style number for the table.
fn sci(x: f64) -> String {
    format!("{x:.3e}")
}

/// The rate, and with repeated measurements their range: `median (min–max)`.
fn rate_cell(r: &Record) -> String {
    let (lo, hi) = r
        .rates
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    if r.rates.len() > 1 {
        format!(
            "{} ({}–{})",
            sci(r.particle_steps_per_second),
            sci(lo),
            sci(hi)
        )
    } else {
        sci(r.particle_steps_per_second)
    }
}

/// The records as a Markdown table, the GPU/CPU ratios and, where timed,
/// the GPU stages.
pub fn table(records: &[Record]) -> String {
    let mut s = String::new();
    s.push_str(&table_head(&[
        "backend",
        "adapter",
        "integrator",
        "particles",
        "R/Δx",
        "mean neighbours",
        "steps",
        "wall (s)",
        "particle-steps/s",
        "per core",
        "memory/particle",
        "in contact",
    ]));
    for r in records {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.2} | {:.1} | {} | {:.3} | {} | {} | {:.0} B ({}) | {} |\n",
            r.backend,
            r.adapter,
            r.integrator,
            r.particles,
            r.r_over_dx,
            r.mean_neighbours,
            r.steps,
            r.wall_seconds,
            rate_cell(r),
            r.particle_steps_per_second_per_core.map_or("–".into(), sci),
            r.bytes_per_particle,
            r.memory_kind,
            if r.in_contact { "yes" } else { "no" },
        ));
    }
    let mut ratios = String::new();
    for g in records.iter().filter(|r| r.backend == "gpu") {
        if let Some(c) = records
            .iter()
            .find(|c| c.backend == "cpu" && c.particles == g.particles)
        {
            ratios.push_str(&format!(
                "GPU/CPU throughput at {} particles: {:.3}\n",
                g.particles,
                g.particle_steps_per_second / c.particle_steps_per_second
            ));
        }
    }
    if !ratios.is_empty() {
        s.push('\n');
        s.push_str(&ratios);
    }
    for g in records.iter().filter(|r| r.stages.is_some()) {
        let stages = g.stages.as_deref().unwrap_or_default();
        let step = g.wall_seconds / g.steps as f64;
        let sum: f64 = stages.iter().map(|t| t.seconds_per_step).sum();
        s.push_str(&format!(
            "\nGPU stages alone at {} particles ({}): step {:.3} ms measured, {:.3} ms as the sum of its stages\n\n",
            g.particles,
            g.adapter,
            1e3 * step,
            1e3 * sum
        ));
        if let Some(w) = &g.work {
            s.push_str(&work_table(w));
        }
        s.push_str(&table_head(&[
            "stage",
            "per call (ms)",
            "calls per step",
            "per step (ms)",
            "share of the sum",
        ]));
        for t in stages {
            s.push_str(&format!(
                "| {} | {:.4} | {} | {:.4} | {:.1} % |\n",
                t.name,
                1e3 * t.seconds_per_call,
                t.calls_per_step,
                1e3 * t.seconds_per_step,
                100.0 * t.seconds_per_step / sum.max(1e-300)
            ));
        }
        if let Some(p) = &g.step_profile {
            s.push_str(&profile_table(p, step));
        }
    }
    s
}

/// Each dispatch's time inside real steps, as a table.
fn profile_table(p: &StepProfile, wall_step: f64) -> String {
    let mut s = format!(
        "\nInside {} real steps (timestamp queries): {:.3} ms of device time a step \
         ({:.3} ms wall a step in the timed batches)\n\n",
        p.steps,
        1e3 * p.seconds_per_step,
        1e3 * wall_step
    );
    s.push_str(&table_head(&[
        "stage",
        "dispatch",
        "calls per step",
        "per step (ms)",
        "share of the step",
    ]));
    for d in &p.dispatches {
        s.push_str(&format!(
            "| {} | {} | {:.4} | {:.4} | {:.1} % |\n",
            d.stage,
            d.kernel,
            d.calls_per_step,
            1e3 * d.seconds_per_step,
            100.0 * d.seconds_per_step / p.seconds_per_step.max(1e-300)
        ));
    }
    s
}
