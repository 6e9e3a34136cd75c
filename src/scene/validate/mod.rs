//! Semantic validation of a parsed scene (docs/scenes.md, "Validation"). Serde has
//! already rejected unknown keys, missing required keys and wrong types; what
//! is left is every rule that needs values, and the ones that need the placed
//! particles (empty shapes, overlapping bodies, a fixed step above the CFL
//! limit).

use std::collections::{HashMap, HashSet};

use super::{place_bodies, Interaction, Probe, Scene, Shape};
use crate::error::SceneError;
use crate::physics::material::{cfl_step, MaterialModel};

mod constraints;
mod shapes;
pub use constraints::constraint_name;
use shapes::{validate_particles, validate_revolution, validate_shape};

type R = Result<(), SceneError>;

fn positive(key: &str, v: f64) -> R {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(SceneError::at(key, format!("must be > 0 (got {v})")))
    }
}

fn non_negative(key: &str, v: f64) -> R {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(SceneError::at(key, format!("must be >= 0 (got {v})")))
    }
}

/// A static coefficient, if given, is finite and no smaller than the
/// sliding one `mu`.
fn static_at_least(key: &str, v: Option<f64>, mu: f64) -> R {
    match v {
        Some(s) if !(s.is_finite() && s >= mu) => Err(SceneError::at(
            key,
            format!("must be >= the sliding coefficient friction = {mu} (got {s})"),
        )),
        _ => Ok(()),
    }
}

fn finite(key: &str, v: &[f64]) -> R {
    match v.iter().find(|x| !x.is_finite()) {
        Some(x) => Err(SceneError::at(key, format!("must be finite (got {x})"))),
        None => Ok(()),
    }
}

fn dimension_of(key: &str, v: &[f64], dim: usize) -> R {
    if v.len() != dim {
        return Err(SceneError::at(
            key,
            format!(
                "has {} component(s) but the scene is {dim}-D (expected {dim})",
                v.len()
            ),
        ));
    }
    finite(key, v)
}

/// The dispersion correction's θ is in [0, 1.5] (docs/method.md §4): the
/// scene key's rule, and `validate --dispersion-correction`'s.
pub fn dispersion_correction_in_range(theta: f64) -> Result<(), String> {
    if theta.is_finite() && (0.0..=1.5).contains(&theta) {
        Ok(())
    } else {
        Err(format!(
            "must lie in [0, 1.5] (got {theta}; 0.7 is the measured best, 0 is off)"
        ))
    }
}

/// Check every rule of docs/scenes.md ("Validation") that serde does not.
pub fn validate(scene: &Scene) -> R {
    validate_simulation(scene)?;
    validate_materials(scene)?;
    let names = validate_bodies(scene)?;
    validate_probes(scene, &names)?;
    validate_contact_pairs(scene, &names)?;
    validate_symmetry(scene)?;
    validate_placement(scene)
}

