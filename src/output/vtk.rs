//! Particle snapshots (docs/scenes.md, "Snapshots"): one VTK XML
//! UnstructuredGrid file (`.vtu`) per snapshot in `<out>/snapshots/`, and
//! `<out>/snapshots.pvd`, the ParaView collection that lists them with
//! their times (its file paths are relative to the output directory).
//!
//! Each `.vtu` holds one VTK_VERTEX cell per particle, the positions as the
//! points (z = 0), and as point data every particle quantity of docs/scenes.md
//! (`velocity` as a 3-vector; `density`, `pressure`, `stress_xx`,
//! `stress_yy`, `stress_xy`, `von_mises`, `internal_energy`), `body` (the
//! body's index), `boundary` (1 on the contact boundary set) and `normal`
//! (outward unit normal on boundary particles, zero elsewhere). The field
//! data holds `TimeValue` (ParaView's time key) and one `body:<name>` array
//! per body with that body's index.
//!
//! The arrays are raw little-endian binary in one `AppendedData` block
//! (each array: a UInt64 byte count, then the values), Float64 for the
//! real quantities: [`BYTES_PER_PARTICLE`] a particle, written at disk speed,
//! where ASCII would take three times the space and much longer to print.

use glam::DVec2;
use rayon::prelude::*;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::write_atomic;
use crate::error::RunError;
use crate::model::{Model, State};
use crate::probe::particle_value;
use crate::scene::ParticleQuantity;

/// Folder of the `.vtu` files, inside the output directory.
pub const SNAPSHOT_DIR: &str = "snapshots";
/// The collection file, in the output directory.
pub const COLLECTION: &str = "snapshots.pvd";

/// Bytes a particle takes in a `.vtu` file, the XML header and the arrays'
/// byte counts aside: position, velocity and normal (3 × Float64 each),
/// the seven scalars (Float64), `body` (Int32), `boundary` (UInt8), and the
/// vertex cell's connectivity and offset (Int64 each) and type (UInt8).
pub const BYTES_PER_PARTICLE: u64 = 3 * 24 + 7 * 8 + 4 + 1 + 2 * 8 + 1;

/// What one snapshot writes: the particles' constants and state, and the
/// boundary set with its normals (computed at the same state).
pub struct Fields<'a> {
    pub model: &'a Model,
    pub state: &'a State,
    pub normal: &'a [DVec2],
    pub boundary: &'a [bool],
}

/// The scalar point-data arrays, in file order, with the probe quantity
/// each one is.
const SCALARS: [(&str, ParticleQuantity); 7] = [
    ("density", ParticleQuantity::Density),
    ("pressure", ParticleQuantity::Pressure),
    ("stress_xx", ParticleQuantity::StressXx),
    ("stress_yy", ParticleQuantity::StressYy),
    ("stress_xy", ParticleQuantity::StressXy),
    ("von_mises", ParticleQuantity::VonMises),
    ("internal_energy", ParticleQuantity::InternalEnergy),
];

/// The plastic history's arrays, written when the scene's materials carry
/// one (8 bytes a particle each beyond [`BYTES_PER_PARTICLE`]).
const HISTORY: [(&str, ParticleQuantity); 4] = [
    ("plastic_strain", ParticleQuantity::PlasticStrain),
    ("temperature", ParticleQuantity::Temperature),
    ("damage", ParticleQuantity::Damage),
    ("failure_time", ParticleQuantity::FailureTime),
];

/// One appended array: its XML description and a way to make its bytes
/// when its turn to be written comes (so only one array is in memory).
struct Array<'a> {
    name: &'a str,
    vtk_type: &'static str,
    components: usize,
    bytes_per_value: usize,
    make: Box<dyn Fn() -> Vec<u8> + 'a>,
}

