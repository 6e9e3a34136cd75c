//! The neighbours stage (twin of `shaders/neighbours.wgsl`): the cell list
//! ([`CellList`], cells of side `2 h_max` plus a skin), then each
//! particle's candidates from the 3 (1-D) or 3×3 (2-D) cells around its
//! own. The cell list's sort is stable, so the neighbour order is
//! deterministic. The solver keeps its lists, built with a skin, while no
//! particle has moved more than half the skin ([`Neighbours::still_valid`]),
//! and walks their rows in the layout of its pair-once sweeps
//! ([`super::sweep`]).

use glam::DVec2;
use rayon::prelude::*;
use std::sync::OnceLock;

use crate::math::cells::CellList;
use crate::math::Mirror;
use crate::model::{Frame, Model};
use crate::physics::kernel;
use crate::physics::support::Metric;

/// One neighbour of particle i: `j`, `W_ij`, `∇_i W_ij` and `q²`, the
/// squared distance in units of the pair's smoothing length (`r²/h_ij²`
/// with round supports); where supports adapt, `scale` is the pair
/// metric's `√det Q` (a volume in its units is the volume times it; 0
/// with round supports).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nbr {
    pub j: u32,
    pub w: f64,
    pub gw: DVec2,
    pub q2: f64,
    pub scale: f64,
}

/// Candidate neighbours in compressed rows: every particle within
/// `2 h_ij + skin` of particle i when the lists were built.
///
/// The kernel values are not stored: a pass computes `W_ij` and `∇_i W_ij`
/// from the current positions as it walks a row ([`Neighbours::of`]). Stored
/// pairs cost 32 bytes each, written once and read by every pass of every
/// evaluation, and at 10⁵ particles that traffic alone (≈ 60 MB per
/// evaluation) took longer than the arithmetic it saved. Four bytes per pair
/// plus the kernel recomputed in registers is what the GPU path does too.
///
/// With a skin the lists stay valid while no pair has closed by more than
/// the skin since they were built, so a solver rebuilds them only every
/// many steps ([`Neighbours::still_valid`]); the true pairs are exactly
/// the candidates closer than `2 h_ij`, whatever the skin.
#[derive(Debug, Clone, Default)]
pub struct Neighbours {
    /// Candidate SPH partners (same body in penalty mode, everyone in kernel mode).
    pub start: Vec<u32>,
    pub list: Vec<u32>,
    /// Candidate particles of other bodies (penalty mode): contact candidates.
    pub cross_start: Vec<u32>,
    pub cross: Vec<u32>,
    /// Extra reach beyond `2 h_ij` the lists were built with.
    pub skin: f64,
    /// Positions at the build.
    pub x_ref: Vec<DVec2>,
    /// Row layout for the pair sweep ([`Neighbours::sweep`]), set by
    /// [`Neighbours::index_rows`]: each SPH row holds its near partners
    /// `j > i` first (up to `fwd_end[i]`), then its far partners (up to
    /// `far_end[i]`), then its near partners `j < i`. Empty until indexed.
    pub fwd_end: Vec<u32>,
    pub far_end: Vec<u32>,
    /// Where each row's visited slots (its near `j > i` and far partners,
    /// `start[i]..far_end[i]`) begin in a per-pair store laid out row after
    /// row ([`Neighbours::sweep_store`]); `n + 1` entries, the last the
    /// total. Set with the row layout.
    pub visited: Vec<u32>,
    /// Particles per chunk of the sweep; near means in the same or an
    /// adjacent chunk.
    pub chunk: usize,
    /// Bodies of revolution and symmetry planes: each particle's candidate
    /// images across the axis or the plane (docs/method.md §12, §13), row
    /// i `image_start[i]..image_start[i + 1]` of `images`: itself first, then the SPH candidates whose mirror
    /// image lay within `2 h_ij + skin` of it at the build (an image is
    /// never nearer than its particle, so they are all candidates). Empty
    /// without a mirror. Derived from the rows and `x_ref`
    /// ([`Neighbours::index_images`]), not saved.
    pub image_start: Vec<u32>,
    pub images: Vec<u32>,
    /// With a symmetry plane and the penalty contact, each particle's
    /// contact candidates' images (docs/method.md §13): row i
    /// `cross_image_start[i]..cross_image_start[i + 1]` of `cross_images`,
    /// the particles of other bodies whose mirror image (of a kind of
    /// `Model::contact_images`, [`image_entry`]) lay within `2 h_ij +
    /// skin` of it at the build. Empty otherwise (the axis of a
    /// body of revolution has none). Derived as the image rows are.
    pub cross_image_start: Vec<u32>,
    pub cross_images: Vec<u32>,
    /// Where supports adapt, each particle's support at the build: a row
    /// holds the partners that can enter the pair's support before any
    /// support grows by [`REACH_MARGIN`] in some direction or any particle
    /// moves half the skin ([`Neighbours::still_valid`]). Empty with
    /// round supports.
    pub support_ref: Vec<Metric>,
    /// The build positions' cells for the test on relative displacements
    /// ([`Neighbours::still_valid`]), made the first time it is needed.
    pub moved_cells: OnceLock<MovedCells>,
}

