//! Polygon outlines for the `polygon` shape: area, inside test, distance to
//! the outline, and the checks a user's outline must pass (closed, simple,
//! holes inside it and apart).

use glam::DVec2;

/// A closed polygon: its vertices in order, the last joined to the first.
pub type Ring = [DVec2];

/// The edges of a closed polygon, `(a, b)` each.
fn edges(ring: &Ring) -> impl Iterator<Item = (DVec2, DVec2)> + '_ {
    (0..ring.len()).map(move |k| (ring[k], ring[(k + 1) % ring.len()]))
}

/// Signed area (shoelace): positive for a counter-clockwise outline.
pub fn signed_area(ring: &Ring) -> f64 {
    0.5 * edges(ring).map(|(a, b)| a.perp_dot(b)).sum::<f64>()
}

/// Whether `p` is inside the closed polygon (crossing number; a point on
/// an edge may go either way, and placement never puts a cell centre
/// there for a lattice fitted to the outline's box).
pub fn contains(ring: &Ring, p: DVec2) -> bool {
    let mut inside = false;
    for (a, b) in edges(ring) {
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if p.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Distance from `p` to the segment `ab`. Axis-parallel edges take the
/// plain coordinate difference where `p` projects inside them, so that a
/// polygon drawn as a rectangle gives the rectangle's surface offsets bit
/// for bit.
pub fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    if a.x == b.x && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y) {
        return (p.x - a.x).abs();
    }
    if a.y == b.y && p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) {
        return (p.y - a.y).abs();
    }
    let d = b - a;
    let t = ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
    p.distance(a + t * d)
}

/// Orientation of the triple `(a, b, c)`: the sign of `(b − a) × (c − a)`.
fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Whether `c`, collinear with `ab`, lies on the segment `ab`.
fn on_segment(a: DVec2, b: DVec2, c: DVec2) -> bool {
    c.x >= a.x.min(b.x) && c.x <= a.x.max(b.x) && c.y >= a.y.min(b.y) && c.y <= a.y.max(b.y)
}

/// Whether the closed segments `ab` and `cd` meet (crossing, touching or
/// overlapping).
pub fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let (o1, o2) = (orient(a, b, c), orient(a, b, d));
    let (o3, o4) = (orient(c, d, a), orient(c, d, b));
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    (o1 == 0.0 && on_segment(a, b, c))
        || (o2 == 0.0 && on_segment(a, b, d))
        || (o3 == 0.0 && on_segment(c, d, a))
        || (o4 == 0.0 && on_segment(c, d, b))
}

/// The first pair of edges `(k, l)` of `ring` that meet other than at the
/// vertex two neighbouring edges share; `None` for a simple polygon.
/// Edges are tested pairwise after a sort by their lowest x, so that only
/// edges whose x ranges overlap are compared.
pub fn self_intersection(ring: &Ring) -> Option<(usize, usize)> {
    let n = ring.len();
    let e: Vec<(DVec2, DVec2)> = edges(ring).collect();
    let mut order: Vec<usize> = (0..n).collect();
    let lo = |k: usize| e[k].0.x.min(e[k].1.x);
    let hi = |k: usize| e[k].0.x.max(e[k].1.x);
    order.sort_by(|&a, &b| lo(a).total_cmp(&lo(b)));
    for (s, &k) in order.iter().enumerate() {
        for &l in &order[s + 1..] {
            if lo(l) > hi(k) {
                break;
            }
            let (k, l) = (k.min(l), k.max(l));
            let adjacent = l == k + 1 || (k == 0 && l == n - 1);
            if adjacent {
                // Neighbours share one vertex; they must not fold back
                // onto each other.
                let (a, b) = e[k];
                let c = e[l].1;
                let (p, q, r) = if l == k + 1 {
                    (a, b, c)
                } else {
                    (e[l].0, a, b)
                };
                if orient(p, q, r) == 0.0 && (r - q).dot(p - q) > 0.0 {
                    return Some((k, l));
                }
                continue;
            }
            if segments_meet(e[k].0, e[k].1, e[l].0, e[l].1) {
                return Some((k, l));
            }
        }
    }
    None
}

