//! The GPU path as the run loop drives it: batches of steps on the device.

use super::stepper::{Advanced, Stepper};
use super::*;

/// Wall seconds a GPU batch is sized to take at most, so that a slow
/// device (a software one, a scene of millions of particles) still returns
/// to the host for progress lines and history rows every few seconds.
pub(super) const BATCH_SECONDS: f64 = 2.0;

/// The GPU path as a [`Stepper`]: batches of steps on the device, each
/// handing back the observations of the states it passed through. The
/// device stops at the stop it is given: the batches run until it reports
/// the stop reached.
pub(super) struct GpuStepper {
    solver: GpuSolver,
    adapter: String,
    /// The run's end time.
    end: f64,
    /// The stop the device was last given.
    stop: Option<f64>,
    /// The last state delivered.
    t_last: f64,
    /// The stored penalty energy at the first and the last state.
    stored: (Option<f64>, f64),
    steps: u64,
    /// The step size the batches are sized by: the longest step of the
    /// last batch (the device's own last step may be one shortened to a
    /// stop).
    dt_est: f64,
    seconds_per_step: f64,
    /// Where the device is to be lost on purpose (`SPHCONTACT_GPU_LOSE_AT`,
    /// simulated seconds): the tests of a run that loses its device.
    lose_at: Option<f64>,
}

/// The simulated time `SPHCONTACT_GPU_LOSE_AT` names, if set: after the
/// first batch that reaches it the device is destroyed, as a driver reset
/// would lose it (tests of a failing device).
fn lose_at() -> Result<Option<f64>, RunError> {
    crate::gpu::env_value(
        "SPHCONTACT_GPU_LOSE_AT",
        |t: &f64| t.is_finite() && *t >= 0.0,
        "a time >= 0 in seconds",
    )
    .map_err(gpu_cannot)
}

/// The GPU backend cannot run the scene: why.
fn gpu_cannot(message: String) -> RunError {
    RunError::Backend {
        backend: "gpu",
        message,
    }
}

impl GpuStepper {
    /// `Err` if the device has failed: nothing it hands back is a state.
    fn check_device(&self) -> Result<(), RunError> {
        match self.solver.fault() {
            None => Ok(()),
            Some(f) => Err(RunError::Device(format!(
                "the GPU failed after t = {:.6e} s ({} steps): {f}",
                self.t_last, self.steps
            ))),
        }
    }

    pub(super) fn new(
        ctx: Arc<GpuContext>,
        model: Model,
        state: State,
        probes: &[probe::Resolved],
        end: f64,
        resume: Option<(SolverState, Ledger)>,
    ) -> Result<Self, RunError> {
        let adapter = ctx.adapter_name();
        let lose_at = lose_at()?;
        // A resumed solver is made from the initial state (which fixes the
        // grid's frame and every constant) before its buffers are
        // overwritten.
        let mut solver = GpuSolver::new(ctx, model, &state, probes, end).map_err(gpu_cannot)?;
        let mut stored = (None, 0.0);
        let mut t_last = 0.0;
        if let Some((saved, ledger)) = resume {
            let SolverState::Gpu(g) = saved else {
                unreachable!("a checkpoint resumes on the backend that wrote it");
            };
            solver
                .restore_raw(&g.device)
                .map_err(|e| RunError::checkpoint(crate::checkpoint::FILE, e))?;
            stored = (Some(ledger.stored0), g.stored_last);
            t_last = g.t_last;
        }
        Ok(GpuStepper {
            solver,
            adapter,
            end,
            stop: None,
            t_last,
            stored,
            steps: 0,
            dt_est: 0.0,
            seconds_per_step: 0.0,
            lose_at,
        })
    }
}

