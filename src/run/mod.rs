//! Running a scene: the stepping loop, history rows and snapshots at exact
//! times, the progress display and the output files.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

use std::sync::Arc;

use crate::checkpoint::{Checkpoint, CpuState, GpuState, Ledger, RecorderState, SolverState};
use crate::cpu::CpuSolver;
use crate::error::{Instability, RunError};
use crate::gpu::{GpuContext, GpuSolver};
use crate::model::ContactStats;
use crate::model::Diagnostics;
use crate::model::{Model, State};
use crate::output::vtk::{Fields, SnapshotSeries};
use crate::output::{vec_of, BodySummary, History, Summary};
use crate::probe;
use crate::scene::{Backend, Integrator, Scene};

/// How to run a scene.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Output directory; `None` with `write = true` uses the scene's
    /// `output.dir` or `out/<scene stem>`.
    pub out_dir: Option<PathBuf>,
    /// Overrides the scene's backend.
    pub backend: Option<Backend>,
    /// Overrides the scene's end time.
    pub end_time: Option<f64>,
    /// Overrides the scene's integrator (`simulation.integrator`).
    pub integrator: Option<Integrator>,
    /// Plain occasional progress lines instead of a bar.
    pub quiet: bool,
    /// Print no progress at all (library use, tests).
    pub silent: bool,
    /// Write `history.csv`, `summary.json` and, when the scene sets
    /// `output.snapshot_interval`, the snapshots. Without it a run keeps
    /// nothing on disk, and does not shorten steps for snapshots either.
    pub write: bool,
    /// Write a checkpoint ([`crate::checkpoint`]) at the first state at or
    /// after every multiple of this simulated time, s (needs `write`).
    pub checkpoint_every: Option<f64>,
}

/// What a run returns.
#[derive(Debug)]
pub struct RunOutput {
    pub history: History,
    pub summary: Summary,
    pub out_dir: Option<PathBuf>,
    /// The particles' constants and their state at the end of the run (on
    /// the GPU path, read back once).
    pub model: Model,
    pub state: State,
}

/// The output directory docs/scenes.md gives ("Output section").
pub fn output_dir(scene: &Scene, scene_path: Option<&Path>, opts: &RunOptions) -> PathBuf {
    if let Some(d) = &opts.out_dir {
        return d.clone();
    }
    if let Some(d) = &scene.output.dir {
        return d.clone();
    }
    let stem = scene_path
        .and_then(|p| p.file_stem())
        .map_or("scene".to_string(), |s| s.to_string_lossy().into_owned());
    PathBuf::from("out").join(stem)
}

/// The backend that runs, its device when it is the GPU, and the warning to
/// print when the choice was a fallback.
pub struct BackendChoice {
    pub backend: Backend,
    pub gpu: Option<Arc<GpuContext>>,
    pub warning: Option<String>,
}

/// `cpu` runs the CPU path; `gpu` runs on any adapter (a software one
/// included) or fails; `auto` runs on a hardware GPU when there is one and
/// otherwise on the CPU path with one warning line: a software rasteriser
/// (lavapipe) is slower than the CPU path on the same cores.
pub fn choose_backend(scene: &Scene, opts: &RunOptions) -> Result<BackendChoice, RunError> {
    let cpu = |warning| BackendChoice {
        backend: Backend::Cpu,
        gpu: None,
        warning,
    };
    let backend = opts.backend.unwrap_or(scene.simulation.backend);
    match backend {
        Backend::Cpu => Ok(cpu(None)),
        Backend::Gpu => match crate::gpu::shared_context() {
            Ok(ctx) => Ok(BackendChoice {
                backend: Backend::Gpu,
                gpu: Some(ctx),
                warning: None,
            }),
            Err(e) => Err(RunError::Backend(format!(
                "backend gpu: {e}; use --backend cpu (or auto) to run on the CPU"
            ))),
        },
        Backend::Auto => match crate::gpu::shared_context() {
            Ok(ctx) if !ctx.is_software() => Ok(BackendChoice {
                backend: Backend::Gpu,
                gpu: Some(ctx),
                warning: None,
            }),
            Ok(ctx) => Ok(cpu(Some(format!(
                "backend auto: the only adapter is a software one ({}); running the CPU path (--backend gpu uses it anyway)",
                ctx.adapter_name()
            )))),
            Err(e) => Ok(cpu(Some(format!(
                "backend auto: {e}; running the CPU path"
            )))),
        },
    }
}