/// The simulation's keys and the scene-wide tables (artificial terms,
/// contact, output).
fn validate_simulation(scene: &Scene) -> R {
    let sim = &scene.simulation;
    let dim = sim.dimension as usize;
    if dim != 1 && dim != 2 {
        return Err(SceneError::at(
            "simulation.dimension",
            format!("must be 1 or 2 (got {})", sim.dimension),
        ));
    }
    if scene.axisymmetric() && dim != 2 {
        return Err(SceneError::at(
            "simulation.geometry",
            format!("\"axisymmetric\" needs dimension = 2 (the r-z plane; got {dim})"),
        ));
    }
    positive("simulation.end_time", sim.end_time)?;
    positive("simulation.cfl", sim.cfl)?;
    positive("simulation.smoothing_ratio", sim.smoothing_ratio)?;
    if let Some(dt) = sim.dt {
        positive("simulation.dt", dt)?;
    }
    if let Some(band) = sim.support_band {
        if !sim.adaptive() {
            return Err(SceneError::at(
                "simulation.support_band",
                "applies to supports that adapt, not with support = \"fixed\"",
            ));
        }
        let b = band.band();
        for f in [b.drawn, b.squeezed] {
            if !(f.is_finite() && (1.0..=4.0).contains(&f)) {
                return Err(SceneError::at(
                    "simulation.support_band",
                    format!("each factor must lie in [1, 4] (got {f})"),
                ));
            }
        }
    }
    if let Some(g) = &sim.gravity {
        dimension_of("simulation.gravity", g, dim)?;
        if scene.axisymmetric() && g[0] != 0.0 {
            return Err(SceneError::at(
                "simulation.gravity",
                format!(
                    "in a body of revolution gravity acts along the axis: its first (radial) component must be 0 (got {})",
                    g[0]
                ),
            ));
        }
    }
    let theta = sim.dispersion_correction;
    dispersion_correction_in_range(theta)
        .map_err(|e| SceneError::at("simulation.dispersion_correction", e))?;
    if let Some(av) = &scene.artificial_viscosity {
        non_negative("artificial_viscosity.alpha", av.alpha)?;
        non_negative("artificial_viscosity.beta", av.beta)?;
        non_negative("artificial_viscosity.hourglass", av.hourglass)?;
    }
    if let Some(st) = &scene.artificial_stress {
        non_negative("artificial_stress.epsilon", st.epsilon)?;
        positive("artificial_stress.n", st.n)?;
        non_negative("artificial_stress.plastic_hourglass", st.plastic_hourglass)?;
    }
    if let Some(c) = &scene.contact {
        positive("contact.boundary_threshold", c.boundary_threshold)?;
        non_negative("contact.friction", c.friction)?;
        static_at_least("contact.static_friction", c.static_friction, c.friction)?;
    }
    if let Some(v) = scene.output.history_interval {
        positive("output.history_interval", v)?;
    }
    if scene.output.snapshot_png && scene.output.snapshot_interval.is_none() {
        return Err(SceneError::at(
            "output.snapshot_png",
            "draws the snapshots, and needs output.snapshot_interval to write them",
        ));
    }
    if let Some(v) = scene.output.snapshot_interval {
        positive("output.snapshot_interval", v)?;
    }
    Ok(())
}

/// Each material's keys.
fn validate_materials(scene: &Scene) -> R {
    if scene.materials.is_empty() {
        return Err(SceneError::at(
            "materials",
            "at least one material is required",
        ));
    }
    for (name, m) in &scene.materials {
        let k = |f: &str| format!("materials.{name}.{f}");
        positive(&k("density"), m.density)?;
        m.eos
            .check()
            .map_err(|(key, msg)| SceneError::at(k(&format!("eos.{key}")), msg))?;
        if let Some(g) = m.shear_modulus {
            non_negative(&k("shear_modulus"), g)?;
        }
        if let Some(y) = m.yield_stress {
            non_negative(&k("yield_stress"), y)?;
        }
        validate_strength(m, &k)?;
    }
    Ok(())
}