/// The build positions in cells of the lists' widest reach, each cell with
/// the cells of its 5×5 block (3 in 1-D) at or after it: every pair that
/// can become a pair before some particle has moved half a cell lies in
/// one cell or two of one block ([`Neighbours::still_valid`]).
#[derive(Debug, Clone, Default)]
pub struct MovedCells {
    /// The cells' side: the lists' widest reach, skin included.
    side: f64,
    /// Each particle's cell.
    cell: Vec<u32>,
    /// Cell c's block, `block[block_start[c]..block_start[c + 1]]`.
    block_start: Vec<u32>,
    block: Vec<u32>,
}

impl MovedCells {
    fn new(x: &[DVec2], side: f64, dim: usize) -> Self {
        let key = |p: DVec2| {
            let k = |v: f64| (v / side).floor() as i64;
            (k(p.x), if dim == 1 { 0 } else { k(p.y) })
        };
        let keys: Vec<(i64, i64)> = x.iter().map(|&p| key(p)).collect();
        let mut cells = keys.clone();
        cells.sort_unstable();
        cells.dedup();
        let find = |k: &(i64, i64)| cells.binary_search(k).ok();
        let cell = keys.iter().map(|k| find(k).unwrap_or(0) as u32).collect();
        let ys = if dim == 1 { 0 } else { 2 };
        let (mut block_start, mut block) = (vec![0], Vec::new());
        for (c, &(kx, ky)) in cells.iter().enumerate() {
            for dx in -2..=2 {
                for dy in -ys..=ys {
                    if let Some(d) = find(&(kx + dx, ky + dy)).filter(|&d| d >= c) {
                        block.push(d as u32);
                    }
                }
            }
            block_start.push(block.len() as u32);
        }
        MovedCells {
            side,
            cell,
            block_start,
            block,
        }
    }

    /// Whether no two particles of one block have moved apart or together
    /// by more than `skin`: the diameter of the box around both cells'
    /// displacements `u = x − x_ref` at most the skin.
    fn within(&self, x: &[DVec2], x_ref: &[DVec2], skin: f64) -> bool {
        let cells = self.block_start.len() - 1;
        let mut lo = vec![DVec2::splat(f64::INFINITY); cells];
        let mut hi = vec![DVec2::splat(f64::NEG_INFINITY); cells];
        for ((&c, a), b) in self.cell.iter().zip(x).zip(x_ref) {
            let u = *a - *b;
            let c = c as usize;
            lo[c] = lo[c].min(u);
            hi[c] = hi[c].max(u);
        }
        let skin2 = skin * skin;
        (0..cells).all(|c| {
            let blk = &self.block[self.block_start[c] as usize..self.block_start[c + 1] as usize];
            blk.iter().all(|&d| {
                let d = d as usize;
                (hi[c].max(hi[d]) - lo[c].min(lo[d])).length_squared() <= skin2
            })
        })
    }
}

