//! The forces pass: momentum and energy sums (docs/method.md §4) with Monaghan artificial
//! viscosity and, when the scene asks for it, Gray–Monaghan–Swift artificial
//! stress. The pair-antisymmetric `G_ij = ½ (L_i + L_j) ∇_i W_ij` conserves
//! momentum and energy exactly in semi-discrete form.

use glam::DVec2;

use super::neighbours::{Chunk, Nbr, Neighbours};
use crate::math::lanes::{columns, F4, LANES};
use crate::math::{Mat2, Sym};
use crate::model::{Model, State};
use crate::physics::{kernel, strength};
use crate::scene::ArtPairs;

/// Per-particle inputs of the momentum pass, computed once per evaluation.
#[derive(Debug, Clone, Copy, Default)]
pub struct StressPoint {
    /// `σ_i / ρ_i²`, in plane (tension positive).
    pub sr2: Sym,
    /// Artificial stress `R_i` (zero when off).
    pub r: Sym,
    /// Sound speed for the viscosity.
    pub c: f64,
}

/// The Cauchy stress `σ = −p I + s` (in plane; `zz` = `−p + s_zz`).
#[inline]
pub fn cauchy(p: f64, s: &Sym) -> Sym {
    Sym {
        xx: s.xx - p,
        yy: s.yy - p,
        xy: s.xy,
        zz: s.zz - p,
    }
}

/// Artificial stress (Gray, Monaghan & Swift 2001): `−ε σ̄/ρ²` of each
/// tensile principal value `σ̄` of σ, on its principal axis.
///
/// Written without the principal angle: with both principal values
/// tensile it is `−ε σ/ρ²` (in plane), with one (`a > 0 ≥ b`) it is
/// `−ε a/ρ² P_a` with the projector `P_a = (σ − b I)/(a − b)`, and with
/// none it is zero. No trigonometry, and exact where the two principal
/// values meet.
#[inline]
pub fn artificial_stress(eps: f64, sigma: &Sym, rho: f64) -> Sym {
    let m = 0.5 * (sigma.xx + sigma.yy);
    let d = 0.5 * (sigma.xx - sigma.yy);
    let rad = (d * d + sigma.xy * sigma.xy).sqrt();
    let (a, b) = (m + rad, m - rad);
    let k = -eps / (rho * rho);
    if b > 0.0 {
        Sym {
            xx: k * sigma.xx,
            yy: k * sigma.yy,
            xy: k * sigma.xy,
            zz: 0.0,
        }
    } else if a > 0.0 {
        let s = k * a / (a - b);
        Sym {
            xx: s * (sigma.xx - b),
            yy: s * (sigma.yy - b),
            xy: s * sigma.xy,
            zz: 0.0,
        }
    } else {
        Sym::default()
    }
}

/// The artificial stress's pair weight `f^n`, `f = W(r)/W(Δp)` at `h_ij`
/// (the kernel's normalisation cancels, so only the spline's shape is
/// evaluated), from `r² = |x_ij|²`, `Δp` and `h_ij`. `n = 4`, the usual
/// choice, is two squarings.
#[inline]
pub fn art_weight(r2: f64, dp: f64, hij: f64, n: f64) -> f64 {
    let q2 = r2 / (hij * hij);
    let qd = dp / hij;
    let f = kernel::shape(q2.sqrt(), q2) / kernel::shape(qd, qd * qd);
    if n == 4.0 {
        let f2 = f * f;
        f2 * f2
    } else {
        f.powf(n)
    }
}

/// The share of the local spacing at and below which
/// [`ArtPairs::Close`]'s gate is fully open ([`close_gate`]).
pub const CLOSE_FULL: f64 = 0.95;

/// The gate's slope in `u = (r/s)²`: from 0 at `u = 1` to 1 at
/// `u = CLOSE_FULL²`.
const CLOSE_SLOPE: f64 = 1.0 / (1.0 - CLOSE_FULL * CLOSE_FULL);

/// The close-pair gate of the artificial stress ([`ArtPairs::Close`]): 0
/// for a pair at or beyond its local spacing `s = κ V̄^(1/d)` (`V̄` the
/// pair's mean particle volume `m/ρ`, so `s` follows the local strain;
/// `κ²` the smaller of the pair's [`Model::close_scales`], 1 on a square
/// lattice), rising linearly in `(r/s)²` to 1 at `r = CLOSE_FULL s`. A
/// smoothly strained lattice keeps its nearest neighbours at `s` and sees
/// none of the term; the zig-zag clumping of the tensile instability
/// brings every other pair inside it.
#[inline]
pub fn close_gate(r2: f64, vol: f64, k2: f64, dim: usize) -> f64 {
    let s2 = if dim == 1 { vol * vol } else { vol } * k2;
    ((1.0 - r2 / s2) * CLOSE_SLOPE).clamp(0.0, 1.0)
}

/// [`close_gate`] for four pairs, one to a lane (bit-identical).
#[inline(always)]
fn close_gate_lanes(r2: F4, vol: F4, k2: F4, dim: usize) -> F4 {
    let s2 = if dim == 1 { vol * vol } else { vol } * k2;
    ((1.0 - r2 / s2) * CLOSE_SLOPE)
        .min(F4::splat(1.0))
        .max(F4::splat(0.0))
}

/// [`art_weight`] for four pairs, one to a lane: the same operations in
/// the same order (bit-identical); lanes outside the support hold values
/// for the caller to drop.
#[inline(always)]
fn art_weight_lanes(r2: F4, dp: F4, hij: F4, n: f64) -> F4 {
    let q2 = r2 / (hij * hij);
    let qd = dp / hij;
    let f = kernel::shape_lanes(q2.sqrt(), q2) / kernel::shape_lanes(qd, qd * qd);
    if n == 4.0 {
        let f2 = f * f;
        f2 * f2
    } else {
        F4::new(f.to_array().map(|f| f.powf(n)))
    }
}

