//! The pair terms of four pairs at once in vector lanes: the partners'
//! rows laid out for the lanes, and `lane_terms`, the one-pair code's
//! arithmetic (`cpu::forces::pair_terms`) on each lane, bit for bit.

use super::Chunk;
use crate::cpu::kinematics::{Kinematics, StressPoint};
use crate::math::lanes::{columns, F4, LANES};
use crate::math::Mat2;
use crate::model::{Model, State};
use crate::physics::strength;
use crate::physics::tension::{art_weight_lanes, close_gate_lanes, heat_share_lanes, HEAT_SPEED};
use crate::scene::{ArtPairs, ArtWork, ArtificialStress};

/// What four pairs of one row add to their particles' sums: i's side and
/// j's, the masses applied.
pub(super) struct LaneTerms {
    pub(super) tg_mj: [[f64; LANES]; 2],
    pub(super) tg_mi: [[f64; LANES]; 2],
    pub(super) e_i: [f64; LANES],
    pub(super) e_j: [f64; LANES],
    /// The pair's [`PairVectors`] (x and y rows).
    pub(super) x_i: [[f64; LANES]; 2],
    pub(super) x_j: [[f64; LANES]; 2],
    /// The artificial parts of both sides' energy vectors (`PairTerms::a`
    /// and the hourglass control's `X`), summed, times `m_i m_j`; and the
    /// dissipation rate each side books at the pair's velocities.
    pub(super) y_mm: [[f64; LANES]; 2],
    pub(super) d_i: [f64; LANES],
    pub(super) d_j: [f64; LANES],
}

/// What the momentum pass reads of a particle, in one record of five rows
/// of four, so that four partners' values come into lanes by a transpose
/// of their rows ([`columns`]) instead of twenty single gathers.
#[derive(Clone, Copy)]
#[repr(C, align(32))]
pub(super) struct Partner {
    /// `x`, `v`.
    pub(super) xv: [f64; 4],
    /// `L` (xx, xy, yx, yy).
    pub(super) l: [f64; 4],
    /// `∇v` (xx, xy, yx, yy); zero unless the viscosity is reconstructed.
    pub(super) gv: [f64; 4],
    /// `σ/ρ²` (xx, xy, yy) and the sound speed.
    pub(super) sc: [f64; 4],
    /// `ρ`, `h`, `m`, and 1 on a surface particle (else 0).
    pub(super) rhm: [f64; 4],
}

