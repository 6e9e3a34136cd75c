//! The CPU path as the run loop drives it: one step at a time.

use super::record::OUT_OF_RANGE_STEPS;
use super::stepper::{Advanced, Stepper};
use super::*;

/// The CPU path as a [`Stepper`]: one step at a time, each state observed
/// before the next step.
pub(super) struct CpuStepper<'a> {
    solver: CpuSolver,
    probes: &'a [probe::Resolved],
    /// The first step of this process (progress counts from it).
    first_step: u64,
    /// Whether the current state has been fed to the recorder.
    fed: bool,
    max_fallback: usize,
    /// The stored penalty energy at the first state.
    stored0: Option<f64>,
}

impl<'a> CpuStepper<'a> {
    pub(super) fn new(
        model: Model,
        state: State,
        probes: &'a [probe::Resolved],
        resume: Option<(SolverState, Ledger)>,
    ) -> Self {
        let mut max_fallback = 0;
        let mut stored0 = None;
        let solver = match resume {
            Some((saved, ledger)) => {
                let SolverState::Cpu(c) = saved else {
                    unreachable!("a checkpoint resumes on the backend that wrote it");
                };
                max_fallback = ledger.max_fallback as usize;
                stored0 = Some(ledger.stored0);
                let CpuState {
                    state,
                    initial_dt,
                    energy_limit,
                    lists,
                    carried,
                } = *c;
                CpuSolver::restored(model, state, initial_dt, energy_limit, lists, carried)
            }
            None => CpuSolver::new(model, state),
        };
        CpuStepper {
            first_step: solver.state.step,
            solver,
            probes,
            fed: false,
            max_fallback,
            stored0,
        }
    }
}

impl Stepper for CpuStepper<'_> {
    fn advance(&mut self, rec: &mut Recorder, stop: f64) -> Result<Advanced, RunError> {
        loop {
            let t = self.solver.state.t;
            if !self.fed {
                let (model, st, diag) = self.solver.observe();
                self.max_fallback = self.max_fallback.max(diag.correction_fallback);
                rec.progress.debris = Some(diag.correction_fallback);
                self.stored0.get_or_insert(diag.contact.stored);
                rec.feed(t, probe::evaluate(self.probes, model, st, diag))?;
                self.fed = true;
            }
            // The steps land on the snapshot times.
            if rec.snapshot_due(t) {
                return Ok(Advanced::Stop);
            }
            if rec.finished() || t >= rec.end {
                return Ok(Advanced::Finished);
            }
            if rec.checkpoint_due(t) {
                return Ok(Advanced::CheckpointDue);
            }
            if let Err(e) = self.solver.step(stop - t) {
                return Ok(Advanced::Failed(e));
            }
            self.fed = false;
            let st = &self.solver.state;
            if st.step.is_multiple_of(OUT_OF_RANGE_STEPS) {
                rec.progress.out_of_range =
                    Some(probe::count_out_of_range(&self.solver.model, st).total());
            }
            rec.report(st.t, st.step - self.first_step);
        }
    }

    fn time(&self) -> f64 {
        self.solver.state.t
    }

    fn steps(&self) -> u64 {
        self.solver.state.step - self.first_step
    }

    fn snapshot(&mut self, rec: &mut Recorder, t: f64) -> Result<(), RunError> {
        let prepared = Instant::now();
        let (model, st) = (&self.solver.model, &self.solver.state);
        let (normal, boundary) = crate::cpu::surface(model, st);
        let fields = Fields {
            model,
            state: st,
            normal: &normal,
            boundary: &boundary,
        };
        rec.snapshot(t, &fields, prepared)
    }

    fn checkpoint(&mut self, rec: &mut Recorder) -> Result<(), RunError> {
        let solver = &self.solver;
        let (initial_dt, energy_limit, lists) = solver.resume_parts();
        let saved = SolverState::Cpu(Box::new(CpuState {
            state: solver.state.clone(),
            initial_dt,
            energy_limit,
            lists: lists.clone(),
            carried: solver.carried().cloned(),
        }));
        let (t, stored0) = (solver.state.t, self.stored0.unwrap_or(0.0));
        rec.checkpoint(t, stored0, self.max_fallback as u32, saved)
    }

    fn finish(mut self, failure: Option<Instability>) -> Result<Outcome, RunError> {
        let stored1 = self.solver.diagnostics().contact.stored;
        let CpuSolver { model, state, .. } = self.solver;
        Ok(Outcome {
            model,
            state,
            stored: (self.stored0.unwrap_or(0.0), stored1),
            failure,
            max_fallback: self.max_fallback as u32,
            adapter: None,
            warnings: Vec::new(),
        })
    }
}
