//! The rules of each shape: its keys, a polygon's outline and holes, a
//! particles file.

use super::*;

pub(super) fn validate_shape(shape: &Shape, dim: usize, key: &str) -> R {
    let want = match shape {
        Shape::Segment { .. } => 1,
        Shape::Particles { .. } => dim,
        _ => 2,
    };
    if want != dim {
        return Err(SceneError::at(
            format!("{key}.kind"),
            format!(
                "a {} is a {want}-D shape but the scene is {dim}-D",
                shape.kind()
            ),
        ));
    }
    match shape {
        Shape::Segment { from, to } => {
            finite(key, &[*from, *to])?;
            if to <= from {
                return Err(SceneError::at(
                    format!("{key}.to"),
                    format!("must be greater than from (got from = {from}, to = {to})"),
                ));
            }
        }
        Shape::Rectangle { min, max } => {
            dimension_of(&format!("{key}.min"), min, dim)?;
            dimension_of(&format!("{key}.max"), max, dim)?;
            if max[0] <= min[0] || max[1] <= min[1] {
                return Err(SceneError::at(
                    format!("{key}.max"),
                    "must be greater than min on every axis",
                ));
            }
        }
        Shape::Disk { center, radius, .. } => {
            dimension_of(&format!("{key}.center"), center, dim)?;
            positive(&format!("{key}.radius"), *radius)?;
        }
        Shape::Ring {
            center,
            inner_radius,
            outer_radius,
            ..
        } => {
            dimension_of(&format!("{key}.center"), center, dim)?;
            non_negative(&format!("{key}.inner_radius"), *inner_radius)?;
            positive(&format!("{key}.outer_radius"), *outer_radius)?;
            if outer_radius <= inner_radius {
                return Err(SceneError::at(
                    format!("{key}.outer_radius"),
                    "must be greater than inner_radius",
                ));
            }
        }
        Shape::Polygon {
            vertices, holes, ..
        } => validate_polygon(vertices, holes, key)?,
        // Read with the body's other keys (`validate_particles`).
        Shape::Particles { .. } => {}
    }
    Ok(())
}

/// A polygon's outline: at least three points of two finite coordinates,
/// a non-zero area, no edge meeting another but at their shared vertex;
/// each hole the same, inside the outline, and apart from the others.
fn validate_polygon(vertices: &[Vec<f64>], holes: &[Vec<Vec<f64>>], key: &str) -> R {
    use crate::scene::outline::{contains, rings_meet, self_intersection, signed_area};
    use glam::DVec2;
    let ring = |v: &[Vec<f64>], k: &str| -> Result<Vec<DVec2>, SceneError> {
        if v.len() < 3 {
            return Err(SceneError::at(
                k,
                format!("needs at least 3 vertices (got {})", v.len()),
            ));
        }
        for (i, p) in v.iter().enumerate() {
            dimension_of(&format!("{k}[{i}]"), p, 2)?;
        }
        let r: Vec<DVec2> = v.iter().map(|p| DVec2::new(p[0], p[1])).collect();
        // An edge of no length has no direction: the boundary lattice
        // moves each edge along its normal.
        if let Some(i) = (0..r.len()).find(|&i| r[i] == r[(i + 1) % r.len()]) {
            return Err(SceneError::at(
                format!("{k}[{}]", (i + 1) % r.len()),
                format!("repeats vertex {i}: consecutive vertices must differ"),
            ));
        }
        if let Some((a, b)) = self_intersection(&r) {
            return Err(SceneError::at(
                k,
                format!(
                    "the outline intersects itself: edge {a} (from vertex {a}) meets edge {b} (from vertex {b})"
                ),
            ));
        }
        if signed_area(&r) == 0.0 {
            return Err(SceneError::at(k, "the outline encloses no area"));
        }
        Ok(r)
    };
    let outer = ring(vertices, &format!("{key}.vertices"))?;
    let mut inner: Vec<Vec<DVec2>> = Vec::with_capacity(holes.len());
    for (h, v) in holes.iter().enumerate() {
        let k = format!("{key}.holes[{h}]");
        let r = ring(v, &k)?;
        if rings_meet(&outer, &r) || !r.iter().all(|&p| contains(&outer, p)) {
            return Err(SceneError::at(
                k,
                "the hole is not inside the outline (a hole must lie within it, touching nowhere)",
            ));
        }
        for (g, other) in inner.iter().enumerate() {
            if rings_meet(other, &r) || contains(other, r[0]) || contains(&r, other[0]) {
                return Err(SceneError::at(k, format!("the hole overlaps holes[{g}]")));
            }
        }
        inner.push(r);
    }
    Ok(())
}

