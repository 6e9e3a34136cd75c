//! The speed-against-error sweep over resolution and backend: its
//! observables, `sweep.csv` and the log–log plots.

use serde::Serialize;
use std::fmt::Write as _;
use std::path::PathBuf;

use crate::plot::{Figure, Style};
use crate::scene::{Backend, Integrator, Scene};
use crate::RunError;

use super::bars::exact_bars;
use super::report::{draw, series};
use super::runs::{bar_scene, disk_scene, run_case, BarScores, CaseRun, DiskScores, Tuning};
use super::{BARS, DISKS_CONTACT_TIME, DISKS_PEAK_FORCE};

/// One point of the speed-against-error sweep.
#[derive(Debug, Clone, Serialize)]
pub struct SweepPoint {
    pub case: String,
    /// `segment` for the bars, `square`/`polar` for the disks.
    pub lattice: String,
    pub backend: String,
    /// Particles per bar, or R/Δx.
    pub resolution: f64,
    pub particles: usize,
    pub steps: u64,
    pub particle_steps: f64,
    pub wall_seconds: f64,
    pub observable: String,
    pub exact: f64,
    pub measured: f64,
    pub relative_error: f64,
}

/// What the sweep runs.
#[derive(Debug, Clone)]
pub struct SweepOptions {
    pub backends: Vec<Backend>,
    pub bar_particles: Vec<usize>,
    pub disk_r_over_dx: Vec<f64>,
    /// Time integration of every run (the leapfrog: CPU backend only).
    pub integrator: Integrator,
    /// The dispersion correction and the viscosity, where not the scenes'.
    pub tuning: Tuning,
    pub out: PathBuf,
    pub verbose: bool,
}

impl SweepOptions {
    /// The default ladders: 25 to 400 particles per bar, R/Δx 10 to 50.
    pub fn new(backends: Vec<Backend>, out: PathBuf) -> Self {
        Self {
            backends,
            bar_particles: vec![25, 50, 100, 200, 400],
            disk_r_over_dx: vec![10.0, 15.0, 20.0, 30.0, 40.0, 50.0],
            integrator: Integrator::default(),
            tuning: Tuning::default(),
            out,
            verbose: false,
        }
    }
}

/// Convergence order: minus the least-squares slope of `ln |err|` against
/// `ln res` (1 means the error halves when the resolution doubles).
pub fn convergence_order(res: &[f64], err: &[f64]) -> f64 {
    let pts: Vec<(f64, f64)> = res
        .iter()
        .zip(err)
        .filter(|(r, e)| **r > 0.0 && e.abs() > 0.0)
        .map(|(r, e)| (r.ln(), e.abs().ln()))
        .collect();
    let n = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
    let (mx, my) = (sx / n, sy / n);
    let (mut num, mut den) = (0.0, 0.0);
    for (x, y) in &pts {
        num += (x - mx) * (y - my);
        den += (x - mx) * (x - mx);
    }
    -num / den
}

/// One observable of a sweep point: its exact (or reference) value and what
/// the run measured.
#[derive(Debug, Clone, Copy)]
pub struct Observed {
    pub name: &'static str,
    pub exact: f64,
    pub measured: f64,
}

impl Observed {
    pub fn error(&self) -> f64 {
        self.measured / self.exact - 1.0
    }
}

/// The steel bars at `n` particles per bar: rebound velocity, contact
/// pressure plateau and separation time against the exact answer.
pub fn bar_observables(
    n: usize,
    backend: Option<Backend>,
) -> Result<(CaseRun, [Observed; 3]), RunError> {
    bar_observables_of(&bar_scene(BARS, n, 5e-9), backend)
}

/// As [`bar_observables`] for a variant of the steel-bars scene (other
/// viscosity, smoothing ratio, ...).
pub fn bar_observables_of(
    scene: &Scene,
    backend: Option<Backend>,
) -> Result<(CaseRun, [Observed; 3]), RunError> {
    let run = run_case(scene, backend, None, None)?;
    let r = exact_bars(&run.scene, "steel")?.result;
    let sc = BarScores::of(&run);
    let obs = [
        Observed {
            name: "rebound velocity",
            exact: r.final_velocity_1,
            measured: sc.final_left,
        },
        Observed {
            name: "contact pressure plateau",
            exact: -r.contact_stress,
            measured: sc.plateau,
        },
        Observed {
            name: "separation time",
            exact: r.separation_time,
            measured: sc.separation,
        },
    ];
    Ok((run, obs))
}

/// The two disks at `R/Δx = r` on `lattice`: peak force and contact time
/// against the dynamic reference, and the restitution (against 1).
pub fn disk_observables(
    lattice: &str,
    r: f64,
    backend: Option<Backend>,
) -> Result<(CaseRun, [Observed; 3]), RunError> {
    disk_observables_of(&disk_scene(lattice, r), backend)
}

/// As [`disk_observables`] for a variant of a paper disk scene.
pub fn disk_observables_of(
    scene: &Scene,
    backend: Option<Backend>,
) -> Result<(CaseRun, [Observed; 3]), RunError> {
    let run = run_case(scene, backend, None, None)?;
    let sc = DiskScores::of(&run);
    let obs = [
        Observed {
            name: "peak contact force",
            exact: DISKS_PEAK_FORCE,
            measured: sc.peak,
        },
        Observed {
            name: "contact time",
            exact: DISKS_CONTACT_TIME,
            measured: sc.contact_time,
        },
        Observed {
            name: "restitution",
            exact: 1.0,
            measured: sc.restitution,
        },
    ];
    Ok((run, obs))
}

