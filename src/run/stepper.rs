//! The run loop of both backends ([`drive`]) and what it asks of each
//! ([`Stepper`]).

use super::*;

/// What a backend's advance towards a stop ended on ([`Stepper::advance`]).
pub(super) enum Advanced {
    /// The state at the stop is observed.
    Stop,
    /// A checkpoint fell due at the last state observed.
    CheckpointDue,
    /// The history is complete.
    Finished,
    /// The solver went unstable.
    Failed(Instability),
}

/// A backend as the run loop ([`drive`]) sees it: it steps towards a stop,
/// feeding the recorder every state it observes, and writes snapshots and
/// checkpoints of its current state.
pub(super) trait Stepper {
    /// Step towards `stop`, never past it, feeding `rec` each state: until
    /// the state at `stop` is observed, a checkpoint falls due, the
    /// history is complete, or the solver fails.
    fn advance(&mut self, rec: &mut Recorder, stop: f64) -> Result<Advanced, RunError>;
    /// The time of the last state observed.
    fn time(&self) -> f64;
    /// Steps this process has made.
    fn steps(&self) -> u64;
    /// The snapshot of the current state, at the stop `t`.
    fn snapshot(&mut self, rec: &mut Recorder, t: f64) -> Result<(), RunError>;
    /// The checkpoint of the current state.
    fn checkpoint(&mut self, rec: &mut Recorder) -> Result<(), RunError>;
    /// What the run hands back for the summary.
    fn finish(self, failure: Option<Instability>) -> Result<Outcome, RunError>;
}

/// The run loop of both backends: from stop to stop (the snapshot times,
/// then the end), a snapshot at each, checkpoints where they fall due.
pub(super) fn drive(mut s: impl Stepper, rec: &mut Recorder) -> Result<Outcome, RunError> {
    // The snapshot of the state the run starts from (the GPU observes a
    // state only by stepping from it).
    if rec.snapshot_due(s.time()) {
        s.snapshot(rec, s.time())?;
    }
    let mut failure = None;
    'run: loop {
        let stop = rec.next_stop();
        loop {
            match s.advance(rec, stop)? {
                Advanced::Stop => break,
                Advanced::CheckpointDue => s.checkpoint(rec)?,
                Advanced::Finished => break 'run,
                Advanced::Failed(e) => {
                    failure = Some(e);
                    break 'run;
                }
            }
        }
        if rec.snapshot_due(stop) {
            s.snapshot(rec, stop)?;
        }
        if stop >= rec.end || rec.finished() {
            break;
        }
        if rec.checkpoint_due(s.time()) {
            s.checkpoint(rec)?;
        }
        rec.report(s.time(), s.steps());
    }
    s.finish(failure)
}
