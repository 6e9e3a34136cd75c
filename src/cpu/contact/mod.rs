//! Penalty contact (docs/method.md §8): contact test and normal, gap from the
//! contact distance, impedance dashpot + spring pressure clipped to
//! compression, and a two-pass pairing that conserves momentum exactly.
//!
//! Pairing (docs/method.md §8.4, scheme (c)): each boundary particle P interpolates
//! the partner body's surface around it with kernel weights (position,
//! normal, velocity, surface offset), computes one pressure `p_P` against that
//! surface, keeps `−½ p_P A_P n_P` itself and hands `+½ p_P A_P n_P` to the
//! partner particles in proportion to their weights (`q_P` per unit weight).
//! Every pass is a gather over neighbours: no atomics on the GPU.

use glam::DVec2;
use rayon::prelude::*;

use super::axis;
use super::kinematics::Boundary;
use super::neighbours::{pair_inv_h, Neighbours};
use crate::model::{ContactStats, Model, State};
use crate::physics::kernel;
use crate::physics::material::series;
use crate::physics::penalty::{
    self, entry_rule, spring_stiffness, stiffness_slope, touching, yield_overlap, Sums, SumsBar,
};

/// Whether boundary particle `q` (another body) is a contact candidate of
/// boundary particle `p` (docs/method.md §8.2): within `2 h_pq`, normals facing
/// each other, and each particle no further in front of the other's surface
/// than the contact distance plus `h_pq`. The last bound is deliberately
/// looser than the paper's `h_pq` so that pairs whose gap is already closed
/// by large surface offsets are never rejected; pressure only arises where
/// the gap is ≤ 0, so the looser gate changes nothing for pairs apart.
#[inline]
pub fn is_candidate(
    model: &Model,
    st: &State,
    bd: &Boundary,
    p: usize,
    q: usize,
) -> Option<(f64, DVec2)> {
    // d = x_P − x_q from either side of the pair: the same bits in both passes.
    let d = st.x[p] - st.x[q];
    let hpq = 0.5 * (model.h[p] + model.h[q]);
    let (np, nq) = (bd.normal[p], bd.normal[q]);
    if np.dot(nq) >= 0.0 {
        return None;
    }
    let reach = model.offset[p] + model.offset[q] + hpq;
    if (-np.dot(d)).max(nq.dot(d)) > reach {
        return None;
    }
    let (w, gw) = kernel::w_grad(model.dim, d, d.length_squared(), 1.0 / hpq)?;
    if model.dim == 1 {
        return Some((w, gw));
    }
    let r = surface_ramp(ramp_measure(model, bd, p), model.boundary_threshold)
        * surface_ramp(ramp_measure(model, bd, q), model.boundary_threshold);
    if r <= 0.0 {
        return None;
    }
    Some((w * r, gw * r))
}

/// How fully a boundary particle with `h |∇ψ⁰|` = `hg` takes part in the
/// contact (docs/method.md §8.2): 0 at the boundary threshold, rising
/// linearly to 1 at 1.5 times it. A particle joining the surface set, or a
/// candidate entering a pass, then moves the interpolated partner surface
/// gradually instead of at once, which made the springs' stored energy
/// jump without work (3.5 % of the energy in a penetration at 400 m/s).
/// The ramp's own derivative is not in the spring's gradient.
#[inline]
pub fn surface_ramp(hg: f64, threshold: f64) -> f64 {
    ((hg - threshold) / (SURFACE_RAMP * threshold)).clamp(0.0, 1.0)
}

/// What [`surface_ramp`] reads of boundary particle `i`: `h |∇ψ⁰|`, in a
/// body of revolution the boundary test's own measure
/// ([`Boundary::measure`]).
#[inline]
fn ramp_measure(model: &Model, bd: &Boundary, i: usize) -> f64 {
    match bd.measure.get(i) {
        Some(&m) => m,
        None => model.h[i] * bd.grad_norm[i],
    }
}

