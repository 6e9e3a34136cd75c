//! Output files (docs/scenes.md, "Outputs"): `history.csv`, `summary.json` and
//! the particle snapshots ([`vtk`]).

pub mod history_plot;
pub mod render;
pub mod vtk;

use serde::Serialize;
use std::path::{Path, PathBuf};

use crate::error::RunError;

/// The recorded history: one row per history time, kept in memory and,
/// when a directory is given, in `history.csv`.
///
/// The file is only ever replaced whole (written to a temporary file and
/// renamed, [`write_atomic`]), never appended to, so a run killed at any
/// moment leaves a file of whole rows: at most [`History::EVERY`] seconds
/// of wall time behind the run, and complete once the run ends or fails
/// ([`History::flush`]). The CSV text is kept alongside the rows so that a
/// rewrite costs one write, not a re-formatting.
#[derive(Debug)]
pub struct History {
    pub names: Vec<String>,
    pub times: Vec<f64>,
    pub rows: Vec<Vec<f64>>,
    file: Option<HistoryFile>,
}

#[derive(Debug)]
struct HistoryFile {
    path: PathBuf,
    text: String,
    /// The text's length at the last write, and when that was.
    written: usize,
    at: std::time::Instant,
}

impl History {
    /// Wall seconds between rewrites of `history.csv` while rows come.
    pub const EVERY: f64 = 1.0;

    pub fn new(names: Vec<String>, dir: Option<&Path>) -> Result<Self, RunError> {
        Self::resume(names, Vec::new(), Vec::new(), dir)
    }

    /// A history that already holds `times` and `rows` (a resumed run):
    /// `history.csv` is written anew with them at once.
    pub fn resume(
        names: Vec<String>,
        times: Vec<f64>,
        rows: Vec<Vec<f64>>,
        dir: Option<&Path>,
    ) -> Result<Self, RunError> {
        let file = dir.map(|d| {
            let mut text = String::from("time");
            for n in &names {
                text.push(',');
                text.push_str(n);
            }
            text.push('\n');
            for (t, row) in times.iter().zip(&rows) {
                text.push_str(&line(*t, row));
            }
            HistoryFile {
                path: d.join("history.csv"),
                text,
                written: 0,
                at: std::time::Instant::now(),
            }
        });
        let mut h = Self {
            names,
            times,
            rows,
            file,
        };
        h.flush()?;
        Ok(h)
    }

    pub fn push(&mut self, t: f64, row: Vec<f64>) -> Result<(), RunError> {
        if let Some(f) = &mut self.file {
            f.text.push_str(&line(t, &row));
            if f.at.elapsed().as_secs_f64() >= Self::EVERY {
                self.flush()?;
            }
        }
        self.times.push(t);
        self.rows.push(row);
        Ok(())
    }

    /// Bring `history.csv` up to date with every row recorded.
    pub fn flush(&mut self) -> Result<(), RunError> {
        if let Some(f) = &mut self.file {
            if f.written != f.text.len() || f.written == 0 {
                write_atomic(&f.path, f.text.as_bytes())?;
                f.written = f.text.len();
            }
            f.at = std::time::Instant::now();
        }
        Ok(())
    }

    /// The column of probe `name`.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let k = self.names.iter().position(|n| n == name)?;
        Some(self.rows.iter().map(|r| r[k]).collect())
    }
}

/// One row of `history.csv`, its newline included: full precision, so
/// that a row read back is the value recorded.
fn line(t: f64, row: &[f64]) -> String {
    let mut line = format!("{t:e}");
    for v in row {
        line.push(',');
        line.push_str(&format!("{v:e}"));
    }
    line.push('\n');
    line
}

/// Time of the first and the last contact: where `force` first and last
/// leaves zero, interpolated linearly between rows.
pub fn contact_window(t: &[f64], force: &[f64]) -> (f64, f64) {
    let first = force
        .iter()
        .position(|&f| f > 0.0)
        .expect("contact happens");
    let last = force
        .iter()
        .rposition(|&f| f > 0.0)
        .expect("contact happens");
    let start = if first == 0 { 0.0 } else { t[first - 1] };
    // Between the last positive row and the next zero, the force falls
    // through zero: extrapolate its slope from the two rows before.
    let end = if last + 1 < t.len() && last >= 1 {
        let slope = (force[last] - force[last - 1]) / (t[last] - t[last - 1]);
        if slope < 0.0 {
            (t[last] - force[last] / slope).min(t[last + 1])
        } else {
            t[last]
        }
    } else {
        t[last]
    };
    (start, end)
}

