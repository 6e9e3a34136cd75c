//! The GPU path: the whole time step in WGSL compute shaders, particle state
//! resident in device storage buffers for the whole run.
//!
//! ## One step on the device
//!
//! The stages and the two integrators' schedules are listed once, in
//! [`crate::stage`]; the dispatches of each:
//!
//! | dispatches | shader | CPU twin |
//! |---|---|---|
//! | cell list: cells, count, two-pass prefix sum, scatter, per-bucket sort | `neighbours.wgsl` | [`crate::cpu::neighbours`] |
//! | correction, colour gradient, EOS, velocity gradient, rates | `kinematics.wgsl` | [`crate::cpu::kinematics`] |
//! | momentum, energy, contact area | `forces.wgsl` | [`crate::cpu::forces`] |
//! | contact pass 1 and 2, and the spread of the spring's pull through the normals (only with contact; the midpoint rule's advance passes gather the spread) | `contact.wgsl`, `penalty.wgsl`, `spread.wgsl` | [`crate::cpu::contact`] |
//! | CFL minimum, time, observations | `reduce.wgsl` | [`crate::cpu::reduce`], [`crate::probe`] |
//! | midpoint half step; then the evaluation again, adding `Δt k2` in place; positions and checks | `advance.wgsl`, the passes at the midpoint | [`crate::cpu::advance`] |
//! | every 16 steps: particles reordered by cell | `reorder.wgsl` | (none needed) |
//!
//! There are no buffers of rates. The evaluation at the base state leaves
//! its rates in the midpoint buffers, which `advance_half` turns into the
//! midpoint state in place; the evaluation at the midpoint adds `Δt k2` to
//! the base state itself, each particle to its own entries (its neighbours
//! are read from the midpoint buffers then), and the contact's second pass
//! books the contact energy ledger. The kernels tell the two apart by the
//! pipeline constant `MID` (`common.wgsl`).
//!
//! The leapfrog (`integrator = "leapfrog"`, pipeline constant `LEAP`) makes
//! one evaluation a step, its twin `cpu::CpuSolver::leapfrog`: the
//! reductions of the state the step starts from, kick and drift
//! (`advance.wgsl`), one cell list, the kinematic pass at `n+1`
//! (`kinematics_leap`: density and stress to `n+1`, the EOS, the predicted
//! velocity), the momentum and the contact forces at the predicted
//! velocity, the kick to `v_{n+1}`, then the energy sums at `v_{n+1}` and
//! the contact's booking, and the energy update with the checks. Its one
//! full neighbour walk is the kinematic pass's: it leaves each particle a
//! 64-bit mask of which of its candidates are SPH pairs, and the momentum
//! and energy walks (the forces pass, twice) visit only those, in the same order
//! (`walk.wgsl`, [`work::GridView::count_masked`]); the contact's
//! gathers run over the list of boundary particles that the kinematics
//! pass makes in either integrator (`contact.wgsl`). Its rates `a_n`, `de_n` (and the contact's heat and
//! spring rates) are carried in buffers of their own, and checkpoints hold
//! them with what the next step's reductions read.
//!
//! The host encodes a batch of steps into one submission and reads back
//! only a small control block and the ring of per-step observations the
//! history is interpolated from (and the whole state at the end).
//!
//! For benchmarks, each stage of the step ([`crate::stage`]) can be run
//! and timed alone on the current state ([`GpuSolver::time_stage`]).
//!
//! ## The module's files
//!
//! [`GpuSolver`] is made for a scene in `build.rs` (device arrays and
//! buffers, one field each in `buffers.rs`) and `kernels.rs` (the entry
//! points compiled and bound through the alias tables of `aliases.rs`); its
//! step is encoded from the schedule in `encode.rs` and run in batches in
//! `batch.rs`; `state.rs` reads and writes the device state (downloads,
//! snapshots, checkpoints); `inspect.rs` times stages and reads one
//! evaluation's stage outputs for the tests. [`context`] holds the device
//! and the pipeline cache, [`shaders`] the WGSL sources, [`layout`] the
//! host structs the shaders read, [`probes`] the observations, [`profile`]
//! and [`work`] the step's timings and work counts.
//!
//! ## Precision plan (f32 on the device)
//!
//! * Positions are a reference cell (integral, exact in f32), the offset in
//!   it at the start, and a displacement `u`; a pair's difference is
//!   `(c_i − c_j)·cell + (o_i − o_j) + (u_i − u_j)`, so its round-off scales
//!   with the pair distance wherever the pair is, and a step's increment
//!   `v dt` is added to a number of its own size, not to a coordinate
//!   10³–10⁵ times larger.
//! * Density is `μ = ρ/ρ0 − 1`: the EOS needs μ, and a step changes ρ by
//!   parts in 10⁶, which f32 would lose against ρ itself.
//! * Time is a compensated `(hi, lo)` pair, so thousands of steps of
//!   ~10⁻⁸ s add up without drift; the end time is met exactly.
//! * Sums over neighbours are gathers in a fixed order (no atomics on
//!   floats): a run is bitwise repeatable on one adapter.
//!
//! ## Model only what a scene needs
//!
//! Dimension, contact, gradient correction, plasticity, artificial stress
//! and the plastic history of strength and failure (shaders/strength.wgsl)
//! are pipeline-override constants: a scene that does not switch them on
//! compiles them out, and the contact passes are not dispatched; the
//! history's buffers exist only in scenes that carry one.

