//! PNG figures for `validate`: line plots (time histories, convergence) and
//! particle field plots.
//!
//! Pure Rust on purpose: plotters' bitmap backend with `ab_glyph` text needs
//! no system libraries at build time (no fontconfig/freetype) and runs
//! headless. The one runtime requirement is a TrueType font file, found once.
//!
//! Degenerate data never panics: non-finite (or absurdly large or tiny)
//! values are skipped, lines break there, log axes also skip values <= 0, and
//! a figure without usable data is drawn as an empty but valid plot on a
//! default range. Inconsistent input
//! (mismatched `Field` lengths, absurd image sizes) is `PlotError::Input`.

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::ops::Range;
use std::path::Path;
use std::sync::OnceLock;

/// Errors from drawing a figure.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    #[error("no TrueType font found for plot text: install one (e.g. the Debian/Ubuntu package fonts-dejavu-core) or set SPHCONTACT_FONT to the path of a .ttf file")]
    NoFont,
    #[error("font given by SPHCONTACT_FONT is unusable: {0}")]
    Font(String),
    #[error("invalid plot input: {0}")]
    Input(String),
    #[error("plot drawing failed: {0}")]
    Draw(String),
}

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        PlotError::Draw(e.to_string())
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    Solid,
    Dashed,
    /// Small filled circles, no line: for sparse or scattered samples.
    Markers,
}

/// One curve of a line plot.
#[derive(Debug, Clone)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    /// Palette index (wraps around); `None` takes the next automatic colour.
    pub color: Option<usize>,
    /// The exact answer: drawn black, dashed, thicker and on top, so that the
    /// numerical curves underneath stay visible through the gaps.
    pub exact: bool,
}

/// A line plot; `Figure::new` gives the 1000x650 default size.
#[derive(Debug, Clone, Default)]
pub struct Figure {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub log_x: bool,
    pub log_y: bool,
    pub width: u32,
    pub height: u32,
}

impl Figure {
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Figure {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            width: 1000,
            height: 650,
            ..Self::default()
        }
    }
}

/// Scattered particle values: `x`, `y` and `value` hold one entry per particle.
#[derive(Debug, Clone, Default)]
pub struct Field {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub value: Vec<f64>,
}

/// Pixel size of field plots: a square-ish plotting area plus a colour bar.
pub const FIELD_SIZE: (u32, u32) = (1000, 800);

/// Registered family name; "sans-serif" is also what plotters' defaults use.
const FAMILY: &str = "sans-serif";
const FONT_PATHS: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu-sans-fonts/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/truetype/liberation2/LiberationSans-Regular.ttf",
    "/usr/share/fonts/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/liberation-sans/LiberationSans-Regular.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
    "C:\\Windows\\Fonts\\arial.ttf",
];

/// Loads and registers the font once per process. plotters keeps a `&'static`
/// reference, so the bytes are leaked on purpose (a few hundred kB, once).
fn ensure_font() -> Result<(), PlotError> {
    static STATE: OnceLock<Result<(), Option<String>>> = OnceLock::new();
    let install = |path: &Path| -> Result<(), String> {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        register_font(FAMILY, FontStyle::Normal, bytes)
            .map_err(|_| format!("{}: not a TrueType/OpenType font", path.display()))
    };
    let state = STATE.get_or_init(|| match std::env::var_os("SPHCONTACT_FONT") {
        // An explicit choice that fails is reported, not silently replaced.
        Some(p) if !p.is_empty() => install(Path::new(&p)).map_err(Some),
        _ => FONT_PATHS
            .iter()
            .find_map(|p| install(Path::new(p)).ok())
            .ok_or(None),
    });
    match state {
        Ok(()) => Ok(()),
        Err(None) => Err(PlotError::NoFont),
        Err(Some(e)) => Err(PlotError::Font(e.clone())),
    }
}

/// Whether text, and hence any plot, can be drawn.
pub fn font_available() -> bool {
    ensure_font().is_ok()
}

/// Okabe–Ito (colour-blind safe) without black, reserved for exact curves, and
/// with its pale yellow, weak on white, replaced by brown and grey.
const PALETTE: [u32; 8] = [
    0x0072B2, 0xD55E00, 0x009E73, 0xCC79A7, 0xE69F00, 0x56B4E9, 0x8C5628, 0x787878,
];