/// Every particle's [`Partner`] record for one momentum pass (written once,
/// read by the twenty or so pairs each particle is in).
pub(super) fn partners(
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
pub(super) struct ArtRows {
    pub(super) rows: Vec<[f64; 4]>,
    pub(super) tension: Vec<bool>,
    /// Whether each particle's pairs take only the term's heat
    /// ([`Model::art_heats`]: a body that can yield, or a particle that
    /// flows) where `work = "yielding"` or `"plastic"` can find one; empty
    /// otherwise.
    pub(super) flows: Vec<bool>,
}

/// 1 for each particle that has not failed, 0 for one that has or has a
/// void open (`State::damage_of`: no more bonded than a failed one);
/// empty while no particle is either. A pair with a particle at 0 takes
/// no artificial stress, nor the Riemann form's damping while it recedes.
pub(super) fn intact_rows(st: &State) -> Vec<f64> {
    let broken = |i: usize| strength::failed(st.damage_of(i));
    if (0..st.damage.len()).any(broken) {
        (0..st.damage.len())
            .map(|i| if broken(i) { 0.0 } else { 1.0 })
            .collect()
    } else {
        Vec::new()
    }
}

/// The [`ArtRows`] of one momentum pass, when the scene has the
/// artificial stress (else none: the pass reads nothing more).
pub(super) fn art_rows(model: &Model, st: &State, pts: &[StressPoint]) -> Option<ArtRows> {
    use rayon::prelude::*;
    model.artificial_stress?;
    let (rows, tension) = (0..model.len())
        .into_par_iter()
        .map(|i| {
            let r = &pts[i].r;
            ([r.xx, r.xy, r.yy, model.spacing_of(i)], r.xx + r.yy < 0.0)
        })
        .unzip();
    let flows = if model.art_keyed_on_flow() {
        (0..model.len())
            .into_par_iter()
            .map(|i| model.art_heats(st, i))
            .collect()
    } else {
        Vec::new()
    };
    Some(ArtRows {
        rows,
        tension,
        flows,
    })
}

/// What the lane code reads of the hourglass control: each particle's
/// velocity and velocity gradient as the control sees them
/// (`forces::Side::vh`, `gh`), and minus its coefficient, when it is on.
pub(super) struct HgRows {
    pub(super) v: Vec<[f64; 4]>,
    pub(super) g: Vec<[f64; 4]>,
}

/// The [`HgRows`] of one momentum pass (none with the control off).
pub(super) fn hg_rows(model: &Model, st: &State, kin: &Kinematics) -> Option<HgRows> {
    use rayon::prelude::*;
    if model.hourglass <= 0.0 {
        return None;
    }
    let (v, g) = (0..model.len())
        .into_par_iter()
        .map(|i| {
            let gv = kin.gv.get(i).copied().unwrap_or(Mat2::ZERO);
            let vh = kin.hv.get(i).copied().unwrap_or(st.v[i]);
            let gh = kin.hgrad.get(i).copied().unwrap_or(gv);
            (
                [vh.x, vh.y, -model.hourglass_of(i), 0.0],
                [gh.xx, gh.xy, gh.yx, gh.yy],
            )
        })
        .unzip();
    Some(HgRows { v, g })
}

/// One row's pair in lanes: partner j's rows as columns, particle i's as
/// scalars, and what the pair terms share (`pair_terms_of`'s preamble).
struct PairLanes {
    /// `x_ij`, `v_ij`.
    xx: F4,
    xy: F4,
    vx: F4,
    vy: F4,
    /// `∇_i W_ij`.
    gwx: F4,
    gwy: F4,
    /// G = ½ (L_i + L_j) ∇W.
    gx: F4,
    gy: F4,
    /// The pair's mean smoothing length, and where supports adapt the
    /// smoothing length along the pair (else the mean).
    h0: F4,
    hij: F4,
    c_mean: F4,
    /// `L` (xx, xy, yx, yy) of i and of the partners.
    li: [f64; 4],
    lj: [F4; 4],
    /// `σ/ρ²` (xx, xy, yy) and the sound speed.
    si: [f64; 4],
    sj: [F4; 4],
    /// `ρ`, `h`, `m`, surface.
    ri: [f64; 4],
    rj: [F4; 4],
}

impl PairLanes {
    #[inline(always)]
    fn of(me: &Partner, r: &[&Partner; LANES], c: &Chunk) -> Self {
        let [xjx, xjy, vjx, vjy] = columns([&r[0].xv, &r[1].xv, &r[2].xv, &r[3].xv]);
        let lj = columns([&r[0].l, &r[1].l, &r[2].l, &r[3].l]);
        let sj = columns([&r[0].sc, &r[1].sc, &r[2].sc, &r[3].sc]);
        let rj = columns([&r[0].rhm, &r[1].rhm, &r[2].rhm, &r[3].rhm]);
        let [xix, xiy, vix, viy] = me.xv;
        let (li, si, ri) = (me.l, me.sc, me.rhm);
        let h0 = 0.5 * (ri[1] + rj[1]);
        let xx = xix - xjx;
        let xy = xiy - xjy;
        // As `pair_terms_of`: where supports adapt, the smoothing length
        // along the pair.
        let hij = match c.scale {
            None => h0,
            Some(_) => {
                let r2 = xx * xx + xy * xy;
                F4::splat(0.0).lt(c.q2).select((r2 / c.q2).sqrt(), h0)
            }
        };
        let (gwx, gwy) = (c.gwx, c.gwy);
        let axx = (li[0] + lj[0]) * 0.5;
        let axy = (li[1] + lj[1]) * 0.5;
        let ayx = (li[2] + lj[2]) * 0.5;
        let ayy = (li[3] + lj[3]) * 0.5;
        PairLanes {
            xx,
            xy,
            vx: vix - vjx,
            vy: viy - vjy,
            gwx,
            gwy,
            gx: axx * gwx + axy * gwy,
            gy: ayx * gwx + ayy * gwy,
            h0,
            hij,
            c_mean: 0.5 * (si[3] + sj[3]),
            li,
            lj,
            si,
            sj,
            ri,
            rj,
        }
    }
}

/// The viscosity's velocity jump (`reconstructed_jump`); the plain jump
/// unless the viscosity is reconstructed.
#[inline(always)]
fn viscosity_jump(p: &PairLanes, me: &Partner, r: &[&Partner; LANES], model: &Model) -> (F4, F4) {
    let (xx, xy, vx, vy) = (p.xx, p.xy, p.vx, p.vy);
    if !model.av_reconstruct {
        return (vx, vy);
    }
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
    let mut keep = (si * sj).le(F4::splat(0.0));
    if !model.av_recon_surface {
        keep = keep.or((p.ri[3] + p.rj[3]).ge(F4::splat(1.0)));
    }
    (
        keep.select(vx, vx - (dix + djx) * half),
        keep.select(vy, vy - (diy + djy) * half),
    )
}

/// Monaghan's Π (`viscosity_pi`) on the jump `(wx, wy)` the viscosity
/// sees; `bonded`, where some particle is not intact, 1 on the lanes
/// whose pair is bonded and 0 on the others.
#[inline(always)]
fn viscosity_pi(p: &PairLanes, model: &Model, (wx, wy): (F4, F4), bonded: Option<F4>) -> F4 {
    let (xx, xy, vx, vy, hij) = (p.xx, p.xy, p.vx, p.vy, p.hij);
    let rho_mean = 0.5 * (p.ri[0] + p.rj[0]);
    let mut wdx = wx * xx + wy * xy;
    let d = (xx * xx + xy * xy) + 0.01 * hij * hij;
    let (beta, on) = if model.av_release {
        // The smaller of the seen and the true jump where they agree in
        // sign (viscosity_pi).
        let vdx = vx * xx + vy * xy;
        let mut on = F4::splat(0.0).lt(wdx * vdx);
        if let Some(b) = bonded {
            on = on.and(F4::splat(0.0).lt(b).or(vdx.lt(F4::splat(0.0))));
        }
        wdx = (vdx * vdx).lt(wdx * wdx).select(vdx, wdx);
        let approach = wdx.lt(F4::splat(0.0));
        (approach.select(F4::splat(model.beta), F4::splat(0.0)), on)
    } else {
        (F4::splat(model.beta), wdx.lt(F4::splat(0.0)))
    };
    let hv = hij * wdx;
    let pi_raw = hv * (-model.alpha * p.c_mean * d + beta * hv) / (d * d * rho_mean);
    on.select(pi_raw, F4::splat(0.0))
}

/// The close-pair form's gate (`close_gate`) of the four lanes, in the
/// pair's metric where supports adapt; none in the form over all pairs.
#[inline(always)]
fn art_gate(p: &PairLanes, a: &ArtificialStress, model: &Model, i: usize, c: &Chunk) -> Option<F4> {
    match a.pairs {
        ArtPairs::All => None,
        ArtPairs::Close => {
            let (mut mi, mut mj, rhoi, rhoj) = (p.ri[2], p.rj[2], p.ri[0], p.rj[0]);
            if !model.share.is_empty() {
                // The whole particles' volumes, on a symmetry plane too.
                mi /= model.share(i);
                mj = mj / F4::gather(|k| model.share(c.j[k] as usize));
            }
            let vol = (mi / rhoi + mj / rhoj) * 0.5;
            let (u, vol) = match c.scale {
                None => (p.xx * p.xx + p.xy * p.xy, vol),
                Some(scale) => (c.q2, vol * scale),
            };
            let mut gate = close_gate_lanes(u, vol, F4::splat(1.0), model.dim);
            // κ² ≤ 1 only shuts the gate further, so a gate shut at κ² = 1
            // is shut.
            let ks = &model.close_scale;
            if !ks.is_empty() && F4::splat(0.0).lt(gate).bits() != 0 {
                let k2 = F4::gather(|k| ks[c.j[k] as usize]).min(F4::splat(ks[i]));
                gate = close_gate_lanes(u, vol, k2, model.dim);
            }
            Some(gate)
        }
    }
}

/// 1 in the lanes whose pair's artificial stress may only heat (every
/// lane with "heat", those with a particle of a body that can yield with
/// "yielding", or one that flows with "plastic"), 0 in the others; none:
/// no lane.
#[inline(always)]
fn art_heat_lanes(a: &ArtificialStress, art: &ArtRows, i: usize, c: &Chunk) -> Option<F4> {
    match a.work {
        ArtWork::Heat => Some(F4::splat(1.0)),
        ArtWork::Either => None,
        ArtWork::Yielding | ArtWork::Plastic if art.flows.is_empty() => None,
        ArtWork::Yielding | ArtWork::Plastic => {
            let fl = F4::gather(|k| (art.flows[i] || art.flows[c.j[k] as usize]) as u8 as f64);
            (F4::splat(0.0).lt(fl).bits() != 0).then_some(fl)
        }
    }
}

/// The artificial stress `(R_i + R_j) f^n` of the lanes where the trace of
/// `R_i + R_j` is negative and the gate open, added to `t` (xx, yy, xy):
/// returns its work `½ v·(R f^n G)` and `R f^n G`, zero in the other
/// lanes; none where no lane takes it (`pair_terms`).
#[inline(always)]
fn art_lanes(
    p: &PairLanes,
    (art, a, intact): (&ArtRows, &ArtificialStress, &[f64]),
    model: &Model,
    i: usize,
    c: &Chunk,
    t: &mut [F4; 3],
) -> Option<(F4, F4, F4)> {
    let (xx, xy, vx, vy, gx, gy) = (p.xx, p.xy, p.vx, p.vy, p.gx, p.gy);
    // Rows untouched by tension skip it, and so do rows with no close pair
    // in the close-pair form: most rows have no pair inside the gate and
    // read no R.
    if !(art.tension[i] || c.j.iter().any(|&j| art.tension[j as usize])) {
        return None;
    }
    let gate = art_gate(p, a, model, i, c);
    if gate.is_some_and(|g| F4::splat(0.0).lt(g).bits() == 0) {
        return None;
    }
    let [rjxx, rjxy, rjyy, spj] = columns(c.j.map(|j| &art.rows[j as usize]));
    let [rixx, rixy, riyy, spi] = art.rows[i];
    let (sxx, sxy, syy) = (rixx + rjxx, rixy + rjxy, riyy + rjyy);
    let mut on = (sxx + syy).lt(F4::splat(0.0));
    if let Some(gate) = gate {
        on = on.and(F4::splat(0.0).lt(gate));
    }
    if !intact.is_empty() {
        let ok = F4::gather(|k| intact[c.j[k] as usize]);
        on = on.and(F4::splat(0.0).lt(ok));
    }
    if on.bits() == 0 {
        return None;
    }
    let dp = 0.5 * (spi + spj);
    let mut fnn = match c.scale {
        None => art_weight_lanes(xx * xx + xy * xy, dp, p.hij, a.n),
        Some(_) => art_weight_lanes(c.q2, dp / p.h0, F4::splat(1.0), a.n),
    };
    if let Some(gate) = gate {
        fnn = fnn * gate;
    }
    let (mut rfxx, mut rfxy, mut rfyy) = (sxx * fnn, sxy * fnn, syy * fnn);
    // Where its work may only be heat, the share of it that is
    // (forces::pair_terms_of).
    if let Some(fl) = art_heat_lanes(a, art, i, c) {
        let (rgx, rgy) = (rfxx * gx + rfxy * gy, rfxy * gx + rfyy * gy);
        let vr = vx * rgx + vy * rgy;
        let scale = F4::splat(HEAT_SPEED) * p.c_mean * (rgx * rgx + rgy * rgy).sqrt();
        let share = F4::splat(0.0)
            .lt(fl)
            .select(heat_share_lanes(vr, scale), F4::splat(1.0));
        (rfxx, rfxy, rfyy) = (rfxx * share, rfxy * share, rfyy * share);
    }
    let [txx, tyy, txy] = *t;
    *t = [
        on.select(txx + rfxx, txx),
        on.select(tyy + rfyy, tyy),
        on.select(txy + rfxy, txy),
    ];
    let (rgx, rgy) = (rfxx * gx + rfxy * gy, rfxy * gx + rfyy * gy);
    let zero = F4::splat(0.0);
    Some((
        on.select(0.5 * (vx * rgx + vy * rgy), zero),
        on.select(rgx, zero),
        on.select(rgy, zero),
    ))
}

/// Each side's stress vector (`PairTerms::s`): i's (x, y), then j's.
#[inline(always)]
fn stress_vectors(p: &PairLanes, model: &Model) -> [F4; 4] {
    let (gx, gy, gwx, gwy) = (p.gx, p.gy, p.gwx, p.gwy);
    let [sixx, sixy, siyy, _] = p.si;
    let [sjxx, sjxy, sjyy, _] = p.sj;
    if model.variational {
        // σ_i/(ρ_i ρ_j) L_i ∇W and σ_j/(ρ_i ρ_j) L_j ∇W.
        let [lixx, lixy, liyx, liyy] = p.li;
        let [ljxx, ljxy, ljyx, ljyy] = p.lj;
        let lgix = lixx * gwx + lixy * gwy;
        let lgiy = liyx * gwx + liyy * gwy;
        let lgjx = ljxx * gwx + ljxy * gwy;
        let lgjy = ljyx * gwx + ljyy * gwy;
        let (rhoi, rhoj) = (p.ri[0], p.rj[0]);
        let (fi, fj) = if model.axisymmetric {
            (F4::splat(1.0), F4::splat(1.0))
        } else {
            (rhoi / rhoj, rhoj / rhoi)
        };
        [
            (sixx * lgix + sixy * lgiy) * fi,
            (sixy * lgix + siyy * lgiy) * fi,
            (sjxx * lgjx + sjxy * lgjy) * fj,
            (sjxy * lgjx + sjyy * lgjy) * fj,
        ]
    } else {
        // σ_i/ρ_i² G and σ_j/ρ_j² G.
        [
            sixx * gx + sixy * gy,
            sixy * gx + siyy * gy,
            sjxx * gx + sjxy * gy,
            sjxy * gx + sjyy * gy,
        ]
    }
}

/// The hourglass control (`forces::hourglass`): i's part (x, y), then
/// j's.
#[inline(always)]
fn hourglass_lanes(p: &PairLanes, hg: &HgRows, model: &Model, i: usize, c: &Chunk) -> [F4; 4] {
    // −α_j rides in the velocity row (the one-pair code's −k).
    let [vhjx, vhjy, naj, _] = columns(c.j.map(|j| &hg.v[j as usize]));
    let [gjxx, gjxy, gjyx, gjyy] = columns(c.j.map(|j| &hg.g[j as usize]));
    let [vhix, vhiy, nai, _] = hg.v[i];
    let [gixx, gixy, giyx, giyy] = hg.g[i];
    let (gwx, gwy) = (p.gwx, p.gwy);
    // x_ji = −x_ij, exactly.
    let (zx, zy) = (F4::splat(0.0) - p.xx, F4::splat(0.0) - p.xy);
    let r2 = zx * zx + zy * zy;
    let w = (gwx * zx + gwy * zy) / r2;
    let (vjix, vjiy) = (vhjx - vhix, vhjy - vhiy);
    let dix = vjix - (gixx * zx + gixy * zy);
    let diy = vjiy - (giyx * zx + giyy * zy);
    let djx = (gjxx * zx + gjxy * zy) - vjix;
    let djy = (gjyx * zx + gjyy * zy) - vjiy;
    let (rhoi, rhoj) = (p.ri[0], p.rj[0]);
    let (rho_i, rho_j) = if model.axisymmetric {
        (F4::splat(rhoi), rhoj)
    } else {
        (rhoj, F4::splat(rhoi))
    };
    let fi = -nai * w * p.si[3] * p.ri[1] / rho_i;
    let fj = naj * w * p.sj[3] * p.rj[1] / rho_j;
    let on = F4::splat(0.0).lt(r2);
    let zero = F4::splat(0.0);
    [
        on.select(dix * fi, zero),
        on.select(diy * fi, zero),
        on.select(djx * fj, zero),
        on.select(djy * fj, zero),
    ]
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
pub(super) fn lane_terms(
    rec: &[Partner],
    intact: &[f64],
    art: Option<&ArtRows>,
    hg: Option<&HgRows>,
    model: &Model,
    i: usize,
    c: &Chunk,
) -> LaneTerms {
    let r: [&Partner; LANES] = std::array::from_fn(|k| &rec[c.j[k] as usize]);
    let me = &rec[i];
    let p = PairLanes::of(me, &r, c);
    let (vx, vy, gx, gy) = (p.vx, p.vy, p.gx, p.gy);
    let bonded = (model.av_release && !intact.is_empty()).then(|| {
        if intact[i] > 0.0 {
            F4::gather(|k| intact[c.j[k] as usize])
        } else {
            F4::splat(0.0)
        }
    });
    let pi = viscosity_pi(&p, model, viscosity_jump(&p, me, &r, model), bonded);
    // t = σ_i/ρ_i² + σ_j/ρ_j² − Π I (+ (R_i + R_j) f^n), t G, and each
    // side's energy term. The paper's form keeps the stress terms in t;
    // the variational one gives each side its own gradient
    // (pair_terms_of).
    let [sixx, sixy, siyy, _] = p.si;
    let [sjxx, sjxy, sjyy, _] = p.sj;
    let mut t = if model.variational {
        let zero = F4::splat(0.0);
        [zero - pi, zero - pi, zero]
    } else {
        [sixx + sjxx - pi, siyy + sjyy - pi, sixy + sjxy]
    };
    let art_on = match (
        art.filter(|_| intact.is_empty() || intact[i] > 0.0),
        model.artificial_stress.as_ref(),
    ) {
        (Some(art), Some(a)) => art_lanes(&p, (art, a, intact), model, i, c, &mut t),
        _ => None,
    };
    let [txx, tyy, txy] = t;
    let mut tgx = txx * gx + txy * gy;
    let mut tgy = txy * gx + tyy * gy;
    let mut shared = 0.5 * pi * (vx * gx + vy * gy);
    let (mut rgx_on, mut rgy_on) = (F4::splat(0.0), F4::splat(0.0));
    if let Some((w, rgx, rgy)) = art_on {
        shared = shared - w;
        (rgx_on, rgy_on) = (rgx, rgy);
    }
    let [mut sigx, mut sigy, mut sjgx, mut sjgy] = stress_vectors(&p, model);
    if model.variational {
        tgx = tgx + (sigx + sjgx);
        tgy = tgy + (sigy + sjgy);
    }
    // PairTerms::a, and with the hourglass control each side's own part.
    let (ax, ay) = ((rgx_on - gx * pi) * 0.5, (rgy_on - gy * pi) * 0.5);
    let (mut aix, mut aiy, mut ajx, mut ajy) = (ax, ay, ax, ay);
    if let Some(hg) = hg {
        // Its parts added where the one-pair code adds them: to t G, and
        // to each side's σ/ρ² G in its energy term and pair vectors.
        let [h0x, h0y, h1x, h1y] = hourglass_lanes(&p, hg, model, i, c);
        tgx = tgx + h0x + h1x;
        tgy = tgy + h0y + h1y;
        (sigx, sigy) = (sigx + h0x, sigy + h0y);
        (sjgx, sjgy) = (sjgx + h1x, sjgy + h1y);
        (aix, aiy, ajx, ajy) = (ax + h0x, ay + h0y, ax + h1x, ay + h1y);
    }
    let (mi, mj) = (p.ri[2], p.rj[2]);
    let mm = F4::splat(0.0) - mi * mj;
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
        y_mm: [
            ((aix + ajx) * (mi * mj)).to_array(),
            ((aiy + ajy) * (mi * mj)).to_array(),
        ],
        d_i: (mm * (vx * aix + vy * aiy)).to_array(),
        d_j: (mm * (vx * ajx + vy * ajy)).to_array(),
    }
}