/// The speed-against-error study: every resolution on every backend,
/// written as `sweep.csv` and log–log plots.
pub fn sweep(opts: &SweepOptions) -> Result<(Vec<SweepPoint>, Vec<String>), RunError> {
    std::fs::create_dir_all(&opts.out).map_err(|e| RunError::io(&opts.out, e))?;
    let mut points = Vec::new();
    let mut push = |case: &str, lattice: &str, res: f64, run: &CaseRun, obs: &[Observed]| {
        let s = &run.out.summary;
        for o in obs {
            points.push(SweepPoint {
                case: case.into(),
                lattice: lattice.into(),
                backend: s.backend.clone(),
                resolution: res,
                particles: s.particles,
                steps: s.steps,
                particle_steps: s.steps as f64 * s.particles as f64,
                wall_seconds: s.wall_seconds,
                observable: o.name.into(),
                exact: o.exact,
                measured: o.measured,
                relative_error: o.error(),
            });
        }
    };
    for &b in &opts.backends {
        for &n in &opts.bar_particles {
            if opts.verbose {
                eprintln!("sweep: bars, {n} per bar, {b}");
            }
            let mut scene = opts.tuning.apply(bar_scene(BARS, n, 5e-9));
            scene.simulation.integrator = opts.integrator;
            let (run, obs) = bar_observables_of(&scene, Some(b))?;
            push("bars", "segment", n as f64, &run, &obs);
        }
        for lattice in ["square", "polar"] {
            for &r in &opts.disk_r_over_dx {
                if opts.verbose {
                    eprintln!("sweep: disks, {lattice}, R/dx = {r}, {b}");
                }
                let mut scene = opts.tuning.apply(disk_scene(lattice, r));
                scene.simulation.integrator = opts.integrator;
                let (run, obs) = disk_observables_of(&scene, Some(b))?;
                push("disks", lattice, r, &run, &obs);
            }
        }
    }
    let mut warnings = Vec::new();
    write_sweep(opts, &points, &mut warnings)?;
    Ok((points, warnings))
}

fn write_sweep(
    opts: &SweepOptions,
    points: &[SweepPoint],
    warnings: &mut Vec<String>,
) -> Result<(), RunError> {
    let mut s = String::from(
        "case,lattice,backend,resolution,particles,steps,particle_steps,wall_seconds,observable,exact,measured,relative_error\n",
    );
    for p in points {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{:e},{:e},{},{:e},{:e},{:e}",
            p.case,
            p.lattice,
            p.backend,
            p.resolution,
            p.particles,
            p.steps,
            p.particle_steps,
            p.wall_seconds,
            p.observable,
            p.exact,
            p.measured,
            p.relative_error
        );
    }
    crate::output::write_atomic(&opts.out.join("sweep.csv"), s.as_bytes())?;
    let backends: std::collections::BTreeSet<&str> =
        points.iter().map(|p| p.backend.as_str()).collect();
    let plots = [
        (
            "bars",
            "rebound velocity",
            "sweep_bars_rebound",
            "1-D steel bars: |error| of the rebound velocity",
        ),
        (
            "bars",
            "contact pressure plateau",
            "sweep_bars_plateau",
            "1-D steel bars: |error| of the contact pressure plateau",
        ),
        (
            "disks",
            "peak contact force",
            "sweep_disks_peak_force",
            "two disks: |error| of the peak force against 1.198 MN/m",
        ),
        (
            "disks",
            "contact time",
            "sweep_disks_contact_time",
            "two disks: |error| of the contact time against 8.39 µs",
        ),
    ];
    for (case, obs, file, title) in plots {
        for (xname, xlabel, xof) in [
            (
                "wall",
                "wall time (s)",
                (|p: &SweepPoint| p.wall_seconds) as fn(&SweepPoint) -> f64,
            ),
            ("work", "particle-steps", |p: &SweepPoint| p.particle_steps),
        ] {
            let mut f = Figure::new(
                &format!("Speed against error, {title}"),
                xlabel,
                "|relative error|",
            );
            f.log_x = true;
            f.log_y = true;
            let mut color = 0;
            for b in &backends {
                let lattices: &[&str] = if case == "bars" {
                    &["segment"]
                } else {
                    &["square", "polar"]
                };
                for &l in lattices {
                    let line: Vec<(f64, f64)> = points
                        .iter()
                        .filter(|p| {
                            p.case == case
                                && p.observable == obs
                                && p.backend == *b
                                && p.lattice == l
                        })
                        .map(|p| (xof(p), p.relative_error.abs()))
                        .collect();
                    if line.is_empty() {
                        continue;
                    }
                    let label = if case == "bars" {
                        b.to_string()
                    } else {
                        format!("{b}, {l} lattice")
                    };
                    f.series.push(series(&label, line, Style::Solid, color));
                    color += 1;
                }
            }
            draw(&opts.out.join(format!("{file}_{xname}.png")), &f, warnings);
        }
    }
    Ok(())
}
