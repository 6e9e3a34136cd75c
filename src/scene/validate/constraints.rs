//! The rules of `[[bodies.constraints]]` (docs/scenes.md, "Constraints").

use super::*;
use crate::scene::{Axis, Body, Constraint, Region};

/// The constraints of body `i` (`b`), before placement: each a velocity or
/// `fixed`, a region of the scene's dimension, free components that leave
/// one constrained, and names unique over the scene (`names`).
pub(super) fn validate_constraints(
    b: &Body,
    i: usize,
    dim: usize,
    names: &mut HashSet<String>,
) -> R {
    for (k, c) in b.constraints.iter().enumerate() {
        let key = |f: &str| format!("bodies[{i}].constraints[{k}].{f}");
        if b.rigid {
            return Err(SceneError::at(
                format!("bodies[{i}].constraints"),
                "a rigid body moves as one at its velocity: it takes no constraints",
            ));
        }
        match (&c.velocity, c.fixed) {
            (None, false) => {
                return Err(SceneError::at(
                    key("velocity"),
                    "give the region's velocity, or fixed = true",
                ))
            }
            (Some(_), true) => {
                return Err(SceneError::at(
                    key("fixed"),
                    "give a velocity or fixed = true, not both",
                ))
            }
            (Some(v), false) => dimension_of(&key("velocity"), v, dim)?,
            (None, true) => {}
        }
        if dim == 1 && c.free.contains(&Axis::Y) {
            return Err(SceneError::at(
                key("free"),
                "a 1-D scene has only the component \"x\"",
            ));
        }
        let free = [Axis::X, Axis::Y][..dim]
            .iter()
            .filter(|a| c.free.contains(a))
            .count();
        if free == dim {
            return Err(SceneError::at(
                key("free"),
                "leaves every component free: the region would hold nothing",
            ));
        }
        validate_region(&c.region, dim, &key("region"))?;
        if !names.insert(constraint_name(b, k, c)) {
            return Err(SceneError::at(
                key("name"),
                format!("duplicate constraint name '{}'", constraint_name(b, k, c)),
            ));
        }
    }
    Ok(())
}

/// What probes call constraint `k` of body `b`.
pub fn constraint_name(b: &Body, k: usize, c: &Constraint) -> String {
    c.name.clone().unwrap_or_else(|| format!("{}[{k}]", b.name))
}

fn validate_region(r: &Region, dim: usize, key: &str) -> R {
    let at = |f: &str| format!("{key}.{f}");
    match r {
        Region::Segment { from, to } => {
            if dim != 1 {
                return Err(SceneError::at(
                    key,
                    "a segment is a 1-D region: use a rectangle, disk or polygon",
                ));
            }
            finite(&at("from"), &[*from])?;
            finite(&at("to"), &[*to])
        }
        Region::Rectangle { min, max } => {
            dimension_of(&at("min"), min, dim)?;
            dimension_of(&at("max"), max, dim)?;
            if min.iter().zip(max).any(|(a, b)| a > b) {
                return Err(SceneError::at(key, "min must not exceed max"));
            }
            Ok(())
        }
        Region::Disk { center, radius } => {
            if dim != 2 {
                return Err(SceneError::at(key, "a disk is a 2-D region"));
            }
            dimension_of(&at("center"), center, dim)?;
            positive(&at("radius"), *radius)
        }
        Region::Polygon { vertices } => {
            if dim != 2 {
                return Err(SceneError::at(key, "a polygon is a 2-D region"));
            }
            if vertices.len() < 3 {
                return Err(SceneError::at(
                    at("vertices"),
                    format!("needs at least 3 vertices (got {})", vertices.len()),
                ));
            }
            for v in vertices {
                dimension_of(&at("vertices"), v, 2)?;
            }
            Ok(())
        }
    }
}

/// After placement: each constraint's region holds some of its body's
/// particles, and none of them lies in two regions of the body.
pub(super) fn validate_constrained(b: &Body, i: usize, positions: &[glam::DVec2]) -> R {
    let mut taken = vec![None; positions.len()];
    for (k, c) in b.constraints.iter().enumerate() {
        let key = format!("bodies[{i}].constraints[{k}].region");
        let mut any = false;
        for (p, x) in positions.iter().enumerate() {
            if !c.region.contains(*x) {
                continue;
            }
            any = true;
            if let Some(first) = taken[p] {
                return Err(SceneError::at(
                    key,
                    format!(
                        "overlaps constraints[{first}]: the particle at ({}, {}) lies in both",
                        x.x, x.y
                    ),
                ));
            }
            taken[p] = Some(k);
        }
        if !any {
            return Err(SceneError::at(
                key,
                format!("holds none of body '{}''s particles", b.name),
            ));
        }
    }
    Ok(())
}
