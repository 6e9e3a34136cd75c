//! The scored records, the table `validate` prints, and the CSV and figure
//! writers every case shares.

use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::plot::{self, Figure, Series, Style};
use crate::RunError;

use super::exact;
use super::runs::{BarScores, CaseRun};

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

pub(super) fn pts(x: &[f64], y: &[f64], sx: f64, sy: f64) -> Vec<(f64, f64)> {
    x.iter().zip(y).map(|(a, b)| (a * sx, b * sy)).collect()
}

pub(super) fn series(label: &str, points: Vec<(f64, f64)>, style: Style, color: usize) -> Series {
    Series {
        label: label.into(),
        points,
        style,
        color: Some(color),
        exact: false,
    }
}

pub(super) fn exact_series(label: &str, points: Vec<(f64, f64)>) -> Series {
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
pub(super) fn draw(path: &Path, fig: &Figure, warnings: &mut Vec<String>) {
    if let Err(e) = plot::line_plot(path, fig) {
        warnings.push(format!("{}: {e}", path.display()));
    }
}

/// The results of `validate`, and where its files go.
#[derive(Debug)]
pub struct Report {
    pub records: Vec<Record>,
    pub warnings: Vec<String>,
    pub(super) out: PathBuf,
}

impl Report {
    pub(super) fn new(out: &Path) -> Self {
        Self {
            records: Vec::new(),
            warnings: Vec::new(),
            out: out.to_path_buf(),
        }
    }

    /// `<out>/<name>.csv`.
    pub(super) fn csv(
        &self,
        name: &str,
        header: &[&str],
        cols: &[Vec<f64>],
    ) -> Result<(), RunError> {
        write_csv(&self.out.join(format!("{name}.csv")), header, cols)
    }

    /// `<out>/<name>.png`.
    pub(super) fn figure(&mut self, name: &str, fig: &Figure) {
        draw(
            &self.out.join(format!("{name}.png")),
            fig,
            &mut self.warnings,
        );
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn add(
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
    pub(super) fn within(
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
    pub(super) fn contact_phase(
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
    pub(super) fn momentum(&mut self, case: &str, unit: &str, run: &CaseRun, scale: f64) {
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
