//! A body (`[[bodies]]`): its shape, lattice and initial velocity.

use super::*;

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Body {
    pub name: String,
    pub material: String,
    /// Particle spacing Δx, m.
    pub spacing: f64,
    /// Initial velocity, one component per dimension.
    #[serde(default)]
    pub velocity: Option<Vec<f64>>,
    /// Moves at its initial velocity and is an infinitely stiff contact partner.
    #[serde(default)]
    pub rigid: bool,
    pub shape: Shape,
    /// Optional placement jitter (an addition to the contract), a fraction
    /// of the spacing in `[0, 0.5)`: each coordinate of each particle is
    /// displaced uniformly in `[−jitter, +jitter]·Δx` after placement (see
    /// [`place_bodies`]). Absent or 0: the regular lattice.
    #[serde(default)]
    pub jitter: Option<f64>,
    /// Seed of the jitter's generator (absent: the body's index in the
    /// file), so a jittered scene places the same particles on every run
    /// and every backend.
    #[serde(default)]
    pub seed: Option<u64>,
    /// A velocity field added to `velocity` particle by particle (an
    /// imploding or expanding shell, say).
    #[serde(default)]
    pub velocity_field: Option<VelocityField>,
    /// Regions of the body whose particles move at a prescribed velocity
    /// (clamped, driven), the whole run.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub constraints: Vec<Constraint>,
}

/// A clamped or driven region of a body (`[[bodies.constraints]]`): the
/// particles placed inside `region` move at `velocity` (or, `fixed`, stay
/// at rest), in every component but those listed `free`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Constraint {
    /// What probes call it; absent: `"<body>[k]"`, k its place in the
    /// body's list.
    #[serde(default)]
    pub name: Option<String>,
    pub region: Region,
    /// The prescribed velocity, m/s, one component per dimension.
    #[serde(default)]
    pub velocity: Option<Vec<f64>>,
    /// At rest: the velocity zero.
    #[serde(default)]
    pub fixed: bool,
    /// Components left free (`"x"`, `"y"`): a roller.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub free: Vec<Axis>,
}

/// A component of a vector.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    X,
    Y,
}

/// A part of the plane (or of the line, in 1-D) that picks particles.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Region {
    Segment {
        from: f64,
        to: f64,
    },
    Rectangle {
        min: Vec<f64>,
        max: Vec<f64>,
    },
    Disk {
        center: Vec<f64>,
        radius: f64,
    },
    /// A closed outline, the last vertex joined to the first.
    Polygon {
        vertices: Vec<Vec<f64>>,
    },
}

impl Region {
    /// Whether `p` lies in the region (its boundary included).
    pub fn contains(&self, p: glam::DVec2) -> bool {
        let at = |v: &[f64]| glam::DVec2::new(v[0], v.get(1).copied().unwrap_or(0.0));
        match self {
            Region::Segment { from, to } => p.x >= from.min(*to) && p.x <= from.max(*to),
            Region::Rectangle { min, max } => {
                let (a, b) = (at(min), at(max));
                p.x >= a.x && p.x <= b.x && (min.len() < 2 || (p.y >= a.y && p.y <= b.y))
            }
            Region::Disk { center, radius } => (p - at(center)).length() <= *radius,
            Region::Polygon { vertices } => {
                let ring: Vec<glam::DVec2> = vertices.iter().map(|v| at(v)).collect();
                outline::contains(&ring, p)
            }
        }
    }
}

/// An initial velocity that varies over a body.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum VelocityField {
    /// Along the direction from `center`, `speed (radius/r)^exponent` at
    /// distance `r` (negative: inward). Exponent 1 is the incompressible
    /// flow of a cylinder in the plane; 2 that of a sphere, drawn as a body
    /// of revolution centred on the axis.
    Radial {
        center: Vec<f64>,
        speed: f64,
        radius: f64,
        #[serde(default)]
        exponent: f64,
    },
}

impl VelocityField {
    /// The field's velocity at `x`; `None` at the centre, where a radial
    /// field has no direction.
    pub fn at(&self, x: glam::DVec2) -> Option<glam::DVec2> {
        match self {
            VelocityField::Radial {
                center,
                speed,
                radius,
                exponent,
            } => {
                let c = glam::DVec2::new(center[0], center.get(1).copied().unwrap_or(0.0));
                let d = x - c;
                let r = d.length();
                (r > 0.0).then(|| d / r * (*speed * (radius / r).powf(*exponent)))
            }
        }
    }
}

#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Lattice {
    #[default]
    Square,
    Polar,
}

/// How a polygon is filled.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum PolygonLattice {
    /// The square lattice fitted to the outline's bounding box.
    #[default]
    Square,
    /// Layers at depths `(k + ½) Δx` along the boundary
    /// ([`outline::boundary_lattice`]).
    Boundary,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    Segment {
        from: f64,
        to: f64,
    },
    Rectangle {
        min: Vec<f64>,
        max: Vec<f64>,
    },
    Disk {
        center: Vec<f64>,
        radius: f64,
        #[serde(default)]
        lattice: Lattice,
    },
    Ring {
        center: Vec<f64>,
        inner_radius: f64,
        outer_radius: f64,
        #[serde(default)]
        lattice: Lattice,
    },
    /// A closed outline (`[[x, y], ...]`, the last vertex joined to the
    /// first, either orientation) with optional holes, filled on the square
    /// lattice fitted to the outline's bounding box or in layers that
    /// follow the boundary ([`PolygonLattice`]). The outline and holes are
    /// typed, or read from a drawn section (`file`, an SVG or DXF file,
    /// [`super::drawing`]) when the scene is loaded, which fills
    /// `vertices` and `holes` and clears the drawing's keys.
    Polygon {
        #[serde(default)]
        vertices: Vec<Vec<f64>>,
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        holes: Vec<Vec<Vec<f64>>>,
        #[serde(default)]
        lattice: PolygonLattice,
        /// A drawn section; a relative path is taken from the scene
        /// file's folder.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        file: Option<PathBuf>,
        /// Metres per drawing unit (absent: the unit the drawing states).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        scale: Option<f64>,
        /// The drawing's part to read: an SVG element's id or label, a
        /// DXF layer (absent: the whole drawing).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        layer: Option<String>,
        /// Largest distance, m, between a drawn curve and the chords that
        /// replace it (absent: a twentieth of the spacing).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        tolerance: Option<f64>,
        /// Added to every drawn point after scaling, m.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        offset: Option<Vec<f64>>,
    },
    /// Particles read from a CSV file ([`particles_file`]); a relative path
    /// is taken from the scene file's folder.
    Particles {
        file: PathBuf,
    },
}

impl Shape {
    /// A typed polygon: its outline, holes and lattice.
    pub fn polygon(
        vertices: Vec<Vec<f64>>,
        holes: Vec<Vec<Vec<f64>>>,
        lattice: PolygonLattice,
    ) -> Shape {
        Shape::Polygon {
            vertices,
            holes,
            lattice,
            file: None,
            scale: None,
            layer: None,
            tolerance: None,
            offset: None,
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Segment { .. } => "segment",
            Shape::Rectangle { .. } => "rectangle",
            Shape::Disk { .. } => "disk",
            Shape::Ring { .. } => "ring",
            Shape::Polygon { .. } => "polygon",
            Shape::Particles { .. } => "particles",
        }
    }
}
