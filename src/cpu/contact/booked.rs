//! The penalty contact's passes with the work booked at chosen velocities:
//! the spring as the exact gradient of its stored energy, through the
//! normals' turning ([`normal_rates`]).

use super::*;

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
/// volumes ([`forces::boundary`](crate::cpu::forces::boundary)).
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
                let (xj, vj) = match image {
                    Some(m) => (m.point(st.x[j]), m.vector(v[j])),
                    None => (st.x[j], v[j]),
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
    penalty_ahead(model, st, nb, bd, book, 0.0)
}

/// [`penalty_booked`] with friction's slip looked `horizon` ahead where
/// it sticks (docs/method.md §8.6): the leapfrog's contact at `n+1`
/// holds `u_{n+½}` in `st.slip` and the slip it moves the bodies with is
/// `u_{n+½} + ½Δt w`, the slip at `n+1` were the pass to stick.
pub fn penalty_ahead(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    bd: &Boundary,
    book: Option<&[DVec2]>,
    horizon: f64,
) -> ContactForces {
    let vb = book.unwrap_or(&st.v);
    let bk = Booking {
        model,
        st,
        nb,
        bd,
        book,
        horizon,
        vb,
        ndot: normal_rates(model, st, nb, bd, vb),
        mirrors: &model.contact_images,
    };
    // Pass 1: every boundary particle against each partner body around it
    // (entry k for particle `bd.list[k]`; only boundary particles have
    // contact terms, so the passes go over the boundary list alone).
    let pass1: Vec<P1> = bd
        .list
        .par_iter()
        .enumerate()
        .map(|(kp, &p)| bk.pass1(kp, p as usize))
        .collect();
    // Pass 2: every boundary particle Q gathers what its partners handed it,
    // over exactly the candidate set each of them used; then its normal's
    // derivative, complete, turns into forces on Q and its neighbours.
    let mut gathered: Vec<Gathered> = bd
        .list
        .par_iter()
        .enumerate()
        .map(|(kq, &q)| bk.pass2(&pass1, kq, q as usize))
        .collect();
    let mut out = assemble(model, bd, &pass1, &mut gathered);
    if model.rubs {
        friction::add(&bk, &pass1, &gathered, &mut out);
    }
    out
}

/// A contact candidate as P sees it ([`Booking::seen`]).
struct Seen {
    x: DVec2,
    n: DVec2,
    v: DVec2,
    vb: DVec2,
    book: Option<DVec2>,
}

/// What one evaluation's booked passes read.
pub(super) struct Booking<'a> {
    pub(super) model: &'a Model,
    pub(super) st: &'a State,
    pub(super) nb: &'a Neighbours,
    pub(super) bd: &'a Boundary,
    /// The booking velocities, if not the state's.
    pub(super) book: Option<&'a [DVec2]>,
    /// How far ahead friction's slip is taken where it sticks
    /// ([`penalty_ahead`]).
    pub(super) horizon: f64,
    /// The velocities the work is booked at.
    vb: &'a [DVec2],
    /// How fast each boundary particle's normal turns at `vb`.
    ndot: Vec<DVec2>,
    /// The images across the symmetry planes that the passes also meet
    /// their partners' (none for the axis of a body of revolution).
    pub(super) mirrors: &'a [crate::math::Mirror],
}

/// Pass 1's result for one boundary particle P.
pub(super) struct P1 {
    entry: f64,
    pub(super) force: DVec2,
    heat: f64,
    /// `∂Φ/∂n_P` from P's own passes.
    n_bar: DVec2,
    shares: Vec<Share>,
    stats: Vec<PassStat>,
    /// With friction, the partners P may rub on: their sums, the contact
    /// normal, and the normal force P's own pass against them applies
    /// (`½ p A`, 0 without one) ([`friction`](super::friction)).
    pub(super) rubs: Vec<(PartnerSums, DVec2, f64)>,
}

/// What Q gathers: its force and heat from its partners, and the
/// forces its normal's derivative puts on its neighbours.
pub(super) struct Gathered {
    pub(super) force: DVec2,
    heat: f64,
    spread: Vec<(u32, DVec2)>,
    /// With friction, the normal force the passes of each partner body
    /// applied, shared to Q by weight as their dashpots' are.
    pub(super) normal: Vec<(u32, f64)>,
}