mod aliases;
mod batch;
mod buffers;
mod build;
pub mod context;
mod dispatch;
mod encode;
mod inspect;
mod kernels;
pub mod layout;
mod make;
pub mod probes;
pub mod profile;
pub mod shaders;
mod state;
pub mod work;

use std::sync::Arc;

use buffers::{Buf, DeviceBuffers};
use build::bucket_count;
use dispatch::*;
use make::MAX_SURF_CAP;

use glam::DVec2;

use crate::error::Instability;
use crate::math::Sym;
use crate::model::{Model, State};
use crate::physics::kernel::CORRECTION_MIN_SINGULAR;
use crate::probe::Resolved;
use crate::scene::{ArtPairs, ArtWork, Correction, Integrator};
use crate::stage::{self, Role, Scheduled, Stage};
pub use context::GpuContext;
use context::Pipeline;
use layout::{BodyGpu, Control, Params, PlasticGpu};
pub use probes::ProbePlan;

/// The leapfrog's per-particle arrays that carry a run from one step to the
/// next, with their bytes a particle: the state, the carried rates, and
/// what the next step's reductions read of the last step's passes (the
/// sound speeds, the stored spring energy, the contact forces and areas).
/// Checkpoints hold them; the reorder permutes them.
fn leap_arrays(model: &Model) -> Vec<(Buf, u64)> {
    let mut a = vec![
        (Buf::X0, 16),
        (Buf::U, 8),
        (Buf::V, 8),
        (Buf::R, 8),
        (Buf::S, 16),
        (Buf::Pinfo, 16),
        (Buf::Acc, 8),
        (Buf::Rdt, 8),
        (Buf::Sr2c, 16),
        (Buf::Nbo, 16),
    ];
    if model.history {
        a.push((Buf::Hist, 16));
    }
    if model.adaptive {
        a.push((Buf::Metric, 16));
    }
    if model.contact {
        a.extend([
            (Buf::Qheat, 8),
            (Buf::Qrate, 8),
            (Buf::Cown, 16),
            (Buf::Area, 4),
            (Buf::Centry, 4),
        ]);
    }
    a
}

/// A symmetric tensor from the device's `(xx, yy, xy, zz)`.
fn sym_of(a: [f32; 4]) -> Sym {
    let [xx, yy, xy, zz] = a.map(f64::from);
    Sym { xx, yy, xy, zz }
}

/// Whether the largest buffers [`GpuSolver::new`] makes for `n` particles
/// fit the adapter's limits: the widest per-particle arrays (one `vec4<f32>`,
/// 16 bytes, a particle) and the bucket starts. A check before building
/// (the bench skips a size with it); `new` itself checks every buffer.
pub fn fits(ctx: &GpuContext, n: usize) -> bool {
    widest_buffer(n)
        <= ctx
            .limits
            .max_storage_buffer_binding_size
            .min(ctx.limits.max_buffer_size)
}