/// The largest pull a body felt from its partners: the largest rate,
/// between consecutive rows, at which its momentum `mass × v` grew toward
/// them (`v` its mean velocity along the direction to its partner; in the
/// units of the contact force probe). Only contact changes a body's
/// momentum, so this is the contact's net traction on the body, read
/// before anything is clamped: a contact that never pulls gives round-off
/// at most. With it, the largest push, the largest rate at which the
/// momentum grew away from them: `(pull, push)`.
pub fn pull_and_push(t: &[f64], v: &[f64], mass: f64) -> (f64, f64) {
    t.windows(2)
        .zip(v.windows(2))
        .map(|(t, v)| mass * (v[1] - v[0]) / (t[1] - t[0]))
        .fold((f64::NEG_INFINITY, f64::NEG_INFINITY), |(pull, push), r| {
            (pull.max(r), push.max(-r))
        })
}

/// Per-body line of the summary.
#[derive(Debug, Clone, Serialize)]
pub struct BodySummary {
    pub name: String,
    pub particles: usize,
    pub mass: f64,
    pub velocity_final: Vec<f64>,
    /// The body's failed particles, for a body whose material can fail
    /// (a damage law or a spall pressure); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failure: Option<BodyFailure>,
}

/// How much of a body has failed by the end of a run, and where it began.
#[derive(Debug, Clone, Serialize)]
pub struct BodyFailure {
    /// Particles failed at the end.
    pub failed: usize,
    /// The first particle to fail (the lowest index among those failing in
    /// the same step); absent while none has.
    pub first: Option<FirstFailure>,
}

#[derive(Debug, Clone, Serialize)]
pub struct FirstFailure {
    /// The end of the step it failed in, s.
    pub time: f64,
    /// The particle's index in the scene's order (bodies in turn).
    pub particle: usize,
    /// Where it was placed at the start of the run, m.
    pub position_initial: Vec<f64>,
}

impl BodyFailure {
    /// Body `b`'s failures in state `st`, `x0` the positions the run
    /// started from; `None` for a body whose material cannot fail.
    pub fn of(
        model: &crate::model::Model,
        st: &crate::model::State,
        x0: &[glam::DVec2],
        b: usize,
    ) -> Option<Self> {
        let body = &model.bodies[b];
        if !(model.history && body.material.can_fail()) {
            return None;
        }
        let range = body.range.clone();
        let failed = range
            .clone()
            .filter(|&i| crate::physics::strength::failed(st.damage[i]))
            .count();
        let first = range
            .filter(|&i| st.failed_at[i] >= 0.0)
            .min_by(|&i, &j| st.failed_at[i].total_cmp(&st.failed_at[j]).then(i.cmp(&j)))
            .map(|i| FirstFailure {
                time: st.failed_at[i],
                particle: i,
                position_initial: vec_of(x0[i], model.dim),
            });
        Some(BodyFailure { failed, first })
    }
}

/// The first `dim` components of `v`.
pub fn vec_of(v: glam::DVec2, dim: usize) -> Vec<f64> {
    if dim == 1 {
        vec![v.x]
    } else {
        vec![v.x, v.y]
    }
}

/// The particles of the final state outside the solid range: how many,
/// how many in each body, and the one furthest outside.
#[derive(Debug, Clone, Default, Serialize)]
pub struct OutOfRangeSummary {
    pub count: usize,
    /// The internal energy they hold (J, per unit thickness in 2-D), part
    /// of `energy_final`.
    pub internal_energy: f64,
    pub bodies: Vec<BodyCount>,
    pub worst: Option<WorstParticle>,
}

#[derive(Debug, Clone, Serialize)]
pub struct BodyCount {
    pub name: String,
    pub count: usize,
}

#[derive(Debug, Clone, Serialize)]
pub struct WorstParticle {
    /// The particle's index in the scene's order (bodies in turn).
    pub particle: usize,
    pub body: String,
    pub quantity: String,
    /// J/kg for an energy, kg/m³ for a density.
    pub value: f64,
}

/// How many particles were debris: the most at any one evaluation of the
/// run, and at its final state, by body.
#[derive(Debug, Clone, Default, Serialize)]
pub struct DebrisSummary {
    pub max: usize,
    pub count: usize,
    pub bodies: Vec<BodyCount>,
}

