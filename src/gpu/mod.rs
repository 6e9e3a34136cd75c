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
//! | contact pass 1 and 2, and the spread of the spring's pull through the normals (only with contact; the midpoint rule's advance passes gather the spread) | `contact.wgsl`, `spread.wgsl` | [`crate::cpu::contact`] |
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
//! (`common.wgsl`, [`work::GridView::count_masked`]); the contact's
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

pub mod context;
pub mod layout;
pub mod probes;
pub mod profile;
pub mod shaders;
pub mod work;

use std::collections::HashMap;
use std::sync::Arc;

use glam::DVec2;

use crate::error::Instability;
use crate::math::Sym;
use crate::model::{Model, State};
use crate::physics::kernel::CORRECTION_MIN_DET;
use crate::probe::Resolved;
use crate::scene::{ArtPairs, Correction, Integrator};
use crate::stage::{self, Role, Scheduled, Stage};
pub use context::GpuContext;
use context::Pipeline;
use layout::{BodyGpu, Control, Params, PlasticGpu};
pub use probes::ProbePlan;

/// Cell-list buckets for `n` particles: a power of two at least the count.
///
/// A cell's key is row-major over the initial bounding box (`bucket_of`,
/// common.wgsl), so distinct cells share a bucket only once the keys span
/// more than the bucket count. Cells are a little larger than `h`, so
/// bodies that fill their box (the disks: 0.9 cells a particle) stay
/// collision-free until they have spread over their starting box times the
/// buckets a particle (1 to 2) over 0.9. Twice as many buckets would halve
/// the collisions of scattered bodies (a wasted candidate read each) for 4
/// bytes a particle more.
fn bucket_count(n: usize) -> u32 {
    n.next_power_of_two().max(256) as u32
}

/// The contact's two gather buffers and the pass-scratch buffer each lives
/// in, if the scene has one (else it gets its own).
///
/// The contact's `cshare` (pass 1 → pass 2) and `cown` (pass 1 → pass 2
/// and the reductions after the first evaluation) are written after the forces pass
/// and dead before the next kinematics pass. The correction matrices (`lmat`), the
/// velocity gradients (`gradv`, reconstructed viscosity) are written by the
/// kinematics pass and last read by the forces pass, and no
/// kernel binds one of them together with the contact buffer it hosts (the
/// reorder uses `lmat` and `cown` as scratch, at the start of a step, as
/// two different buffers). So `cshare` lives in `lmat`, and `cown` in
/// `gradv` when the scene has it: 16 or 32 bytes a particle less.
/// In the same way the stored spring energy (an observation) goes to
/// `sr2c.x` (`σ_xx/ρ²`, dead after the forces pass; the reductions read only its
/// sound speed `w`), written by the particle's own thread in contact pass 1,
/// which reads no other part of `sr2c`.
///
/// The leapfrog's first evaluation and its booking (after the energy walk,
/// the scratch's last reader) use the same homes; `cown` then carries the
/// forces to the next step's reductions, through the reorder (whose
/// scratch is `lmat`). Its force passes, before the energy walk, keep the
/// entries on the list of boundary particles instead (`cown_e`, `cshare_e`;
/// contact.wgsl).
fn contact_homes(model: &Model) -> [(&'static str, Option<&'static str>); 2] {
    let own_home = if model.av_reconstruct {
        Some("gradv")
    } else {
        None
    };
    [("cshare", Some("lmat")), ("cown", own_home)]
}

/// Places on the contact's list of boundary particles (kinematics.wgsl,
/// list_surface) that a solver for `n` particles starts with: the boundary
/// of a body large enough to matter for memory is a small share of it
/// (3.2 % of the benchmark's disks at 2e4, 1.4 % at 1e5, 0.25 % at 4e6),
/// so a thirty-second and a margin: 2.4 bytes a particle at 4e6 for the
/// 76 bytes a place holds. A list that the state a run starts from fills
/// past three quarters is lengthened before its first step, and one that
/// fills so during the run pauses it to be made twice as long
/// ([`GpuSolver::run_batch`]).
fn surf_capacity(n: usize) -> u32 {
    (n / 32 + 512).min(n).min(MAX_SURF_CAP) as u32
}

/// The most entries the list of boundary particles may have: the kinematics pass writes
/// a particle's place there as a float (kinematics.wgsl, list_surface).
const MAX_SURF_CAP: usize = 1 << 24;

/// Where the leapfrog's neighbour masks (common.wgsl) live: with contact in
/// `qrate`, the contact's rates for the ledger's next half step, which the
/// booking writes after the energy walk (the masks' last reader) and the
/// next step's drift reads before the kinematics pass writes the masks again; the first
/// evaluation's contact writes it after its forces pass too. Only the boundary
/// particles' entries are rates (the drift reads no others). Without
/// contact (`None`), in a buffer of their own.
fn mask_home(model: &Model) -> Option<&'static str> {
    (model.integrator == Integrator::Leapfrog && model.contact).then_some("qrate")
}

/// The leapfrog's per-particle arrays that carry a run from one step to the
/// next, with their bytes a particle: the state, the carried rates, and
/// what the next step's reductions read of the last step's passes (the
/// sound speeds, the stored spring energy, the contact forces and areas).
/// Checkpoints hold them; the reorder permutes them.
fn leap_arrays(model: &Model) -> Vec<(&'static str, u64)> {
    let mut a = vec![
        ("x0", 16),
        ("u", 8),
        ("v", 8),
        ("r", 8),
        ("s", 16),
        ("pinfo", 16),
        ("acc", 8),
        ("rdt", 8),
        ("sr2c", 16),
        ("nbo", 16),
    ];
    if model.history {
        a.push(("hist", 16));
    }
    if model.contact {
        a.extend([
            ("qheat", 8),
            ("qrate", 8),
            ("cown", 16),
            ("area", 4),
            ("centry", 4),
        ]);
    }
    a
}

/// A symmetric tensor from the device's `(xx, yy, xy, zz)`.
fn sym_of(a: [f32; 4]) -> Sym {
    let [xx, yy, xy, zz] = a.map(f64::from);
    Sym { xx, yy, xy, zz }
}

/// The device's constants of a material's strength and failure laws
/// (strength.wgsl, `Plastic`).
fn plastic_gpu(m: &crate::physics::material::MaterialModel) -> PlasticGpu {
    let mut p = PlasticGpu {
        heat: if m.specific_heat > 0.0 {
            (m.taylor_quinney / m.specific_heat) as f32
        } else {
            0.0
        },
        rate0: 1.0,
        melt_rise: 1.0,
        spall: if m.spall.is_finite() {
            m.spall as f32
        } else {
            f32::MAX
        },
        ..Default::default()
    };
    if let Some(jc) = &m.strength {
        p.strength = 1;
        (p.a, p.b, p.n, p.c, p.m) = (
            jc.a as f32,
            jc.b as f32,
            jc.n as f32,
            jc.c as f32,
            jc.m as f32,
        );
        p.rate0 = jc.reference_strain_rate as f32;
        p.melt_rise = (jc.melt_temperature - jc.room_temperature) as f32;
    }
    if let Some(f) = &m.failure {
        p.damage = 1;
        (p.d1, p.d2, p.d3, p.d4, p.d5) = (
            f.d1 as f32,
            f.d2 as f32,
            f.d3 as f32,
            f.d4 as f32,
            f.d5 as f32,
        );
    }
    p
}

/// The GPU's particle-probe tables from the plan's `(particle, code)` list:
/// the probed particle ids sorted and deduplicated, padded with `u32::MAX`
/// to one entry a probe, and each probe as `(entry, code)`.
fn probe_tables(particles: &[[u32; 2]]) -> (Vec<u32>, Vec<[u32; 2]>) {
    let mut ids: Vec<u32> = particles.iter().map(|p| p[0]).collect();
    ids.sort_unstable();
    ids.dedup();
    let refs = particles
        .iter()
        .map(|p| {
            [
                ids.binary_search(&p[0]).expect("an id of the list") as u32,
                p[1],
            ]
        })
        .collect();
    ids.resize(particles.len(), u32::MAX);
    (ids, refs)
}

/// Whether the largest buffers [`GpuSolver::new`] makes for `n` particles
/// fit the adapter's limits: the widest per-particle arrays (one `vec4<f32>`,
/// 16 bytes, a particle) and the bucket starts. A check before building
/// (the bench skips a size with it); `new` itself checks every buffer.
pub fn fits(ctx: &GpuContext, n: usize) -> bool {
    let need = (16 * n as u64).max(4 * (bucket_count(n) as u64 + 1));
    need <= ctx.limits.max_storage_buffer_binding_size && need <= ctx.limits.max_buffer_size
}

/// The process-wide GPU context (opened once; pipelines compiled once),
/// or why there is none.
pub fn shared_context() -> Result<Arc<GpuContext>, String> {
    static CTX: std::sync::OnceLock<Result<Arc<GpuContext>, String>> = std::sync::OnceLock::new();
    CTX.get_or_init(|| GpuContext::new().map(Arc::new)).clone()
}

/// Threads per workgroup of the per-particle kernels.
const WG: u32 = 64;
/// Ring rows: a batch is at most `RING_LEN − 2` steps.
pub const RING_LEN: u32 = 256;
/// Steps between reorderings of the particles by cell.
pub const REORDER_EVERY: u64 = 16;
const NONE: u32 = u32::MAX;
/// The cell-list build writes, under these names, the buffers every other
/// stage reads under the second names.
const WRITER_ALIASES: &[(&str, &str)] = &[
    ("bstart_w", "bstart"),
    ("blist_w", "blist"),
    ("hist_w", "hist"),
];
/// Cell size over the largest smoothing length (see `GpuSolver::with_options`).
const CELL_OVER_H: f64 = 1.002;
/// Margin, in cells, of a particle's support radius in the row stencil.
const REACH_MARGIN: f64 = 1e-3;
/// Bytes of the control block.
const CTL_BYTES: u64 = size_of::<Control>() as u64;
/// The entry of a saved device state that names its grid
/// ([`GpuSolver::save_raw`]).
const FRAME: &str = "frame";
/// A binding name no buffer has: bound to a placeholder the kernel's
/// variant never writes (`kernel_in`).
const UNUSED: &str = "unused";
/// Buckets a workgroup of the cell list's scan takes (neighbours.wgsl, BLOCK).
const SCAN_BLOCK: u32 = 1024;
/// Particles per workgroup of the reductions (256 threads × 4).
const RED_CHUNK: u32 = 1024;

/// How many threads a kernel runs.
#[derive(Debug, Clone, Copy)]
enum Size {
    Particles,
    Buckets,
    ScanBlocks,
    RedGroups,
    /// One workgroup for the step and one for each observation slot.
    FinalGroups,
    One,
}

/// Which state the evaluation reads: the step's base state or the midpoint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Var {
    Base,
    Mid,
}

/// Whether a kernel walks the neighbours, and whose.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Walk {
    None,
    /// Every particle's thread walks.
    All,
    /// Only the boundary particles' threads walk (the contact).
    Boundary,
    /// The threads of a list of the boundary particles walk, one a
    /// particle (the leapfrog's contact, dispatched over the list).
    Listed,
    /// Every particle's thread visits the pairs of its neighbour mask
    /// (common.wgsl), or walks in full where the mask overflowed.
    Masked,
}

struct Kernel {
    /// The entry point.
    name: String,
    /// Its shader (a stage of [`crate::stage::STAGES`]).
    stage: String,
    /// Its role where a step runs one entry point in two roles (what a
    /// step profile calls it then, [`Kernel::label`]).
    role: Option<&'static str>,
    pipeline: Arc<Pipeline>,
    bind: wgpu::BindGroup,
    groups: (u32, u32),
    walk: Walk,
    /// A dispatch sized on the device: its workgroups are the three words
    /// at byte 4 of this buffer (`surf_args`, contact.wgsl).
    indirect: Option<wgpu::Buffer>,
}

