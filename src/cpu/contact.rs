//! Penalty contact (METHOD.md §8): contact test and normal, gap from the
//! contact distance, impedance dashpot + spring pressure clipped to
//! compression, and a two-pass pairing that conserves momentum exactly.
//!
//! Pairing (METHOD.md §8.4, scheme (c)): each boundary particle P interpolates
//! the partner body's surface around it with kernel weights (position,
//! normal, velocity, surface offset), computes one pressure `p_P` against that
//! surface, keeps `−½ p_P A_P n_P` itself and hands `+½ p_P A_P n_P` to the
//! partner particles in proportion to their weights (`q_P` per unit weight).
//! Every pass is a gather over neighbours: no atomics on the GPU.

use glam::DVec2;
use rayon::prelude::*;

use super::kinematics::Boundary;
use super::neighbours::Neighbours;
use crate::model::{Model, State};
use crate::physics::kernel;
use crate::physics::material::series;

/// Whether boundary particle `q` (another body) is a contact candidate of
/// boundary particle `p` (METHOD.md §8.2): within `2 h_pq`, normals facing
/// each other, and each particle no further in front of the other's surface
/// than the contact distance plus `h_pq`. The last bound is deliberately
/// looser than the paper's `h_pq` so that pairs whose gap is already closed
/// by large surface offsets are never rejected; pressure only arises where
/// the gap is ≤ 0, so the looser gate changes nothing for pairs apart.
#[inline]
pub fn is_candidate(model: &Model, st: &State, bd: &Boundary, p: usize, q: usize) -> Option<f64> {
    let r = st.x[q] - st.x[p];
    let hpq = 0.5 * (model.h[p] + model.h[q]);
    let dist = r.length();
    if dist >= 2.0 * hpq {
        return None;
    }
    let (np, nq) = (bd.normal[p], bd.normal[q]);
    if np.dot(nq) >= 0.0 {
        return None;
    }
    let reach = model.offset[p] + model.offset[q] + hpq;
    if np.dot(r).max(-nq.dot(r)) > reach {
        return None;
    }
    Some(kernel::w(model.dim, dist, hpq))
}

/// What P's pass hands to the partner body `body`.
#[derive(Debug, Clone, Copy)]
struct Share {
    body: u32,
    /// `½ p_P A_P n_c / ΣW`: force per unit kernel weight on partner particles.
    q: DVec2,
    /// Dashpot heat per unit weight, for a rigid P that cannot keep its heat.
    eta: f64,
}

/// Contact result of one evaluation.
#[derive(Debug, Clone, Default)]
pub struct ContactForces {
    /// Contact force on each boundary particle, entry k for particle
    /// `Boundary::list[k]` (no other particle has contact terms).
    pub force: Vec<DVec2>,
    /// Dashpot heat rate booked into each boundary particle, W (entries as
    /// `force`).
    pub heat: Vec<f64>,
    pub stats: ContactStats,
}

/// Totals per pair of bodies (`a < b`), and the energies of the contact.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContactStats {
    /// `(a, b, total normal force, largest pressure)`.
    pub pairs: Vec<(u32, u32, f64, f64)>,
    /// Stored penalty-spring energy.
    pub stored: f64,
    /// Total dashpot heat rate.
    pub heat_rate: f64,
    /// Rate of work absorbed by the springs, `Σ ½ k δ A w` over the passes.
    pub spring_rate: f64,
}

impl ContactStats {
    pub fn pair(&self, a: u32, b: u32) -> (f64, f64) {
        let (a, b) = (a.min(b), a.max(b));
        self.pairs
            .iter()
            .find(|p| p.0 == a && p.1 == b)
            .map_or((0.0, 0.0), |p| (p.2, p.3))
    }

    fn add(&mut self, a: u32, b: u32, force: f64, p: f64) {
        let (a, b) = (a.min(b), a.max(b));
        match self.pairs.iter_mut().find(|x| x.0 == a && x.1 == b) {
            Some(x) => {
                x.2 += force;
                x.3 = x.3.max(p);
            }
            None => self.pairs.push((a, b, force, p)),
        }
    }
}

