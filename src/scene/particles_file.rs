//! The `particles` shape's file: one particle per line of a CSV file,
//! geometry made elsewhere (docs/scenes.md, "Particles from a file").
//!
//! The first line that is not blank or a `#` comment names the columns:
//! `x` (and `y` in 2-D), one of `volume` (m² in 2-D, per unit thickness;
//! m in 1-D) or `mass` (kg, the same way), and optionally `vx` (and `vy`),
//! the initial velocity, and `offset`, the distance to the body's surface
//! (m; found from the particles when absent, docs/method.md §8.3). Every
//! later line that is not blank or a comment is one particle. A field that
//! is not a number is reported with its line and column.

use glam::DVec2;
use std::path::Path;

/// The particles of a file, as read.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ParticleTable {
    pub x: Vec<DVec2>,
    /// Each particle's volume or mass, as the header says.
    pub amount: Vec<f64>,
    /// Whether `amount` is mass (else volume).
    pub is_mass: bool,
    /// Initial velocities when the file gives them; empty otherwise.
    pub v: Vec<DVec2>,
    /// Surface offsets when the file gives them; empty otherwise.
    pub offset: Vec<f64>,
}

impl ParticleTable {
    /// The particle masses for a material of density `rho0`.
    pub fn masses(&self, rho0: f64) -> Vec<f64> {
        if self.is_mass {
            self.amount.clone()
        } else {
            self.amount.iter().map(|v| rho0 * v).collect()
        }
    }

    /// The particle volumes for a material of density `rho0`.
    pub fn volumes(&self, rho0: f64) -> Vec<f64> {
        if self.is_mass {
            self.amount.iter().map(|m| m / rho0).collect()
        } else {
            self.amount.clone()
        }
    }
}

/// Read and parse `path` for a `dim`-D scene. The error names the file,
/// and the line and column where one applies.
pub fn read(path: &Path, dim: usize) -> Result<ParticleTable, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read the particles file {}: {e}", path.display()))?;
    parse(&text, dim).map_err(|e| format!("{}, {e}", path.display()))
}