/// Width of [`surface_ramp`] as a fraction of the boundary threshold.
pub const SURFACE_RAMP: f64 = 0.5;

/// What P's pass hands to the partner body `body`.
#[derive(Debug, Clone, Copy)]
struct Share {
    body: u32,
    /// `½ z w A n_c / ΣW`: dashpot force per unit kernel weight on partner
    /// particles.
    q: DVec2,
    /// Dashpot heat per unit weight, for a rigid P that cannot keep its heat.
    eta: f64,
    /// The spring's derivative and P's surface point, where the spring acts.
    spring: Option<(SumsBar, DVec2)>,
}

/// Contact result of one evaluation.
#[derive(Debug, Clone, Default)]
pub struct ContactForces {
    /// Contact force on each boundary particle, entry k for particle
    /// `Boundary::list[k]` (other particles have only [`Self::spread`]).
    pub force: Vec<DVec2>,
    /// Forces on other particles `(i, f)`, in a fixed order: the spring's
    /// pull through the normals reaches the neighbours of the boundary
    /// particles whose normals it turns.
    pub spread: Vec<(u32, DVec2)>,
    /// Dashpot heat rate booked into each boundary particle, W (entries as
    /// `force`).
    pub heat: Vec<f64>,
    /// Each boundary particle's entry overlap after this evaluation
    /// (`(particle, overlap)`, entries as `force`; [`State::entry`]).
    pub entry: Vec<(u32, f64)>,
    pub stats: ContactStats,
}

/// Writes the entry overlaps of every particle into `out` (a state's
/// [`State::entry`]): the listed boundary particles' `(particle, overlap)`,
/// none (−1) elsewhere.
pub fn write_entries(entries: &[(u32, f64)], out: &mut [f64]) {
    out.fill(-1.0);
    for &(i, e) in entries {
        out[i as usize] = e;
    }
}

impl ContactForces {
    /// Adds the contact's accelerations to `dv` (rigid particles left as
    /// they are): the boundary particles' forces, then the spread ones, in
    /// their fixed order.
    pub fn add_forces(&self, model: &Model, bd: &Boundary, dv: &mut [DVec2]) {
        for (k, &i) in bd.list.iter().enumerate() {
            let i = i as usize;
            if !model.rigid(i) {
                dv[i] += self.force[k] / model.mass[i];
            }
        }
        for &(i, f) in &self.spread {
            let i = i as usize;
            if !model.rigid(i) {
                dv[i] += f / model.mass[i];
            }
        }
    }
}

/// Impedance and constrained modulus of a body (∞ when rigid, docs/method.md §8.5).
#[inline]
fn body_constants(model: &Model, b: u32) -> (f64, f64) {
    let info = &model.bodies[b as usize];
    if info.rigid {
        (f64::INFINITY, f64::INFINITY)
    } else {
        (info.material.z, info.material.m)
    }
}

/// The fade of P's pass against `partner` with candidates' total weight
/// `sw` ([`penalty::fade`]), and its derivative with respect to `sw`. The
/// reference is a quarter of what a flat partner surface through P gives,
/// `∫W dℓ / Δx`; in 1-D a pass has one candidate and never fades.
#[inline]
fn pass_fade(model: &Model, p: usize, partner: u32, sw: f64) -> (f64, f64) {
    if model.dim == 1 {
        return (1.0, 0.0);
    }
    let w_ref =
        0.25 * kernel::line_integral_2d(model.h[p]) / model.bodies[partner as usize].spacing;
    let (f, slope) = penalty::fade(sw / w_ref);
    (f, slope / w_ref)
}

/// P's kernel-weighted sums over the candidates of one partner body.
#[derive(Debug, Clone, Copy)]
struct PartnerSums {
    body: u32,
    s: Sums,
    /// `ΣW v_q`
    swv: DVec2,
    /// `ΣW v_q` at the booking velocities ([`penalty_booked`]).
    swb: DVec2,
}