impl Neighbours {
    /// The SPH partners of particle `i` at positions `x`: candidates closer
    /// than `2 h_ij`, with `W_ij` and `∇_i W_ij`, in list order.
    #[inline]
    pub fn of<'a>(
        &'a self,
        model: &'a Model,
        f: Frame<'a>,
        i: usize,
    ) -> impl Iterator<Item = Nbr> + 'a {
        let inv_hi = 1.0 / model.h[i];
        self.candidates(i)
            .iter()
            .filter_map(move |&j| pair(model, f, i, inv_hi, j))
    }

    /// [`Neighbours::of`] and then [`Neighbours::images_of`]: each partner
    /// of particle i with the mirror it is an image across, if it is one
    /// (none is without mirrors).
    #[inline]
    pub fn with_images<'a>(
        &'a self,
        model: &'a Model,
        f: Frame<'a>,
        i: usize,
    ) -> impl Iterator<Item = (Nbr, Option<Mirror>)> + 'a {
        self.of(model, f, i)
            .map(|b| (b, None))
            .chain(self.images_of(model, f, i).map(|(b, _, m)| (b, Some(m))))
    }

    /// The mirror images of particle i's partners ([`Neighbours::images`])
    /// that lie within `2 h_ij` at positions `x`, with `W` and `∇_i W` at
    /// `x_i − x̄_j`, each one's slot in the row and the mirror it is an
    /// image across (`j` the particle's own index).
    #[inline]
    pub fn images_of<'a>(
        &'a self,
        model: &'a Model,
        f: Frame<'a>,
        i: usize,
    ) -> impl Iterator<Item = (Nbr, usize, Mirror)> + 'a {
        let inv_hi = 1.0 / model.h[i];
        self.image_candidates(i)
            .iter()
            .enumerate()
            .filter_map(move |(slot, &e)| {
                let (j, kind) = image_entry(e);
                let m = model.images[kind];
                let d = f.x[i] - m.point(f.x[j as usize]);
                let k = if f.metric.is_empty() {
                    let inv_h = pair_inv_h(model.h[i], model.h[j as usize], inv_hi);
                    kernel::w_grad_q(model.dim, d, d.length_squared(), inv_h)
                        .map(|(w, gw, q2)| (w, gw, q2, 0.0))
                } else {
                    // The image's support is the particle's, mirrored.
                    let qj = f.metric[j as usize].mirrored(&m);
                    kernel::w_grad_pair(model.dim, d, &f.metric[i], &qj)
                };
                k.map(|(w, gw, q2, scale)| {
                    (
                        Nbr {
                            j,
                            w,
                            gw,
                            q2,
                            scale,
                        },
                        slot,
                        m,
                    )
                })
            })
    }

    /// [`Neighbours::with_images`] with the round supports of the bodies'
    /// `h` whatever the scene's supports: the contact's boundary set,
    /// normals and areas, which are functions of the positions alone
    /// (docs/method.md, "Supports that follow the deformation").
    #[inline]
    pub fn round_with_images<'a>(
        &'a self,
        model: &'a Model,
        x: &'a [DVec2],
        i: usize,
    ) -> impl Iterator<Item = (Nbr, Option<Mirror>)> + 'a {
        self.with_images(model, Frame::round(x), i)
    }

    /// Particle i's candidate images (none without a mirror), as entries
    /// ([`image_entry`]).
    #[inline]
    pub fn image_candidates(&self, i: usize) -> &[u32] {
        match self.image_start.get(i..i + 2) {
            Some(&[a, b]) => &self.images[a as usize..b as usize],
            _ => &[],
        }
    }

    /// The particles with candidate images, ascending.
    pub fn image_rows(&self) -> impl Iterator<Item = usize> + '_ {
        self.image_start
            .windows(2)
            .enumerate()
            .filter(|(_, w)| w[1] > w[0])
            .map(|(i, _)| i)
    }

    /// Builds the image rows across the model's mirror (a body of
    /// revolution's axis, a symmetry plane) from the candidate rows and the
    /// positions at the build (after [`Neighbours::index_rows`], whose row
    /// order they keep); clears them without one.
    pub fn index_images(&mut self, model: &Model) {
        let (mut start, mut images) = (Vec::new(), Vec::new());
        if !model.images.is_empty() {
            let x = &self.x_ref;
            let h_max = model.h.iter().cloned().fold(0.0, f64::max);
            // As the rows (a mirror image's support is its particle's,
            // mirrored).
            let q = &self.support_ref;
            let adaptive = !q.is_empty();
            let reach = if adaptive {
                adaptive_reach(model, q, self.skin)
            } else {
                2.0 * h_max + self.skin
            };
            start.push(0);
            for i in 0..x.len() {
                for (kind, m) in model.images.iter().enumerate() {
                    // Every image lies at least as far from the particle
                    // as the particle lies from each of its lines.
                    if !m.within(x[i], reach) {
                        continue;
                    }
                    let cands = std::iter::once(i as u32).chain(self.candidates(i).iter().copied());
                    for j in cands {
                        let j_ = j as usize;
                        let round = model.h[i] + model.h[j_] + self.skin;
                        let d = x[i] - m.point(x[j_]);
                        let near = if adaptive {
                            near_adaptive(d, &q[i], &q[j_].mirrored(m), round, self.skin)
                        } else {
                            d.length_squared() < round * round
                        };
                        if near {
                            images.push(j | (kind as u32) << KIND_SHIFT);
                        }
                    }
                }
                start.push(images.len() as u32);
            }
        }
        self.image_start = start;
        self.images = images;
        self.index_cross_images(model);
    }

    /// The contact candidates' image rows ([`Neighbours::cross_images`])
    /// across a symmetry plane, from the contact rows: a pair of bodies
    /// cut by the plane meets across it as well.
    fn index_cross_images(&mut self, model: &Model) {
        let (mut start, mut images) = (Vec::new(), Vec::new());
        if !model.contact_images.is_empty() && !self.cross_start.is_empty() {
            let x = &self.x_ref;
            let h_max = model.h.iter().cloned().fold(0.0, f64::max);
            let reach = 2.0 * h_max + self.skin;
            start.push(0);
            for i in 0..x.len() {
                for (kind, m) in model.contact_images.iter().enumerate() {
                    if !m.within(x[i], reach) {
                        continue;
                    }
                    for &j in self.cross_of(i) {
                        let j_ = j as usize;
                        let round = model.h[i] + model.h[j_] + self.skin;
                        if (x[i] - m.point(x[j_])).length_squared() < round * round {
                            images.push(j | (kind as u32) << KIND_SHIFT);
                        }
                    }
                }
                start.push(images.len() as u32);
            }
        }
        self.cross_image_start = start;
        self.cross_images = images;
    }

    /// The particles of other bodies whose images are contact candidates
    /// of particle i (none without a symmetry plane), as entries
    /// ([`image_entry`]: the kind indexes `Model::contact_images`).
    #[inline]
    pub fn cross_images_of(&self, i: usize) -> &[u32] {
        match self.cross_image_start.get(i..i + 2) {
            Some(&[a, b]) => &self.cross_images[a as usize..b as usize],
            _ => &[],
        }
    }

    /// Raw candidate SPH partners of `i` (a superset of [`Neighbours::of`]).
    #[inline]
    pub fn candidates(&self, i: usize) -> &[u32] {
        &self.list[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// Candidate particles of other bodies near `i` (exactly those within
    /// `2 h_ij` in lists without a skin); the contact test itself rejects
    /// those beyond.
    #[inline]
    pub fn cross_of(&self, i: usize) -> &[u32] {
        &self.cross[self.cross_start[i] as usize..self.cross_start[i + 1] as usize]
    }

    /// Whether the lists still hold every pair in the frame `f`: no support
    /// has grown by [`REACH_MARGIN`], and no pair that could meet has
    /// closed by more than the skin since the build. Either no particle
    /// has moved more than half the skin, or (without a mirror) none has
    /// moved half the lists' widest reach and no two particles of one
    /// block of [`MovedCells`] have moved apart or together by more than
    /// the skin: a rod flying through its target keeps its lists while
    /// its own particles keep their places.
    pub fn still_valid(&self, model: &Model, f: Frame) -> bool {
        if self.x_ref.len() != f.x.len() || self.support_ref.len() != f.metric.len() {
            return false;
        }
        let grown = 1.0 / (REACH_MARGIN * REACH_MARGIN);
        if !f
            .metric
            .par_iter()
            .zip(self.support_ref.par_iter())
            .all(|(q, p)| q.least_ratio(p) >= grown)
        {
            return false;
        }
        let moved2 =
            f.x.par_iter()
                .zip(self.x_ref.par_iter())
                .map(|(a, b)| (*a - *b).length_squared())
                .reduce(|| 0.0, f64::max);
        if moved2 <= 0.25 * self.skin * self.skin {
            return true;
        }
        // A body that moves as a whole closes none of its pairs: what
        // matters is how far particles that can meet have moved apart or
        // together. Mirror images move against their particles, so with
        // a mirror the test stays on each particle's own displacement.
        if !model.images.is_empty() || !model.contact_images.is_empty() {
            return false;
        }
        let cells = self.moved_cells.get_or_init(|| {
            let h_max = model.h.iter().cloned().fold(0.0, f64::max);
            let side = if self.support_ref.is_empty() {
                2.0 * h_max + self.skin
            } else {
                adaptive_reach(model, &self.support_ref, self.skin)
            };
            MovedCells::new(&self.x_ref, side, model.dim)
        });
        4.0 * moved2 <= cells.side * cells.side && cells.within(f.x, &self.x_ref, self.skin)
    }

    /// Bytes the lists hold.
    pub fn bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(&self.start[..])
            + size_of_val(&self.list[..])
            + size_of_val(&self.cross_start[..])
            + size_of_val(&self.cross[..])
            + size_of_val(&self.x_ref[..])
            + size_of_val(&self.fwd_end[..])
            + size_of_val(&self.far_end[..])
            + size_of_val(&self.visited[..])
            + size_of_val(&self.image_start[..])
            + size_of_val(&self.images[..])
            + size_of_val(&self.cross_image_start[..])
            + size_of_val(&self.cross_images[..])
            + size_of_val(&self.support_ref[..])
    }
}

