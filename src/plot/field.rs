//! Particle field plots: a scatter coloured by value, at equal aspect, with
//! a colour bar.

use plotters::prelude::*;
use std::ops::Range;
use std::path::Path;

use super::axis::{close_frame, extent, usable, Axis};
use super::style::{font, guarded, viridis};
use super::{Field, PlotError, FIELD_SIZE};

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
    check_lengths(field)?;
    guarded(|| {
        let root = BitMapBackend::new(path, FIELD_SIZE).into_drawing_area();
        draw_field(&root, title, [x_label, y_label, value_label], field)
    })
}

/// [`field_plot`]'s pictures of `frames` (each a title and a field) as
/// one animated GIF, `delay_ms` between frames.
pub fn field_animation(
    path: &Path,
    frames: &[(String, Field)],
    [x_label, y_label, value_label]: [&str; 3],
    delay_ms: u32,
) -> Result<(), PlotError> {
    for (_, f) in frames {
        check_lengths(f)?;
    }
    guarded(|| {
        let root = BitMapBackend::gif(path, FIELD_SIZE, delay_ms)
            .map_err(|e| PlotError::Draw(e.to_string()))?
            .into_drawing_area();
        for (title, f) in frames {
            draw_field(&root, title, [x_label, y_label, value_label], f)?;
        }
        Ok(())
    })
}

fn check_lengths(field: &Field) -> Result<(), PlotError> {
    let (n, ny, nv) = (field.x.len(), field.y.len(), field.value.len());
    if ny != n || nv != n {
        let msg = format!("field lengths differ: x {n}, y {ny}, value {nv}");
        return Err(PlotError::Input(msg));
    }
    Ok(())
}

/// Draws one picture on `root` and presents it (a PNG's file, a GIF's
/// next frame).
fn draw_field(
    root: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    title: &str,
    labels: [&str; 3],
    f: &Field,
) -> Result<(), PlotError> {
    let shown = |x: f64, y: f64| {
        usable(x)
            && usable(y)
            && f.window
                .is_none_or(|w| x >= w[0] && x <= w[1] && y >= w[2] && y <= w[3])
    };
    let pts: Vec<(f64, f64, f64)> = (0..f.x.len())
        .map(|i| (f.x[i], f.y[i], f.value[i]))
        .filter(|p| shown(p.0, p.1))
        .collect();
    let (mut xa, mut ya) = match f.window {
        Some(w) => (
            Axis::new([w[0], w[1]].into_iter(), false),
            Axis::new([w[2], w[3]].into_iter(), false),
        ),
        None => (
            Axis::new(pts.iter().map(|p| p.0), false),
            Axis::new(pts.iter().map(|p| p.1), false),
        ),
    };
    // The colour bar spans the data exactly unless that range is degenerate.
    let (lo, hi) = f.range.unwrap_or_else(|| extent(pts.iter().map(|p| p.2)));
    let va = if lo < hi {
        Axis { lo, hi, log: false }
    } else {
        Axis::new(pts.iter().map(|p| p.2), false)
    };
    root.fill(&WHITE)?;
    let body = if title.is_empty() {
        root.clone()
    } else {
        root.titled(title, font(24))?
    };
    let tick = font(16);
    let bar_w = va.label_width(root, &tick) + 100;
    let (main, bar) = body.split_horizontally(body.dim_in_pixel().0.saturating_sub(bar_w));
    let (margin, x_area, y_area) = (12, 62, ya.label_width(root, &tick) + 48);
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
        true => viridis(((v - va.lo) / (va.hi - va.lo)).clamp(0.0, 1.0)),
        false => RGBColor(150, 150, 150),
    };
    // Each particle a filled cell of its spacing (at least a pixel), 1.4
    // times as wide: cells tile a square lattice, and the overlap closes
    // the pinholes where a polar lattice's rings meet (1.2 left some on
    // the paper's disks at R/Δx = 50).
    let s = spacing(&pts);
    let h = 0.7 * s.max(1.0 / scale);
    let square = |&(x, y, v): &(f64, f64, f64)| {
        Rectangle::new([(x - h, y - h), (x + h, y + h)], colour(v).filled())
    };
    chart.draw_series(pts.iter().map(square))?;
    // Marks: a dot a third of a cell wide, at least 3 pixels.
    let dot = (0.35 * s).max(1.5 / scale);
    let marked = (0..f.marked.len().min(f.x.len()))
        .filter(|&i| f.marked[i] && shown(f.x[i], f.y[i]))
        .map(|i| {
            let (x, y) = (f.x[i], f.y[i]);
            Rectangle::new([(x - dot, y - dot), (x + dot, y + dot)], BLACK.filled())
        });
    chart.draw_series(marked)?;
    // Labels on a pale box, centred on their points.
    let text = font(18);
    for (x, y, label) in f.labels.iter().filter(|l| shown(l.0, l.1)) {
        let (w, h) = root.estimate_text_size(label, &text)?;
        let (w, h) = (w as i32, h as i32);
        let tag = EmptyElement::at((*x, *y))
            + Rectangle::new(
                [(-w / 2 - 5, -h / 2 - 3), (w / 2 + 5, h / 2 + 3)],
                WHITE.mix(0.85).filled(),
            )
            + Rectangle::new([(-w / 2 - 5, -h / 2 - 3), (w / 2 + 5, h / 2 + 3)], BLACK)
            + Text::new(label.clone(), (-w / 2, -h / 2), text.clone());
        chart.plotting_area().draw(&tag)?;
    }
    close_frame(root, chart.plotting_area().get_pixel_range())?;
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
