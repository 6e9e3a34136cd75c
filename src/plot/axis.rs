//! Axes: usable values, ranges, tick labels, the breaks in a polyline, and
//! the frame closed around a plotting area.

use plotters::prelude::*;
use std::ops::Range;

use super::PlotError;

/// Whether a coordinate can be plotted: finite, and not so extreme that
/// ranges overflow or plotters' tick search stops terminating (it does for
/// ranges near f64::MAX or among subnormals).
pub(super) fn usable(v: f64) -> bool {
    v == 0.0 || (1e-300..1e300).contains(&v.abs())
}

/// Smallest and largest usable value; (inf, -inf) when there is none.
pub(super) fn extent(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    let minmax = |(a, b): (f64, f64), v: f64| (a.min(v), b.max(v));
    vals.filter(|v| usable(*v))
        .fold((f64::INFINITY, f64::NEG_INFINITY), minmax)
}

/// One axis: its range, whether it is logarithmic, and how it labels ticks.
pub(super) struct Axis {
    pub(super) lo: f64,
    pub(super) hi: f64,
    pub(super) log: bool,
}

impl Axis {
    /// Data range with a small margin, never zero-sized. Log axes use positive
    /// values only and widen to whole decades when fewer than two powers of
    /// ten would show, since only those carry tick labels.
    pub(super) fn new(vals: impl Iterator<Item = f64>, log: bool) -> Self {
        let (lo, hi) = extent(vals.filter(|v| !log || *v > 0.0));
        let (lo, hi) = match (lo <= hi, log) {
            (false, false) => (0.0, 1.0),
            (false, true) => (1.0, 10.0),
            (true, true) => {
                let (a, b) = (lo.log10(), hi.log10());
                let pad = (0.05 * (b - a)).max(0.05);
                // plotters overflows (and loops) on ratios beyond f64::MAX.
                let b = (b + pad).min(300.0);
                let a = (a - pad).max(b - 300.0);
                let snap = b.floor() - a.ceil() < 1.0;
                let (a, b) = if snap { (a.floor(), b.ceil()) } else { (a, b) };
                (10f64.powf(a), 10f64.powf(b))
            }
            _ if hi - lo <= 1e-12 * lo.abs().max(hi.abs()) => {
                let pad = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
                (lo - pad, hi + pad)
            }
            _ => (lo - 0.04 * (hi - lo), hi + 0.04 * (hi - lo)),
        };
        Axis { lo, hi, log }
    }

    pub(super) fn label(&self, v: f64) -> String {
        match self.log {
            true => log_label(v, (self.hi / self.lo).log10()),
            false => lin_label(v, self.lo, self.hi),
        }
    }

    /// Position of `v` along the axis as a fraction of its length.
    pub(super) fn frac(&self, v: f64) -> f64 {
        let f = |v: f64| if self.log { v.log10() } else { v };
        (f(v) - f(self.lo)) / (f(self.hi) - f(self.lo))
    }

    /// Pixel width of the widest tick label, so that the label area can hold
    /// it without clipping it or overlapping the axis title.
    pub(super) fn label_width(&self, area: &Area, style: &TextStyle) -> u32 {
        let (lo, hi) = (self.lo.log10().floor(), self.hi.log10().ceil());
        let samples: Vec<f64> = match self.log {
            true => (lo as i32..=hi as i32)
                .flat_map(|e| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(e)))
                .collect(),
            false => (0..=8)
                .map(|i| self.lo + (self.hi - self.lo) * i as f64 / 8.0)
                .collect(),
        };
        let width = |v: &f64| area.estimate_text_size(&self.label(*v), style).ok();
        samples
            .iter()
            .filter_map(width)
            .map(|d| d.0)
            .max()
            .unwrap_or(0)
    }
}

pub(super) type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

fn trim_zeros(s: String) -> String {
    match s.contains('.') {
        true => s.trim_end_matches('0').trim_end_matches('.').to_string(),
        false => s,
    }
}

fn superscript(e: i32) -> String {
    let digit = |c: char| "⁰¹²³⁴⁵⁶⁷⁸⁹".chars().nth(c as usize - 48).unwrap_or('?');
    let digits: String = e.unsigned_abs().to_string().chars().map(digit).collect();
    if e < 0 {
        format!("⁻{digits}")
    } else {
        digits
    }
}

/// Tick label on a linear axis `[lo, hi]`: enough decimals for the tick step,
/// `m×10ⁿ` when the axis magnitude is extreme, and a typographic minus sign.
pub(super) fn lin_label(v: f64, lo: f64, hi: f64) -> String {
    let step = ((hi - lo).abs() / 10.0).max(1e-300).log10().floor();
    if v.abs() < 10f64.powf(step - 8.0) {
        return "0".into();
    }
    let s = if (1e-3..1e5).contains(&lo.abs().max(hi.abs())) {
        let d = (1.0 - step).clamp(0.0, 12.0) as usize;
        trim_zeros(format!("{v:.d$}"))
    } else {
        let e = v.abs().log10().floor();
        let d = (e - step + 1.0).clamp(0.0, 6.0) as usize;
        let m = trim_zeros(format!("{:.d$}", v / 10f64.powf(e)));
        format!("{m}×10{}", superscript(e as i32))
    };
    s.replace('-', "−")
}

/// Tick label on a log axis: powers of ten as `10ⁿ`; when about one decade is
/// shown, 2 and 5 are labelled too. Other ticks keep only their grid line.
pub(super) fn log_label(v: f64, decades: f64) -> String {
    let e = v.log10().floor();
    let m = v / 10f64.powf(e);
    let near = |t: f64| (m - t).abs() < 1e-6 * t;
    if near(1.0) || near(10.0) {
        format!("10{}", superscript(e as i32 + i32::from(near(10.0))))
    } else if decades < 1.5 && (near(2.0) || near(5.0)) {
        format!("{}×10{}", m.round(), superscript(e as i32))
    } else {
        String::new()
    }
}

/// Splits a polyline at unusable points so that gaps show as gaps, not as
/// lines drawn across them.
pub(super) fn runs(points: &[(f64, f64)], log_x: bool, log_y: bool) -> Vec<Vec<(f64, f64)>> {
    let ok = |v: f64, log: bool| usable(v) && (!log || v > 0.0);
    let bad = |p: &(f64, f64)| !(ok(p.0, log_x) && ok(p.1, log_y));
    let runs = points.split(bad).filter(|r| !r.is_empty());
    runs.map(<[_]>::to_vec).collect()
}

/// Draws the top and right edges of a plotting area (plotters draws only the
/// left and bottom axes) for a closed, publication-style frame; the range
/// is in the backend's pixels, `root` may be a panel of it.
pub(super) fn close_frame(
    root: &Area,
    (px, py): (Range<i32>, Range<i32>),
) -> Result<(), PlotError> {
    let (bx, by) = root.get_base_pixel();
    let (px, py) = (px.start - bx..px.end - bx, py.start - by..py.end - by);
    let corners = vec![(px.start, py.start), (px.end, py.start), (px.end, py.end)];
    root.draw(&PathElement::new(corners, BLACK))?;
    Ok(())
}
