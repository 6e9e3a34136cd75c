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
pub(super) fn validate_particles(
    b: &crate::scene::Body,
    file: &std::path::Path,
    dim: usize,
    rho0: f64,
    k: &dyn Fn(&str) -> String,
) -> R {
    let t = crate::scene::particles_file::read(file, dim)
        .map_err(|e| SceneError::at(k("shape.file"), e))?;
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
    if !t.v.is_empty() && b.rigid {
        return Err(SceneError::at(
            k("rigid"),
            "a rigid body moves as one: give its velocity, not a velocity per particle",
        ));
    }
    let mut side: Vec<f64> = t
        .volumes(rho0)
        .iter()
        .map(|&v| if dim == 1 { v } else { v.sqrt() })
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
