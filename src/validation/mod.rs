//! `sphcontact validate`: the paper's cases run and scored against their
//! exact answers (docs/method.md §10), with one PNG figure per paper figure, the
//! CSV behind every curve, `validation.json`, and a speed-against-error
//! sweep over resolution and backend.
//!
//! Every case starts from a scene of `scenes/paper/` (embedded in the
//! binary, so `validate` runs from any directory) with only the resolution
//! and the recording interval changed.

pub mod exact;

use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::model::Model;
use crate::output::contact_window;
use crate::physics::material::MaterialModel;
use crate::plot::{self, Field, Figure, Series, Style};
use crate::probe::particle_value;
use crate::run::{run_scene, RunOptions, RunOutput};
use crate::scene::{Backend, Integrator, ParticleQuantity, Scene};
use crate::RunError;
use exact::{
    bar_impact_history, hertz_c_inertia, hertz_disks, BarId, BarImpactHistory, HERTZ_C_JOHNSON,
};

/// The paper's scenes, embedded.
pub const BARS: &str = include_str!("../../scenes/paper/bars_steel.toml");
pub const BARS_KERNEL: &str = include_str!("../../scenes/paper/bars_steel_kernel.toml");
pub const STEEL_AL: &str = include_str!("../../scenes/paper/bars_steel_aluminium.toml");
pub const STEEL_AL_KERNEL: &str =
    include_str!("../../scenes/paper/bars_steel_aluminium_kernel.toml");
pub const DISKS_SQUARE: &str = include_str!("../../scenes/paper/disks_square.toml");
pub const DISKS_POLAR: &str = include_str!("../../scenes/paper/disks_polar.toml");

/// Converged dynamic reference for the two disks (docs/method.md §8.4: a
/// converged dynamic finite-element solution): peak force per unit
/// thickness, N/m, and contact time, s. It lies inside the quasi-static
/// Hertz bracket of docs/method.md §10 (1.161–1.224 MN/m, 8.30–8.71 µs).
pub const DISKS_PEAK_FORCE: f64 = 1.198e6;
pub const DISKS_CONTACT_TIME: f64 = 8.39e-6;

/// The cases `validate` knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Case {
    /// Case 1: two steel bars (Figs. 4, 5, 6).
    Bars,
    /// Case 2: steel against aluminium (Fig. 7).
    SteelAluminium,
    /// Case 3: two steel disks, both lattices (Figs. 8, 9).
    Disks,
}

impl Case {
    pub const ALL: [Case; 3] = [Case::Bars, Case::SteelAluminium, Case::Disks];

    pub fn name(self) -> &'static str {
        match self {
            Case::Bars => "bars",
            Case::SteelAluminium => "steel_aluminium",
            Case::Disks => "disks",
        }
    }

    pub fn parse(s: &str) -> Option<Case> {
        Case::ALL.into_iter().find(|c| c.name() == s)
    }
}

/// Resolutions of a validation run.
#[derive(Debug, Clone, Copy)]
pub struct Resolution {
    /// Particles per bar (cases 1 and 2).
    pub bar_particles: usize,
    /// Disk radius over particle spacing (case 3).
    pub disk_r_over_dx: f64,
}

impl Default for Resolution {
    /// The defaults: 100 particles per bar (the paper's figures), R/Δx = 50
    /// (where the accuracy goals are set). Both run on 2 CPU cores in about
    /// three minutes.
    fn default() -> Self {
        Self {
            bar_particles: 100,
            disk_r_over_dx: 50.0,
        }
    }
}

/// What `validate` does.
#[derive(Debug, Clone)]
pub struct Options {
    pub cases: Vec<Case>,
    /// `None`: the scenes' `auto`.
    pub backend: Option<Backend>,
    /// `None`: the scenes' (the midpoint rule).
    pub integrator: Option<Integrator>,
    pub out: PathBuf,
    pub resolution: Resolution,
    /// Print progress lines.
    pub verbose: bool,
}

/// One scored observable (a row of `validation.json` and of the table).
#[derive(Debug, Clone, Serialize)]
pub struct Record {
    pub case: String,
    pub observable: String,
    pub exact: f64,
    pub measured: f64,
    /// `measured/exact − 1`; `null` where the exact answer is 0 (then
    /// `measured` is itself the error).
    pub relative_error: Option<f64>,
    pub backend: String,
    pub particles: usize,
    pub wall_seconds: f64,
    /// The acceptance this project sets for the observable.
    pub target: String,
    /// Whether `measured` meets `target`.
    pub pass: bool,
}