/// The velocity jump the viscosity sees: `v_ij` less the linear
/// reconstruction of each side to the pair's midpoint, limited (van Leer).
///
/// Plain Monaghan viscosity acts on every approaching pair, so it also damps
/// smooth compression and smears every wave; what survives of a step after
/// one transit is then lost at a contact that cannot pull (the release front
/// reaches the face spread out, and the face opens on its first part). With
/// each side extrapolated to the midpoint by its own velocity gradient
/// `∇v` (pass B), the jump is `O(Δx²)` where the field is smooth and stays
/// whole at a front, where the two sides' slopes disagree and the limiter
/// `φ = 4r/(1+r)²` (`r` the ratio of the projected slopes, 0 when they
/// differ in sign) turns the reconstruction off. The same idea is used for
/// the viscosity of CRKSPH (Frontiere, Raskin & Owen 2017). `x_ij = x_i − x_j`.
#[inline]
pub fn reconstructed_jump(vij: DVec2, xij: DVec2, gv_i: &Mat2, gv_j: &Mat2) -> DVec2 {
    let di = gv_i.mul_vec(xij);
    let dj = gv_j.mul_vec(xij);
    let (si, sj) = (xij.dot(di), xij.dot(dj));
    if si * sj <= 0.0 {
        return vij;
    }
    // 4r/(1+r)² with r = si/sj, in one division.
    let phi = (4.0 * si * sj / ((si + sj) * (si + sj))).min(1.0);
    vij - (di + dj) * (0.5 * phi)
}

/// Monaghan's `Π_ij` (docs/method.md §4), zero for receding pairs.
#[inline]
pub fn viscosity_pi(
    alpha: f64,
    beta: f64,
    hij: f64,
    xij: DVec2,
    vij: DVec2,
    c_mean: f64,
    rho_mean: f64,
) -> f64 {
    let vx = vij.dot(xij);
    if vx >= 0.0 {
        return 0.0;
    }
    // μ = h v·x / D, Π = (−α c̄ μ + β μ²)/ρ̄, in one division.
    let d = xij.length_squared() + 0.01 * hij * hij;
    let hv = hij * vx;
    hv * (-alpha * c_mean * d + beta * hv) / (d * d * rho_mean)
}

/// What a pair contributes to both of its particles' momentum and energy
/// sums, from particle i's side.
struct PairTerms {
    /// `t G_ij`, `t = σ_i/ρ_i² + σ_j/ρ_j² − Π_ij I (+ artificial stress)`.
    tg: DVec2,
    /// `G_ij = ½ (L_i + L_j) ∇_i W_ij`.
    g: DVec2,
    /// `v_ij = v_i − v_j`.
    vij: DVec2,
    /// `½ Π_ij v_ij·G_ij − ½ (R_i + R_j) f^n : (v_ij ⊗ G_ij)`, the part of
    /// either particle's energy term that is the pair's own.
    shared: f64,
}

/// The momentum and energy terms of the pair `(i, b.j)`.
///
/// Swapping the particles flips `G`, `v_ij`, `x_ij` and the reconstructed
/// jump and keeps `Π_ij`, `t` and `f`, so particle j's terms are
/// `dv_j −= m_i t G_ij` and `de_j −= m_i (v_ij·(σ_j/ρ_j² G_ij) − shared)`:
/// one evaluation of a pair serves both of its particles.
#[inline]
#[allow(clippy::too_many_arguments)]
fn pair_terms(
    model: &Model,
    st: &State,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
    i: usize,
    b: &Nbr,
) -> PairTerms {
    let j = b.j as usize;
    let (pi_, pj) = (&pts[i], &pts[j]);
    let hij = 0.5 * (model.h[i] + model.h[j]);
    let xij = st.x[i] - st.x[j];
    let vij = st.v[i] - st.v[j];
    let g = (l[i] + l[j]).scale(0.5).mul_vec(b.gw);
    // The viscosity sees the reconstructed jump; the energy equation keeps
    // the true v_ij, so the viscous work is still exactly the heat booked
    // (energy conserved). Not at a surface: there ∇v is extrapolated from
    // one side only, and the face is where a contact loads the body
    // impulsively; full viscosity damps that start-up ringing.
    let vis = if model.av_reconstruct && !surface[i] && !surface[j] {
        reconstructed_jump(vij, xij, &gv[i], &gv[j])
    } else {
        vij
    };
    let pi = viscosity_pi(
        model.alpha,
        model.beta,
        hij,
        xij,
        vis,
        0.5 * (pi_.c + pj.c),
        0.5 * (st.rho[i] + st.rho[j]),
    );
    let mut t = pi_.sr2.add_scaled(&pj.sr2, 1.0);
    t.xx -= pi;
    t.yy -= pi;
    // The artificial stress's work on the pair, half to each particle, is
    // booked as heat: ½ (R_i + R_j) f^n : (v_ij ⊗ G_ij). docs/method.md §4 puts
    // R in the momentum bracket only, which leaves its work in no energy
    // (the rubber rings' total swung by 8 %); booked, the ledger closes as
    // for the viscosity.
    //
    // A pair acts only where one of its particles is in tension, which
    // both codes test alike on the trace of `R_i + R_j` (R is negative
    // semi-definite, so the trace is zero only with R): the lane code
    // skips whole rows of four untouched by tension on that test.
    //
    // It holds intact material together against the tensile instability;
    // a failed particle is bonded to nothing and takes no part in it.
    let mut art_work = 0.0;
    let bonded = || {
        st.damage.is_empty() || !(strength::failed(st.damage[i]) || strength::failed(st.damage[j]))
    };
    if let Some(a) = model.artificial_stress.filter(|_| bonded()) {
        let rs = pi_.r.add_scaled(&pj.r, 1.0);
        let r2 = xij.length_squared();
        let gate = match a.pairs {
            ArtPairs::All => 1.0,
            ArtPairs::Close => {
                let vol = 0.5 * (model.mass[i] / st.rho[i] + model.mass[j] / st.rho[j]);
                let ks = &model.close_scale;
                let k2 = if ks.is_empty() { 1.0 } else { ks[i].min(ks[j]) };
                close_gate(r2, vol, k2, model.dim)
            }
        };
        if rs.xx + rs.yy < 0.0 && gate > 0.0 {
            let dp = 0.5 * (model.spacing_of(i) + model.spacing_of(j));
            let rf = rs.scale(art_weight(r2, dp, hij, a.n) * gate);
            t = t.add_scaled(&rf, 1.0);
            art_work = 0.5 * vij.dot(rf.mul_vec(g));
        }
    }
    PairTerms {
        tg: t.mul_vec(g),
        g,
        vij,
        shared: 0.5 * pi * vij.dot(g) - art_work,
    }
}