/// Whether adaptive supports are carried at a step's end with the
/// viscosity's kept gradient (`gradv`), where it is the step's own
/// (`Model::kept_gradient_is_the_steps`), instead of a copy (`lgrad`,
/// override constant `LGRAD`). The contact's second evaluation then keeps
/// its entries on the list (contact.wgsl, `on_list`).
fn supports_carried_by_gradv(model: &Model) -> bool {
    model.adaptive && model.kept_gradient_is_the_steps()
}

/// The value of environment variable `var` parsed as a `T` for which
/// `valid` holds: `None` where unset, an error naming the variable and
/// `what` it must be otherwise.
pub(crate) fn env_value<T: std::str::FromStr>(
    var: &str,
    valid: impl Fn(&T) -> bool,
    what: &str,
) -> Result<Option<T>, String> {
    match std::env::var(var) {
        Err(_) => Ok(None),
        Ok(text) => match text.trim().parse::<T>() {
            Ok(v) if valid(&v) => Ok(Some(v)),
            _ => Err(format!("{var} must be {what} (got '{text}')")),
        },
    }
}

/// The largest buffer the solver makes for `n` particles: a `vec4<f32>`
/// a particle, or the bucket starts.
fn widest_buffer(n: usize) -> u64 {
    (16 * n as u64).max(4 * (bucket_count(n) as u64 + 1))
}

