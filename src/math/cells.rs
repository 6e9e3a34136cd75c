//! The cell list: particles sorted by the key of their cell (cells of side
//! at least the interaction reach), so that the particles within reach of a
//! point are among those of the 3 (1-D) or 3×3 (2-D) cells around it. Keys
//! are row-major over a grid that spans only the particles' bounding box,
//! so bodies far apart cost nothing extra; ties sort by particle index, so
//! every order is deterministic. The CPU's neighbour search
//! ([`crate::cpu::neighbours`]) and the model's set-up build on it; the
//! GPU's is `shaders/neighbours.wgsl`.

use glam::DVec2;
use rayon::prelude::*;

/// Particles sorted by cell key.
#[derive(Debug, Clone)]
pub struct CellList {
    pub cell: f64,
    pub origin: DVec2,
    /// Cells per row, padding included.
    pub nx: u64,
    /// `(key, particle)` sorted by key, then by particle index.
    pub sorted: Vec<(u64, u32)>,
}

impl CellList {
    pub fn build(x: &[DVec2], cell: f64) -> CellList {
        let mut list = CellList::grid(x, cell);
        let mut sorted: Vec<(u64, u32)> = x
            .par_iter()
            .enumerate()
            .map(|(i, p)| (list.key(*p), i as u32))
            .collect();
        sorted.par_sort_unstable();
        list.sorted = sorted;
        list
    }

    /// The grid [`CellList::build`] lays over `x`, with no particles
    /// sorted into it: its keys ([`CellList::key`]) give the order a 3×3
    /// scan of its cells visits particles in.
    pub fn grid(x: &[DVec2], cell: f64) -> CellList {
        let (lo, hi) = crate::math::bounds(x);
        // At least one padding cell on every side keeps the 3×3 scan inside
        // the grid; 1.5 so that rounding can never put the lowest particle
        // in cell 0 (whose lower neighbour would underflow).
        let origin = lo - DVec2::splat(1.5 * cell);
        let nx = ((hi.x - origin.x) / cell).floor() as u64 + 2;
        CellList {
            cell,
            origin,
            nx,
            sorted: Vec::new(),
        }
    }

    #[inline]
    pub fn coords(&self, p: DVec2) -> (u64, u64) {
        let d = (p - self.origin) / self.cell;
        (d.x.floor() as u64, d.y.floor() as u64)
    }

    /// The key of the cell holding `p` (row-major).
    #[inline]
    pub fn key(&self, p: DVec2) -> u64 {
        let (cx, cy) = self.coords(p);
        cy * self.nx + cx
    }

    /// Call `f(j)` for every particle in the cells within `rings` cells of
    /// `p`'s ((2 rings + 1)² cells in 2-D, 2 rings + 1 in a row in 1-D),
    /// clipped to the grid: every particle within `rings × cell` of `p`.
    #[inline]
    pub fn for_each_within(&self, p: DVec2, rings: u64, dim: usize, mut f: impl FnMut(usize)) {
        let (cx, cy) = self.coords(p);
        let top = self.sorted.last().map_or(0, |&(k, _)| k / self.nx);
        let rows = if dim == 1 {
            cy..=cy
        } else {
            cy.saturating_sub(rings)..=(cy + rings).min(top)
        };
        let (x0, x1) = (cx.saturating_sub(rings), (cx + rings).min(self.nx - 1));
        for row in rows {
            let (lo, hi) = (row * self.nx + x0, row * self.nx + x1);
            let start = self.sorted.partition_point(|&(k, _)| k < lo);
            for &(k, j) in &self.sorted[start..] {
                if k > hi {
                    break;
                }
                f(j as usize);
            }
        }
    }

    /// Call `f(j)` for every particle in the cells around `p`: the one
    /// ring of [`CellList::for_each_within`].
    #[inline]
    pub fn for_each_near(&self, p: DVec2, dim: usize, f: impl FnMut(usize)) {
        self.for_each_within(p, 1, dim, f);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four particles in cells of side 1: the keys, the order and the
    /// particles near each point, worked out by hand.
    #[test]
    fn cells_of_four_particles_by_hand() {
        let x = [
            DVec2::new(0.2, 0.2),
            DVec2::new(2.6, 0.4),
            DVec2::new(0.9, 0.1),
            DVec2::new(1.1, 1.9),
        ];
        let cells = CellList::build(&x, 1.0);
        // Bounds (0.2..2.6, 0.1..1.9): the origin 1.5 cells below the
        // lowest corner, (-1.3, -1.4); rows of floor(2.6 + 1.3) + 2 = 5.
        assert_eq!(cells.origin, DVec2::new(0.2, 0.1) - DVec2::splat(1.5));
        assert_eq!(cells.nx, 5);
        assert_eq!(cells.coords(x[0]), (1, 1));
        assert_eq!(cells.coords(x[1]), (3, 1));
        assert_eq!(cells.coords(x[2]), (2, 1));
        assert_eq!(cells.coords(x[3]), (2, 3));
        // Keys 5 cy + cx: 6, 8, 7, 17.
        assert_eq!(cells.sorted, vec![(6, 0), (7, 2), (8, 1), (17, 3)]);
        let near = |p: DVec2, dim: usize| {
            let mut v = Vec::new();
            cells.for_each_near(p, dim, |j| v.push(j));
            v
        };
        // Cell (1, 1) scans x 0..2 of rows 0..2: keys 6 and 7.
        assert_eq!(near(x[0], 2), vec![0, 2]);
        // Cell (2, 1): keys 6..8 of row 1; particle 3 is two rows up.
        assert_eq!(near(x[2], 2), vec![0, 2, 1]);
        // Cell (3, 1): keys 7..9.
        assert_eq!(near(x[1], 2), vec![2, 1]);
        // Cell (2, 3): rows 2..4, only key 17.
        assert_eq!(near(x[3], 2), vec![3]);
        // In 1-D only the point's own row is scanned: cell (2, 3) finds
        // nothing of row 1 or 2.
        assert_eq!(near(x[3], 1), vec![3]);
        assert_eq!(near(DVec2::new(1.6, 0.5), 1), vec![0, 2, 1]);
    }

    /// The rings around a particle find every particle within `rings ×
    /// cell` of it, at the grid's edges too: against every pair, on a
    /// scattered cloud.
    #[test]
    fn rings_find_every_particle_within_their_reach() {
        let x: Vec<DVec2> = (0..400u64)
            .map(|k| {
                // A fixed scatter over a 7 × 3 box.
                let a = (k * 7919 % 1000) as f64 / 1000.0;
                let b = (k * 104_729 % 997) as f64 / 997.0;
                DVec2::new(7.0 * a, 3.0 * b)
            })
            .collect();
        let cells = CellList::build(&x, 0.5);
        for rings in 1..4u64 {
            let reach = rings as f64 * 0.5;
            for (i, p) in x.iter().enumerate() {
                let mut found = Vec::new();
                cells.for_each_within(*p, rings, 2, |j| found.push(j));
                let mut want: Vec<usize> = (0..x.len())
                    .filter(|&j| x[j].distance(*p) < reach)
                    .collect();
                want.retain(|j| !found.contains(j));
                assert!(
                    want.is_empty(),
                    "rings {rings}, particle {i}: missed {want:?}"
                );
                let mut seen = found.clone();
                seen.sort_unstable();
                seen.dedup();
                assert_eq!(seen.len(), found.len(), "a particle found twice");
            }
        }
    }
}