/// One contact candidate of P: particle, body, `W` and `∇_P W`.
#[derive(Debug, Clone, Copy)]
struct Cand {
    q: usize,
    body: u32,
    w: f64,
    gw: DVec2,
}

/// What one pass of P adds to the statistics.
#[derive(Debug, Clone, Copy)]
struct PassStat {
    partner: u32,
    /// `½ p A`, the pass's share of the pair force, `p` the pressure it
    /// applies along its normal (its spring faded as it acts).
    force: f64,
    pressure: f64,
    /// `¼ k δ² A`
    stored: f64,
    /// Dashpot heat rate.
    heat: f64,
    /// `dΦ/dt` of the pass.
    spring_rate: f64,
}

/// The pressure law of one pass: `p = max(z w + k δ, 0)`.
struct Pass {
    gap: penalty::Gap,
    p: f64,
    /// `z w + k δ < 0`: the dashpot would pull harder than the spring
    /// pushes, and the pass lets go.
    clipped: bool,
    z: f64,
    w_rate: f64,
    stiffness: f64,
    /// `∂k/∂ō`
    slope: f64,
    delta: f64,
}

impl Pass {
    /// The spring measured from the entry overlap `e`, and the pressure
    /// law at that overlap.
    fn offset(&mut self, e: f64) {
        self.delta = (self.delta - e).max(0.0);
        let push = self.z * self.w_rate + self.stiffness * self.delta;
        self.p = push.max(0.0);
        self.clipped = push < 0.0;
    }
}

/// The gap and pressure of P against the interpolated partner surface
/// ([`penalty::gap`]), at the raw overlap (the entry rule then measures
/// it from the entry, [`Pass::offset`]); `None` where the surfaces are
/// apart.
fn pressure(model: &Model, p_idx: usize, np: DVec2, vp: DVec2, s: &PartnerSums) -> Option<Pass> {
    let gap = penalty::gap(np, &s.s)?;
    let partner = s.body;
    let bp = model.body[p_idx];
    if gap.gap > touching(model.bodies[bp as usize].spacing) {
        return None;
    }
    let delta = (-gap.gap).max(0.0);
    let w_rate = (vp - s.swv / s.s.sw).dot(gap.n);
    let (za, ma) = body_constants(model, bp);
    let (zb, mb) = body_constants(model, partner);
    if za.is_infinite() && zb.is_infinite() {
        // Two rigid bodies move as prescribed: nothing to push.
        return None;
    }
    let z = series(za, zb);
    let (o_b, dx_b) = (s.s.swo / s.s.sw, model.bodies[partner as usize].spacing);
    let stiffness = spring_stiffness(
        model.offset[p_idx],
        model.bodies[bp as usize].spacing,
        ma,
        o_b,
        dx_b,
        mb,
    );
    let mut pass = Pass {
        gap,
        p: 0.0,
        clipped: false,
        z,
        w_rate,
        stiffness,
        slope: stiffness_slope(stiffness, o_b, dx_b, mb),
        delta,
    };
    pass.offset(0.0);
    Some(pass)
}

/// Both passes: returns contact forces, booked heat and the statistics.
pub fn penalty(model: &Model, st: &State, nb: &Neighbours, bd: &Boundary) -> ContactForces {
    penalty_booked(model, st, nb, bd, None)
}

/// `∇∇W` of the pair `d = x_i − x_j` of particles i and j of one body, applied to `b`.
#[inline]
fn hessian_times(model: &Model, i: usize, j: usize, d: DVec2, b: DVec2) -> DVec2 {
    let inv_h = pair_inv_h(model.h[i], model.h[j], 1.0 / model.h[i]);
    match kernel::hessian(model.dim, d.length_squared(), inv_h) {
        Some((s, t)) => b * s + d * (t * d.dot(b)),
        None => DVec2::ZERO,
    }
}

