//! The benchmark case: the two-disk impact sized to a particle count.

use crate::model::{Model, State};
use crate::probe::{self, Resolved};
use crate::scene::{Integrator, Scene, Support};
use crate::validation::{disk_scene, DISKS_CONTACT_TIME};

use super::{BenchError, CONTACT_WINDOW, END_TIME, MAX_PARTICLES, MIN_PARTICLES};

/// R/Δx whose square-lattice disks (two of them) hold the total particle
/// count closest to `particles`, and that count.
///
/// A lattice point `((i + ½)Δx, (j + ½)Δx)` is inside the disk when
/// `(i + ½)² + (j + ½)² < (R/Δx)²`, i.e. when the integer `q = i² + i + j² + j`
/// is below `(R/Δx)² − ½`. Sorting the q of the points near the expected
/// radius gives every achievable count; `(R/Δx)² = q + 1` sits half-way
/// between two achievable thresholds, so round-off in the placement cannot
/// move a point across the circle.
pub fn lattice_radius(particles: usize) -> (f64, usize) {
    let per_disk = particles as f64 / 2.0;
    let r = (per_disk / std::f64::consts::PI).sqrt();
    let n = (1.2 * r).ceil() as i64 + 2;
    // One quadrant: i ↦ −1 − i leaves q unchanged, so each point of the
    // quadrant i, j ≥ 0 stands for four.
    let mut q: Vec<i64> = Vec::with_capacity((n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            q.push(i * i + i + j * j + j);
        }
    }
    q.sort_unstable();
    // Points up to each distinct q: (total count, that q).
    let mut best = (usize::MAX, 0i64);
    let mut k = 0;
    while k < q.len() {
        let v = q[k];
        while k < q.len() && q[k] == v {
            k += 1;
        }
        let total = 2 * 4 * k;
        if total.abs_diff(particles) < best.0.abs_diff(particles) {
            best = (total, v);
        }
        if total > particles {
            break;
        }
    }
    (((best.1 + 1) as f64).sqrt(), best.0)
}

/// `Err` (bad input) outside [`MIN_PARTICLES`]..=[`MAX_PARTICLES`].
pub fn check_particles(particles: usize) -> Result<(), BenchError> {
    if particles < MIN_PARTICLES {
        return Err(BenchError::Input(format!(
            "--particles must be at least {MIN_PARTICLES} (got {particles})"
        )));
    }
    if particles > MAX_PARTICLES {
        return Err(BenchError::Input(format!(
            "--particles must be at most {MAX_PARTICLES} (got {particles})"
        )));
    }
    Ok(())
}

/// The disk impact at one size, with everything the backends start from.
#[derive(Clone)]
pub struct DiskCase {
    pub requested: usize,
    pub r_over_dx: f64,
    pub scene: Scene,
    pub model: Model,
    pub state: State,
    pub probes: Vec<Resolved>,
}

impl DiskCase {
    /// The case closest to `particles` in all (see [`lattice_radius`]).
    pub fn new(particles: usize) -> Result<Self, BenchError> {
        check_particles(particles)?;
        let (r_over_dx, _) = lattice_radius(particles);
        let mut scene = disk_scene("square", r_over_dx);
        scene.simulation.end_time = END_TIME;
        let (model, state) = Model::new(&scene);
        let probes = probe::resolve(&scene, &model, &state);
        Ok(Self {
            requested: particles,
            r_over_dx,
            scene,
            model,
            state,
            probes,
        })
    }

    pub fn particles(&self) -> usize {
        self.model.len()
    }

    /// The same case stepped by integrator `i`.
    pub fn with_integrator(mut self, i: Integrator) -> Self {
        self.scene.simulation.integrator = i;
        self.model.integrator = i;
        self
    }

    /// The same case with the kernel supports `support` (the disks as
    /// placed, the model and probes made anew).
    pub fn with_support(mut self, support: Support) -> Self {
        self.scene.simulation.support = Some(support);
        let (model, state) = Model::new(&self.scene);
        self.probes = probe::resolve(&self.scene, &model, &state);
        (self.model, self.state) = (model, state);
        self
    }

    /// The same case with the dispersion correction at `theta` (0: off;
    /// docs/method.md, "The dispersion correction").
    pub fn with_dispersion(mut self, theta: f64) -> Self {
        self.scene.simulation.dispersion_correction = theta;
        self.model.dispersion = theta;
        self
    }

    /// The same case with the hourglass control at `alpha` (on top of the
    /// disks' artificial stress).
    pub fn with_hourglass(mut self, alpha: f64) -> Self {
        self.scene
            .artificial_viscosity
            .get_or_insert_with(Default::default)
            .hourglass = alpha;
        self.model.set_hourglass(alpha);
        self
    }

    /// The step a timed run stops at, from the step `onset` that ended
    /// the approach and the step size `dt` there.
    pub(super) fn window_end(dt: f64, onset: u64) -> u64 {
        onset + ((CONTACT_WINDOW * DISKS_CONTACT_TIME / dt).floor() as u64).max(1)
    }
}
