//! The work of the device's neighbour walks, counted on the host from the
//! device's own cell list.
//!
//! A GPU runs the threads of a group (a warp: 32 on NVIDIA hardware) in
//! lock step, so a walk's cost is not the candidates each particle visits
//! but the loop trips of each group: every row range of the stencil runs as
//! long as its longest lane's. [`GridView::count_walk`] repeats the stencil of
//! `row_span` (walk.wgsl) in the same f32 arithmetic over the cell list
//! read back from the device, and counts both: what a walk costs on a
//! device follows from these counts without one. The leapfrog's momentum
//! and energy walks visit only the pairs of the neighbour masks its
//! kinematic walk leaves (walk.wgsl); [`GridView::count_masked`] counts
//! them from the masks read back.

use serde::Serialize;

use super::layout::Params;

/// Threads of a group that step together (an NVIDIA warp).
pub const WARP: usize = 32;

/// Rows of the stencil and its reach in cells (walk.wgsl: `scan_rows`,
/// `REACH`).
const REACH: i32 = 2;

/// The work of one neighbour walk.
#[derive(Debug, Clone, Serialize)]
pub struct WalkWork {
    /// The kernel that walks (`kinematics`, `forces`, `contact_pass1`, ...).
    pub name: String,
    /// How many times a step runs it.
    pub per_step: u32,
    /// Particles whose threads walk (every particle, or the boundary set).
    pub walkers: usize,
    /// Mean candidates a walking particle visits (every place of its row
    /// ranges, the ones the filters reject included; in a masked walk, the
    /// pairs of its mask).
    pub candidates: f64,
    /// Mean loop trips of a group of [`WARP`] threads that holds a walking
    /// particle: the sum over the rows of the longest lane's range.
    pub group_trips: f64,
    /// Candidates over the lane trips groups run (`WARP` × trips): the
    /// share of lock-step lanes doing a visit.
    pub lane_use: f64,
}

/// The work of one step on the device.
#[derive(Debug, Clone, Serialize)]
pub struct StepWork {
    /// Compute dispatches of a step, the periodic reorder excluded.
    pub dispatches: u32,
    /// Neighbour walks over every particle a step.
    pub walks: u32,
    /// Walks over the boundary particles only (the contact's gathers).
    pub contact_walks: u32,
    /// Device bytes a particle.
    pub device_bytes_per_particle: f64,
    pub per_walk: Vec<WalkWork>,
}

/// A particle's cell and its place in the cell (walk.wgsl `home`).
fn home(x0: [f32; 4], u: [f32; 2], inv_cell: f32) -> ([i32; 2], [f32; 2]) {
    let p = [(x0[2] + u[0]) * inv_cell, (x0[3] + u[1]) * inv_cell];
    let f = [p[0].floor(), p[1].floor()];
    (
        [x0[0] as i32 + f[0] as i32, x0[1] as i32 + f[1] as i32],
        [p[0] - f[0], p[1] - f[1]],
    )
}

/// The bucket of a cell (walk.wgsl `bucket_of`).
fn bucket_of(c: [i32; 2], p: &Params) -> u32 {
    (c[0] as u32).wrapping_add((c[1] as u32).wrapping_mul(p.row_stride)) & (p.buckets - 1)
}

/// The device's cell list and the state it was built from, read back.
pub struct GridView<'a> {
    pub params: &'a Params,
    pub dim: usize,
    pub x0: &'a [[f32; 4]],
    pub u: &'a [[f32; 2]],
    /// Bucket starts, `buckets + 1` of them (neighbours.wgsl).
    pub bstart: &'a [u32],
}

