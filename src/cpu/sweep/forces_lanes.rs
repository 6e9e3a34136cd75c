//! The forces stage's sweep: every pair once, its terms added to both of
//! its particles; four pairs of a row at a time in vector lanes where the
//! scene has no rigid body (`lane_terms`), one at a time with the plain
//! pair code (`cpu::forces::pair_terms`) elsewhere. Both give the same
//! bits (tested in `tests.rs`).

use glam::DVec2;

use super::lane_terms::{art_rows, hg_rows, intact_rows, lane_terms, partners, LaneTerms};
use crate::cpu::forces::{pair_terms, PairTerms};
use crate::cpu::forces::{vectors_of, PairVectors};
use crate::cpu::kinematics::Kinematics;
use crate::cpu::kinematics::StressPoint;
use crate::cpu::neighbours::{Nbr, Neighbours};
use crate::model::{Model, State};

/// Where a pass's energy terms go: into the particles' sums and the row's
/// artificial dissipation (`()`, no memory) or into the pair's slot
/// ([`PairVectors`]), the artificial part's work kept per particle
/// ([`Acc`]).
pub(super) trait EnergyTerms: Send + Default {
    /// Whether the pass keeps its energy terms (and the particles' `C_k`).
    const KEEPS: bool;
    /// Lane k of the pair terms `t`: i's and, for a near pair, j's.
    fn lane(self_: &mut Self, t: &LaneTerms, k: usize, ai: &mut Acc, aj: Option<&mut Acc>);
    /// The one-pair terms `p` of pair `(i, j)` with the velocities `v =
    /// (v_i, v_j)` and the masses `m = (m_i, m_j)`, seen from row i: i's
    /// side unless i is rigid, j's for a near pair (`aj`) unless j is
    /// rigid.
    #[allow(clippy::too_many_arguments)]
    fn pair(
        self_: &mut Self,
        p: &PairTerms,
        v: (DVec2, DVec2),
        rigid: (bool, bool),
        m: (f64, f64),
        ai: &mut Acc,
        aj: Option<&mut Acc>,
        near: bool,
    );
}

impl EnergyTerms for () {
    const KEEPS: bool = false;

    #[inline(always)]
    fn lane(_: &mut (), t: &LaneTerms, k: usize, ai: &mut Acc, aj: Option<&mut Acc>) {
        ai.1 -= t.e_i[k];
        ai.2 += t.d_i[k];
        if let Some(aj) = aj {
            aj.1 -= t.e_j[k];
            ai.2 += t.d_j[k];
        }
    }

    #[inline(always)]
    fn pair(
        _: &mut (),
        p: &PairTerms,
        _: (DVec2, DVec2),
        (ri, _): (bool, bool),
        (mi, mj): (f64, f64),
        ai: &mut Acc,
        aj: Option<&mut Acc>,
        _: bool,
    ) {
        let mm = mi * mj;
        if !ri {
            ai.1 -= mj * (p.vij.dot(p.s[0] + p.hg[0]) - p.shared);
            ai.2 -= mm * p.vij.dot(p.a + p.hg[0]);
        }
        if let Some(aj) = aj {
            aj.1 -= mi * (p.vij.dot(p.s[1] + p.hg[1]) - p.shared);
            ai.2 -= mm * p.vij.dot(p.a + p.hg[1]);
        }
    }
}

impl EnergyTerms for PairVectors {
    const KEEPS: bool = true;

    #[inline(always)]
    fn lane(slot: &mut Self, t: &LaneTerms, k: usize, ai: &mut Acc, aj: Option<&mut Acc>) {
        *slot = [
            DVec2::new(t.x_i[0][k], t.x_i[1][k]),
            DVec2::new(t.x_j[0][k], t.x_j[1][k]),
        ];
        // No rigid particle in the lane code: both sides are booked.
        let y = DVec2::new(t.y_mm[0][k], t.y_mm[1][k]);
        ai.3 += y;
        if let Some(aj) = aj {
            aj.3 -= y;
        }
    }

    #[inline(always)]
    fn pair(
        slot: &mut Self,
        p: &PairTerms,
        (vi, vj): (DVec2, DVec2),
        (ri, rj): (bool, bool),
        (mi, mj): (f64, f64),
        ai: &mut Acc,
        aj: Option<&mut Acc>,
        near: bool,
    ) {
        *slot = vectors_of(p);
        // The pair's artificial work at velocities w is −m_i m_j w_ij·y,
        // y the artificial parts of the sides some visit books (a rigid
        // particle books none): its w_i part goes to i's vector, its w_j
        // part to j's (a far pair's: in j's own visit); a rigid
        // particle's velocity does not change in the step, so its part
        // is fixed now.
        let mut y = DVec2::ZERO;
        if !ri {
            y += p.a + p.hg[0];
        }
        if !rj {
            y += p.a + p.hg[1];
        }
        let y = y * (mi * mj);
        if ri {
            ai.2 -= vi.dot(y);
        } else {
            ai.3 += y;
        }
        if rj {
            ai.2 += vj.dot(y);
        } else if let Some(aj) = aj.filter(|_| near) {
            aj.3 -= y;
        }
    }
}

