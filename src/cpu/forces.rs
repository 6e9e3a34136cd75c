//! The forces pass: momentum and energy sums (METHOD.md §4) with Monaghan artificial
//! viscosity and, when the scene asks for it, Gray–Monaghan–Swift artificial
//! stress. The pair-antisymmetric `G_ij = ½ (L_i + L_j) ∇_i W_ij` conserves
//! momentum and energy exactly in semi-discrete form.

use glam::DVec2;

use super::lanes::{columns, F4, LANES};
use super::neighbours::{Chunk, Nbr, Neighbours};
use crate::math::{Mat2, Sym};
use crate::model::{Model, State};
use crate::physics::kernel;

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

/// Artificial stress of METHOD.md §4: rotate σ/ρ² to principal axes, take
/// `−ε σ̄/ρ²` of each tensile principal value, rotate back.
#[inline]
pub fn artificial_stress(eps: f64, sigma: &Sym, rho: f64) -> Sym {
    let (a, b, th) = sigma.principal();
    let r2 = rho * rho;
    let ra = if a > 0.0 { -eps * a / r2 } else { 0.0 };
    let rb = if b > 0.0 { -eps * b / r2 } else { 0.0 };
    Sym::from_principal(ra, rb, th)
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

/// Monaghan's `Π_ij` (METHOD.md §4), zero for receding pairs.
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
    // booked as heat: ½ (R_i + R_j) f^n : (v_ij ⊗ G_ij). METHOD.md §4 puts
    // R in the momentum bracket only, which leaves its work in no energy
    // (the rubber rings' total swung by 8 %); booked, the ledger closes as
    // for the viscosity.
    let mut art_work = 0.0;
    if let Some((_, n)) = model.artificial_stress {
        let dp = 0.5
            * (model.bodies[model.body[i] as usize].spacing
                + model.bodies[model.body[j] as usize].spacing);
        let f = b.w / kernel::w(model.dim, dp, hij);
        let rf = pi_.r.add_scaled(&pj.r, 1.0).scale(f.powf(n));
        t = t.add_scaled(&rf, 1.0);
        art_work = 0.5 * vij.dot(rf.mul_vec(g));
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
/// ½ (R_i + R_j) f^n) : (v_ij ⊗ G_ij)` (METHOD.md §4).
///
/// Scenes with no rigid body and no artificial stress (the common case:
/// elastic and elasto-plastic impacts) take the lane code, four pairs of a
/// row at a time (`lane_terms`); the others take the one-pair code
/// (`pair_terms`). Both give the same bits.
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

/// Whether the lane code serves the scene: it has neither the rigid
/// bodies' zero rates nor the artificial stress.
fn lanes_serve(model: &Model) -> bool {
    !model.any_rigid && model.artificial_stress.is_none()
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
        nb.sweep_chunks_store(
            model,
            &st.x,
            &mut acc,
            slots,
            |i, c, ai, piece, base, slots| {
                let t = lane_terms(&rec, model, i, c);
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

/// [`pair_terms`] and the sums' updates for up to four pairs of row i at
/// once, with no rigid particle and no artificial stress. Operation for
/// operation the one-pair code in its order, so the results are
/// bit-identical; its branches (the reconstruction's early return and
/// surface test, the viscosity's receding pairs) become selects between
/// both outcomes. Lanes that hold no pair (`c.inside` clear) compute
/// values the caller drops.
#[inline(always)]
fn lane_terms(rec: &[Partner], model: &Model, i: usize, c: &Chunk) -> LaneTerms {
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
    // t = σ_i/ρ_i² + σ_j/ρ_j² − Π I, t G, and each side's energy term.
    let txx = sixx + sjxx - pi;
    let tyy = siyy + sjyy - pi;
    let txy = sixy + sjxy;
    let tgx = txx * gx + txy * gy;
    let tgy = txy * gx + tyy * gy;
    let shared = 0.5 * pi * (vx * gx + vy * gy);
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
        for (reconstruct, h_ratio) in [(true, 1.0), (false, 1.0), (true, 1.15)] {
            let mut model = base.clone();
            model.av_reconstruct = reconstruct;
            model.contact = h_ratio == 1.0;
            for i in 0..model.len() {
                if model.body[i] == 1 {
                    model.h[i] *= h_ratio;
                }
            }
            let skin = SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max);
            let nb = neighbours::find_with_skin(&model, &st.x, skin);
            let k = kinematics::kinematics(&model, &st, &nb);
            let pts = eos_and_stress(&model, &st);
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