impl Booking<'_> {
    /// Boundary particle q's entry in the boundary list.
    pub(super) fn slot(&self, q: usize) -> usize {
        self.bd
            .list
            .binary_search(&(q as u32))
            .expect("a boundary particle is listed")
    }

    /// Pass 1 of boundary particle `p` (entry `kp`): its passes against
    /// each partner body, what it keeps and what it hands its partners.
    fn pass1(&self, kp: usize, p: usize) -> P1 {
        let (model, st, bd) = (self.model, self.st, self.bd);
        let mut out = P1 {
            entry: -1.0,
            force: DVec2::ZERO,
            heat: 0.0,
            n_bar: DVec2::ZERO,
            shares: Vec::new(),
            stats: Vec::new(),
            rubs: Vec::new(),
        };
        let (np, op) = (bd.normal[p], model.offset[p]);
        let sp = st.x[p] + np * op;
        let (cands, sums) = self.partners(p, sp);
        let passes: Vec<(&PartnerSums, Pass)> = sums
            .iter()
            .filter_map(|s| Some((s, pressure(model, p, np, st.v[p], s)?)))
            .collect();
        let deepest = passes.iter().map(|(_, ps)| ps.delta).fold(0.0, f64::max);
        let cap = yield_overlap(model.bodies[model.body[p] as usize].spacing);
        let (entry, yielded) = entry_rule(st.entry[p], deepest, cap);
        out.entry = entry;
        // The pass that presses hardest (almost always the only one).
        let mut hardest: Option<(&PartnerSums, DVec2, f64)> = None;
        let a = bd.area[p];
        for (s, ps) in passes {
            let sat = yielded && ps.delta == deepest;
            let n = ps.gap.n;
            let applied = self.book_pass((kp, p), sp, (s, ps, sat), &cands, &mut out);
            if applied > hardest.map_or(0.0, |h| h.2) {
                hardest = Some((s, n, applied));
            }
        }
        if model.rubs && !model.rigid(p) {
            // Every partner P may rub on: the partners' passes may press
            // on P where its own pass against them does not.
            out.rubs = sums
                .iter()
                .filter_map(|s| {
                    let own = hardest.filter(|h| h.0.body == s.body);
                    let n = match own {
                        Some(h) => h.1,
                        None => penalty::gap(np, &s.s)?.n,
                    };
                    Some((*s, n, own.map_or(0.0, |h| 0.5 * h.2 * a)))
                })
                .collect();
        }
        out
    }

    /// P's candidates and one set of sums per partner body around it
    /// (almost always one), its surface point at `sp`.
    fn partners(&self, p: usize, sp: DVec2) -> (Vec<Cand>, Vec<PartnerSums>) {
        let (model, st, bd) = (self.model, self.st, self.bd);
        let mut cands: Vec<Cand> = Vec::new();
        let mut sums: Vec<PartnerSums> = Vec::new();
        for &q in self.nb.cross_of(p) {
            let q = q as usize;
            if !bd.is_boundary[q] {
                continue;
            }
            let Some((w, gw)) = is_candidate(model, st, bd, p, q) else {
                continue;
            };
            self.add_partner(&mut cands, &mut sums, sp, (q, None), (w, gw));
        }
        // Across the symmetry planes, the partners' images.
        for &e in self.nb.cross_images_of(p) {
            let (q, kind) = image_entry(e);
            let (q, m) = (q as usize, self.mirrors[kind]);
            if !bd.is_boundary[q] {
                continue;
            }
            let Some((w, gw)) = is_image_candidate(model, st, bd, &m, p, q) else {
                continue;
            };
            self.add_partner(&mut cands, &mut sums, sp, (q, Some(m)), (w, gw));
        }
        (cands, sums)
    }

    /// What P sees of candidate q (its image across `image` where given):
    /// position, normal, velocity and booking velocities.
    #[inline]
    fn seen(&self, q: usize, image: Option<crate::math::Mirror>) -> Seen {
        let (st, bd) = (self.st, self.bd);
        let s = Seen {
            x: st.x[q],
            n: bd.normal[q],
            v: st.v[q],
            vb: self.vb[q],
            book: self.book.map(|b| b[q]),
        };
        match image {
            Some(m) => Seen {
                x: m.point(s.x),
                n: m.vector(s.n),
                v: m.vector(s.v),
                vb: m.vector(s.vb),
                book: s.book.map(|b| m.vector(b)),
            },
            None => s,
        }
    }

    /// How fast candidate q's normal turns, as P sees it (its image's
    /// across `image` where given).
    #[inline]
    fn ndot_of(&self, q: usize, image: Option<crate::math::Mirror>) -> DVec2 {
        let nd = self.ndot[self.slot(q)];
        match image {
            Some(m) => m.vector(nd),
            None => nd,
        }
    }

    /// Adds candidate q (its image where `image`), of weight `w` and
    /// gradient `gw`, to P's candidates and its partner body's sums.
    fn add_partner(
        &self,
        cands: &mut Vec<Cand>,
        sums: &mut Vec<PartnerSums>,
        sp: DVec2,
        (q, image): (usize, Option<crate::math::Mirror>),
        (w, gw): (f64, DVec2),
    ) {
        let model = self.model;
        let bq = model.body[q];
        cands.push(Cand {
            q,
            body: bq,
            w,
            gw,
            image,
        });
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
        let c = self.seen(q, image);
        let oq = model.offset[q];
        s.s.add(w, sp, c.x + c.n * oq, c.n, oq);
        s.swv += c.v * w;
        if let Some(b) = c.book {
            s.swb += b * w;
        }
    }

    /// One pass of P (entry `kp`, surface point `sp`) against partner sums
    /// `s`: its spring and dashpot, their heat and stored energy, its
    /// share for the partners; `sat` where its spring has yielded.
    fn book_pass(
        &self,
        (kp, p): (usize, usize),
        sp: DVec2,
        (s, mut ps, sat): (&PartnerSums, Pass, bool),
        cands: &[Cand],
        out: &mut P1,
    ) -> f64 {
        let (model, bd, book, vb) = (self.model, self.bd, self.book, self.vb);
        let (np, op) = (bd.normal[p], model.offset[p]);
        let a = bd.area[p];
        let rigid = model.rigid(p);
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
                let (q, oq) = (self.seen(c.q, c.image), model.offset[c.q]);
                let d = penalty::candidate(&bar, sp, c.w, q.x + q.n * oq, q.n, oq);
                xp_bar += c.gw * d.w;
                phi_dot += (d.x - c.gw * d.w).dot(q.vb) + d.n.dot(self.ndot_of(c.q, c.image));
            }
            phi_dot += xp_bar.dot(vb[p]) + np_bar.dot(self.ndot[kp]);
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
        // What the pass applies along its normal: the dashpot and
        // the spring as faded (the pressure law's own p where the
        // pass does not fade).
        let applied = if fade < 1.0 && !ps.clipped {
            (ps.z * ps.w_rate + ps.stiffness * ps.delta * fade).max(0.0)
        } else {
            ps.p
        };
        out.shares.push(Share {
            body: bq,
            q: n * (dash / sw),
            eta: if rigid { heat / sw } else { 0.0 },
            spring,
            normal: if model.rubs {
                0.5 * applied * a / sw
            } else {
                0.0
            },
        });
        out.stats.push(PassStat {
            partner: bq,
            force: 0.5 * applied * a,
            pressure: applied,
            // Finite: a pair with two rigid sides has no pressure.
            stored: phi0 * fade,
            heat,
            spring_rate: phi_dot,
        });
        applied
    }

    /// Pass 2 of boundary particle `q` (entry `kq`): what its partners'
    /// passes `pass1` handed it, and its normal's derivative spread.
    fn pass2(&self, pass1: &[P1], kq: usize, q: usize) -> Gathered {
        let (model, st, nb, bd) = (self.model, self.st, self.nb, self.bd);
        let mut f = DVec2::ZERO;
        let mut heat = 0.0;
        let mut n_bar = pass1[kq].n_bar;
        let mut normal = Vec::new();
        let bq = model.body[q];
        let (nq, oq) = (bd.normal[q], model.offset[q]);
        let sq = st.x[q] + nq * oq;
        for &p in nb.cross_of(q) {
            if !bd.is_boundary[p as usize] {
                continue;
            }
            let p = p as usize;
            let Some(share) = pass1[self.slot(p)].shares.iter().find(|s| s.body == bq) else {
                continue;
            };
            let Some((w, gw)) = is_candidate(model, st, bd, p, q) else {
                continue;
            };
            f += share.q * w;
            heat += share.eta * w;
            if model.rubs {
                add_normal(&mut normal, model.body[p], share.normal * w);
            }
            if let Some((bar, sp)) = &share.spring {
                let d = penalty::candidate(bar, *sp, w, sq, nq, oq);
                f += gw * d.w - d.x;
                n_bar += d.n;
            }
        }
        // Across the symmetry planes: the passes of the partners whose
        // images met q's, as they saw q's image (its force and the
        // derivative by its normal mirrored back; a pair meets across the
        // same mirror from either side).
        for &e in nb.cross_images_of(q) {
            let (p, kind) = image_entry(e);
            let (p, m) = (p as usize, self.mirrors[kind]);
            if !bd.is_boundary[p] {
                continue;
            }
            let Some(share) = pass1[self.slot(p)].shares.iter().find(|s| s.body == bq) else {
                continue;
            };
            let Some((w, gw)) = is_image_candidate(model, st, bd, &m, p, q) else {
                continue;
            };
            let (sx, nx) = (m.point(st.x[q]) + m.vector(nq) * oq, m.vector(nq));
            f += m.vector(share.q * w);
            heat += share.eta * w;
            if model.rubs {
                add_normal(&mut normal, model.body[p], share.normal * w);
            }
            if let Some((bar, sp)) = &share.spring {
                let d = penalty::candidate(bar, *sp, w, sx, nx, oq);
                f += m.vector(gw * d.w - d.x);
                n_bar += m.vector(d.n);
            }
        }
        let mut spread = Vec::new();
        if model.dim == 2 && n_bar != DVec2::ZERO && !model.rigid(q) {
            // ∂Φ/∂g for g = ∇ψ: g moves with Q against each neighbour
            // j by V_j ∇∇W, and with j the other way.
            let b = (n_bar - nq * nq.dot(n_bar)) / bd.grad_norm[q];
            // j moves its image across the axis of a body of
            // revolution or a symmetry plane the mirror way.
            for (nbr, image) in nb.round_with_images(model, &st.x, q) {
                let j = nbr.j as usize;
                let vol = model.reference_volume(j);
                let xj = image.map_or(st.x[j], |m| m.point(st.x[j]));
                let hb = hessian_times(model, q, j, st.x[q] - xj, b) * vol;
                f += hb;
                spread.push((nbr.j, image.map_or(-hb, |m| m.vector(-hb))));
            }
        }
        Gathered {
            force: f,
            heat,
            spread,
            normal,
        }
    }
}