/// Where an image row's entry keeps its image's kind (an index into
/// [`Model::images`]): the bits above the particle's index.
const KIND_SHIFT: u32 = 30;

/// An image row's entry: the particle's index and its image's kind.
#[inline]
pub fn image_entry(e: u32) -> (u32, usize) {
    (e & ((1 << KIND_SHIFT) - 1), (e >> KIND_SHIFT) as usize)
}

/// Candidate `j` of particle `i` if it lies within the pair's support in
/// the frame `f` (within `2 h_ij` with round supports), with `W_ij`,
/// `∇_i W_ij` and `q²`; `inv_hi = 1/h_i`.
#[inline]
pub(super) fn pair(model: &Model, f: Frame, i: usize, inv_hi: f64, j: u32) -> Option<Nbr> {
    let d = f.x[i] - f.x[j as usize];
    let k = if f.metric.is_empty() {
        let inv_h = pair_inv_h(model.h[i], model.h[j as usize], inv_hi);
        kernel::w_grad_q(model.dim, d, d.length_squared(), inv_h)
            .map(|(w, gw, q2)| (w, gw, q2, 0.0))
    } else {
        kernel::w_grad_pair(model.dim, d, &f.metric[i], &f.metric[j as usize])
    };
    k.map(|(w, gw, q2, scale)| Nbr {
        j,
        w,
        gw,
        q2,
        scale,
    })
}

