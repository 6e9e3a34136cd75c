//! Running a scene: the stepping loop, history rows and snapshots at exact
//! times, the progress display and the output files.
//!
//! One loop runs both backends (`stepper.rs`: from stop to stop, the
//! snapshot times then the end), each backend behind the same trait
//! (`cpu.rs`: one step at a time; `gpu.rs`: batches of steps on the
//! device); `record.rs` turns the states they observe into history rows,
//! snapshots, checkpoints and progress.

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

mod cpu;
mod gpu;
mod record;
mod setup;
mod stepper;

use cpu::CpuStepper;
use gpu::GpuStepper;
pub use record::history_times;
use record::{next_multiple, Checkpoints, Progress, Recorder, Snapshots};
use setup::{RunSetup, Start};
use stepper::drive;

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
    /// No progress: warnings only (the command line adds its closing line).
    pub quiet: bool,
    /// Print nothing at all, warnings included (library use, tests).
    pub silent: bool,
    /// Write `history.csv`, `summary.json` and, when the scene sets
    /// `output.snapshot_interval`, the snapshots. Without it a run keeps
    /// nothing on disk, and does not shorten steps for snapshots either.
    pub write: bool,
    /// Write a checkpoint ([`crate::checkpoint`]) at the first state at or
    /// after every multiple of this simulated time, s (needs `write`).
    pub checkpoint_every: Option<f64>,
    /// Overrides the scene's `output.snapshot_interval`, s; `Some(0.0)`
    /// writes no snapshots (and draws none: `output.snapshot_png` off).
    pub snapshot_every: Option<f64>,
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
            Err(e) => Err(RunError::Backend {
                backend: "gpu",
                message: format!("{e}; use --backend cpu (or auto) to run on the CPU"),
            }),
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
            return Err(RunError::option(
                "--end-time",
                format!("must be > 0 (got {t})"),
            ));
        }
        scene.simulation.end_time = t;
    }
    if let Some(i) = opts.integrator {
        scene.simulation.integrator = i;
    }
    if let Some(t) = opts.snapshot_every {
        if !(t.is_finite() && t >= 0.0) {
            return Err(RunError::option(
                "--snapshot-every",
                format!("must be ≥ 0, 0 for no snapshots (got {t})"),
            ));
        }
        scene.output.snapshot_interval = (t > 0.0).then_some(t);
        scene.output.snapshot_png &= t > 0.0;
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
        return Err(RunError::option(
            "--end-time",
            "cannot be combined with --resume: a resumed run continues to the end time it was started with",
        ));
    }
    if opts.integrator.is_some() {
        return Err(RunError::option(
            "--integrator",
            "cannot be combined with --resume: a resumed run continues with the integrator it was started with",
        ));
    }
    if opts.snapshot_every.is_some() {
        return Err(RunError::option(
            "--snapshot-every",
            "cannot be combined with --resume: snapshots end the steps that would cross them, so a resumed run keeps the interval it was started with",
        ));
    }
    if let Some(b) = opts
        .backend
        .filter(|&b| b != Backend::Auto && b != ck.backend)
    {
        return Err(RunError::option(
            "--backend",
            format!(
                "{b}: the checkpoint in {} was written by the {} backend, and a run resumes on the backend that wrote it",
                dir.display(),
                ck.backend
            ),
        ));
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
    check_checkpoint_option(opts, dir.as_deref())?;
    let choice = choose_backend(&scene, opts)?;
    let backend = choice.backend;
    let mut warnings = Vec::new();
    if let Some(w) = choice.warning {
        warn(opts, &mut warnings, w);
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
                warn(opts, &mut warnings, w);
            }
        }
    }

    // The model and the probes come from the scene's initial state, also
    // when resuming: probes are fixed by where particles start.
    let (model, state) = Model::new(&scene);
    if let Some(ck) = &resume {
        ck.check_sizes(&model, "the checkpoint")?;
    }
    let (start, resume) = Start::of(&model, &state, resume);
    let probes = probe::resolve(&scene, &model, &state);
    let run = RunSetup {
        scene: &scene,
        label: &label,
        dir: dir.as_deref(),
        backend,
        adapter: adapter.clone(),
    };
    let (mut rec, resume) = run.recorder(opts, &start, resume, &warnings, model.len())?;
    let out = match choice.gpu {
        Some(ctx) => drive(
            GpuStepper::new(ctx, model, state, &probes, rec.end, resume)?,
            &mut rec,
        ),
        None => drive(CpuStepper::new(model, state, &probes, resume), &mut rec),
    };
    let out = match out {
        Ok(out) => out,
        Err(RunError::Device(why)) => return Err(device_failure(&mut rec, why)?),
        Err(e) => return Err(e),
    };
    rec.progress.finish();
    rec.history.flush()?;
    let mut late = Vec::new();
    if let Some(d) = &dir {
        // A picture of the run; one that cannot be drawn (no font) is a
        // warning, never the run's failure.
        if let Err(e) = crate::output::history_plot::write(d, &scene, &rec.history) {
            warn(opts, &mut late, format!("history.png not drawn: {e}"));
        }
        let drew = rec.snaps.as_ref().is_some_and(|s| s.series.count() > 0);
        if scene.output.snapshot_png && drew {
            let drawing = crate::output::render::Drawing {
                names: Some(scene.bodies.iter().map(|b| b.name.clone()).collect()),
                boundary: false,
                window: None,
            };
            if let Err(e) = crate::output::render::render(d, "von_mises", None, false, &drawing) {
                warn(opts, &mut late, format!("snapshot pictures not drawn: {e}"));
            }
        }
    }
    let wall = start.wall_before + rec.start.elapsed().as_secs_f64();
    let snapshots = rec.snaps.as_ref().map_or((0, 0, 0.0), |s| {
        (s.series.count(), s.series.bytes, s.series.seconds)
    });
    let failure = out.failure.clone();
    let (summary, model, state) = run.summary(out, [warnings, late], &start, wall, snapshots);
    if let Some(d) = &dir {
        summary.write(d)?;
    }
    if let Some(f) = failure {
        return Err(RunError::Unstable(f));
    }
    Ok(RunOutput {
        history: rec.history,
        summary,
        out_dir: dir,
        model,
        state,
    })
}