/// Parse the text of a particles file; errors begin with `line L:` or
/// `line L, column C:` (1-based, C counting fields).
pub fn parse(text: &str, dim: usize) -> Result<ParticleTable, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (head_line, head) = lines.next().ok_or_else(|| {
        "line 1: the file has no header line (x, y, volume or mass, ...)".to_string()
    })?;
    let names: Vec<&str> = head.split(',').map(str::trim).collect();
    let allowed: &[&str] = if dim == 1 {
        &["x", "volume", "mass", "vx", "offset"]
    } else {
        &["x", "y", "volume", "mass", "vx", "vy", "offset"]
    };
    let mut col = std::collections::HashMap::new();
    for (k, &name) in names.iter().enumerate() {
        if !allowed.contains(&name) {
            return Err(format!(
                "line {head_line}, column {}: unknown column '{name}' (a {dim}-D file has {})",
                k + 1,
                allowed.join(", ")
            ));
        }
        if col.insert(name, k).is_some() {
            return Err(format!(
                "line {head_line}, column {}: column '{name}' twice",
                k + 1
            ));
        }
    }
    let need: &[&str] = if dim == 1 { &["x"] } else { &["x", "y"] };
    for n in need {
        if !col.contains_key(n) {
            return Err(format!("line {head_line}: the header has no column '{n}'"));
        }
    }
    let is_mass = match (col.get("volume"), col.get("mass")) {
        (Some(_), None) => false,
        (None, Some(_)) => true,
        (Some(_), Some(_)) => {
            return Err(format!(
                "line {head_line}: give a column 'volume' or a column 'mass', not both"
            ))
        }
        (None, None) => {
            return Err(format!(
                "line {head_line}: the header has no column 'volume' or 'mass'"
            ))
        }
    };
    let vel: &[&str] = if dim == 1 { &["vx"] } else { &["vx", "vy"] };
    let has_v = vel.iter().filter(|n| col.contains_key(*n)).count();
    if has_v != 0 && has_v != vel.len() {
        return Err(format!(
            "line {head_line}: give every velocity column ({}) or none",
            vel.join(", ")
        ));
    }
    let mut t = ParticleTable {
        is_mass,
        ..Default::default()
    };
    let amount_col = col[if is_mass { "mass" } else { "volume" }];
    for (line, l) in lines {
        let fields: Vec<&str> = l.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            return Err(format!(
                "line {line}: {} fields where the header names {}",
                fields.len(),
                names.len()
            ));
        }
        let num = |name: &str| -> Result<f64, String> {
            let k = col[name];
            let s = fields[k];
            match s.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(format!(
                    "line {line}, column {}: '{s}' in column '{name}' is not a finite number",
                    k + 1
                )),
            }
        };
        let x = DVec2::new(num("x")?, if dim == 1 { 0.0 } else { num("y")? });
        let a = num(names[amount_col])?;
        if a <= 0.0 {
            return Err(format!(
                "line {line}, column {}: the {} must be positive (got {a})",
                amount_col + 1,
                names[amount_col]
            ));
        }
        if col.contains_key("offset") {
            let o = num("offset")?;
            if o < 0.0 {
                return Err(format!(
                    "line {line}, column {}: the offset must be >= 0 (got {o})",
                    col["offset"] + 1
                ));
            }
            t.offset.push(o);
        }
        t.x.push(x);
        t.amount.push(a);
        if has_v > 0 {
            t.v.push(DVec2::new(
                num("vx")?,
                if dim == 1 { 0.0 } else { num("vy")? },
            ));
        }
    }
    if t.x.is_empty() {
        return Err(format!(
            "line {head_line}: the file has a header but no particle"
        ));
    }
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_with_comments_volumes_and_velocities() {
        let t = parse(
            "# made elsewhere\nx, y, volume, vx, vy\n\n0.0, 1e-3, 4e-8, 5, 0\n# a comment\n2e-4,1e-3,4e-8,5,-1\n",
            2,
        )
        .expect("parses");
        assert_eq!(t.x, vec![DVec2::new(0.0, 1e-3), DVec2::new(2e-4, 1e-3)]);
        assert_eq!(t.masses(7850.0), vec![7850.0 * 4e-8; 2]);
        assert_eq!(t.v[1], DVec2::new(5.0, -1.0));
        let m = parse("mass,x\n2.0,0.5\n", 1).expect("parses");
        assert!(m.is_mass && m.v.is_empty());
        assert_eq!(m.volumes(4.0), vec![0.5]);
    }

    #[test]
    fn errors_name_the_line_and_column() {
        let e = |text: &str| parse(text, 2).expect_err("refused");
        assert_eq!(
            e("x,y,volume\n0,0,1e-8\n0,abc,1e-8\n"),
            "line 3, column 2: 'abc' in column 'y' is not a finite number"
        );
        assert_eq!(
            e("x,y,volume\n0,0\n"),
            "line 2: 2 fields where the header names 3"
        );
        assert!(e("x,y,z,volume\n").starts_with("line 1, column 3: unknown column 'z'"));
        assert_eq!(
            e("x,y\n0,0\n"),
            "line 1: the header has no column 'volume' or 'mass'"
        );
        assert!(e("x,y,volume,mass\n").contains("not both"));
        assert!(e("x,y,volume,vx\n").contains("every velocity column"));
        assert_eq!(
            e("x,y,volume\n0,0,-1\n"),
            "line 2, column 3: the volume must be positive (got -1)"
        );
        assert_eq!(
            e("x,y,volume\n0,0,nan\n"),
            "line 2, column 3: 'nan' in column 'volume' is not a finite number"
        );
        assert!(e("# only a comment\n").starts_with("line 1: the file has no header"));
        assert!(e("x,y,mass\n").contains("no particle"));
    }
}
