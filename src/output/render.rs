//! Particle pictures of a finished run (`sphcontact render`,
//! docs/usage.md "Particle pictures"): each snapshot of the output
//! directory read back from its `.vtu` ([`read_vtu`]) and drawn as a PNG,
//! the particles as filled cells coloured by one field on one colour
//! scale for every frame.

use glam::DVec2;
use std::path::{Path, PathBuf};

use super::vtk::{COLLECTION, SNAPSHOT_DIR};
use crate::plot::{field_animation, field_plot, Field};

/// The fields `render` draws, with their units: the snapshot's arrays and
/// the velocity's components and magnitude.
pub const FIELDS: [(&str, &str); 16] = [
    ("density", "kg/m³"),
    ("pressure", "Pa"),
    ("stress_xx", "Pa"),
    ("stress_yy", "Pa"),
    ("stress_xy", "Pa"),
    ("von_mises", "Pa"),
    ("internal_energy", "J/kg"),
    ("plastic_strain", "–"),
    ("temperature", "K"),
    ("damage", "–"),
    ("failure_time", "s"),
    ("velocity_x", "m/s"),
    ("velocity_y", "m/s"),
    ("speed", "m/s"),
    ("body", "index"),
    ("boundary", "1 on the contact boundary"),
];

/// One snapshot read back: its time, the particles' positions and every
/// point array as reals (vectors split into `_x` and `_y`).
#[derive(Debug, Clone, Default)]
pub struct Snapshot {
    pub time: f64,
    pub x: Vec<DVec2>,
    pub arrays: Vec<(String, Vec<f64>)>,
}

impl Snapshot {
    /// The values of field `name` ([`FIELDS`]) at each particle, if the
    /// snapshot holds it.
    pub fn field(&self, name: &str) -> Option<Vec<f64>> {
        let get = |n: &str| {
            self.arrays
                .iter()
                .find(|(a, _)| a == n)
                .map(|(_, v)| v.clone())
        };
        if name == "speed" {
            let (vx, vy) = (get("velocity_x")?, get("velocity_y")?);
            return Some(vx.iter().zip(&vy).map(|(a, b)| a.hypot(*b)).collect());
        }
        get(name)
    }
}

/// An attribute's value in one XML tag.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let len = tag[start..].find('"')?;
    Some(&tag[start..start + len])
}

/// Reads a snapshot this solver wrote ([`super::vtk::write_vtu`]): the
/// XML header's arrays and their offsets into the raw appended block
/// (each a UInt64 byte count, then little-endian values).
pub fn read_vtu(path: &Path) -> Result<Snapshot, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let bad = |what: &str| format!("{}: {what}", path.display());
    let marker = b"<AppendedData encoding=\"raw\">";
    let at = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .ok_or_else(|| bad("no raw appended block (not a snapshot of this solver)"))?;
    let head = std::str::from_utf8(&bytes[..at]).map_err(|_| bad("header is not text"))?;
    let underscore = bytes[at..]
        .iter()
        .position(|&b| b == b'_')
        .ok_or_else(|| bad("appended block without its '_'"))?;
    let data = &bytes[at + underscore + 1..];
    let mut snap = Snapshot::default();
    let mut in_points = false;
    for line in head.lines().map(str::trim) {
        if line.starts_with("<Points>") {
            in_points = true;
        } else if line.starts_with("</Points>") {
            in_points = false;
        }
        if !line.starts_with("<DataArray") {
            continue;
        }
        let name = attr(line, "Name").unwrap_or("");
        if name == "TimeValue" {
            let v = line
                .split('>')
                .nth(1)
                .and_then(|s| s.split('<').next())
                .and_then(|s| s.trim().parse().ok())
                .ok_or_else(|| bad("unreadable TimeValue"))?;
            snap.time = v;
            continue;
        }
        let Some(offset) = attr(line, "offset").and_then(|o| o.parse::<usize>().ok()) else {
            continue;
        };
        let ty = attr(line, "type").unwrap_or("");
        let comps: usize = attr(line, "NumberOfComponents")
            .and_then(|c| c.parse().ok())
            .unwrap_or(1);
        let count = data
            .get(offset..offset + 8)
            .map(|b| u64::from_le_bytes(b.try_into().expect("8")) as usize)
            .ok_or_else(|| bad("an array lies past the end of the file"))?;
        let raw = data
            .get(offset + 8..offset + 8 + count)
            .ok_or_else(|| bad("an array lies past the end of the file"))?;
        let values: Vec<f64> = match ty {
            "Float64" => raw
                .chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().expect("8")))
                .collect(),
            "Int32" => raw
                .chunks_exact(4)
                .map(|c| i32::from_le_bytes(c.try_into().expect("4")) as f64)
                .collect(),
            "UInt8" => raw.iter().map(|&b| b as f64).collect(),
            // The cells' arrays (Int64 connectivity and offsets) are not
            // drawn.
            _ => continue,
        };
        if in_points {
            snap.x = values
                .chunks_exact(3)
                .map(|c| DVec2::new(c[0], c[1]))
                .collect();
        } else if comps == 3 {
            for (k, axis) in ["x", "y"].iter().enumerate() {
                let v = values.chunks_exact(3).map(|c| c[k]).collect();
                snap.arrays.push((format!("{name}_{axis}"), v));
            }
        } else if comps == 1 {
            snap.arrays.push((name.to_string(), values));
        }
    }
    if snap.x.is_empty() {
        return Err(bad("no points"));
    }
    Ok(snap)
}

