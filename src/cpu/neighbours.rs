//! Cell-list neighbour search (O(N)): particles sorted by the key of their
//! cell (cells of side `2 h_max`), each particle then scans the 3 (1-D) or
//! 3×3 (2-D) cells around its own. Keys are row-major over a grid that spans
//! only the particles' bounding box, so bodies far apart cost nothing extra,
//! and the sort is stable, so the neighbour order is deterministic.

use glam::DVec2;
use rayon::prelude::*;

use crate::model::Model;
use crate::physics::kernel;

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
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for p in x {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        // At least one padding cell on every side keeps the 3×3 scan inside
        // the grid; 1.5 so that rounding can never put the lowest particle
        // in cell 0 (whose lower neighbour would underflow).
        let origin = lo - DVec2::splat(1.5 * cell);
        let nx = ((hi.x - origin.x) / cell).floor() as u64 + 2;
        let mut list = CellList {
            cell,
            origin,
            nx,
            sorted: Vec::new(),
        };
        let mut sorted: Vec<(u64, u32)> = x
            .par_iter()
            .enumerate()
            .map(|(i, p)| {
                let (cx, cy) = list.coords(*p);
                (cy * nx + cx, i as u32)
            })
            .collect();
        sorted.par_sort_unstable();
        list.sorted = sorted;
        list
    }

    #[inline]
    pub fn coords(&self, p: DVec2) -> (u64, u64) {
        let d = (p - self.origin) / self.cell;
        (d.x.floor() as u64, d.y.floor() as u64)
    }

    /// Call `f(j)` for every particle in the cells around `p`.
    #[inline]
    pub fn for_each_near(&self, p: DVec2, dim: usize, mut f: impl FnMut(usize)) {
        let (cx, cy) = self.coords(p);
        let rows = if dim == 1 { cy..cy + 1 } else { cy - 1..cy + 2 };
        for row in rows {
            let lo = row * self.nx + cx - 1;
            let hi = row * self.nx + cx + 1;
            let start = self.sorted.partition_point(|&(k, _)| k < lo);
            for &(k, j) in &self.sorted[start..] {
                if k > hi {
                    break;
                }
                f(j as usize);
            }
        }
    }
}

/// One neighbour of particle i: `j`, `W_ij` and `∇_i W_ij` (with `h_ij`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nbr {
    pub j: u32,
    pub w: f64,
    pub gw: DVec2,
}

/// Neighbour lists in compressed rows.
#[derive(Debug, Clone, Default)]
pub struct Neighbours {
    /// SPH partners (same body in penalty mode, everyone in kernel mode).
    pub start: Vec<usize>,
    pub list: Vec<Nbr>,
    /// Particles of other bodies within `2 h_ij` (penalty mode): contact candidates.
    pub cross_start: Vec<usize>,
    pub cross: Vec<u32>,
}

impl Neighbours {
    #[inline]
    pub fn of(&self, i: usize) -> &[Nbr] {
        &self.list[self.start[i]..self.start[i + 1]]
    }

    #[inline]
    pub fn cross_of(&self, i: usize) -> &[u32] {
        &self.cross[self.cross_start[i]..self.cross_start[i + 1]]
    }
}

/// `W_ij` and `∇_i W_ij` for the pair, with `h_ij = (h_i + h_j)/2`.
#[inline]
pub fn pair_kernel(dim: usize, xi: DVec2, xj: DVec2, hij: f64) -> (f64, DVec2, f64) {
    let d = xi - xj;
    let r = d.length();
    let w = kernel::w(dim, r, hij);
    let gw = if r > 0.0 {
        d * (kernel::dw(dim, r, hij) / r)
    } else {
        DVec2::ZERO
    };
    (w, gw, r)
}

/// Mean number of neighbours per particle within `2 h_ij` at positions `x`
/// (SPH partners and other-body contact candidates together): the work
/// measure that goes with a throughput figure.
pub fn mean_neighbours(model: &Model, x: &[DVec2]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    let nb = find(model, x);
    (nb.list.len() + nb.cross.len()) as f64 / x.len() as f64
}

