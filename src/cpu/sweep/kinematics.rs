//! The kinematic pass pair by pair: each pair's terms added to both of
//! its particles, then finished as the plain gather is
//! ([`crate::cpu::kinematics`]).

use glam::DVec2;

use crate::cpu::dispersion::Kept;
use crate::cpu::kinematics::{finish, gradient_weight, volumes, Kinematics, Seen, Sums};
use crate::cpu::neighbours::Neighbours;
use crate::math::Mat2;
use crate::model::{Model, State};

/// The kinematic pass at `st` ([`crate::cpu::kinematics::kinematics`]).
///
/// The walk visits each pair once ([`Neighbours::sweep`]): with
/// `∇_j W_ji = −∇_i W_ij`, particle j's terms are i's outer products
/// `∇_i W_ij ⊗ (x_j − x_i)` and `(v_j − v_i) ⊗ ∇_i W_ij` weighted by `V_i`
/// instead of `V_j`, and its colour-gradient term changes sign.
pub fn kinematics(model: &Model, st: &State, nb: &Neighbours) -> Kinematics {
    kinematics_in::<(), ()>(model, st, nb, &[], &mut nb.no_store())
}

/// [`kinematics`], with the velocity gradient the viscosity's
/// reconstruction uses ([`Kinematics::gv`](crate::cpu::kinematics::Kinematics::gv)) taken at the velocities `seen`
/// (the leapfrog's predicted `v_n + cΔt a_n` at `x_{n+1}`) instead of the
/// state's, in the same walk: the reconstruction then removes exactly the
/// linear part of the jump the viscosity sees.
pub fn kinematics_seen(model: &Model, st: &State, nb: &Neighbours, seen: &[DVec2]) -> Kinematics {
    if model.keeps_gradient() {
        kinematics_in::<Mat2, ()>(model, st, nb, seen, &mut nb.no_store())
    } else {
        kinematics(model, st, nb)
    }
}

/// [`kinematics_seen`] (without `seen`, [`kinematics`]) that also keeps
/// each pair's kernel gradient `∇_i W_ij` in `kept` for the dispersion
/// correction's sums, which replay them ([`Kept`]).
pub fn kinematics_keeping(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    seen: Option<&[DVec2]>,
    kept: &mut Kept,
) -> Kinematics {
    let store = kept.slots(nb.store_len());
    match seen {
        Some(seen) if model.keeps_gradient() => {
            kinematics_in::<Mat2, DVec2>(model, st, nb, seen, store)
        }
        _ => kinematics_in::<(), DVec2>(model, st, nb, &[], store),
    }
}

/// A pair's slot of the kinematic walk's store: the kernel gradient, or
/// nothing (a zero-sized slot: no memory and no work).
trait KeepGradient: Send + Default {
    fn keep(&mut self, gw: DVec2);
}

impl KeepGradient for () {
    #[inline]
    fn keep(&mut self, _: DVec2) {}
}

impl KeepGradient for DVec2 {
    #[inline]
    fn keep(&mut self, gw: DVec2) {
        *self = gw;
    }
}

fn kinematics_in<S: Seen, K: KeepGradient>(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    seen: &[DVec2],
    store: &mut [K],
) -> Kinematics {
    let vol = volumes(model, st);
    let vel = S::vel(&st.v, seen);
    let mut sums = vec![Sums::<S>::default(); model.len()];
    let axi = model.axisymmetric;
    if !st.round_supports() {
        // The gradient sums over the pairs of the supports, the colour
        // gradient over the round pairs (kinematics::round_colour), in
        // one walk.
        nb.sweep_two_store(
            model,
            st.frame(),
            &mut sums,
            store,
            |i, m, r, si, mut sj, slot| {
                let j = match (m, r) {
                    (Some(b), _) | (_, Some(b)) => b.j as usize,
                    _ => return,
                };
                // ∇_j W_ji = −∇_i W_ij.
                if let Some(r) = r {
                    si.add_colour(r.gw, r.w, vol[j], axi);
                }
                if let (Some(r), Some(sj)) = (r, sj.as_deref_mut()) {
                    sj.add_colour(-r.gw, r.w, vol[i], axi);
                }
                let Some(b) = m else { return };
                slot.keep(b.gw);
                let (vi, vj) = (vel[i], vel[j]);
                let (dx, dv) = (st.x[j] - st.x[i], S::v(vj) - S::v(vi));
                let gi = b.gw * gradient_weight(model, st, &vol, i, j);
                let near = u32::from(b.q2 > 0.0);
                si.m += Mat2::outer(gi, dx);
                si.gsum += Mat2::outer(dv, gi);
                si.seen.add(vj, vi, gi);
                si.n += near;
                if let Some(sj) = sj {
                    let gj = b.gw * gradient_weight(model, st, &vol, j, i);
                    sj.m += Mat2::outer(gj, dx);
                    sj.gsum += Mat2::outer(dv, gj);
                    sj.seen.add(vj, vi, gj);
                    sj.n += near;
                }
            },
        );
        if !model.images.is_empty() {
            crate::cpu::axis::add_kinematics(model, st, nb, &vol, &vel, &mut sums);
        }
        return finish(model, st, sums);
    }
    nb.sweep_store(model, st.frame(), &mut sums, store, |i, b, si, sj, slot| {
        let j = b.j as usize;
        slot.keep(b.gw);
        let (vi, vj) = (vel[i], vel[j]);
        let (dx, dv) = (st.x[j] - st.x[i], S::v(vj) - S::v(vi));
        let gi = b.gw * gradient_weight(model, st, &vol, i, j);
        let near = u32::from(b.q2 > 0.0);
        si.m += Mat2::outer(gi, dx);
        si.gsum += Mat2::outer(dv, gi);
        si.add_colour(b.gw, b.w, vol[j], axi);
        si.seen.add(vj, vi, gi);
        si.n += near;
        if let Some(sj) = sj {
            let gj = b.gw * gradient_weight(model, st, &vol, j, i);
            sj.m += Mat2::outer(gj, dx);
            sj.gsum += Mat2::outer(dv, gj);
            sj.add_colour(-b.gw, b.w, vol[i], axi);
            sj.seen.add(vj, vi, gj);
            sj.n += near;
        }
    });
    if !model.images.is_empty() {
        crate::cpu::axis::add_kinematics(model, st, nb, &vol, &vel, &mut sums);
    }
    finish(model, st, sums)
}