/// Each body's keys; the bodies' names.
fn validate_bodies(scene: &Scene) -> Result<HashSet<&str>, SceneError> {
    let sim = &scene.simulation;
    let dim = sim.dimension as usize;
    if scene.bodies.is_empty() {
        return Err(SceneError::at("bodies", "at least one body is required"));
    }
    let mut names = HashSet::new();
    let mut constraint_names = HashSet::new();
    for (i, b) in scene.bodies.iter().enumerate() {
        let k = |f: &str| format!("bodies[{i}].{f}");
        if b.name.is_empty() {
            return Err(SceneError::at(k("name"), "must not be empty"));
        }
        if !names.insert(b.name.as_str()) {
            return Err(SceneError::at(
                k("name"),
                format!("duplicate body name '{}'", b.name),
            ));
        }
        if !scene.materials.contains_key(&b.material) {
            return Err(SceneError::at(
                k("material"),
                format!(
                    "unknown material '{}' (the scene defines: {})",
                    b.material,
                    listed(scene.materials.keys())
                ),
            ));
        }
        positive(&k("spacing"), b.spacing)?;
        if let Some(v) = &b.velocity {
            dimension_of(&k("velocity"), v, dim)?;
        }
        if let Some(super::VelocityField::Radial {
            center,
            speed,
            radius,
            exponent,
        }) = &b.velocity_field
        {
            let f = |x: &str| k(&format!("velocity_field.{x}"));
            dimension_of(&f("center"), center, dim)?;
            finite(&f("center"), center)?;
            finite(&f("speed"), &[*speed])?;
            positive(&f("radius"), *radius)?;
            non_negative(&f("exponent"), *exponent)?;
            if b.rigid {
                return Err(SceneError::at(
                    k("velocity_field"),
                    "a rigid body moves as one: give its velocity, not a field",
                ));
            }
        }
        if b.rigid && sim.interaction == Interaction::Kernel {
            return Err(SceneError::at(
                k("rigid"),
                "a rigid body needs simulation.interaction = \"penalty\"",
            ));
        }
        if let Some(j) = b.jitter {
            // Below half a spacing every particle stays inside its own cell:
            // no two particles of a body can meet or swap.
            if !(j.is_finite() && (0.0..0.5).contains(&j)) {
                return Err(SceneError::at(
                    k("jitter"),
                    format!("must be >= 0 and < 0.5 (a fraction of the spacing; got {j})"),
                ));
            }
        }
        validate_shape(&b.shape, dim, &k("shape"))?;
        constraints::validate_constraints(b, i, dim, &mut constraint_names)?;
        if scene.axisymmetric() {
            validate_revolution(&b.shape, &k("shape"))?;
        }
        if let Shape::Particles { file } = &b.shape {
            let rho0 = scene.materials.get(&b.material).map_or(1.0, |m| m.density);
            validate_particles(b, file, dim, rho0, scene.axisymmetric(), &k)?;
        }
    }
    Ok(names)
}

/// Each `[[contact.pairs]]` entry: two distinct known bodies, a pair named
/// once, a coefficient ≥ 0.
fn validate_contact_pairs(scene: &Scene, names: &HashSet<&str>) -> R {
    let Some(c) = &scene.contact else {
        return Ok(());
    };
    let mut seen = HashSet::new();
    for (k, p) in c.pairs.iter().enumerate() {
        let key = format!("contact.pairs[{k}].bodies");
        for b in &p.bodies {
            if !names.contains(b.as_str()) {
                return Err(SceneError::at(
                    key,
                    format!(
                        "unknown body '{b}' (the scene defines: {})",
                        listed(scene.bodies.iter().map(|b| &b.name))
                    ),
                ));
            }
        }
        let [a, b] = &p.bodies;
        if a == b {
            return Err(SceneError::at(key, format!("names '{a}' twice")));
        }
        if !seen.insert((a.min(b), a.max(b))) {
            return Err(SceneError::at(
                key,
                format!("the pair '{a}', '{b}' is named twice"),
            ));
        }
        non_negative(&format!("contact.pairs[{k}].friction"), p.friction)?;
        static_at_least(
            &format!("contact.pairs[{k}].static_friction"),
            p.static_friction,
            p.friction,
        )?;
    }
    Ok(())
}

/// The symmetry plane's keys (docs/scenes.md, "Symmetry planes"), and
/// what does not run with one.
fn validate_symmetry(scene: &Scene) -> R {
    if scene.symmetry.is_empty() {
        return Ok(());
    }
    let mut seen = [false; 2];
    for (i, p) in scene.symmetry.iter().enumerate() {
        let key = |k: &str| format!("symmetry[{i}]{k}");
        if scene.dim() != 2 {
            return Err(SceneError::at(
                key(""),
                format!(
                    "needs dimension = 2 (got {}; in 1-D a rigid wall is the symmetry point)",
                    scene.dim()
                ),
            ));
        }
        dimension_of(&key(".normal"), &p.normal, 2)?;
        dimension_of(&key(".point"), &p.point, 2)?;
        let n = &p.normal;
        if !(n[0] == 0.0 && n[1].abs() == 1.0 || n[1] == 0.0 && n[0].abs() == 1.0) {
            return Err(SceneError::at(
                key(".normal"),
                format!(
                    "must be [1, 0], [-1, 0], [0, 1] or [0, -1], pointing into the modelled half (got [{}, {}])",
                    n[0], n[1]
                ),
            ));
        }
        let (k, _) = p.axis();
        if std::mem::replace(&mut seen[k], true) {
            return Err(SceneError::at(
                key(".normal"),
                "one symmetry plane per coordinate axis: another plane already has this normal's axis",
            ));
        }
        if scene.axisymmetric() && k == 0 {
            return Err(SceneError::at(
                key(".normal"),
                "in a body of revolution a symmetry plane is normal to the axis ([0, 1] or [0, -1]): the axis itself is already a mirror",
            ));
        }
        if let Some(g) = scene.simulation.gravity.as_ref().filter(|g| g[k] != 0.0) {
            return Err(SceneError::at(
                "simulation.gravity",
                format!(
                    "has a component normal to the symmetry plane {key} ({}), which the mirrored half would feel reversed",
                    g[k],
                    key = key("")
                ),
            ));
        }
    }
    Ok(())
}