/// Impedance and constrained modulus of a body (∞ when rigid, METHOD.md §8.5).
#[inline]
fn body_constants(model: &Model, b: u32) -> (f64, f64) {
    let info = &model.bodies[b as usize];
    if info.rigid {
        (f64::INFINITY, f64::INFINITY)
    } else {
        (info.material.z, info.material.m)
    }
}

/// Stiffness of the penalty spring, Pa/m (METHOD.md §8.3, derived here).
///
/// The spring stands for the two surface layers between the particle
/// centres and the surfaces they meet: thickness `o_a` of body A and `o_b`
/// of body B, each squeezed in uniaxial strain (the layer is thin against
/// the body, so the constrained modulus `M = K + 4G/3 = ρ0 c_L²` holds).
/// In series their compliance is `o_a/M_a + o_b/M_b`. On a conforming
/// lattice (`o = Δx/2`) between equal bodies this is `M/Δx`, where the
/// paper's `E*/h0` gives `E/(2Δx)`: for steel 2.7 times more compliant than
/// the material it stands for, which made contacts soft and long.
///
/// A layer is taken at least `Δx/4` thick: on a square lattice around a curve
/// a particle centre can sit almost on the surface, and a zero-thickness
/// layer would be an infinitely stiff spring. At the floor the spring's
/// frequency is `√2 c_L/Δx`, so `ω Δt ≈ 0.5` at the CFL step: stable with margin.
/// A rigid side (`M = ∞`) adds no compliance.
pub fn spring_stiffness(o_a: f64, dx_a: f64, m_a: f64, o_b: f64, dx_b: f64, m_b: f64) -> f64 {
    let layer = |o: f64, dx: f64, m: f64| {
        if m.is_infinite() {
            0.0
        } else {
            o.max(0.25 * dx) / m
        }
    };
    1.0 / (layer(o_a, dx_a, m_a) + layer(o_b, dx_b, m_b))
}

/// The gap below which two surfaces count as touching: `1e-5 Δx`.
///
/// Bodies placed touching have a gap of zero up to the round-off of their
/// coordinates (`+2e-19 m` for the paper's bars in f64, a few `1e-7 Δx` on
/// the GPU's f32 offsets). A gap of `+ε` makes the contact start inside the
/// first step instead of at it: the midpoint step then applies the dashpot
/// from its half state, which has not yet felt it, and books 0.3 % too much
/// heat for the bar impact. Counting round-off as touching starts both
/// backends alike; the dashpot engages `1e-5 Δx / w` early at most (a
/// thousandth of a time step), the spring only on a true overlap.
#[inline]
pub fn touching(spacing: f64) -> f64 {
    1e-5 * spacing
}

/// P's kernel-weighted sums over the candidates of one partner body.
#[derive(Debug, Clone, Copy)]
struct PartnerSums {
    body: u32,
    /// `ΣW`
    sw: f64,
    /// `ΣW (s_q − S_P)`: partner surface points relative to P's.
    sws: DVec2,
    /// `ΣW n_q`
    swn: DVec2,
    /// `ΣW v_q`
    swv: DVec2,
    /// `ΣW v_q` at the booking velocities ([`penalty_booked`]).
    swb: DVec2,
    /// `ΣW n_q·(S_P − s_q)`: distances to the partners' tangent lines.
    swt: f64,
    /// `ΣW o_q`: the partners' surface offsets (the spring's far layer).
    swo: f64,
}

impl PartnerSums {
    fn new(body: u32) -> Self {
        Self {
            body,
            sw: 0.0,
            sws: DVec2::ZERO,
            swn: DVec2::ZERO,
            swv: DVec2::ZERO,
            swb: DVec2::ZERO,
            swt: 0.0,
            swo: 0.0,
        }
    }
}

/// What one pass of P adds to the statistics.
#[derive(Debug, Clone, Copy)]
struct PassStat {
    partner: u32,
    /// `½ p A`, the pass's share of the pair force.
    force: f64,
    pressure: f64,
    /// `¼ k δ² A`
    stored: f64,
    /// Dashpot heat rate `½ (p − kδ) A w`.
    heat: f64,
    /// Spring power `½ k δ A w`.
    spring_rate: f64,
}

