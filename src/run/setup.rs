//! What a run sets up around its steps: where it starts (fresh or from a
//! checkpoint), its recorder, and its summary at the end.

use super::*;

/// Where a run starts: its time and the ledger's reference values, fresh
/// or taken over from a checkpoint (which it takes apart, nothing copied).
pub(super) struct Start {
    pub(super) t: f64,
    /// The momentum and the total energy the ledger is held to.
    pub(super) p0: glam::DVec2,
    pub(super) base_energy: f64,
    /// Wall time the run had taken before a resume.
    pub(super) wall_before: f64,
    /// Where particles start, for the summary's first failures (empty
    /// without a plastic history).
    pub(super) x0: Vec<glam::DVec2>,
}

/// What a resumed run takes over: the ledger, the recorder's state and
/// the solver's.
pub(super) type Resumed = (Ledger, RecorderState, SolverState);

impl Start {
    pub(super) fn of(
        model: &Model,
        state: &State,
        resume: Option<Checkpoint>,
    ) -> (Start, Option<Resumed>) {
        let x0 = if model.history {
            state.x.clone()
        } else {
            Vec::new()
        };
        let resume = resume.map(|ck| (ck.time(), ck.ledger, ck.recorder, ck.solver));
        let t = resume.as_ref().map_or(0.0, |r| r.0);
        let ledger = resume.as_ref().map(|r| &r.1);
        let (p0, base_energy) = match ledger {
            Some(l) => (l.momentum, l.base_energy),
            None => (
                probe::momentum(model, state),
                probe::energies(model, state, &Diagnostics::default()).total(),
            ),
        };
        let wall_before = ledger.map_or(0.0, |l| l.wall_seconds);
        let start = Start {
            t,
            p0,
            base_energy,
            wall_before,
            x0,
        };
        (start, resume.map(|(_, l, r, s)| (l, r, s)))
    }
}

/// What a run's recorder and summary read of the run.
pub(super) struct RunSetup<'a> {
    pub(super) scene: &'a Scene,
    pub(super) label: &'a str,
    pub(super) dir: Option<&'a Path>,
    pub(super) backend: Backend,
    pub(super) adapter: Option<String>,
}

