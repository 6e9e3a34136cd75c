//! The ballistic limit: the least impact speed at which a projectile
//! perforates a target, found by bisection over whole runs of a scene, and
//! the residual velocity of each shot (docs/usage.md, "Ballistic limit").
//!
//! A shot is the scene with the projectile's speed set (its direction
//! kept) and, for a coarse search, every body's spacing set. At the end of
//! the run the projectile has *perforated* when its centre of mass is past
//! the target's far face (the furthest target particle along the impact
//! direction as placed, plus half its spacing, carried with the target's
//! centre of mass: a free target moves) and still moving away from the
//! target; its residual velocity is then its mean velocity along the
//! impact direction, and 0 otherwise. A projectile still moving into the
//! target faster than 5 % of its impact speed, inside it, at the end is
//! *undecided*: near the limit the projectile takes longest to decide, and
//! the search stops there with the bracket it has, asking for a longer end
//! time.

use std::path::{Path, PathBuf};

use glam::DVec2;
use serde::Serialize;

use crate::error::RunError;
use crate::model::Model;
use crate::run::{run_scene, RunOptions, RunOutput};
use crate::scene::{Backend, Scene};

/// A projectile still moving into the target faster than this share of
/// its impact speed, inside it, at the end of a shot: undecided.
const STILL_GOING: f64 = 0.05;

/// What to search and how.
#[derive(Debug, Clone)]
pub struct BallisticOptions {
    /// The projectile and target bodies, by name.
    pub projectile: String,
    pub target: String,
    /// A speed that does not perforate and one that does, m/s.
    pub low: f64,
    pub high: f64,
    /// The search stops when the bracket is this narrow, m/s.
    pub tolerance: f64,
    /// Every body's particle spacing for the search, m (default: the
    /// scene's).
    pub spacing: Option<f64>,
    /// The shots' end time, s (default: the scene's).
    pub end_time: Option<f64>,
    /// More impact speeds to shoot once the limit is bracketed, for the
    /// residual-velocity curve.
    pub speeds: Vec<f64>,
    pub backend: Option<Backend>,
    /// Each shot's outputs go to `<out>/v<speed>`; the search's own to
    /// `<out>`. `None`: nothing written.
    pub out_dir: Option<PathBuf>,
}

/// One run of the scene at one impact speed.
#[derive(Debug, Clone, Serialize)]
pub struct Shot {
    /// Impact speed, m/s.
    pub speed: f64,
    pub perforated: bool,
    /// Still moving into the target, inside it, at the end: neither
    /// perforated nor stopped.
    pub undecided: bool,
    /// The projectile's mean velocity along the impact direction at the
    /// end when it perforated, else 0, m/s.
    pub residual_velocity: f64,
    /// The projectile's centre of mass past the target's far face along the
    /// impact direction at the end, m (negative: short of it).
    pub depth_past_far_face: f64,
    /// The target's failed particles at the end.
    pub target_failed: usize,
    pub particles: usize,
    pub steps: u64,
    pub wall_seconds: f64,
}

/// The search's result (`ballistic.json`).
#[derive(Debug, Clone, Serialize)]
pub struct Ballistic {
    pub scene: String,
    pub projectile: String,
    pub target: String,
    /// The spacing the shots ran at, m (each body's, when the scene's).
    pub spacing: Vec<f64>,
    pub end_time: f64,
    pub backend: String,
    /// The highest speed that did not perforate and the lowest that did.
    pub limit_bracket: [f64; 2],
    /// The bracket's midpoint, m/s.
    pub ballistic_limit: f64,
    /// Why the bisection stopped before the tolerance, if it did (a shot
    /// left undecided by the end time).
    pub stopped: Option<String>,
    /// Every shot, in the order shot.
    pub shots: Vec<Shot>,
}

/// The scene of one shot: the projectile at `speed` along its scene
/// velocity, every spacing `spacing` when given, the end time `end`.
fn shot_scene(scene: &Scene, opts: &BallisticOptions, speed: f64) -> Scene {
    let mut s = scene.clone();
    for b in &mut s.bodies {
        if let Some(dx) = opts.spacing {
            b.spacing = dx;
        }
        if b.name == opts.projectile {
            let v = b.velocity.clone().unwrap_or_default();
            let dir = direction(&v).expect("checked: the projectile moves");
            b.velocity = Some(
                [dir.x, dir.y][..v.len()]
                    .iter()
                    .map(|c| c * speed)
                    .collect(),
            );
        }
    }
    if let Some(t) = opts.end_time {
        s.simulation.end_time = t;
    }
    s
}

/// The unit vector of a scene velocity (1 or 2 components).
fn direction(v: &[f64]) -> Option<DVec2> {
    let d = DVec2::new(
        v.first().copied().unwrap_or(0.0),
        v.get(1).copied().unwrap_or(0.0),
    );
    (d.length() > 0.0).then(|| d.normalize())
}

