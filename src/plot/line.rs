//! Line plots: one figure per PNG, or several stacked as panels.

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::path::Path;

use super::axis::{close_frame, runs, Area, Axis};
use super::style::{font, guarded, rgb, PALETTE};
use super::{Figure, PlotError, Series, Style};

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