/// What both backends' loops record into: history rows at exact times,
/// snapshots at exact times, and the progress display.
///
/// A history row between two observed states is their linear
/// interpolation, so steps are never shortened for history. A snapshot
/// holds a whole state, which interpolation would not make a state of the
/// method (its boundary set and normals least of all), so the loops shorten
/// the step that would cross a snapshot time to land on it
/// ([`Recorder::next_stop`]): about one shortened step per snapshot.
struct Recorder {
    times: Vec<f64>,
    next: usize,
    prev: Option<(f64, Vec<f64>)>,
    history: History,
    snaps: Option<Snapshots>,
    progress: Progress,
    start: Instant,
    end: f64,
    particles: usize,
    checkpoints: Option<Checkpoints>,
}

/// Where and when checkpoints go, and what each carries besides the
/// solver's and the recorder's state.
struct Checkpoints {
    dir: PathBuf,
    every: f64,
    next: f64,
    scene: Scene,
    scene_label: String,
    backend: Backend,
    adapter: Option<String>,
    /// The ledger as of the start of this process (its wall seconds those
    /// of the run before it); each checkpoint fills in the rest.
    ledger: Ledger,
}

/// The snapshot times not yet written and the files written so far.
struct Snapshots {
    times: Vec<f64>,
    next: usize,
    series: SnapshotSeries,
}

/// Relative tolerance under which a state's time counts as a recorded
/// time: round-off of the time sum, far below any step.
const AT_TIME: f64 = 1e-12;

impl Recorder {
    /// Observations `obs` of the state at time `t`: writes every history
    /// row up to `t`.
    fn feed(&mut self, t: f64, obs: Vec<f64>) -> Result<(), RunError> {
        while self.next < self.times.len() && self.times[self.next] <= t * (1.0 + AT_TIME) {
            let tr = self.times[self.next];
            let row = match &self.prev {
                Some((tp, vp)) if tr < t => {
                    let a = (tr - tp) / (t - tp);
                    vp.iter().zip(&obs).map(|(p, c)| p + a * (c - p)).collect()
                }
                _ => obs.clone(),
            };
            self.history.push(tr, row)?;
            self.next += 1;
        }
        self.prev = Some((t, obs));
        Ok(())
    }

    fn finished(&self) -> bool {
        self.next >= self.times.len()
    }

    /// A snapshot is due at the state at time `t`.
    fn snapshot_due(&self, t: f64) -> bool {
        self.snaps.as_ref().is_some_and(|s| {
            s.times
                .get(s.next)
                .is_some_and(|&ts| ts <= t * (1.0 + AT_TIME))
        })
    }

    /// Where the coming steps must stop: the next snapshot time, else the end.
    fn next_stop(&self) -> f64 {
        self.snaps
            .as_ref()
            .and_then(|s| s.times.get(s.next))
            .map_or(self.end, |&ts| ts.min(self.end))
    }

    /// Write the snapshot due at the state at `t` (labelled with its exact
    /// time, which `t` meets up to round-off). `prepared` is when the loop
    /// began making `fields` (the boundary set, the device readback), so
    /// that the snapshot's whole cost is booked.
    fn snapshot(&mut self, t: f64, fields: &Fields, prepared: Instant) -> Result<(), RunError> {
        self.progress.out_of_range =
            Some(probe::count_out_of_range(fields.model, fields.state).total());
        let Some(s) = &mut self.snaps else {
            return Ok(());
        };
        let writing = Instant::now();
        s.series.seconds += (writing - prepared).as_secs_f64();
        while let Some(&ts) = s.times.get(s.next).filter(|&&ts| ts <= t * (1.0 + AT_TIME)) {
            s.series.write(ts, fields)?;
            s.next += 1;
        }
        self.progress.snapshots = Some(s.series.count());
        Ok(())
    }

    /// The time of the next checkpoint, if the run writes checkpoints.
    fn next_checkpoint(&self) -> Option<f64> {
        self.checkpoints.as_ref().map(|c| c.next)
    }

    /// A checkpoint is due at the state at time `t` (never at the end: the
    /// run is complete there).
    fn checkpoint_due(&self, t: f64) -> bool {
        self.checkpoints
            .as_ref()
            .is_some_and(|c| t >= c.next * (1.0 - AT_TIME) && !self.finished() && t < self.end)
    }