/// The snapshot files of an output directory, in order.
pub fn snapshot_files(out: &Path) -> Result<Vec<PathBuf>, String> {
    let dir = out.join(SNAPSHOT_DIR);
    let listing = std::fs::read_dir(&dir).map_err(|e| {
        format!(
            "{}: {e} (the run wrote no snapshots: set output.snapshot_interval)",
            dir.display()
        )
    })?;
    let mut files: Vec<PathBuf> = listing
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("snapshot_") && n.ends_with(".vtu"))
        })
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(format!(
            "{} holds no snapshot (see {})",
            dir.display(),
            out.join(COLLECTION).display()
        ));
    }
    Ok(files)
}

/// A time in the unit that reads best.
fn time_label(t: f64) -> String {
    let a = t.abs();
    if a == 0.0 {
        "t = 0".into()
    } else if a < 1e-6 {
        format!("t = {:.4} ns", t * 1e9)
    } else if a < 1e-3 {
        format!("t = {:.4} µs", t * 1e6)
    } else if a < 1.0 {
        format!("t = {:.4} ms", t * 1e3)
    } else {
        format!("t = {t:.4} s")
    }
}

/// Milliseconds between an animation's frames.
pub const GIF_DELAY_MS: u32 = 100;

/// How the frames are drawn: what goes over the particles, and which
/// part of the plane they show.
#[derive(Debug, Clone, Default)]
pub struct Drawing {
    /// The bodies' names, in the scene's order, each written on its body;
    /// `None`: no names.
    pub names: Option<Vec<String>>,
    /// A black dot on each particle of the contact boundary.
    pub boundary: bool,
    /// The part of the plane shown, `[x_min, x_max, y_min, y_max]` (m);
    /// `None`: all the particles.
    pub window: Option<[f64; 4]>,
}

impl Drawing {
    /// The names a finished run's `summary.json` gives its bodies (none
    /// when it cannot be read: a run that was stopped).
    pub fn names_of_run(out: &Path) -> Option<Vec<String>> {
        let text = std::fs::read_to_string(out.join("summary.json")).ok()?;
        let json: serde_json::Value = serde_json::from_str(&text).ok()?;
        json["bodies"]
            .as_array()?
            .iter()
            .map(|b| b["name"].as_str().map(str::to_string))
            .collect()
    }
}