/// A run of one scene for validation.
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
    fn backend(&self) -> String {
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

fn last(run: &CaseRun, name: &str) -> f64 {
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
    /// Least contact force over the run (negative would be tension).
    pub least_force: f64,
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
            least_force: f.iter().copied().fold(f64::INFINITY, f64::min),
        }
    }
}

/// Writes a CSV of named columns (equal lengths, or padded with blanks).
pub fn write_csv(path: &Path, header: &[&str], cols: &[Vec<f64>]) -> Result<(), RunError> {
    let rows = cols.iter().map(Vec::len).max().unwrap_or(0);
    let mut s = header.join(",");
    s.push('\n');
    for r in 0..rows {
        let line: Vec<String> = cols
            .iter()
            .map(|c| c.get(r).map_or(String::new(), |v| format!("{v:e}")))
            .collect();
        s.push_str(&line.join(","));
        s.push('\n');
    }
    crate::output::write_atomic(path, s.as_bytes())
}

fn pts(x: &[f64], y: &[f64], sx: f64, sy: f64) -> Vec<(f64, f64)> {
    x.iter().zip(y).map(|(a, b)| (a * sx, b * sy)).collect()
}

fn series(label: &str, points: Vec<(f64, f64)>, style: Style, color: usize) -> Series {
    Series {
        label: label.into(),
        points,
        style,
        color: Some(color),
        exact: false,
    }
}

fn exact_series(label: &str, points: Vec<(f64, f64)>) -> Series {
    Series {
        label: label.into(),
        points,
        style: Style::Dashed,
        color: None,
        exact: true,
    }
}

/// Draws a line figure; a drawing error (no font) becomes a warning, since
/// the CSV behind it is written regardless.
fn draw(path: &Path, fig: &Figure, warnings: &mut Vec<String>) {
    if let Err(e) = plot::line_plot(path, fig) {
        warnings.push(format!("{}: {e}", path.display()));
    }
}

/// The results of `validate`, and where its files go.
#[derive(Debug)]
pub struct Report {
    pub records: Vec<Record>,
    pub warnings: Vec<String>,
    out: PathBuf,
}

impl Report {
    fn new(out: &Path) -> Self {
        Self {
            records: Vec::new(),
            warnings: Vec::new(),
            out: out.to_path_buf(),
        }
    }

    /// `<out>/<name>.csv`.
    fn csv(&self, name: &str, header: &[&str], cols: &[Vec<f64>]) -> Result<(), RunError> {
        write_csv(&self.out.join(format!("{name}.csv")), header, cols)
    }

    /// `<out>/<name>.png`.
    fn figure(&mut self, name: &str, fig: &Figure) {
        draw(
            &self.out.join(format!("{name}.png")),
            fig,
            &mut self.warnings,
        );
    }

    #[allow(clippy::too_many_arguments)]
    fn add(
        &mut self,
        case: &str,
        observable: &str,
        exact: f64,
        measured: f64,
        run: &CaseRun,
        target: &str,
        pass: bool,
    ) {
        self.records.push(Record {
            case: case.into(),
            observable: observable.into(),
            exact,
            measured,
            relative_error: (exact != 0.0).then(|| measured / exact - 1.0),
            backend: run.backend(),
            particles: run.out.summary.particles,
            wall_seconds: run.out.summary.wall_seconds,
            target: target.into(),
            pass,
        });
    }

    /// A record whose target is a relative error below `tol`.
    fn within(
        &mut self,
        case: &str,
        observable: &str,
        exact: f64,
        measured: f64,
        run: &CaseRun,
        tol: f64,
    ) {
        let pass = (measured / exact - 1.0).abs() < tol;
        let target = format!("within {} %", 100.0 * tol);
        self.add(case, observable, exact, measured, run, &target, pass);
    }

    /// The contact phase of a bar case: plateau within 1 %, separation
    /// within `sep_tol`. Returns the scores for the rest of the case.
    fn contact_phase(
        &mut self,
        case: &str,
        plateau: &str,
        run: &CaseRun,
        r: &exact::BarImpact,
        sep_tol: f64,
    ) -> BarScores {
        let sc = BarScores::of(run);
        self.within(case, plateau, -r.contact_stress, sc.plateau, run, 0.01);
        let sep = "separation time (s)";
        self.within(case, sep, r.separation_time, sc.separation, run, sep_tol);
        sc
    }