/// Little-endian bytes of `values`, `W` bytes each, into a buffer sized
/// once (a million-particle array is megabytes: no regrowing).
fn le_bytes<T, const W: usize>(values: &[T], bytes: impl Fn(&T) -> [u8; W]) -> Vec<u8> {
    let mut out = Vec::with_capacity(W * values.len());
    for v in values {
        out.extend_from_slice(&bytes(v));
    }
    out
}

/// 3-component Float64 bytes of 2-D vectors (z = 0).
fn vec3_bytes(v: &[DVec2]) -> Vec<u8> {
    le_bytes(v, |p| {
        let mut b = [0u8; 24];
        b[..8].copy_from_slice(&p.x.to_le_bytes());
        b[8..16].copy_from_slice(&p.y.to_le_bytes());
        b
    })
}

/// Escape text for an XML attribute value. Control characters, which XML
/// 1.0 cannot carry even escaped, become `?`.
fn xml_attr(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r') => out.push('?'),
            c => out.push(c),
        }
    }
    out
}

/// Write one snapshot as a `.vtu` file at `path` (through a temporary file
/// and a rename). Returns the file's size in bytes.
pub fn write_vtu(path: &Path, time: f64, f: &Fields) -> Result<u64, RunError> {
    let (model, st) = (f.model, f.state);
    let n = model.len();
    let point_data = point_arrays(f);
    let points = Array {
        name: "Points",
        vtk_type: "Float64",
        components: 3,
        bytes_per_value: 8,
        make: Box::new(move || vec3_bytes(&st.x)),
    };
    let cells = cell_arrays(n);
    let xml = vtu_header(time, model, &point_data, &points, &cells);
    write_streamed(path, |w| {
        w.write_all(xml.as_bytes())?;
        for a in point_data.iter().chain([&points]).chain(&cells) {
            let bytes = (a.make)();
            debug_assert_eq!(bytes.len(), n * a.components * a.bytes_per_value);
            w.write_all(&(bytes.len() as u64).to_le_bytes())?;
            w.write_all(&bytes)?;
        }
        w.write_all(b"\n  </AppendedData>\n</VTKFile>\n")
    })
}

/// The point-data arrays of a snapshot of `f`, in file order.
fn point_arrays<'a>(f: &Fields<'a>) -> Vec<Array<'a>> {
    let (model, st) = (f.model, f.state);
    let n = model.len();
    let mut point_data: Vec<Array> = vec![Array {
        name: "velocity",
        vtk_type: "Float64",
        components: 3,
        bytes_per_value: 8,
        make: Box::new(move || vec3_bytes(&st.v)),
    }];
    let history = if model.history { &HISTORY[..] } else { &[] };
    for &(name, q) in SCALARS.iter().chain(history) {
        point_data.push(Array {
            name,
            vtk_type: "Float64",
            components: 1,
            bytes_per_value: 8,
            make: Box::new(move || {
                let v: Vec<f64> = (0..n)
                    .into_par_iter()
                    .map(|i| particle_value(model, st, i, q))
                    .collect();
                le_bytes(&v, |x| x.to_le_bytes())
            }),
        });
    }
    point_data.push(Array {
        name: "body",
        vtk_type: "Int32",
        components: 1,
        bytes_per_value: 4,
        make: Box::new(move || le_bytes(&model.body, |&b| (b as i32).to_le_bytes())),
    });
    let boundary = f.boundary;
    point_data.push(Array {
        name: "boundary",
        vtk_type: "UInt8",
        components: 1,
        bytes_per_value: 1,
        make: Box::new(move || le_bytes(boundary, |&b| [b as u8])),
    });
    let normal = f.normal;
    point_data.push(Array {
        name: "normal",
        vtk_type: "Float64",
        components: 3,
        bytes_per_value: 8,
        make: Box::new(move || vec3_bytes(normal)),
    });
    point_data
}