/// `1/h_ij` of a pair, `h_ij = (h_i + h_j)/2`, with `inv_hi = 1/h_i`: one
/// division only across bodies of different spacing (the same value from
/// either side: the sum commutes).
#[inline]
pub fn pair_inv_h(hi: f64, hj: f64, inv_hi: f64) -> f64 {
    if hj == hi {
        inv_hi
    } else {
        2.0 / (hi + hj)
    }
}

/// Mean number of neighbours per particle within `2 h_ij` at positions `x`
/// (SPH partners and other-body contact candidates together): the work
/// measure that goes with a throughput figure.
pub fn mean_neighbours(model: &Model, x: &[DVec2]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    // Lists without a skin hold exactly the pairs within `2 h_ij`.
    let nb = find(model, Frame::round(x));
    (nb.list.len() + nb.cross.len()) as f64 / x.len() as f64
}

/// Lists without a skin in the frame `f` (with round supports: exactly
/// the pairs within `2 h_ij`).
pub fn find(model: &Model, f: Frame) -> Neighbours {
    find_with_skin(model, f, 0.0)
}

/// How much a support may grow along any direction before the lists
/// built for it are rebuilt: 10 %.
pub const REACH_MARGIN: f64 = 1.1;

/// Whether particles `i` and `j` of one body, at separation `d` and with
/// supports `qi`, `qj` at the build, go into each other's rows where
/// supports adapt: within the round supports' `h_i + h_j` plus the skin
/// (the contact's boundary set and normals), or near enough to enter the
/// pair's support before the lists lapse. While no support grows by more
/// than [`REACH_MARGIN`] along any direction the pair's metric stays above
/// the build's over `REACH_MARGIN²`, so a pair in its support then has
/// `|d'|_Q < 2 REACH_MARGIN` in the build's metric `Q`, and `d'` lies
/// within half a skin of each particle's move from `d`.
#[inline]
fn near_adaptive(d: DVec2, qi: &Metric, qj: &Metric, round: f64, skin: f64) -> bool {
    if d.length_squared() < round * round {
        return true;
    }
    let q = qi.mean(qj);
    let reach = 2.0 * REACH_MARGIN + skin * q.largest().sqrt();
    q.quad(d) < reach * reach
}

