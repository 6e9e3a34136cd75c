//! Particle placement (docs/scenes.md, "Shapes and how particles are placed").
//!
//! Particles sit at cell centres, so a body's surface lies half a spacing
//! beyond its outer particles and bodies built touching start with zero gap.
//! Each particle also gets its *surface offset* `o`: the distance of its
//! centre to the shape's boundary (docs/method.md §8.3). The contact distance of a
//! pair is `o_i + o_j`, which is what keeps square-lattice disks from touching
//! along a flat facet.

use crate::math::circumference;
use glam::DVec2;
use std::f64::consts::PI;

use super::outline::{self, Polygon};
use super::{particles_file, surface};
use super::{Lattice, PolygonLattice, Scene, Shape};

/// The particles of one body, in placement order.
#[derive(Debug, Clone, Default)]
pub struct PlacedBody {
    pub positions: Vec<DVec2>,
    /// Mass per unit area (1-D) or per unit thickness (2-D), kg.
    pub masses: Vec<f64>,
    /// Distance of each centre to the shape's boundary, m.
    pub offsets: Vec<f64>,
    /// The spacing actually used (the scene's spacing rounded to fit the shape):
    /// sets `h = smoothing_ratio × spacing` and the penalty length `h0`.
    pub spacing: f64,
    /// Each particle's initial velocity where the shape gives them (a
    /// particles file with velocity columns); empty: the body's velocity.
    pub velocities: Vec<DVec2>,
}

fn cells(len: f64, spacing: f64) -> usize {
    (len / spacing).round().max(0.0) as usize
}

/// Place every body of a validated scene, with its optional jitter
/// (`jitter`). Both backends build their particles from this, so they get
/// the same positions.
pub fn place_bodies(scene: &Scene) -> Vec<PlacedBody> {
    scene
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let rho0 = scene.materials[&b.material].density;
            let axisymmetric = scene.axisymmetric();
            let mut placed = match &b.shape {
                Shape::Particles { file } => from_file(
                    file,
                    scene.dim(),
                    b.spacing,
                    scene.simulation.smoothing_ratio * b.spacing,
                    rho0,
                    axisymmetric,
                ),
                shape => {
                    let mut placed = place(shape, b.spacing, rho0, axisymmetric);
                    if let Some(fraction) = b.jitter.filter(|&j| j > 0.0) {
                        jitter(
                            &mut placed,
                            shape,
                            fraction,
                            b.seed.unwrap_or(i as u64),
                            axisymmetric,
                        );
                    }
                    if axisymmetric {
                        revolve(&mut placed);
                    }
                    placed
                }
            };
            for s in &scene.symmetry {
                cut(&mut placed, s);
            }
            if let Some(field) = &b.velocity_field {
                apply_field(&mut placed, b.velocity.as_deref(), field);
            }
            placed
        })
        .collect()
}