impl DebrisSummary {
    /// `max` over the run, and the final state's debris (one neighbour
    /// search and one kinematic pass, on the CPU path).
    pub fn of(model: &crate::model::Model, st: &crate::model::State, max: usize) -> Self {
        let nb = crate::cpu::neighbours::find(model, st.frame());
        let k = crate::cpu::kinematics::kinematics(model, st, &nb);
        let mut per_body = vec![0usize; model.bodies.len()];
        for i in k.fallback.iter().map(|&i| i as usize) {
            if !model.rigid(i) {
                per_body[model.body[i] as usize] += 1;
            }
        }
        DebrisSummary {
            max,
            count: per_body.iter().sum(),
            bodies: model
                .bodies
                .iter()
                .zip(per_body)
                .map(|(b, count)| BodyCount {
                    name: b.name.clone(),
                    count,
                })
                .collect(),
        }
    }
}

impl OutOfRangeSummary {
    pub fn of(model: &crate::model::Model, st: &crate::model::State) -> Self {
        let c = crate::probe::count_out_of_range(model, st);
        OutOfRangeSummary {
            count: c.total(),
            internal_energy: c.internal_energy,
            bodies: model
                .bodies
                .iter()
                .zip(&c.per_body)
                .map(|(b, &count)| BodyCount {
                    name: b.name.clone(),
                    count,
                })
                .collect(),
            worst: c.worst.map(|(i, what, value)| WorstParticle {
                particle: i,
                body: model.bodies[model.body[i] as usize].name.clone(),
                quantity: what.name().to_string(),
                value,
            }),
        }
    }

    /// One line for people, `None` when every particle is in range.
    pub fn line(&self) -> Option<String> {
        let w = self.worst.as_ref()?;
        let bodies: Vec<String> = self
            .bodies
            .iter()
            .filter(|b| b.count > 0)
            .map(|b| format!("{} in {}", b.count, b.name))
            .collect();
        Some(format!(
            "{} particle(s) end outside the solid range ({}), holding {:.4e} of internal energy; the furthest, particle {} of {}: {} ({:.3e})",
            self.count,
            bodies.join(", "),
            self.internal_energy,
            w.particle,
            w.body,
            w.quantity,
            w.value
        ))
    }
}

/// `summary.json` (docs/scenes.md, "summary.json"): the documented keys, plus `status`, `error`,
/// `time_reached`, `energy_spring_loss` and the snapshot counts.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    pub scene: String,
    pub dimension: usize,
    pub backend: String,
    pub adapter: Option<String>,
    /// `midpoint` or `leapfrog` (docs/method.md §9).
    pub integrator: String,
    pub particles: usize,
    pub steps: u64,
    pub end_time: f64,
    pub time_reached: f64,
    pub wall_seconds: f64,
    pub particle_steps_per_second: f64,
    pub momentum_initial: Vec<f64>,
    pub momentum_final: Vec<f64>,
    pub energy_initial: f64,
    pub energy_final: f64,
    /// Work the penalty springs absorbed and did not store (J per unit area
    /// in 1-D, per unit thickness in 2-D): the energy the discrete contact
    /// lost, which `energy_final` does not count. 0 without contact.
    pub energy_spring_loss: f64,
    /// The energy ledger term by term (docs/scenes.md, "summary.json").
    pub energy: EnergyLedger,
    pub bodies: Vec<BodySummary>,
    /// The particles whose final state is outside the solid range
    /// (`probe::out_of_range`).
    pub out_of_range: OutOfRangeSummary,
    /// Debris (docs/method.md, "Debris"): particles whose neighbourhood
    /// cannot support a corrected gradient, which carry no deviatoric
    /// stress and no tension while they are so.
    pub debris: DebrisSummary,
    /// The clamped and driven regions: each one's impulse on its region
    /// and its work (docs/scenes.md, "Constraints"); absent without any.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub constraints: Vec<ConstraintSummary>,
    /// Snapshots written (0 without `output.snapshot_interval`), their
    /// bytes on disk and the wall seconds they took (inside
    /// `wall_seconds`): the boundary set or the device readback, and the
    /// writing.
    pub snapshots: usize,
    pub snapshot_bytes: u64,
    pub snapshot_seconds: f64,
    pub warnings: Vec<String>,
    /// "completed" or "failed".
    pub status: String,
    pub error: Option<String>,
}