/// The forces pass: `dv_i/dt` and `de_i/dt` from the SPH sums, each pair evaluated
/// once ([`Neighbours::sweep`]); rigid particles get zero rates.
///
/// `dv_i/dt = Σ_j m_j t G_ij` and `de_i/dt = −Σ_j m_j (σ_i/ρ_i² − ½Π I +
/// ½ (R_i + R_j) f^n) : (v_ij ⊗ G_ij)` (docs/method.md §4).
///
/// Scenes with no rigid body (the common case: impacts between deforming
/// bodies) take the lane code, four pairs of a row at a time
/// (`lane_terms`); the others take the one-pair code (`pair_terms`). Both
/// give the same bits.
pub fn momentum_energy(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
) -> (Vec<DVec2>, Vec<f64>) {
    sums(model, st, nb, l, gv, surface, pts, lanes_serve(model), None)
}

/// A pair's energy vectors, kept by [`momentum_keeping`] in the pair's
/// slot of the sweep: particle i's `X_i = (σ_i/ρ_i² − ½Π_ij I + ½ (R_i +
/// R_j) f^n) G_ij` and particle j's `X_j = t G_ij − X_i`, so that the
/// energy sums at any velocities `w` are `de_i/dt = −Σ_j m_j w_ij·X_i`
/// and `de_j/dt = −Σ_i m_i w_ij·X_j` ([`energy_replay`]).
pub type PairVectors = [DVec2; 2];

/// The forces pass's momentum sums (`dv/dt`, as [`momentum_energy`], the same bits)
/// with the energy sums left for later: each pair's [`PairVectors`] go to
/// `keep` instead. The leapfrog (`CpuSolver::step`) books the work of the
/// forces on the velocity at the end of the step, which the momentum sums
/// themselves give.
#[allow(clippy::too_many_arguments)]
pub fn momentum_keeping(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
    keep: &mut Vec<PairVectors>,
) -> Vec<DVec2> {
    keep.resize(nb.store_len(), [DVec2::ZERO; 2]);
    let lanes = lanes_serve(model);
    sums(model, st, nb, l, gv, surface, pts, lanes, Some(keep)).0
}

/// `de/dt` from the pairs kept by [`momentum_keeping`] with the work done
/// on the velocities `w` (rigid particles: zero), in the sweep's order.
pub fn energy_replay(
    model: &Model,
    nb: &Neighbours,
    kept: &[PairVectors],
    w: &[DVec2],
) -> Vec<f64> {
    let mut acc = vec![0.0f64; model.len()];
    nb.replay(&mut acc, kept, |i, j, x, ai, aj| {
        let wij = w[i] - w[j];
        if !model.rigid(i) {
            *ai -= model.mass[j] * wij.dot(x[0]);
        }
        if let Some(aj) = aj.filter(|_| !model.rigid(j)) {
            *aj -= model.mass[i] * wij.dot(x[1]);
        }
    });
    acc
}

/// Particle i's energy vector `X_i = ½ (t G + (σ_i/ρ_i² − σ_j/ρ_j²) G)`
/// and j's `t G − X_i` ([`PairVectors`]).
#[inline]
fn pair_vectors(tg: DVec2, sig: DVec2, sjg: DVec2) -> PairVectors {
    let xi = (tg + (sig - sjg)) * 0.5;
    [xi, tg - xi]
}

/// Whether the lane code serves the scene: it does not do the rigid
/// bodies' zero rates.
fn lanes_serve(model: &Model) -> bool {
    !model.any_rigid
}

/// [`momentum_energy`] by the lane code (`lanes`, [`lanes_serve`]) or by
/// the one-pair code; with `keep`, the energy terms' vectors go there
/// instead of into the sums ([`momentum_keeping`]).
#[allow(clippy::too_many_arguments)]
fn sums(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
    lanes: bool,
    keep: Option<&mut Vec<PairVectors>>,
) -> (Vec<DVec2>, Vec<f64>) {
    let args = (model, st, nb, l, gv, surface, pts);
    match keep {
        Some(keep) => sums_into(args, lanes, keep),
        // Zero-sized slots: the energy terms go into the sums.
        None => sums_into(args, lanes, &mut vec![(); nb.store_len()]),
    }
}

/// Where a pass's energy terms go: into the particles' sums (`()`, no
/// memory) or into the pair's slot ([`PairVectors`]).
trait EnergyTerms: Send + Default {
    /// Lane k of the pair terms `t`: i's and, for a near pair, j's.
    fn lane(self_: &mut Self, t: &LaneTerms, k: usize, ei: &mut f64, ej: Option<&mut f64>);
    /// The one-pair terms `p` of pair `ij = (i, j)` with the masses
    /// `m = (m_i, m_j)`: i's side unless i is rigid, j's for a near pair.
    fn pair(
        self_: &mut Self,
        p: &PairTerms,
        pts: &[StressPoint],
        ij: (usize, usize),
        m: (f64, f64),
        ei: Option<&mut f64>,
        ej: Option<&mut f64>,
    );
}

impl EnergyTerms for () {
    #[inline(always)]
    fn lane(_: &mut (), t: &LaneTerms, k: usize, ei: &mut f64, ej: Option<&mut f64>) {
        *ei -= t.e_i[k];
        if let Some(ej) = ej {
            *ej -= t.e_j[k];
        }
    }

    #[inline(always)]
    fn pair(
        _: &mut (),
        p: &PairTerms,
        pts: &[StressPoint],
        (i, j): (usize, usize),
        (mi, mj): (f64, f64),
        ei: Option<&mut f64>,
        ej: Option<&mut f64>,
    ) {
        if let Some(ei) = ei {
            *ei -= mj * (p.vij.dot(pts[i].sr2.mul_vec(p.g)) - p.shared);
        }
        if let Some(ej) = ej {
            *ej -= mi * (p.vij.dot(pts[j].sr2.mul_vec(p.g)) - p.shared);
        }
    }
}

impl EnergyTerms for PairVectors {
    #[inline(always)]
    fn lane(slot: &mut Self, t: &LaneTerms, k: usize, _: &mut f64, _: Option<&mut f64>) {
        *slot = [
            DVec2::new(t.x_i[0][k], t.x_i[1][k]),
            DVec2::new(t.x_j[0][k], t.x_j[1][k]),
        ];
    }

    #[inline(always)]
    fn pair(
        slot: &mut Self,
        p: &PairTerms,
        pts: &[StressPoint],
        (i, j): (usize, usize),
        _: (f64, f64),
        _: Option<&mut f64>,
        _: Option<&mut f64>,
    ) {
        *slot = pair_vectors(p.tg, pts[i].sr2.mul_vec(p.g), pts[j].sr2.mul_vec(p.g));
    }
}