impl Kernel {
    fn dispatch(&self, pass: &mut wgpu::ComputePass<'_>) {
        pass.set_pipeline(&self.pipeline.pipeline);
        pass.set_bind_group(0, &self.bind, &[]);
        match &self.indirect {
            Some(args) => pass.dispatch_workgroups_indirect(args, 4),
            None => pass.dispatch_workgroups(self.groups.0, self.groups.1, 1),
        }
    }

    /// The kernel dispatched over the contact's list of boundary particles.
    fn listed(mut self, args: &wgpu::Buffer) -> Self {
        self.walk = Walk::Listed;
        self.indirect = Some(args.clone());
        self
    }

    fn walking(mut self, walk: Walk) -> Self {
        self.walk = walk;
        self
    }

    fn labelled(mut self, role: &'static str) -> Self {
        self.role = Some(role);
        self
    }

    /// What a step profile calls it: its role, else its entry point.
    fn label(&self) -> &str {
        self.role.unwrap_or(&self.name)
    }
}

/// Where a step's dispatches go: into a compute pass, or into a tally of
/// the work ([`GpuSolver::step_work`]). The step is encoded by one code for
/// both, so the tally counts what runs.
trait Dispatches {
    fn run(&mut self, k: &Kernel);
}

impl Dispatches for wgpu::ComputePass<'_> {
    fn run(&mut self, k: &Kernel) {
        k.dispatch(self);
    }
}

/// Dispatches and neighbour walks, by kernel entry point in the order run.
#[derive(Default)]
struct Tally {
    dispatches: u32,
    walks: Vec<(String, Walk)>,
}

/// A compute pass with a timestamp after every dispatch
/// ([`GpuSolver::run_batch_profiled`]).
struct Timed<'a, 'p> {
    pass: &'a mut wgpu::ComputePass<'p>,
    timer: &'a mut profile::StepTimer,
}

impl Dispatches for Timed<'_, '_> {
    fn run(&mut self, k: &Kernel) {
        k.dispatch(self.pass);
        self.timer
            .after_pass_dispatch(self.pass, &k.stage, k.label());
    }
}

impl Dispatches for Tally {
    fn run(&mut self, k: &Kernel) {
        self.dispatches += 1;
        if k.walk != Walk::None {
            self.walks.push((k.name.clone(), k.walk));
        }
    }
}

/// An evaluation's kernels for one state variant.
struct Eval {
    // The cell list's two per-particle passes read the evaluation's state
    // (a particle's cell is recomputed, not stored; neighbours.wgsl).
    cells: Kernel,
    scatter: Kernel,
    kinematics: Kernel,
    forces: Kernel,
    contact: Option<ContactKernels>,
}

/// The contact's force passes in their order: the two gathers, then the
/// spread of the spring's pull through the normals (contact.wgsl), which
/// the midpoint rule's steps gather in their advance passes instead: its
/// evaluation at the midpoint has none, its base one only as a stage.
struct ContactKernels {
    pass1: Kernel,
    pass2: Kernel,
    spread: Option<Kernel>,
}

impl ContactKernels {
    fn all(&self) -> impl Iterator<Item = &Kernel> {
        [&self.pass1, &self.pass2].into_iter().chain(&self.spread)
    }
}

/// The leapfrog step's kernels besides the cell list and the reductions
/// (advance.wgsl has the order).
struct LeapKernels {
    kick_drift: Kernel,
    kinematics: Kernel,
    forces: Kernel,
    contact: Option<ContactKernels>,
    /// The booking's contact passes (none without contact): the first,
    /// and the second only with a rigid body (contact.wgsl, pass1_at).
    book: Vec<Kernel>,
    energy: Kernel,
    finish: Kernel,
}

struct Kernels {
    clear: Kernel,
    scan_local: Kernel,
    scan_add: Kernel,
    sort: Kernel,
    /// The evaluation at the base state and, for the midpoint rule, at the
    /// midpoint; for the leapfrog its first evaluation (LEAP = 1) alone.
    eval: Vec<Eval>,
    leap: Option<LeapKernels>,
    /// The reductions (reduce.wgsl): the CFL minimum and the observation
    /// sums over the particles, then the step, the observations, the
    /// energy guard and the probes.
    reduce_partial: Kernel,
    reduce_final: Kernel,
    advance_half: Option<Kernel>,
    advance_full: Option<Kernel>,
    end_step: Kernel,
    /// The midpoint rule's reorder: every array at once into the midpoint
    /// state's buffers and pass scratch.
    permute: Option<Kernel>,
    /// The leapfrog's: each array of [`leap_arrays`] in turn through one
    /// scratch buffer (`lmat`), with its name and bytes a particle.
    permute_each: Vec<(Kernel, &'static str, u64)>,
    /// Refreshes the probed particles' slots after a reorder (none without
    /// particle probes).
    map_slots: Option<Kernel>,
}

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
    /// `σ/ρ²` (xx, yy, xy) and the sound speed.
    pub sr2: Vec<[f64; 3]>,
    pub c: Vec<f64>,
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
    buffers: HashMap<&'static str, wgpu::Buffer>,
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

/// The failure code of a contact list more than three quarters full
/// (kinematics.wgsl, list_surface): the steps pause for a longer list.
const LIST_FULL: u32 = 7;

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
    /// Upload a model and state. `probes` are the scene's resolved probes;
    /// `end_time` is where the device stops stepping. `Err` when the scene
    /// does not fit the adapter.
    pub fn new(
        ctx: Arc<GpuContext>,
        model: Model,
        state: &State,
        probes: &[Resolved],
        end_time: f64,
    ) -> Result<Self, String> {
        Self::with_options(ctx, model, state, probes, end_time, GpuOptions::default())
    }

    /// [`GpuSolver::new`] under limits tighter than the adapter's.
    pub fn with_options(
        ctx: Arc<GpuContext>,
        model: Model,
        state: &State,
        probes: &[Resolved],
        end_time: f64,
        opts: GpuOptions,
    ) -> Result<Self, String> {
        Self::build(ctx, model, state, probes, end_time, opts, None)
    }

