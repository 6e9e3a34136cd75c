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