/// The inputs of the momentum pass.
type Inputs<'a> = (
    &'a Model,
    &'a State,
    &'a Neighbours,
    &'a [Mat2],
    &'a [Mat2],
    &'a [bool],
    &'a [StressPoint],
);

/// [`sums`] with the energy terms going to `E` (one slot per visited
/// candidate).
fn sums_into<E: EnergyTerms>(
    (model, st, nb, l, gv, surface, pts): Inputs<'_>,
    lanes: bool,
    slots: &mut [E],
) -> (Vec<DVec2>, Vec<f64>) {
    let mut acc = vec![(DVec2::ZERO, 0.0); model.len()];
    if lanes {
        assert!(lanes_serve(model), "the lane code serves this scene");
        let rec = partners(model, st, l, gv, surface, pts);
        let art = art_rows(model, st, pts);
        nb.sweep_chunks_store(
            model,
            &st.x,
            &mut acc,
            slots,
            |i, c, ai, piece, base, slots| {
                let t = lane_terms(&rec, art.as_ref(), model, i, c);
                for (k, slot) in slots.iter_mut().enumerate() {
                    if c.inside & (1 << k) == 0 {
                        *slot = E::default();
                        continue;
                    }
                    ai.0 += DVec2::new(t.tg_mj[0][k], t.tg_mj[1][k]);
                    let aj = c.near.then(|| &mut piece[c.j[k] as usize - base]);
                    let ej = aj.map(|aj| {
                        aj.0 -= DVec2::new(t.tg_mi[0][k], t.tg_mi[1][k]);
                        &mut aj.1
                    });
                    E::lane(slot, &t, k, &mut ai.1, ej);
                }
            },
        );
        return acc.into_iter().unzip();
    }
    let terms = |i, b: &Nbr| pair_terms(model, st, l, gv, surface, pts, i, b);
    nb.sweep_store(model, &st.x, &mut acc, slots, |i, b, ai, aj, slot| {
        let j = b.j as usize;
        // Rigid particles keep zero rates; a far pair has no j side here.
        let aj = aj.filter(|_| !model.rigid(j));
        let ri = model.rigid(i);
        if ri && aj.is_none() {
            *slot = E::default();
            return;
        }
        let p = terms(i, b);
        let (mi, mj) = (model.mass[i], model.mass[j]);
        let ei = (!ri).then(|| {
            ai.0 += p.tg * mj;
            &mut ai.1
        });
        let ej = aj.map(|aj| {
            aj.0 -= p.tg * mi;
            &mut aj.1
        });
        E::pair(slot, &p, pts, (i, j), (mi, mj), ei, ej);
    });
    acc.into_iter().unzip()
}

/// What four pairs of one row add to their particles' sums: i's side and
/// j's, the masses applied.
struct LaneTerms {
    tg_mj: [[f64; LANES]; 2],
    tg_mi: [[f64; LANES]; 2],
    e_i: [f64; LANES],
    e_j: [f64; LANES],
    /// The pair's [`PairVectors`] (x and y rows).
    x_i: [[f64; LANES]; 2],
    x_j: [[f64; LANES]; 2],
}

/// What the momentum pass reads of a particle, in one record of five rows
/// of four, so that four partners' values come into lanes by a transpose
/// of their rows ([`columns`]) instead of twenty single gathers.
#[derive(Clone, Copy)]
#[repr(C, align(32))]
struct Partner {
    /// `x`, `v`.
    xv: [f64; 4],
    /// `L` (xx, xy, yx, yy).
    l: [f64; 4],
    /// `∇v` (xx, xy, yx, yy); zero unless the viscosity is reconstructed.
    gv: [f64; 4],
    /// `σ/ρ²` (xx, xy, yy) and the sound speed.
    sc: [f64; 4],
    /// `ρ`, `h`, `m`, and 1 on a surface particle (else 0).
    rhm: [f64; 4],
}

/// Every particle's [`Partner`] record for one momentum pass (written once,
/// read by the twenty or so pairs each particle is in).
fn partners(
    model: &Model,
    st: &State,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
) -> Vec<Partner> {
    use rayon::prelude::*;
    (0..model.len())
        .into_par_iter()
        .map(|i| {
            let (x, v, li, p) = (st.x[i], st.v[i], &l[i], &pts[i]);
            let g = if model.av_reconstruct {
                gv[i]
            } else {
                Mat2::ZERO
            };
            Partner {
                xv: [x.x, x.y, v.x, v.y],
                l: [li.xx, li.xy, li.yx, li.yy],
                gv: [g.xx, g.xy, g.yx, g.yy],
                sc: [p.sr2.xx, p.sr2.xy, p.sr2.yy, p.c],
                rhm: [
                    st.rho[i],
                    model.h[i],
                    model.mass[i],
                    if surface[i] { 1.0 } else { 0.0 },
                ],
            }
        })
        .collect()
}

/// What the lane code reads of the artificial stress: every particle's
/// `R` (xx, xy, yy) and its body's spacing, one row of four each, and
/// whether `R` is not zero (the particle is in tension).
struct ArtRows {
    rows: Vec<[f64; 4]>,
    tension: Vec<bool>,
    /// 1 for a particle that has not failed, 0 for one that has (which
    /// takes no part in the term); empty while no particle has failed.
    intact: Vec<f64>,
}

/// The [`ArtRows`] of one momentum pass, when the scene has the
/// artificial stress (else none: the pass reads nothing more).
fn art_rows(model: &Model, st: &State, pts: &[StressPoint]) -> Option<ArtRows> {
    use rayon::prelude::*;
    model.artificial_stress?;
    let (rows, tension) = (0..model.len())
        .into_par_iter()
        .map(|i| {
            let r = &pts[i].r;
            ([r.xx, r.xy, r.yy, model.spacing_of(i)], r.xx + r.yy < 0.0)
        })
        .unzip();
    let intact = if st.damage.iter().any(|&d| strength::failed(d)) {
        let state = |&d: &f64| if strength::failed(d) { 0.0 } else { 1.0 };
        st.damage.iter().map(state).collect()
    } else {
        Vec::new()
    };
    Some(ArtRows {
        rows,
        tension,
        intact,
    })
}

