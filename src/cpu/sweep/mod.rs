//! The optimised CPU solver's pair-once sweeps: each candidate pair
//! evaluated once and added to both of its particles, rows laid out in
//! chunks so that two threads never write one entry and every sum's order
//! is fixed by the lists alone. The solver's kinematic and forces passes
//! run on them ([`kinematics()`], [`momentum_energy`], the forces four pairs at a
//! time in vector lanes); the plain per-particle gathers of
//! [`super::kinematics`] and [`super::forces`], which read like their
//! shaders, are the twins they are tested against (`tests.rs`).

use rayon::prelude::*;

use super::neighbours::{pair, Nbr, Neighbours, BLOCK};
use crate::math::lanes::{F4, LANES};
use crate::model::{Frame, Model};
use crate::physics::kernel;

pub mod forces;
mod forces_lanes;
pub mod kinematics;
mod lane_terms;
#[cfg(test)]
mod tests;

pub use super::forces::PairVectors;
pub use forces::{energy_replay, momentum_energy, momentum_keeping, rates_and_dissipation};
pub use kinematics::{kinematics, kinematics_keeping, kinematics_seen};

/// Up to four candidates of one row with their kernel values in lanes
/// ([`Neighbours::sweep_chunks`]).
pub struct Chunk {
    /// The candidates; missing lanes repeat the last one.
    pub j: [u32; LANES],
    /// Bit k set where candidate k lies within `2 h_ij` (a pair).
    pub inside: u32,
    /// Near pairs (both sides add) or far pairs (i's side only).
    pub near: bool,
    /// `∇_i W_ij` (`W_ij` itself is not computed).
    pub gwx: F4,
    pub gwy: F4,
    /// `q²`, the squared distance in units of the pair's smoothing length.
    pub q2: F4,
    /// Where supports adapt, the pair's kernel normalisation `½ (√det Q_i
    /// + √det Q_j)` (`√Q_xx` in 1-D); `None` with round supports.
    pub scale: Option<F4>,
}

/// Particles per chunk of the pair sweep over the rows `start`/`list`: the
/// smallest power of two above the index distance `|j − i|` of 99 % of the
/// candidate pairs (the rest are far pairs, visited from both sides), and
/// no smaller than 256 particles or a 256th of them, so that a task is
/// worth scheduling. The chunk depends on the lists alone, so the order of
/// every sum, and every result, is the same whatever the thread count. In
/// the generated lattices neighbours are a few lattice rows apart (about
/// 700 indices in a 10⁵-particle disk).
fn chunk_len(start: &[u32], list: &[u32]) -> usize {
    let n = start.len().saturating_sub(1);
    // Pairs by the bit length of their index distance.
    let hist = (0..n)
        .into_par_iter()
        .fold(
            || [0u64; 33],
            |mut h, i| {
                for &j in &list[start[i] as usize..start[i + 1] as usize] {
                    h[(usize::BITS - (j as usize).abs_diff(i).leading_zeros()).min(32) as usize] +=
                        1;
                }
                h
            },
        )
        .reduce(
            || [0u64; 33],
            |mut a, b| {
                a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
                a
            },
        );
    let total: u64 = hist.iter().sum();
    let mut covered = 0;
    let mut bits = 0;
    for (b, &c) in hist.iter().enumerate() {
        covered += c;
        bits = b;
        if covered * 100 >= total * 99 {
            break;
        }
    }
    // Distances below 2^bits: a chunk of that size keeps them near.
    (1usize << bits).max(256).max(n / 256)
}

impl Neighbours {
    /// Partition every SPH row for the pair sweep and record where its
    /// segments end (the layout of [`Neighbours::fwd_end`]). The partition
    /// is stable, so indexing rows that are already indexed changes nothing.
    pub fn index_rows(&mut self) {
        self.index_rows_in(chunk_len(&self.start, &self.list));
    }

