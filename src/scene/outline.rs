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

/// Distance from `p` to the nearest edge of any of `rings`.
pub fn distance_to_edges(rings: &[&Ring], p: DVec2) -> f64 {
    rings
        .iter()
        .flat_map(|r| edges(r))
        .map(|(a, b)| segment_distance(p, a, b))
        .fold(f64::INFINITY, f64::min)
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
        assert_eq!(distance_to_edges(&[&sq], DVec2::new(0.5, 1.25)), 0.5);
        // Outside, beyond a corner: the distance to the corner.
        let d = distance_to_edges(&[&sq], DVec2::new(3.0, 3.0));
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