/// [`pair_terms`] and the sums' updates for up to four pairs of row i at
/// once, with no rigid particle; `art` holds the artificial stress's
/// rows ([`art_rows`]) when the scene has it. Operation for
/// operation the one-pair code in its order, so the results are
/// bit-identical; its branches (the reconstruction's early return and
/// surface test, the viscosity's receding pairs) become selects between
/// both outcomes. Lanes that hold no pair (`c.inside` clear) compute
/// values the caller drops.
#[inline(always)]
fn lane_terms(
    rec: &[Partner],
    art: Option<&ArtRows>,
    model: &Model,
    i: usize,
    c: &Chunk,
) -> LaneTerms {
    let r: [&Partner; LANES] = std::array::from_fn(|k| &rec[c.j[k] as usize]);
    let me = &rec[i];
    // Partner j's rows into lanes, particle i's as scalars.
    let [xjx, xjy, vjx, vjy] = columns([&r[0].xv, &r[1].xv, &r[2].xv, &r[3].xv]);
    let [ljxx, ljxy, ljyx, ljyy] = columns([&r[0].l, &r[1].l, &r[2].l, &r[3].l]);
    let [sjxx, sjxy, sjyy, cj] = columns([&r[0].sc, &r[1].sc, &r[2].sc, &r[3].sc]);
    let [rhoj, hj, mj, surj] = columns([&r[0].rhm, &r[1].rhm, &r[2].rhm, &r[3].rhm]);
    let [xix, xiy, vix, viy] = me.xv;
    let [lixx, lixy, liyx, liyy] = me.l;
    let [sixx, sixy, siyy, ci] = me.sc;
    let [rhoi, hi, mi, suri] = me.rhm;

    let hij = 0.5 * (hi + hj);
    let xx = xix - xjx;
    let xy = xiy - xjy;
    let vx = vix - vjx;
    let vy = viy - vjy;
    let (gwx, gwy) = (c.gwx, c.gwy);
    // G = ½ (L_i + L_j) ∇W.
    let axx = (lixx + ljxx) * 0.5;
    let axy = (lixy + ljxy) * 0.5;
    let ayx = (liyx + ljyx) * 0.5;
    let ayy = (liyy + ljyy) * 0.5;
    let gx = axx * gwx + axy * gwy;
    let gy = ayx * gwx + ayy * gwy;
    // The viscosity's velocity jump (reconstructed_jump).
    let (wx, wy) = if model.av_reconstruct {
        let [gixx, gixy, giyx, giyy] = me.gv;
        let [gjxx, gjxy, gjyx, gjyy] = columns([&r[0].gv, &r[1].gv, &r[2].gv, &r[3].gv]);
        let dix = gixx * xx + gixy * xy;
        let diy = giyx * xx + giyy * xy;
        let djx = gjxx * xx + gjxy * xy;
        let djy = gjyx * xx + gjyy * xy;
        let si = xx * dix + xy * diy;
        let sj = xx * djx + xy * djy;
        let sum = si + sj;
        let phi = (4.0 * si * sj / (sum * sum)).min(F4::splat(1.0));
        let half = 0.5 * phi;
        let surface = (suri + surj).ge(F4::splat(1.0));
        let keep = surface.or((si * sj).le(F4::splat(0.0)));
        (
            keep.select(vx, vx - (dix + djx) * half),
            keep.select(vy, vy - (diy + djy) * half),
        )
    } else {
        (vx, vy)
    };
    // Monaghan's Π (viscosity_pi).
    let c_mean = 0.5 * (ci + cj);
    let rho_mean = 0.5 * (rhoi + rhoj);
    let wdx = wx * xx + wy * xy;
    let d = (xx * xx + xy * xy) + 0.01 * hij * hij;
    let hv = hij * wdx;
    let pi_raw = hv * (-model.alpha * c_mean * d + model.beta * hv) / (d * d * rho_mean);
    let pi = wdx.ge(F4::splat(0.0)).select(F4::splat(0.0), pi_raw);
    // t = σ_i/ρ_i² + σ_j/ρ_j² − Π I (+ (R_i + R_j) f^n), t G, and each
    // side's energy term.
    let mut txx = sixx + sjxx - pi;
    let mut tyy = siyy + sjyy - pi;
    let mut txy = sixy + sjxy;
    let mut art_work = None;
    let bonded = |art: &ArtRows| art.intact.is_empty() || art.intact[i] > 0.0;
    if let (Some(art), Some(a)) = (art.filter(|a| bonded(a)), model.artificial_stress) {
        // Rows untouched by tension skip it, and so do rows with no close
        // pair in the close-pair form; the others take it lane by lane
        // where the trace of R_i + R_j is negative and the gate open
        // (pair_terms).
        if art.tension[i] || c.j.iter().any(|&j| art.tension[j as usize]) {
            let r2 = xx * xx + xy * xy;
            // The close-pair gate first: most rows have no pair inside
            // it and read no R. κ² ≤ 1 only shuts it further, so a gate
            // shut at κ² = 1 is shut.
            let gate = match a.pairs {
                ArtPairs::All => None,
                ArtPairs::Close => {
                    let vol = (mi / rhoi + mj / rhoj) * 0.5;
                    let mut gate = close_gate_lanes(r2, vol, F4::splat(1.0), model.dim);
                    let ks = &model.close_scale;
                    if !ks.is_empty() && F4::splat(0.0).lt(gate).bits() != 0 {
                        let k2 = F4::gather(|k| ks[c.j[k] as usize]).min(F4::splat(ks[i]));
                        gate = close_gate_lanes(r2, vol, k2, model.dim);
                    }
                    Some(gate)
                }
            };
            let open = gate.map_or(true, |g| F4::splat(0.0).lt(g).bits() != 0);
            if open {
                let [rjxx, rjxy, rjyy, spj] = columns(c.j.map(|j| &art.rows[j as usize]));
                let [rixx, rixy, riyy, spi] = art.rows[i];
                let (sxx, sxy, syy) = (rixx + rjxx, rixy + rjxy, riyy + rjyy);
                let mut on = (sxx + syy).lt(F4::splat(0.0));
                if let Some(gate) = gate {
                    on = on.and(F4::splat(0.0).lt(gate));
                }
                if !art.intact.is_empty() {
                    let ok = F4::gather(|k| art.intact[c.j[k] as usize]);
                    on = on.and(F4::splat(0.0).lt(ok));
                }
                if on.bits() != 0 {
                    let dp = 0.5 * (spi + spj);
                    let mut fnn = art_weight_lanes(r2, dp, hij, a.n);
                    if let Some(gate) = gate {
                        fnn = fnn * gate;
                    }
                    let (rfxx, rfxy, rfyy) = (sxx * fnn, sxy * fnn, syy * fnn);
                    txx = on.select(txx + rfxx, txx);
                    tyy = on.select(tyy + rfyy, tyy);
                    txy = on.select(txy + rfxy, txy);
                    let (rgx, rgy) = (rfxx * gx + rfxy * gy, rfxy * gx + rfyy * gy);
                    art_work = Some(on.select(0.5 * (vx * rgx + vy * rgy), F4::splat(0.0)));
                }
            }
        }
    }
    let tgx = txx * gx + txy * gy;
    let tgy = txy * gx + tyy * gy;
    let mut shared = 0.5 * pi * (vx * gx + vy * gy);
    if let Some(w) = art_work {
        shared = shared - w;
    }
    // σ_i/ρ_i² G and σ_j/ρ_j² G.
    let (sigx, sigy) = (sixx * gx + sixy * gy, sixy * gx + siyy * gy);
    let (sjgx, sjgy) = (sjxx * gx + sjxy * gy, sjxy * gx + sjyy * gy);
    let ei = vx * sigx + vy * sigy;
    let ej = vx * sjgx + vy * sjgy;
    // pair_vectors, lane by lane.
    let xix = (tgx + (sigx - sjgx)) * 0.5;
    let xiy = (tgy + (sigy - sjgy)) * 0.5;
    LaneTerms {
        tg_mj: [(tgx * mj).to_array(), (tgy * mj).to_array()],
        tg_mi: [(tgx * mi).to_array(), (tgy * mi).to_array()],
        e_i: (mj * (ei - shared)).to_array(),
        e_j: (mi * (ej - shared)).to_array(),
        x_i: [xix.to_array(), xiy.to_array()],
        x_j: [(tgx - xix).to_array(), (tgy - xiy).to_array()],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::{CpuBench, DiskCase};
    use crate::cpu::{eos_and_stress, kinematics, neighbours, SKIN_FRACTION};

    /// The lane code gives the one-pair code's sums bit for bit, on the
    /// disks in contact with a velocity field stirred so that every branch
    /// is taken both ways in many pairs (receding and approaching pairs,
    /// the limiter on and off): with the reconstructed viscosity and
    /// without, on candidate lists with a skin (candidates beyond the
    /// support in the rows), and in kernel mode (SPH sums across the
    /// bodies) with the second disk's `h` changed, so that pairs across
    /// the contact take `h_ij` of two different lengths.
    #[test]
    fn lanes_match_one_pair_code_bit_for_bit() {
        let bench = CpuBench::new(&DiskCase::new(3_000).expect("the case")).expect("in contact");
        let (base, mut st) = (bench.model().clone(), bench.state().clone());
        for (i, v) in st.v.iter_mut().enumerate() {
            let a = (i as f64 * 0.618_033_988_7).fract() * std::f64::consts::TAU;
            *v += DVec2::new(a.cos(), a.sin()) * 0.3;
        }
        // Densities and deviators stirred too, so that the principal
        // stresses take every sign pattern and the artificial stress acts.
        let rho0 = st.rho[0];
        for i in 0..st.rho.len() {
            let a = (i as f64 * 0.414_213_562_3).fract() - 0.5;
            let b = (i as f64 * 0.732_050_807_6).fract() - 0.5;
            st.rho[i] *= 1.0 + 2e-3 * a;
            st.s[i] = Sym {
                xx: 2e-3 * rho0 * b,
                yy: -1e-3 * rho0 * a,
                xy: 1.5e-3 * rho0 * (a + b),
                zz: 1e-3 * rho0 * (b - a),
            };
        }
        let tensile = |m: &Model, st: &State| {
            let pts = eos_and_stress(m, st);
            pts.iter().filter(|p| p.r != Sym::default()).count()
        };
        // Every seventh particle failed: it takes no part in the artificial
        // stress, and no tension.
        let mut failed = st.clone();
        failed.damage = (0..st.x.len())
            .map(|i| if i % 7 == 3 { 1.0 } else { 0.4 })
            .collect();
        for (reconstruct, h_ratio, art, damaged) in [
            (true, 1.0, None, false),
            (false, 1.0, None, false),
            (true, 1.15, None, false),
            (true, 1.0, Some((0.3, 4.0, ArtPairs::All)), false),
            (false, 1.15, Some((0.2, 3.5, ArtPairs::All)), false),
            (true, 1.0, Some((0.3, 4.0, ArtPairs::Close)), false),
            (false, 1.15, Some((0.2, 3.5, ArtPairs::Close)), false),
            (true, 1.0, Some((0.3, 4.0, ArtPairs::All)), true),
            (false, 1.0, Some((0.3, 4.0, ArtPairs::Close)), true),
        ] {
            let st = if damaged { &failed } else { &st };
            let mut model = base.clone();
            model.artificial_stress = art.map(as_of);
            if art.is_some_and(|a| a.1 == 3.5 && a.2 == ArtPairs::Close) {
                // Placement scales below 1, as jitter leaves them.
                model.close_scale = (0..model.len())
                    .map(|i| 1.0 - 0.03 * (i as f64 * 0.377_964_473_0).fract())
                    .collect();
            }
            if art.is_some() {
                let n = tensile(&model, st);
                assert!(n > model.len() / 4 && n < model.len(), "{n} in tension");
            }
            model.av_reconstruct = reconstruct;
            model.contact = h_ratio == 1.0;
            for i in 0..model.len() {
                if model.body[i] == 1 {
                    model.h[i] *= h_ratio;
                }
            }
            let skin = SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max);
            let nb = neighbours::find_with_skin(&model, &st.x, skin);
            let k = kinematics::kinematics(&model, st, &nb);
            let pts = eos_and_stress(&model, st);
            let args = (&model, &st, &nb, &k.l, &k.gv, &k.surface, &pts);
            let one = sums(
                args.0, args.1, args.2, args.3, args.4, args.5, args.6, false, None,
            );
            let four = sums(
                args.0, args.1, args.2, args.3, args.4, args.5, args.6, true, None,
            );
            let bits = |v: &DVec2| (v.x.to_bits(), v.y.to_bits());
            for i in 0..model.len() {
                assert_eq!(bits(&one.0[i]), bits(&four.0[i]), "dv of {i}");
                assert_eq!(one.1[i].to_bits(), four.1[i].to_bits(), "de of {i}");
            }
            // The sums are not trivially equal: the pass does work.
            assert!(one.0.iter().filter(|a| a.length() > 0.0).count() > model.len() / 2);
        }
    }

    /// The lane code gives the one-pair code's sums bit for bit in 1-D too
    /// (rows of two to five candidates, so most chunks are partial), with
    /// the artificial stress on a stirred state in tension and compression.
    #[test]
    fn lanes_match_one_pair_code_in_1d() {
        let scene = crate::scene::Scene::from_toml_str(
            r#"
            [simulation]
            dimension = 1
            end_time = 1.0e-6
            interaction = "penalty"
            [materials.steel]
            density = 7850.0
            shear_modulus = 77.0e9
            eos = { kind = "mie_gruneisen", c0 = 4580.0, s = 1.49, gamma0 = 2.02 }
            [[bodies]]
            name = "flyer"
            material = "steel"
            spacing = 1.0e-5
            velocity = [200.0]
            shape = { kind = "segment", from = -0.001, to = 0.0 }
            [[bodies]]
            name = "target"
            material = "steel"
            spacing = 1.0e-5
            velocity = [0.0]
            shape = { kind = "segment", from = 0.0, to = 0.002 }
            "#,
            "the 1-D test scene",
        )
        .expect("a valid scene");
        let (mut model, mut st) = Model::new(&scene);
        for i in 0..st.rho.len() {
            let a = (i as f64 * 0.414_213_562_3).fract() - 0.5;
            st.rho[i] *= 1.0 + 2e-3 * a;
            st.v[i].x += 30.0 * ((i as f64 * 0.618_033_988_7).fract() - 0.5);
            st.s[i].xx = 1e8 * ((i as f64 * 0.732_050_807_6).fract() - 0.5);
            st.s[i].yy = -0.5 * st.s[i].xx;
            st.s[i].zz = -0.5 * st.s[i].xx;
        }
        let mut seen = Vec::new();
        for art in [
            None,
            Some((0.3, 4.0, ArtPairs::All)),
            Some((0.2, 3.5, ArtPairs::All)),
            Some((0.3, 4.0, ArtPairs::Close)),
        ] {
            model.artificial_stress = art.map(as_of);
            let skin = SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max);
            let nb = neighbours::find_with_skin(&model, &st.x, skin);
            let k = kinematics::kinematics(&model, &st, &nb);
            let pts = eos_and_stress(&model, &st);
            let a = (&model, &st, &nb, &k.l, &k.gv, &k.surface, &pts);
            let one = sums(a.0, a.1, a.2, a.3, a.4, a.5, a.6, false, None);
            let four = sums(a.0, a.1, a.2, a.3, a.4, a.5, a.6, true, None);
            for i in 0..model.len() {
                assert_eq!(
                    one.0[i].x.to_bits(),
                    four.0[i].x.to_bits(),
                    "dv of {i}, {art:?}"
                );
                assert_eq!(
                    one.1[i].to_bits(),
                    four.1[i].to_bits(),
                    "de of {i}, {art:?}"
                );
            }
            seen.push(one.0);
        }
        // Each form does work of its own: the close-pair form acts (the
        // stirred densities open its gate on some pairs) and differs from
        // the classic one.
        let differ = |a: &[DVec2], b: &[DVec2]| a.iter().zip(b).filter(|(p, q)| p != q).count();
        assert!(differ(&seen[0], &seen[1]) > model.len() / 2);
        let close = differ(&seen[0], &seen[3]);
        assert!(
            close > 10 && close < differ(&seen[0], &seen[1]),
            "{close} changed"
        );
    }

    fn as_of((epsilon, n, pairs): (f64, f64, ArtPairs)) -> crate::scene::ArtificialStress {
        crate::scene::ArtificialStress { epsilon, n, pairs }
    }

    /// The close-pair gate: shut at and beyond the local spacing `V̄^(1/d)`,
    /// open fully from `CLOSE_FULL` of it in, linear in `(r/s)²` between,
    /// in 1-D (`s = V̄`) and 2-D (`s = √V̄`).
    #[test]
    fn close_gate_opens_inside_the_local_spacing() {
        for (dim, vol, s) in [(1, 2.0e-5, 2.0e-5), (2, 4.0e-10, 2.0e-5)] {
            let g = |r: f64| close_gate(r * r, vol, 1.0, dim);
            assert_eq!(g(s), 0.0);
            assert_eq!(g(1.5 * s), 0.0);
            assert_eq!(g(CLOSE_FULL * s * (1.0 - 1e-12)), 1.0);
            assert_eq!(g(0.5 * s), 1.0);
            let r = 0.975 * s;
            let want = (1.0 - 0.975f64.powi(2)) / (1.0 - CLOSE_FULL * CLOSE_FULL);
            assert!((g(r) - want).abs() < 1e-12, "{} against {want}", g(r));
            assert!(g(0.99 * s) > 0.0 && g(0.99 * s) < g(0.98 * s));
            // κ² scales the spacing: shut beyond κ s.
            assert_eq!(close_gate((0.91 * s).powi(2), vol, 0.81, dim), 0.0);
            assert_eq!(close_gate((0.85 * s).powi(2), vol, 0.81, dim), 1.0);
        }
    }

    /// The artificial stress without the principal angle is the angle
    /// form's (rotate to principal axes, keep `−ε σ̄/ρ²` of the tensile
    /// values, rotate back) on stresses with no, one and two tensile
    /// principal values, and where the two principal values meet.
    #[test]
    fn artificial_stress_is_the_principal_axes_form() {
        let angle_form = |eps: f64, s: &Sym, rho: f64| {
            let (a, b, th) = s.principal();
            let k = |v: f64| if v > 0.0 { -eps * v / (rho * rho) } else { 0.0 };
            Sym::from_principal(k(a), k(b), th)
        };
        let mut seen = [0usize; 3];
        for i in 0..400 {
            let u = |m: f64| ((i as f64 * m).fract() - 0.5) * 2.0e9;
            let mut s = Sym {
                xx: u(0.618_033_988_7),
                yy: u(0.414_213_562_3),
                xy: u(0.732_050_807_6) * 0.5,
                zz: u(0.236_067_977_5),
            };
            if i % 50 == 0 {
                (s.yy, s.xy) = (s.xx, 0.0);
            }
            let (a, b, _) = s.principal();
            seen[(a > 0.0) as usize + (b > 0.0) as usize] += 1;
            let (got, want) = (
                artificial_stress(0.3, &s, 7850.0),
                angle_form(0.3, &s, 7850.0),
            );
            let scale = 0.3 * 2.0e9 / (7850.0f64 * 7850.0);
            for (g, w) in [(got.xx, want.xx), (got.yy, want.yy), (got.xy, want.xy)] {
                assert!(
                    (g - w).abs() <= 1e-12 * scale,
                    "{s:?}: {got:?} against {want:?}"
                );
            }
            assert_eq!(got.zz, 0.0);
        }
        assert!(seen.iter().all(|&n| n > 50), "sign patterns {seen:?}");
    }

    /// The pair weight is `(W(r)/W(Δp))^n` from the kernel itself, inside
    /// and outside `q = 1`, with `n = 4` by squarings and other `n` by
    /// powers.
    #[test]
    fn art_weight_is_the_kernel_ratio() {
        let (dp, h) = (1.0e-5, 1.2e-5);
        for r in [0.0, 0.3e-5, 1.0e-5, 1.3e-5, 2.2e-5, 2.39e-5] {
            for n in [4.0, 3.5, 1.0] {
                let want = (kernel::w(2, r, h) / kernel::w(2, dp, h)).powf(n);
                let got = art_weight(r * r, dp, h, n);
                assert!((got - want).abs() <= 1e-13 * want.max(1.0), "r {r} n {n}");
            }
        }
        assert!((art_weight(dp * dp, dp, h, 4.0) - 1.0).abs() < 1e-14);
    }

    /// The leapfrog's momentum pass gives `momentum_energy`'s `dv/dt` bit
    /// for bit, keeps the same pair vectors in the lane code and in the
    /// one-pair code, and the energy replayed from them at the pass's own
    /// velocities is its `de/dt` up to round-off (the same terms, grouped
    /// `w·(S_i G − ½ΠG)` instead of `w·S_i G − ½Π w·G`). With velocities
    /// that differ, the replay differs: it does book the work on them.
    #[test]
    fn kept_pair_vectors_replay_the_energy_sums() {
        let bench = CpuBench::new(&DiskCase::new(3_000).expect("the case")).expect("in contact");
        let (model, mut st) = (bench.model().clone(), bench.state().clone());
        for (i, v) in st.v.iter_mut().enumerate() {
            let a = (i as f64 * 0.618_033_988_7).fract() * std::f64::consts::TAU;
            *v += DVec2::new(a.cos(), a.sin()) * 0.3;
        }
        let skin = SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max);
        let nb = neighbours::find_with_skin(&model, &st.x, skin);
        let k = kinematics::kinematics(&model, &st, &nb);
        let pts = eos_and_stress(&model, &st);
        let args = (&model, &st, &nb, &k.l, &k.gv, &k.surface, &pts);
        let (dv, de) = momentum_energy(args.0, args.1, args.2, args.3, args.4, args.5, args.6);
        let mut kept = [Vec::new(), Vec::new()];
        for (lanes, kept) in [true, false].into_iter().zip(&mut kept) {
            kept.resize(nb.store_len(), [DVec2::ZERO; 2]);
            let (kdv, _) = sums(
                args.0,
                args.1,
                args.2,
                args.3,
                args.4,
                args.5,
                args.6,
                lanes,
                Some(kept),
            );
            for i in 0..model.len() {
                assert_eq!(kdv[i].x.to_bits(), dv[i].x.to_bits(), "dv.x of {i}");
                assert_eq!(kdv[i].y.to_bits(), dv[i].y.to_bits(), "dv.y of {i}");
            }
        }
        let bits = |x: &PairVectors| x.map(|v| [v.x.to_bits(), v.y.to_bits()]);
        assert!(kept[0].iter().map(bits).eq(kept[1].iter().map(bits)));
        let pairs = kept[0].iter().filter(|x| x[0] != DVec2::ZERO).count();
        assert!(pairs > 5 * model.len(), "{pairs} kept pairs");

        let scale = de.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        let replay = energy_replay(&model, &nb, &kept[0], &st.v);
        for i in 0..model.len() {
            assert!(
                (replay[i] - de[i]).abs() <= 1e-12 * scale,
                "de of {i}: {} against {}",
                replay[i],
                de[i]
            );
        }
        // At other velocities the replay moves with them.
        let w: Vec<DVec2> = st.v.iter().map(|v| *v * 1.5 + DVec2::X).collect();
        let other = energy_replay(&model, &nb, &kept[0], &w);
        let moved = (0..model.len()).filter(|&i| (other[i] - de[i]).abs() > 1e-6 * scale);
        assert!(moved.count() > model.len() / 2);
        // Energy is conserved pair by pair: Σ m_i de_i = Σ_pairs m_i m_j
        // w_ij·t G_ij = −Σ m_i w_i·dv_i (the work of the forces on w).
        let heat: f64 = (0..model.len()).map(|i| model.mass[i] * other[i]).sum();
        let work: f64 = (0..model.len())
            .map(|i| model.mass[i] * w[i].dot(dv[i]))
            .sum();
        let size: f64 = (0..model.len())
            .map(|i| model.mass[i] * (w[i].dot(dv[i])).abs())
            .sum();
        assert!(
            (heat + work).abs() <= 1e-10 * size,
            "internal {heat:e} against work {work:e}"
        );
    }

    /// The lane code's sums do not depend on the thread count: the chunks
    /// of the sweep fix every sum's order (one thread against three).
    #[test]
    fn lanes_are_the_same_on_any_thread_count() {
        let bench = CpuBench::new(&DiskCase::new(3_000).expect("the case")).expect("in contact");
        let (model, st) = (bench.model(), bench.state());
        let skin = SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max);
        let nb = neighbours::find_with_skin(model, &st.x, skin);
        let k = kinematics::kinematics(model, st, &nb);
        let pts = eos_and_stress(model, st);
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a thread pool");
            pool.install(|| sums(model, st, &nb, &k.l, &k.gv, &k.surface, &pts, true, None))
        };
        let (one, three) = (on(1), on(3));
        for i in 0..model.len() {
            assert_eq!(one.0[i].x.to_bits(), three.0[i].x.to_bits(), "dv.x of {i}");
            assert_eq!(one.0[i].y.to_bits(), three.0[i].y.to_bits(), "dv.y of {i}");
            assert_eq!(one.1[i].to_bits(), three.1[i].to_bits(), "de of {i}");
        }
    }
}