impl GridView<'_> {
    /// Length of each row range of particle `i`'s stencil (walk.wgsl
    /// `row_span`); rows the support does not reach have none.
    fn row_lengths(&self, i: usize) -> [u32; 5] {
        let p = self.params;
        let (cell, frac) = home(self.x0[i], self.u[i], p.inv_cell);
        let rows = if self.dim == 1 { 1 } else { 5 };
        let mut out = [0; 5];
        for (row, len) in out.iter_mut().enumerate().take(rows) {
            let mut dy = row as i32 - REACH;
            let mut gap = 0.0f32;
            if self.dim == 1 {
                dy = 0;
            } else if dy > 0 {
                gap = dy as f32 - frac[1];
            } else if dy < 0 {
                gap = frac[1] - (dy + 1) as f32;
            }
            if gap >= p.reach {
                continue;
            }
            let w = (p.reach * p.reach - gap * gap).sqrt();
            let lo = ((frac[0] - w).floor() as i32).max(-REACH);
            let hi = ((frac[0] + w).floor() as i32).min(REACH);
            let b = bucket_of([cell[0] + lo, cell[1] + dy], p);
            let e = b + (hi - lo + 1) as u32;
            let end = if e <= p.buckets {
                self.bstart[e as usize]
            } else {
                self.bstart[(e - p.buckets) as usize] + p.n
            };
            *len = end - self.bstart[b as usize];
        }
        out
    }

    /// Count one walk, run `per_step` times a step: `walks(i)` says whether
    /// particle slot `i`'s thread walks. The threads of the others return at
    /// once, but share their groups with the walkers'; where the walkers are
    /// `listed` (the leapfrog's contact, dispatched over a list of them), a
    /// group is 32 walkers, taken here in slot order (the device's list is
    /// in the order its atomic counter gave, which changes the grouping but
    /// not the candidates).
    pub fn count_walk(
        &self,
        name: &str,
        per_step: u32,
        walks: &dyn Fn(usize) -> bool,
        listed: bool,
    ) -> WalkWork {
        let n = self.x0.len();
        let walkers: Vec<usize> = (0..n).filter(|&i| walks(i)).collect();
        let (mut candidates, mut groups, mut trips) = (0u64, 0usize, 0u64);
        let mut rest = walkers.as_slice();
        while let Some(&first) = rest.first() {
            // The walkers of one group: the next 32 of the list, or those
            // in the 32 slots from the first one's group start.
            let len = if listed {
                rest.len().min(WARP)
            } else {
                let end = (first / WARP + 1) * WARP;
                rest.iter().take_while(|&&i| i < end).count()
            };
            let mut longest = [0u32; 5];
            for &i in &rest[..len] {
                for (l, r) in longest.iter_mut().zip(self.row_lengths(i)) {
                    candidates += r as u64;
                    *l = (*l).max(r);
                }
            }
            groups += 1;
            trips += longest.iter().map(|&l| l as u64).sum::<u64>();
            rest = &rest[len..];
        }
        walk_work(name, per_step, walkers.len(), candidates, groups, trips)
    }

    /// Count one masked walk (every particle walks; forces.wgsl) from the
    /// device's neighbour masks (walk.wgsl): a particle visits the pairs
    /// its mask holds in one loop, a group as long as its fullest lane; a
    /// particle whose mask overflowed walks its row ranges in full, and its
    /// group runs those rows too.
    pub fn count_masked(&self, name: &str, per_step: u32, masks: &[[u32; 2]]) -> WalkWork {
        const FULL: u32 = 1 << 31;
        let n = self.x0.len();
        let (mut candidates, mut groups, mut trips) = (0u64, 0usize, 0u64);
        for g in (0..n).step_by(WARP) {
            let mut fullest = 0u32;
            let mut longest = [0u32; 5];
            for (i, m) in masks.iter().enumerate().take((g + WARP).min(n)).skip(g) {
                if m[1] & FULL != 0 {
                    for (l, r) in longest.iter_mut().zip(self.row_lengths(i)) {
                        candidates += r as u64;
                        *l = (*l).max(r);
                    }
                } else {
                    let pairs = m[0].count_ones() + m[1].count_ones();
                    candidates += pairs as u64;
                    fullest = fullest.max(pairs);
                }
            }
            groups += 1;
            trips += fullest as u64 + longest.iter().map(|&l| l as u64).sum::<u64>();
        }
        walk_work(name, per_step, n, candidates, groups, trips)
    }
}

fn walk_work(
    name: &str,
    per_step: u32,
    walkers: usize,
    candidates: u64,
    groups: usize,
    trips: u64,
) -> WalkWork {
    let per = |x: u64, of: u64| if of == 0 { 0.0 } else { x as f64 / of as f64 };
    WalkWork {
        name: name.to_string(),
        per_step,
        walkers,
        candidates: per(candidates, walkers as u64),
        group_trips: per(trips, groups as u64),
        lane_use: per(candidates, WARP as u64 * trips),
    }
}