/// The cells of `n` particles: one vertex cell each, cell k is point k.
fn cell_arrays<'a>(n: usize) -> Vec<Array<'a>> {
    vec![
        Array {
            name: "connectivity",
            vtk_type: "Int64",
            components: 1,
            bytes_per_value: 8,
            make: Box::new(move || {
                let ids: Vec<i64> = (0..n as i64).collect();
                le_bytes(&ids, |k| k.to_le_bytes())
            }),
        },
        Array {
            name: "offsets",
            vtk_type: "Int64",
            components: 1,
            bytes_per_value: 8,
            make: Box::new(move || {
                let ends: Vec<i64> = (1..=n as i64).collect();
                le_bytes(&ends, |k| k.to_le_bytes())
            }),
        },
        Array {
            name: "types",
            vtk_type: "UInt8",
            components: 1,
            bytes_per_value: 1,
            // VTK_VERTEX
            make: Box::new(move || vec![1u8; n]),
        },
    ]
}

/// The XML before the appended block at `time`, each array described
/// with its offset into that block.
fn vtu_header(
    time: f64,
    model: &Model,
    point_data: &[Array],
    points: &Array,
    cells: &[Array],
) -> String {
    let n = model.len();
    // The header, with each array's offset into the appended block.
    let mut offset = 0u64;
    let mut describe = |a: &Array, xml: &mut String| {
        let size = (n * a.components * a.bytes_per_value) as u64;
        let comps = if a.components > 1 {
            format!(" NumberOfComponents=\"{}\"", a.components)
        } else {
            String::new()
        };
        xml.push_str(&format!(
            "        <DataArray type=\"{}\" Name=\"{}\"{comps} format=\"appended\" offset=\"{offset}\"/>\n",
            a.vtk_type, a.name
        ));
        offset += 8 + size;
    };
    let mut xml = String::from(
        "<?xml version=\"1.0\"?>\n\
         <VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n\
         \x20 <UnstructuredGrid>\n\
         \x20   <FieldData>\n",
    );
    xml.push_str(&format!(
        "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{time:e}</DataArray>\n"
    ));
    for (k, b) in model.bodies.iter().enumerate() {
        xml.push_str(&format!(
            "      <DataArray type=\"Int32\" Name=\"body:{}\" NumberOfTuples=\"1\" format=\"ascii\">{k}</DataArray>\n",
            xml_attr(&b.name)
        ));
    }
    xml.push_str("    </FieldData>\n");
    xml.push_str(&format!(
        "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{n}\">\n      <PointData Scalars=\"density\" Vectors=\"velocity\">\n"
    ));
    for a in point_data {
        describe(a, &mut xml);
    }
    xml.push_str("      </PointData>\n      <Points>\n");
    describe(points, &mut xml);
    xml.push_str("      </Points>\n      <Cells>\n");
    for a in cells {
        describe(a, &mut xml);
    }
    xml.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _");

    xml
}

/// Write a file through `fill`, atomically as [`write_atomic`] does (a
/// temporary file in the same directory, then a rename), but streamed:
/// a snapshot of millions of particles is never held whole in memory.
fn write_streamed(
    path: &Path,
    fill: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> Result<u64, RunError> {
    let name = path
        .file_name()
        .map_or("out".into(), |n| n.to_string_lossy().into_owned());
    let tmp = path.with_file_name(format!(".{name}.tmp"));
    let file = File::create(&tmp).map_err(|e| RunError::io(&tmp, e))?;
    let mut w = BufWriter::with_capacity(1 << 20, file);
    let written = fill(&mut w)
        .and_then(|_| w.flush())
        .and_then(|_| w.get_ref().metadata().map(|m| m.len()));
    let size = match written {
        Ok(s) => s,
        Err(e) => {
            drop(w);
            // The half-written temporary is of no use to anyone.
            let _ = std::fs::remove_file(&tmp);
            return Err(RunError::io(&tmp, e));
        }
    };
    drop(w);
    std::fs::rename(&tmp, path).map_err(|e| RunError::io(path, e))?;
    Ok(size)
}

/// The `.pvd` collection text for `(time, file)` entries, files relative
/// to the collection's folder.
pub fn collection_text(entries: &[(f64, String)]) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n\
         <VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n\
         \x20 <Collection>\n",
    );
    for (t, file) in entries {
        s.push_str(&format!(
            "    <DataSet timestep=\"{t:e}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
            xml_attr(file)
        ));
    }
    s.push_str("  </Collection>\n</VTKFile>\n");
    s
}