/// The farthest two particles go into each other's rows where supports
/// adapt ([`near_adaptive`]): the largest major semi-axis times
/// `2 REACH_MARGIN`, plus the skin stretched by the largest aspect
/// ratio, or the round supports' reach.
fn adaptive_reach(model: &Model, metric: &[Metric], skin: f64) -> f64 {
    let (major, aspect) = metric
        .par_iter()
        .map(|q| {
            let (lo, hi) = q.axes();
            (hi, hi / lo)
        })
        .reduce(|| (0.0, 1.0), |a, b| (a.0.max(b.0), a.1.max(b.1)));
    reach_of(model, major, aspect, skin)
}

/// [`adaptive_reach`] from the largest major semi-axis and the largest
/// aspect ratio.
fn reach_of(model: &Model, major: f64, aspect: f64, skin: f64) -> f64 {
    let h_max = model.h.iter().cloned().fold(0.0, f64::max);
    (2.0 * REACH_MARGIN * major + skin * aspect).max(2.0 * h_max + skin)
}

/// The list build where supports adapt. Its rows hold the particles of
/// the 3×3 cells of side [`adaptive_reach`] around each particle that
/// [`near_adaptive`] passes, in those cells' order. Cells that wide hold
/// many times a row's partners wherever one support is drawn out, so the
/// build finds them in cells of the round reach instead, each particle
/// scanning as many rings of them as its own support can reach
/// ([`Wide::rings`]), keeps those inside the wide cells' 3×3 block and
/// puts them in the wide cells' order: the same rows, so the sums' order
/// and bits are kept.
struct Wide {
    /// The wide cells: each particle's `(column, row)` in them orders the
    /// rows.
    grid: CellList,
    at: Vec<(u32, u32)>,
    /// How many rings of round-reach cells each particle scans, and the
    /// square of how far its partners can be ([`Wide::reach`]).
    rings: Vec<u64>,
    reach2: Vec<f64>,
}

impl Wide {
    fn new(model: &Model, f: Frame, skin: f64, cell: f64) -> Wide {
        let x = f.x;
        let axes: Vec<(f64, f64)> = f.metric.par_iter().map(|q| q.axes()).collect();
        // The largest major semi-axis and aspect ratio (as
        // `adaptive_reach`, from the axes taken once), the smallest minor.
        let (a_max, aspect, b_min) = axes
            .iter()
            .fold((0.0f64, 1.0f64, f64::INFINITY), |m, &(lo, hi)| {
                (m.0.max(hi), m.1.max(hi / lo), m.2.min(lo))
            });
        let grid = CellList::grid(x, reach_of(model, a_max, aspect, skin));
        let at = x
            .par_iter()
            .map(|p| {
                let (cx, cy) = grid.coords(*p);
                (cx as u32, cy as u32)
            })
            .collect();
        let reach: Vec<f64> = axes
            .par_iter()
            .map(|&(lo, hi)| Wide::reach(lo, hi, b_min, a_max, skin).max(cell))
            .collect();
        let rings = reach.iter().map(|r| (r / cell).ceil() as u64).collect();
        let reach2 = reach.iter().map(|r| r * r).collect();
        Wide {
            grid,
            at,
            rings,
            reach2,
        }
    }

