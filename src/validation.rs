//! `sphcontact validate`: the paper's cases run and scored against their
//! exact answers (METHOD.md §10), with one PNG figure per paper figure, the
//! CSV behind every curve, `validation.json`, and a speed-against-error
//! sweep over resolution and backend.
//!
//! Every case starts from a scene of `scenes/paper/` (embedded in the
//! binary, so `validate` runs from any directory) with only the resolution
//! and the recording interval changed.

use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::model::Model;
use crate::output::contact_window;
use crate::physics::exact::{
    bar_impact_history, hertz_c_inertia, hertz_disks, BarId, BarImpactHistory, HERTZ_C_JOHNSON,
};
use crate::physics::material::MaterialModel;
use crate::plot::{self, Field, Figure, Series, Style};
use crate::probe::particle_value;
use crate::run::{run_scene, RunOptions, RunOutput};
use crate::scene::{Backend, ParticleQuantity, Scene};
use crate::RunError;

/// The paper's scenes, embedded.
const BARS: &str = include_str!("../scenes/paper/bars_steel.toml");
const BARS_KERNEL: &str = include_str!("../scenes/paper/bars_steel_kernel.toml");
const STEEL_AL: &str = include_str!("../scenes/paper/bars_steel_aluminium.toml");
const STEEL_AL_KERNEL: &str = include_str!("../scenes/paper/bars_steel_aluminium_kernel.toml");
const DISKS_SQUARE: &str = include_str!("../scenes/paper/disks_square.toml");
const DISKS_POLAR: &str = include_str!("../scenes/paper/disks_polar.toml");