/// The most particles whose widest buffer fits in `limit` bytes.
pub(crate) fn particles_within(limit: u64) -> usize {
    let (mut lo, mut hi) = (0usize, (limit / 16) as usize);
    while lo < hi {
        let mid = hi - (hi - lo) / 2;
        if widest_buffer(mid) <= limit {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    lo
}

/// The process-wide GPU context (opened once; pipelines compiled once),
/// or why there is none.
pub fn shared_context() -> Result<Arc<GpuContext>, String> {
    static CTX: std::sync::OnceLock<Result<Arc<GpuContext>, String>> = std::sync::OnceLock::new();
    CTX.get_or_init(|| GpuContext::new().map(Arc::new)).clone()
}

/// Threads per workgroup of the per-particle kernels. 128 runs 3–5 %
/// faster than 64 on an H200 (both integrators, 4e6 and 1.6e7 particles;
/// 32 is 10 % slower, 256 no faster), the same on lavapipe, and gives the
/// same bits (docs/performance.md).
const WG: u32 = 128;
// The forces pass's dissipation tree holds at most 256 threads, halved
// at each level (forces.wgsl, book_dissipation).
const _: () = assert!(WG <= 256 && WG.is_power_of_two());

/// Workgroups of the per-particle kernels for `n` particles: the slots of
/// the artificial dissipation's sums (`dheat`, forces.wgsl).
fn particle_groups(n: usize) -> u64 {
    (n as u64).div_ceil(WG as u64).max(1)
}
/// Ring rows: a batch is at most `RING_LEN − 2` steps.
pub const RING_LEN: u32 = 256;
/// Steps between reorderings of the particles by cell.
pub const REORDER_EVERY: u64 = 16;
const NONE: u32 = u32::MAX;
/// Cell size over the largest smoothing length (see `GpuSolver::with_options`).
const CELL_OVER_H: f64 = 1.002;

/// The cells either side a walk reaches where supports adapt (walk.wgsl,
/// `ADAPT_ROWS`): a pair lies within `√(8 / (1/a_i² + 1/a_j²))` of each
/// particle, at most twice the largest major semi-axis, `2 STRETCH_MAX
/// h`, and a row band reaches one cell past the support's radius.
fn adaptive_rows() -> u32 {
    (2.0 * crate::physics::support::STRETCH_MAX / CELL_OVER_H).ceil() as u32 + 1
}
/// Margin, in cells, of a particle's support radius in the row stencil.
const REACH_MARGIN: f64 = 1e-3;
/// Bytes of the control block.
const CTL_BYTES: u64 = size_of::<Control>() as u64;
/// The entry of a saved device state that names its grid
/// ([`GpuSolver::save_raw`]).
const FRAME: &str = "frame";
/// Buckets a workgroup of the cell list's scan takes (neighbours.wgsl, BLOCK).
const SCAN_BLOCK: u32 = 1024;
/// Particles per workgroup of the reductions (256 threads × 4).
const RED_CHUNK: u32 = 1024;

/// What one batch of steps produced.
#[derive(Debug, Default)]
pub struct Batch {
    /// `(t, probe values, stored penalty energy)` of every state observed,
    /// in order.
    pub states: Vec<(f64, Vec<f64>, f64)>,
    /// The end time was reached (and the final state observed).
    pub done: bool,
    pub failure: Option<Instability>,
}

/// Per-particle results of one evaluation, in the model's particle order
/// (for checking the device stage by stage against the CPU).
#[derive(Debug, Clone, Default)]
pub struct StageOutputs {
    /// Neighbours within `2 h_ij` of every particle (all bodies), sorted.
    pub neighbours: Vec<Vec<u32>>,
    /// Candidates each particle's neighbour walk visits.
    pub visits: Vec<u32>,
    /// `L_i` as (xx, xy, yx, yy).
    pub l: Vec<[f64; 4]>,
    pub normal: Vec<DVec2>,
    pub boundary: Vec<bool>,
    /// `σ/ρ²` (xx, yy, xy; `σ/(ηρ)` in a body of revolution) and the
    /// sound speed.
    pub sr2: Vec<[f64; 3]>,
    pub c: Vec<f64>,
    /// Whether the particle's pairs take only the artificial stress's heat
    /// (`work = "yielding"` or `"plastic"`:
    /// [`crate::model::Model::art_heats`]); all false where nothing is
    /// keyed on it.
    pub flows: Vec<bool>,
    /// `dρ/dt` of the density itself (the device's state; a body of
    /// revolution's CPU state keeps `η = 2π r ρ`).
    pub drho: Vec<f64>,
    pub ds: Vec<Sym>,
    /// SPH part of `dv/dt` and `de/dt` (the forces pass), before contact.
    pub dv_sph: Vec<DVec2>,
    pub de_sph: Vec<f64>,
    /// Contact area (0 off the boundary or without contact).
    pub area: Vec<f64>,
    /// Contact force on each particle.
    pub contact_force: Vec<DVec2>,
    /// Full rates.
    pub dv: Vec<DVec2>,
    pub de: Vec<f64>,
    /// The device's step (CFL, clipped to the end time).
    pub dt: f64,
    /// With a plastic history: the midpoint state's deviatoric stress,
    /// density and history (eps_p, T, D, failure time) after
    /// `advance_half` (the strength update at `t + dt/2`); empty otherwise.
    pub mid_s: Vec<Sym>,
    pub mid_rho: Vec<f64>,
    pub mid_hist: Vec<[f64; 4]>,
}

/// Limits below the adapter's, to exercise a small adapter's paths (2-D
/// dispatch wrap-around, the too-large-scene error) on any device.
#[derive(Debug, Clone, Copy, Default)]
pub struct GpuOptions {
    pub max_workgroups_per_dimension: Option<u32>,
    pub max_binding_size: Option<u64>,
    /// The most device memory the solver may take, in bytes (with the
    /// context's `memory_budget`, the smaller).
    pub max_device_bytes: Option<u64>,
    /// Places on the contact's list of boundary particles to start with,
    /// in place of `surf_capacity`'s (tests: a list that grows).
    pub surf_capacity: Option<u32>,
    /// The list is not checked against the state before the first step
    /// (tests: a list that fills during a run).
    pub unchecked_list: bool,
}

/// The grid a solver's reference positions are given in: its origin, cell
/// size and row stride, fixed by the state it was made from. A solver
/// remade for a longer list keeps its predecessor's
/// ([`GpuSolver::run_batch`]).
#[derive(Debug, Clone, Copy)]
struct Frame {
    origin: DVec2,
    cell: f64,
    row_stride: u32,
}

/// A device state as stored: the buffers that carry a run from step to
/// step, byte for byte, and the host's counters of encoded and delivered
/// steps ([`GpuSolver::save_raw`]).
#[derive(Debug, Clone, PartialEq)]
pub struct RawDevice {
    pub buffers: Vec<(String, Vec<u8>)>,
    pub encoded: u64,
    pub delivered: u64,
    pub zero_seen: u32,
    pub last_dt: f64,
}

/// The GPU solver: model constants on the host, everything else on the device.
pub struct GpuSolver {
    ctx: Arc<GpuContext>,
    pub model: Model,
    n: usize,
    buffers: DeviceBuffers,
    staging: wgpu::Buffer,
    plan: ProbePlan,
    k: Kernels,
    /// The real step the next encoded step will be, if it is not one of
    /// the zero-length steps at a stop: the reorder schedule counts real
    /// steps (see reorder.wgsl), re-based on the device's count after
    /// every batch.
    encoded: u64,
    /// States observed so far (the next state to deliver).
    delivered: u64,
    zero_seen: u32,
    last_dt: f64,
    device_bytes: u64,
    /// The run-wide constants, as uploaded.
    params: Params,
    /// The leapfrog's first evaluation is still to be made (its rates are
    /// carried, so a restored state has them).
    first_pending: bool,
    /// Grid origin and cell size: the frame of the reference positions.
    origin: DVec2,
    cell: f64,
    /// What the solver was made from, to remake it with a longer list of
    /// boundary particles ([`GpuSolver::run_batch`]).
    probes: Vec<Resolved>,
    opts: GpuOptions,
    /// The list has been checked against the state the steps start from.
    list_checked: bool,
    /// The last batch paused with the list this full.
    list_full: Option<u32>,
}

/// Why a step failed: `Control::fail_code` is the particle's id times 8
/// plus one of these, written by the shaders under the same names with a
/// `FAIL_` prefix (common.wgsl; `tests::fail_codes_are_the_shaders`).
pub(crate) mod fail {
    pub const POSITION: u32 = 0;
    pub const VELOCITY: u32 = 1;
    pub const ENERGY: u32 = 2;
    pub const DENSITY: u32 = 3;
    /// The step collapsed (reduce.wgsl); names no particle.
    pub const TIME_STEP: u32 = 4;
    pub const DOMAIN: u32 = 5;
    /// The energy guard (reduce.wgsl); names no particle.
    pub const ENERGY_GUARD: u32 = 6;
    /// A contact list more than three quarters full (kinematics.wgsl,
    /// list_surface): the steps pause for a longer list.
    pub const LIST_FULL: u32 = 7;
}
use fail::LIST_FULL;

/// The next length of a list of `cap` places that held `count` boundary
/// particles: twice as long, and at least twice the count.
fn grown_capacity(cap: u32, count: u32, n: usize) -> u32 {
    (2 * cap.max(count)).min(n as u32).min(MAX_SURF_CAP as u32)
}

/// `(hi, lo)` f32 pair of an f64.
fn split(t: f64) -> (f32, f32) {
    let hi = t as f32;
    (hi, (t - hi as f64) as f32)
}

impl GpuSolver {
    /// Bytes of device memory the run holds.
    pub fn device_bytes(&self) -> u64 {
        self.device_bytes
    }

    pub fn adapter_name(&self) -> String {
        self.ctx.adapter_name()
    }

    /// A buffer the scene has made (a missing one is a solver bug).
    fn buf(&self, b: Buf) -> &wgpu::Buffer {
        self.buffers
            .get(b)
            .unwrap_or_else(|| panic!("no device buffer '{}' for this scene", b.name()))
    }
}

#[cfg(test)]
mod tests {
    /// The failure codes the host reads are the ones the shaders write:
    /// every `const FAIL_*` of common.wgsl, by name and value, and no other.
    #[test]
    fn fail_codes_are_the_shaders() {
        let wgsl = include_str!("../../shaders/common.wgsl");
        let mut found: Vec<(String, u32)> = wgsl
            .lines()
            .filter_map(|l| {
                let rest = l.strip_prefix("const FAIL_")?;
                let (name, value) = rest.split_once(": u32 = ")?;
                let value = value.strip_suffix("u;")?.parse().ok()?;
                Some((format!("FAIL_{name}"), value))
            })
            .collect();
        found.sort_by_key(|f| f.1);
        use super::fail::*;
        let ours: Vec<(String, u32)> = [
            ("FAIL_POSITION", POSITION),
            ("FAIL_VELOCITY", VELOCITY),
            ("FAIL_ENERGY", ENERGY),
            ("FAIL_DENSITY", DENSITY),
            ("FAIL_TIME_STEP", TIME_STEP),
            ("FAIL_DOMAIN", DOMAIN),
            ("FAIL_ENERGY_GUARD", ENERGY_GUARD),
            ("FAIL_LIST_FULL", LIST_FULL),
        ]
        .iter()
        .map(|(n, v)| (n.to_string(), *v))
        .collect();
        assert_eq!(found, ours);
    }
}