    /// Write the checkpoint of the state at `t`: the solver's part comes
    /// from the loop, with the stored penalty energy at the first state
    /// and the largest correction fallback so far.
    fn checkpoint(
        &mut self,
        t: f64,
        stored0: f64,
        max_fallback: u32,
        solver: SolverState,
    ) -> Result<(), RunError> {
        let wall = self.start.elapsed().as_secs_f64();
        let Some(c) = &mut self.checkpoints else {
            return Ok(());
        };
        let next = next_multiple(t, c.every);
        let ck = Checkpoint {
            scene_label: c.scene_label.clone(),
            scene: c.scene.clone(),
            backend: c.backend,
            adapter: c.adapter.clone(),
            ledger: Ledger {
                stored0,
                max_fallback,
                wall_seconds: c.ledger.wall_seconds + wall,
                ..c.ledger.clone()
            },
            recorder: RecorderState {
                times: self.history.times.clone(),
                rows: self.history.rows.clone(),
                prev: self.prev.clone(),
                snapshots: self
                    .snaps
                    .as_ref()
                    .map_or(Vec::new(), |s| s.series.entries().to_vec()),
                checkpoint_every: c.every,
                next_checkpoint: next,
            },
            solver,
        };
        ck.write(&c.dir)?;
        c.next = next;
        Ok(())
    }

    /// Progress after `steps` steps, at simulated time `t`.
    fn report(&mut self, t: f64, steps: u64) {
        let secs = self.start.elapsed().as_secs_f64().max(1e-9);
        let rate = steps as f64 * self.particles as f64 / secs;
        self.progress.update(t, self.end, steps, rate, secs);
    }
}

/// The first multiple of `every` after `t` (a `t` within round-off of a
/// multiple counts as on it).
fn next_multiple(t: f64, every: f64) -> f64 {
    ((t / every * (1.0 + AT_TIME)).floor() + 1.0) * every
}

/// What a backend's loop hands back for the summary.
struct Outcome {
    model: Model,
    state: State,
    /// Stored penalty energy at the first and the last state.
    stored: (f64, f64),
    failure: Option<Instability>,
    max_fallback: u32,
    adapter: Option<String>,
    warnings: Vec<String>,
}

/// History times: `k · interval` from 0 through `end`, plus `end` itself if
/// the interval does not divide it.
pub fn history_times(end: f64, interval: f64) -> Vec<f64> {
    let n = (end / interval * (1.0 + 1e-12)).floor() as usize;
    let mut t: Vec<f64> = (0..=n).map(|k| k as f64 * interval).collect();
    if end - t[n] > 1e-9 * interval {
        t.push(end);
    }
    t
}

/// Plain progress lines come at least this often in simulated time (per
/// cent of the end time) and in wall time (seconds), whichever is first.
const LINE_PERCENT: f64 = 5.0;
const LINE_SECONDS: f64 = 10.0;

struct Progress {
    bar: Option<ProgressBar>,
    plain: bool,
    /// Per cent of the end time at which the next plain line is due.
    next_percent: f64,
    last_line: Instant,
    /// Snapshots written so far, when the run writes snapshots.
    snapshots: Option<usize>,
    /// Particles outside the solid range (`probe::out_of_range`) when last
    /// counted: every few steps on the CPU, at each snapshot on the GPU.
    out_of_range: Option<usize>,
    /// Simulated time this process started from (that of the checkpoint
    /// when resuming): the wall time so far covers only what came after.
    t0: f64,
}

/// The per cent of the end time at which the plain line after one at
/// `percent` is due: the next multiple of [`LINE_PERCENT`].
fn next_line_percent(percent: f64) -> f64 {
    ((percent / LINE_PERCENT).floor() + 1.0) * LINE_PERCENT
}

/// Wall seconds left when this process has taken `elapsed` seconds to go
/// from simulated time `t0` to `t` of `end`, at the same pace; `None`
/// before any simulated time has passed.
fn eta_seconds(elapsed: f64, t0: f64, t: f64, end: f64) -> Option<f64> {
    (t > t0).then(|| elapsed * (end - t).max(0.0) / (t - t0))
}