impl Stepper for GpuStepper {
    fn advance(&mut self, rec: &mut Recorder, stop: f64) -> Result<Advanced, RunError> {
        if self.stop != Some(stop) {
            self.solver.set_stop_time(stop);
            self.stop = Some(stop);
        }
        loop {
            if self.lose_at.is_some_and(|t| self.t_last >= t) {
                self.lose_at = None;
                self.solver.lose_device();
            }
            // Enough steps to reach the stop at the estimated step size,
            // plus the zero-length step that observes the state there; or,
            // with a checkpoint due before the stop, to reach its time (a
            // checkpoint is taken between batches, and steps are never
            // shortened for one).
            let t_last = self.t_last;
            let mut want = match (self.dt_est > 0.0, rec.next_checkpoint()) {
                (false, _) => 16.0,
                (true, Some(tc)) if tc < stop => ((tc - t_last) / self.dt_est).ceil().max(1.0),
                (true, _) => ((stop - t_last) / self.dt_est).ceil() + 2.0,
            };
            if self.seconds_per_step > 0.0 {
                want = want.min((BATCH_SECONDS / self.seconds_per_step).floor().max(1.0));
            }
            // (`run_batch` caps a batch at what the observation ring holds.)
            let started = Instant::now();
            let encoded = (want as u32).clamp(1, crate::gpu::RING_LEN - 2);
            let batch = self.solver.run_batch(encoded);
            self.check_device()?;
            self.seconds_per_step = started.elapsed().as_secs_f64() / encoded as f64;
            let count = batch.states.len();
            let mut longest: f64 = 0.0;
            for (k, (t, obs, e_stored)) in batch.states.into_iter().enumerate() {
                // The device stops within 1e-4 of a step of the stop: that
                // state is at the stop.
                let t = if batch.done && k + 1 == count {
                    stop
                } else {
                    t
                };
                self.stored.0.get_or_insert(e_stored);
                self.stored.1 = e_stored;
                rec.feed(t, obs)?;
                longest = longest.max(t - self.t_last);
                self.t_last = t;
            }
            if longest > 0.0 {
                self.dt_est = longest;
            }
            self.steps += count as u64;
            if let Some(e) = batch.failure {
                return Ok(Advanced::Failed(e));
            }
            if batch.done || rec.finished() {
                return Ok(Advanced::Stop);
            }
            if rec.checkpoint_due(self.t_last) {
                return Ok(Advanced::CheckpointDue);
            }
            rec.report(self.t_last, self.steps);
        }
    }

    fn time(&self) -> f64 {
        self.t_last
    }

    fn steps(&self) -> u64 {
        self.steps
    }

    fn snapshot(&mut self, rec: &mut Recorder, t: f64) -> Result<(), RunError> {
        let prepared = Instant::now();
        let (state, normal, boundary) = self.solver.snapshot();
        self.check_device()?;
        let fields = Fields {
            model: &self.solver.model,
            state: &state,
            normal: &normal,
            boundary: &boundary,
        };
        rec.snapshot(t, &fields, prepared)
    }

    /// The checkpoint of the device's state after the states delivered so
    /// far (the last at `t_last`).
    fn checkpoint(&mut self, rec: &mut Recorder) -> Result<(), RunError> {
        let g = GpuState {
            device: self.solver.save_raw(),
            t_last: self.t_last,
            stored_last: self.stored.1,
        };
        // A failed device's readback must not replace the last checkpoint.
        self.check_device()?;
        // (The device keeps its own count of correction fallbacks, in the
        // saved control block.)
        let fallback = 0;
        let stored0 = self.stored.0.unwrap_or(0.0);
        rec.checkpoint(
            self.t_last,
            stored0,
            fallback,
            SolverState::Gpu(Box::new(g)),
        )
    }

    fn finish(self, failure: Option<Instability>) -> Result<Outcome, RunError> {
        let (mut state, ctl) = self.solver.download_with_control();
        self.check_device()?;
        if failure.is_none() {
            state.t = self.end;
        }
        let mut warnings = Vec::new();
        let multi = ctl.multi_partner;
        if multi > 0 {
            warnings.push(format!(
                "{multi} contact evaluation(s) met two partner bodies at one particle; the GPU path pairs each particle with the first"
            ));
        }
        Ok(Outcome {
            model: self.solver.into_model(),
            state,
            stored: (self.stored.0.unwrap_or(0.0), self.stored.1),
            failure,
            max_fallback: ctl.fallback_max,
            adapter: Some(self.adapter),
            warnings,
        })
    }
}