/// How fast each boundary particle's normal turns at velocities `v` (entry
/// k for `bd.list[k]`): `ṅ = (I − n nᵀ) ġ / |g|` with `g = ∇ψ = −Σ_j V_j
/// ∇W(x_P − x_j)` and `ġ = −Σ_j V_j ∇∇W (v_P − v_j)`, `V_j` the reference
/// volumes ([`kinematics::boundary`]).
fn normal_rates(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    bd: &Boundary,
    v: &[DVec2],
) -> Vec<DVec2> {
    if model.dim == 1 {
        return vec![DVec2::ZERO; bd.list.len()];
    }
    bd.list
        .par_iter()
        .map(|&p| {
            let p = p as usize;
            let mut gdot = DVec2::ZERO;
            for (b, image) in nb.round_with_images(model, &st.x, p) {
                let j = b.j as usize;
                let vol = model.reference_volume(j);
                let (xj, vj) = if image {
                    (axis::mirror(st.x[j]), axis::mirror(v[j]))
                } else {
                    (st.x[j], v[j])
                };
                gdot -= hessian_times(model, p, j, st.x[p] - xj, v[p] - vj) * vol;
            }
            let n = bd.normal[p];
            (gdot - n * n.dot(gdot)) / bd.grad_norm[p]
        })
        .collect()
}

