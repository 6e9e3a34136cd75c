//! Coulomb friction (docs/method.md §8.6): after the normal passes, each
//! boundary particle P that presses on a partner rubs on it with a
//! tangential spring and dashpot held to `μ` times the normal force the
//! contact puts on P; a last gather hands the reaction to the partner's
//! particles by weight. Nothing here runs without friction.

use super::booked::{Booking, Gathered, P1};
use super::*;

/// What P's friction keeps, books and hands on.
#[derive(Debug, Clone, Copy, Default)]
struct Rub {
    force: DVec2,
    heat: f64,
    /// The spring's power.
    spring: f64,
    /// The partner body, and the force handed to its candidates per unit
    /// weight.
    share: Option<(u32, DVec2)>,
    friction: Friction,
    /// The partner and `[f τ A, A |slip rate|, A]`.
    stat: Option<(u32, [f64; 3])>,
}

/// Adds the friction of every boundary particle to `out`, the normal
/// contact's forces, heat and statistics from `pass1` and `gathered`.
pub(super) fn add(bk: &Booking, pass1: &[P1], gathered: &[Gathered], out: &mut ContactForces) {
    let (model, st, bd) = (bk.model, bk.st, bk.bd);
    let rubs: Vec<Rub> = bd
        .list
        .par_iter()
        .enumerate()
        .map(|(k, &p)| rub(bk, p as usize, &pass1[k], &gathered[k]))
        .collect();
    // Each particle Q gathers what the particles rubbing on its body
    // handed it, over exactly their candidate sets.
    let handed: Vec<DVec2> = bd
        .list
        .par_iter()
        .map(|&q| {
            let q = q as usize;
            let mut f = DVec2::ZERO;
            if model.rigid(q) {
                return f;
            }
            let bq = model.body[q];
            // What boundary particle p handed q (or q's image, met with
            // weight `w`) where p rubs on q's body.
            let handed_by = |p: usize| {
                bd.is_boundary[p]
                    .then(|| rubs[bk.slot(p)].share)
                    .flatten()
                    .filter(|s| s.0 == bq)
                    .map(|s| s.1)
            };
            for &p in bk.nb.cross_of(q) {
                let p = p as usize;
                if let Some(share) = handed_by(p) {
                    if let Some((w, _)) = is_candidate(model, st, bd, p, q) {
                        f += share * w;
                    }
                }
            }
            // Across the symmetry planes: what the partners whose images
            // met q's handed to q's image, mirrored back.
            for &e in bk.nb.cross_images_of(q) {
                let (p, kind) = image_entry(e);
                let (p, m) = (p as usize, bk.mirrors[kind]);
                if let Some(share) = handed_by(p) {
                    if let Some((w, _)) = is_image_candidate(model, st, bd, &m, p, q) {
                        f += m.vector(share * w);
                    }
                }
            }
            f
        })
        .collect();
    out.friction = Vec::with_capacity(bd.list.len());
    for (k, &p) in bd.list.iter().enumerate() {
        let r = &rubs[k];
        out.force[k] += r.force + handed[k];
        out.heat[k] += r.heat;
        out.stats.heat_rate += r.heat;
        out.stats.friction_rate += r.heat;
        out.stats.spring_rate += r.spring;
        if let Some((partner, t)) = r.stat {
            out.stats.add_tangential(model.body[p as usize], partner, t);
        }
        out.friction.push((p, r.friction));
    }
}

/// P's friction against the partner it rubs on (pass 1's
/// [`P1::rubs`]), `gathered` what P gathered in pass 2.
///
/// A spring on P's elastic slip and a dashpot on the relative tangential
/// velocity, their traction `τ` held to the Coulomb limit `μ N / A`, `N`
/// the normal force on P: what P's own pass applies (`½ p A`) and the
/// partner's passes' applied forces shared to P by weight. Summed over a
/// body, `N` is the pair's normal force as the contact probe reports it.
/// P keeps `−f τ A t` and hands `+f τ A t` to its
/// candidates by weight; `f` is ½ against a deformable partner, whose
/// particles rub back with the other half, and 1 against a rigid one,
/// whose particles do not rub. Summed over a body, the limit is `μ` times
/// the normal force between the bodies.
fn rub(bk: &Booking, p: usize, own: &P1, gathered: &Gathered) -> Rub {
    // Friction acts against the partner that presses hardest on P: P
    // carries one slip.
    let shared = |b: u32| {
        gathered
            .normal
            .iter()
            .find(|x| x.0 == b)
            .map_or(0.0, |x| x.1)
    };
    let Some((s, n, normal)) = own
        .rubs
        .iter()
        .map(|&(s, n, own)| (s, n, own + shared(s.body)))
        .filter(|r| r.2 > 0.0)
        .reduce(|a, b| if b.2 > a.2 { b } else { a })
    else {
        return Rub::default();
    };
    let (model, st, bd) = (bk.model, bk.st, bk.bd);
    let (bp, bq) = (model.body[p], s.body);
    let mu = model.friction_between(bp, bq);
    if mu.sticking == 0.0 {
        return Rub::default();
    }
    let t = n.perp();
    let a = bd.area[p];
    let f = if model.bodies[bq as usize].rigid {
        1.0
    } else {
        0.5
    };
    let (za, ga) = shear_constants(model, bp);
    let (zb, gb) = shear_constants(model, bq);
    let sw = s.s.sw;
    let kt = spring_stiffness(
        model.offset[p],
        model.bodies[bp as usize].spacing,
        ga,
        s.s.swo / sw,
        model.bodies[bq as usize].spacing,
        gb,
    );
    let zt = series(za, zb);
    let w = (st.v[p] - s.swv / sw).dot(t);
    let w_book = bk.book.map_or(w, |b| (b[p] - s.swb / sw).dot(t));
    // The sliding limit, and the limit a sticking pass holds to: the
    // static one unless the particle slid at the last return.
    let limit = mu.sliding * normal / a;
    let hold = if st.sliding[p] {
        limit
    } else {
        mu.sticking * normal / a
    };
    // The slip each limit allows: the state's slip is returned onto the
    // step's at this state ([`return_slip`]).
    let cap_of = |l: f64| if kt > 0.0 { l / kt } else { 0.0 };
    let (cap, cap_hold) = (cap_of(limit), cap_of(hold));
    let u0 = st.slip[p];
    let c = f * a * kt;
    // Sticking, the slip `horizon` ahead; sliding, where it is (both
    // held to their limit).
    let u_stick = (u0 + bk.horizon * w).clamp(-cap_hold, cap_hold);
    let trial = kt * u_stick + zt * w;
    let stick = trial.abs() <= hold;
    let u = if stick { u_stick } else { u0.clamp(-cap, cap) };
    let (tau, rate, heat, spring) = if stick {
        // Sticking: the spring stores, the dashpot heats.
        let d = f * a * zt * w * w_book;
        (trial, w_book, d.max(0.0), c * u * w_book + d.min(0.0))
    } else {
        // Sliding: the traction's work is heat. Where the booking velocity
        // has turned against it (a reversal inside the step) that work goes
        // to the spring's ledger instead, so that heat is never negative.
        let tau = limit.copysign(trial);
        let d = f * a * tau * w_book;
        (tau, 0.0, d.max(0.0), d.min(0.0))
    };
    let force = t * (f * a * tau);
    Rub {
        force: -force,
        heat,
        spring,
        share: Some((bq, force / sw)),
        friction: Friction {
            stiffness: c,
            cap: if stick { cap_hold } else { cap },
            rate,
            sliding: !stick,
        },
        stat: Some((bq, [f * a * tau, a * (w_book - rate).abs(), a])),
    }
}