impl Progress {
    fn new(opts: &RunOptions, t0: f64, end: f64) -> Self {
        let mut p = Self {
            bar: None,
            plain: false,
            // A resumed run's first plain line is due at the next multiple.
            next_percent: next_line_percent(100.0 * t0 / end),
            last_line: Instant::now(),
            snapshots: None,
            out_of_range: None,
            t0,
        };
        if opts.silent {
            return p;
        }
        if !opts.quiet && std::io::stderr().is_terminal() {
            let bar = ProgressBar::new(1000);
            bar.set_style(
                ProgressStyle::with_template(
                    "{bar:40} t = {msg} [{elapsed_precise} < {eta_precise}]",
                )
                .expect("a valid template"),
            );
            // A resumed run's bar starts where the checkpoint was, and its
            // rate estimate from there (not from a jump at the first step).
            bar.set_position(((t0 / end).clamp(0.0, 1.0) * 1000.0) as u64);
            bar.reset_eta();
            p.bar = Some(bar);
        } else {
            p.plain = true;
        }
        p
    }

    /// `elapsed`: wall seconds since the run started.
    fn update(&mut self, t: f64, end: f64, steps: u64, rate: f64, elapsed: f64) {
        let frac = (t / end).clamp(0.0, 1.0);
        let mut tail = self
            .snapshots
            .map_or(String::new(), |k| format!(", snapshots written: {k}"));
        if let Some(k) = self.out_of_range.filter(|&k| k > 0) {
            tail += &format!(", {k} particle(s) outside the solid range");
        }
        if let Some(bar) = &self.bar {
            bar.set_position((frac * 1000.0) as u64);
            bar.set_message(format!(
                "{t:.3e} / {end:.3e} s, {steps} steps, {rate:.3e} particle-steps/s{tail}"
            ));
        } else if self.plain {
            let percent = frac * 100.0;
            let quiet_for = self.last_line.elapsed().as_secs_f64();
            if percent < self.next_percent && quiet_for < LINE_SECONDS {
                return;
            }
            self.next_percent = next_line_percent(percent);
            self.last_line = Instant::now();
            let eta = eta_seconds(elapsed, self.t0, t, end).map_or("unknown".into(), duration);
            eprintln!(
                "t = {t:.4e} s ({percent:.0} %), {steps} steps, {rate:.3e} particle-steps/s, ETA {eta}{tail}"
            );
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// How often the CPU loop counts the particles outside the solid range
/// for the progress line (a pass over the state, cheap against a step).
const OUT_OF_RANGE_STEPS: u64 = 64;

/// A wall-clock duration for people: `42 s`, `3 min 07 s`, `2 h 05 min`.
fn duration(secs: f64) -> String {
    let s = secs.max(0.0).round() as u64;
    if s < 60 {
        format!("{s} s")
    } else if s < 3600 {
        format!("{} min {:02} s", s / 60, s % 60)
    } else {
        format!("{} h {:02} min", s / 3600, (s % 3600) / 60)
    }
}

/// Run a validated scene. `scene_path` names it in the summary and sets the
/// default output directory.
pub fn run_scene(
    scene: &Scene,
    scene_path: Option<&Path>,
    opts: &RunOptions,
) -> Result<RunOutput, RunError> {
    let mut scene = scene.clone();
    if let Some(t) = opts.end_time {
        if !(t.is_finite() && t > 0.0) {
            return Err(RunError::Backend(format!(
                "--end-time must be > 0 (got {t})"
            )));
        }
        scene.simulation.end_time = t;
    }
    if let Some(i) = opts.integrator {
        scene.simulation.integrator = i;
    }
    let label = scene_path.map_or(String::new(), |p| p.display().to_string());
    let dir = opts.write.then(|| output_dir(&scene, scene_path, opts));
    run_from(scene, label, dir, opts, None)
}

/// Continue the run whose checkpoint is in output directory `dir`
/// ([`crate::checkpoint`]) to its end time, on the backend that wrote the
/// checkpoint, writing into `opts.out_dir` (default: `dir` itself). The
/// history comes out as the uninterrupted run's.
pub fn resume_run(dir: &Path, opts: &RunOptions) -> Result<RunOutput, RunError> {
    let ck = Checkpoint::read(dir)?;
    if opts.end_time.is_some() {
        return Err(RunError::Backend(
            "--end-time cannot be combined with --resume: a resumed run continues to the end time it was started with".into(),
        ));
    }
    if opts.integrator.is_some() {
        return Err(RunError::Backend(
            "--integrator cannot be combined with --resume: a resumed run continues with the integrator it was started with".into(),
        ));
    }
    if let Some(b) = opts
        .backend
        .filter(|&b| b != Backend::Auto && b != ck.backend)
    {
        return Err(RunError::Backend(format!(
            "--backend {b}: the checkpoint in {} was written by the {} backend, and a run resumes on the backend that wrote it",
            dir.display(),
            ck.backend
        )));
    }
    let mut opts = opts.clone();
    opts.backend = Some(ck.backend);
    opts.write = true;
    let out = opts.out_dir.clone().unwrap_or_else(|| dir.to_path_buf());
    run_from(
        ck.scene.clone(),
        ck.scene_label.clone(),
        Some(out),
        &opts,
        Some(ck),
    )
}

/// Run `scene` (its end time final), from its start or from checkpoint
/// `resume`, writing into `dir` when given.
fn run_from(
    scene: Scene,
    label: String,
    dir: Option<PathBuf>,
    opts: &RunOptions,
    resume: Option<Checkpoint>,
) -> Result<RunOutput, RunError> {
    if let Some(every) = opts.checkpoint_every {
        if !(every.is_finite() && every > 0.0) {
            return Err(RunError::Backend(format!(
                "--checkpoint-every must be > 0 (got {every})"
            )));
        }
        if dir.is_none() {
            return Err(RunError::Backend(
                "checkpoints need an output directory (a run that writes its outputs)".into(),
            ));
        }
    }
    let choice = choose_backend(&scene, opts)?;
    let backend = choice.backend;
    let mut warnings = Vec::new();
    if let Some(w) = choice.warning {
        if !opts.silent {
            eprintln!("warning: {w}");
        }
        warnings.push(w);
    }
    if let Some(d) = &dir {
        std::fs::create_dir_all(d).map_err(|e| RunError::io(d, e))?;
    }
    let adapter = choice.gpu.as_ref().map(|c| c.adapter_name());
    if let Some(ck) = &resume {
        warnings.extend(ck.ledger.warnings.iter().cloned());
        if let (Some(was), Some(now)) = (&ck.adapter, &adapter) {
            if was != now {
                let w = format!(
                    "the checkpoint was written on adapter '{was}' and resumes on '{now}': the history may differ from an uninterrupted run in its last digits"
                );
                if !opts.silent {
                    eprintln!("warning: {w}");
                }
                warnings.push(w);
            }
        }
    }

    // The model and the probes come from the scene's initial state, also
    // when resuming: probes are fixed by where particles start.
    let (model, state) = Model::new(&scene);
    // Where particles start, for the summary's first failures.
    let x0 = if model.history {
        state.x.clone()
    } else {
        Vec::new()
    };
    if let Some(ck) = &resume {
        ck.check_sizes(&model, "the checkpoint")?;
    }
    let dim = model.dim;
    let probes = probe::resolve(&scene, &model, &state);
    let names = scene.probes.iter().map(|p| p.name().to_string()).collect();
    let end = scene.simulation.end_time;
    let n = model.len();
    // What a resumed run takes over: the ledger, the recorder's state and
    // the solver's (the checkpoint taken apart, nothing copied).
    let resume = resume.map(|ck| (ck.time(), ck.ledger, ck.recorder, ck.solver));
    let t_start = resume.as_ref().map_or(0.0, |r| r.0);
    let ledger = resume.as_ref().map(|r| &r.1);
    let (p0, base_energy) = match ledger {
        Some(l) => (l.momentum, l.base_energy),
        None => (
            probe::momentum(&model, &state),
            probe::energies(&model, &state, &Diagnostics::default()).total(),
        ),
    };
    let wall_before = ledger.map_or(0.0, |l| l.wall_seconds);
    // A resumed run goes on writing checkpoints at the interval it was
    // started with, unless told another.
    let every = opts
        .checkpoint_every
        .or(resume.as_ref().map(|r| r.2.checkpoint_every));
    let checkpoints = match (&dir, every) {
        (Some(d), Some(every)) => Some(Checkpoints {
            dir: d.clone(),
            every,
            next: match &resume {
                Some((_, _, rec, _)) if rec.checkpoint_every == every => rec.next_checkpoint,
                Some((t, ..)) => next_multiple(*t, every),
                None => every,
            },
            scene: scene.clone(),
            scene_label: label.clone(),
            backend,
            adapter: adapter.clone(),
            ledger: Ledger {
                base_energy,
                momentum: p0,
                stored0: 0.0,
                max_fallback: 0,
                wall_seconds: wall_before,
                warnings: warnings.clone(),
            },
        }),
        _ => None,
    };
    let (recorded, resume) = match resume {
        Some((_, ledger, rec, solver)) => (Some(rec), Some((solver, ledger))),
        None => (None, None),
    };
    let RecorderState {
        times: done_times,
        rows: done_rows,
        prev,
        snapshots: done_snaps,
        ..
    } = recorded.unwrap_or_default();
    let snaps = match (&dir, scene.output.snapshot_interval) {
        (Some(d), Some(interval)) => Some(Snapshots {
            times: history_times(end, interval),
            next: done_snaps.len(),
            // (A fresh run's list is empty: every old file goes.)
            series: SnapshotSeries::open(d, done_snaps)?,
        }),
        _ => None,
    };
    let mut rec = Recorder {
        times: history_times(end, scene.history_interval()),
        next: done_times.len(),
        prev,
        history: History::resume(names, done_times, done_rows, dir.as_deref())?,
        snaps,
        progress: Progress::new(opts, t_start, end),
        start: Instant::now(),
        end,
        particles: n,
        checkpoints,
    };
    let out = match choice.gpu {
        Some(ctx) => run_gpu(ctx, model, state, &probes, &mut rec, resume)?,
        None => run_cpu(model, state, &probes, &mut rec, resume)?,
    };
    rec.progress.finish();
    rec.history.flush()?;
    let mut rec_warnings = Vec::new();
    if let Some(d) = &dir {
        // A picture of the run; one that cannot be drawn (no font) is a
        // warning, never the run's failure.
        if let Err(e) = crate::output::history_plot::write(d, &scene, &rec.history) {
            let w = format!("history.png not drawn: {e}");
            if !opts.silent {
                eprintln!("warning: {w}");
            }
            rec_warnings.push(w);
        }
    }
    let wall = wall_before + rec.start.elapsed().as_secs_f64();
    let history = rec.history;
    let (snapshots, snapshot_bytes, snapshot_seconds) = rec.snaps.map_or((0, 0, 0.0), |s| {
        (s.series.count(), s.series.bytes, s.series.seconds)
    });
    let Outcome {
        model,
        state,
        stored,
        failure,
        max_fallback,
        adapter,
        warnings: extra,
    } = out;
    let (final_model, final_state) = (model, state);
    let (model, st) = (&final_model, &final_state);
    warnings.extend(extra);
    warnings.extend(rec_warnings);
    let e0 = base_energy + stored.0;
    let final_diag = Diagnostics {
        contact: ContactStats {
            stored: stored.1,
            ..Default::default()
        },
        ..Default::default()
    };
    let out_of_range = crate::output::OutOfRangeSummary::of(model, st);
    if let Some(line) = out_of_range.line() {
        eprintln!("warning: {line}");
        warnings.push(line);
    }
    if max_fallback > 0 {
        warnings.push(format!(
            "up to {max_fallback} particle(s) at a time had too few neighbours for the corrected gradient and used L = I"
        ));
    }
    let summary = Summary {
        scene: label,
        dimension: dim,
        backend: backend.to_string(),
        adapter,
        integrator: model.integrator.to_string(),
        particles: n,
        steps: st.step,
        end_time: end,
        time_reached: st.t,
        wall_seconds: wall,
        particle_steps_per_second: st.step as f64 * n as f64 / wall.max(1e-9),
        momentum_initial: vec_of(p0, dim),
        momentum_final: vec_of(probe::momentum(model, st), dim),
        energy_initial: e0,
        energy_final: probe::energies(model, st, &final_diag).total(),
        energy_spring_loss: st.spring_work - (stored.1 - stored.0),
        bodies: (0..model.bodies.len())
            .map(|b| {
                let (m, mv, _, _) = probe::body_means(model, st, b);
                BodySummary {
                    name: model.bodies[b].name.clone(),
                    particles: model.bodies[b].range.len(),
                    mass: m,
                    velocity_final: vec_of(mv / m, dim),
                    failure: crate::output::BodyFailure::of(model, st, &x0, b),
                }
            })
            .collect(),
        out_of_range,
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
    if let Some(d) = &dir {
        summary.write(d)?;
    }
    if let Some(f) = failure {
        return Err(RunError::Unstable(f));
    }
    Ok(RunOutput {
        history,
        summary,
        out_dir: dir,
        model: final_model,
        state: final_state,
    })
}

/// The CPU loop: each state is evaluated once and observed once.
fn run_cpu(
    model: Model,
    state: State,
    probes: &[probe::Resolved],
    rec: &mut Recorder,
    resume: Option<(SolverState, Ledger)>,
) -> Result<Outcome, RunError> {
    let end = rec.end;
    let mut max_fallback = 0;
    let mut stored0 = None;
    let mut solver = match resume {
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
    // Progress counts this process's steps.
    let first_step = solver.state.step;
    let mut failure = None;
    loop {
        let t = solver.state.t;
        let (model, st, diag) = solver.observe();
        max_fallback = max_fallback.max(diag.correction_fallback);
        stored0.get_or_insert(diag.contact.stored);
        let obs = probe::evaluate(probes, model, st, diag);
        rec.feed(t, obs)?;
        if rec.snapshot_due(t) {
            let prepared = Instant::now();
            let (model, st) = (&solver.model, &solver.state);
            let (normal, boundary) = crate::cpu::surface(model, st);
            let fields = Fields {
                model,
                state: st,
                normal: &normal,
                boundary: &boundary,
            };
            rec.snapshot(t, &fields, prepared)?;
        }
        if rec.finished() || t >= end {
            break;
        }
        if rec.checkpoint_due(t) {
            let (initial_dt, energy_limit, lists) = solver.resume_parts();
            let saved = SolverState::Cpu(Box::new(CpuState {
                state: solver.state.clone(),
                initial_dt,
                energy_limit,
                lists: lists.clone(),
                carried: solver.carried().cloned(),
            }));
            rec.checkpoint(t, stored0.unwrap_or(0.0), max_fallback as u32, saved)?;
        }
        if let Err(e) = solver.step(rec.next_stop() - t) {
            failure = Some(e);
            break;
        }
        if solver.state.step % OUT_OF_RANGE_STEPS == 0 {
            rec.progress.out_of_range =
                Some(probe::count_out_of_range(&solver.model, &solver.state).total());
        }
        rec.report(solver.state.t, solver.state.step - first_step);
    }
    let stored1 = solver.diagnostics().contact.stored;
    let CpuSolver { model, state, .. } = solver;
    Ok(Outcome {
        model,
        state,
        stored: (stored0.unwrap_or(0.0), stored1),
        failure,
        max_fallback: max_fallback as u32,
        adapter: None,
        warnings: Vec::new(),
    })
}

/// Wall seconds a GPU batch is sized to take at most, so that a slow
/// device (a software one, a scene of millions of particles) still returns
/// to the host for progress lines and history rows every few seconds.
const BATCH_SECONDS: f64 = 2.0;

/// The GPU loop: batches of steps on the device; each batch hands back the
/// observations of the states it passed through. The device stops at the
/// next snapshot time (then the end): the batches of one segment run until
/// it reports the stop reached.
fn run_gpu(
    ctx: Arc<GpuContext>,
    model: Model,
    state: State,
    probes: &[probe::Resolved],
    rec: &mut Recorder,
    resume: Option<(SolverState, Ledger)>,
) -> Result<Outcome, RunError> {
    let end = rec.end;
    let adapter = ctx.adapter_name();
    // A resumed solver is made from the initial state (which fixes the
    // grid's frame and every constant) before its buffers are overwritten.
    let mut solver = GpuSolver::new(ctx, model, &state, probes, end).map_err(RunError::Backend)?;
    let mut failure = None;
    let mut stored = (None, 0.0);
    let mut t_last = 0.0;
    if let Some((saved, ledger)) = resume {
        let SolverState::Gpu(g) = saved else {
            unreachable!("a checkpoint resumes on the backend that wrote it");
        };
        solver.restore_raw(&g.device).map_err(RunError::Backend)?;
        stored = (Some(ledger.stored0), g.stored_last);
        t_last = g.t_last;
    }
    let mut steps = 0u64;
    // The step size the batches are sized by: the longest step of the last
    // batch (the device's own last step may be one shortened to a stop).
    let mut dt_est = 0.0;
    let mut seconds_per_step = 0.0;
    if rec.snapshot_due(t_last) {
        gpu_snapshot(&mut solver, rec, t_last)?;
    }
    // The checkpoint of the device's state after the states delivered so
    // far (the last at `t_last`).
    let checkpoint =
        |solver: &GpuSolver, rec: &mut Recorder, t_last: f64, stored: (Option<f64>, f64)| {
            let g = GpuState {
                device: solver.save_raw(),
                t_last,
                stored_last: stored.1,
            };
            // (The device keeps its own count of correction fallbacks, in
            // the saved control block.)
            let fallback = 0;
            rec.checkpoint(
                t_last,
                stored.0.unwrap_or(0.0),
                fallback,
                SolverState::Gpu(Box::new(g)),
            )
        };
    'run: loop {
        let stop = rec.next_stop();
        solver.set_stop_time(stop);
        loop {
            // Enough steps to reach the stop at the estimated step size,
            // plus the zero-length step that observes the state there; or,
            // with a checkpoint due before the stop, to reach its time (a
            // checkpoint is taken between batches, and steps are never
            // shortened for one).
            let mut want = match (dt_est > 0.0, rec.next_checkpoint()) {
                (false, _) => 16.0,
                (true, Some(tc)) if tc < stop => ((tc - t_last) / dt_est).ceil().max(1.0),
                (true, _) => ((stop - t_last) / dt_est).ceil() + 2.0,
            };
            if seconds_per_step > 0.0 {
                want = want.min((BATCH_SECONDS / seconds_per_step).floor().max(1.0));
            }
            // (`run_batch` caps a batch at what the observation ring holds.)
            let started = Instant::now();
            let encoded = (want as u32).clamp(1, crate::gpu::RING_LEN - 2);
            let batch = solver.run_batch(encoded);
            seconds_per_step = started.elapsed().as_secs_f64() / encoded as f64;
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
                stored.0.get_or_insert(e_stored);
                stored.1 = e_stored;
                rec.feed(t, obs)?;
                longest = longest.max(t - t_last);
                t_last = t;
            }
            if longest > 0.0 {
                dt_est = longest;
            }
            steps += count as u64;
            if batch.failure.is_some() {
                failure = batch.failure;
                break 'run;
            }
            if batch.done || rec.finished() {
                break;
            }
            if rec.checkpoint_due(t_last) {
                checkpoint(&solver, rec, t_last, stored)?;
            }
            rec.report(t_last, steps);
        }
        if rec.snapshot_due(stop) {
            gpu_snapshot(&mut solver, rec, stop)?;
        }
        if stop >= end || rec.finished() {
            break;
        }
        if rec.checkpoint_due(t_last) {
            checkpoint(&solver, rec, t_last, stored)?;
        }
        rec.report(t_last, steps);
    }
    let (mut state, ctl) = solver.download_with_control();
    if failure.is_none() {
        state.t = end;
    }
    let mut warnings = Vec::new();
    let multi = ctl.multi_partner;
    if multi > 0 {
        warnings.push(format!(
            "{multi} contact evaluation(s) met two partner bodies at one particle; the GPU path pairs each particle with the first"
        ));
    }
    Ok(Outcome {
        model: solver.into_model(),
        state,
        stored: (stored.0.unwrap_or(0.0), stored.1),
        failure,
        max_fallback: ctl.fallback_max,
        adapter: Some(adapter),
        warnings,
    })
}

/// The snapshot of the device's current state, at time `t`.
fn gpu_snapshot(solver: &mut GpuSolver, rec: &mut Recorder, t: f64) -> Result<(), RunError> {
    let prepared = Instant::now();
    let (state, normal, boundary) = solver.snapshot();
    let fields = Fields {
        model: &solver.model,
        state: &state,
        normal: &normal,
        boundary: &boundary,
    };
    rec.snapshot(t, &fields, prepared)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The time left is the pace of this process over what is left: a
    /// fresh run 40 % through after 8 s has 12 s to go; a run resumed at
    /// 50 % that reached 75 % in 10 s has 10 s to go (not the 3.3 s that
    /// the fraction since t = 0 would give).
    #[test]
    fn eta_counts_from_where_the_process_started() {
        let close = |a: Option<f64>, b: f64| (a.expect("known") - b).abs() < 1e-12;
        assert!(close(eta_seconds(8.0, 0.0, 4e-6, 1e-5), 12.0));
        assert!(close(eta_seconds(10.0, 5e-6, 7.5e-6, 1e-5), 10.0));
        assert!(close(eta_seconds(3.0, 0.0, 1e-5, 1e-5), 0.0));
        assert_eq!(eta_seconds(1.0, 5e-6, 5e-6, 1e-5), None);
    }

    /// Plain lines come at the multiples of LINE_PERCENT: a fresh run's
    /// first at 5 %, one resumed at 83 % next at 85 %, and after a line at
    /// exactly 85 % the next at 90 %.
    #[test]
    fn plain_lines_at_the_next_multiple() {
        assert_eq!(next_line_percent(0.0), LINE_PERCENT);
        assert_eq!(next_line_percent(83.3), 85.0);
        assert_eq!(next_line_percent(85.0), 90.0);
    }
}