/// One pass of P against partner body `body` from the weighted sums.
struct Pass {
    p: f64,
    n: DVec2,
    w_rate: f64,
    stiffness: f64,
    delta: f64,
}

/// The gap and pressure of P against the interpolated partner surface.
///
/// Surfaces, not particle centres, are interpolated: P's surface point is
/// `S_P = x_P + o_P n_P` and each partner's `s_q = x_q + o_q n_q`, so the gap
/// is `g_N = d_N − d_c` of METHOD.md §8.3 on a flat face. On a curved face the
/// weighted mean of the partners' surface points lies on chords, behind the
/// surface by ≈ Rφ²/2 (φ the angle the partners span); the weighted distance
/// to the partners' tangent lines errs by the same amount the other way.
/// Their mean is exact to second order in φ.
fn pressure(model: &Model, p_idx: usize, np: DVec2, vp: DVec2, s: &PartnerSums) -> Option<Pass> {
    if s.sw <= 0.0 {
        return None;
    }
    let nbar = s.swn.normalize_or_zero();
    if nbar == DVec2::ZERO {
        return None;
    }
    let partner = s.body;
    let r = s.sws / s.sw;
    let tangent_gap = s.swt / s.sw;
    let vrel = vp - s.swv / s.sw;
    // Contact normal: of n_P, −n̄ and their bisector, the one with the largest
    // projected distance (least penetration; METHOD.md §8.2).
    let mut best = (np, np.dot(r));
    for cand in [-nbar, (np - nbar).normalize_or_zero()] {
        if cand != DVec2::ZERO {
            let d = cand.dot(r);
            if d > best.1 {
                best = (cand, d);
            }
        }
    }
    let (n, chord_gap) = best;
    let gap = 0.5 * (chord_gap + tangent_gap);
    let bp = model.body[p_idx];
    if gap > touching(model.bodies[bp as usize].spacing) {
        return None;
    }
    let delta = (-gap).max(0.0);
    let w_rate = vrel.dot(n);
    let (za, ma) = body_constants(model, bp);
    let (zb, mb) = body_constants(model, partner);
    if za.is_infinite() && zb.is_infinite() {
        // Two rigid bodies move as prescribed: nothing to push.
        return None;
    }
    let z = series(za, zb);
    let stiffness = spring_stiffness(
        model.offset[p_idx],
        model.bodies[bp as usize].spacing,
        ma,
        s.swo / s.sw,
        model.bodies[partner as usize].spacing,
        mb,
    );
    let p = (z * w_rate + stiffness * delta).max(0.0);
    Some(Pass {
        p,
        n,
        w_rate,
        stiffness,
        delta,
    })
}

/// Both passes: returns contact forces, booked heat and the statistics.
pub fn penalty(model: &Model, st: &State, nb: &Neighbours, bd: &Boundary) -> ContactForces {
    penalty_booked(model, st, nb, bd, None)
}

