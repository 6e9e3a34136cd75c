//! Shared styling: the font (found once), the colour palettes, text styles,
//! and the guard every drawing runs inside.

use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::path::Path;
use std::sync::OnceLock;

use super::PlotError;

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
pub(super) fn ensure_font() -> Result<(), PlotError> {
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
pub(super) const PALETTE: [u32; 8] = [
    0x0072B2, 0xD55E00, 0x009E73, 0xCC79A7, 0xE69F00, 0x56B4E9, 0x8C5628, 0x787878,
];

/// Viridis at 11 evenly spaced stops; linear interpolation between them is
/// visually indistinguishable from the full 256-entry table.
pub(super) const VIRIDIS: [u32; 11] = [
    0x440154, 0x482475, 0x414487, 0x355F8D, 0x2A788E, 0x21918C, 0x22A884, 0x44BF70, 0x7AD151,
    0xBDDF26, 0xFDE725,
];

pub(super) fn rgb(c: u32) -> RGBColor {
    RGBColor((c >> 16) as u8, (c >> 8) as u8, c as u8)
}

pub(super) fn viridis(t: f64) -> RGBColor {
    let s = 10.0 * if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let i = (s as usize).min(9);
    let (a, b, f) = (rgb(VIRIDIS[i]), rgb(VIRIDIS[i + 1]), s - i as f64);
    let mix = |p: u8, q: u8| (p as f64 + (q as f64 - p as f64) * f).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

pub(super) fn font(size: u32) -> TextStyle<'static> {
    (FAMILY, size).into_font().color(&BLACK)
}

/// Checks the font, then runs the drawing and turns a panic inside plotters
/// into an error: a figure must never take down a validation run.
pub(super) fn guarded(f: impl FnOnce() -> Result<(), PlotError>) -> Result<(), PlotError> {
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