    /// [`Neighbours::index_rows`] with chunks of `chunk` particles.
    pub(in crate::cpu) fn index_rows_in(&mut self, chunk: usize) {
        let n = self.start.len().saturating_sub(1);
        let near = |i: usize, j: usize| (i / chunk).abs_diff(j / chunk) <= 1;
        // Rows in blocks: each block's rows are one contiguous run of the
        // list, partitioned in parallel with one scratch row per block.
        let mut pieces = Vec::with_capacity(n.div_ceil(BLOCK));
        let mut rest: &mut [u32] = &mut self.list;
        for b in 0..n.div_ceil(BLOCK) {
            let (lo, hi) = (b * BLOCK, ((b + 1) * BLOCK).min(n));
            let len = (self.start[hi] - self.start[lo]) as usize;
            let (piece, tail) = rest.split_at_mut(len);
            pieces.push((lo, hi, piece));
            rest = tail;
        }
        let start = &self.start;
        let ends: Vec<Vec<(u32, u32)>> = pieces
            .into_par_iter()
            .map(|(lo, hi, piece)| {
                let base = start[lo];
                let mut scratch = Vec::new();
                (lo..hi)
                    .map(|i| {
                        let (a, b) = ((start[i] - base) as usize, (start[i + 1] - base) as usize);
                        let row = &mut piece[a..b];
                        scratch.clear();
                        let iu = i as u32;
                        scratch.extend(row.iter().filter(|&&j| j > iu && near(i, j as usize)));
                        let fwd = scratch.len();
                        scratch.extend(row.iter().filter(|&&j| !near(i, j as usize)));
                        let far = scratch.len();
                        scratch.extend(row.iter().filter(|&&j| j < iu && near(i, j as usize)));
                        row.copy_from_slice(&scratch);
                        (start[i] + fwd as u32, start[i] + far as u32)
                    })
                    .collect()
            })
            .collect();
        (self.fwd_end, self.far_end) = ends.into_iter().flatten().unzip();
        let mut at = 0;
        self.visited = std::iter::once(0)
            .chain((0..n).map(|i| {
                at += self.far_end[i] - self.start[i];
                at
            }))
            .collect();
        self.chunk = chunk;
    }

    /// Every SPH pair within `2 h_ij` at positions `x`, each evaluated
    /// once, summed into `acc` (one entry per particle).
    ///
    /// A pair's kernel gradient and most of its terms are the same for both
    /// particles up to sign, so a near pair is visited once, from its lower
    /// index, and `pair(i, nbr, acc_i, Some(acc_j))` adds to both sides; a
    /// far pair (rows indexed by [`Neighbours::index_rows`]) is visited from
    /// both of its particles, and `pair(i, nbr, acc_i, None)` adds to i
    /// only. One function serves both, so i's side is written once.
    ///
    /// Writes to `acc_j` need `j` to be owned by the task too: chunks are
    /// taken in two phases, even chunks with their right neighbour and then
    /// odd ones, so two tasks never share an entry. Each entry then receives
    /// its terms in an order fixed by the lists and the chunk size alone,
    /// whatever the thread count.
    pub fn sweep<T, P>(&self, model: &Model, f: Frame, acc: &mut [T], pair_fn: P)
    where
        T: Send + Default,
        P: Fn(usize, &Nbr, &mut T, Option<&mut T>) + Sync,
    {
        // A store of zero-sized slots: no memory, and no work once inlined.
        let mut none = self.no_store();
        self.sweep_store(model, f, acc, &mut none, |i, b, ai, aj, _| {
            pair_fn(i, b, ai, aj)
        });
    }

    /// [`Neighbours::sweep`] of the two pairs each candidate makes where
    /// supports adapt: in the frame `f` and with the round supports of
    /// the bodies' `h`. `pair_fn(i, metric, round, acc_i, acc_j)` for each
    /// candidate that is a pair either way (`None` for the way it is not).
    pub fn sweep_two<T, P>(&self, model: &Model, f: Frame, acc: &mut [T], pair_fn: P)
    where
        T: Send + Default,
        P: Fn(usize, Option<&Nbr>, Option<&Nbr>, &mut T, Option<&mut T>) + Sync,
    {
        let mut none = self.no_store();
        self.sweep_two_store(model, f, acc, &mut none, |i, m, r, ai, aj, _| {
            pair_fn(i, m, r, ai, aj)
        });
    }