    /// Momentum change of a run against round-off of its `Σ m |v0|`
    /// (`scale`): 1e-12 in f64 on the CPU, 1e-6 in f32 on the GPU.
    fn momentum(&mut self, case: &str, unit: &str, run: &CaseRun, scale: f64) {
        let s = &run.out.summary;
        let round_off = if s.backend == "gpu" { 1e-6 } else { 1e-12 };
        let dp = s
            .momentum_final
            .iter()
            .zip(&s.momentum_initial)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let obs = format!("momentum change ({unit})");
        let target = format!("round-off ({round_off:e} of Σ m|v0|)");
        self.add(case, &obs, 0.0, dp, run, &target, dp < round_off * scale);
    }

    /// The table `validate` prints (Markdown).
    pub fn table(&self) -> String {
        let mut s = String::from(
            "| case | observable | exact | measured | error | target | backend | particles | wall (s) |\n|---|---|---|---|---|---|---|---|---|\n",
        );
        for r in &self.records {
            let err = r
                .relative_error
                .map_or("—".to_string(), |e| format!("{:+.2} %", 100.0 * e));
            let mark = if r.pass { "" } else { " ✗" };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {}{} | {} | {} | {} | {:.1} |",
                r.case,
                r.observable,
                fmt_num(r.exact),
                fmt_num(r.measured),
                err,
                mark,
                r.target,
                r.backend,
                r.particles,
                r.wall_seconds
            );
        }
        s
    }
}

fn fmt_num(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.abs() >= 1e4 || v.abs() < 1e-2 {
        format!("{v:.4e}")
    } else {
        format!("{v:.4}")
    }
}

/// Runs the chosen cases, writes every figure, CSV and `validation.json`
/// into `opts.out`, and returns the records.
pub fn validate(opts: &Options) -> Result<Report, RunError> {
    std::fs::create_dir_all(&opts.out).map_err(|e| RunError::io(&opts.out, e))?;
    let mut rep = Report::new(&opts.out);
    for &case in &opts.cases {
        if opts.verbose {
            eprintln!("validate: {} ...", case.name());
        }
        match case {
            Case::Bars => bars(opts, &mut rep)?,
            Case::SteelAluminium => steel_aluminium(opts, &mut rep)?,
            Case::Disks => disks(opts, &mut rep)?,
        }
    }
    let text = serde_json::to_string_pretty(&rep.records).expect("records serialise");
    crate::output::write_atomic(&opts.out.join("validation.json"), (text + "\n").as_bytes())?;
    Ok(rep)
}

/// Largest tensile (positive) value of column `col` over the run.
fn max_tension(run: &CaseRun, col: &str) -> f64 {
    run.col(col).into_iter().fold(0.0, f64::max)
}

/// Initial distance from the contact face of the particle a probe at `at`
/// follows (the nearest of the left bar, as the probe picks it).
fn probe_distance(scene: &Scene, at: f64) -> f64 {
    let (model, st) = Model::new(scene);
    model.bodies[0]
        .range
        .clone()
        .map(|i| st.x[i].x)
        .min_by(|a, c| (a - at).abs().total_cmp(&(c - at).abs()))
        .map_or(at.abs(), f64::abs)
}

/// The exact answer of a bar case (docs/method.md §10) over the scene's run.
fn exact_bars(scene: &Scene, right: &str) -> Result<BarImpactHistory, RunError> {
    let steel = MaterialModel::new(&scene.materials["steel"]);
    let other = MaterialModel::new(&scene.materials[right]);
    let end = scene.simulation.end_time;
    bar_impact_history(&steel, 0.005, 10.0, &other, 0.005, -10.0, end)
        .ok_or_else(|| RunError::Backend("exact bar answer unavailable".into()))
}