/// The inputs of the momentum pass: the state, its neighbour lists, its
/// kinematics and its stress points.
pub(in crate::cpu) type Inputs<'a> = (
    &'a Model,
    &'a State,
    &'a Neighbours,
    &'a Kinematics,
    &'a [StressPoint],
);

/// Each particle's sums: `dv/dt`, `de/dt`, the artificial dissipation
/// rate of the pairs its row books (where the energy terms are kept, the
/// part of it already fixed), and where they are kept the vector `C_k`
/// whose work `−w_k·C_k` at the booking velocities is the rest
/// ([`super::forces::KeptWork`]).
pub(super) type Acc = (DVec2, f64, f64, DVec2);

/// What the forces sums give: `dv/dt`, `de/dt`, the artificial
/// dissipation rate (where the energy terms are kept, its fixed part) and
/// the particles' `C_k` (empty unless kept).
pub(in crate::cpu) type SumsOut = (Vec<DVec2>, Vec<f64>, f64, Vec<DVec2>);

/// The sums' totals, summed in particle order; `keep`: with the `C_k`.
fn totals(acc: Vec<Acc>, keep: bool) -> SumsOut {
    let d = acc.iter().map(|a| a.2).sum();
    let c = if keep {
        acc.iter().map(|a| a.3).collect()
    } else {
        Vec::new()
    };
    let (dv, de) = acc.into_iter().map(|a| (a.0, a.1)).unzip();
    (dv, de, d, c)
}

/// [`sums`] with the energy terms going to `E` (one slot per visited
/// candidate).
pub(super) fn sums_into<E: EnergyTerms>(
    (model, st, nb, kin, pts): Inputs<'_>,
    lanes: bool,
    slots: &mut [E],
) -> SumsOut {
    let (l, gv, surface) = (&kin.l[..], &kin.gv[..], &kin.surface[..]);
    let keep = E::KEEPS;
    let mut acc: Vec<Acc> = vec![Acc::default(); model.len()];
    if lanes {
        assert!(lanes_serve(model), "the lane code serves this scene");
        let rec = partners(model, st, l, gv, surface, pts);
        let intact = intact_rows(st);
        let art = art_rows(model, st, pts);
        let hg = hg_rows(model, st, kin);
        nb.sweep_chunks_store(
            model,
            st.frame(),
            &mut acc,
            slots,
            |i, c, ai, piece, base, slots| {
                let t = lane_terms(&rec, &intact, art.as_ref(), hg.as_ref(), model, i, c);
                for (k, slot) in slots.iter_mut().enumerate() {
                    if c.inside & (1 << k) == 0 {
                        *slot = E::default();
                        continue;
                    }
                    ai.0 += DVec2::new(t.tg_mj[0][k], t.tg_mj[1][k]);
                    let mut aj = c.near.then(|| &mut piece[c.j[k] as usize - base]);
                    if let Some(aj) = aj.as_deref_mut() {
                        aj.0 -= DVec2::new(t.tg_mi[0][k], t.tg_mi[1][k]);
                    }
                    E::lane(slot, &t, k, ai, aj);
                }
            },
        );
        return totals(acc, keep);
    }
    let terms = |i, b: &Nbr| pair_terms(model, st, kin, pts, i, b);
    nb.sweep_store(model, st.frame(), &mut acc, slots, |i, b, ai, aj, slot| {
        let j = b.j as usize;
        // Rigid particles keep zero rates; a far pair has no j side here.
        let near = aj.is_some();
        let (ri, rj) = (model.rigid(i), model.rigid(j));
        let aj = aj.filter(|_| !rj);
        if ri && aj.is_none() {
            *slot = E::default();
            return;
        }
        let p = terms(i, b);
        let (mi, mj) = (model.mass[i], model.mass[j]);
        if !ri {
            ai.0 += p.tg * mj;
        }
        let mut aj = aj;
        if let Some(aj) = aj.as_deref_mut() {
            aj.0 -= p.tg * mi;
        }
        E::pair(
            slot,
            &p,
            (st.v[i], st.v[j]),
            (ri, rj),
            (mi, mj),
            ai,
            aj,
            near,
        );
    });
    totals(acc, keep)
}

/// Whether the lane code serves the scene: it does not do the rigid
/// bodies' zero rates (it does the hourglass control).
pub(in crate::cpu) fn lanes_serve(model: &Model) -> bool {
    !model.any_rigid
}