/// Each body's label: its name at the particle nearest its particles'
/// centroid (on the body, whatever its shape).
fn labels(snap: &Snapshot, names: &[String]) -> Vec<(f64, f64, String)> {
    let Some(body) = snap.field("body") else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let mine: Vec<DVec2> = (0..snap.x.len())
            .filter(|&i| body[i] == k as f64 && snap.x[i].is_finite())
            .map(|i| snap.x[i])
            .collect();
        if mine.is_empty() {
            continue;
        }
        let c = mine.iter().sum::<DVec2>() / mine.len() as f64;
        let at = mine
            .iter()
            .min_by(|a, b| a.distance_squared(c).total_cmp(&b.distance_squared(c)))
            .expect("a body with particles");
        out.push((at.x, at.y, name.clone()));
    }
    out
}

/// Draws field `name` of every snapshot in `out` into `out/frames/`
/// (`<name>_NNNNNN.png`, and with `gif` all of them as `<name>.gif`), one
/// colour scale for all of them: `range`, or the field's least and
/// greatest over every snapshot, with `drawing` drawn over the
/// particles. Returns the files written.
pub fn render(
    out: &Path,
    name: &str,
    range: Option<(f64, f64)>,
    gif: bool,
    drawing: &Drawing,
) -> Result<Vec<PathBuf>, String> {
    let Some(&(_, unit)) = FIELDS.iter().find(|f| f.0 == name) else {
        let known: Vec<&str> = FIELDS.iter().map(|f| f.0).collect();
        return Err(format!(
            "unknown field '{name}' (known: {})",
            known.join(", ")
        ));
    };
    if let Some(w) = drawing.window {
        if !(w.iter().all(|v| v.is_finite()) && w[0] < w[1] && w[2] < w[3]) {
            return Err(format!(
                "--window {} {} {} {}: needs finite values, each minimum below its maximum",
                w[0], w[1], w[2], w[3]
            ));
        }
    }
    if let Some((a, b)) = range {
        if !(a.is_finite() && b.is_finite() && a < b) {
            return Err(format!(
                "--range {a} {b}: needs two finite values, the first below the second"
            ));
        }
    }
    let files = snapshot_files(out)?;
    let mut frames = Vec::with_capacity(files.len());
    for f in &files {
        let snap = read_vtu(f)?;
        let v = snap.field(name).ok_or_else(|| {
            format!(
                "{}: no field '{name}' (a history field is written only when a material carries one)",
                f.display()
            )
        })?;
        frames.push((snap, v));
    }
    let range = range.unwrap_or_else(|| {
        frames
            .iter()
            .flat_map(|(_, v)| v.iter().copied())
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
    });
    let dir = out.join("frames");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let pictures: Vec<(String, Field)> = frames
        .into_iter()
        .map(|(snap, v)| {
            let marked = match drawing.boundary {
                true => snap
                    .field("boundary")
                    .map(|b| b.iter().map(|&b| b != 0.0).collect())
                    .unwrap_or_default(),
                false => Vec::new(),
            };
            let labels = drawing
                .names
                .as_deref()
                .map(|n| labels(&snap, n))
                .unwrap_or_default();
            let field = Field {
                x: snap.x.iter().map(|p| p.x).collect(),
                y: snap.x.iter().map(|p| p.y).collect(),
                value: v,
                range: range.0.is_finite().then_some(range),
                marked,
                labels,
                window: drawing.window,
            };
            (format!("{name}, {}", time_label(snap.time)), field)
        })
        .collect();
    let value_label = format!("{name} ({unit})");
    let mut written = Vec::with_capacity(pictures.len() + 1);
    for (k, (title, field)) in pictures.iter().enumerate() {
        let path = dir.join(format!("{name}_{k:06}.png"));
        field_plot(&path, title, "x (m)", "y (m)", &value_label, field)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path);
    }
    if gif {
        let path = dir.join(format!("{name}.gif"));
        field_animation(
            &path,
            &pictures,
            ["x (m)", "y (m)", &value_label],
            GIF_DELAY_MS,
        )
        .map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path);
    }
    Ok(written)
}