/// Viridis at 11 evenly spaced stops; linear interpolation between them is
/// visually indistinguishable from the full 256-entry table.
const VIRIDIS: [u32; 11] = [
    0x440154, 0x482475, 0x414487, 0x355F8D, 0x2A788E, 0x21918C, 0x22A884, 0x44BF70, 0x7AD151,
    0xBDDF26, 0xFDE725,
];

fn rgb(c: u32) -> RGBColor {
    RGBColor((c >> 16) as u8, (c >> 8) as u8, c as u8)
}

fn viridis(t: f64) -> RGBColor {
    let s = 10.0 * if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let i = (s as usize).min(9);
    let (a, b, f) = (rgb(VIRIDIS[i]), rgb(VIRIDIS[i + 1]), s - i as f64);
    let mix = |p: u8, q: u8| (p as f64 + (q as f64 - p as f64) * f).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

fn font(size: u32) -> TextStyle<'static> {
    (FAMILY, size).into_font().color(&BLACK)
}

/// Checks the font, then runs the drawing and turns a panic inside plotters
/// into an error: a figure must never take down a validation run.
fn guarded(f: impl FnOnce() -> Result<(), PlotError>) -> Result<(), PlotError> {
    ensure_font()?;
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).unwrap_or_else(|p| {
        let msg = p.downcast_ref::<&str>().map(|s| s.to_string());
        let msg = msg.or_else(|| p.downcast_ref::<String>().cloned());
        Err(PlotError::Draw(format!(
            "panic: {}",
            msg.unwrap_or_default()
        )))
    })
}

/// Whether a coordinate can be plotted: finite, and not so extreme that
/// ranges overflow or plotters' tick search stops terminating (it does for
/// ranges near f64::MAX or among subnormals).
fn usable(v: f64) -> bool {
    v == 0.0 || (1e-300..1e300).contains(&v.abs())
}

/// Smallest and largest usable value; (inf, -inf) when there is none.
fn extent(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    let minmax = |(a, b): (f64, f64), v: f64| (a.min(v), b.max(v));
    vals.filter(|v| usable(*v))
        .fold((f64::INFINITY, f64::NEG_INFINITY), minmax)
}

/// One axis: its range, whether it is logarithmic, and how it labels ticks.
struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
}

