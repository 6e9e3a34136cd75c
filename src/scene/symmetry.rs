//! Symmetry planes (`[[symmetry]]`, docs/scenes.md): the scene is the half
//! on the side a plane's normal points to, and the other half is its
//! mirror image.

use glam::DVec2;
use serde::{Deserialize, Serialize};

use crate::math::Mirror;

/// One symmetry plane (a line of the 2-D plane): `normal` along a
/// coordinate axis, pointing into the half the scene models, through
/// `point`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Symmetry {
    pub normal: Vec<f64>,
    pub point: Vec<f64>,
}

impl Symmetry {
    /// The coordinate the plane's normal runs along and its sign (a
    /// validated plane's normal is `[±1, 0]` or `[0, ±1]`).
    pub fn axis(&self) -> (usize, f64) {
        let k = usize::from(self.normal[0] == 0.0);
        (k, self.normal[k].signum())
    }

    /// The reflection across the plane.
    pub fn mirror(&self) -> Mirror {
        let (axis, _) = self.axis();
        Mirror::across(axis, self.point[axis])
    }

    /// How far `x` lies on the modelled side of the plane (negative
    /// beyond it).
    pub fn side(&self, x: DVec2) -> f64 {
        let (k, s) = self.axis();
        s * (x[k] - self.point[k])
    }
}