/// A particles file: readable, of the scene's dimension, its particles'
/// spacing `V^(1/d)` (median) within 25 % of the body's `spacing` (which
/// sets their `h`), velocities from the file or the body, not both, and
/// no jitter (the file's positions are the user's).
///
/// In a body of revolution every particle lies at `r > 0` and its volume
/// is its ring's: the spacing is that of the cross-section, `√(V/2πr)`.
pub(super) fn validate_particles(
    b: &crate::scene::Body,
    file: &std::path::Path,
    dim: usize,
    rho0: f64,
    axisymmetric: bool,
    k: &dyn Fn(&str) -> String,
) -> R {
    let t = crate::scene::particles_file::read(file, dim)
        .map_err(|e| SceneError::at(k("shape.file"), e))?;
    if axisymmetric {
        if let Some(i) = t.x.iter().position(|p| p.x <= 0.0 || p.x.is_nan()) {
            return Err(SceneError::at(
                k("shape.file"),
                format!(
                    "particle {} (data line {}) lies at r = {} m: in an axisymmetric scene the first column is the radius, and every particle lies at r > 0",
                    i,
                    i + 1,
                    t.x[i].x
                ),
            ));
        }
    }
    if b.jitter.is_some_and(|j| j > 0.0) {
        return Err(SceneError::at(
            k("jitter"),
            "a particles file is placed as given: jitter applies to the generated lattices",
        ));
    }
    if !t.v.is_empty() && b.velocity.is_some() {
        return Err(SceneError::at(
            k("velocity"),
            "the particles file gives each particle's velocity: drop the body's velocity or the file's columns",
        ));
    }
    if !t.v.is_empty() && b.velocity_field.is_some() {
        return Err(SceneError::at(
            k("velocity_field"),
            "the particles file gives each particle's velocity: drop the field or the file's columns",
        ));
    }
    if !t.v.is_empty() && b.rigid {
        return Err(SceneError::at(
            k("rigid"),
            "a rigid body moves as one: give its velocity, not a velocity per particle",
        ));
    }
    let mut side: Vec<f64> = t
        .volumes(rho0)
        .iter()
        .zip(&t.x)
        .map(|(&v, p)| match (dim, axisymmetric) {
            (1, _) => v,
            (_, false) => v.sqrt(),
            (_, true) => (v / crate::math::circumference(p.x)).sqrt(),
        })
        .collect();
    {
        side.sort_by(f64::total_cmp);
        let median = side[side.len() / 2];
        if !(0.75..=1.25).contains(&(median / b.spacing)) {
            return Err(SceneError::at(
                k("spacing"),
                format!(
                    "the file's particles are spaced {median:e} m (the median of volume^(1/{dim})), the body's spacing is {:e} m: they must agree within 25 % (the spacing sets h)",
                    b.spacing
                ),
            ));
        }
    }
    Ok(())
}

/// A body of revolution's cross-section lies at `r >= 0`: a rectangle or
/// polygon on the axis's right, a disk or ring either there or centred on
/// the axis (its other half is its mirror image, the same body).
pub(super) fn validate_revolution(shape: &Shape, key: &str) -> R {
    let refuse = |what: String| {
        Err(SceneError::at(
            key,
            format!(
                "{what}: in an axisymmetric scene the first coordinate is the radius, and a body lies at r >= 0 (a disk or ring may also be centred on the axis)"
            ),
        ))
    };
    match shape {
        Shape::Rectangle { min, .. } if min[0] < 0.0 => {
            refuse(format!("the rectangle reaches r = {}", min[0]))
        }
        Shape::Disk { center, radius, .. } if center[0] != 0.0 && center[0] - radius < 0.0 => {
            refuse(format!(
                "the disk reaches r = {} without being centred on the axis",
                center[0] - radius
            ))
        }
        Shape::Ring {
            center,
            outer_radius,
            ..
        } if center[0] != 0.0 && center[0] - outer_radius < 0.0 => refuse(format!(
            "the ring reaches r = {} without being centred on the axis",
            center[0] - outer_radius
        )),
        Shape::Polygon {
            vertices, holes, ..
        } => match vertices
            .iter()
            .chain(holes.iter().flatten())
            .find(|p| p[0] < 0.0)
        {
            Some(p) => refuse(format!("the polygon has a vertex at r = {}", p[0])),
            None => Ok(()),
        },
        _ => Ok(()),
    }
}