impl RunSetup<'_> {
    /// The recorder of a run of `n` particles from `start` (a resumed
    /// run's rows, snapshots and checkpoint interval taken over from
    /// `resume`), and the solver state and ledger to resume with; its
    /// checkpoints carry the run's `warnings` so far.
    pub(super) fn recorder(
        &self,
        opts: &RunOptions,
        start: &Start,
        resume: Option<Resumed>,
        warnings: &[String],
        n: usize,
    ) -> Result<(Recorder, Option<(SolverState, Ledger)>), RunError> {
        let (scene, end) = (self.scene, self.scene.simulation.end_time);
        // A resumed run goes on writing checkpoints at the interval it was
        // started with, unless told another.
        let every = opts
            .checkpoint_every
            .or(resume.as_ref().map(|r| r.1.checkpoint_every));
        let checkpoints = match (self.dir, every) {
            (Some(d), Some(every)) => Some(Checkpoints {
                dir: d.to_path_buf(),
                every,
                next: match &resume {
                    Some((_, rec, _)) if rec.checkpoint_every == every => rec.next_checkpoint,
                    Some(_) => next_multiple(start.t, every),
                    None => every,
                },
                scene: scene.clone(),
                scene_label: self.label.to_string(),
                backend: self.backend,
                adapter: self.adapter.clone(),
                ledger: Ledger {
                    base_energy: start.base_energy,
                    momentum: start.p0,
                    stored0: 0.0,
                    max_fallback: 0,
                    wall_seconds: start.wall_before,
                    warnings: warnings.to_vec(),
                },
            }),
            _ => None,
        };
        let (recorded, resume) = match resume {
            Some((ledger, rec, solver)) => (Some(rec), Some((solver, ledger))),
            None => (None, None),
        };
        let RecorderState {
            times: done_times,
            rows: done_rows,
            prev,
            snapshots: done_snaps,
            ..
        } = recorded.unwrap_or_default();
        let snaps = match (self.dir, scene.output.snapshot_interval) {
            (Some(d), Some(interval)) => Some(Snapshots {
                times: history_times(end, interval),
                next: done_snaps.len(),
                // (A fresh run's list is empty: every old file goes.)
                series: SnapshotSeries::open(d, done_snaps)?,
            }),
            _ => None,
        };
        let names = scene.probes.iter().map(|p| p.name().to_string()).collect();
        let rec = Recorder {
            times: history_times(end, scene.history_interval()),
            next: done_times.len(),
            prev,
            history: History::resume(names, done_times, done_rows, self.dir)?,
            snaps,
            progress: Progress::new(opts, start.t, end),
            start: Instant::now(),
            end,
            particles: n,
            checkpoints,
        };
        Ok((rec, resume))
    }

    /// The run's summary from the solver's outcome `out`, its warnings
    /// (those before the steps, those after), its wall time and its
    /// snapshots' `(count, bytes, seconds)`; and the final model and state.
    pub(super) fn summary(
        &self,
        out: Outcome,
        [mut warnings, late]: [Vec<String>; 2],
        start: &Start,
        wall: f64,
        (snapshots, snapshot_bytes, snapshot_seconds): (usize, u64, f64),
    ) -> (Summary, Model, State) {
        let Outcome {
            model: final_model,
            state: final_state,
            stored,
            failure,
            max_fallback,
            adapter,
            warnings: extra,
        } = out;
        let (model, st) = (&final_model, &final_state);
        warnings.extend(extra);
        warnings.extend(late);
        let dim = model.dim;
        let n = model.len();
        let e0 = start.base_energy + stored.0;
        let final_diag = Diagnostics {
            contact: ContactStats {
                stored: stored.1,
                ..Default::default()
            },
            ..Default::default()
        };
        let end_energy = probe::energies(model, st, &final_diag);
        let spring_loss = st.spring_work - (stored.1 - stored.0);
        let out_of_range = crate::output::OutOfRangeSummary::of(model, st);
        if let Some(line) = out_of_range.line() {
            eprintln!("warning: {line}");
            warnings.push(line);
        }
        if max_fallback > 0 {
            warnings.push(format!(
                "up to {max_fallback} particle(s) at a time were debris: too few neighbours for the corrected gradient, so L = I and no deviatoric stress or tension"
            ));
        }
        let debris = crate::output::DebrisSummary::of(model, st, max_fallback as usize);
        let summary = Summary {
            scene: self.label.to_string(),
            dimension: dim,
            backend: self.backend.to_string(),
            adapter,
            integrator: model.integrator.to_string(),
            particles: n,
            steps: st.step,
            end_time: self.scene.simulation.end_time,
            time_reached: st.t,
            wall_seconds: wall,
            particle_steps_per_second: st.step as f64 * n as f64 / wall.max(1e-9),
            momentum_initial: vec_of(start.p0, dim),
            momentum_final: vec_of(probe::momentum(model, st), dim),
            energy_initial: e0,
            energy_final: end_energy.total(),
            energy_spring_loss: spring_loss,
            energy: crate::output::EnergyLedger::new(
                e0,
                &end_energy,
                spring_loss,
                model.gravity.is_some(),
                (!model.held.is_empty()).then_some(st.held_work),
                model.rubs.then_some(st.friction_heat),
            ),
            bodies: (0..model.bodies.len())
                .map(|b| {
                    let (m, mv, _, _) = probe::body_means(model, st, b);
                    BodySummary {
                        name: model.bodies[b].name.clone(),
                        particles: model.bodies[b].range.len(),
                        mass: m,
                        velocity_final: vec_of(mv / m, dim),
                        failure: crate::output::BodyFailure::of(model, st, &start.x0, b),
                    }
                })
                .collect(),
            out_of_range,
            debris,
            constraints: model
                .held
                .iter()
                .zip(&st.held_impulse)
                .map(|(c, j)| crate::output::ConstraintSummary {
                    name: c.name.clone(),
                    particles: c.particles.len(),
                    impulse: vec_of(*j, dim),
                    work: c.velocity.dot(*j),
                })
                .collect(),
            snapshots,
            snapshot_bytes,
            snapshot_seconds,
            warnings,
            status: if failure.is_some() {
                "failed"
            } else {
                "completed"
            }
            .into(),
            error: failure.as_ref().map(|f| f.to_string()),
        };
        (summary, final_model, final_state)
    }
}