/// Case 1, Figs. 4–6: velocity at point b, stress at the contact point a,
/// and the bars' mean velocities, kernel and contact modes against exact.
fn bars(opts: &Options, rep: &mut Report) -> Result<(), RunError> {
    let n = opts.resolution.bar_particles;
    let pen = run_case(
        &bar_scene(BARS, n, 5e-9),
        opts.backend,
        opts.integrator,
        None,
    )?;
    let ker = run_case(
        &bar_scene(BARS_KERNEL, n, 5e-9),
        opts.backend,
        opts.integrator,
        None,
    )?;
    let ex = exact_bars(&pen.scene, "steel")?;
    let t = pen.times().to_vec();
    let tk = ker.times().to_vec();
    let us = 1e6;
    let d_b = probe_distance(&pen.scene, -0.0025);

    // Fig. 4: velocity at b.
    let exact_vb: Vec<f64> = t
        .iter()
        .map(|&s| ex.point_velocity(BarId::One, d_b, s))
        .collect();
    let (vb_p, vb_k) = (pen.col("velocity_b"), ker.col("velocity_b"));
    let mut f = Figure::new(
        &format!(
            "Fig. 4: velocity at b ({:.2} mm from the contact), steel bars, N = {n}",
            d_b * 1e3
        ),
        "time (µs)",
        "velocity (m/s)",
    );
    f.series.push(series(
        "kernel mode",
        pts(&tk, &vb_k, us, 1.0),
        Style::Solid,
        1,
    ));
    f.series.push(series(
        "contact mode",
        pts(&t, &vb_p, us, 1.0),
        Style::Solid,
        0,
    ));
    f.series
        .push(exact_series("exact", pts(&t, &exact_vb, us, 1.0)));
    rep.figure("fig4_velocity_b", &f);
    rep.csv(
        "fig4_velocity_b",
        &["time_s", "exact_m_s", "contact_m_s", "kernel_m_s"],
        &[t.clone(), exact_vb, vb_p, vb_k],
    )?;

    // Fig. 5: stress at the contact point a. In contact mode that is the
    // contact pressure (docs/method.md §11); in kernel mode the SPH stress of the
    // face particle (tension positive), shown as −σ_xx (compression up).
    let p_pen = pen.col("contact_pressure");
    let s_ker: Vec<f64> = ker.col("stress_a").iter().map(|s| -s).collect();
    let exact_p: Vec<f64> = t.iter().map(|&s| -ex.interface_stress(s)).collect();
    let mut f = Figure::new(
        &format!("Fig. 5: stress at the contact point a, steel bars, N = {n}"),
        "time (µs)",
        "contact stress (MPa)",
    );
    f.series.push(series(
        "kernel mode (−σxx of the face particle)",
        pts(&tk, &s_ker, us, 1e-6),
        Style::Solid,
        1,
    ));
    f.series.push(series(
        "contact mode (contact pressure p)",
        pts(&t, &p_pen, us, 1e-6),
        Style::Solid,
        0,
    ));
    f.series
        .push(exact_series("exact", pts(&t, &exact_p, us, 1e-6)));
    rep.figure("fig5_stress_a", &f);
    // The traction the bodies exert on each other is the contact pressure
    // (docs/method.md §11): never tensile.
    let tension = p_pen.iter().fold(0.0f64, |a, &p| a.max(-p));
    rep.csv(
        "fig5_stress_a",
        &[
            "time_s",
            "exact_pressure_pa",
            "contact_pressure_pa",
            "kernel_minus_stress_xx_pa",
        ],
        &[t.clone(), exact_p, p_pen, s_ker],
    )?;

    // Fig. 6: mean velocities.
    let ex_l: Vec<f64> = t.iter().map(|&s| ex.mean_velocity(BarId::One, s)).collect();
    let ex_r: Vec<f64> = t.iter().map(|&s| ex.mean_velocity(BarId::Two, s)).collect();
    let mut f = Figure::new(
        &format!("Fig. 6: mean velocities of the bars, steel bars, N = {n}"),
        "time (µs)",
        "mean velocity (m/s)",
    );
    let cols = [
        ("kernel mode, left", &ker, "velocity_left", 1),
        ("kernel mode, right", &ker, "velocity_right", 3),
        ("contact mode, left", &pen, "velocity_left", 0),
        ("contact mode, right", &pen, "velocity_right", 2),
    ]
    .map(|(label, run, col, color)| {
        let v = run.col(col);
        f.series.push(series(
            label,
            pts(run.times(), &v, us, 1.0),
            Style::Solid,
            color,
        ));
        v
    });
    f.series
        .push(exact_series("exact", pts(&t, &ex_l, us, 1.0)));
    f.series.push(exact_series("", pts(&t, &ex_r, us, 1.0)));
    rep.figure("fig6_mean_velocity", &f);
    let [kl, kr, cl, cr] = cols;
    rep.csv(
        "fig6_mean_velocity",
        &[
            "time_s",
            "exact_left_m_s",
            "exact_right_m_s",
            "contact_left_m_s",
            "contact_right_m_s",
            "kernel_left_m_s",
            "kernel_right_m_s",
        ],
        &[t, ex_l, ex_r, cl, cr, kl, kr],
    )?;

    // Scores.
    let case = "steel bars, contact";
    let r = &ex.result;
    let sc = rep.contact_phase(case, "contact pressure plateau (Pa)", &pen, r, 0.01);
    rep.add(
        case,
        "rebound: left bar mean velocity at 4 µs (m/s)",
        r.final_velocity_1,
        sc.final_left,
        &pen,
        "≥ 0.97 of exact",
        sc.final_left / r.final_velocity_1 >= 0.97,
    );
    rep.add(
        case,
        "largest tensile traction between the bars (Pa)",
        0.0,
        tension,
        &pen,
        "0 (no tension)",
        tension <= 0.0,
    );
    rep.momentum(case, "kg m/s per m²", &pen, 2.0 * 39.25 * 10.0);
    let s = &pen.out.summary;
    let de = s.energy_final / s.energy_initial - 1.0;
    rep.add(
        case,
        "total energy change (relative)",
        0.0,
        de,
        &pen,
        "|·| < 1e-3 (docs/method.md §11)",
        de.abs() < 1e-3,
    );

    // Kernel mode: the paper's point is that it fails; the records pass
    // when it does (bars still stuck, tension at the face).
    let case = "steel bars, kernel";
    let v = last(&ker, "velocity_left");
    rep.add(
        case,
        "left bar mean velocity at 4 µs (m/s)",
        r.final_velocity_1,
        v,
        &ker,
        "off by > 10 % (the paper's point)",
        (v / r.final_velocity_1 - 1.0).abs() > 0.1,
    );
    // The bodies pull on each other through the SPH sums: the face
    // particle's own stress shows it.
    let tension = max_tension(&ker, "stress_a");
    rep.add(
        case,
        "largest tension at the contact face (Pa)",
        0.0,
        tension,
        &ker,
        "> 10 % of the contact stress (the paper's point)",
        tension > 0.1 * r.contact_stress.abs(),
    );
    Ok(())
}

