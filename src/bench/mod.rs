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
//! On the GPU the timed steps run in batches of up to [`RING_LEN`](crate::gpu::RING_LEN)` − 2`
//! steps, one submission and one readback of the per-step observations each
//! (as in a run): no host round trip per step, and each batch ends with the
//! device idle.

mod case;
mod cpu_bench;
mod gpu_bench;
mod measure;
mod table;

pub use case::{check_particles, lattice_radius, DiskCase};
pub use cpu_bench::CpuBench;
pub use gpu_bench::GpuBench;
pub use measure::{bench, cpu_name};
pub use table::table;

use serde::Serialize;

use crate::gpu::profile::StepProfile;
use crate::gpu::work::StepWork;
use crate::scene::{Integrator, Support};

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
    /// Measurements per backend and size (at least 1), one after another
    /// in the same run: the first sets the number of steps, the rest take
    /// as many ([`Record::rates`]).
    pub repeat: u32,
    /// Also time each GPU stage alone.
    pub stages: bool,
    /// Time integration of the timed steps.
    pub integrator: Integrator,
    /// The hourglass control's coefficient in the disks (0: off).
    pub hourglass: f64,
    /// The dispersion correction's θ in the disks (0: off).
    pub dispersion: f64,
    /// The disks' kernel supports (docs/method.md, "Supports that follow
    /// the deformation").
    pub support: Support,
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
    /// The hourglass control's coefficient α_hg (0: off).
    pub hourglass: f64,
    /// The dispersion correction's θ (0: off).
    pub dispersion: f64,
    /// The kernel supports: `fixed` or `adaptive`.
    pub support: String,
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
