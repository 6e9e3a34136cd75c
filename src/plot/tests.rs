//! Unit tests of the plots: PNGs drawn from good and degenerate input, and
//! the labels, ranges and colours behind them.

use super::axis::{lin_label, log_label, runs, Axis};
use super::style::{ensure_font, rgb, viridis, VIRIDIS};
use super::*;
use std::path::Path;

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
    let f = Field {
        x,
        y,
        value,
        range: None,
        ..Field::default()
    };
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
            range: None,
            ..Field::default()
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

/// The RGB pixels of a PNG, row by row.
fn pixels(path: &Path) -> (usize, Vec<[u8; 3]>) {
    let decoder = png::Decoder::new(std::fs::File::open(path).unwrap());
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let px = buf[..info.buffer_size()]
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    (info.width as usize, px)
}

/// Every particle's cell is painted: a polar disk at R/Δx = 50 (where
/// rings meet at angles) and a square-lattice block draw as solid
/// figures, without a background pixel inside; marks and labels then go
/// on top.
#[test]
fn field_cells_leave_no_gaps() {
    let Some(d) = dir("gaps") else { return };
    let (mut x, mut y) = (Vec::new(), Vec::new());
    let rings = 50;
    let dr = 1.0 / rings as f64;
    for k in 0..rings {
        let r = (k as f64 + 0.5) * dr;
        let n = (std::f64::consts::TAU * r / dr).round().max(1.0) as usize;
        for j in 0..n {
            let a = std::f64::consts::TAU * j as f64 / n as f64;
            x.push(r * a.cos());
            y.push(r * a.sin());
        }
    }
    let disk = x.len();
    for j in 0..50 {
        for i in 0..100 {
            x.push(1.5 + (i as f64 + 0.5) * dr);
            y.push(-0.5 + (j as f64 + 0.5) * dr);
        }
    }
    let mut f = Field {
        value: vec![0.5; x.len()],
        x,
        y,
        range: Some((0.0, 1.0)),
        ..Field::default()
    };
    let plain = d.join("plain.png");
    field_plot(&plain, "gaps", "x", "y", "v", &f).unwrap();
    let (w, px) = pixels(&plain);
    let paint = viridis(0.5);
    let painted = |p: [u8; 3]| p == [paint.0, paint.1, paint.2];
    // The figures' pixel boxes: the disk left of the gap, the block right.
    let boxes = |keep: &dyn Fn(usize) -> bool| {
        let mut b = (usize::MAX, usize::MAX, 0, 0);
        for (i, &p) in px.iter().enumerate() {
            let (c, r) = (i % w, i / w);
            if painted(p) && keep(c) {
                b = (b.0.min(c), b.1.min(r), b.2.max(c), b.3.max(r));
            }
        }
        b
    };
    let mut cols: Vec<usize> = (0..px.len())
        .filter(|&i| painted(px[i]))
        .map(|i| i % w)
        .collect();
    cols.sort_unstable();
    cols.dedup();
    // Column gaps: between the disk and the block, and before the colour
    // bar (drawn in the same colours).
    let gaps: Vec<usize> = cols
        .windows(2)
        .filter(|c| c[1] > c[0] + 5)
        .map(|c| c[1])
        .collect();
    let (split, bar) = (gaps[0], gaps[1]);
    let (l, t, r, b) = boxes(&|c| c < split);
    let (cx, cy) = ((l + r) as f64 / 2.0, (t + b) as f64 / 2.0);
    let radius = (r - l) as f64 / 2.0;
    assert!(radius > 100.0, "{radius}");
    assert!(((b - t) as f64 / 2.0 - radius).abs() <= 1.5, "equal aspect");
    let mut holes = 0;
    for row in t..=b {
        for col in l..=r {
            let d = ((col as f64 - cx).powi(2) + (row as f64 - cy).powi(2)).sqrt();
            if d < radius - 2.0 && !painted(px[row * w + col]) {
                holes += 1;
            }
        }
    }
    assert_eq!(holes, 0, "background pixels inside the disk");
    let (l, t, r, b) = boxes(&|c| c >= split && c < bar);
    assert!(((r - l) as f64 / (b - t) as f64 - 2.0).abs() < 0.03);
    let inside = (t..=b).flat_map(|row| (l..=r).map(move |col| row * w + col));
    assert!(inside.clone().all(|i| painted(px[i])), "gaps in the block");
    // Marks on the disk's outer ring and a label: black dots of at least
    // 3 × 3 pixels each, and the label's box.
    let outer = (disk - (std::f64::consts::TAU * (rings as f64 - 0.5)).round() as usize)..disk;
    f.marked = (0..f.x.len()).map(|i| outer.contains(&i)).collect();
    f.labels = vec![(0.0, 0.0, "disk".into())];
    let over = d.join("over.png");
    field_plot(&over, "gaps", "x", "y", "v", &f).unwrap();
    let (_, px2) = pixels(&over);
    let black = |v: &[[u8; 3]]| v.iter().filter(|p| **p == [0, 0, 0]).count();
    assert!(
        black(&px2) >= black(&px) + 9 * outer.len(),
        "{} black pixels, {} before, {} marks",
        black(&px2),
        black(&px),
        outer.len()
    );
    let at = |v: &[[u8; 3]]| v[cy as usize * w + cx as usize];
    assert!(
        painted(at(&px)) && !painted(at(&px2)),
        "the label covers the centre"
    );
    std::fs::remove_dir_all(d).ok();
}
