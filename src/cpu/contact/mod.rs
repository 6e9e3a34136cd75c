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

mod booked;
mod friction;

pub use booked::{penalty_ahead, penalty_booked};

use glam::DVec2;
use rayon::prelude::*;

use super::forces::Boundary;
use super::neighbours::{image_entry, pair_inv_h, Neighbours};
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
    candidate_at(model, bd, (p, q), st.x[p] - st.x[q], bd.normal[q])
}

/// [`is_candidate`] of P against the mirror image of q across a symmetry
/// plane `m` (docs/method.md §13): q at `m(x_q)` with normal `m(n_q)`.
/// Both passes compute it from P's side, so with the same bits.
#[inline]
fn is_image_candidate(
    model: &Model,
    st: &State,
    bd: &Boundary,
    m: &crate::math::Mirror,
    p: usize,
    q: usize,
) -> Option<(f64, DVec2)> {
    candidate_at(
        model,
        bd,
        (p, q),
        st.x[p] - m.point(st.x[q]),
        m.vector(bd.normal[q]),
    )
}

/// The contact test of P and q at `d = x_P − x_q`, q's normal `nq`.
#[inline]
fn candidate_at(
    model: &Model,
    bd: &Boundary,
    (p, q): (usize, usize),
    d: DVec2,
    nq: DVec2,
) -> Option<(f64, DVec2)> {
    let hpq = 0.5 * (model.h[p] + model.h[q]);
    let np = bd.normal[p];
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
    // A candidate on a symmetry plane weighs its share; its image, met
    // as a candidate too, the rest.
    let r = surface_ramp(ramp_measure(model, bd, p), model.boundary_threshold)
        * surface_ramp(ramp_measure(model, bd, q), model.boundary_threshold)
        * model.share(q);
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
    /// `½ p A / ΣW`: the normal force the pass applies, per unit weight
    /// (what friction's limit reads, [`friction`]).
    normal: f64,
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
    /// Each boundary particle's friction (`(particle, friction)`, entries
    /// as `force`); empty without friction.
    pub friction: Vec<(u32, Friction)>,
    pub stats: ContactStats,
}

/// One boundary particle's friction in an evaluation (docs/method.md §8.6).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Friction {
    /// The tangential spring `f A k_t` of its frictional pass, N/m per
    /// unit thickness (0: none, and its slip lets go).
    pub stiffness: f64,
    /// The largest elastic slip the Coulomb limit allows, `μ p / k_t`.
    pub cap: f64,
    /// The slip's rate at the booking velocities: the relative tangential
    /// velocity while the pass sticks, 0 while it slides.
    pub rate: f64,
    /// Whether the pass slides (it holds to the sliding coefficient until
    /// it sticks again).
    pub sliding: bool,
}

/// The Coulomb return at the end of a step (docs/method.md §8.6): each
/// boundary particle's slip in `st` clipped to the limit the step's
/// evaluation `friction` found, with that evaluation's stiffness; a
/// particle without a frictional pass lets its slip go. The spring energy
/// released, `½ f A k_t (u² − u_c²)`, is heat in the particle's internal
/// energy (and in `st.heat` and `st.friction_heat`), taken from the work
/// the springs absorbed (`st.spring_work`).
pub fn return_slip(model: &Model, friction: &[(u32, Friction)], st: &mut State) {
    let mut released = 0.0;
    let mut held = vec![false; st.slip.len()];
    let mut release = |i: usize, q: f64, e: &mut [f64]| {
        e[i] += q / model.mass[i];
        released += q;
    };
    for &(i, fr) in friction {
        let i = i as usize;
        if fr.stiffness == 0.0 {
            continue;
        }
        held[i] = true;
        let u = st.slip[i];
        let uc = u.clamp(-fr.cap, fr.cap);
        release(i, 0.5 * fr.stiffness * (u * u - uc * uc), &mut st.e);
        st.slip[i] = uc;
        st.slip_stiffness[i] = fr.stiffness;
        st.sliding[i] = fr.sliding;
    }
    for (i, held) in held.into_iter().enumerate() {
        if !held && (st.slip[i] != 0.0 || st.slip_stiffness[i] != 0.0) {
            let u = st.slip[i];
            release(i, 0.5 * st.slip_stiffness[i] * u * u, &mut st.e);
            st.slip[i] = 0.0;
            st.slip_stiffness[i] = 0.0;
        }
        if !held {
            st.sliding[i] = false;
        }
    }
    // The springs had absorbed it (`spring_work`); it is heat now.
    st.spring_work -= released;
    st.heat += released;
    st.friction_heat += released;
}

/// The tangential springs' stored energy in a state, `Σ ½ f A k_t u²`.
pub fn slip_stored(st: &State) -> f64 {
    st.slip
        .iter()
        .zip(&st.slip_stiffness)
        .map(|(u, c)| 0.5 * c * u * u)
        .sum()
}

/// `slip = base + k · rate` over the frictional passes of `friction`
/// (the integrators' update of [`State::slip`]).
pub fn advance_slip(base: &[f64], friction: &[(u32, Friction)], k: f64, out: &mut Vec<f64>) {
    out.clear();
    out.extend_from_slice(base);
    for &(i, fr) in friction {
        out[i as usize] += fr.rate * k;
    }
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

/// Shear impedance `√(ρ0 G)` and shear modulus of a body (∞ when
/// rigid; docs/method.md §8.6).
#[inline]
fn shear_constants(model: &Model, b: u32) -> (f64, f64) {
    let info = &model.bodies[b as usize];
    if info.rigid {
        (f64::INFINITY, f64::INFINITY)
    } else {
        let m = &info.material;
        ((m.rho0 * m.g).sqrt(), m.g)
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
pub(super) struct PartnerSums {
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
    /// The mirror (one of `Model::contact_images`) where the candidate is
    /// q's image across a symmetry plane.
    image: Option<crate::math::Mirror>,
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