    /// [`Neighbours::sweep_two`] that also hands the pair function the
    /// candidate's slot of `store` (as [`Neighbours::sweep_store`], whose
    /// pairs are the frame's: the metric ones); the slots of candidates
    /// that are no pair in the frame are reset to the default.
    pub fn sweep_two_store<T, S, P>(
        &self,
        model: &Model,
        f: Frame,
        acc: &mut [T],
        store: &mut [S],
        pair_fn: P,
    ) where
        T: Send + Default,
        S: Send + Default,
        P: Fn(usize, Option<&Nbr>, Option<&Nbr>, &mut T, Option<&mut T>, &mut S) + Sync,
    {
        let round = Frame::round(f.x);
        self.rows_store(acc, store, |i, ai, piece, base, slots| {
            let inv_hi = 1.0 / model.h[i];
            let (s, fe, e) = self.row_ends(i);
            for (q, &j) in self.list[s..fe].iter().enumerate() {
                let (m, r) = (
                    pair(model, f, i, inv_hi, j),
                    pair(model, round, i, inv_hi, j),
                );
                let slot = &mut slots[q];
                if m.is_none() {
                    *slot = S::default();
                }
                if m.is_some() || r.is_some() {
                    // j is at most one chunk on: inside this task's piece.
                    let aj = Some(&mut piece[j as usize - base]);
                    pair_fn(i, m.as_ref(), r.as_ref(), ai, aj, slot);
                }
            }
            for (q, &j) in self.list[fe..e].iter().enumerate() {
                let (m, r) = (
                    pair(model, f, i, inv_hi, j),
                    pair(model, round, i, inv_hi, j),
                );
                let slot = &mut slots[fe - s + q];
                if m.is_none() {
                    *slot = S::default();
                }
                if m.is_some() || r.is_some() {
                    pair_fn(i, m.as_ref(), r.as_ref(), ai, None, slot);
                }
            }
        });
    }

    /// [`Neighbours::sweep`] that also hands the pair function the pair's
    /// slot of `store` (one per visited candidate, laid out by
    /// [`Neighbours::visited`]); the slots of candidates outside the support
    /// are reset to the default. A later pass reads them back with
    /// [`Neighbours::replay`] in the same order.
    pub fn sweep_store<T, S, P>(
        &self,
        model: &Model,
        f: Frame,
        acc: &mut [T],
        store: &mut [S],
        pair_fn: P,
    ) where
        T: Send + Default,
        S: Send + Default,
        P: Fn(usize, &Nbr, &mut T, Option<&mut T>, &mut S) + Sync,
    {
        self.rows_store(acc, store, |i, ai, piece, base, slots| {
            let inv_hi = 1.0 / model.h[i];
            let (s, fe, e) = self.row_ends(i);
            for (q, &j) in self.list[s..fe].iter().enumerate() {
                match pair(model, f, i, inv_hi, j) {
                    // j is at most one chunk on: inside this task's piece.
                    Some(b) => pair_fn(
                        i,
                        &b,
                        ai,
                        Some(&mut piece[j as usize - base]),
                        &mut slots[q],
                    ),
                    None => slots[q] = S::default(),
                }
            }
            for (q, &j) in self.list[fe..e].iter().enumerate() {
                let slot = &mut slots[fe - s + q];
                match pair(model, f, i, inv_hi, j) {
                    Some(b) => pair_fn(i, &b, ai, None, slot),
                    None => *slot = S::default(),
                }
            }
        });
    }

    /// The pairs of the last [`Neighbours::sweep_store`] (or
    /// [`Neighbours::sweep_chunks_store`]) again, from their slots alone
    /// (no positions, no kernel), in the sweep's order and with its task
    /// layout: `pair_fn(i, j, slot, acc_i, acc_j)`, `acc_j` `None` for a
    /// far pair. Slots of candidates outside the support hold the default.
    pub fn replay<T, S, P>(&self, acc: &mut [T], store: &[S], pair_fn: P)
    where
        T: Send + Default,
        S: Sync,
        P: Fn(usize, usize, &S, &mut T, Option<&mut T>) + Sync,
    {
        self.replay_rows(acc, store, |i, ai, near, far, piece, base| {
            for (&j, slot) in near.0.iter().zip(near.1) {
                let j = j as usize;
                pair_fn(i, j, slot, ai, Some(&mut piece[j - base]));
            }
            for (&j, slot) in far.0.iter().zip(far.1) {
                pair_fn(i, j as usize, slot, ai, None);
            }
        });
    }