/// Each probe's keys, against the bodies' `names`.
fn validate_probes(scene: &Scene, names: &HashSet<&str>) -> R {
    let dim = scene.simulation.dimension as usize;
    let mut probe_names = HashSet::new();
    let known = |i: usize, key: &str, body: &str| -> R {
        if names.contains(body) {
            Ok(())
        } else {
            Err(SceneError::at(
                format!("probes[{i}].{key}"),
                format!(
                    "unknown body '{body}' (the scene defines: {})",
                    listed(scene.bodies.iter().map(|b| &b.name))
                ),
            ))
        }
    };
    for (i, p) in scene.probes.iter().enumerate() {
        let name = p.name();
        if name.is_empty() || name.contains([',', '"', '\n']) {
            return Err(SceneError::at(
                format!("probes[{i}].name"),
                "must be non-empty and contain no comma, quote or newline (it is a CSV column)",
            ));
        }
        if name == "time" || !probe_names.insert(name) {
            return Err(SceneError::at(
                format!("probes[{i}].name"),
                format!("duplicate probe name '{name}'"),
            ));
        }
        match p {
            Probe::Particle {
                body, at, quantity, ..
            } => {
                known(i, "body", body)?;
                dimension_of(&format!("probes[{i}].at"), at, dim)?;
                if quantity.needs_history() {
                    let b = scene.bodies.iter().find(|b| &b.name == body);
                    let carries =
                        b.is_some_and(|b| !b.rigid && scene.materials[&b.material].has_history());
                    if !carries {
                        return Err(SceneError::at(
                            format!("probes[{i}].quantity"),
                            format!(
                                "body '{body}' carries no plastic history: its material has no strength law, failure model or spall pressure"
                            ),
                        ));
                    }
                }
            }
            Probe::Body { body, .. } => known(i, "body", body)?,
            Probe::Contact { bodies, .. } => {
                known(i, "bodies", &bodies[0])?;
                known(i, "bodies", &bodies[1])?;
                if bodies[0] == bodies[1] {
                    return Err(SceneError::at(
                        format!("probes[{i}].bodies"),
                        "must name two different bodies",
                    ));
                }
            }
            Probe::Energy { .. } => {}
            Probe::Constraint { constraint, .. } => {
                let defined: Vec<String> = scene
                    .bodies
                    .iter()
                    .flat_map(|b| {
                        b.constraints
                            .iter()
                            .enumerate()
                            .map(move |(k, c)| constraint_name(b, k, c))
                    })
                    .collect();
                if !defined.contains(constraint) {
                    return Err(SceneError::at(
                        format!("probes[{i}].constraint"),
                        format!(
                            "unknown constraint '{constraint}' (the scene defines: {})",
                            if defined.is_empty() {
                                "none".to_string()
                            } else {
                                defined.join(", ")
                            }
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The strength, heating and failure keys of one material; `k` makes the
/// dotted key of a field.
fn validate_strength(m: &super::Material, k: &dyn Fn(&str) -> String) -> R {
    let g = m.shear_modulus.unwrap_or(0.0);
    if let Some(law) = &m.strength {
        if m.yield_stress.is_some() {
            return Err(SceneError::at(
                k("strength"),
                "give either yield_stress (perfect plasticity) or a strength law, not both",
            ));
        }
        if g <= 0.0 {
            return Err(SceneError::at(
                k("shear_modulus"),
                "a strength law needs a shear modulus > 0",
            ));
        }
        law.check()
            .map_err(|(key, msg)| SceneError::at(k(&format!("strength.{key}")), msg))?;
        match m.specific_heat {
            Some(cp) => positive(&k("specific_heat"), cp)?,
            None => return Err(SceneError::at(
                k("specific_heat"),
                "a strength law needs the specific heat (J/(kg K)) for the plastic work's heating",
            )),
        }
    } else if let Some(cp) = m.specific_heat {
        positive(&k("specific_heat"), cp)?;
    }
    if let Some(tq) = m.taylor_quinney {
        if !(tq.is_finite() && (0.0..=1.0).contains(&tq)) {
            return Err(SceneError::at(
                k("taylor_quinney"),
                format!("must be in [0, 1] (got {tq})"),
            ));
        }
    }
    if let Some(law) = &m.failure {
        law.check().map_err(|(key, msg)| {
            let at = if key.is_empty() {
                k("failure")
            } else {
                k(&format!("failure.{key}"))
            };
            SceneError::at(at, msg)
        })?;
        if m.strength.is_none() && m.yield_stress.is_none() {
            return Err(SceneError::at(
                k("failure"),
                "a damage law needs plastic strain: give yield_stress or a strength law",
            ));
        }
        if law.reads_temperature() && m.strength.is_some_and(|l| l.melt_temperature().is_none()) {
            return Err(SceneError::at(
                k("failure.d5"),
                "a temperature term needs the strength law's melt_temperature (its T* reads it)",
            ));
        }
    }
    if let Some(p) = m.spall_pressure {
        positive(&k("spall_pressure"), p)?;
    }
    if let Some(p) = m.cavitation_pressure {
        if p.is_nan() || p <= 0.0 {
            return Err(SceneError::at(
                k("cavitation_pressure"),
                format!("must be > 0, or inf for none (got {p})"),
            ));
        }
    }
    Ok(())
}

/// The rules that need the particles: empty shapes, overlapping bodies, and a
/// fixed `dt` above the CFL step at t = 0.
fn validate_placement(scene: &Scene) -> R {
    // Refuse before allocating: a spacing far too small for its shape would
    // otherwise exhaust memory instead of giving an error.
    let mut total = 0.0;
    for (i, b) in scene.bodies.iter().enumerate() {
        let n = estimated_particles(&b.shape, b.spacing);
        total += n;
        if total.is_nan() || total > MAX_PARTICLES {
            return Err(SceneError::at(
                format!("bodies[{i}].spacing"),
                format!(
                    "the scene would place about {total:.3e} particles (more than {MAX_PARTICLES:.0e}); increase the spacing"
                ),
            ));
        }
    }
    let placed = place_bodies(scene);
    for (i, p) in placed.iter().enumerate() {
        if p.positions.is_empty() {
            return Err(SceneError::at(
                format!("bodies[{i}].shape"),
                format!(
                    "body '{}' has no particle ({})",
                    scene.bodies[i].name,
                    if scene.symmetry.is_empty() {
                        "the shape is smaller than its spacing"
                    } else {
                        "the shape is smaller than its spacing, or lies beyond the symmetry plane"
                    }
                ),
            ));
        }
        constraints::validate_constrained(&scene.bodies[i], i, &p.positions)?;
        if let Some(field) = &scene.bodies[i].velocity_field {
            if let Some(x) = p.positions.iter().find(|&&x| field.at(x).is_none()) {
                return Err(SceneError::at(
                    format!("bodies[{i}].velocity_field.center"),
                    format!(
                        "a particle lies at the centre ({}, {}), where a radial field has no direction",
                        x.x, x.y
                    ),
                ));
            }
        }
    }

    // Overlap: any two particles of different bodies closer than half their
    // mean spacing. A hash grid of cell size max spacing keeps this O(N).
    if placed.len() > 1 {
        let cell = placed.iter().map(|p| p.spacing).fold(0.0, f64::max);
        let key = |x: f64, y: f64| ((x / cell).floor() as i64, (y / cell).floor() as i64);
        let mut grid: HashMap<(i64, i64), Vec<(usize, usize)>> = HashMap::new();
        for (b, p) in placed.iter().enumerate() {
            for (k, x) in p.positions.iter().enumerate() {
                grid.entry(key(x.x, x.y)).or_default().push((b, k));
            }
        }
        for (b, p) in placed.iter().enumerate() {
            for x in &p.positions {
                let (cx, cy) = key(x.x, x.y);
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        let Some(list) = grid.get(&(cx + dx, cy + dy)) else {
                            continue;
                        };
                        for &(b2, k2) in list {
                            if b2 <= b {
                                continue;
                            }
                            let lim = 0.25 * (p.spacing + placed[b2].spacing);
                            if x.distance(placed[b2].positions[k2]) < lim {
                                return Err(SceneError::at(
                                    format!("bodies[{b2}].shape"),
                                    format!(
                                        "body '{}' overlaps body '{}' near ({:e}, {:e})",
                                        scene.bodies[b2].name, scene.bodies[b].name, x.x, x.y
                                    ),
                                ));
                            }
                        }
                    }
                }
            }
        }
    }

    if let Some(dt) = scene.simulation.dt {
        let limit = cfl_step_at_start(scene, &placed);
        if dt > limit {
            return Err(SceneError::at(
                "simulation.dt",
                format!("{dt:e} s is above the CFL step at t = 0 ({limit:e} s)"),
            ));
        }
    }
    Ok(())
}

/// Names as an error lists them: sorted, comma-separated, `none` for none.
fn listed<'a>(names: impl Iterator<Item = &'a String>) -> String {
    let mut v: Vec<&str> = names.map(String::as_str).collect();
    v.sort_unstable();
    if v.is_empty() {
        "none".to_string()
    } else {
        v.join(", ")
    }
}

/// Largest number of particles a scene may place.
pub const MAX_PARTICLES: f64 = 2e8;

/// Particle count of a shape, from its length or area (before placing).
fn estimated_particles(shape: &Shape, dx: f64) -> f64 {
    use std::f64::consts::PI;
    match shape {
        Shape::Segment { from, to } => (to - from) / dx,
        Shape::Rectangle { min, max } => (max[0] - min[0]) * (max[1] - min[1]) / (dx * dx),
        Shape::Disk { radius, .. } => PI * radius * radius / (dx * dx),
        Shape::Ring {
            inner_radius,
            outer_radius,
            ..
        } => PI * (outer_radius * outer_radius - inner_radius * inner_radius) / (dx * dx),
        Shape::Polygon { vertices, .. } => {
            // The bounding box: an upper bound, cheap for any outline.
            let (lo, hi) = vertices.iter().fold(
                ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
                |(lo, hi), p| {
                    (
                        [lo[0].min(p[0]), lo[1].min(p[1])],
                        [hi[0].max(p[0]), hi[1].max(p[1])],
                    )
                },
            );
            (hi[0] - lo[0]) * (hi[1] - lo[1]) / (dx * dx)
        }
        // Counted when read (the file is no larger than it is).
        Shape::Particles { .. } => 0.0,
    }
}

/// The CFL step at t = 0 (docs/method.md §9): `C min h / (c_L + |v|)` over the
/// deformable bodies (a rigid body has no wave to resolve).
pub fn cfl_step_at_start(scene: &Scene, placed: &[super::PlacedBody]) -> f64 {
    let mut dt = f64::INFINITY;
    for (b, p) in scene.bodies.iter().zip(placed) {
        if b.rigid {
            continue;
        }
        let mat = MaterialModel::new(&scene.materials[&b.material]);
        let uniform = b
            .velocity
            .as_ref()
            .map_or(0.0, |v| v.iter().map(|x| x * x).sum::<f64>().sqrt());
        let v = p
            .velocities
            .iter()
            .map(|v| v.length())
            .fold(uniform, f64::max);
        let h = scene.simulation.smoothing_ratio * p.spacing;
        dt = dt.min(cfl_step(scene.simulation.cfl, h, mat.c_l, v));
    }
    dt
}