/// Build the neighbour lists of every particle.
pub fn find(model: &Model, x: &[DVec2]) -> Neighbours {
    let h_max = model.h.iter().cloned().fold(0.0, f64::max);
    let cells = CellList::build(x, 2.0 * h_max);
    let dim = model.dim;
    let split = model.contact;
    let per: Vec<(Vec<Nbr>, Vec<u32>)> = (0..x.len())
        .into_par_iter()
        .map(|i| {
            let mut own = Vec::new();
            let mut cross = Vec::new();
            cells.for_each_near(x[i], dim, |j| {
                if j == i {
                    return;
                }
                let hij = 0.5 * (model.h[i] + model.h[j]);
                let r = (x[i] - x[j]).length();
                if r >= 2.0 * hij {
                    return;
                }
                if split && model.body[i] != model.body[j] {
                    cross.push(j as u32);
                } else {
                    let (w, gw, _) = pair_kernel(dim, x[i], x[j], hij);
                    own.push(Nbr { j: j as u32, w, gw });
                }
            });
            (own, cross)
        })
        .collect();
    let mut nb = Neighbours {
        start: Vec::with_capacity(x.len() + 1),
        cross_start: Vec::with_capacity(x.len() + 1),
        ..Default::default()
    };
    nb.list.reserve(per.iter().map(|p| p.0.len()).sum());
    nb.start.push(0);
    nb.cross_start.push(0);
    for (own, cross) in per {
        nb.list.extend_from_slice(&own);
        nb.cross.extend_from_slice(&cross);
        nb.start.push(nb.list.len());
        nb.cross_start.push(nb.cross.len());
    }
    nb
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    /// The cell list finds exactly the pairs an O(N²) search finds, in a
    /// scattered 2-D cloud spanning many cells and two bodies.
    #[test]
    fn cell_list_equals_brute_force() {
        let text = r#"
[simulation]
dimension = 2
end_time = 1e-6
[materials.m]
density = 1000.0
eos = { kind = "linear", c0 = 1000.0 }
[[bodies]]
name = "a"
material = "m"
spacing = 0.1
shape = { kind = "disk", center = [0.0, 0.0], radius = 1.0, lattice = "polar" }
[[bodies]]
name = "b"
material = "m"
spacing = 0.13
shape = { kind = "rectangle", min = [1.01, -0.5], max = [2.0, 0.7] }
"#;
        let scene = Scene::from_toml_str(text, "test").unwrap();
        let (model, mut state) = Model::new(&scene);
        // Jitter positions deterministically so no pair sits on a lattice.
        let mut seed = 12345u64;
        for p in state.x.iter_mut() {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let a = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let b = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            *p += DVec2::new(a, b) * 0.08;
        }
        let nb = find(&model, &state.x);
        let n = state.x.len();
        let mut pairs_found = 0;
        for i in 0..n {
            let mut fast: Vec<u32> = nb.of(i).iter().map(|b| b.j).collect();
            fast.extend_from_slice(nb.cross_of(i));
            fast.sort();
            let mut slow = Vec::new();
            for j in 0..n {
                let hij = 0.5 * (model.h[i] + model.h[j]);
                if j != i && (state.x[i] - state.x[j]).length() < 2.0 * hij {
                    slow.push(j as u32);
                }
            }
            assert_eq!(fast, slow, "particle {i}");
            pairs_found += slow.len();
        }
        assert!(pairs_found > 10 * n, "a real neighbourhood: {pairs_found}");
        // Cross-body candidates exist and are symmetric.
        assert!(!nb.cross.is_empty());
        for i in 0..n {
            for &j in nb.cross_of(i) {
                assert!(nb.cross_of(j as usize).contains(&(i as u32)));
            }
        }
    }
}
