//! The GPU path of the benchmark: the disk impact stepped and timed in
//! batches, and its stages timed alone.

use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::gpu::profile::StepProfile;
use crate::gpu::{GpuContext, GpuSolver, RING_LEN};

use super::case::DiskCase;
use super::{BenchError, StageTime, END_TIME, MAX_APPROACH_STEPS, PROFILE_STEPS, SETTLE_STEPS};

/// The GPU path stepping the disk impact in batches, restarting it when a
/// timed run would leave the contact phase.
pub struct GpuBench {
    ctx: Arc<GpuContext>,
    case: DiskCase,
    pub(super) solver: GpuSolver,
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
        if let Some(f) = self.solver.fault() {
            return Err(BenchError::Failed(format!(
                "the GPU benchmark run failed: {f}"
            )));
        }
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
