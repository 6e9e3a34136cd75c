//! A small reader of the VTK XML UnstructuredGrid files the snapshots are
//! (appended raw data, UInt64 block headers): what the snapshot tests and
//! the hard cases read particle fields back with.

use std::collections::HashMap;
use std::path::Path;

/// One `.vtu` file read back: the header's attributes and the appended
/// arrays by name, as raw bytes.
pub struct Vtu {
    pub points: usize,
    pub time: f64,
    pub field_ints: HashMap<String, i32>,
    pub arrays: HashMap<String, (String, usize, Vec<u8>)>,
}

/// The value of attribute `name` in an XML tag.
pub fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let len = tag[start..].find('"')?;
    Some(&tag[start..start + len])
}

pub fn read_vtu(path: &Path) -> Vtu {
    let bytes = std::fs::read(path).expect("a snapshot file");
    let marker = b"<AppendedData encoding=\"raw\">";
    let at = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .expect("appended data");
    let underscore = at
        + bytes[at..]
            .iter()
            .position(|&b| b == b'_')
            .expect("the '_' marker");
    let data = underscore + 1;
    let header = std::str::from_utf8(&bytes[..at]).expect("an ASCII header");
    assert!(header.contains("type=\"UnstructuredGrid\""));
    assert!(header.contains("byte_order=\"LittleEndian\""));
    assert!(header.contains("header_type=\"UInt64\""));
    let piece = &header[header.find("<Piece ").expect("a piece")..];
    let points: usize = attr(piece, "NumberOfPoints").unwrap().parse().unwrap();
    let cells: usize = attr(piece, "NumberOfCells").unwrap().parse().unwrap();
    assert_eq!(points, cells, "one vertex cell per particle");
    let mut vtu = Vtu {
        points,
        time: f64::NAN,
        field_ints: HashMap::new(),
        arrays: HashMap::new(),
    };
    for chunk in header.split("<DataArray").skip(1) {
        let tag = &chunk[..chunk.find('>').unwrap()];
        let name = attr(tag, "Name").expect("named arrays").to_string();
        let ty = attr(tag, "type").unwrap().to_string();
        if attr(tag, "format") == Some("ascii") {
            let body = &chunk[chunk.find('>').unwrap() + 1..chunk.find("</DataArray>").unwrap()];
            if name == "TimeValue" {
                vtu.time = body.trim().parse().unwrap();
            } else {
                vtu.field_ints.insert(name, body.trim().parse().unwrap());
            }
            continue;
        }
        assert_eq!(attr(tag, "format"), Some("appended"));
        let comps: usize = attr(tag, "NumberOfComponents").map_or(1, |c| c.parse().unwrap());
        let off: usize = attr(tag, "offset").unwrap().parse().unwrap();
        let start = data + off;
        let len = u64::from_le_bytes(bytes[start..start + 8].try_into().unwrap()) as usize;
        let block = bytes[start + 8..start + 8 + len].to_vec();
        vtu.arrays.insert(name, (ty, comps, block));
    }
    let tail = std::str::from_utf8(&bytes[bytes.len() - 40..]).unwrap_or("");
    assert!(tail.contains("</AppendedData>") && tail.contains("</VTKFile>"));
    vtu
}

impl Vtu {
    pub fn f64s(&self, name: &str, comps: usize) -> Vec<f64> {
        let (ty, c, b) = &self.arrays[name];
        assert_eq!((ty.as_str(), *c), ("Float64", comps), "{name}");
        assert_eq!(b.len(), 8 * comps * self.points, "{name}");
        b.chunks_exact(8)
            .map(|x| f64::from_le_bytes(x.try_into().unwrap()))
            .collect()
    }

    pub fn ints(&self, name: &str) -> Vec<i64> {
        let (ty, _, b) = &self.arrays[name];
        match ty.as_str() {
            "UInt8" => b.iter().map(|&x| x as i64).collect(),
            "Int32" => b
                .chunks_exact(4)
                .map(|x| i32::from_le_bytes(x.try_into().unwrap()) as i64)
                .collect(),
            "Int64" => b
                .chunks_exact(8)
                .map(|x| i64::from_le_bytes(x.try_into().unwrap()))
                .collect(),
            t => panic!("{name}: unexpected type {t}"),
        }
    }

    /// Positions (z must be 0).
    pub fn xy(&self, name: &str) -> Vec<[f64; 2]> {
        self.f64s(name, 3)
            .chunks_exact(3)
            .map(|p| {
                assert_eq!(p[2], 0.0, "{name}: z = 0");
                [p[0], p[1]]
            })
            .collect()
    }
}
