//! Running a paper scene in memory and reading its scores off the history.

use crate::output::contact_window;
use crate::run::{run_scene, RunOptions, RunOutput};
use crate::scene::{Backend, Integrator, Scene};
use crate::RunError;

use super::{DISKS_POLAR, DISKS_SQUARE};

/// What `validate` changes in every scene it runs, beyond the backend and
/// the integrator: the dispersion correction's θ and the viscosity's α
/// (`None`: the scene's).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Tuning {
    pub dispersion_correction: Option<f64>,
    pub alpha: Option<f64>,
}

impl Tuning {
    /// `scene` with the tuning applied.
    pub fn apply(&self, mut scene: Scene) -> Scene {
        if let Some(theta) = self.dispersion_correction {
            scene.simulation.dispersion_correction = theta;
        }
        if let Some(alpha) = self.alpha {
            scene
                .artificial_viscosity
                .get_or_insert_with(Default::default)
                .alpha = alpha;
        }
        scene
    }

    /// The tuning's part of a table's title: empty where there is none.
    pub fn label(&self) -> String {
        let mut parts = Vec::new();
        if let Some(t) = self.dispersion_correction {
            parts.push(format!("dispersion correction θ {t}"));
        }
        if let Some(a) = self.alpha {
            parts.push(format!("viscosity α {a}"));
        }
        parts.join(", ")
    }
}

/// A run of one scene for validation.
/// What a contact that never pulls may show of a pull, over its largest
/// push: round-off of the bodies' momenta (measured 1e-13 in f64, 1e-5 in
/// f32 on the paper's bars and disks).
pub(super) const PULL_ROUND_OFF: f64 = 1e-4;

pub struct CaseRun {
    pub scene: Scene,
    pub out: RunOutput,
}

impl CaseRun {
    pub fn col(&self, name: &str) -> Vec<f64> {
        self.out.history.column(name).unwrap_or_default()
    }
    pub fn times(&self) -> &[f64] {
        &self.out.history.times
    }
    /// The largest pull and the largest push body `body` felt from its
    /// partner, from its momentum ([`crate::output::pull_and_push`];
    /// `velocity`, its mean velocity toward the partner).
    pub(super) fn pull_and_push(&self, body: usize, velocity: &str) -> (f64, f64) {
        let mass = self.out.summary.bodies[body].mass;
        crate::output::pull_and_push(self.times(), &self.col(velocity), mass)
    }
    pub(super) fn backend(&self) -> String {
        self.out.summary.backend.clone()
    }
}

fn parse_embedded(text: &str, name: &str) -> Scene {
    Scene::from_toml_str(text, name).expect("the embedded paper scenes are valid")
}

/// The bar scene at `n` particles per bar, recorded every `dt_rec`.
pub fn bar_scene(text: &str, n: usize, dt_rec: f64) -> Scene {
    let mut scene = parse_embedded(text, "paper bar scene");
    for b in &mut scene.bodies {
        if let crate::scene::Shape::Segment { from, to } = b.shape {
            b.spacing = (to - from).abs() / n as f64;
        }
    }
    scene.output.history_interval = Some(dt_rec);
    scene
}

/// The disk scene (`square` or `polar`) at `R/Δx = r_over_dx`.
pub fn disk_scene(lattice: &str, r_over_dx: f64) -> Scene {
    let text = if lattice == "square" {
        DISKS_SQUARE
    } else {
        DISKS_POLAR
    };
    let mut scene = parse_embedded(text, "paper disk scene");
    for b in &mut scene.bodies {
        if let crate::scene::Shape::Disk { radius, .. } = b.shape {
            b.spacing = radius / r_over_dx;
        }
    }
    scene.output.history_interval = Some(2.0e-8);
    scene
}

/// Run a scene in memory (nothing written).
pub fn run_case(
    scene: &Scene,
    backend: Option<Backend>,
    integrator: Option<Integrator>,
    end: Option<f64>,
) -> Result<CaseRun, RunError> {
    let opts = RunOptions {
        silent: true,
        backend,
        integrator,
        end_time: end,
        ..Default::default()
    };
    let out = run_scene(scene, None, &opts)?;
    Ok(CaseRun {
        scene: scene.clone(),
        out,
    })
}

/// Value of column `name` at the row nearest `t`.
fn at(run: &CaseRun, name: &str, t: f64) -> f64 {
    let ts = run.times();
    let k = ts
        .iter()
        .enumerate()
        .min_by(|a, b| (a.1 - t).abs().total_cmp(&(b.1 - t).abs()))
        .map_or(0, |x| x.0);
    run.col(name).get(k).copied().unwrap_or(f64::NAN)
}

pub(super) fn last(run: &CaseRun, name: &str) -> f64 {
    run.col(name).last().copied().unwrap_or(f64::NAN)
}

/// What a bar run measured of the observables the exact answer fixes.
#[derive(Debug, Clone, Copy)]
pub struct BarScores {
    /// Contact pressure at half the contact time, Pa.
    pub plateau: f64,
    /// End of the contact, s.
    pub separation: f64,
    /// Mean velocities of the left and right bar at the end, m/s.
    pub final_left: f64,
    pub final_right: f64,
}

impl BarScores {
    pub fn of(run: &CaseRun) -> Self {
        let (_, ts) = contact_window(run.times(), &run.col("contact_pressure"));
        Self {
            plateau: at(run, "contact_pressure", 0.5 * ts),
            separation: ts,
            final_left: last(run, "velocity_left"),
            final_right: last(run, "velocity_right"),
        }
    }
}

/// What a disk run measured against the dynamic reference.
#[derive(Debug, Clone, Copy)]
pub struct DiskScores {
    /// Peak contact force, N/m, and when it happened, s.
    pub peak: f64,
    pub t_peak: f64,
    /// Contact time, s.
    pub contact_time: f64,
    /// Relative velocity after over before (closing at 10 m/s).
    pub restitution: f64,
}

impl DiskScores {
    pub fn of(run: &CaseRun) -> Self {
        let t = run.times();
        let f = run.col("contact_force");
        let (t0, t1) = contact_window(t, &f);
        let (k, peak) = f
            .iter()
            .enumerate()
            .fold((0, 0.0f64), |a, (i, &v)| if v > a.1 { (i, v) } else { a });
        Self {
            peak,
            t_peak: t[k],
            contact_time: t1 - t0,
            // Separating velocity over the closing speed (10 m/s).
            restitution: (last(run, "velocity_right") - last(run, "velocity_left")) / 10.0,
        }
    }
}