/// Adds `f` to body `b`'s entry of the normal forces a particle gathers
/// from its partners' passes, one entry a body.
fn add_normal(normal: &mut Vec<(u32, f64)>, b: u32, f: f64) {
    match normal.iter_mut().find(|x| x.0 == b) {
        Some(x) => x.1 += f,
        None => normal.push((b, f)),
    }
}

/// The contact's forces, heat, spread and totals from both passes.
/// The spreads are moved out of `gathered`; friction reads the rest.
fn assemble(
    model: &Model,
    bd: &Boundary,
    pass1: &[P1],
    gathered: &mut [Gathered],
) -> ContactForces {
    let mut out = ContactForces {
        entry: bd
            .list
            .iter()
            .zip(pass1)
            .map(|(&i, p)| (i, p.entry))
            .collect(),
        force: Vec::with_capacity(bd.list.len()),
        spread: Vec::new(),
        heat: Vec::with_capacity(bd.list.len()),
        friction: Vec::new(),
        stats: ContactStats::default(),
    };
    for ((&p, own), g) in bd.list.iter().zip(pass1).zip(gathered) {
        let p = p as usize;
        out.force.push(own.force + g.force);
        out.heat.push(if model.rigid(p) {
            0.0
        } else {
            own.heat + g.heat
        });
        out.spread.append(&mut g.spread);
        for s in &own.stats {
            out.stats.add(model.body[p], s.partner, s.force, s.pressure);
            out.stats.stored += s.stored;
            out.stats.heat_rate += s.heat;
            out.stats.spring_rate += s.spring_rate;
        }
    }
    out
}
