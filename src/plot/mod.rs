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

mod axis;
mod field;
mod line;
mod style;
#[cfg(test)]
mod tests;

pub use field::{field_animation, field_plot};
pub use line::{line_plot, panel_plot};
pub use style::font_available;

use plotters::prelude::DrawingAreaErrorKind;

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
    /// The colour bar's span; none: the values' own.
    pub range: Option<(f64, f64)>,
    /// Particles marked with a black dot (the contact boundary, say);
    /// empty: none.
    pub marked: Vec<bool>,
    /// Text written at points (x, y, text): the bodies' names, say.
    pub labels: Vec<(f64, f64, String)>,
    /// The part of the plane drawn, `[x_min, x_max, y_min, y_max]`;
    /// `None`: all the particles.
    pub window: Option<[f64; 4]>,
}

/// Pixel size of field plots: a square-ish plotting area plus a colour bar.
pub const FIELD_SIZE: (u32, u32) = (1000, 800);