impl Axis {
    /// Data range with a small margin, never zero-sized. Log axes use positive
    /// values only and widen to whole decades when fewer than two powers of
    /// ten would show, since only those carry tick labels.
    fn new(vals: impl Iterator<Item = f64>, log: bool) -> Self {
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

    fn label(&self, v: f64) -> String {
        match self.log {
            true => log_label(v, (self.hi / self.lo).log10()),
            false => lin_label(v, self.lo, self.hi),
        }
    }

    /// Position of `v` along the axis as a fraction of its length.
    fn frac(&self, v: f64) -> f64 {
        let f = |v: f64| if self.log { v.log10() } else { v };
        (f(v) - f(self.lo)) / (f(self.hi) - f(self.lo))
    }

    /// Pixel width of the widest tick label, so that the label area can hold
    /// it without clipping it or overlapping the axis title.
    fn label_width(&self, area: &Area, style: &TextStyle) -> u32 {
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

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

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
fn lin_label(v: f64, lo: f64, hi: f64) -> String {
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
fn log_label(v: f64, decades: f64) -> String {
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
fn runs(points: &[(f64, f64)], log_x: bool, log_y: bool) -> Vec<Vec<(f64, f64)>> {
    let ok = |v: f64, log: bool| usable(v) && (!log || v > 0.0);
    let bad = |p: &(f64, f64)| !(ok(p.0, log_x) && ok(p.1, log_y));
    let runs = points.split(bad).filter(|r| !r.is_empty());
    runs.map(<[_]>::to_vec).collect()
}

/// Draws `fig` as a PNG at `path` (the parent directory must exist).
pub fn line_plot(path: &Path, fig: &Figure) -> Result<(), PlotError> {
    check_size(fig.width, fig.height)?;
    guarded(|| {
        let root = BitMapBackend::new(path, (fig.width, fig.height)).into_drawing_area();
        root.fill(&WHITE)?;
        draw_figure(&root, fig)?;
        root.present()?;
        Ok(())
    })
}

/// Draws `figs` as panels stacked top to bottom in one PNG at `path`, each
/// `fig.width` by `fig.height` of the first: one axis each, for quantities
/// of different units against one abscissa.
pub fn panel_plot(path: &Path, figs: &[Figure]) -> Result<(), PlotError> {
    let Some(first) = figs.first() else {
        return Err(PlotError::Input("no panels".into()));
    };
    let (w, h) = (first.width, first.height.saturating_mul(figs.len() as u32));
    check_size(w, h)?;
    guarded(|| {
        let root = BitMapBackend::new(path, (w, h)).into_drawing_area();
        root.fill(&WHITE)?;
        for (area, fig) in root.split_evenly((figs.len(), 1)).iter().zip(figs) {
            draw_figure(area, fig)?;
        }
        root.present()?;
        Ok(())
    })
}

fn check_size(width: u32, height: u32) -> Result<(), PlotError> {
    if !(200..=20_000).contains(&width) || !(150..=20_000).contains(&height) {
        let size = format!("{width}x{height}");
        return Err(PlotError::Input(format!(
            "image size {size} not in 200x150..20000x20000"
        )));
    }
    Ok(())
}

/// One line plot into `root`.
fn draw_figure(root: &Area, fig: &Figure) -> Result<(), PlotError> {
    let pts = || fig.series.iter().flat_map(|s| s.points.iter().copied());
    let (xa, ya) = (
        Axis::new(pts().map(|p| p.0), fig.log_x),
        Axis::new(pts().map(|p| p.1), fig.log_y),
    );
    let ax = [&xa, &ya];
    let (xr, yr) = (ax[0].lo..ax[0].hi, ax[1].lo..ax[1].hi);
    // The coordinate types differ, so each linear/log combination is its own
    // instance of the generic drawing function.
    match (fig.log_x, fig.log_y) {
        (false, false) => draw_lines(root, fig, ax, xr, yr),
        (true, false) => draw_lines(root, fig, ax, xr.log_scale(), yr),
        (false, true) => draw_lines(root, fig, ax, xr, yr.log_scale()),
        (true, true) => draw_lines(root, fig, ax, xr.log_scale(), yr.log_scale()),
    }
}

/// The corner, top-right preferred, where a legend box of `size` pixels in a
/// plotting area of `dim` pixels hides the fewest data samples; lines are
/// sampled between their points so that sparse series count too.
fn legend_corner(fig: &Figure, ax: [&Axis; 2], dim: (u32, u32), size: (u32, u32)) -> usize {
    let w = (size.0 + 16) as f64 / dim.0.max(1) as f64;
    let h = (size.1 + 16) as f64 / dim.1.max(1) as f64;
    let mut hits = [0usize; 4];
    for run in fig
        .series
        .iter()
        .flat_map(|s| runs(&s.points, ax[0].log, ax[1].log))
    {
        let f: Vec<_> = run
            .iter()
            .map(|p| (ax[0].frac(p.0), ax[1].frac(p.1)))
            .collect();
        for (i, &(x1, y1)) in f.iter().enumerate() {
            let (x0, y0) = f[i.saturating_sub(1)];
            for t in [0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875] {
                let (x, y) = (x0 + (x1 - x0) * t, y0 + (y1 - y0) * t);
                let (l, r, b, top) = (x <= w, x >= 1.0 - w, y <= h, y >= 1.0 - h);
                for (c, inside) in [r && top, l && top, r && b, l && b].into_iter().enumerate() {
                    hits[c] += usize::from(inside);
                }
            }
        }
    }
    (0..4).min_by_key(|&c| (hits[c], c)).unwrap_or(0)
}

fn draw_lines<X, Y>(root: &Area, fig: &Figure, ax: [&Axis; 2], x: X, y: Y) -> Result<(), PlotError>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let (tick, y_area) = (font(16), ax[1].label_width(root, &font(16)) + 48);
    let mut builder = ChartBuilder::on(root);
    builder
        .margin(12)
        .margin_right(28)
        .x_label_area_size(62)
        .y_label_area_size(y_area);
    if !fig.title.is_empty() {
        builder.caption(&fig.title, font(24));
    }
    let mut chart = builder.build_cartesian_2d(x, y)?;
    let (fx, fy) = (|v: &f64| ax[0].label(*v), |v: &f64| ax[1].label(*v));
    let mut mesh = chart.configure_mesh();
    mesh.bold_line_style(BLACK.mix(0.13))
        .light_line_style(BLACK.mix(0.04))
        .max_light_lines(5);
    // Ten, not fewer: below that plotters drops the 2..9 ticks of a log axis
    // spanning a single decade, leaving it with just two labels.
    mesh.x_labels(10)
        .y_labels(10)
        .label_style(tick)
        .axis_desc_style(font(19));
    mesh.x_desc(&fig.x_label)
        .y_desc(&fig.y_label)
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .draw()?;
    // Exact answers last so that they sit on top of the numerical curves.
    let (exact, numeric): (Vec<&Series>, Vec<_>) = fig.series.iter().partition(|s| s.exact);
    let mut next = 0;
    for s in numeric.into_iter().chain(exact) {
        let (color, stroke_width, style) = match s.exact {
            true => (BLACK, 3, Style::Dashed),
            false => {
                let c = s.color.unwrap_or_else(|| (next, next += 1).0);
                (rgb(PALETTE[c % PALETTE.len()]), 2, s.style)
            }
        };
        let line = color.stroke_width(stroke_width);
        let parts = runs(&s.points, fig.log_x, fig.log_y).into_iter();
        let anno = match style {
            Style::Solid => chart
                .draw_series(parts.map(|r| PathElement::new(r, line)))?
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 26, y)], line)),
            Style::Dashed => chart
                .draw_series(parts.map(|r| DashedPathElement::new(r, 11, 6, line)))?
                .legend(move |(x, y)| {
                    DashedPathElement::new(vec![(x, y), (x + 26, y)], 8, 5, line)
                }),
            Style::Markers => chart
                .draw_series(parts.flatten().map(|p| Circle::new(p, 4, line.filled())))?
                .legend(move |(x, y)| Circle::new((x + 13, y), 4, line.filled())),
        };
        anno.label(s.label.as_str());
    }
    if !fig.series.is_empty() {
        let text = |s: &Series| root.estimate_text_size(&s.label, &font(16)).ok();
        let w = fig.series.iter().filter_map(text).map(|d| d.0).max();
        let w = w.unwrap_or(0);
        let size = (w + 58, fig.series.len() as u32 * 24 + 8);
        use SeriesLabelPosition::*;
        let i = legend_corner(fig, ax, chart.plotting_area().dim_in_pixel(), size);
        let mut corners = [UpperRight, UpperLeft, LowerRight, LowerLeft].into_iter();
        let corner = corners.nth(i).unwrap_or(UpperRight);
        let mut legend = chart.configure_series_labels();
        legend.position(corner).margin(12).legend_area_size(34);
        legend.label_font(font(16)).border_style(BLACK.mix(0.4));
        legend.background_style(WHITE.mix(0.85)).draw()?;
    }
    close_frame(root, chart.plotting_area().get_pixel_range())?;
    Ok(())
}