    /// [`Neighbours::replay`] a row at a time: `row(i, acc_i, near,
    /// far, piece, base)` with the row's near partners and their slots
    /// (`acc_j` is `piece[j − base]`) and its far partners and theirs
    /// (i's side only), for loops that run over a row's pairs themselves.
    pub fn replay_rows<T, S, R>(&self, acc: &mut [T], store: &[S], row: R)
    where
        T: Send + Default,
        S: Sync,
        R: Fn(usize, &mut T, (&[u32], &[S]), (&[u32], &[S]), &mut [T], usize) + Sync,
    {
        let n = acc.len();
        assert_eq!(
            store.len(),
            self.visited[n] as usize,
            "a store of this sweep's pairs"
        );
        self.rows(acc, |i, ai, piece, base| {
            let (s, f, e) = self.row_ends(i);
            let slots = &store[self.visited[i] as usize..self.visited[i + 1] as usize];
            let (near, far) = slots.split_at(f - s);
            row(
                i,
                ai,
                (&self.list[s..f], near),
                (&self.list[f..e], far),
                piece,
                base,
            );
        });
    }

    /// A store of zero-sized slots for sweeps that keep nothing.
    pub(in crate::cpu) fn no_store(&self) -> Vec<()> {
        vec![(); self.store_len()]
    }

    /// Slots a store for [`Neighbours::sweep_store`] needs.
    pub fn store_len(&self) -> usize {
        self.visited.last().map_or(0, |&t| t as usize)
    }

    /// [`Neighbours::sweep`] four candidates at a time, for passes whose
    /// pair terms run in SIMD lanes: `chunk(i, c, acc_i, piece, base)` for
    /// each [`Chunk`] of row i's candidates in the sweep's order, near
    /// chunks (both sides add: particle j's entry is `piece[j − base]`)
    /// before far ones (i's side only). A pass that adds lane k's terms
    /// only where `c.inside` has bit k, in lane order, sums what the sweep
    /// sums in the sweep's order. No buffer between the kernel and the
    /// terms: a chunk's candidates go from the list straight into lanes
    /// (a row buffer of pairs cost the momentum pass a fifth of its time).
    /// The kinematic pass stays on [`Neighbours::sweep`]: its terms are
    /// few, and in lanes, with or without a buffer, it ran 16–44 % slower.
    pub fn sweep_chunks<T, R>(&self, model: &Model, f: Frame, acc: &mut [T], chunk: R)
    where
        T: Send + Default,
        R: Fn(usize, &Chunk, &mut T, &mut [T], usize) + Sync,
    {
        let mut none = self.no_store();
        self.sweep_chunks_store(model, f, acc, &mut none, |i, c, ai, piece, base, _| {
            chunk(i, c, ai, piece, base)
        });
    }

    /// [`Neighbours::sweep_chunks`] that also hands each chunk its
    /// candidates' slots of `store` (as [`Neighbours::sweep_store`]); a
    /// chunk with no pair is not handed on, its slots reset to the default.
    pub fn sweep_chunks_store<T, S, R>(
        &self,
        model: &Model,
        f: Frame,
        acc: &mut [T],
        store: &mut [S],
        chunk: R,
    ) where
        T: Send + Default,
        S: Send + Default,
        R: Fn(usize, &Chunk, &mut T, &mut [T], usize, &mut [S]) + Sync,
    {
        let x = f.x;
        let h = &model.h[..x.len()];
        let top = x.len().saturating_sub(1);
        self.rows_store(acc, store, |i, ai, piece, base, slots| {
            let (hi, xi) = (h[i], x[i]);
            let inv_hi = 1.0 / hi;
            let (s, fe, e) = self.row_ends(i);
            for (near, at, cands) in [
                (true, 0, &self.list[s..fe]),
                (false, fe - s, &self.list[fe..e]),
            ] {
                for (m, c) in cands.chunks(LANES).enumerate() {
                    let at = at + m * LANES;
                    let slots = &mut slots[at..at + c.len()];
                    let last = c.len() - 1;
                    let j: [u32; LANES] = std::array::from_fn(|k| c[k.min(last)]);
                    let js = j.map(|j| (j as usize).min(top));
                    let dx = xi.x - F4::gather(|k| x[js[k]].x);
                    let dy = xi.y - F4::gather(|k| x[js[k]].y);
                    let (q2, gwx, gwy, scale) = if f.metric.is_empty() {
                        let hj = F4::gather(|k| h[js[k]]);
                        // As `pair`: h_ij's inverse by division only
                        // across bodies of different spacing.
                        let same = hj.eq(F4::splat(hi));
                        let inv_h = if same.bits() == 0b1111 {
                            F4::splat(inv_hi)
                        } else {
                            same.select(F4::splat(inv_hi), 2.0 / (hi + hj))
                        };
                        let q2 = (dx * dx + dy * dy) * inv_h * inv_h;
                        let g = kernel::grad_lanes(model.dim, q2, inv_h);
                        (q2, dx * g, dy * g, None)
                    } else {
                        let (q2, qdx, qdy, scale) =
                            kernel::pair_metric_lanes(model.dim, f.metric, i, &js, dx, dy);
                        let g = kernel::grad_pair_lanes(model.dim, q2, scale);
                        (q2, qdx * g, qdy * g, Some(scale))
                    };
                    // `!(q2 >= 4)` as in `w_grad`: a NaN position still
                    // reaches the sums (and the instability check).
                    let inside = !q2.ge(F4::splat(4.0)).bits() & ((1 << c.len()) - 1);
                    if inside == 0 {
                        slots.iter_mut().for_each(|s| *s = S::default());
                        continue;
                    }
                    let ch = Chunk {
                        j,
                        inside,
                        near,
                        gwx,
                        gwy,
                        q2,
                        scale,
                    };
                    chunk(i, &ch, ai, piece, base, slots);
                }
            }
        });
    }