/// Prints warning `w` (unless the run is silent) and keeps it for the
/// summary.
fn warn(opts: &RunOptions, warnings: &mut Vec<String>, w: String) {
    if !opts.silent {
        eprintln!("warning: {w}");
    }
    warnings.push(w);
}

/// `--checkpoint-every`, if given, is a positive interval and the run
/// writes its outputs.
fn check_checkpoint_option(opts: &RunOptions, dir: Option<&Path>) -> Result<(), RunError> {
    if let Some(every) = opts.checkpoint_every {
        if !(every.is_finite() && every > 0.0) {
            return Err(RunError::option(
                "--checkpoint-every",
                format!("must be > 0 (got {every})"),
            ));
        }
        if dir.is_none() {
            return Err(RunError::option(
                "--checkpoint-every",
                "needs an output directory (a run that writes its outputs)",
            ));
        }
    }
    Ok(())
}

/// The error of a run the device failed: what was written stays (the
/// history up to the last state the device delivered, and the last
/// checkpoint), and the message says how to go on.
fn device_failure(rec: &mut Recorder, why: String) -> Result<RunError, RunError> {
    rec.progress.finish();
    rec.history.flush()?;
    let kept = match &rec.checkpoints {
        Some(c) if c.dir.join(crate::checkpoint::FILE).exists() => format!(
            "the last checkpoint is kept: `sphcontact run --resume {}` continues from it",
            c.dir.display()
        ),
        Some(_) => "no checkpoint was due yet".to_string(),
        None => "the run wrote no checkpoints (--checkpoint-every)".to_string(),
    };
    Ok(RunError::Device(format!("{why}; {kept}")))
}