    /// The farthest a particle with semi-axes `(b, a)` can be from one it
    /// lists by its support ([`near_adaptive`]), `b_min` the smallest minor
    /// semi-axis and `a_max` the largest major one. The pair's metric is
    /// the mean of the two, so `dᵀ Q_ij d ≥ ½ |d|² (1/a² + 1/a_max²)` and
    /// its largest eigenvalue is at most `½ (1/b² + 1/b_min²)`; a pair
    /// within `2 REACH_MARGIN + skin √λ` in it is within
    ///
    /// ```text
    /// (2 REACH_MARGIN + skin √(½ (1/b² + 1/b_min²))) √(2 / (1/a² + 1/a_max²)),
    /// ```
    ///
    /// widened by a part in 10⁹ against rounding. (The round partners,
    /// within the round reach, are within the one ring of cells of that
    /// side.)
    fn reach(b: f64, a: f64, b_min: f64, a_max: f64, skin: f64) -> f64 {
        let lam = 0.5 * (1.0 / (b * b) + 1.0 / (b_min * b_min));
        let bound = 2.0 * REACH_MARGIN + skin * lam.sqrt();
        bound * (2.0 / (1.0 / (a * a) + 1.0 / (a_max * a_max))).sqrt() * (1.0 + 1e-9)
    }

    /// Whether scanning the rings of cells of side `cell` visits fewer
    /// particles than the 3 (1-D) or 3×3 (2-D) wide cells would: where
    /// every support is near round the wide cells are hardly wider, and
    /// the rings' two or more a side scan more.
    fn pays(&self, dim: usize, cell: f64) -> bool {
        let span = |r: u64| (2 * r + 1) as f64;
        let (rings, wide): (f64, f64) = if dim == 1 {
            let rings = self.rings.iter().map(|&r| span(r)).sum::<f64>() * cell;
            (rings, 3.0 * self.grid.cell * self.rings.len() as f64)
        } else {
            let rings = self.rings.iter().map(|&r| span(r) * span(r)).sum::<f64>() * cell * cell;
            (
                rings,
                9.0 * self.grid.cell * self.grid.cell * self.rings.len() as f64,
            )
        };
        rings < wide
    }

    /// Whether `j` is in the wide cells' 3 (1-D) or 3×3 (2-D) block
    /// around `i`'s.
    #[inline]
    fn same_block(&self, i: usize, j: usize, dim: usize) -> bool {
        let ((ci, ri), (cj, rj)) = (self.at[i], self.at[j]);
        ci.abs_diff(cj) <= 1
            && if dim == 1 {
                ri == rj
            } else {
                ri.abs_diff(rj) <= 1
            }
    }

    /// A row in the wide cells' order: by cell (row-major), then by
    /// particle.
    fn order(&self, row: &mut [u32]) {
        row.sort_unstable_by_key(|&j| {
            let (c, r) = self.at[j as usize];
            (r, c, j)
        });
    }
}

/// Whether [`find_with_skin`] scans rings of cells for the frame `f`.
#[cfg(test)]
pub(in crate::cpu) fn rings_pay(model: &Model, f: Frame, skin: f64) -> bool {
    let round = 2.0 * model.h.iter().cloned().fold(0.0, f64::max) + skin;
    Wide::new(model, f, skin, round).pays(model.dim, round)
}

/// Particles per block of the parallel list build: large enough that the
/// per-block vectors amortise, small enough to balance two to many cores.
pub(in crate::cpu) const BLOCK: usize = 2048;

