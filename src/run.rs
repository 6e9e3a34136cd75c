//! Running a scene: the stepping loop, history rows at exact times, the
//! progress display and the output files.

use glam::DVec2;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::cpu::CpuSolver;
use crate::error::RunError;
use crate::model::Model;
use crate::output::{BodySummary, History, Summary};
use crate::probe;
use crate::scene::{Backend, Scene};

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
    /// Plain occasional progress lines instead of a bar.
    pub quiet: bool,
    /// Print no progress at all (library use, tests).
    pub silent: bool,
    /// Write `history.csv` and `summary.json`.
    pub write: bool,
}

/// What a run returns.
#[derive(Debug)]
pub struct RunOutput {
    pub history: History,
    pub summary: Summary,
    pub out_dir: Option<PathBuf>,
}

/// The output directory SCENES.md prescribes.
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

/// Which backend runs, and the warning to print if the choice was a fallback.
pub fn choose_backend(
    scene: &Scene,
    opts: &RunOptions,
) -> Result<(Backend, Option<String>), RunError> {
    match opts.backend.unwrap_or(scene.simulation.backend) {
        Backend::Cpu => Ok((Backend::Cpu, None)),
        Backend::Auto => Ok((
            Backend::Cpu,
            Some(
                "backend auto: this build has no GPU path yet; running the CPU reference path"
                    .into(),
            ),
        )),
        Backend::Gpu => Err(RunError::Backend(
            "the GPU backend is not built yet; use --backend cpu or auto".into(),
        )),
    }
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

fn vec_of(v: DVec2, dim: usize) -> Vec<f64> {
    if dim == 1 {
        vec![v.x]
    } else {
        vec![v.x, v.y]
    }
}

struct Progress {
    bar: Option<ProgressBar>,
    plain: bool,
    next_tenth: u32,
}

impl Progress {
    fn new(opts: &RunOptions) -> Self {
        if opts.silent {
            return Self {
                bar: None,
                plain: false,
                next_tenth: 11,
            };
        }
        if !opts.quiet && std::io::stderr().is_terminal() {
            let bar = ProgressBar::new(1000);
            bar.set_style(
                ProgressStyle::with_template(
                    "{bar:40} t = {msg} [{elapsed_precise} < {eta_precise}]",
                )
                .expect("a valid template"),
            );
            return Self {
                bar: Some(bar),
                plain: false,
                next_tenth: 11,
            };
        }
        Self {
            bar: None,
            plain: true,
            next_tenth: 1,
        }
    }

    fn update(&mut self, t: f64, end: f64, steps: u64, rate: f64) {
        let frac = (t / end).clamp(0.0, 1.0);
        if let Some(bar) = &self.bar {
            bar.set_position((frac * 1000.0) as u64);
            bar.set_message(format!(
                "{t:.3e} / {end:.3e} s, {steps} steps, {rate:.3e} particle-steps/s"
            ));
        } else if self.plain && frac * 10.0 >= self.next_tenth as f64 {
            self.next_tenth = (frac * 10.0).floor() as u32 + 1;
            eprintln!(
                "t = {t:.4e} s ({:.0} %), {steps} steps, {rate:.3e} particle-steps/s",
                frac * 100.0
            );
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
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
    let (backend, warning) = choose_backend(&scene, opts)?;
    let mut warnings = Vec::new();
    if let Some(w) = warning {
        if !opts.silent {
            eprintln!("warning: {w}");
        }
        warnings.push(w);
    }
    let dir = if opts.write {
        let d = output_dir(&scene, scene_path, opts);
        std::fs::create_dir_all(&d).map_err(|e| RunError::io(&d, e))?;
        Some(d)
    } else {
        None
    };

    let (model, state) = Model::new(&scene);
    let dim = model.dim;
    let probes = probe::resolve(&scene, &model, &state);
    let names = scene.probes.iter().map(|p| p.name().to_string()).collect();
    let mut history = History::new(names, dir.as_deref())?;
    let mut solver = CpuSolver::new(model, state);

    let end = scene.simulation.end_time;
    let times = history_times(end, scene.history_interval());
    let mut next_row = 0;
    let n = solver.model.len();
    let p0 = probe::momentum(&solver.model, &solver.state);
    let e0 = {
        let (model, st, diag) = solver.observe();
        probe::energies(model, st, diag).total()
    };
    let mut progress = Progress::new(opts);
    let start = Instant::now();
    let mut max_fallback = 0;

    // Each state is observed once; rows between two states are linear
    // interpolations, so history times are exact without shortening steps.
    let mut prev: Option<(f64, Vec<f64>)> = None;
    let mut failure = None;
    loop {
        let t = solver.state.t;
        let (model, st, diag) = solver.observe();
        max_fallback = max_fallback.max(diag.correction_fallback);
        let obs = probe::evaluate(&probes, model, st, diag);
        while next_row < times.len() && times[next_row] <= t * (1.0 + 1e-12) {
            let tr = times[next_row];
            let row = match &prev {
                Some((tp, vp)) if tr < t => {
                    let a = (tr - tp) / (t - tp);
                    vp.iter().zip(&obs).map(|(p, c)| p + a * (c - p)).collect()
                }
                _ => obs.clone(),
            };
            history.push(tr, row)?;
            next_row += 1;
        }
        if next_row >= times.len() || t >= end {
            break;
        }
        prev = Some((t, obs));
        if let Err(e) = solver.step(end - t) {
            failure = Some(e);
            break;
        }
        let secs = start.elapsed().as_secs_f64().max(1e-9);
        progress.update(
            solver.state.t,
            end,
            solver.state.step,
            solver.state.step as f64 * n as f64 / secs,
        );
    }
    progress.finish();
    let wall = start.elapsed().as_secs_f64();

    if max_fallback > 0 {
        warnings.push(format!(
            "up to {max_fallback} particle(s) at a time had too few neighbours for the corrected gradient and used L = I"
        ));
    }
    let (model, st, diag) = solver.observe();
    let summary = Summary {
        scene: scene_path.map_or(String::new(), |p| p.display().to_string()),
        dimension: dim,
        backend: backend.to_string(),
        adapter: None,
        particles: n,
        steps: st.step,
        end_time: end,
        time_reached: st.t,
        wall_seconds: wall,
        particle_steps_per_second: st.step as f64 * n as f64 / wall.max(1e-9),
        momentum_initial: vec_of(p0, dim),
        momentum_final: vec_of(probe::momentum(model, st), dim),
        energy_initial: e0,
        energy_final: probe::energies(model, st, diag).total(),
        bodies: (0..model.bodies.len())
            .map(|b| {
                let (m, mv, _, _) = probe::body_means(model, st, b);
                BodySummary {
                    name: model.bodies[b].name.clone(),
                    particles: model.bodies[b].range.len(),
                    mass: m,
                    velocity_final: vec_of(mv / m, dim),
                }
            })
            .collect(),
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
    })
}