/// Each particle's velocity: the body's uniform one plus `field` at the
/// particle (validation has refused a particle at a radial field's
/// centre; one there would get the uniform part alone).
fn apply_field(placed: &mut PlacedBody, uniform: Option<&[f64]>, field: &super::VelocityField) {
    let u = uniform.map_or(DVec2::ZERO, |v| {
        DVec2::new(v[0], v.get(1).copied().unwrap_or(0.0))
    });
    placed.velocities = placed
        .positions
        .iter()
        .map(|&x| u + field.at(x).unwrap_or(DVec2::ZERO))
        .collect();
}

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny deterministic generator,
/// enough for placement noise and the same on every platform (no
/// dependency whose sequence could change with its version).
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[−1, 1)`, from the top 53 bits.
    fn symmetric(&mut self) -> f64 {
        2.0 * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    }
}

/// Displace every particle of `placed` by a uniform random amount in
/// `[−fraction, +fraction]·Δx` on each axis of the shape's dimension (Δx the
/// placed spacing), deterministically from `seed`.
///
/// Why the rest follows as it does:
/// * masses stay `ρ0 ×` the nominal cell volume: the jitter perturbs where a
///   particle sits, not how much matter it stands for, so the body's mass
///   and momentum are those of the regular lattice;
/// * the surface offsets are recomputed from the displaced centres (the
///   shape's surface has not moved): bodies built touching still start with
///   zero gap (docs/method.md §8.3's `d_c = o_i + o_j` follows the particles), and
///   a particle pushed past a curved surface gets offset 0 rather than a
///   negative one.
///
/// `fraction < 0.5` (validated) keeps each particle inside its own cell, so
/// the particle order along a segment is kept and no two particles meet.
fn jitter(placed: &mut PlacedBody, shape: &Shape, fraction: f64, seed: u64, axisymmetric: bool) {
    let mut rng = SplitMix64(seed);
    let amplitude = fraction * placed.spacing;
    let two_d = !matches!(shape, Shape::Segment { .. });
    let surface = surface_distance(shape, axisymmetric);
    for (p, o) in placed.positions.iter_mut().zip(placed.offsets.iter_mut()) {
        p.x += amplitude * rng.symmetric();
        if two_d {
            p.y += amplitude * rng.symmetric();
        }
        *o = surface(*p).max(0.0);
    }
}

/// Signed distance to the boundary of `shape` (positive inside), as a
/// function of the point: the surface offset `o` of a particle centred
/// there (docs/method.md §8.3). The one rule for placement and jitter
/// alike; a polygon's outline is prepared once, not for every particle.
/// In a body of revolution the axis is no surface: a side or edge lying on
/// it is left out.
fn surface_distance(shape: &Shape, axisymmetric: bool) -> Box<dyn Fn(DVec2) -> f64 + '_> {
    match shape {
        Shape::Segment { from, to } => Box::new(move |p| (p.x - from).min(to - p.x)),
        Shape::Rectangle { min, max } if axisymmetric && min[0] == 0.0 => {
            Box::new(move |p| (max[0] - p.x).min(p.y - min[1]).min(max[1] - p.y))
        }
        Shape::Rectangle { min, max } => Box::new(move |p| {
            (p.x - min[0])
                .min(max[0] - p.x)
                .min(p.y - min[1])
                .min(max[1] - p.y)
        }),
        Shape::Disk { center, radius, .. } => {
            let c = DVec2::new(center[0], center[1]);
            Box::new(move |p| annulus_offset(0.0, *radius, p.distance(c)))
        }
        Shape::Ring {
            center,
            inner_radius,
            outer_radius,
            ..
        } => {
            let c = DVec2::new(center[0], center[1]);
            Box::new(move |p| annulus_offset(*inner_radius, *outer_radius, p.distance(c)))
        }
        Shape::Polygon {
            vertices, holes, ..
        } => {
            let poly = Polygon::new(vertices, holes).off_axis(axisymmetric);
            Box::new(move |p| {
                let d = poly.distance(p);
                if poly.contains(p) {
                    d
                } else {
                    -d
                }
            })
        }
        // No outline: a file's offsets are its own or found from its
        // particles when placed (`from_file`).
        Shape::Particles { .. } => Box::new(|_| 0.0),
    }
}

/// The particles of a file ([`particles_file`]), of density `rho0`, with
/// the file's surface offsets or, without them, the offsets found from the
/// particles at smoothing length `h` ([`surface::offsets`]); empty if the
/// file cannot be read (validation has reported that). `spacing` is the
/// body's.
/// In a body of revolution a file's volumes and masses are its rings'
/// (m³, kg), and the offsets are found with the particles' mirror images
/// across the axis, which is no surface.
fn from_file(
    path: &std::path::Path,
    dim: usize,
    spacing: f64,
    h: f64,
    rho0: f64,
    axisymmetric: bool,
) -> PlacedBody {
    let Ok(t) = particles_file::read(path, dim) else {
        return PlacedBody {
            spacing,
            ..Default::default()
        };
    };
    let offsets = if !t.offset.is_empty() {
        t.offset.clone()
    } else if axisymmetric {
        let n = t.x.len();
        let mut x = t.x.clone();
        let mut area: Vec<f64> = (t.volumes(rho0).iter().zip(&t.x))
            .map(|(v, p)| v / circumference(p.x))
            .collect();
        for k in 0..n {
            if t.x[k].x < 2.0 * h {
                x.push(DVec2::new(-t.x[k].x, t.x[k].y));
                area.push(area[k]);
            }
        }
        let mut o = surface::offsets(&x, &area, h, dim);
        o.truncate(n);
        o
    } else {
        surface::offsets(&t.x, &t.volumes(rho0), h, dim)
    };
    PlacedBody {
        offsets,
        masses: t.masses(rho0),
        positions: t.x,
        spacing,
        velocities: t.v,
    }
}

/// Distance from radius `r` to the nearer circle of an annulus (the inner
/// one only for a ring, `r_in > 0`).
fn annulus_offset(r_in: f64, r_out: f64, r: f64) -> f64 {
    if r_in > 0.0 {
        (r_out - r).min(r - r_in)
    } else {
        r_out - r
    }
}

/// Keeps the particles of `placed` that `keep` marks (its velocities
/// too, where it has them).
fn pick(placed: &mut PlacedBody, keep: &[bool]) {
    fn pick<T>(v: &mut Vec<T>, keep: &[bool]) {
        let mut k = keep.iter();
        v.retain(|_| *k.next().unwrap_or(&true));
    }
    pick(&mut placed.positions, keep);
    pick(&mut placed.masses, keep);
    pick(&mut placed.offsets, keep);
    if !placed.velocities.is_empty() {
        pick(&mut placed.velocities, keep);
    }
}

/// The half of a body on the modelled side of a symmetry plane: the rest
/// is its mirror image. A particle within round-off of the plane is put
/// on it with half its mass, the half on this side (docs/method.md §13,
/// "Particles on the plane").
fn cut(placed: &mut PlacedBody, plane: &super::Symmetry) {
    let tol = 1e-9 * placed.spacing;
    let keep: Vec<bool> = placed
        .positions
        .iter()
        .map(|&p| plane.side(p) >= -tol)
        .collect();
    pick(placed, &keep);
    let (k, _) = plane.axis();
    for (x, m) in placed.positions.iter_mut().zip(&mut placed.masses) {
        if plane.side(*x).abs() <= tol {
            x[k] = plane.point[k];
            *m *= 0.5;
        }
    }
}

/// A body of revolution from its placed cross-section: the particles at
/// `r > 0` (a shape across the axis is symmetric about it: the rest are
/// their mirror images), each with the mass of its ring, `2π r` times its
/// mass per unit thickness.
fn revolve(placed: &mut PlacedBody) {
    let keep: Vec<bool> = placed.positions.iter().map(|p| p.x > 0.0).collect();
    pick(placed, &keep);
    for (m, p) in placed.masses.iter_mut().zip(&placed.positions) {
        *m *= circumference(p.x);
    }
}

/// Place one shape with nominal spacing `dx` and density `rho0`; in the
/// plane of a body of revolution when `axisymmetric`: the axis is no
/// surface, and a disk or ring centred on it on the polar lattice is placed
/// on half rings whose particles lie off the axis. The masses are still per
/// unit thickness ([`revolve`] makes them rings').
fn place(shape: &Shape, dx: f64, rho0: f64, axisymmetric: bool) -> PlacedBody {
    let mut out = PlacedBody {
        spacing: dx,
        ..Default::default()
    };
    // The direction of the half rings of a disk or ring centred on the
    // axis. (One centred on a symmetry plane is placed whole and cut: its
    // particles on the plane are halved, [`cut`].)
    let half = |center: &[f64]| (axisymmetric && center[0] == 0.0).then_some(DVec2::X);
    match shape {
        Shape::Segment { from, to } => {
            let surface = surface_distance(shape, axisymmetric);
            let n = cells(to - from, dx);
            if n == 0 {
                return out;
            }
            let d = (to - from) / n as f64;
            out.spacing = d;
            for k in 0..n {
                let x = from + (k as f64 + 0.5) * d;
                out.positions.push(DVec2::new(x, 0.0));
                out.masses.push(rho0 * d);
                out.offsets.push(surface(DVec2::new(x, 0.0)));
            }
        }
        Shape::Rectangle { min, max } => {
            let surface = surface_distance(shape, axisymmetric);
            let bounds = (DVec2::new(min[0], min[1]), DVec2::new(max[0], max[1]));
            square_lattice(&mut out, bounds, (dx, rho0), |_| true, surface);
        }
        Shape::Disk {
            center,
            radius,
            lattice,
        } => annulus(
            &mut out,
            center,
            (0.0, *radius),
            *lattice,
            dx,
            rho0,
            half(center),
        ),
        Shape::Ring {
            center,
            inner_radius,
            outer_radius,
            lattice,
        } => annulus(
            &mut out,
            center,
            (*inner_radius, *outer_radius),
            *lattice,
            dx,
            rho0,
            half(center),
        ),
        Shape::Polygon {
            vertices,
            holes,
            lattice: PolygonLattice::Boundary,
            ..
        } => {
            let poly = Polygon::new(vertices, holes);
            let surface = poly.clone().off_axis(axisymmetric);
            for p in outline::boundary_lattice(&poly, dx) {
                out.positions.push(p.x);
                out.masses.push(rho0 * p.area);
                out.offsets.push(surface.distance(p.x));
            }
        }
        Shape::Polygon {
            vertices,
            holes,
            lattice: PolygonLattice::Square,
            ..
        } => {
            // The square lattice fitted to the outline's bounding box, as a
            // rectangle's: a rectangle drawn as a polygon places the same
            // particles, bit for bit.
            let poly = Polygon::new(vertices, holes);
            let surface = poly.clone().off_axis(axisymmetric);
            let (min, max) = poly
                .outline()
                .iter()
                .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(*p), hi.max(*p))
                });
            square_lattice(
                &mut out,
                (min, max),
                (dx, rho0),
                |p| poly.contains(p),
                |p| surface.distance(p),
            );
        }
        // Read by `place_bodies`, which knows the scene's dimension.
        Shape::Particles { .. } => {}
    }
    out
}

/// The square lattice of spacing about `dx` (density `rho0`) fitted to the
/// box `(min, max)`: a whole number of cells each way, a particle at each
/// cell's centre that lies `inside`, with its `surface` offset.
fn square_lattice(
    out: &mut PlacedBody,
    (min, max): (DVec2, DVec2),
    (dx, rho0): (f64, f64),
    inside: impl Fn(DVec2) -> bool,
    surface: impl Fn(DVec2) -> f64,
) {
    let (nx, ny) = (cells(max.x - min.x, dx), cells(max.y - min.y, dx));
    if nx == 0 || ny == 0 {
        return;
    }
    let ddx = (max.x - min.x) / nx as f64;
    let ddy = (max.y - min.y) / ny as f64;
    out.spacing = (ddx * ddy).sqrt();
    for j in 0..ny {
        for i in 0..nx {
            let p = DVec2::new(
                min.x + (i as f64 + 0.5) * ddx,
                min.y + (j as f64 + 0.5) * ddy,
            );
            if inside(p) {
                out.positions.push(p);
                out.masses.push(rho0 * ddx * ddy);
                out.offsets.push(surface(p));
            }
        }
    }
}

/// A disk (`r_in = 0`) or a ring (radii `(r_in, r_out)`) on the square or
/// polar lattice; on the polar lattice's half rings `x > 0` when `half`.
fn annulus(
    out: &mut PlacedBody,
    center: &[f64],
    (r_in, r_out): (f64, f64),
    lattice: Lattice,
    dx: f64,
    rho0: f64,
    half: Option<DVec2>,
) {
    let c = DVec2::new(center[0], center[1]);
    // (From the lattice's own radius, not |p − c|, which differs from it
    // in the last bits.)
    let offset = |r: f64| annulus_offset(r_in, r_out, r);
    match lattice {
        Lattice::Square => {
            let n = (r_out / dx).ceil() as i64 + 1;
            for j in -n..n {
                for i in -n..n {
                    let d = DVec2::new((i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx);
                    let r = d.length();
                    if r < r_out && r >= r_in {
                        out.positions.push(c + d);
                        out.masses.push(rho0 * dx * dx);
                        out.offsets.push(offset(r));
                    }
                }
            }
        }
        Lattice::Polar => {
            let width = r_out - r_in;
            let k_rings = cells(width, dx);
            if k_rings == 0 {
                return;
            }
            let dr = width / k_rings as f64;
            out.spacing = dr;
            for k in 0..k_rings {
                let r = r_in + (k as f64 + 0.5) * dr;
                // docs/scenes.md: max(1, round(2π r_k K / radius)) for a disk; for a
                // ring the same rule reads 2π r_k / dr.
                let ring_area = PI * ((r + 0.5 * dr).powi(2) - (r - 0.5 * dr).powi(2));
                if let Some(n) = half {
                    // The same spacing along the half ring, the particles
                    // at the middles of its arcs, the outermost about
                    // dr/2 from the axis; a disk's innermost half ring
                    // (arc π dr/2) holds one particle, dr/2 from it (two
                    // would sit 0.35 dr from it).
                    let count = if k == 0 && r_in == 0.0 {
                        1
                    } else {
                        ((PI * r / dr).round() as usize).max(1)
                    };
                    let m = rho0 * 0.5 * ring_area / count as f64;
                    for q in 0..count {
                        let th = PI * ((q as f64 + 0.5) / count as f64 - 0.5);
                        // Turned from +x to the half's direction n.
                        let u = DVec2::new(th.cos(), th.sin());
                        out.positions
                            .push(c + r * DVec2::new(n.x * u.x - n.y * u.y, n.y * u.x + n.x * u.y));
                        out.masses.push(m);
                        out.offsets.push(offset(r));
                    }
                    continue;
                }
                let count = ((2.0 * PI * r / dr).round() as usize).max(1);
                let m = rho0 * ring_area / count as f64;
                for q in 0..count {
                    let th = 2.0 * PI * q as f64 / count as f64;
                    out.positions.push(c + r * DVec2::new(th.cos(), th.sin()));
                    out.masses.push(m);
                    out.offsets.push(offset(r));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests;