    /// Row i's list from its start to the end of its near pairs and of its
    /// far pairs.
    #[inline]
    fn row_ends(&self, i: usize) -> (usize, usize, usize) {
        (
            self.start[i] as usize,
            self.fwd_end[i] as usize,
            self.far_end[i] as usize,
        )
    }

    /// The task layout every sweep shares: `row(i, acc_i, piece, base)` for
    /// every row, `piece` the task's entries from `base` on.
    fn rows<T, R>(&self, acc: &mut [T], row: R)
    where
        T: Send + Default,
        R: Fn(usize, &mut T, &mut [T], usize) + Sync,
    {
        let mut none = self.no_store();
        self.rows_store(acc, &mut none, |i, ai, piece, base, _| {
            row(i, ai, piece, base)
        });
    }

    /// [`Neighbours::rows`] that also hands each row its slots of `store`
    /// ([`Neighbours::visited`]): a task's rows' slots are one run of the
    /// store, split off before the tasks start.
    fn rows_store<T, S, R>(&self, acc: &mut [T], store: &mut [S], row: R)
    where
        T: Send + Default,
        S: Send,
        R: Fn(usize, &mut T, &mut [T], usize, &mut [S]) + Sync,
    {
        let n = acc.len();
        assert_eq!(self.fwd_end.len(), n, "rows not indexed for the sweep");
        assert_eq!(
            store.len(),
            self.visited[n] as usize,
            "a store for these rows"
        );
        let c = self.chunk;
        let vis = &self.visited;
        for phase in 0..2 {
            let off = phase * c;
            if off >= n {
                break;
            }
            // Each task's slots, in task order.
            let mut slots: Vec<&mut [S]> = Vec::with_capacity((n - off).div_ceil(2 * c));
            let mut rest: &mut [S] = &mut store[..];
            let mut at = 0;
            for r0 in (off..n).step_by(2 * c) {
                let (a, b) = (vis[r0] as usize, vis[(r0 + c).min(n)] as usize);
                let (_, tail) = std::mem::take(&mut rest).split_at_mut(a - at);
                let (mine, tail) = tail.split_at_mut(b - a);
                slots.push(mine);
                rest = tail;
                at = b;
            }
            acc[off..]
                .par_chunks_mut(2 * c)
                .zip(slots)
                .enumerate()
                .for_each(|(k, (piece, sl))| {
                    let base = off + 2 * k * c;
                    let sbase = vis[base] as usize;
                    for i in base..(base + c).min(n) {
                        // No other row of this task writes to i while
                        // i's row runs (its partners are all j > i), so its
                        // sums stay in registers until the row ends.
                        let mut ai = std::mem::take(&mut piece[i - base]);
                        let (a, b) = (vis[i] as usize - sbase, vis[i + 1] as usize - sbase);
                        row(i, &mut ai, piece, base, &mut sl[a..b]);
                        piece[i - base] = ai;
                    }
                });
        }
    }
}
