//! The scene file: the format of docs/scenes.md.
//!
//! A scene is one TOML document. This module holds its data types exactly as
//! the contract names them (unknown keys are rejected by serde), the loader,
//! and re-exports the semantic validation and the particle placement.

mod artificial;
mod body;
pub mod drawing;
pub mod library;
mod material;
mod model;
pub mod outline;
pub mod particles_file;
mod place;
mod probes;
mod simulation;
mod surface;
mod symmetry;
mod toml_errors;
pub mod validate;

pub use artificial::*;
pub use body::*;
pub use material::{Eos, FailureLaw, Material, MaterialSpec, StrengthLaw};
pub use place::{place_bodies, PlacedBody};
pub use probes::*;
pub use simulation::*;
pub use symmetry::Symmetry;
pub use validate::validate;

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::error::SceneError;
use crate::physics::support::Band;

/// A whole scene: geometry, materials, physics switches and what to record.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    #[serde(default)]
    pub title: Option<String>,
    pub simulation: Simulation,
    #[serde(default)]
    pub artificial_stress: Option<ArtificialStress>,
    #[serde(default)]
    pub artificial_viscosity: Option<ArtificialViscosity>,
    /// Optional contact settings (an addition to the contract; absent: defaults).
    #[serde(default)]
    pub contact: Option<ContactSettings>,
    pub materials: BTreeMap<String, Material>,
    pub bodies: Vec<Body>,
    #[serde(default)]
    pub probes: Vec<Probe>,
    #[serde(default)]
    pub output: Output,
    /// Symmetry planes (`[[symmetry]]`): at most one per coordinate axis.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub symmetry: Vec<Symmetry>,
}

impl Scene {
    /// Parse a scene from TOML text and validate it. `origin` names the source
    /// in error messages (usually the file path).
    /// Relative particle files are taken from the working folder.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Scene, SceneError> {
        Self::from_toml_in(text, origin, Path::new(""))
    }

    /// Read, parse and validate a scene file.
    pub fn from_file(path: &Path) -> Result<Scene, SceneError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SceneError {
            file: origin.clone(),
            key: None,
            message: format!("cannot read the scene file: {e}"),
        })?;
        let base = path.parent().unwrap_or(Path::new(""));
        Self::from_toml_in(&text, &origin, base)
    }

    /// [`Scene::from_toml_str`] with the relative paths inside the scene
    /// (particle files) taken from `base`. They are kept absolute, so a
    /// run resumed from its checkpoint finds them from any folder.
    pub fn from_toml_in(text: &str, origin: &str, base: &Path) -> Result<Scene, SceneError> {
        let mut scene: Scene =
            toml::from_str(text).map_err(|e| SceneError::parse(origin, text, &e))?;
        for (i, b) in scene.bodies.iter_mut().enumerate() {
            if let Shape::Particles { file } = &mut b.shape {
                let joined = base.join(&*file);
                *file = std::path::absolute(&joined).unwrap_or(joined);
            }
            read_drawing(b, base)
                .map_err(|(key, m)| SceneError::at(format!("bodies[{i}].shape.{key}"), m))
                .map_err(|e| e.in_file(origin))?;
        }
        validate(&scene).map_err(|e| e.in_file(origin))?;
        Ok(scene)
    }

    /// Serialise back to TOML (used by examples that build scenes in code).
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).expect("a Scene always serialises")
    }

    pub fn dim(&self) -> usize {
        self.simulation.dimension as usize
    }

    /// Whether the scene's bodies are bodies of revolution.
    pub fn axisymmetric(&self) -> bool {
        self.simulation.geometry == Geometry::Axisymmetric
    }

    pub fn viscosity(&self) -> ArtificialViscosity {
        self.artificial_viscosity.unwrap_or_default()
    }

    pub fn contact_settings(&self) -> ContactSettings {
        self.contact.clone().unwrap_or_default()
    }

    pub fn history_interval(&self) -> f64 {
        self.output
            .history_interval
            .unwrap_or(self.simulation.end_time / 1000.0)
    }
}

/// A polygon drawn in a file ([`drawing`]): its outline and holes read
/// into `vertices` and `holes`, the drawing's keys then cleared, so the
/// scene (and a checkpoint's copy of it) no longer needs the file. A
/// failure names the key and says why.
fn read_drawing(b: &mut Body, base: &Path) -> Result<(), (&'static str, String)> {
    let spacing = b.spacing;
    let Shape::Polygon {
        vertices,
        holes,
        file,
        scale,
        layer,
        tolerance,
        offset,
        ..
    } = &mut b.shape
    else {
        return Ok(());
    };
    let Some(path) = file.take() else {
        for (key, given) in [
            ("scale", scale.is_some()),
            ("layer", layer.is_some()),
            ("tolerance", tolerance.is_some()),
            ("offset", offset.is_some()),
        ] {
            if given {
                return Err((key, "applies to a drawn section: give `file` too".into()));
            }
        }
        return Ok(());
    };
    if !vertices.is_empty() || !holes.is_empty() {
        return Err((
            "file",
            "give the outline either as `vertices` (and `holes`) or as a drawn `file`, not both"
                .into(),
        ));
    }
    let positive = |key: &'static str, v: Option<f64>| match v {
        Some(x) if !(x.is_finite() && x > 0.0) => {
            Err((key, format!("must be a positive number (got {x})")))
        }
        _ => Ok(()),
    };
    positive("scale", *scale)?;
    positive("tolerance", *tolerance)?;
    let offset = match offset.take() {
        None => glam::DVec2::ZERO,
        Some(o) if o.len() == 2 && o.iter().all(|x| x.is_finite()) => glam::DVec2::new(o[0], o[1]),
        Some(o) => {
            return Err((
                "offset",
                format!("must be two finite numbers, m (got {o:?})"),
            ))
        }
    };
    // A spacing that is not positive is reported by the body's check.
    if !(spacing.is_finite() && spacing > 0.0) {
        return Ok(());
    }
    let joined = base.join(&path);
    let section = drawing::read(&drawing::Request {
        file: &joined,
        scale: *scale,
        layer: layer.as_deref(),
        tolerance: tolerance.unwrap_or(spacing / 20.0),
        offset,
    })
    .map_err(|m| ("file", m))?;
    let coords = |ring: &[glam::DVec2]| ring.iter().map(|p| vec![p.x, p.y]).collect::<Vec<_>>();
    *vertices = coords(&section.outline);
    *holes = section.holes.iter().map(|h| coords(h)).collect();
    (*scale, *layer, *tolerance) = (None, None, None);
    Ok(())
}