/// [`penalty`] with the forces of the velocities `st.v` but the heat and
/// the spring power booked at the velocities `book` (`None`: `st.v`): the rate of work of
/// a pass's force `½ p A` on the bodies is `½ p A w` with the approach
/// rate `w` the bodies actually move at, and the ledger closes only when
/// the heat and the spring power split that `w`. The leapfrog
/// (`CpuSolver::step`) computes its forces at predicted velocities and
/// books their work at the step's end.
pub fn penalty_booked(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    bd: &Boundary,
    book: Option<&[DVec2]>,
) -> ContactForces {
    // Pass 1: every boundary particle against each partner body around it
    // (entry k for particle `bd.list[k]`; only boundary particles have
    // contact terms, so the passes go over the boundary list alone).
    type P1 = (DVec2, f64, Vec<Share>, Vec<PassStat>);
    let pass1: Vec<P1> = bd
        .list
        .par_iter()
        .map(|&p| {
            let p = p as usize;
            let mut own_force = DVec2::ZERO;
            let mut own_heat = 0.0;
            let mut shares = Vec::new();
            let mut stats = Vec::new();
            // One set of sums per partner body (almost always one).
            let mut sums: Vec<PartnerSums> = Vec::new();
            let sp = st.x[p] + bd.normal[p] * model.offset[p];
            for &q in nb.cross_of(p) {
                let q = q as usize;
                if !bd.is_boundary[q] {
                    continue;
                }
                let Some(w) = is_candidate(model, st, bd, p, q) else {
                    continue;
                };
                let bq = model.body[q];
                let k = match sums.iter().position(|s| s.body == bq) {
                    Some(k) => k,
                    None => {
                        sums.push(PartnerSums::new(bq));
                        sums.len() - 1
                    }
                };
                let s = &mut sums[k];
                let sq = st.x[q] + bd.normal[q] * model.offset[q];
                s.sw += w;
                s.sws += (sq - sp) * w;
                s.swn += bd.normal[q] * w;
                s.swv += st.v[q] * w;
                if let Some(book) = book {
                    s.swb += book[q] * w;
                }
                s.swt += bd.normal[q].dot(sp - sq) * w;
                s.swo += model.offset[q] * w;
            }
            for s in &sums {
                let Some(ps) = pressure(model, p, bd.normal[p], st.v[p], s) else {
                    continue;
                };
                let (bq, sw) = (s.body, s.sw);
                let a = bd.area[p];
                // Without booking velocities the booked rates are the
                // pressure's own.
                let w_book = book.map_or(ps.w_rate, |b| (b[p] - s.swb / sw).dot(ps.n));
                // Dashpot heat of this half pass: ½ (p − kδ) A w ≥ 0 (the
                // spring's share of the work is stored, the rest dissipated).
                let heat = 0.5 * (ps.p - ps.stiffness * ps.delta) * a * w_book;
                // Finite: a pair with two rigid sides has no pressure.
                let stored = 0.25 * ps.stiffness * ps.delta * ps.delta * a;
                own_force -= ps.n * (0.5 * ps.p * a);
                let rigid = model.rigid(p);
                if !rigid {
                    own_heat += heat;
                }
                shares.push(Share {
                    body: bq,
                    q: ps.n * (0.5 * ps.p * a / sw),
                    eta: if rigid { heat / sw } else { 0.0 },
                });
                stats.push(PassStat {
                    partner: bq,
                    force: 0.5 * ps.p * a,
                    pressure: ps.p,
                    stored,
                    heat,
                    spring_rate: 0.5 * ps.stiffness * ps.delta * a * w_book,
                });
            }
            (own_force, own_heat, shares, stats)
        })
        .collect();

    // Pass 2: every boundary particle Q gathers what its partners handed it,
    // over exactly the candidate set each of them used.
    let gathered: Vec<(DVec2, f64)> = bd
        .list
        .par_iter()
        .map(|&q| {
            let q = q as usize;
            let mut f = DVec2::ZERO;
            let mut heat = 0.0;
            let bq = model.body[q];
            for &p in nb.cross_of(q) {
                if !bd.is_boundary[p as usize] {
                    continue;
                }
                let k = bd
                    .list
                    .binary_search(&p)
                    .expect("a boundary particle is listed");
                let p = p as usize;
                let Some(share) = pass1[k].2.iter().find(|s| s.body == bq) else {
                    continue;
                };
                let Some(w) = is_candidate(model, st, bd, p, q) else {
                    continue;
                };
                f += share.q * w;
                heat += share.eta * w;
            }
            (f, heat)
        })
        .collect();

    let mut out = ContactForces {
        force: Vec::with_capacity(bd.list.len()),
        heat: Vec::with_capacity(bd.list.len()),
        stats: ContactStats::default(),
    };
    for ((&p, own), g) in bd.list.iter().zip(&pass1).zip(&gathered) {
        let p = p as usize;
        out.force.push(own.0 + g.0);
        out.heat
            .push(if model.rigid(p) { 0.0 } else { own.1 + g.1 });
        for s in &own.3 {
            out.stats.add(model.body[p], s.partner, s.force, s.pressure);
            out.stats.stored += s.stored;
            out.stats.heat_rate += s.heat;
            out.stats.spring_rate += s.spring_rate;
        }
    }
    out
}