/// Case 2, Fig. 7: axial stress against position at fixed times, steel
/// against aluminium, kernel and contact modes against the exact profile.
fn steel_aluminium(opts: &Options, rep: &mut Report) -> Result<(), RunError> {
    let n = opts.resolution.bar_particles;
    let pen = run_case(
        &bar_scene(STEEL_AL, n, 5e-9),
        opts.backend,
        opts.integrator,
        None,
    )?;
    let kscene = bar_scene(STEEL_AL_KERNEL, n, 5e-9);
    let ex = exact_bars(&pen.scene, "aluminium")?;
    // Particle positions at t = 0 (the profiles are drawn against them; the
    // displacements are micrometres) and the exact profile's coordinates.
    let (m0, s0) = Model::new(&pen.scene);
    let x0: Vec<f64> = s0.x.iter().map(|x| x.x).collect();
    let at_face: Vec<(BarId, f64)> = (0..m0.len())
        .map(|i| {
            if m0.body[i] == 0 {
                (BarId::One, -x0[i])
            } else {
                (BarId::Two, x0[i])
            }
        })
        .collect();
    let stress = |r: &CaseRun| -> Vec<f64> {
        (0..r.out.model.len())
            .map(|i| particle_value(&r.out.model, &r.out.state, i, ParticleQuantity::StressXx))
            .collect()
    };
    let scale = ex.result.contact_stress.abs();

    // Profiles at three times inside the contact (the exact answer ends at
    // separation, 1.574 µs).
    let title =
        |mode: &str| format!("Fig. 7: σxx against position, steel | aluminium, {mode}, N = {n}");
    let ylabel = "σxx (MPa, tension positive)";
    let mut f = Figure::new(&title("contact mode"), "position (mm)", ylabel);
    let mut fk = Figure::new(&title("kernel mode"), "position (mm)", ylabel);
    let mut header = vec!["position_m".to_string()];
    let mut cols = vec![x0.clone()];
    for (k, tk) in [0.3e-6, 0.6e-6, 1.2e-6].into_iter().enumerate() {
        let p = run_case(&pen.scene, opts.backend, opts.integrator, Some(tk))?;
        let kr = run_case(&kscene, opts.backend, opts.integrator, Some(tk))?;
        let (sp, sk) = (stress(&p), stress(&kr));
        let exact: Vec<f64> = at_face
            .iter()
            .map(|&(bar, d)| ex.point_stress(bar, d, tk))
            .collect();
        // Mean |σ − σ_exact| over the particles, relative to the contact
        // stress (each front is a jump any particle spacing smears).
        let l1 = |s: &[f64]| {
            s.iter()
                .zip(&exact)
                .map(|(a, b)| (a - b).abs())
                .sum::<f64>()
                / s.len() as f64
                / scale
        };
        let (err, err_k) = (l1(&sp), l1(&sk));
        let label = format!("{:.1} µs", tk * 1e6);
        let obs = format!("stress profile at {label}: mean |error| / |σ_contact|");
        rep.add(
            "steel/aluminium, contact",
            &obs,
            0.0,
            err,
            &p,
            "< 0.1",
            err < 0.1,
        );
        rep.add(
            "steel/aluminium, kernel",
            &obs,
            0.0,
            err_k,
            &kr,
            "worse than contact mode (the paper's point)",
            err_k > err,
        );
        f.series.push(series(
            &format!("SPH, {label}"),
            pts(&x0, &sp, 1e3, 1e-6),
            Style::Solid,
            k,
        ));
        fk.series.push(series(
            &format!("SPH, {label}"),
            pts(&x0, &sk, 1e3, 1e-6),
            Style::Solid,
            k,
        ));
        let mut ep = pts(&x0, &exact, 1e3, 1e-6);
        ep.sort_by(|a, b| a.0.total_cmp(&b.0));
        let label_ex = if k == 0 { "exact" } else { "" };
        f.series.push(exact_series(label_ex, ep.clone()));
        fk.series.push(exact_series(label_ex, ep));
        for (name, c) in [("contact", sp), ("kernel", sk), ("exact", exact)] {
            header.push(format!("{name}_{:.1}us_pa", tk * 1e6));
            cols.push(c);
        }
    }
    let h: Vec<&str> = header.iter().map(String::as_str).collect();
    rep.csv("fig7_stress_profiles", &h, &cols)?;
    rep.figure("fig7_stress_profiles", &f);
    rep.figure("fig7_stress_profiles_kernel", &fk);

    let case = "steel/aluminium, contact";
    let r = &ex.result;
    let sc = rep.contact_phase(case, "interface stress plateau (Pa)", &pen, r, 0.03);
    rep.within(
        case,
        "aluminium mean velocity at 4 µs (m/s)",
        r.final_velocity_2,
        sc.final_right,
        &pen,
        0.03,
    );
    Ok(())
}