/// Draws the top and right edges of a plotting area (plotters draws only the
/// left and bottom axes) for a closed, publication-style frame; the range
/// is in the backend's pixels, `root` may be a panel of it.
fn close_frame(root: &Area, (px, py): (Range<i32>, Range<i32>)) -> Result<(), PlotError> {
    let (bx, by) = root.get_base_pixel();
    let (px, py) = (px.start - bx..px.end - bx, py.start - by..py.end - by);
    let corners = vec![(px.start, py.start), (px.end, py.start), (px.end, py.end)];
    root.draw(&PathElement::new(corners, BLACK))?;
    Ok(())
}

/// Typical particle spacing, sqrt(covered area / N). The covered area is the
/// number of occupied cells of a grid, refined around the estimate a few times,
/// so bodies far apart in a mostly empty bounding box are handled.
fn spacing(pts: &[(f64, f64, f64)]) -> f64 {
    let (x0, x1) = extent(pts.iter().map(|p| p.0));
    let (y0, y1) = extent(pts.iter().map(|p| p.1));
    let n = pts.len().max(1) as f64;
    let area = ((x1 - x0) * (y1 - y0)).max((x1 - x0).max(y1 - y0).powi(2) * 1e-6);
    let mut s = (area / n).sqrt();
    for _ in 0..3 {
        let cell = 2.0 * s;
        let key = |p: &(f64, f64, f64)| ((p.0 / cell).floor() as i64, (p.1 / cell).floor() as i64);
        let mut cells: Vec<_> = pts.iter().map(key).collect();
        cells.sort_unstable();
        cells.dedup();
        s = (cells.len() as f64 * cell * cell / n).sqrt();
    }
    s
}