/// One constraint's account over the run.
#[derive(Debug, Clone, Serialize)]
pub struct ConstraintSummary {
    pub name: String,
    /// Particles it holds.
    pub particles: usize,
    /// Its impulse on its region, N·s/m² (1-D) or N·s/m (2-D), one
    /// component per dimension.
    pub impulse: Vec<f64>,
    /// The work it did on the bodies, J/m² or J/m.
    pub work: f64,
}

/// Where the energy of a run went (J per unit area in 1-D, per unit
/// thickness in 2-D): what the bodies hold at the end, by kind, the heat
/// the contact's dashpot booked into it, the work the discrete penalty
/// spring lost, and what is left unaccounted: the time integration's error.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct EnergyLedger {
    /// Total energy at the start (kinetic + internal + stored spring).
    pub initial: f64,
    /// Kinetic energy at the end, rigid bodies included.
    pub kinetic: f64,
    /// Internal energy of the deformable bodies at the end: elastic
    /// energy, plastic work, and the heat of the viscosity, the artificial
    /// stress and the dashpot.
    pub internal: f64,
    /// Energy stored in the penalty springs at the end.
    pub spring: f64,
    /// The deformable bodies' potential energy in the body force at the
    /// end, zero as placed (`[simulation] gravity`; absent without it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub potential: Option<f64>,
    /// Heat the contact's dashpots and friction dissipated (part of
    /// `internal`).
    pub dashpot_heat: f64,
    /// The frictional part of `dashpot_heat` (absent without friction).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction_heat: Option<f64>,
    /// Work the viscosity, the artificial stress and the hourglass
    /// control booked into the internal energy (part of `internal`).
    pub artificial_dissipation: f64,
    /// Work the penalty springs absorbed and did not store
    /// (`energy_spring_loss`).
    pub spring_loss: f64,
    /// The work the clamped and driven regions did on the bodies (absent
    /// without constraints).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub constraint_work: Option<f64>,
    /// `kinetic + internal + spring (+ potential) + spring_loss − initial
    /// (− constraint_work)`.
    pub residual: f64,
}

impl EnergyLedger {
    /// `gravity`: whether the scene has a body force (the ledger then
    /// names the potential energy); `held`: the constraints' work, where
    /// the scene has some; `friction`: the frictional heat, where the
    /// scene has friction.
    pub fn new(
        initial: f64,
        end: &crate::probe::Energies,
        spring_loss: f64,
        gravity: bool,
        held: Option<f64>,
        friction: Option<f64>,
    ) -> Self {
        EnergyLedger {
            initial,
            kinetic: end.kinetic,
            internal: end.internal,
            spring: end.stored,
            potential: gravity.then_some(end.potential),
            dashpot_heat: end.contact_heat,
            friction_heat: friction,
            artificial_dissipation: end.dissipation,
            spring_loss,
            constraint_work: held,
            residual: end.total() + spring_loss - initial - held.unwrap_or(0.0),
        }
    }
}

impl Summary {
    /// The energy ledger's closure, relative to the start: what the bodies
    /// hold plus what the discrete penalty spring lost, against what they
    /// started with. What is left is the time integration's error.
    pub fn energy_balance(&self) -> f64 {
        (self.energy_final + self.energy_spring_loss) / self.energy_initial - 1.0
    }

    pub fn write(&self, dir: &Path) -> Result<(), RunError> {
        let path = dir.join("summary.json");
        let text = serde_json::to_string_pretty(self).expect("a summary always serialises");
        write_atomic(&path, (text + "\n").as_bytes())
    }
}

/// Writes `bytes` to `path` through a temporary file in the same directory
/// and a rename, so a reader (or a killed run) never sees a half-written file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), RunError> {
    let name = path
        .file_name()
        .map_or("out".into(), |n| n.to_string_lossy().into_owned());
    let tmp = path.with_file_name(format!(".{name}.tmp"));
    std::fs::write(&tmp, bytes).map_err(|e| RunError::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| RunError::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::pull_and_push;

    #[test]
    fn a_pull_is_momentum_gained_toward_the_partner() {
        let t = [0.0, 1.0, 2.0, 4.0];
        // Pushed back at 2 m/s², then pulled: +0.5 m/s over 2 s.
        let v = [10.0, 8.0, 6.0, 6.5];
        assert_eq!(pull_and_push(&t, &v, 3.0), (0.75, 6.0));
        assert_eq!(pull_and_push(&t[..3], &v[..3], 3.0), (-6.0, 6.0));
    }
}