    /// The solver for a state, on the grid `frame` where given (else the
    /// state's own).
    fn build(
        ctx: Arc<GpuContext>,
        model: Model,
        state: &State,
        probes: &[Resolved],
        end_time: f64,
        opts: GpuOptions,
        frame: Option<Frame>,
    ) -> Result<Self, String> {
        let n = model.len();
        let buckets = bucket_count(n);
        let red_groups = (n as u32).div_ceil(RED_CHUNK).max(1);
        let h_max = model.h.iter().cloned().fold(0.0, f64::max);
        // Cells of h_max and a hair more: a pair within 2 h_ij is then at
        // most two cells apart along each axis, and a particle's candidates
        // lie in five rows of at most five cells (`row_span`, common.wgsl).
        // Each row's columns are clipped to the disk of radius `reach`
        // cells; the support's 2 h_max / cell is 1.996 cells, and the
        // margin of 1e-3 cells up to 2 covers the f32 rounding of a
        // particle's place in its cell (1e-5 cells at 100 cells from its
        // reference cell).
        let reach = (2.0 / CELL_OVER_H + REACH_MARGIN) as f32;
        let frame = frame.unwrap_or_else(|| {
            let cell = h_max * CELL_OVER_H;
            let (lo, hi) = crate::math::bounds(&state.x);
            let origin = lo - DVec2::splat(1.5 * cell);
            Frame {
                origin,
                cell,
                row_stride: ((hi.x - origin.x) / cell).floor() as u32 + 3,
            }
        });
        let Frame {
            origin,
            cell,
            row_stride,
        } = frame;
        // Positions are observed relative to the grid origin; the plan adds
        // it back in f64.
        let plan = ProbePlan::new(probes, &model, origin);
        let (end_hi, end_lo) = split(end_time);
        let maxd = opts
            .max_workgroups_per_dimension
            .map_or(ctx.limits.max_compute_workgroups_per_dimension, |m| {
                m.min(ctx.limits.max_compute_workgroups_per_dimension)
            })
            .max(1);
        let leapfrog = model.integrator == Integrator::Leapfrog;
        let contact = model.contact;
        let surf_cap = if contact {
            opts.surf_capacity
                .unwrap_or_else(|| surf_capacity(n))
                .clamp(1, MAX_SURF_CAP as u32)
        } else {
            0
        };
        let params = Params {
            n: n as u32,
            nbodies: model.bodies.len() as u32,
            buckets,
            row_stride,
            energy_growth: crate::model::ENERGY_GROWTH as f32,
            energy_floor: model.energy_floor as f32,
            inv_cell: (1.0 / cell) as f32,
            alpha: model.alpha as f32,
            beta: model.beta as f32,
            cfl: model.cfl as f32,
            fixed_dt: model.fixed_dt.unwrap_or(0.0) as f32,
            boundary_threshold: model.boundary_threshold as f32,
            as_eps: model.artificial_stress.map_or(0.0, |a| a.epsilon) as f32,
            as_n: model.artificial_stress.map_or(0.0, |a| a.n) as f32,
            end_hi,
            end_lo,
            ring_len: RING_LEN,
            ring_width: plan.row_width() as u32,
            surf_cap,
            nprobes: plan.particles.len() as u32,
            cell: cell as f32,
            red_groups,
            min_det: CORRECTION_MIN_DET as f32,
            reach,
            domain: {
                let [lo, hi] = model.domain;
                let (lo, hi) = (lo - origin, hi - origin);
                [lo.x as f32, lo.y as f32, hi.x as f32, hi.y as f32]
            },
            energy_kin: plan.energy.map_or(0, |e| e.0 as u32),
            energy_int: plan.energy.map_or(0, |e| e.1 as u32),
            energy_stored: plan.stored.map_or(NONE, |k| k as u32),
            surf_groups: maxd,
        };
        let bodies: Vec<BodyGpu> = model
            .bodies
            .iter()
            .map(|b| {
                let m = &b.material;
                BodyGpu {
                    rho0: m.rho0 as f32,
                    k: m.k as f32,
                    s: m.s as f32,
                    gamma0: m.gamma0 as f32,
                    g: m.g as f32,
                    y0: if m.y0.is_finite() { m.y0 as f32 } else { 0.0 },
                    z: m.z as f32,
                    modulus: m.m as f32,
                    spacing: b.spacing as f32,
                    h: model.h[b.range.start] as f32,
                    rigid: b.rigid as u32,
                    linear: m.linear as u32,
                    elastic: (!m.y0.is_finite()) as u32,
                    ..Default::default()
                }
            })
            .collect();
        let control = Control {
            fail_step: NONE,
            fail_code: NONE,
            energy_limit: -1.0,
            ..Default::default()
        };

        // Per-particle arrays, in the model's order to start with.
        // Reference cell and offset in it (precision plan), from f64.
        let x0: Vec<[f32; 4]> = state
            .x
            .iter()
            .map(|p| {
                let d = (*p - origin) / cell;
                let c = d.floor();
                let off = *p - origin - c * cell;
                [c.x as f32, c.y as f32, off.x as f32, off.y as f32]
            })
            .collect();
        let zeros2 = vec![[0f32; 2]; n];
        let v: Vec<[f32; 2]> = state.v.iter().map(|p| [p.x as f32, p.y as f32]).collect();
        let r: Vec<[f32; 2]> = (0..n)
            .map(|i| {
                let rho0 = model.material(i).rho0;
                [(state.rho[i] / rho0 - 1.0) as f32, state.e[i] as f32]
            })
            .collect();
        let s: Vec<[f32; 4]> = state
            .s
            .iter()
            .map(|s| [s.xx as f32, s.yy as f32, s.xy as f32, s.zz as f32])
            .collect();
        let meta: Vec<[u32; 4]> = (0..n)
            .map(|i| {
                [
                    (model.mass[i] as f32).to_bits(),
                    (model.offset[i] as f32).to_bits(),
                    model.body[i],
                    i as u32,
                ]
            })
            .collect();
        let hist: Vec<[f32; 4]> = if model.history {
            (0..n)
                .map(|i| {
                    let room = model.material(i).initial_temperature();
                    [
                        state.eps_p[i] as f32,
                        (state.temperature[i] - room) as f32,
                        state.damage[i] as f32,
                        state.failed_at[i] as f32,
                    ]
                })
                .collect()
        } else {
            Vec::new()
        };
        // Particle probes find their particle through a slot per probed
        // particle, not a map of every particle (4 B a particle): the probed
        // ids sorted (padded to one per probe with ids no particle has, so
        // that the kernels know the length), each probe pointing at its
        // entry, and the entry's slot, found by a binary search from every
        // particle (reorder.wgsl, map_slots) now and after each reorder.
        let (probe_ids, probe_refs) = probe_tables(&plan.particles);

        let dev = &ctx.device;
        let limits = &ctx.limits;
        let max_binding = opts
            .max_binding_size
            .map_or(limits.max_storage_buffer_binding_size, |m| {
                m.min(limits.max_storage_buffer_binding_size)
            });
        let max_buffer = limits.max_buffer_size;
        let mut buffers = HashMap::new();
        let mut device_bytes = 0u64;
        // A device buffer for storage and copies, and any `extra` use.
        let mut make_as = |name: &'static str,
                           size: u64,
                           data: Option<&[u8]>,
                           extra: wgpu::BufferUsages|
         -> Result<(), String> {
            let size = size.max(16).next_multiple_of(4);
            if size > max_binding || size > max_buffer {
                return Err(format!(
                    "the scene does not fit this adapter: its {n} particles need a {size}-byte \
                     device buffer '{name}', and the adapter allows {} bytes per binding and {} per \
                     buffer; use fewer particles or --backend cpu",
                    max_binding, max_buffer
                ));
            }
            let usage = wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST
                | extra;
            let buf = dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(name),
                size,
                usage,
                mapped_at_creation: false,
            });
            if let Some(d) = data {
                ctx.queue.write_buffer(&buf, 0, d);
            }
            device_bytes += size;
            buffers.insert(name, buf);
            Ok(())
        };
        let mut make = |name: &'static str, size: u64, data: Option<&[u8]>| {
            make_as(name, size, data, wgpu::BufferUsages::empty())
        };
        let nn = n as u64;
        make("x0", 16 * nn, Some(bytemuck::cast_slice(&x0)))?;
        make("u", 8 * nn, Some(bytemuck::cast_slice(&zeros2)))?;
        make("v", 8 * nn, Some(bytemuck::cast_slice(&v)))?;
        make("r", 8 * nn, Some(bytemuck::cast_slice(&r)))?;
        make("s", 16 * nn, Some(bytemuck::cast_slice(&s)))?;
        make("pinfo", 16 * nn, Some(bytemuck::cast_slice(&meta)))?;
        if model.history {
            // The plastic history (strength.wgsl's precision plan), its
            // laws' constants a body, and the midpoint rule's midpoint
            // history and strain rates.
            make("hist", 16 * nn, Some(bytemuck::cast_slice(&hist)))?;
            let plastic: Vec<PlasticGpu> = model
                .bodies
                .iter()
                .map(|b| plastic_gpu(&b.material))
                .collect();
            make(
                "plastic",
                64 * plastic.len() as u64,
                Some(bytemuck::cast_slice(&plastic)),
            )?;
            if !leapfrog {
                make("histm", 16 * nn, None)?;
                if model.strain_rate {
                    make("srate", 4 * nn, None)?;
                }
            }
        }
        if !model.close_scale.is_empty() {
            // By original index (pinfo.w): constant, never permuted. Not
            // made when every scale is 1 (ART_KAPPA off).
            let k2: Vec<f32> = model.close_scale.iter().map(|&k| k as f32).collect();
            make("kappa", 4 * nn, Some(bytemuck::cast_slice(&k2)))?;
        }
        if leapfrog {
            // The carried rates a_n and (_, de_n/dt), and the predicted
            // velocity (common.wgsl, LEAP); buffers wgpu zeroes.
            for name in ["acc", "rdt", "vstar"] {
                make(name, 8 * nn, None)?;
            }
            if mask_home(&model).is_none() {
                make("nmask", 8 * nn, None)?;
            }
            if contact {
                make("qrate", 8 * nn, None)?;
                // The force passes' entries, on the list.
                for name in ["cown_e", "cshare_e"] {
                    make(name, 16 * surf_cap as u64, None)?;
                }
            }
        } else {
            // The midpoint state; the evaluation at the base state leaves
            // its rates there (common.wgsl, MID), so there are no rate
            // buffers.
            for name in ["um", "vm", "rm", "sm"] {
                make(name, if name == "sm" { 16 } else { 8 } * nn, None)?;
            }
        }
        for name in ["lmat", "nbo", "sr2c"] {
            make(name, 16 * nn, None)?;
        }
        if model.av_reconstruct {
            make("gradv", 16 * nn, None)?;
        }
        if contact {
            // Per particle: (dashpot heat booked, spring work of its passes).
            make(
                "qheat",
                8 * nn,
                Some(bytemuck::cast_slice(&vec![0f32; 2 * n])),
            )?;
            // What a boundary particle carries between the contact's passes
            // on the list of boundary particles (kinematics.wgsl,
            // list_surface): the list, the normals, the spring's derivative
            // and dPhi/dg (contact.wgsl); the midpoint rule's contact areas
            // too, which the leapfrog carries a particle from step to step
            // (common.wgsl, area_index).
            let cap = surf_cap as u64;
            make("surf", 4 * cap, None)?;
            for name in ["cn", "cbar0", "cbar1", "ckeep"] {
                make(name, 16 * cap, None)?;
            }
            make("bt", 4 * cap, None)?;
            make("area", 4 * if leapfrog { nn } else { cap }, None)?;
            // The spread's claims, a bit a particle (spread.wgsl).
            make("claim", 4 * nn.div_ceil(32), None)?;
            let entry: Vec<f32> = state.entry.iter().map(|&e| e as f32).collect();
            make("centry", 4 * nn, Some(bytemuck::cast_slice(&entry)))?;
            // The two gather buffers share memory with pass scratch where
            // the scene has it (below); the rest get their own.
            for (name, home) in contact_homes(&model) {
                if home.is_none() {
                    make(name, 16 * nn, None)?;
                }
            }
        }
        make("blist", 4 * nn, None)?;
        // Counts, then ends, then starts (neighbours.wgsl): one array.
        make("bstart", 4 * (buckets as u64 + 1), None)?;
        make("bsum", 4 * buckets.div_ceil(SCAN_BLOCK) as u64, None)?;
        let red_len = red_groups as u64 * (1 + plan.slots.len() as u64);
        make("red", 4 * red_len, None)?;
        let ring_bytes = 4 * RING_LEN as u64 * plan.row_width() as u64;
        make("ring", ring_bytes, None)?;
        make(
            "probes",
            8 * plan.particles.len() as u64,
            Some(bytemuck::cast_slice(&probe_refs)),
        )?;
        if !plan.particles.is_empty() {
            make(
                "probe_ids",
                4 * probe_ids.len() as u64,
                Some(bytemuck::cast_slice(&probe_ids)),
            )?;
            make("probe_slot", 4 * probe_ids.len() as u64, None)?;
        }
        make(
            "bodies",
            64 * bodies.len() as u64,
            Some(bytemuck::cast_slice(&bodies)),
        )?;
        make("ctl", CTL_BYTES, Some(bytemuck::bytes_of(&control)))?;
        if contact {
            // The contact list's (count, workgroups x, y, z): the
            // leapfrog's indirect dispatch's arguments from byte 4
            // (contact.wgsl).
            make_as(
                "surf_args",
                16,
                Some(bytemuck::cast_slice(&[0u32, 0, 1, 1])),
                wgpu::BufferUsages::INDIRECT,
            )?;
        }
        if let Some(home) = mask_home(&model) {
            buffers.insert("nmask", buffers[home].clone());
        }
        if contact {
            for (name, home) in contact_homes(&model) {
                if let Some(home) = home {
                    let shared = buffers[home].clone();
                    buffers.insert(name, shared);
                }
            }
        }
        let surf_args = buffers.get("surf_args").cloned();
        let params_buf = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("params"),
            size: size_of::<Params>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        ctx.queue
            .write_buffer(&params_buf, 0, bytemuck::bytes_of(&params));
        buffers.insert("params", params_buf);
        let staging = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("staging"),
            size: CTL_BYTES + ring_bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });

        let constants: Vec<(&str, f64)> = vec![
            ("DIM", model.dim as f64),
            ("CONTACT", contact as u8 as f64),
            (
                "CORRECTED",
                (model.correction == Correction::Gradient) as u8 as f64,
            ),
            ("PLASTIC", model.plastic as u8 as f64),
            ("ART_STRESS", model.artificial_stress.is_some() as u8 as f64),
            (
                "ART_CLOSE",
                model
                    .artificial_stress
                    .is_some_and(|a| a.pairs == ArtPairs::Close) as u8 as f64,
            ),
            ("ART_KAPPA", !model.close_scale.is_empty() as u8 as f64),
            ("RECON", model.av_reconstruct as u8 as f64),
            ("HISTORY", model.history as u8 as f64),
            ("FAILURE", model.can_fail() as u8 as f64),
            ("STRAIN_RATE", model.strain_rate as u8 as f64),
            ("WG", WG as f64),
            ("GUARD", plan.energy.is_some() as u8 as f64),
            ("RIGID", model.any_rigid as u8 as f64),
            // The leapfrog's kernels outside its step: its first
            // evaluation and the reductions (common.wgsl, LEAP).
            (
                "LEAP",
                (model.integrator == Integrator::Leapfrog) as u8 as f64,
            ),
        ];
        let groups_of = |size: Size| -> (u32, u32) {
            let g = match size {
                Size::Particles => (n as u32).div_ceil(WG),
                Size::Buckets => buckets.div_ceil(WG),
                Size::ScanBlocks => buckets.div_ceil(SCAN_BLOCK),
                Size::RedGroups => red_groups,
                Size::FinalGroups => 1 + plan.slots.len() as u32,
                Size::One => 1,
            }
            .max(1);
            if g <= maxd {
                (g, 1)
            } else {
                (maxd, g.div_ceil(maxd))
            }
        };
        // Where an evaluation's rates go (common.wgsl, MID): at the base
        // state into the midpoint buffers; at the midpoint, which the
        // evaluation reads instead of the base state, into the base state.
        let base_aliases: &[(&str, &str)] = &[("dv", "vm"), ("dr", "rm"), ("ds", "sm")];
        let mid_aliases: &[(&str, &str)] = &[
            ("hist", "histm"),
            ("hist_w", "histm"),
            ("u", "um"),
            ("v", "vm"),
            ("r", "rm"),
            ("s", "sm"),
            ("dv", "v"),
            ("dr", "r"),
            ("ds", "s"),
            ("qheat_w", "qheat"),
        ];
        // The reductions are compiled for this scene's observation slots.
        let slot_wgsl = plan.wgsl();
        let mut mid_constants = constants.clone();
        mid_constants.push(("MID", 1.0));
        let kernel_in = |consts: &[(&str, f64)],
                         stage: &str,
                         entry: &str,
                         size: Size,
                         aliases: &[(&str, &str)]|
         -> Result<Kernel, String> {
            let prelude = if stage == "reduce" {
                slot_wgsl.as_str()
            } else {
                ""
            };
            let pipeline = ctx.pipeline(stage, prelude, entry, consts);
            let storage_used = pipeline.bindings.iter().filter(|b| !b.uniform).count() as u32;
            if storage_used > limits.max_storage_buffers_per_shader_stage {
                return Err(format!(
                    "{stage}::{entry} binds {storage_used} storage buffers; this adapter allows {}",
                    limits.max_storage_buffers_per_shader_stage
                ));
            }
            // Buffers a scene does not need (artificial stress, contact)
            // are bound to small placeholders the compiled-out code never
            // reads (the bind group keeps them alive).
            let key_of = |name: &str| -> String {
                aliases
                    .iter()
                    .chain(WRITER_ALIASES)
                    .find(|a| a.0 == name)
                    .map_or(name, |a| a.1)
                    .to_string()
            };
            let placeholders: Vec<(u32, wgpu::Buffer)> = pipeline
                .bindings
                .iter()
                .filter(|bu| !buffers.contains_key(key_of(&bu.name).as_str()))
                .map(|bu| {
                    let buf = dev.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(&bu.name),
                        size: 64,
                        usage: wgpu::BufferUsages::STORAGE,
                        mapped_at_creation: false,
                    });
                    (bu.binding, buf)
                })
                .collect();
            let mut entries: Vec<wgpu::BindGroupEntry> = pipeline
                .bindings
                .iter()
                .filter_map(|bu| {
                    buffers
                        .get(key_of(&bu.name).as_str())
                        .map(|buf| wgpu::BindGroupEntry {
                            binding: bu.binding,
                            resource: buf.as_entire_binding(),
                        })
                })
                .collect();
            entries.extend(placeholders.iter().map(|(b, buf)| wgpu::BindGroupEntry {
                binding: *b,
                resource: buf.as_entire_binding(),
            }));
            let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(entry),
                layout: &pipeline.layout,
                entries: &entries,
            });
            Ok(Kernel {
                name: entry.to_string(),
                stage: stage.to_string(),
                role: None,
                pipeline,
                bind,
                groups: groups_of(size),
                walk: Walk::None,
                indirect: None,
            })
        };
        let kernel = |stage: &str, entry: &str, size: Size, aliases: &[(&str, &str)]| {
            kernel_in(&constants, stage, entry, size, aliases)
        };

        // The leapfrog's first evaluation leaves a_0 and de_0 in the carried
        // rates and makes no density or stress rates.
        let first_aliases: &[(&str, &str)] = &[("dv", "acc"), ("dr", "rdt"), ("ds", UNUSED)];
        let variants: &[Var] = if leapfrog {
            &[Var::Base]
        } else {
            &[Var::Base, Var::Mid]
        };
        let mut evals = Vec::new();
        for &var in variants {
            let (consts, al) = match (var, leapfrog) {
                (Var::Base, false) => (constants.as_slice(), base_aliases),
                (Var::Base, true) => (constants.as_slice(), first_aliases),
                (Var::Mid, _) => (mid_constants.as_slice(), mid_aliases),
            };
            let eval_kernel = |stage, entry| kernel_in(consts, stage, entry, Size::Particles, al);
            evals.push(Eval {
                cells: eval_kernel("neighbours", "grid_cells")?,
                scatter: eval_kernel("neighbours", "grid_scatter")?,
                kinematics: eval_kernel("kinematics", "kinematics")?.walking(Walk::All),
                forces: eval_kernel("forces", "forces")?.walking(Walk::All),
                contact: if contact {
                    Some(ContactKernels {
                        pass1: eval_kernel("contact", "contact_pass1")?.walking(Walk::Boundary),
                        pass2: eval_kernel("contact", "contact_pass2")?.walking(Walk::Boundary),
                        spread: match var {
                            Var::Base => Some(eval_kernel("contact", "contact_spread")?),
                            Var::Mid => None,
                        },
                    })
                } else {
                    None
                },
            });
        }
        let leap = if leapfrog {
            let mut step_constants = constants.clone();
            step_constants.retain(|c| c.0 != "LEAP");
            let mut book_constants = step_constants.clone();
            step_constants.push(("LEAP", 2.0));
            book_constants.push(("LEAP", 3.0));
            let state_w: &[(&str, &str)] = &[
                ("u_w", "u"),
                ("v_w", "v"),
                ("r_w", "r"),
                ("qheat_w", "qheat"),
            ];
            let at_n1: &[(&str, &str)] =
                &[("v", "vstar"), ("dv", "acc"), ("dr", "rdt"), ("vkick", "v")];
            let listed_at_n1: Vec<(&str, &str)> = at_n1
                .iter()
                .copied()
                .chain([("cown", "cown_e"), ("cshare", "cshare_e")])
                .collect();
            let booking: &[(&str, &str)] = &[
                ("v", "vstar"),
                ("vbook", "v"),
                ("dr", "rdt"),
                ("dv", UNUSED),
                ("qheat_w", "qheat"),
            ];
            let energy: &[(&str, &str)] = &[("dr", "rdt"), ("dv", UNUSED)];
            let step =
                |stage, entry, al| kernel_in(&step_constants, stage, entry, Size::Particles, al);
            let book =
                |stage, entry| kernel_in(&book_constants, stage, entry, Size::Particles, booking);
            Some(LeapKernels {
                kick_drift: kernel("advance", "kick_drift_cells", Size::Particles, state_w)?,
                kinematics: step("kinematics", "kinematics_leap", &[("ds", "s")])?
                    .walking(Walk::All),
                forces: step("forces", "forces", at_n1)?.walking(Walk::Masked),
                contact: match &surf_args {
                    Some(a) => Some(ContactKernels {
                        pass1: step("contact", "contact_pass1", &listed_at_n1)?.listed(a),
                        pass2: step("contact", "contact_pass2", &listed_at_n1)?.listed(a),
                        spread: Some(step("contact", "contact_spread", at_n1)?),
                    }),
                    None => None,
                },
                book: match &surf_args {
                    Some(a) => {
                        let passes: &[(&str, &'static str)] = if model.any_rigid {
                            &[
                                ("contact_pass1", "book_pass1"),
                                ("contact_pass2", "book_pass2"),
                            ]
                        } else {
                            &[("contact_pass1", "book_pass1")]
                        };
                        passes
                            .iter()
                            .map(|&(entry, role)| {
                                Ok(book("contact", entry)?.listed(a).labelled(role))
                            })
                            .collect::<Result<_, String>>()?
                    }
                    None => Vec::new(),
                },
                energy: kernel_in(&book_constants, "forces", "forces", Size::Particles, energy)?
                    .walking(Walk::Masked)
                    .labelled("energy"),
                finish: kernel("advance", "finish", Size::Particles, state_w)?,
            })
        } else {
            None
        };
        let k = Kernels {
            clear: kernel("neighbours", "grid_clear", Size::Buckets, &[])?,
            scan_local: kernel("neighbours", "scan_local", Size::ScanBlocks, &[])?,
            scan_add: kernel("neighbours", "scan_add", Size::ScanBlocks, &[])?,
            sort: kernel("neighbours", "grid_sort", Size::Buckets, &[])?,
            eval: evals,
            leap,
            reduce_partial: kernel("reduce", "reduce_partial", Size::RedGroups, &[])?,
            reduce_final: kernel("reduce", "reduce_final", Size::FinalGroups, &[])?,
            advance_half: if leapfrog {
                None
            } else {
                Some(kernel(
                    "advance",
                    "advance_half",
                    Size::Particles,
                    &[
                        ("u_w", "um"),
                        ("v_w", "vm"),
                        ("r_w", "rm"),
                        ("s_w", "sm"),
                        ("hist_w", "histm"),
                    ],
                )?)
            },
            advance_full: if leapfrog {
                None
            } else {
                Some(kernel(
                    "advance",
                    "advance_full",
                    Size::Particles,
                    // The spread reads the midpoint's positions, which
                    // its cell list was made at.
                    &[
                        ("u_w", "u"),
                        ("v_w", "v"),
                        ("r_w", "r"),
                        ("s_w", "s"),
                        ("u", "um"),
                    ],
                )?)
            },
            end_step: kernel("reduce", "end_step", Size::One, &[])?,
            permute_each: {
                let arrays = if leapfrog {
                    leap_arrays(&model)
                } else if model.history {
                    // The midpoint rule's `permute` has no room for it.
                    vec![("hist", 16)]
                } else {
                    Vec::new()
                };
                arrays
                    .into_iter()
                    .map(|(name, bytes)| {
                        let (entry, src, dst) = match bytes {
                            16 => ("permute4", "p_src4", "p_dst4"),
                            8 => ("permute2", "p_src2", "p_dst2"),
                            _ => ("permute1", "p_src1", "p_dst1"),
                        };
                        let al = [(src, name), (dst, "lmat")];
                        Ok((kernel("reorder", entry, Size::Particles, &al)?, name, bytes))
                    })
                    .collect::<Result<_, String>>()?
            },
            permute: if leapfrog {
                None
            } else {
                Some(kernel(
                    "reorder",
                    "permute",
                    Size::Particles,
                    &[
                        ("t_x0", "lmat"),
                        ("t_u", "um"),
                        ("t_v", "vm"),
                        ("t_r", "rm"),
                        ("t_s", "sm"),
                        ("t_pinfo", "sr2c"),
                        ("t_qheat", "cown"),
                        ("t_centry", "nbo"),
                    ],
                )?)
            },
            map_slots: if plan.particles.is_empty() {
                None
            } else {
                Some(kernel("reorder", "map_slots", Size::Particles, &[])?)
            },
        };
        let solver = Self {
            ctx,
            model,
            n,
            buffers,
            staging,
            plan,
            k,
            encoded: 0,
            delivered: 0,
            zero_seen: 0,
            last_dt: 0.0,
            device_bytes,
            params,
            first_pending: leapfrog,
            origin,
            cell,
            probes: probes.to_vec(),
            opts,
            list_checked: opts.unchecked_list,
            list_full: None,
        };
        solver.refresh_probe_slots();
        Ok(solver)
    }

    /// The contact's list of boundary particles made `cap` places long: the
    /// solver remade on the same grid and the device state carried over,
    /// byte for byte (the list itself is rebuilt by every evaluation).
    fn lengthen_list(&mut self, cap: u32) -> Result<(), String> {
        let raw = self.save_raw();
        // The state the new solver is first made with (the saved buffers
        // then replace it): the saved buffers begin with the state's.
        let saved: Vec<&[u8]> = raw.buffers.iter().map(|b| b.1.as_slice()).collect();
        let (state, _) = self.unpack_state(&saved);
        let opts = GpuOptions {
            surf_capacity: Some(cap),
            ..self.opts
        };
        let frame = Frame {
            origin: self.origin,
            cell: self.cell,
            row_stride: self.params.row_stride,
        };
        let end = self.params.end_hi as f64 + self.params.end_lo as f64;
        let mut g = Self::build(
            self.ctx.clone(),
            self.model.clone(),
            &state,
            &self.probes,
            end,
            opts,
            Some(frame),
        )?;
        g.restore_raw(&raw)?;
        g.first_pending = self.first_pending;
        g.list_checked = true;
        g.clear_list_full();
        *self = g;
        Ok(())
    }

    /// The control block's record of a full list cleared: that pause is
    /// over (a failure of the state itself is kept).
    fn clear_list_full(&self) {
        let mut ctl = self.control();
        if ctl.fail_code == LIST_FULL {
            ctl.fail_step = NONE;
            ctl.fail_code = NONE;
        }
        ctl.list_peak = 0;
        self.ctx
            .queue
            .write_buffer(self.buf("ctl"), 0, bytemuck::bytes_of(&ctl));
    }

    /// Before a solver's first steps: the list of boundary particles long
    /// enough for the state it starts from, with a quarter to spare (the
    /// steps only pause to lengthen it as the boundary grows).
    fn make_list_room(&mut self) -> Result<(), String> {
        if self.list_checked || !self.model.contact {
            return Ok(());
        }
        self.list_checked = true;
        loop {
            let cap = self.params.surf_cap;
            if cap as usize >= self.n {
                return Ok(());
            }
            let count = self.boundary_count();
            if count <= cap - cap / 4 {
                return Ok(());
            }
            self.lengthen_list(grown_capacity(cap, count, self.n))?;
        }
    }

    /// The boundary particles at the current state.
    fn boundary_count(&mut self) -> u32 {
        let d = self.kinematics_outside_step(&[("surf_args", 4)]);
        bytemuck::pod_read_unaligned(&d[0])
    }

    /// The cell list and the kinematics pass at the current state, outside
    /// a step, and `read` read back after them. What they change that a
    /// run carries is put back: the leapfrog's carried arrays, and the
    /// control block (the correction fallbacks and the list's fill they
    /// count).
    fn kinematics_outside_step(&mut self, read: &[(&str, u64)]) -> Vec<Vec<u8>> {
        let leap = self.k.leap.is_some();
        let raw = leap.then(|| self.save_raw());
        let ctl = (!leap).then(|| self.read_buffers(None, &[("ctl", CTL_BYTES)]).remove(0));
        let pending = self.first_pending;
        let mut enc = self.ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            self.encode_grid(&mut pass, Var::Base);
            pass.run(&self.k.eval[Var::Base as usize].kinematics);
        }
        let d = self.read_buffers(Some(enc), read);
        if let Some(raw) = raw {
            self.restore_raw(&raw).expect("the state just saved");
            self.first_pending = pending;
            self.leap_clear();
        }
        if let Some(ctl) = ctl {
            self.ctx.queue.write_buffer(self.buf("ctl"), 0, &ctl);
        }
        d
    }

    /// Find the probed particles' slots (nothing without particle probes).
    fn encode_map_slots(&self, enc: &mut wgpu::CommandEncoder) {
        if let Some(k) = &self.k.map_slots {
            let mut pass = enc.begin_compute_pass(&Default::default());
            k.dispatch(&mut pass);
        }
    }

    /// [`Self::encode_map_slots`] submitted on its own: for a state that
    /// did not come from a step (built, or restored from a checkpoint).
    fn refresh_probe_slots(&self) {
        if self.k.map_slots.is_none() {
            return;
        }
        let mut enc = self.ctx.device.create_command_encoder(&Default::default());
        self.encode_map_slots(&mut enc);
        self.ctx.queue.submit([enc.finish()]);
    }

    /// Bytes of device memory the run holds.
    pub fn device_bytes(&self) -> u64 {
        self.device_bytes
    }

    pub fn adapter_name(&self) -> String {
        self.ctx.adapter_name()
    }

    fn buf(&self, name: &str) -> &wgpu::Buffer {
        &self.buffers[name]
    }

    fn encode_grid(&self, pass: &mut impl Dispatches, var: Var) {
        let k = &self.k;
        pass.run(&k.clear);
        pass.run(&k.eval[var as usize].cells);
        self.encode_grid_after_counts(pass, var);
    }

    /// The cell list from its counts on: the scan, the scatter, the sort.
    fn encode_grid_after_counts(&self, pass: &mut impl Dispatches, var: Var) {
        let k = &self.k;
        pass.run(&k.scan_local);
        pass.run(&k.scan_add);
        pass.run(&k.eval[var as usize].scatter);
        pass.run(&k.sort);
    }

    /// An evaluation: the cell list, the kinematics, the forces and the
    /// contact. The midpoint rule's advance passes gather the contact's
    /// spread (advance.wgsl); the leapfrog's first evaluation runs it.
    fn encode_eval(&self, pass: &mut impl Dispatches, var: Var) {
        self.encode_grid(pass, var);
        let e = &self.k.eval[var as usize];
        pass.run(&e.kinematics);
        pass.run(&e.forces);
        if let Some(c) = &e.contact {
            pass.run(&c.pass1);
            pass.run(&c.pass2);
            if let Some(spread) = c.spread.as_ref().filter(|_| self.k.leap.is_some()) {
                pass.run(spread);
            }
        }
    }

    /// Reorder the particles by cell: gather into scratch, copy back.
    fn encode_reorder(&self, enc: &mut wgpu::CommandEncoder) {
        let n = self.n as u64;
        if self.k.leap.is_some() {
            self.encode_grid(&mut enc.begin_compute_pass(&Default::default()), Var::Base);
            for (k, name, bytes) in &self.k.permute_each {
                k.dispatch(&mut enc.begin_compute_pass(&Default::default()));
                enc.copy_buffer_to_buffer(self.buf("lmat"), 0, self.buf(name), 0, bytes * n);
            }
            self.encode_map_slots(enc);
            // Between leapfrog steps the cell list's counts are zero.
            self.k
                .clear
                .dispatch(&mut enc.begin_compute_pass(&Default::default()));
            return;
        }
        let Some(permute) = &self.k.permute else {
            return;
        };
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            self.encode_grid(&mut pass, Var::Base);
            permute.dispatch(&mut pass);
        }
        let mut copy = |from: &str, to: &str, bytes: u64| {
            enc.copy_buffer_to_buffer(self.buf(from), 0, self.buf(to), 0, bytes * n);
        };
        copy("lmat", "x0", 16);
        copy("um", "u", 8);
        copy("vm", "v", 8);
        copy("rm", "r", 8);
        copy("sm", "s", 16);
        copy("sr2c", "pinfo", 16);
        if self.model.contact {
            copy("cown", "qheat", 8);
            copy("nbo", "centry", 4);
        }
        // The arrays `permute` has no room for, through `lmat` (its x0 is
        // copied out above).
        for (k, name, bytes) in &self.k.permute_each {
            k.dispatch(&mut enc.begin_compute_pass(&Default::default()));
            enc.copy_buffer_to_buffer(self.buf("lmat"), 0, self.buf(name), 0, bytes * n);
        }
        self.encode_map_slots(enc);
    }

    /// The reductions after the first evaluation of a step: the CFL step,
    /// then the per-step observations and probes when the run records any.
    /// One sequence for the step and for timing the stage alone.
    fn encode_reduce(&self, pass: &mut impl Dispatches) {
        pass.run(&self.k.reduce_partial);
        pass.run(&self.k.reduce_final);
    }

    fn encode_step(
        &self,
        enc: &mut wgpu::CommandEncoder,
        step_index: u64,
        mut timer: Option<&mut profile::StepTimer>,
    ) {
        if step_index % REORDER_EVERY == 0 {
            self.encode_reorder(enc);
            if let Some(t) = timer.as_deref_mut() {
                t.after_encoder_work(enc, "reorder", "reorder");
            }
        }
        let mut pass = enc.begin_compute_pass(&Default::default());
        match timer {
            Some(timer) => self.encode_step_pass(&mut Timed {
                pass: &mut pass,
                timer,
            }),
            None => self.encode_step_pass(&mut pass),
        }
    }

    /// The step's schedule ([`crate::stage`]).
    fn schedule(&self) -> &'static [Scheduled] {
        stage::schedule(self.model.integrator)
    }

    /// A step's dispatches after the periodic reorder, in one compute
    /// pass: the schedule's entries in order.
    fn encode_step_pass(&self, pass: &mut impl Dispatches) {
        for &e in self.schedule() {
            if e.stage != Stage::Reorder {
                self.encode_entry(pass, e);
            }
        }
    }

    /// The dispatches of one entry of the schedule (the reorder aside: it
    /// copies buffers between its dispatches, [`GpuSolver::encode_reorder`]).
    ///
    /// Leapfrog: the reductions read the state the step starts from; the
    /// cell list at `x_{n+1}` takes its counts from the drift (the last
    /// step's `finish` zeroed them); the energy walk reads the neighbour
    /// masks that the booking's rates then overwrite (`mask_home`).
    fn encode_entry(&self, pass: &mut impl Dispatches, e: Scheduled) {
        let k = &self.k;
        let var = if e.role == Role::Mid {
            Var::Mid
        } else {
            Var::Base
        };
        let ev = &k.eval[var as usize];
        let midpoint = "a kernel of the midpoint rule";
        match (e.stage, e.role, &k.leap) {
            (Stage::Neighbours, Role::Drifted, Some(_)) => {
                self.encode_grid_after_counts(pass, Var::Base)
            }
            (Stage::Neighbours, _, None) => self.encode_grid(pass, var),
            (Stage::Kinematics, _, Some(l)) => pass.run(&l.kinematics),
            (Stage::Kinematics, _, None) => pass.run(&ev.kinematics),
            (Stage::Forces, Role::Energy, Some(l)) => pass.run(&l.energy),
            (Stage::Forces, _, Some(l)) => pass.run(&l.forces),
            (Stage::Forces, _, None) => pass.run(&ev.forces),
            (Stage::Contact, Role::Book, Some(l)) => l.book.iter().for_each(|k| pass.run(k)),
            (Stage::Contact, _, Some(l)) => l
                .contact
                .iter()
                .flat_map(ContactKernels::all)
                .for_each(|k| pass.run(k)),
            (Stage::Contact, _, None) => {
                if let Some(c) = &ev.contact {
                    pass.run(&c.pass1);
                    pass.run(&c.pass2);
                }
            }
            (Stage::Reduce, _, _) => self.encode_reduce(pass),
            (Stage::Advance, Role::HalfStep, None) => {
                pass.run(k.advance_half.as_ref().expect(midpoint))
            }
            (Stage::Advance, Role::FullStep, None) => {
                pass.run(k.advance_full.as_ref().expect(midpoint));
                pass.run(&k.end_step);
            }
            (Stage::Advance, Role::KickDrift, Some(l)) => pass.run(&l.kick_drift),
            (Stage::Advance, Role::Finish, Some(l)) => {
                pass.run(&l.finish);
                pass.run(&k.end_step);
            }
            _ => unreachable!("{e:?} is not an entry of this integrator's step"),
        }
    }

    /// The leapfrog's first evaluation, if the run has not made it yet: the
    /// rates at the initial state that its first step starts from.
    fn encode_first(&mut self, enc: &mut wgpu::CommandEncoder) {
        if !self.first_pending {
            return;
        }
        self.first_pending = false;
        let mut pass = enc.begin_compute_pass(&Default::default());
        self.encode_eval(&mut pass, Var::Base);
        self.k.clear.dispatch(&mut pass);
    }

    /// After a cell list built outside a leapfrog step: zero the counts
    /// again, which the next step's drift counts into (advance.wgsl,
    /// finish).
    fn leap_clear(&self) {
        if self.k.leap.is_some() {
            let mut enc = self.ctx.device.create_command_encoder(&Default::default());
            self.k
                .clear
                .dispatch(&mut enc.begin_compute_pass(&Default::default()));
            self.ctx.queue.submit([enc.finish()]);
        }
    }

    /// The work of a step: its dispatches and neighbour walks (tallied from
    /// the code that encodes a step), the device bytes, and each walk's
    /// candidates and group trips counted on the host from the cell list
    /// the device builds at the current state ([`work`]).
    pub fn step_work(&mut self) -> work::StepWork {
        let mut tally = Tally::default();
        self.encode_step_pass(&mut tally);
        let nn = self.n as u64;
        let buckets = self.params.buckets as u64;
        let mut enc = self.ctx.device.create_command_encoder(&Default::default());
        self.encode_first(&mut enc);
        self.ctx.queue.submit([enc.finish()]);
        // The kinematics pass gives the boundary flags and the leapfrog's
        // neighbour masks at these positions.
        let mut read = vec![
            ("x0", 16 * nn),
            ("u", 8 * nn),
            ("bstart", 4 * (buckets + 1)),
            ("nbo", 16 * nn),
        ];
        if self.k.leap.is_some() {
            read.push(("nmask", 8 * nn));
        }
        let d = self.kinematics_outside_step(&read);
        let x0: &[[f32; 4]] = bytemuck::cast_slice(&d[0]);
        let u: &[[f32; 2]] = bytemuck::cast_slice(&d[1]);
        let bstart: &[u32] = bytemuck::cast_slice(&d[2]);
        let nbo: &[[f32; 4]] = bytemuck::cast_slice(&d[3]);
        let masks: &[[u32; 2]] = d.get(4).map_or(&[], |m| bytemuck::cast_slice(m));
        let view = work::GridView {
            params: &self.params,
            dim: self.model.dim,
            x0,
            u,
            bstart,
        };
        // Each distinct walk once, with how often a step runs it.
        let mut per_walk: Vec<work::WalkWork> = Vec::new();
        for (name, walk) in &tally.walks {
            if let Some(w) = per_walk.iter_mut().find(|w| &w.name == name) {
                w.per_step += 1;
                continue;
            }
            let boundary = |i: usize| nbo[i][2] > 0.0;
            per_walk.push(match walk {
                Walk::Masked => view.count_masked(name, 1, masks),
                Walk::Boundary => view.count_walk(name, 1, &boundary, false),
                Walk::Listed => view.count_walk(name, 1, &boundary, true),
                _ => view.count_walk(name, 1, &|_| true, false),
            });
        }
        let count = |w: Walk| tally.walks.iter().filter(|x| x.1 == w).count() as u32;
        work::StepWork {
            dispatches: tally.dispatches,
            walks: count(Walk::All) + count(Walk::Masked),
            contact_walks: count(Walk::Boundary) + count(Walk::Listed),
            device_bytes_per_particle: self.device_bytes as f64 / self.n as f64,
            per_walk,
        }
    }

    /// Copy `bytes` from the start of each named buffer back to the host.
    fn read_buffers(
        &self,
        enc: Option<wgpu::CommandEncoder>,
        names: &[(&str, u64)],
    ) -> Vec<Vec<u8>> {
        let dev = &self.ctx.device;
        let total: u64 = names.iter().map(|x| x.1.next_multiple_of(4)).sum();
        let stage = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: total.max(4),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = enc.unwrap_or_else(|| dev.create_command_encoder(&Default::default()));
        let mut off = 0;
        for (name, bytes) in names {
            enc.copy_buffer_to_buffer(self.buf(name), 0, &stage, off, *bytes);
            off += bytes.next_multiple_of(4);
        }
        self.ctx.queue.submit([enc.finish()]);
        let data = map_read(dev, &stage, total.max(4));
        let mut out = Vec::new();
        let mut off = 0usize;
        for (_, bytes) in names {
            out.push(data[off..off + *bytes as usize].to_vec());
            off += bytes.next_multiple_of(4) as usize;
        }
        out
    }

    /// Run up to `steps` steps in one submission and deliver the states
    /// they observed.
    ///
    /// A list of boundary particles that fills past three quarters pauses
    /// the steps (the batch ends early, the state where it paused): the
    /// solver is remade with a list twice as long, and the next batch goes
    /// on from there, bitwise as if the list had been long enough from the
    /// start. A boundary that outgrows the list within a step, or a longer
    /// list the adapter has no room for, is the batch's failure.
    pub fn run_batch(&mut self, steps: u32) -> Batch {
        if let Err(e) = self.make_list_room() {
            return self.list_failure(e);
        }
        let batch = self.batch_with(steps, None).0;
        self.after_batch(batch)
    }

    /// A batch that paused for a full list: the list lengthened.
    fn after_batch(&mut self, mut batch: Batch) -> Batch {
        if let Some(count) = self.list_full.take() {
            let cap = self.params.surf_cap;
            if let Err(e) = self.lengthen_list(grown_capacity(cap, count, self.n)) {
                batch.failure = self.list_failure(e).failure;
            }
        }
        batch
    }

    /// A batch that could not go on for want of a longer list.
    fn list_failure(&self, why: String) -> Batch {
        let ctl = self.control();
        let time = ctl.t_hi as f64 + ctl.t_lo as f64;
        Batch {
            states: Vec::new(),
            done: false,
            failure: Some(self.list_instability(&ctl, ctl.step, time, &why)),
        }
    }

    /// A boundary the contact's list could not hold, at `step` and `time`.
    fn list_instability(&self, ctl: &Control, step: u32, time: f64, why: &str) -> Instability {
        Instability {
            step: step as u64,
            time,
            body: self.model.bodies[0].name.clone(),
            particle: 0,
            quantity: format!(
                "boundary particles, more than the contact's list of {} holds ({why})",
                self.params.surf_cap
            ),
            value: ctl.list_peak as f64,
        }
    }

    /// [`Self::run_batch`] with a timestamp after every dispatch: the same
    /// steps, and where their device time went. `Err` where the adapter
    /// has no timestamp queries inside passes.
    pub fn run_batch_profiled(
        &mut self,
        steps: u32,
    ) -> Result<(Batch, profile::StepProfile), String> {
        if !self.ctx.timestamps {
            return Err(format!(
                "the adapter {} has no timestamp queries inside compute passes",
                self.ctx.adapter_name()
            ));
        }
        let steps = steps.clamp(1, RING_LEN - 2);
        let mut tally = Tally::default();
        self.encode_step_pass(&mut tally);
        // A timestamp after each dispatch and after each reorder, and the
        // first; within the query set's limit (fewer steps where it binds).
        let per_step = tally.dispatches + 1;
        let steps = steps.min((wgpu::QUERY_SET_MAX_QUERIES - 1) / per_step);
        let mut timer = profile::StepTimer::new(&self.ctx.device, per_step * steps + 1);
        let (batch, ticks) = self.batch_with(steps, Some(&mut timer));
        let batch = self.after_batch(batch);
        let ticks = ticks.expect("timestamps resolved with a timer");
        let period = self.ctx.queue.get_timestamp_period();
        Ok((batch, timer.profile(&ticks, period, steps)))
    }

    /// A batch of steps, timed where `timer` is given (then also the
    /// resolved timestamps).
    fn batch_with(
        &mut self,
        steps: u32,
        mut timer: Option<&mut profile::StepTimer>,
    ) -> (Batch, Option<Vec<u64>>) {
        let steps = steps.clamp(1, RING_LEN - 2);
        let mut enc = self.ctx.device.create_command_encoder(&Default::default());
        self.encode_first(&mut enc);
        if let Some(t) = timer.as_deref_mut() {
            t.start(&mut enc);
        }
        let dev = &self.ctx.device;
        for s in 0..steps as u64 {
            self.encode_step(&mut enc, self.encoded + s, timer.as_deref_mut());
        }
        let ring_bytes = self.staging.size() - CTL_BYTES;
        enc.copy_buffer_to_buffer(self.buf("ctl"), 0, &self.staging, 0, CTL_BYTES);
        enc.copy_buffer_to_buffer(self.buf("ring"), 0, &self.staging, CTL_BYTES, ring_bytes);
        let stamps = timer.map(|t| {
            let n = t.written();
            let bytes = 8 * n as u64;
            let resolved = dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps"),
                size: bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let read = dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps read"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            enc.resolve_query_set(&t.set, 0..n, &resolved, 0);
            enc.copy_buffer_to_buffer(&resolved, 0, &read, 0, bytes);
            (read, bytes)
        });
        self.ctx.queue.submit([enc.finish()]);
        let ticks = stamps.map(|(read, bytes)| {
            bytemuck::cast_slice::<u8, u64>(&map_read(dev, &read, bytes)).to_vec()
        });
        (self.finish_batch(), ticks)
    }

    /// The batch's states from the control block and the ring, once the
    /// submission that copied them to the staging buffer is done.
    fn finish_batch(&mut self) -> Batch {
        let dev = &self.ctx.device;
        let data = map_read(dev, &self.staging, self.staging.size());
        let ctl: Control = bytemuck::pod_read_unaligned(&data[..CTL_BYTES as usize]);
        let ring: &[f32] = bytemuck::cast_slice(&data[CTL_BYTES as usize..]);
        let width = self.plan.row_width();
        let row = |s: u64| {
            let r = (s % RING_LEN as u64) as usize * width;
            &ring[r..r + width]
        };
        let mut batch = Batch::default();
        let failed = ctl.fail_step != NONE;
        // A list that filled past three quarters pauses the steps as a
        // failure does; one that overflowed within a step is one.
        let paused = failed && ctl.fail_code == LIST_FULL && ctl.list_peak <= self.params.surf_cap;
        if paused {
            self.list_full = Some(ctl.list_peak);
        }
        let reached = ctl.step as u64;
        self.encoded = reached;
        let done = ctl.zero_steps > self.zero_seen;
        self.zero_seen = ctl.zero_steps;
        // States before `reached` were observed by the step that left them;
        // `reached` itself only by a zero-length step at the end.
        let last = if failed {
            ctl.fail_step as u64
        } else if done {
            reached
        } else {
            reached.saturating_sub(1)
        };
        while self.delivered <= last && (self.delivered < reached || done || failed) {
            let r = row(self.delivered);
            let t = r[0] as f64 + r[1] as f64;
            batch
                .states
                .push((t, self.plan.values(r), self.plan.stored_energy(r)));
            self.delivered += 1;
        }
        let r = row(reached.saturating_sub(1));
        if r[2] > 0.0 {
            self.last_dt = r[2] as f64;
        }
        batch.done = done && !failed;
        if failed && !paused {
            batch.failure = Some(self.instability(&ctl, row(ctl.fail_step as u64)));
        }
        batch
    }

    /// The last step the device took (for sizing the next batch).
    pub fn last_dt(&self) -> f64 {
        self.last_dt
    }

    fn instability(&self, ctl: &Control, row: &[f32]) -> Instability {
        let code = ctl.fail_code;
        let (id, q) = ((code / 8) as usize, code % 8);
        let time = row[0] as f64 + row[1] as f64;
        if code == LIST_FULL {
            let why = "the boundary grew by more than a quarter of it within one step";
            return self.list_instability(ctl, ctl.fail_step, time, why);
        }
        let guard = q == 6;
        let (quantity, value) = if q == 4 {
            ("time step".to_string(), row[2] as f64)
        } else if guard {
            (
                self.model.energy_quantity(ctl.energy_limit as f64),
                self.plan.guarded_energy(row),
            )
        } else {
            let st = self.download();
            let named = |name: &str, v: f64| (name.to_string(), v);
            match q {
                0 => named("position", st.x[id].x + st.x[id].y),
                1 => named("velocity", st.v[id].x + st.v[id].y),
                2 => named("internal energy", st.e[id]),
                5 => self.model.outside_domain(st.x[id]),
                _ => named("density", st.rho[id]),
            }
        };
        let id = match q {
            4 => 0,
            6 => self.model.most_energetic(&self.download()),
            _ => id,
        };
        let (body, particle) = self.model.locate(id.min(self.n - 1));
        // As the CPU path: a bad state is reported with its own step and
        // time; a collapsed step with the state it was computed at.
        let (step, time) = if q == 4 || guard {
            (ctl.fail_step as u64, time)
        } else {
            (ctl.fail_step as u64 + 1, time + row[2] as f64)
        };
        Instability {
            step,
            time,
            body: body.to_string(),
            particle,
            quantity,
            value,
        }
    }

    /// The device state in f64, in the model's particle order.
    pub fn download(&self) -> State {
        self.download_with_control().0
    }

    /// Give the model back (the device buffers are dropped).
    pub fn into_model(self) -> Model {
        self.model
    }

    /// The state and the control block, in one readback.
    pub fn download_with_control(&self) -> (State, Control) {
        let d = self.read_buffers(None, &self.state_buffers());
        self.unpack_state(&d)
    }

    /// Move the time the device stops at (a snapshot time, then the end
    /// time): the step that would cross it is shortened to land on it and
    /// the steps after it have zero length, as at the end of a run, until
    /// the stop moves again. Takes effect from the next batch.
    pub fn set_stop_time(&mut self, t: f64) {
        let (hi, lo) = split(t);
        (self.params.end_hi, self.params.end_lo) = (hi, lo);
        let at = std::mem::offset_of!(Params, end_hi) as u64;
        debug_assert_eq!(std::mem::offset_of!(Params, end_lo) as u64, at + 4);
        self.ctx
            .queue
            .write_buffer(self.buf("params"), at, bytemuck::cast_slice(&[hi, lo]));
    }

    /// The state with its outward unit normals and boundary set, in the
    /// model's particle order (snapshots). The normals in "nbo" after a step
    /// belong to its midpoint, so the cell list and the kinematics pass run once more at
    /// the state itself first. They only rewrite per-evaluation scratch
    /// that every step recomputes before reading, and the control block,
    /// which is put back (`kinematics_outside_step`).
    /// Normals are zero off the boundary, as on the CPU path.
    pub fn snapshot(&mut self) -> (State, Vec<DVec2>, Vec<bool>) {
        let mut names = self.state_buffers();
        names.push(("nbo", 16 * self.n as u64));
        let d = if self.k.leap.is_some() {
            // The normals of the last step's kinematic pass, at these
            // positions: an evaluation now would overwrite what the next
            // step's reductions read.
            let mut enc = self.ctx.device.create_command_encoder(&Default::default());
            self.encode_first(&mut enc);
            self.read_buffers(Some(enc), &names)
        } else {
            self.kinematics_outside_step(&names)
        };
        let (st, _) = self.unpack_state(&d);
        let meta: &[[u32; 4]] = bytemuck::cast_slice(&d[5]);
        let nbo: &[[f32; 4]] = bytemuck::cast_slice(d.last().expect("nbo was read"));
        let mut normal = vec![DVec2::ZERO; self.n];
        let mut boundary = vec![false; self.n];
        for (m, nb) in meta.iter().zip(nbo) {
            let i = m[3] as usize;
            if nb[2] > 0.0 {
                boundary[i] = true;
                normal[i] = DVec2::new(nb[0] as f64, nb[1] as f64);
            }
        }
        (st, normal, boundary)
    }

    /// The buffers that carry a run from one step to the next, as stored
    /// (checkpoints): the state and the control block. Everything else is
    /// rewritten by every step before it is read, or (the probed
    /// particles' slots) follows from the state.
    fn persistent_buffers(&self) -> Vec<(&'static str, u64)> {
        let mut names = self.state_buffers();
        if self.k.leap.is_some() {
            let n = self.n as u64;
            let state: Vec<&str> = names.iter().map(|b| b.0).collect();
            names.extend(
                leap_arrays(&self.model)
                    .into_iter()
                    .filter(|a| !state.contains(&a.0))
                    .map(|(name, bytes)| (name, bytes * n)),
            );
        }
        names
    }

    /// The device's state as stored, with the host's step counters (a
    /// checkpoint's part from the device).
    pub fn save_raw(&self) -> RawDevice {
        let names = self.persistent_buffers();
        let data = self.read_buffers(None, &names);
        let mut buffers: Vec<(String, Vec<u8>)> = names
            .iter()
            .zip(data)
            .map(|((name, _), d)| (name.to_string(), d))
            .collect();
        buffers.push((FRAME.to_string(), self.frame_bytes()));
        RawDevice {
            buffers,
            encoded: self.encoded,
            delivered: self.delivered,
            zero_seen: self.zero_seen,
            last_dt: self.last_dt,
        }
    }

    /// The grid the reference positions are given in: origin and cell
    /// size, as f64 bytes.
    fn frame_bytes(&self) -> Vec<u8> {
        [self.origin.x, self.origin.y, self.cell]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect()
    }

    /// Put a saved device state back (a solver made for the same scene):
    /// the buffers byte for byte, then the counters. `Err` when the saved
    /// buffers are not this solver's.
    pub fn restore_raw(&mut self, raw: &RawDevice) -> Result<(), String> {
        let names = self.persistent_buffers();
        // The reference cells in `x0` count cells of this solver's grid.
        let frame = raw.buffers.iter().find(|(m, _)| m == FRAME);
        if frame.map(|f| &f.1) != Some(&self.frame_bytes()) {
            return Err(
                "the saved device state is laid out on another cell grid than this \
                        build's (a checkpoint of an older build, or of another scene); resume \
                        it with the build that wrote it"
                    .into(),
            );
        }
        // Checkpoints from before the probes kept their own slots also hold
        // a map of every particle's slot: not needed, rebuilt below.
        let saved: Vec<&(String, Vec<u8>)> = raw
            .buffers
            .iter()
            .filter(|(m, _)| m != "slot_of" && m != FRAME)
            .collect();
        let same = names.len() == saved.len()
            && names
                .iter()
                .zip(&saved)
                .all(|((n, size), (m, d))| n == m && *size == d.len() as u64);
        if !same {
            return Err("the saved device buffers do not match this scene's".into());
        }
        for (name, d) in saved {
            self.ctx.queue.write_buffer(self.buf(name), 0, d);
        }
        self.refresh_probe_slots();
        self.first_pending = false;
        self.encoded = raw.encoded;
        self.delivered = raw.delivered;
        self.zero_seen = raw.zero_seen;
        self.last_dt = raw.last_dt;
        Ok(())
    }

    /// The buffers the state is read from, in the order `unpack_state`
    /// takes them.
    fn state_buffers(&self) -> Vec<(&'static str, u64)> {
        let n = self.n as u64;
        let mut names = vec![
            ("x0", 16 * n),
            ("u", 8 * n),
            ("v", 8 * n),
            ("r", 8 * n),
            ("s", 16 * n),
            ("pinfo", 16 * n),
            ("ctl", CTL_BYTES),
        ];
        if self.model.contact {
            names.push(("qheat", 8 * n));
            names.push(("centry", 4 * n));
        }
        if self.model.history {
            names.push(("hist", 16 * n));
        }
        names
    }

    /// Where buffer `name` is among `state_buffers`.
    fn state_index(&self, name: &str) -> usize {
        self.state_buffers()
            .iter()
            .position(|b| b.0 == name)
            .unwrap_or_else(|| panic!("no state buffer '{name}'"))
    }

    /// Particle i's history `(ε_p, T, D, t_f)` in f64 from the device's
    /// (strength.wgsl's precision plan: the temperature as its rise).
    fn history_of(&self, i: usize, h: [f32; 4]) -> [f64; 4] {
        let room = self.model.material(i).initial_temperature();
        let [eps, rise, d, t] = h.map(f64::from);
        [eps, room + rise, d, t]
    }

    /// The f64 state (model order) and the control block from the buffers
    /// of `state_buffers`.
    fn unpack_state<B: AsRef<[u8]>>(&self, d: &[B]) -> (State, Control) {
        let x0: &[[f32; 4]] = bytemuck::cast_slice(d[0].as_ref());
        let u: &[[f32; 2]] = bytemuck::cast_slice(d[1].as_ref());
        let v: &[[f32; 2]] = bytemuck::cast_slice(d[2].as_ref());
        let r: &[[f32; 2]] = bytemuck::cast_slice(d[3].as_ref());
        let s: &[[f32; 4]] = bytemuck::cast_slice(d[4].as_ref());
        let meta: &[[u32; 4]] = bytemuck::cast_slice(d[5].as_ref());
        let ctl: Control = bytemuck::pod_read_unaligned(d[6].as_ref());
        let n = self.n;
        let mut st = State {
            t: ctl.t_hi as f64 + ctl.t_lo as f64,
            step: ctl.step as u64,
            x: vec![DVec2::ZERO; n],
            v: vec![DVec2::ZERO; n],
            rho: vec![0.0; n],
            e: vec![0.0; n],
            s: vec![Sym::default(); n],
            heat: 0.0,
            spring_work: 0.0,
            ..Default::default()
        };
        for k in 0..n {
            let i = meta[k][3] as usize;
            let c = DVec2::new(x0[k][0] as f64, x0[k][1] as f64);
            let off = DVec2::new(
                x0[k][2] as f64 + u[k][0] as f64,
                x0[k][3] as f64 + u[k][1] as f64,
            );
            st.x[i] = self.origin + c * self.cell + off;
            st.v[i] = DVec2::new(v[k][0] as f64, v[k][1] as f64);
            st.rho[i] = self.model.material(i).rho0 * (1.0 + r[k][0] as f64);
            st.e[i] = r[k][1] as f64;
            st.s[i] = sym_of(s[k]);
        }
        if self.model.contact {
            let q: &[[f32; 2]] = bytemuck::cast_slice(d[self.state_index("qheat")].as_ref());
            st.heat = q.iter().map(|x| x[0] as f64).sum();
            st.spring_work = q.iter().map(|x| x[1] as f64).sum();
            let e: &[f32] = bytemuck::cast_slice(d[self.state_index("centry")].as_ref());
            st.entry = vec![0.0; n];
            for k in 0..n {
                st.entry[meta[k][3] as usize] = e[k] as f64;
            }
        }
        if self.model.history {
            let h: &[[f32; 4]] = bytemuck::cast_slice(d[self.state_index("hist")].as_ref());
            st.eps_p = vec![0.0; n];
            st.temperature = vec![0.0; n];
            st.damage = vec![0.0; n];
            st.failed_at = vec![0.0; n];
            for k in 0..n {
                let i = meta[k][3] as usize;
                [
                    st.eps_p[i],
                    st.temperature[i],
                    st.damage[i],
                    st.failed_at[i],
                ] = self.history_of(i, h[k]);
            }
        }
        (st, ctl)
    }

    /// The stages [`GpuSolver::time_stage`] can run for this scene (the
    /// contact only when the scene has contact), in the order of
    /// [`stage::STAGES`].
    pub fn stage_names(&self) -> Vec<&'static str> {
        stage::STAGES
            .iter()
            .filter(|s| s.stage != Stage::Contact || self.model.contact)
            .map(|s| s.name)
            .collect()
    }

    /// How many times a step runs what [`GpuSolver::time_stage`] times of
    /// a stage: its entries at the step's own state (the evaluation at the
    /// midpoint runs the same kernels again).
    pub fn stage_per_step(&self, name: &str) -> f64 {
        Stage::named(name).map_or(1.0, |s| stage::per_step(self.schedule(), s, REORDER_EVERY))
    }

    /// Encode one run of a stage: its entries of the schedule at the base
    /// state ([`stage::at_base`]).
    fn encode_stage(&self, enc: &mut wgpu::CommandEncoder, stage: Stage) {
        if stage == Stage::Reorder {
            self.encode_reorder(enc);
            return;
        }
        let mut pass = enc.begin_compute_pass(&Default::default());
        for e in stage::at_base(self.schedule(), stage) {
            if e.role == Role::Drifted {
                // Alone, the cell list counts for itself (in a step the
                // drift counts).
                self.encode_grid(&mut pass, Var::Base);
            } else {
                self.encode_entry(&mut pass, e);
            }
        }
    }

    /// Wall time of `reps` runs of one stage (a name of
    /// [`GpuSolver::stage_names`]) encoded into one command buffer, from
    /// submission to the device going idle: one stage timed alone, on the
    /// current state.
    ///
    /// Before timing, one untimed evaluation at the current state (cell
    /// list, passes, contact, CFL step) gives every stage valid inputs, so
    /// a stage can be timed in any order. The state is left as it was: the
    /// evaluation stages only rewrite per-evaluation scratch that the next
    /// step recomputes, the reordering only permutes the particles, and
    /// what the rest changes (the control block's counters, and for
    /// `advance`, which is not idempotent, the state itself) is saved
    /// before and copied back after, so stepping may go on afterwards.
    /// (A reordering timed between the steps that reorder anyway leaves a
    /// different particle order until the next one, so the sums after it
    /// may differ from an untimed run's in the last bits.)
    ///
    /// Wall time rather than timestamp queries: it needs no optional
    /// adapter feature, and over many repetitions the one submission's
    /// overhead is small.
    pub fn time_stage(&mut self, name: &str, reps: u32) -> Result<std::time::Duration, String> {
        let names = self.stage_names();
        let stage = match Stage::named(name) {
            Some(s) if names.contains(&name) => s,
            _ => {
                return Err(format!(
                    "no GPU stage '{name}' for this scene (stages: {})",
                    names.join(", ")
                ))
            }
        };
        if reps == 0 {
            return Err("a stage is timed over at least one repetition".into());
        }
        let ctx = self.ctx.clone();
        let dev = &ctx.device;
        let nn = self.n as u64;
        let mut saved = vec![("ctl", CTL_BYTES)];
        if self.k.leap.is_some() {
            // Every stage of a leapfrog step changes the state or what it
            // carries: all of it is put back afterwards.
            saved = self.persistent_buffers();
        } else if stage == Stage::Advance {
            // Of the state it moves the positions only: the rest of the full
            // step is added in place by the passes at the midpoint.
            saved.push(("u", 8 * nn));
        }
        let backups: Vec<wgpu::Buffer> = saved
            .iter()
            .map(|(label, bytes)| {
                dev.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: *bytes,
                    usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            })
            .collect();
        let wait = || {
            dev.poll(wgpu::PollType::wait_indefinitely())
                .map(|_| ())
                .map_err(|e| format!("waiting for the device: {e}"))
        };

        let mut enc = dev.create_command_encoder(&Default::default());
        self.encode_first(&mut enc);
        for ((from, bytes), to) in saved.iter().zip(&backups) {
            enc.copy_buffer_to_buffer(self.buf(from), 0, to, 0, *bytes);
        }
        if let Some(l) = &self.k.leap {
            // A whole step, then the cell list it ends by zeroing and the
            // neighbour masks its booking overwrites: every stage's inputs
            // are then valid. The kinematics pass lists the boundary particles again,
            // from an empty list.
            self.encode_step_pass(&mut enc.begin_compute_pass(&Default::default()));
            if let Some(args) = self.buffers.get("surf_args") {
                enc.clear_buffer(args, 0, Some(4));
            }
            let mut pass = enc.begin_compute_pass(&Default::default());
            self.encode_grid(&mut pass, Var::Base);
            pass.run(&l.kinematics);
        } else {
            let mut pass = enc.begin_compute_pass(&Default::default());
            self.encode_eval(&mut pass, Var::Base);
            self.encode_reduce(&mut pass);
        }
        self.ctx.queue.submit([enc.finish()]);
        wait()?;

        let mut enc = dev.create_command_encoder(&Default::default());
        for _ in 0..reps {
            self.encode_stage(&mut enc, stage);
        }
        let commands = enc.finish();
        let start = std::time::Instant::now();
        self.ctx.queue.submit([commands]);
        wait()?;
        let elapsed = start.elapsed();

        let mut enc = dev.create_command_encoder(&Default::default());
        for ((to, bytes), from) in saved.iter().zip(&backups) {
            enc.copy_buffer_to_buffer(from, 0, self.buf(to), 0, *bytes);
        }
        self.ctx.queue.submit([enc.finish()]);
        self.leap_clear();
        if self.k.leap.is_some() {
            // The particles are back in their order; the probes' slots too.
            self.refresh_probe_slots();
        }
        wait()?;
        Ok(elapsed)
    }

    /// The control block: time, step, status, and the counts of particles
    /// whose correction fell back to `L = I` (most at one state) and of
    /// contact evaluations that met two partner bodies.
    pub fn control(&self) -> Control {
        let d = self.read_buffers(None, &[("ctl", CTL_BYTES)]);
        bytemuck::pod_read_unaligned(&d[0])
    }

    /// One evaluation at the current state, with every stage's output read
    /// back (tests: the device against its CPU twins). Does not step.
    pub fn stage_outputs(&mut self) -> StageOutputs {
        assert!(
            self.k.leap.is_none(),
            "stage_outputs reads the midpoint rule's evaluation"
        );
        let n = self.n;
        let nn = n as u64;
        let dev = &self.ctx.device;
        // Reorder first, as a run does, so the check covers permuted slots.
        let mut enc = dev.create_command_encoder(&Default::default());
        self.encode_reorder(&mut enc);
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            self.encode_grid(&mut pass, Var::Base);
            let e = &self.k.eval[0];
            e.kinematics.dispatch(&mut pass);
            e.forces.dispatch(&mut pass);
        }
        let first = self.read_buffers(
            Some(enc),
            &[
                ("pinfo", 16 * nn),
                ("lmat", 16 * nn),
                ("nbo", 16 * nn),
                ("sr2c", 16 * nn),
                // The rates at the base state, left in the midpoint buffers.
                ("rm", 8 * nn),
                ("sm", 16 * nn),
                ("vm", 8 * nn),
            ],
        );
        let mut enc = dev.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            for k in self.k.eval[0].contact.iter().flat_map(ContactKernels::all) {
                k.dispatch(&mut pass);
            }
            self.encode_reduce(&mut pass);
        }
        let mut names = vec![("vm", 8 * nn), ("rm", 8 * nn), ("ctl", CTL_BYTES)];
        if self.model.contact {
            let cap = self.params.surf_cap as u64;
            names.push(("area", 4 * cap));
            names.push(("cn", 16 * cap));
        }
        let second = self.read_buffers(Some(enc), &names);
        // The strength update of the midpoint state, at the step the
        // reductions chose.
        let mid = self.model.history.then(|| {
            let mut enc = dev.create_command_encoder(&Default::default());
            if let Some(k) = &self.k.advance_half {
                k.dispatch(&mut enc.begin_compute_pass(&Default::default()));
            }
            self.read_buffers(
                Some(enc),
                &[("sm", 16 * nn), ("rm", 8 * nn), ("histm", 16 * nn)],
            )
        });

        // Neighbour dump (test-only kernel), indexed by original id.
        let consts = [("DIM", self.model.dim as f64), ("WG", WG as f64)];
        let p = self.ctx.pipeline("debug", "", "dump_neighbours", &consts);
        let dump = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dump"),
            size: 4 * 128 * nn,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let entries: Vec<wgpu::BindGroupEntry> = p
            .bindings
            .iter()
            .map(|b| wgpu::BindGroupEntry {
                binding: b.binding,
                resource: if b.name == "dump" {
                    dump.as_entire_binding()
                } else {
                    self.buf(&b.name).as_entire_binding()
                },
            })
            .collect();
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("dump"),
            layout: &p.layout,
            entries: &entries,
        });
        let mut enc = dev.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&p.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            let g = (n as u32).div_ceil(WG);
            let maxd = self.ctx.limits.max_compute_workgroups_per_dimension;
            if g <= maxd {
                pass.dispatch_workgroups(g, 1, 1);
            } else {
                pass.dispatch_workgroups(maxd, g.div_ceil(maxd), 1);
            }
        }
        let stage = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dump readback"),
            size: 4 * 128 * nn,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        enc.copy_buffer_to_buffer(&dump, 0, &stage, 0, 4 * 128 * nn);
        self.ctx.queue.submit([enc.finish()]);
        let dump_data = map_read(dev, &stage, 4 * 128 * nn);
        let dump_u: &[u32] = bytemuck::cast_slice(&dump_data);

        let meta: &[[u32; 4]] = bytemuck::cast_slice(&first[0]);
        let l: &[[f32; 4]] = bytemuck::cast_slice(&first[1]);
        let nbo: &[[f32; 4]] = bytemuck::cast_slice(&first[2]);
        let sr2c: &[[f32; 4]] = bytemuck::cast_slice(&first[3]);
        let dr1: &[[f32; 2]] = bytemuck::cast_slice(&first[4]);
        let ds: &[[f32; 4]] = bytemuck::cast_slice(&first[5]);
        let dv1: &[[f32; 2]] = bytemuck::cast_slice(&first[6]);
        let dv2: &[[f32; 2]] = bytemuck::cast_slice(&second[0]);
        let dr2: &[[f32; 2]] = bytemuck::cast_slice(&second[1]);
        let ctl: Control = bytemuck::pod_read_unaligned(&second[2]);
        // With contact, the areas and the contact's normals (forces.wgsl)
        // at each boundary particle's place on the list; else the colour
        // gradient's normals.
        let area: Option<&[f32]> = second.get(3).map(|a| bytemuck::cast_slice(a));
        let cn: Option<&[[f32; 4]]> = second.get(4).map(|a| bytemuck::cast_slice(a));
        let mut out = StageOutputs {
            neighbours: vec![Vec::new(); n],
            visits: vec![0; n],
            l: vec![[0.0; 4]; n],
            normal: vec![DVec2::ZERO; n],
            boundary: vec![false; n],
            sr2: vec![[0.0; 3]; n],
            c: vec![0.0; n],
            drho: vec![0.0; n],
            ds: vec![Sym::default(); n],
            dv_sph: vec![DVec2::ZERO; n],
            de_sph: vec![0.0; n],
            area: vec![0.0; n],
            contact_force: vec![DVec2::ZERO; n],
            dv: vec![DVec2::ZERO; n],
            de: vec![0.0; n],
            dt: ctl.dt as f64,
            mid_s: Vec::new(),
            mid_rho: Vec::new(),
            mid_hist: Vec::new(),
        };
        if let Some(m) = &mid {
            let sm: &[[f32; 4]] = bytemuck::cast_slice(&m[0]);
            let rm: &[[f32; 2]] = bytemuck::cast_slice(&m[1]);
            let hm: &[[f32; 4]] = bytemuck::cast_slice(&m[2]);
            out.mid_s = vec![Sym::default(); n];
            out.mid_rho = vec![0.0; n];
            out.mid_hist = vec![[0.0; 4]; n];
            for k in 0..n {
                let i = meta[k][3] as usize;
                let mat = self.model.material(i);
                out.mid_s[i] = sym_of(sm[k]);
                out.mid_rho[i] = mat.rho0 * (1.0 + rm[k][0] as f64);
                out.mid_hist[i] = self.history_of(i, hm[k]);
            }
        }
        let v2 = |a: [f32; 2]| DVec2::new(a[0] as f64, a[1] as f64);
        for k in 0..n {
            let i = meta[k][3] as usize;
            let base = i * 128;
            let cnt = dump_u[base] as usize;
            let mut nb = dump_u[base + 1..base + 1 + cnt].to_vec();
            nb.sort_unstable();
            out.neighbours[i] = nb;
            out.visits[i] = dump_u[base + 127];
            out.l[i] = l[k].map(|x| x as f64);
            out.boundary[i] = nbo[k][2] > 0.0;
            let place = nbo[k][3] as usize;
            let nk = match cn {
                Some(c) if out.boundary[i] => c[place],
                Some(_) => [0.0; 4],
                None => nbo[k],
            };
            out.normal[i] = DVec2::new(nk[0] as f64, nk[1] as f64);
            out.sr2[i] = [sr2c[k][0] as f64, sr2c[k][1] as f64, sr2c[k][2] as f64];
            out.c[i] = sr2c[k][3] as f64;
            out.drho[i] = self.model.material(i).rho0 * dr1[k][0] as f64;
            out.ds[i] = sym_of(ds[k]);
            out.dv_sph[i] = v2(dv1[k]);
            out.de_sph[i] = dr1[k][1] as f64;
            out.dv[i] = v2(dv2[k]);
            out.de[i] = dr2[k][1] as f64;
            out.contact_force[i] = (out.dv[i] - out.dv_sph[i]) * self.model.mass[i];
            if let Some(a) = area.filter(|_| out.boundary[i]) {
                out.area[i] = a[place] as f64;
            }
        }
        out
    }
}

/// Map a MAP_READ buffer and copy out its first `size` bytes.
fn map_read(dev: &wgpu::Device, buf: &wgpu::Buffer, size: u64) -> Vec<u8> {
    let slice = buf.slice(0..size);
    slice.map_async(wgpu::MapMode::Read, |r| {
        r.expect("mapping a readback buffer");
    });
    dev.poll(wgpu::PollType::wait_indefinitely())
        .expect("the device finishes its work");
    let data = slice
        .get_mapped_range()
        .expect("mapped range of a mapped buffer")
        .to_vec();
    buf.unmap();
    data
}

#[cfg(test)]
mod tests {
    use super::probe_tables;

    #[test]
    fn probe_tables_sort_deduplicate_and_pad() {
        // Three probes on two particles, out of order.
        let (ids, refs) = probe_tables(&[[40, 1], [7, 2], [40, 5]]);
        assert_eq!(ids, vec![7, 40, u32::MAX]);
        assert_eq!(refs, vec![[1, 1], [0, 2], [1, 5]]);
        let (ids, refs) = probe_tables(&[]);
        assert!(ids.is_empty() && refs.is_empty());
    }
}