fn body_index(scene: &Scene, name: &str, role: &'static str) -> Result<usize, RunError> {
    scene
        .bodies
        .iter()
        .position(|b| b.name == name)
        .ok_or_else(|| {
            let names: Vec<&str> = scene.bodies.iter().map(|b| b.name.as_str()).collect();
            RunError::option(
                role,
                format!("{name}: no such body (the scene has {})", names.join(", ")),
            )
        })
}

/// Check the options against the scene: bad input, exit status 2.
fn check(scene: &Scene, opts: &BallisticOptions) -> Result<(usize, usize), RunError> {
    let bad = |option, m: String| Err(RunError::option(option, m));
    let p = body_index(scene, &opts.projectile, "--projectile")?;
    let t = body_index(scene, &opts.target, "--target")?;
    if p == t {
        return bad("--projectile", "and --target name the same body".into());
    }
    let v = scene.bodies[p].velocity.clone().unwrap_or_default();
    if direction(&v).is_none() {
        return bad(
            "--projectile",
            format!(
                "{}: the body has no velocity in the scene; its direction is the impact direction",
                opts.projectile
            ),
        );
    }
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !(positive(opts.low) && positive(opts.high) && opts.low < opts.high) {
        return bad(
            "--low",
            format!(
                "and --high must be speeds with 0 < low < high (got {} and {})",
                opts.low, opts.high
            ),
        );
    }
    if !positive(opts.tolerance) {
        return bad(
            "--tolerance",
            format!("must be > 0 (got {})", opts.tolerance),
        );
    }
    if let Some(dx) = opts.spacing.filter(|&dx| !positive(dx)) {
        return bad("--spacing", format!("must be > 0 (got {dx})"));
    }
    if let Some(&v) = opts.speeds.iter().find(|&&v| !positive(v)) {
        return bad("--speeds", format!("must be > 0 (got {v})"));
    }
    Ok((p, t))
}

/// Whether and how the projectile came through, from the run's end state.
fn judge(
    out: &RunOutput,
    x0: &[DVec2],
    (p, t): (usize, usize),
    dir: DVec2,
    speed: f64,
) -> (bool, bool, f64, f64) {
    let (model, st) = (&out.model, &out.state);
    let target = &model.bodies[t];
    let range = target.range.clone();
    let far0 = range
        .clone()
        .map(|i| x0[i].dot(dir))
        .fold(f64::MIN, f64::max)
        + 0.5 * target.spacing;
    let mt: f64 = range.clone().map(|i| model.mass[i]).sum();
    let cm_t0 = range.map(|i| x0[i] * model.mass[i]).sum::<DVec2>() / mt;
    let (_, mv_t, cm_t, _) = crate::probe::body_means(model, st, t);
    let far = far0 + (cm_t - cm_t0).dot(dir);
    let (m, mv, cm, _) = crate::probe::body_means(model, st, p);
    let along = (mv / m).dot(dir);
    let (depth, relative) = (cm.dot(dir) - far, along - (mv_t / mt).dot(dir));
    let perforated = depth > 0.0 && relative > 0.0;
    let undecided = !perforated && relative > STILL_GOING * speed;
    let residual = if perforated { along } else { 0.0 };
    (perforated, undecided, residual, depth)
}

/// One shot at `speed`.
pub fn shoot(scene: &Scene, opts: &BallisticOptions, speed: f64) -> Result<Shot, RunError> {
    let pt = check(scene, opts)?;
    shoot_checked(scene, opts, pt, speed)
}

/// [`shoot`] with the options checked: `pt` the projectile's and the
/// target's body indices.
fn shoot_checked(
    scene: &Scene,
    opts: &BallisticOptions,
    pt: (usize, usize),
    speed: f64,
) -> Result<Shot, RunError> {
    let s = shot_scene(scene, opts, speed);
    crate::scene::validate::validate(&s)?;
    let x0 = Model::new(&s).1.x;
    let dir = direction(s.bodies[pt.0].velocity.as_deref().unwrap_or_default())
        .expect("checked: the projectile moves");
    let run_opts = RunOptions {
        backend: opts.backend,
        out_dir: opts.out_dir.as_ref().map(|d| d.join(format!("v{speed}"))),
        write: opts.out_dir.is_some(),
        silent: true,
        ..Default::default()
    };
    let out = run_scene(&s, None, &run_opts)?;
    let (perforated, undecided, residual_velocity, depth_past_far_face) =
        judge(&out, &x0, pt, dir, speed);
    let sm = &out.summary;
    Ok(Shot {
        speed,
        perforated,
        undecided,
        residual_velocity,
        depth_past_far_face,
        target_failed: sm.bodies[pt.1].failure.as_ref().map_or(0, |f| f.failed),
        particles: sm.particles,
        steps: sm.steps,
        wall_seconds: sm.wall_seconds,
    })
}

