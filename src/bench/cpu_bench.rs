//! The CPU path of the benchmark: the disk impact stepped and timed.

use std::time::{Duration, Instant};

use crate::cpu::CpuSolver;
use crate::model::{Model, State};

use super::case::DiskCase;
use super::{BenchError, MAX_APPROACH_STEPS, SETTLE_STEPS};

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