/// Draws a particle scatter coloured by `value` (viridis, colour bar on the
/// right) with 1 m in x as long on screen as 1 m in y, at `FIELD_SIZE` pixels.
/// Non-finite positions are skipped; particles with a non-finite value are
/// drawn grey so that blow-ups stay visible.
pub fn field_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    value_label: &str,
    field: &Field,
) -> Result<(), PlotError> {
    let (n, ny, nv) = (field.x.len(), field.y.len(), field.value.len());
    if ny != n || nv != n {
        let msg = format!("field lengths differ: x {n}, y {ny}, value {nv}");
        return Err(PlotError::Input(msg));
    }
    guarded(|| draw_field(path, title, [x_label, y_label, value_label], field))
}

fn draw_field(path: &Path, title: &str, labels: [&str; 3], f: &Field) -> Result<(), PlotError> {
    let pts: Vec<(f64, f64, f64)> = (0..f.x.len())
        .map(|i| (f.x[i], f.y[i], f.value[i]))
        .filter(|p| usable(p.0) && usable(p.1))
        .collect();
    let mut xa = Axis::new(pts.iter().map(|p| p.0), false);
    let mut ya = Axis::new(pts.iter().map(|p| p.1), false);
    // The colour bar spans the data exactly unless that range is degenerate.
    let (lo, hi) = extent(pts.iter().map(|p| p.2));
    let va = if lo < hi {
        Axis { lo, hi, log: false }
    } else {
        Axis::new(pts.iter().map(|p| p.2), false)
    };
    let root = BitMapBackend::new(path, FIELD_SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let body = if title.is_empty() {
        root.clone()
    } else {
        root.titled(title, font(24))?
    };
    let tick = font(16);
    let bar_w = va.label_width(&root, &tick) + 100;
    let (main, bar) = body.split_horizontally(body.dim_in_pixel().0.saturating_sub(bar_w));
    let (margin, x_area, y_area) = (12, 62, ya.label_width(&root, &tick) + 48);
    let build = |xr: Range<f64>, yr: Range<f64>| {
        ChartBuilder::on(&main)
            .margin(margin)
            .x_label_area_size(x_area)
            .y_label_area_size(y_area)
            .build_cartesian_2d(xr, yr)
    };
    // Equal aspect: measure the plotting area, then widen whichever data range
    // is relatively short so that both axes get the same pixels per metre.
    let (pw, ph) = build(0.0..1.0, 0.0..1.0)?.plotting_area().dim_in_pixel();
    let (pw, ph) = (pw.max(1) as f64, ph.max(1) as f64);
    let scale = (pw / (xa.hi - xa.lo)).min(ph / (ya.hi - ya.lo));
    for (a, pixels) in [(&mut xa, pw), (&mut ya, ph)] {
        let c = (a.lo + a.hi) / 2.0;
        (a.lo, a.hi) = (c - pixels / scale / 2.0, c + pixels / scale / 2.0);
    }
    let mut chart = build(xa.lo..xa.hi, ya.lo..ya.hi)?;
    let (fx, fy) = (|v: &f64| xa.label(*v), |v: &f64| ya.label(*v));
    let mut mesh = chart.configure_mesh();
    mesh.bold_line_style(BLACK.mix(0.08))
        .light_line_style(TRANSPARENT)
        .x_labels(9)
        .y_labels(9);
    mesh.label_style(tick.clone())
        .axis_desc_style(font(19))
        .x_desc(labels[0])
        .y_desc(labels[1]);
    mesh.x_label_formatter(&fx).y_label_formatter(&fy).draw()?;
    let colour = |v: f64| match v.is_finite() {
        true => viridis((v - va.lo) / (va.hi - va.lo)),
        false => RGBColor(150, 150, 150),
    };
    let s = spacing(&pts);
    if 0.5 * s * scale >= 3.0 {
        // Slightly over half the spacing closes most of the lattice gaps.
        let r = (0.55 * s * scale).min(40.0).round() as i32;
        let dot = |&(x, y, v): &(f64, f64, f64)| Circle::new((x, y), r, colour(v).filled());
        chart.draw_series(pts.iter().map(dot))?;
    } else {
        // At a few pixels per particle circles become blobs with holes between
        // them, whereas squares tile a lattice into a smooth field.
        let h = 0.5 * s.max(1.0 / scale);
        let square = |&(x, y, v): &(f64, f64, f64)| {
            Rectangle::new([(x - h, y - h), (x + h, y + h)], colour(v).filled())
        };
        chart.draw_series(pts.iter().map(square))?;
    }
    close_frame(&root, chart.plotting_area().get_pixel_range())?;
    // Colour bar: a narrow chart whose y axis is the value, labelled on the
    // right, spanning the same rows of pixels as the main plotting area.
    let mut cb = ChartBuilder::on(&bar)
        .margin_top(margin)
        .margin_bottom(margin + x_area)
        .margin_left(14)
        .margin_right(6)
        .set_label_area_size(LabelAreaPosition::Right, bar_w - 44)
        .build_cartesian_2d(0.0..1.0, va.lo..va.hi)?;
    let at = |t: f64| va.lo + t * (va.hi - va.lo);
    let band = |k: u32| {
        let (a, b) = (at(k as f64 / 256.0), at((k + 1) as f64 / 256.0));
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            viridis((k as f64 + 0.5) / 256.0).filled(),
        )
    };
    cb.draw_series((0..256).map(band))?;
    let mut mesh = cb.configure_mesh();
    mesh.disable_mesh()
        .disable_x_axis()
        .set_all_tick_mark_size(6)
        .y_labels(10)
        .label_style(tick);
    mesh.axis_desc_style(font(19))
        .y_desc(labels[2])
        .y_label_formatter(&|v| va.label(*v))
        .draw()?;
    cb.plotting_area()
        .draw(&Rectangle::new([(0.0, va.lo), (1.0, va.hi)], BLACK))?;
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Draws into a fresh folder (unique per process and test) and returns it,
    /// or None, with a note, when no font is installed.
    fn dir(name: &str) -> Option<std::path::PathBuf> {
        if let Err(e) = ensure_font() {
            eprintln!("skipping plot test {name}: {e}");
            return None;
        }
        let d = std::env::temp_dir().join(format!("sphcontact_plot_{}_{name}", std::process::id()));
        std::fs::create_dir_all(&d).ok().map(|_| d)
    }

    /// Checks the PNG signature and returns the size from the IHDR chunk.
    fn png_size(path: &Path) -> (u32, u32) {
        let b = std::fs::read(path).unwrap();
        assert_eq!(&b[..8], b"\x89PNG\r\n\x1a\n");
        let be = |i: usize| u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
        (be(16), be(20))
    }

    fn series(points: Vec<(f64, f64)>, style: Style, exact: bool) -> Series {
        Series {
            label: format!("{style:?}"),
            points,
            style,
            color: None,
            exact,
        }
    }

    #[test]
    fn line_plots_linear_and_log() {
        let Some(d) = dir("line") else { return };
        let mut fig = Figure::new("Damped sine", "time (µs)", "Δσ − σ₀ (MPa)");
        let f = |i: i32| (i as f64, (-i as f64 / 30.0).exp() * (i as f64 / 5.0).sin());
        fig.series
            .push(series((0..200).map(f).collect(), Style::Solid, true));
        fig.series
            .push(series((0..200).map(f).collect(), Style::Dashed, false));
        fig.series.push(series(
            (0..200).step_by(9).map(f).collect(),
            Style::Markers,
            false,
        ));
        line_plot(&d.join("lin.png"), &fig).unwrap();
        assert_eq!(png_size(&d.join("lin.png")), (1000, 650));
        (fig.log_x, fig.log_y, fig.width, fig.height) = (true, true, 640, 480);
        line_plot(&d.join("log.png"), &fig).unwrap();
        assert_eq!(png_size(&d.join("log.png")), (640, 480));
        std::fs::remove_dir_all(d).ok();
    }

    #[test]
    fn field_plot_of_many_particles() {
        let Some(d) = dir("field") else { return };
        let n = 40_000;
        let x: Vec<f64> = (0..n).map(|i| (i % 200) as f64 * 1e-3).collect();
        let y: Vec<f64> = (0..n).map(|i| (i / 200) as f64 * 5e-4).collect();
        let mut value: Vec<f64> = x
            .iter()
            .zip(&y)
            .map(|(x, y)| (x * 30.0).sin() * y)
            .collect();
        value[7] = f64::NAN;
        let start = std::time::Instant::now();
        let f = Field { x, y, value };
        field_plot(&d.join("f.png"), "σ field", "x (m)", "y (m)", "σ (Pa)", &f).unwrap();
        eprintln!("{n} particles drawn in {:?}", start.elapsed());
        assert_eq!(png_size(&d.join("f.png")), FIELD_SIZE);
        std::fs::remove_dir_all(d).ok();
    }

    /// Documented choice: unusable data gives an empty but valid plot, while
    /// inconsistent input and unwritable paths give errors; nothing panics.
    #[test]
    fn degenerate_input_is_not_a_panic() {
        let Some(d) = dir("degenerate") else { return };
        let mut fig = Figure::new("", "x", "y");
        line_plot(&d.join("none.png"), &fig).unwrap();
        let nan = vec![(f64::NAN, 1.0), (1.0, f64::INFINITY)];
        let huge = vec![(1.0, 1e-299), (2.0, 9e299), (f64::MAX, 1.0), (3.0, 1e-310)];
        let cases = [
            nan,
            huge,
            vec![(2.0, 3.0)],
            vec![(1.0, 5.0), (2.0, 5.0)],
            vec![(0.0, -1.0)],
        ];
        for (i, pts) in cases.into_iter().enumerate() {
            fig.series = vec![series(pts, Style::Solid, false)];
            for log in [false, true] {
                (fig.log_x, fig.log_y) = (log, log);
                line_plot(&d.join(format!("d{i}{log}.png")), &fig).unwrap();
                assert_eq!(png_size(&d.join(format!("d{i}{log}.png"))), (1000, 650));
            }
        }
        let plot = |name: &str, f: &Field| field_plot(&d.join(name), "", "x", "y", "v", f);
        plot("empty.png", &Field::default()).unwrap();
        plot(
            "one.png",
            &Field {
                x: vec![1.0],
                y: vec![2.0],
                value: vec![f64::NAN],
            },
        )
        .unwrap();
        let bad = Field {
            x: vec![1.0],
            ..Field::default()
        };
        assert!(matches!(plot("bad.png", &bad), Err(PlotError::Input(_))));
        let missing = line_plot(&d.join("no/such/dir.png"), &fig);
        assert!(matches!(missing, Err(PlotError::Draw(_))));
        fig.width = 0;
        assert!(matches!(
            line_plot(&d.join("w.png"), &fig),
            Err(PlotError::Input(_))
        ));
        std::fs::remove_dir_all(d).ok();
    }

    #[test]
    fn labels_ranges_and_colours() {
        assert_eq!(lin_label(-0.5, -1.0, 1.0), "−0.5");
        assert_eq!(lin_label(0.1 + 0.2, 0.0, 1.0), "0.3");
        assert_eq!(lin_label(1e-17, -1.0, 1.0), "0");
        assert_eq!(lin_label(5e-5, 0.0, 2e-4), "5×10⁻⁵");
        assert_eq!(log_label(1e-5, 3.0), "10⁻⁵");
        assert_eq!(log_label(0.099999999999, 3.0), "10⁻¹");
        assert_eq!(
            (log_label(3e-5, 3.0), log_label(2e3, 1.0)),
            ("".into(), "2×10³".into())
        );
        let a = Axis::new([4.0, 4.0].into_iter(), false);
        assert!(a.lo < 4.0 && a.hi > 4.0);
        let a = Axis::new([3e-5, 5e-5, -1.0, f64::NAN].into_iter(), true);
        assert_eq!((a.lo, a.hi), (1e-5, 1e-4));
        assert_eq!(
            (viridis(0.0), viridis(f64::NAN)),
            (rgb(VIRIDIS[0]), rgb(VIRIDIS[0]))
        );
        assert_eq!(viridis(1.0), rgb(VIRIDIS[10]));
        let pts = [(1.0, 1.0), (2.0, f64::NAN), (3.0, 3.0), (4.0, 4.0)];
        assert_eq!(runs(&pts, false, false).len(), 2);
    }
}