/// Bracket the ballistic limit between `opts.low` (must stop) and
/// `opts.high` (must perforate), halve the bracket down to
/// `opts.tolerance` or to a shot the end time leaves undecided, then shoot
/// `opts.speeds`. `report` sees each shot as it lands.
pub fn search(
    scene: &Scene,
    label: &str,
    opts: &BallisticOptions,
    mut report: impl FnMut(&Shot),
) -> Result<Ballistic, RunError> {
    let pt = check(scene, opts)?;
    let mut shots = Vec::new();
    let mut fire = |v: f64, shots: &mut Vec<Shot>| -> Result<(bool, bool), RunError> {
        let s = shoot_checked(scene, opts, pt, v)?;
        report(&s);
        let p = (s.perforated, s.undecided);
        shots.push(s);
        Ok(p)
    };
    let longer = |v: f64| {
        format!(
            "is too short: at {v} m/s the projectile is still moving into the target at the end; give a longer one"
        )
    };
    // The bracket's ends must be decided, and on their own sides.
    for (v, end, through, wrong) in [
        (
            opts.low,
            "--low",
            false,
            "already perforates: give a lower speed",
        ),
        (
            opts.high,
            "--high",
            true,
            "does not perforate: give a higher speed",
        ),
    ] {
        match fire(v, &mut shots)? {
            (_, true) => return Err(RunError::option("--end-time", longer(v))),
            (p, _) if p != through => {
                return Err(RunError::option(end, format!("{v} m/s {wrong}")))
            }
            _ => {}
        }
    }
    let (mut lo, mut hi) = (opts.low, opts.high);
    let mut stopped = None;
    while hi - lo > opts.tolerance {
        let mid = 0.5 * (lo + hi);
        match fire(mid, &mut shots)? {
            (_, true) => {
                stopped = Some(longer(mid));
                break;
            }
            (true, _) => hi = mid,
            (false, _) => lo = mid,
        }
    }
    for &v in &opts.speeds {
        fire(v, &mut shots)?;
    }
    let s = shot_scene(scene, opts, opts.low);
    Ok(Ballistic {
        scene: label.to_string(),
        projectile: opts.projectile.clone(),
        target: opts.target.clone(),
        spacing: s.bodies.iter().map(|b| b.spacing).collect(),
        end_time: s.simulation.end_time,
        backend: opts.backend.unwrap_or(Backend::Auto).to_string(),
        limit_bracket: [lo, hi],
        ballistic_limit: 0.5 * (lo + hi),
        stopped,
        shots,
    })
}

impl Ballistic {
    /// `ballistic.json`, `residual.csv` (every shot, by speed) and, when a
    /// font is found, `residual.png` (the residual velocity against the
    /// impact speed) in `dir`.
    pub fn write(&self, dir: &Path) -> Result<(), RunError> {
        use crate::output::write_atomic;
        std::fs::create_dir_all(dir).map_err(|e| RunError::io(dir, e))?;
        let json = serde_json::to_string_pretty(self).expect("serialises") + "\n";
        write_atomic(&dir.join("ballistic.json"), json.as_bytes())?;
        let mut shots = self.shots.clone();
        shots.sort_by(|a, b| a.speed.total_cmp(&b.speed));
        let mut csv = String::from(
            "impact_speed,perforated,undecided,residual_velocity,depth_past_far_face,target_failed,wall_seconds\n",
        );
        for s in &shots {
            csv += &format!(
                "{},{},{},{},{},{},{}\n",
                s.speed,
                s.perforated as u8,
                s.undecided as u8,
                s.residual_velocity,
                s.depth_past_far_face,
                s.target_failed,
                s.wall_seconds
            );
        }
        write_atomic(&dir.join("residual.csv"), csv.as_bytes())?;
        if crate::plot::font_available() {
            use crate::plot::{line_plot, Figure, Series, Style};
            let mut fig = Figure::new(
                &format!(
                    "{} through {}: residual velocity (ballistic limit {:.0} m/s, Δx = {:.3e} m)",
                    self.projectile, self.target, self.ballistic_limit, self.spacing[0]
                ),
                "impact speed (m/s)",
                "residual velocity (m/s)",
            );
            fig.series.push(Series {
                label: "shots".into(),
                points: shots
                    .iter()
                    .filter(|s| !s.undecided)
                    .map(|s| (s.speed, s.residual_velocity))
                    .collect(),
                style: Style::Markers,
                color: Some(0),
                exact: false,
            });
            fig.series.push(Series {
                label: "no target (v_r = v)".into(),
                points: vec![(0.0, 0.0), {
                    let v = shots.last().map_or(1.0, |s| s.speed);
                    (v, v)
                }],
                style: Style::Dashed,
                color: Some(1),
                exact: false,
            });
            line_plot(&dir.join("residual.png"), &fig).map_err(|e| RunError::Plot {
                path: dir.join("residual.png").display().to_string(),
                message: e.to_string(),
            })?;
        }
        Ok(())
    }
}