/// [`penalty()`] with the forces of the velocities `st.v` but the heat and
/// the spring power booked at the velocities `book` (`None`: `st.v`): the
/// leapfrog (`CpuSolver::step`) computes its forces at predicted velocities
/// and books their work at the step's end, and the ledger closes only when
/// the heat and the spring power are the work the forces do at the
/// velocities the bodies actually move at.
///
/// Each pass's force is a dashpot `½ z w A` along the contact normal, shared
/// by weight like the pressure it is part of, plus the spring: the exact
/// gradient of the pass's stored energy `Φ = ¼ k δ² A`, through P's and
/// its candidates' positions, their weights and their normals (the area is
/// held over the evaluation). Where the dashpot would pull harder than the
/// spring pushes (`z w + k δ < 0`, the surfaces parting faster than the
/// spring relaxes) the pass applies nothing, and the spring's energy
/// released is booked as heat: the contact never pulls.
pub fn penalty_booked(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    bd: &Boundary,
    book: Option<&[DVec2]>,
) -> ContactForces {
    let vb = book.unwrap_or(&st.v);
    let ndot = normal_rates(model, st, nb, bd, vb);
    let slot = |q: usize| {
        bd.list
            .binary_search(&(q as u32))
            .expect("a boundary particle is listed")
    };
    // Pass 1: every boundary particle against each partner body around it
    // (entry k for particle `bd.list[k]`; only boundary particles have
    // contact terms, so the passes go over the boundary list alone).
    struct P1 {
        entry: f64,
        force: DVec2,
        heat: f64,
        /// `∂Φ/∂n_P` from P's own passes.
        n_bar: DVec2,
        shares: Vec<Share>,
        stats: Vec<PassStat>,
    }
    let pass1: Vec<P1> = bd
        .list
        .par_iter()
        .enumerate()
        .map(|(kp, &p)| {
            let p = p as usize;
            let mut out = P1 {
                entry: -1.0,
                force: DVec2::ZERO,
                heat: 0.0,
                n_bar: DVec2::ZERO,
                shares: Vec::new(),
                stats: Vec::new(),
            };
            let (np, op) = (bd.normal[p], model.offset[p]);
            let sp = st.x[p] + np * op;
            let mut cands: Vec<Cand> = Vec::new();
            // One set of sums per partner body (almost always one).
            let mut sums: Vec<PartnerSums> = Vec::new();
            for &q in nb.cross_of(p) {
                let q = q as usize;
                if !bd.is_boundary[q] {
                    continue;
                }
                let Some((w, gw)) = is_candidate(model, st, bd, p, q) else {
                    continue;
                };
                let bq = model.body[q];
                cands.push(Cand { q, body: bq, w, gw });
                let k = match sums.iter().position(|s| s.body == bq) {
                    Some(k) => k,
                    None => {
                        sums.push(PartnerSums {
                            body: bq,
                            s: Sums::default(),
                            swv: DVec2::ZERO,
                            swb: DVec2::ZERO,
                        });
                        sums.len() - 1
                    }
                };
                let s = &mut sums[k];
                let nq = bd.normal[q];
                s.s.add(w, sp, st.x[q] + nq * model.offset[q], nq, model.offset[q]);
                s.swv += st.v[q] * w;
                if let Some(book) = book {
                    s.swb += book[q] * w;
                }
            }
            let a = bd.area[p];
            let rigid = model.rigid(p);
            let passes: Vec<(&PartnerSums, Pass)> = sums
                .iter()
                .filter_map(|s| Some((s, pressure(model, p, np, st.v[p], s)?)))
                .collect();
            let deepest = passes.iter().map(|(_, ps)| ps.delta).fold(0.0, f64::max);
            let cap = yield_overlap(model.bodies[model.body[p] as usize].spacing);
            let (entry, yielded) = entry_rule(st.entry[p], deepest, cap);
            out.entry = entry;
            for (s, mut ps) in passes {
                let sat = yielded && ps.delta == deepest;
                ps.offset(out.entry);
                let (bq, sw) = (s.body, s.s.sw);
                let n = ps.gap.n;
                // The spring's derivative, and dΦ/dt at the booking
                // velocities (forward, through the same derivative).
                let mut spring = None;
                let mut phi_dot = 0.0;
                let phi0 = 0.25 * ps.stiffness * ps.delta * ps.delta * a;
                let (fade, fade_slope) = pass_fade(model, p, bq, sw);
                if ps.delta > 0.0 {
                    let gbar = -0.5 * ps.stiffness * ps.delta * a * fade;
                    let obar = 0.25 * ps.delta * ps.delta * a * ps.slope * fade;
                    let mut bar = penalty::gap_bar(np, &s.s, &ps.gap, gbar, obar);
                    bar.sw += phi0 * fade_slope;
                    let mut xp_bar = bar.sp;
                    let np_bar = bar.np + bar.sp * op;
                    for c in cands.iter().filter(|c| c.body == bq) {
                        let (nq, oq) = (bd.normal[c.q], model.offset[c.q]);
                        let d = penalty::candidate(&bar, sp, c.w, st.x[c.q] + nq * oq, nq, oq);
                        xp_bar += c.gw * d.w;
                        phi_dot += (d.x - c.gw * d.w).dot(vb[c.q]) + d.n.dot(ndot[slot(c.q)]);
                    }
                    phi_dot += xp_bar.dot(vb[p]) + np_bar.dot(ndot[kp]);
                    if !ps.clipped {
                        out.force -= xp_bar;
                        out.n_bar += np_bar;
                        spring = Some((bar, sp));
                    }
                }
                let w_book = book.map_or(ps.w_rate, |b| (b[p] - s.swb / sw).dot(n));
                // Dashpot heat ½ z w A w ≥ 0; where the pass lets go, the
                // spring's energy released.
                let (mut heat, dash) = if ps.clipped {
                    (-phi_dot, 0.0)
                } else {
                    (
                        0.5 * ps.z * ps.w_rate * a * w_book,
                        0.5 * ps.z * ps.w_rate * a,
                    )
                };
                // A yielded spring pressed further stores nothing more: the
                // work it takes is heat.
                if sat && !ps.clipped && phi_dot > 0.0 {
                    heat += phi_dot;
                    phi_dot = 0.0;
                }
                out.force -= n * dash;
                if !rigid {
                    out.heat += heat;
                }
                out.shares.push(Share {
                    body: bq,
                    q: n * (dash / sw),
                    eta: if rigid { heat / sw } else { 0.0 },
                    spring,
                });
                // What the pass applies along its normal: the dashpot and
                // the spring as faded (the pressure law's own p where the
                // pass does not fade).
                let applied = if fade < 1.0 && !ps.clipped {
                    (ps.z * ps.w_rate + ps.stiffness * ps.delta * fade).max(0.0)
                } else {
                    ps.p
                };
                out.stats.push(PassStat {
                    partner: bq,
                    force: 0.5 * applied * a,
                    pressure: applied,
                    // Finite: a pair with two rigid sides has no pressure.
                    stored: phi0 * fade,
                    heat,
                    spring_rate: phi_dot,
                });
            }
            out
        })
        .collect();

    // Pass 2: every boundary particle Q gathers what its partners handed it,
    // over exactly the candidate set each of them used; then its normal's
    // derivative, complete, turns into forces on Q and its neighbours.
    /// What Q gathers: its force and heat from its partners, and the
    /// forces its normal's derivative puts on its neighbours.
    struct Gathered {
        force: DVec2,
        heat: f64,
        spread: Vec<(u32, DVec2)>,
    }
    let gathered: Vec<Gathered> = bd
        .list
        .par_iter()
        .enumerate()
        .map(|(kq, &q)| {
            let q = q as usize;
            let mut f = DVec2::ZERO;
            let mut heat = 0.0;
            let mut n_bar = pass1[kq].n_bar;
            let bq = model.body[q];
            let (nq, oq) = (bd.normal[q], model.offset[q]);
            let sq = st.x[q] + nq * oq;
            for &p in nb.cross_of(q) {
                if !bd.is_boundary[p as usize] {
                    continue;
                }
                let p = p as usize;
                let Some(share) = pass1[slot(p)].shares.iter().find(|s| s.body == bq) else {
                    continue;
                };
                let Some((w, gw)) = is_candidate(model, st, bd, p, q) else {
                    continue;
                };
                f += share.q * w;
                heat += share.eta * w;
                if let Some((bar, sp)) = &share.spring {
                    let d = penalty::candidate(bar, *sp, w, sq, nq, oq);
                    f += gw * d.w - d.x;
                    n_bar += d.n;
                }
            }
            let mut spread = Vec::new();
            if model.dim == 2 && n_bar != DVec2::ZERO && !model.rigid(q) {
                // ∂Φ/∂g for g = ∇ψ: g moves with Q against each neighbour
                // j by V_j ∇∇W, and with j the other way.
                let b = (n_bar - nq * nq.dot(n_bar)) / bd.grad_norm[q];
                // In a body of revolution j moves its image across the
                // axis the mirror way.
                for (nbr, image) in nb.round_with_images(model, &st.x, q) {
                    let j = nbr.j as usize;
                    let vol = model.reference_volume(j);
                    let xj = if image {
                        axis::mirror(st.x[j])
                    } else {
                        st.x[j]
                    };
                    let hb = hessian_times(model, q, j, st.x[q] - xj, b) * vol;
                    f += hb;
                    spread.push((nbr.j, if image { axis::mirror(-hb) } else { -hb }));
                }
            }
            Gathered {
                force: f,
                heat,
                spread,
            }
        })
        .collect();

    let mut out = ContactForces {
        entry: bd
            .list
            .iter()
            .zip(&pass1)
            .map(|(&i, p)| (i, p.entry))
            .collect(),
        force: Vec::with_capacity(bd.list.len()),
        spread: Vec::new(),
        heat: Vec::with_capacity(bd.list.len()),
        stats: ContactStats::default(),
    };
    for ((&p, own), g) in bd.list.iter().zip(&pass1).zip(gathered) {
        let p = p as usize;
        out.force.push(own.force + g.force);
        out.heat.push(if model.rigid(p) {
            0.0
        } else {
            own.heat + g.heat
        });
        out.spread.extend(g.spread);
        for s in &own.stats {
            out.stats.add(model.body[p], s.partner, s.force, s.pressure);
            out.stats.stored += s.stored;
            out.stats.heat_rate += s.heat;
            out.stats.spring_rate += s.spring_rate;
        }
    }
    out
}