/// Whether any edge of `a` meets any edge of `b`.
pub fn rings_meet(a: &Ring, b: &Ring) -> bool {
    edges(a).any(|(p, q)| edges(b).any(|(r, s)| segments_meet(p, q, r, s)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring(v: &[[f64; 2]]) -> Vec<DVec2> {
        v.iter().map(|&[x, y]| DVec2::new(x, y)).collect()
    }

    #[test]
    fn area_inside_and_distance_of_a_square() {
        let sq = ring(&[[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]);
        assert_eq!(signed_area(&sq), 4.0);
        let cw: Vec<DVec2> = sq.iter().rev().copied().collect();
        assert_eq!(signed_area(&cw), -4.0);
        assert!(contains(&sq, DVec2::new(0.5, 1.5)));
        assert!(!contains(&sq, DVec2::new(2.5, 1.0)));
        assert!(!contains(&sq, DVec2::new(-0.1, 1.0)));
        let square = Polygon::new(
            &[
                vec![0.0, 0.0],
                vec![2.0, 0.0],
                vec![2.0, 2.0],
                vec![0.0, 2.0],
            ],
            &[],
        );
        assert_eq!(square.area(), 4.0);
        assert_eq!(square.distance(DVec2::new(0.5, 1.25)), 0.5);
        // Outside, beyond a corner: the distance to the corner.
        let d = square.distance(DVec2::new(3.0, 3.0));
        assert!((d - 2f64.sqrt()).abs() < 1e-15);
        // A slanted edge: the distance from (0, 0) to x + y = 1 is 1/√2.
        let d = segment_distance(DVec2::ZERO, DVec2::new(1.0, 0.0), DVec2::new(0.0, 1.0));
        assert!((d - 0.5f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn self_intersections_are_found() {
        // A bow tie: edges 0 and 2 cross.
        let bow = ring(&[[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]);
        assert_eq!(self_intersection(&bow), Some((0, 2)));
        // An L shape is simple.
        let l = ring(&[
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ]);
        assert_eq!(self_intersection(&l), None);
        assert_eq!(signed_area(&l), 3.0);
        // A vertex touching another edge.
        let touch = ring(&[[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]]);
        assert!(self_intersection(&touch).is_some());
        // An edge folding back onto its neighbour.
        let fold = ring(&[[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
        assert!(self_intersection(&fold).is_some());
        let hole = ring(&[[0.5, 0.5], [1.5, 0.5], [1.5, 1.5]]);
        let sq = ring(&[[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]);
        assert!(!rings_meet(&sq, &hole));
        let across = ring(&[[1.5, 1.5], [2.5, 1.5], [2.5, 2.5]]);
        assert!(rings_meet(&sq, &across));
    }
}

/// A polygon with holes, prepared once: its outline counter-clockwise
/// and its holes clockwise (the material on every edge's left), for the
/// inside test and the distance to its boundary.
#[derive(Debug, Clone)]
pub struct Polygon {
    /// The outline first, then the holes.
    rings: Vec<Vec<DVec2>>,
    /// Whether edges on the line `x = 0` are left out of the distance (the
    /// axis of a body of revolution is no surface).
    off_axis: bool,
}

impl Polygon {
    /// From a scene's `vertices` and `holes` (`[x, y]` each).
    pub fn new(vertices: &[Vec<f64>], holes: &[Vec<Vec<f64>>]) -> Polygon {
        let ring = |v: &[Vec<f64>], ccw: bool| {
            let mut r: Vec<DVec2> = v.iter().map(|p| DVec2::new(p[0], p[1])).collect();
            if (signed_area(&r) > 0.0) != ccw {
                r.reverse();
            }
            r
        };
        let mut rings = vec![ring(vertices, true)];
        rings.extend(holes.iter().map(|h| ring(h, false)));
        Polygon {
            rings,
            off_axis: false,
        }
    }

    /// This polygon with its edges on `x = 0` left out of
    /// [`Polygon::distance`] when `axisymmetric`: the cross-section of a
    /// body of revolution, whose axis is no surface.
    pub fn off_axis(mut self, axisymmetric: bool) -> Polygon {
        self.off_axis = axisymmetric;
        self
    }

    pub fn outline(&self) -> &Ring {
        &self.rings[0]
    }

    /// Whether `p` lies inside the outline and inside no hole.
    pub fn contains(&self, p: DVec2) -> bool {
        contains(&self.rings[0], p) && !self.rings[1..].iter().any(|h| contains(h, p))
    }

    /// Distance from `p` to the nearest edge of the outline or a hole
    /// (but one on the axis, [`Polygon::off_axis`]).
    pub fn distance(&self, p: DVec2) -> f64 {
        self.rings
            .iter()
            .flat_map(|r| edges(r))
            .filter(|(a, b)| !(self.off_axis && a.x == 0.0 && b.x == 0.0))
            .map(|(a, b)| segment_distance(p, a, b))
            .fold(f64::INFINITY, f64::min)
    }

    /// The material's area: the outline's less the holes'.
    pub fn area(&self) -> f64 {
        self.rings.iter().map(|r| signed_area(r)).sum()
    }
}

/// One particle of a boundary-following lattice: its position, the area
/// it stands for and its depth below the outline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LayerParticle {
    pub x: DVec2,
    pub area: f64,
    pub depth: f64,
}

/// The boundary-following lattice of a polygon (`outer`, `holes`) at
/// spacing `dx`: layers of particles at depths `(k + ½) dx` below the
/// outline and around the holes, each layer the level curve of the
/// distance to the boundary, walked at spacing `dx`, until the layers
/// meet inside. The level curve at depth `d` is the edges moved `d`
/// inwards, meeting at mitre points at convex corners and joined by arcs
/// of radius `d` around reflex ones, less what lies nearer than `d` to
/// another edge. A particle stands for the band
/// of its layer, `dx` deep and its share of the curve long (the area
/// between two offsets of a polygon is exactly the middle curve's length
/// times their distance); the areas are then scaled to the polygon's area
/// so that the body's mass is exact.
pub fn boundary_lattice(poly: &Polygon, dx: f64) -> Vec<LayerParticle> {
    let area = poly.area();
    let step = dx / 16.0;
    let mut out = Vec::new();
    for k in 0.. {
        let d = (k as f64 + 0.5) * dx;
        let mut layer = Vec::new();
        for ring in &poly.rings {
            // The raw offset curve: each vertex moved `d` inwards (where
            // its edges turn left, the mitre point where the two moved
            // edges meet; where they turn right, an arc of radius `d`
            // around it), sampled every `step` along the closed polyline
            // through those points.
            let n = ring.len();
            let mut corners: Vec<DVec2> = Vec::new();
            for i in 0..n {
                let (a, b, c) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
                let (t1, t2) = ((b - a).normalize(), (c - b).normalize());
                let (n1, n2) = (t1.perp(), t2.perp());
                if t1.perp_dot(t2) >= 0.0 {
                    corners.push(b + d * (n1 + n2) / (1.0 + n1.dot(n2)));
                } else {
                    let (a0, a1) = (n1.to_angle(), n2.to_angle());
                    let mut sweep = a1 - a0;
                    if sweep > 0.0 {
                        sweep -= std::f64::consts::TAU;
                    }
                    let pieces = ((d * -sweep) / step).ceil().max(1.0) as usize;
                    for s in 0..=pieces {
                        let ang = a0 + sweep * (s as f64 / pieces as f64);
                        corners.push(b + d * DVec2::from_angle(ang));
                    }
                }
            }
            let mut samples: Vec<(DVec2, bool)> = Vec::new();
            for i in 0..corners.len() {
                let (p, q) = (corners[i], corners[(i + 1) % corners.len()]);
                let pieces = (p.distance(q) / step).ceil().max(1.0) as usize;
                for s in 0..pieces {
                    samples.push((p + (q - p) * (s as f64 / pieces as f64), false));
                }
            }
            for s in &mut samples {
                s.1 = poly.contains(s.0) && poly.distance(s.0) >= d * (1.0 - 1e-9);
            }
            layer.extend(walk(&samples, dx));
        }
        if layer.is_empty() {
            break;
        }
        let layer = thin(layer, 0.7 * dx);
        out.extend(layer.into_iter().map(|(x, len)| LayerParticle {
            x,
            area: dx * len,
            depth: d,
        }));
    }
    let total: f64 = out.iter().map(|p| p.area).sum();
    for p in &mut out {
        p.area *= area / total;
    }
    out
}

/// A layer without particles nearer than `min` to one kept before them:
/// where the layers from two sides of a thin part meet, the level curve
/// is walked from both. A dropped particle's curve length goes to the one
/// that kept it out.
fn thin(layer: Vec<(DVec2, f64)>, min: f64) -> Vec<(DVec2, f64)> {
    use std::collections::HashMap;
    let key = |p: DVec2| ((p.x / min).floor() as i64, (p.y / min).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    let mut kept: Vec<(DVec2, f64)> = Vec::with_capacity(layer.len());
    for (x, len) in layer {
        let (cx, cy) = key(x);
        let near = (-1..=1)
            .flat_map(|dy| (-1..=1).map(move |dx| (cx + dx, cy + dy)))
            .filter_map(|c| grid.get(&c))
            .flatten()
            .copied()
            .find(|&k| kept[k].0.distance(x) < min);
        match near {
            Some(k) => kept[k].1 += len,
            None => {
                grid.entry((cx, cy)).or_default().push(kept.len());
                kept.push((x, len));
            }
        }
    }
    kept
}

/// The runs of kept samples of a closed sampled curve, each walked at
/// spacing `dx`: particles at equal steps along the run (a whole closed
/// curve from its start, an open run centred), with the length of curve
/// each stands for.
fn walk(samples: &[(DVec2, bool)], dx: f64) -> Vec<(DVec2, f64)> {
    let n = samples.len();
    let mut runs: Vec<Vec<DVec2>> = Vec::new();
    let closed = samples.iter().all(|s| s.1);
    if closed {
        let mut r: Vec<DVec2> = samples.iter().map(|s| s.0).collect();
        r.push(samples[0].0);
        runs.push(r);
    } else if let Some(start) = samples.iter().position(|s| !s.1) {
        // Start after a dropped sample, so that no run wraps around.
        let mut cur: Vec<DVec2> = Vec::new();
        for k in 1..=n {
            let s = samples[(start + k) % n];
            if s.1 {
                cur.push(s.0);
            } else if !cur.is_empty() {
                runs.push(std::mem::take(&mut cur));
            }
        }
    }
    let mut out = Vec::new();
    for run in runs {
        let lens: Vec<f64> = run.windows(2).map(|w| w[0].distance(w[1])).collect();
        let total: f64 = lens.iter().sum();
        if total < 0.25 * dx {
            // A sliver of curve where the layers from two sides meet: too
            // short for a particle of its own (the areas are scaled to the
            // polygon's in the end).
            continue;
        }
        let count = ((total / dx).round() as usize).max(1);
        let seg = total / count as f64;
        // The arc lengths increase with j: one cursor along the run.
        let (mut k, mut start) = (0, 0.0);
        for j in 0..count {
            let s = if closed {
                j as f64 * seg
            } else {
                (j as f64 + 0.5) * seg
            };
            while k + 1 < lens.len() && s > start + lens[k] {
                start += lens[k];
                k += 1;
            }
            let t = if lens[k] > 0.0 {
                ((s - start) / lens[k]).clamp(0.0, 1.0)
            } else {
                0.0
            };
            out.push((run[k] + (run[k + 1] - run[k]) * t, seg));
        }
    }
    out
}

#[cfg(test)]
mod lattice_tests {
    use super::*;

    /// An L-shaped plate with a square hole on the boundary lattice: every
    /// particle inside the material at its layer's depth, none nearer
    /// another than 0.7 Δx (two layers are Δx apart, as their depths are;
    /// within a layer, where it is walked from two sides, the second
    /// walk's particles give way), the areas adding up to the polygon's,
    /// and the outer layer half a spacing below the outline.
    #[test]
    fn an_l_with_a_hole_fills_in_layers() {
        let dx = 1e-4;
        let ring = |v: &[[f64; 2]]| {
            v.iter()
                .map(|&[x, y]| DVec2::new(x, y) * 1e-3)
                .collect::<Vec<_>>()
        };
        let l = ring(&[
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 1.5],
            [1.5, 1.5],
            [1.5, 4.0],
            [0.0, 4.0],
        ]);
        let hole = ring(&[[0.5, 0.5], [0.5, 1.0], [1.0, 1.0], [1.0, 0.5]]);
        let scene = |r: &[DVec2]| r.iter().map(|q| vec![q.x, q.y]).collect::<Vec<_>>();
        let poly = Polygon::new(&scene(&l), &[scene(&hole)]);
        let p = boundary_lattice(&poly, dx);
        let area = signed_area(&l) - signed_area(&hole).abs();
        let sum: f64 = p.iter().map(|q| q.area).sum();
        assert!((sum / area - 1.0).abs() < 1e-12);
        let mut closest = f64::INFINITY;
        for (i, a) in p.iter().enumerate() {
            assert!(
                contains(&l, a.x) && !contains(&hole, a.x),
                "{} outside",
                a.x
            );
            let d = poly.distance(a.x);
            assert!(
                (d - a.depth).abs() < 1e-3 * dx,
                "depth {} against {}",
                d,
                a.depth
            );
            for b in &p[i + 1..] {
                closest = closest.min(a.x.distance(b.x));
            }
        }
        assert!(closest >= 0.7 * dx, "two particles {closest:e} apart");
        let outer = p.iter().filter(|q| q.depth == 0.5 * dx).count();
        // The outline's and the hole's perimeters (16 mm and 2 mm) at
        // 0.1 mm, less the corners' share.
        assert!((160..=190).contains(&outer), "{outer} in the outer layer");
        // The plate is 1.5 mm thick: seven and a half layers, so the
        // eighth meets its mirror image and the ninth is empty.
        assert!(p.iter().all(|q| q.depth < 8.0 * dx));
    }
}