/// Converged dynamic reference for the two disks (METHOD.md §8.4: a
/// converged dynamic finite-element solution): peak force per unit
/// thickness, N/m, and contact time, s. It lies inside the quasi-static
/// Hertz bracket of METHOD.md §10 (1.161–1.224 MN/m, 8.30–8.71 µs).
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
    end: Option<f64>,
) -> Result<CaseRun, RunError> {
    let opts = RunOptions {
        silent: true,
        backend,
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

fn rel(measured: f64, exact: f64) -> Option<f64> {
    (exact != 0.0).then(|| measured / exact - 1.0)
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

/// Draws a figure, turning a missing font into a warning (the CSV behind
/// it is written regardless).
fn draw(path: &Path, fig: &Figure, warnings: &mut Vec<String>) {
    if let Err(e) = plot::line_plot(path, fig) {
        warnings.push(format!("{}: {e}", path.display()));
    }
}

/// The results of `validate`.
#[derive(Debug, Default)]
pub struct Report {
    pub records: Vec<Record>,
    /// Figures and CSVs written.
    pub files: Vec<PathBuf>,
    pub warnings: Vec<String>,
}

impl Report {
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
            relative_error: rel(measured, exact),
            backend: run.backend(),
            particles: run.out.summary.particles,
            wall_seconds: run.out.summary.wall_seconds,
            target: target.into(),
            pass,
        });
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
    let mut rep = Report::default();
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
    let path = opts.out.join("validation.json");
    let text = serde_json::to_string_pretty(&rep.records).expect("records serialise");
    crate::output::write_atomic(&path, (text + "\n").as_bytes())?;
    rep.files.push(path);
    Ok(rep)
}

/// Largest tensile (positive) value of `col` while the pair is in contact.
fn max_tension_in_contact(run: &CaseRun, col: &str, t_end: f64) -> f64 {
    let s = run.col(col);
    run.times()
        .iter()
        .zip(&s)
        .filter(|(t, _)| **t > 0.0 && **t < t_end)
        .map(|(_, v)| *v)
        .fold(0.0, f64::max)
}

/// Initial distance from the contact face of the particle a probe follows.
fn probe_distance(scene: &Scene, at: f64) -> f64 {
    let (model, st) = Model::new(scene);
    let b = &model.bodies[0];
    b.range
        .clone()
        .map(|i| st.x[i].x)
        .min_by(|a, c| (a - at).abs().total_cmp(&(c - at).abs()))
        .map_or(at.abs(), f64::abs)
}

/// Case 1, Figs. 4–6: velocity at point b, stress at the contact point a,
/// and the bars' mean velocities, kernel and contact modes against exact.
fn bars(opts: &Options, rep: &mut Report) -> Result<(), RunError> {
    let n = opts.resolution.bar_particles;
    let pen = run_case(&bar_scene(BARS, n, 5e-9), opts.backend, None)?;
    let ker = run_case(&bar_scene(BARS_KERNEL, n, 5e-9), opts.backend, None)?;
    let steel = MaterialModel::new(&pen.scene.materials["steel"]);
    let l = 0.005;
    let end = pen.scene.simulation.end_time;
    let ex = bar_impact_history(&steel, l, 10.0, &steel, l, -10.0, end)
        .ok_or_else(|| RunError::Backend("exact bar answer unavailable".into()))?;
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
    write_csv(
        &opts.out.join("fig4_velocity_b.csv"),
        &["time_s", "exact_m_s", "contact_m_s", "kernel_m_s"],
        &[t.clone(), exact_vb.clone(), vb_p.clone(), vb_k.clone()],
    )?;
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
    draw(&opts.out.join("fig4_velocity_b.png"), &f, &mut rep.warnings);

    // Fig. 5: stress at the contact point a. In contact mode that is the
    // contact pressure (METHOD.md §11); in kernel mode the SPH stress of the
    // face particle (tension positive), shown as −σ_xx (compression up).
    let p_pen = pen.col("contact_pressure");
    let s_ker: Vec<f64> = ker.col("stress_a").iter().map(|s| -s).collect();
    let exact_p: Vec<f64> = t.iter().map(|&s| -ex.interface_stress(s)).collect();
    write_csv(
        &opts.out.join("fig5_stress_a.csv"),
        &[
            "time_s",
            "exact_pressure_pa",
            "contact_pressure_pa",
            "kernel_minus_stress_xx_pa",
        ],
        &[t.clone(), exact_p.clone(), p_pen.clone(), s_ker.clone()],
    )?;
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
    draw(&opts.out.join("fig5_stress_a.png"), &f, &mut rep.warnings);

    // Fig. 6: mean velocities.
    let ex_l: Vec<f64> = t.iter().map(|&s| ex.mean_velocity(BarId::One, s)).collect();
    let ex_r: Vec<f64> = t.iter().map(|&s| ex.mean_velocity(BarId::Two, s)).collect();
    let cols = [
        t.clone(),
        ex_l.clone(),
        ex_r.clone(),
        pen.col("velocity_left"),
        pen.col("velocity_right"),
        ker.col("velocity_left"),
        ker.col("velocity_right"),
    ];
    write_csv(
        &opts.out.join("fig6_mean_velocity.csv"),
        &[
            "time_s",
            "exact_left_m_s",
            "exact_right_m_s",
            "contact_left_m_s",
            "contact_right_m_s",
            "kernel_left_m_s",
            "kernel_right_m_s",
        ],
        &cols,
    )?;
    let mut f = Figure::new(
        &format!("Fig. 6: mean velocities of the bars, steel bars, N = {n}"),
        "time (µs)",
        "mean velocity (m/s)",
    );
    f.series.push(series(
        "kernel mode, left",
        pts(&tk, &cols[5], us, 1.0),
        Style::Solid,
        1,
    ));
    f.series.push(series(
        "kernel mode, right",
        pts(&tk, &cols[6], us, 1.0),
        Style::Solid,
        3,
    ));
    f.series.push(series(
        "contact mode, left",
        pts(&t, &cols[3], us, 1.0),
        Style::Solid,
        0,
    ));
    f.series.push(series(
        "contact mode, right",
        pts(&t, &cols[4], us, 1.0),
        Style::Solid,
        2,
    ));
    f.series
        .push(exact_series("exact", pts(&t, &ex_l, us, 1.0)));
    f.series.push(Series {
        label: String::new(),
        ..exact_series("", pts(&t, &ex_r, us, 1.0))
    });
    draw(
        &opts.out.join("fig6_mean_velocity.png"),
        &f,
        &mut rep.warnings,
    );

    // Scores.
    let case = "steel bars, contact";
    let (_, ts) = contact_window(&t, &p_pen);
    let plateau = at(&pen, "contact_pressure", 0.5 * ts);
    let p_ex = -ex.result.contact_stress;
    let e = plateau / p_ex - 1.0;
    rep.add(
        case,
        "contact pressure plateau (Pa)",
        p_ex,
        plateau,
        &pen,
        "within 1 %",
        e.abs() < 0.01,
    );
    let e = ts / ex.result.separation_time - 1.0;
    rep.add(
        case,
        "separation time (s)",
        ex.result.separation_time,
        ts,
        &pen,
        "within 1 %",
        e.abs() < 0.01,
    );
    let v = *pen.col("velocity_left").last().unwrap_or(&f64::NAN);
    let r = v / ex.result.final_velocity_1;
    rep.add(
        case,
        "rebound: left bar mean velocity at 4 µs (m/s)",
        ex.result.final_velocity_1,
        v,
        &pen,
        "≥ 0.97 of exact",
        r >= 0.97,
    );
    // The traction the bodies exert on each other: the contact pressure
    // (METHOD.md §11), never tensile.
    let tension = p_pen.iter().fold(0.0f64, |a, &p| a.max(-p));
    rep.add(
        case,
        "largest tensile traction between the bars (Pa)",
        0.0,
        tension,
        &pen,
        "0 (no tension)",
        tension <= 0.0,
    );
    let s = &pen.out.summary;
    let dp = (s.momentum_final[0] - s.momentum_initial[0]).abs();
    rep.add(
        case,
        "momentum change (kg m/s per m²)",
        0.0,
        dp,
        &pen,
        "round-off",
        dp < 1e-6 * 392.5,
    );
    let de = s.energy_final / s.energy_initial - 1.0;
    rep.add(
        case,
        "total energy change (relative)",
        0.0,
        de,
        &pen,
        "|·| < 1e-3 (METHOD.md §11)",
        de.abs() < 1e-3,
    );

    let case = "steel bars, kernel";
    let v = *ker.col("velocity_left").last().unwrap_or(&f64::NAN);
    rep.add(
        case,
        "left bar mean velocity at 4 µs (m/s)",
        ex.result.final_velocity_1,
        v,
        &ker,
        "fails (the paper's point)",
        true,
    );
    // In kernel mode the bodies pull on each other through the SPH sums:
    // the face particle's own stress shows it.
    let tension = max_tension_in_contact(&ker, "stress_a", end);
    rep.add(
        case,
        "largest tension at the contact face (Pa)",
        0.0,
        tension,
        &ker,
        "tension (the paper's point)",
        true,
    );
    for name in ["fig4_velocity_b", "fig5_stress_a", "fig6_mean_velocity"] {
        rep.files.push(opts.out.join(format!("{name}.png")));
        rep.files.push(opts.out.join(format!("{name}.csv")));
    }
    Ok(())
}

/// Case 2, Fig. 7: axial stress against position at fixed times, steel
/// against aluminium, kernel and contact modes against the exact profile.
fn steel_aluminium(opts: &Options, rep: &mut Report) -> Result<(), RunError> {
    let n = opts.resolution.bar_particles;
    let pen = run_case(&bar_scene(STEEL_AL, n, 5e-9), opts.backend, None)?;
    let steel = MaterialModel::new(&pen.scene.materials["steel"]);
    let al = MaterialModel::new(&pen.scene.materials["aluminium"]);
    let l = 0.005;
    let end = pen.scene.simulation.end_time;
    let ex: BarImpactHistory = bar_impact_history(&steel, l, 10.0, &al, l, -10.0, end)
        .ok_or_else(|| RunError::Backend("exact bar answer unavailable".into()))?;

    // Profiles at three times inside the contact (the exact answer ends at
    // separation, 1.574 µs).
    let times = [0.3e-6, 0.6e-6, 1.2e-6];
    let title =
        |mode: &str| format!("Fig. 7: σxx against position, steel | aluminium, {mode}, N = {n}");
    let mut f = Figure::new(
        &title("contact mode"),
        "position (mm)",
        "σxx (MPa, tension positive)",
    );
    let mut fk = Figure::new(
        &title("kernel mode"),
        "position (mm)",
        "σxx (MPa, tension positive)",
    );
    let mut header = Vec::new();
    let mut cols = Vec::new();
    for (k, &tk) in times.iter().enumerate() {
        let p = run_case(&pen.scene, opts.backend, Some(tk))?;
        let kscene = bar_scene(STEEL_AL_KERNEL, n, 5e-9);
        let kr = run_case(&kscene, opts.backend, Some(tk))?;
        let (m0, s0) = Model::new(&pen.scene);
        let x0: Vec<f64> = s0.x.iter().map(|x| x.x).collect();
        let stress = |r: &CaseRun| -> Vec<f64> {
            (0..r.out.model.len())
                .map(|i| particle_value(&r.out.model, &r.out.state, i, ParticleQuantity::StressXx))
                .collect()
        };
        let (sp, sk) = (stress(&p), stress(&kr));
        let exact: Vec<f64> = (0..m0.len())
            .map(|i| {
                let (bar, d) = if m0.body[i] == 0 {
                    (BarId::One, -x0[i])
                } else {
                    (BarId::Two, x0[i])
                };
                ex.point_stress(bar, d, tk)
            })
            .collect();
        // Error: mean |σ − σ_exact| over the particles, relative to the
        // contact stress (the front itself is a jump any grid smears).
        let scale = ex.result.contact_stress.abs();
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
        rep.add(
            "steel/aluminium, kernel",
            &format!("stress profile at {label}: mean |error| / |σ_contact|"),
            0.0,
            err_k,
            &kr,
            "large (the paper's point)",
            true,
        );
        for (name, c) in [("contact", sp), ("kernel", sk), ("exact", exact)] {
            header.push(format!("{name}_{:.1}us_pa", tk * 1e6));
            cols.push(c);
        }
        rep.add(
            "steel/aluminium, contact",
            &format!("stress profile at {label}: mean |error| / |σ_contact|"),
            0.0,
            err,
            &p,
            "< 0.1 (fronts smeared over a few Δx)",
            err < 0.1,
        );
    }
    let (_, s0) = Model::new(&pen.scene);
    let x0: Vec<f64> = s0.x.iter().map(|x| x.x).collect();
    let mut all_cols = vec![x0];
    all_cols.extend(cols);
    let mut h: Vec<&str> = vec!["position_m"];
    h.extend(header.iter().map(String::as_str));
    write_csv(&opts.out.join("fig7_stress_profiles.csv"), &h, &all_cols)?;
    draw(
        &opts.out.join("fig7_stress_profiles.png"),
        &f,
        &mut rep.warnings,
    );
    draw(
        &opts.out.join("fig7_stress_profiles_kernel.png"),
        &fk,
        &mut rep.warnings,
    );
    rep.files.push(opts.out.join("fig7_stress_profiles.png"));
    rep.files
        .push(opts.out.join("fig7_stress_profiles_kernel.png"));
    rep.files.push(opts.out.join("fig7_stress_profiles.csv"));

    let case = "steel/aluminium, contact";
    let t = pen.times().to_vec();
    let p = pen.col("contact_pressure");
    let (_, ts) = contact_window(&t, &p);
    let plateau = at(&pen, "contact_pressure", 0.5 * ts);
    let p_ex = -ex.result.contact_stress;
    let e = plateau / p_ex - 1.0;
    rep.add(
        case,
        "interface stress plateau (Pa)",
        p_ex,
        plateau,
        &pen,
        "within 1 %",
        e.abs() < 0.01,
    );
    let e = ts / ex.result.separation_time - 1.0;
    rep.add(
        case,
        "separation time (s)",
        ex.result.separation_time,
        ts,
        &pen,
        "within 3 %",
        e.abs() < 0.03,
    );
    let v = *pen.col("velocity_right").last().unwrap_or(&f64::NAN);
    let e = v / ex.result.final_velocity_2 - 1.0;
    rep.add(
        case,
        "aluminium mean velocity at 4 µs (m/s)",
        ex.result.final_velocity_2,
        v,
        &pen,
        "within 3 %",
        e.abs() < 0.03,
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
    let mut csv_cols = Vec::new();
    let mut header = Vec::new();
    let mut peak_state = None;
    for (k, lattice) in ["square", "polar"].into_iter().enumerate() {
        let scene = disk_scene(lattice, r);
        let run = run_case(&scene, opts.backend, None)?;
        let t = run.times().to_vec();
        let fc = run.col("contact_force");
        let (t0, t1) = contact_window(&t, &fc);
        let (kp, peak) = fc
            .iter()
            .enumerate()
            .fold((0, 0.0f64), |a, (i, &v)| if v > a.1 { (i, v) } else { a });
        let vl = run.col("velocity_left");
        let restitution = -vl.last().copied().unwrap_or(f64::NAN) / 5.0;
        let case = format!("disks, {lattice} lattice, contact");
        let e = peak / DISKS_PEAK_FORCE - 1.0;
        rep.add(
            &case,
            "peak contact force (N/m)",
            DISKS_PEAK_FORCE,
            peak,
            &run,
            "within 3 %",
            e.abs() < 0.03,
        );
        let e = (t1 - t0) / DISKS_CONTACT_TIME - 1.0;
        rep.add(
            &case,
            "contact time (s)",
            DISKS_CONTACT_TIME,
            t1 - t0,
            &run,
            "within 3 %",
            e.abs() < 0.03,
        );
        rep.add(
            &case,
            "restitution",
            1.0,
            restitution,
            &run,
            "0.95 to 1",
            (0.95..=1.0).contains(&restitution),
        );
        let least = fc.iter().copied().fold(f64::INFINITY, f64::min);
        rep.add(
            &case,
            "least contact force (N/m)",
            0.0,
            least.min(0.0),
            &run,
            "never < 0 (no tension)",
            least >= 0.0,
        );
        let s = &run.out.summary;
        let dp = (s.momentum_final[0] - s.momentum_initial[0]).abs();
        let mass: f64 = s.bodies.iter().map(|b| b.mass).sum();
        rep.add(
            &case,
            "momentum change (kg m/s per m)",
            0.0,
            dp,
            &run,
            "round-off",
            dp < 1e-9 * mass * 5.0,
        );
        fig9.series.push(series(
            &format!("SPH, {lattice} lattice"),
            pts(&t, &fc, us, 1e-6),
            Style::Solid,
            k,
        ));
        header.push(format!("{lattice}_time_s"));
        csv_cols.push(t.clone());
        header.push(format!("{lattice}_force_n_per_m"));
        csv_cols.push(fc.clone());
        if lattice == "polar" {
            peak_state = Some((scene, t[kp]));
        }
    }
    let steel = MaterialModel::new(&parse_embedded(DISKS_POLAR, "disks").materials["steel"]);
    for (k, (c, name)) in [
        (HERTZ_C_JOHNSON, "Hertz, C = 1 (Johnson)"),
        (hertz_c_inertia(steel.nu), "Hertz, C = 1.742 (free disk)"),
    ]
    .into_iter()
    .enumerate()
    {
        let h = hertz_disks(&steel, 0.005, 10.0, c);
        let tt: Vec<f64> = h.curve.iter().map(|p| p.0).collect();
        let ff: Vec<f64> = h.curve.iter().map(|p| p.1).collect();
        let mut s = exact_series(name, pts(&tt, &ff, us, 1e-6));
        if k == 1 {
            s.style = Style::Dashed;
            s.exact = false;
            s.color = Some(4);
        }
        fig9.series.push(s);
        header.push(format!(
            "hertz_c{}_time_s",
            if k == 0 { "1" } else { "1742" }
        ));
        csv_cols.push(tt);
        header.push(format!(
            "hertz_c{}_force_n_per_m",
            if k == 0 { "1" } else { "1742" }
        ));
        csv_cols.push(ff);
    }
    let h: Vec<&str> = header.iter().map(String::as_str).collect();
    write_csv(&opts.out.join("fig9_contact_force.csv"), &h, &csv_cols)?;
    draw(
        &opts.out.join("fig9_contact_force.png"),
        &fig9,
        &mut rep.warnings,
    );
    rep.files.push(opts.out.join("fig9_contact_force.png"));
    rep.files.push(opts.out.join("fig9_contact_force.csv"));

    // Fig. 8: the von Mises field at peak force (polar lattice), from a run
    // stopped at that instant.
    if let Some((scene, tp)) = peak_state {
        let run = run_case(&scene, opts.backend, Some(tp))?;
        let (m, st) = (&run.out.model, &run.out.state);
        let x: Vec<f64> = st.x.iter().map(|p| p.x * 1e3).collect();
        let y: Vec<f64> = st.x.iter().map(|p| p.y * 1e3).collect();
        let vm: Vec<f64> = (0..m.len())
            .map(|i| particle_value(m, st, i, ParticleQuantity::VonMises) * 1e-9)
            .collect();
        write_csv(
            &opts.out.join("fig8_von_mises.csv"),
            &["x_mm", "y_mm", "von_mises_gpa"],
            &[x.clone(), y.clone(), vm.clone()],
        )?;
        let field = Field { x, y, value: vm };
        let title = format!(
            "Fig. 8: von Mises stress at peak force (t = {:.2} µs), polar, R/Δx = {r}",
            tp * 1e6
        );
        if let Err(e) = plot::field_plot(
            &opts.out.join("fig8_von_mises.png"),
            &title,
            "x (mm)",
            "y (mm)",
            "von Mises stress (GPa)",
            &field,
        ) {
            rep.warnings.push(format!("fig8_von_mises.png: {e}"));
        }
        rep.files.push(opts.out.join("fig8_von_mises.png"));
        rep.files.push(opts.out.join("fig8_von_mises.csv"));
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

/// The bars' rebound, plateau and separation errors at `n` per bar.
pub fn bar_errors(
    n: usize,
    backend: Option<Backend>,
) -> Result<(CaseRun, [(String, f64, f64); 3]), RunError> {
    let run = run_case(&bar_scene(BARS, n, 5e-9), backend, None)?;
    let steel = MaterialModel::new(&run.scene.materials["steel"]);
    let ex = crate::physics::exact::bar_impact(&steel, 0.005, 10.0, &steel, 0.005, -10.0);
    let t = run.times().to_vec();
    let p = run.col("contact_pressure");
    let (_, ts) = contact_window(&t, &p);
    let plateau = at(&run, "contact_pressure", 0.5 * ts);
    let v = *run.col("velocity_left").last().unwrap_or(&f64::NAN);
    Ok((
        run,
        [
            ("rebound velocity".into(), ex.final_velocity_1, v),
            (
                "contact pressure plateau".into(),
                -ex.contact_stress,
                plateau,
            ),
            ("separation time".into(), ex.separation_time, ts),
        ],
    ))
}

/// The disks' peak force and contact time at `R/Δx` on `lattice`.
pub fn disk_errors(
    lattice: &str,
    r: f64,
    backend: Option<Backend>,
) -> Result<(CaseRun, [(String, f64, f64); 3]), RunError> {
    let run = run_case(&disk_scene(lattice, r), backend, None)?;
    let t = run.times().to_vec();
    let fc = run.col("contact_force");
    let (t0, t1) = contact_window(&t, &fc);
    let peak = fc.iter().copied().fold(0.0, f64::max);
    let restitution = -run.col("velocity_left").last().copied().unwrap_or(f64::NAN) / 5.0;
    Ok((
        run,
        [
            ("peak contact force".into(), DISKS_PEAK_FORCE, peak),
            ("contact time".into(), DISKS_CONTACT_TIME, t1 - t0),
            ("restitution".into(), 1.0, restitution),
        ],
    ))
}

/// The speed-against-error study: every resolution on every backend,
/// written as `sweep.csv` and log–log plots.
pub fn sweep(opts: &SweepOptions) -> Result<(Vec<SweepPoint>, Vec<String>), RunError> {
    std::fs::create_dir_all(&opts.out).map_err(|e| RunError::io(&opts.out, e))?;
    let mut points = Vec::new();
    let mut push =
        |case: &str, lattice: &str, res: f64, run: &CaseRun, obs: &[(String, f64, f64)]| {
            let s = &run.out.summary;
            for (name, exact, measured) in obs {
                points.push(SweepPoint {
                    case: case.into(),
                    lattice: lattice.into(),
                    backend: s.backend.clone(),
                    resolution: res,
                    particles: s.particles,
                    steps: s.steps,
                    particle_steps: s.steps as f64 * s.particles as f64,
                    wall_seconds: s.wall_seconds,
                    observable: name.clone(),
                    exact: *exact,
                    measured: *measured,
                    relative_error: measured / exact - 1.0,
                });
            }
        };
    for &b in &opts.backends {
        for &n in &opts.bar_particles {
            if opts.verbose {
                eprintln!("sweep: bars, {n} per bar, {b}");
            }
            let (run, obs) = bar_errors(n, Some(b))?;
            push("bars", "segment", n as f64, &run, &obs);
        }
        for lattice in ["square", "polar"] {
            for &r in &opts.disk_r_over_dx {
                if opts.verbose {
                    eprintln!("sweep: disks, {lattice}, R/dx = {r}, {b}");
                }
                let (run, obs) = disk_errors(lattice, r, Some(b))?;
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
    let backends: Vec<String> = {
        let mut b: Vec<String> = points.iter().map(|p| p.backend.clone()).collect();
        b.dedup();
        b.sort();
        b.dedup();
        b
    };
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
                                && &p.backend == b
                                && p.lattice == l
                        })
                        .map(|p| (xof(p), p.relative_error.abs()))
                        .collect();
                    if line.is_empty() {
                        continue;
                    }
                    let label = if case == "bars" {
                        b.clone()
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