/// The snapshots of one run: writes each `.vtu` and rewrites the `.pvd`
/// after it, so a run that stops early leaves a valid collection of what
/// it wrote.
#[derive(Debug)]
pub struct SnapshotSeries {
    out: PathBuf,
    entries: Vec<(f64, String)>,
    /// Bytes and wall seconds spent writing, over all snapshots (the run
    /// adds the time it took to gather each snapshot's fields).
    pub bytes: u64,
    pub seconds: f64,
}

impl SnapshotSeries {
    /// Make `<out>/snapshots/` for a series that has written `entries` so
    /// far (none for a fresh run; a resumed run's, up to its checkpoint).
    /// Files under this writer's names that the list does not hold (an
    /// earlier run's, or written after the checkpoint by the run that
    /// stopped) are removed, so the folder holds exactly what the
    /// collection lists; the collection is written at once (the old one, if
    /// any, no longer describes the folder).
    pub fn open(out: &Path, entries: Vec<(f64, String)>) -> Result<Self, RunError> {
        let dir = out.join(SNAPSHOT_DIR);
        std::fs::create_dir_all(&dir).map_err(|e| RunError::io(&dir, e))?;
        let listing = std::fs::read_dir(&dir).map_err(|e| RunError::io(&dir, e))?;
        for entry in listing.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            let listed = entries
                .iter()
                .any(|(_, f)| f.rsplit('/').next() == Some(name.as_str()));
            if name.starts_with("snapshot_") && name.ends_with(".vtu") && !listed {
                let p = entry.path();
                std::fs::remove_file(&p).map_err(|e| RunError::io(&p, e))?;
            }
        }
        let series = Self {
            out: out.to_path_buf(),
            entries,
            bytes: 0,
            seconds: 0.0,
        };
        series.write_collection()?;
        Ok(series)
    }

    /// Snapshots written so far.
    pub fn count(&self) -> usize {
        self.entries.len()
    }

    /// The `(time, file)` entries written so far, files relative to the
    /// output directory.
    pub fn entries(&self) -> &[(f64, String)] {
        &self.entries
    }

    /// Write the snapshot of `f` at `time`, then the updated collection.
    pub fn write(&mut self, time: f64, f: &Fields) -> Result<(), RunError> {
        let start = Instant::now();
        let file = format!("{SNAPSHOT_DIR}/snapshot_{:06}.vtu", self.entries.len());
        self.bytes += write_vtu(&self.out.join(&file), time, f)?;
        self.entries.push((time, file));
        self.write_collection()?;
        self.seconds += start.elapsed().as_secs_f64();
        Ok(())
    }

    fn write_collection(&self) -> Result<(), RunError> {
        write_atomic(
            &self.out.join(COLLECTION),
            collection_text(&self.entries).as_bytes(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attributes_are_escaped() {
        assert_eq!(xml_attr("a<b>&\"c'\u{1}"), "a&lt;b&gt;&amp;&quot;c&apos;?");
    }

    #[test]
    fn collection_lists_entries_in_order() {
        let t = collection_text(&[
            (0.0, "snapshots/a.vtu".into()),
            (1e-6, "snapshots/b.vtu".into()),
        ]);
        let a = t.find("timestep=\"0e0\"").expect("first entry");
        let b = t.find("timestep=\"1e-6\"").expect("second entry");
        assert!(a < b);
        assert!(t.contains("file=\"snapshots/b.vtu\""));
    }
}