/// Case 3, Figs. 8 and 9: the two disks on both lattices.
fn disks(opts: &Options, rep: &mut Report) -> Result<(), RunError> {
    let r = opts.resolution.disk_r_over_dx;
    let us = 1e6;
    let mut fig9 = Figure::new(
        &format!("Fig. 9: contact force, two steel disks (R = 5 mm, 10 m/s), R/Δx = {r}"),
        "time (µs)",
        "contact force (MN/m)",
    );
    let mut header = Vec::new();
    let mut cols = Vec::new();
    let mut polar_peak = None;
    for (k, lattice) in ["square", "polar"].into_iter().enumerate() {
        let run = run_case(&disk_scene(lattice, r), opts.backend, opts.integrator, None)?;
        let sc = DiskScores::of(&run);
        let case = format!("disks, {lattice} lattice, contact");
        rep.within(
            &case,
            "peak contact force (N/m)",
            DISKS_PEAK_FORCE,
            sc.peak,
            &run,
            0.03,
        );
        rep.within(
            &case,
            "contact time (s)",
            DISKS_CONTACT_TIME,
            sc.contact_time,
            &run,
            0.03,
        );
        let e = sc.restitution;
        rep.add(
            &case,
            "restitution",
            1.0,
            e,
            &run,
            "0.95 to 1",
            (0.95..=1.0).contains(&e),
        );
        rep.add(
            &case,
            "least contact force (N/m)",
            0.0,
            sc.least_force.min(0.0),
            &run,
            "never < 0 (no tension)",
            sc.least_force >= 0.0,
        );
        let s = &run.out.summary;
        // The ledger: bodies' energy plus what the discrete spring lost
        // against the start; the loss itself falls with resolution
        // (0.7 % at R/Δx = 25, 0.08 % at 50 on the polar lattice).
        let balance = s.energy_balance();
        rep.add(
            &case,
            "energy balance incl. spring loss (relative)",
            0.0,
            balance,
            &run,
            "|·| < 5e-3",
            balance.abs() < 5e-3,
        );
        let loss = s.energy_spring_loss / s.energy_initial;
        rep.add(
            &case,
            "energy lost by the penalty spring (relative)",
            0.0,
            loss,
            &run,
            "< 1e-2",
            (-1e-3..1e-2).contains(&loss),
        );
        let mass: f64 = s.bodies.iter().map(|b| b.mass).sum();
        rep.momentum(&case, "kg m/s per m", &run, 5.0 * mass);
        let fc = run.col("contact_force");
        let t = run.times().to_vec();
        fig9.series.push(series(
            &format!("SPH, {lattice} lattice"),
            pts(&t, &fc, us, 1e-6),
            Style::Solid,
            k,
        ));
        header.push(format!("{lattice}_time_s"));
        header.push(format!("{lattice}_force_n_per_m"));
        cols.push(t);
        cols.push(fc);
        if lattice == "polar" {
            polar_peak = Some((run.scene, sc.t_peak));
        }
    }
    let scene = disk_scene("polar", r);
    let steel = MaterialModel::new(&scene.materials["steel"]);
    for (c, name, key) in [
        (HERTZ_C_JOHNSON, "Hertz, C = 1 (Johnson)", "c1"),
        (
            hertz_c_inertia(steel.nu),
            "Hertz, C = 1.742 (free disk)",
            "c1742",
        ),
    ] {
        let h = hertz_disks(&steel, 0.005, 10.0, c);
        let tt: Vec<f64> = h.curve.iter().map(|p| p.0).collect();
        let ff: Vec<f64> = h.curve.iter().map(|p| p.1).collect();
        // Both ends of the bracket drawn as references: C = 1 black dashed,
        // the other dashed in colour.
        let mut s = exact_series(name, pts(&tt, &ff, us, 1e-6));
        if key == "c1742" {
            s.exact = false;
            s.color = Some(4);
        }
        fig9.series.push(s);
        header.push(format!("hertz_{key}_time_s"));
        header.push(format!("hertz_{key}_force_n_per_m"));
        cols.push(tt);
        cols.push(ff);
    }
    let h: Vec<&str> = header.iter().map(String::as_str).collect();
    rep.csv("fig9_contact_force", &h, &cols)?;
    rep.figure("fig9_contact_force", &fig9);

    // Fig. 8: the von Mises field at peak force (polar lattice), from a run
    // stopped at that instant.
    if let Some((scene, tp)) = polar_peak {
        let run = run_case(&scene, opts.backend, opts.integrator, Some(tp))?;
        let (m, st) = (&run.out.model, &run.out.state);
        let x: Vec<f64> = st.x.iter().map(|p| p.x * 1e3).collect();
        let y: Vec<f64> = st.x.iter().map(|p| p.y * 1e3).collect();
        let vm: Vec<f64> = (0..m.len())
            .map(|i| particle_value(m, st, i, ParticleQuantity::VonMises) * 1e-9)
            .collect();
        rep.csv(
            "fig8_von_mises",
            &["x_mm", "y_mm", "von_mises_gpa"],
            &[x.clone(), y.clone(), vm.clone()],
        )?;
        let title = format!(
            "Fig. 8: von Mises stress at peak force (t = {:.2} µs), polar, R/Δx = {r}",
            tp * 1e6
        );
        let field = Field { x, y, value: vm };
        let path = rep.out.join("fig8_von_mises.png");
        if let Err(e) = plot::field_plot(
            &path,
            &title,
            "x (mm)",
            "y (mm)",
            "von Mises stress (GPa)",
            &field,
        ) {
            rep.warnings.push(format!("{}: {e}", path.display()));
        }
    }
    Ok(())
}

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
            integrator: Integrator::Midpoint,
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
            let mut scene = bar_scene(BARS, n, 5e-9);
            scene.simulation.integrator = opts.integrator;
            let (run, obs) = bar_observables_of(&scene, Some(b))?;
            push("bars", "segment", n as f64, &run, &obs);
        }
        for lattice in ["square", "polar"] {
            for &r in &opts.disk_r_over_dx {
                if opts.verbose {
                    eprintln!("sweep: disks, {lattice}, R/dx = {r}, {b}");
                }
                let mut scene = disk_scene(lattice, r);
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