/// Build the candidate lists of every particle in the frame `f`: all
/// particles within `2 h_ij + skin` (where supports adapt, the SPH
/// partners within twice the smaller of the two particles' reaches plus
/// the skin), SPH partners and other-body candidates apart.
pub fn find_with_skin(model: &Model, f: Frame, skin: f64) -> Neighbours {
    find_scanning(model, f, skin, true)
}

/// [`find_with_skin`], where supports adapt scanning rings of cells
/// ([`Wide`]) only with `rings` and where they pay.
pub(in crate::cpu) fn find_scanning(model: &Model, f: Frame, skin: f64, rings: bool) -> Neighbours {
    let x = f.x;
    let adaptive = !f.metric.is_empty();
    let h_max = model.h.iter().cloned().fold(0.0, f64::max);
    let round = 2.0 * h_max + skin;
    let dim = model.dim;
    let (cells, wide) = match adaptive.then(|| Wide::new(model, f, skin, round)) {
        Some(w) if rings && w.pays(dim, round) => (CellList::build(x, round), Some(w)),
        Some(w) => (CellList::build(x, w.grid.cell), None),
        None => (CellList::build(x, round), None),
    };
    let split = model.contact;
    let n = x.len();
    // Each block of particles fills its own rows; the blocks are then joined
    // in order, so the lists are the same whatever the thread count.
    type Block = (Vec<u32>, Vec<u32>, Vec<u32>, Vec<u32>);
    let blocks: Vec<Block> = (0..n.div_ceil(BLOCK))
        .into_par_iter()
        .map(|b| {
            let range = b * BLOCK..((b + 1) * BLOCK).min(n);
            let mut own = Vec::with_capacity(range.len() * 24);
            let mut own_len = Vec::with_capacity(range.len());
            let mut cross = Vec::new();
            let mut cross_len = Vec::with_capacity(range.len());
            for i in range {
                let (o0, c0) = (own.len(), cross.len());
                let mut visit = |j: usize| {
                    if j == i {
                        return;
                    }
                    let cross_body = split && model.body[i] != model.body[j];
                    let round = model.h[i] + model.h[j] + skin;
                    let d = x[i] - x[j];
                    let near = if adaptive && !cross_body {
                        near_adaptive(d, &f.metric[i], &f.metric[j], round, skin)
                    } else {
                        d.length_squared() < round * round
                    };
                    if !near {
                        return;
                    }
                    if cross_body {
                        cross.push(j as u32);
                    } else {
                        own.push(j as u32);
                    }
                };
                match &wide {
                    None => cells.for_each_near(x[i], dim, &mut visit),
                    Some(w) => {
                        let (xi, r2) = (x[i], w.reach2[i]);
                        cells.for_each_within(xi, w.rings[i], dim, |j| {
                            if (x[j] - xi).length_squared() < r2 && w.same_block(i, j, dim) {
                                visit(j)
                            }
                        });
                        w.order(&mut own[o0..]);
                        w.order(&mut cross[c0..]);
                    }
                }
                own_len.push((own.len() - o0) as u32);
                cross_len.push((cross.len() - c0) as u32);
            }
            (own, own_len, cross, cross_len)
        })
        .collect();
    let mut nb = Neighbours {
        start: Vec::with_capacity(n + 1),
        cross_start: Vec::with_capacity(n + 1),
        list: Vec::with_capacity(blocks.iter().map(|b| b.0.len()).sum()),
        cross: Vec::with_capacity(blocks.iter().map(|b| b.2.len()).sum()),
        skin,
        x_ref: x.to_vec(),
        support_ref: f.metric.to_vec(),
        ..Default::default()
    };
    nb.start.push(0);
    nb.cross_start.push(0);
    for (own, own_len, cross, cross_len) in blocks {
        for l in own_len {
            nb.start.push(nb.start.last().copied().unwrap_or(0) + l);
        }
        for l in cross_len {
            nb.cross_start
                .push(nb.cross_start.last().copied().unwrap_or(0) + l);
        }
        nb.list.extend_from_slice(&own);
        nb.cross.extend_from_slice(&cross);
    }
    nb.index_rows();
    nb.index_images(model);
    nb
}
