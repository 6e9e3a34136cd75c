//! The advance stage (twin of `shaders/advance.wgsl`): the midpoint rule's
//! `base + k · rates` with the radial return or the strength update
//! (`shaders/strength.wgsl`, [`crate::physics::strength`]), and the state
//! check a new state must pass.

use glam::DVec2;
use rayon::prelude::*;

use super::Rates;
use crate::math::{Mat2, Sym};
use crate::model::{Model, State};
use crate::physics::strength;
use crate::physics::support::{BandBounds, Metric};

/// `out = base + k · rates` (positions move with `vel`), with the radial
/// return applied to the new deviatoric stress: perfect plasticity, or,
/// when the state carries a plastic history, the material's strength and
/// failure laws ([`strength::update`]) from the history of `base`.
///
/// `whole`: the step's full update, whose rates were evaluated at the
/// midpoint velocities `vel`; its energy is booked compatibly
/// ([`compatible_energy`]).
pub(super) fn advance(
    model: &Model,
    base: &State,
    vel: &[DVec2],
    r: &Rates,
    k: f64,
    whole: bool,
    out: &mut State,
) {
    out.x
        .par_iter_mut()
        .zip(out.v.par_iter_mut())
        .zip(out.rho.par_iter_mut())
        .zip(out.e.par_iter_mut())
        .zip(out.s.par_iter_mut())
        .enumerate()
        .for_each(|(i, ((((x, v), rho), e), s))| {
            *x = base.x[i] + vel[i] * k;
            if model.rigid(i) {
                // A rigid body keeps its velocity and reference state.
                *v = base.v[i];
                *rho = base.rho[i];
                *e = base.e[i];
                *s = base.s[i];
                return;
            }
            *v = match model.gravity {
                None => base.v[i] + r.dv[i] * k,
                Some(g) => base.v[i] + (r.dv[i] + g) * k,
            };
            *v = model.hold(i, *v);
            *rho = base.rho[i] + r.drho[i] * k;
            *e = base.e[i] + r.de[i] * k;
            if whole {
                *e += compatible_energy(base.v[i], vel[i], *v);
            }
            *s = plastic_return(model, i, base.s[i].add_scaled(&r.ds[i], k));
        });
    if model.history {
        return_with_history(model, base, &r.rate, base.t + k, out);
    }
    out.heat = base.heat + r.heat_rate * k;
    out.dissipation = base.dissipation + r.dissipation_rate * k;
    out.spring_work = base.spring_work + r.spring_rate * k;
    out.entry.clone_from(&base.entry);
    if model.rubs {
        out.friction_heat = base.friction_heat + r.friction_rate * k;
        super::contact::advance_slip(&base.slip, &r.friction, k, &mut out.slip);
        out.slip_stiffness.clone_from(&base.slip_stiffness);
        out.sliding.clone_from(&base.sliding);
    }
    out.held_impulse.clone_from(&base.held_impulse);
    out.held_work = base.held_work;
    if whole {
        model.book_held(&r.dv, k, out);
    }
}

/// The midpoint rule's compatible energy (docs/method.md §9): the
/// specific internal energy to add to a particle whose rates, evaluated at
/// the midpoint velocity `vm`, took it from `vn` to `vn1`.
///
/// The rates book each force's work at `vm`, but the kinetic energy
/// changes by the work at the step's mean velocity `v̄ = ½(vn + vn1)`:
/// `½(vn1² − vn²) = (vn1 − vn)·v̄`. Adding `−(vn1 − vn)·(v̄ − vm)` makes
/// `Σ m (½v² + e)` change by what the contact books alone, to round-off.
/// It is `−½Δt² a_{n+½}·(a_{n+½} − a_n)`: nothing where the acceleration
/// holds over the step, and the energy a chattering particle's rates give
/// its motion taken from its own internal energy.
#[inline]
fn compatible_energy(vn: DVec2, vm: DVec2, vn1: DVec2) -> f64 {
    -(vn1 - vn).dot((vn + vn1) * 0.5 - vm)
}

/// Each particle's support at the end of a step of `dt` from `from`,
/// carried with the velocity gradient `lv` of the evaluation that moved
/// the positions ([`Metric::carried`], docs/method.md, "Supports that
/// follow the deformation"); a rigid particle keeps its own. Nothing
/// with round supports (`from` empty). Where supports adapt within a
/// band (`Model::band` above one) the carried ellipse goes to
/// `out_carried` and the supports they give to `out`
/// ([`Model::supports_of`]: none while all are round).
///
/// `lag`: how far ahead of `x_n` the positions `lv` was taken at lie, as
/// a time along `v` (the leapfrog's walk at `x_{n+1}`: `dt`; 0 for none).
/// The carry `I + Δt L` is the step's motion exactly for `L` with respect
/// to `x_n`, so each gradient is mapped back by it first
/// ([`Mat2::gradient_behind`]; kept where the step would have folded the
/// neighbourhood).
pub(super) fn carry_supports(
    model: &Model,
    from: &State,
    (lv, lag): (&[Mat2], f64),
    dt: f64,
    out: &mut Vec<Metric>,
    out_carried: &mut Vec<Metric>,
) {
    let at_start = |l: &Mat2| {
        if lag == 0.0 {
            *l
        } else {
            l.gradient_behind(lag).unwrap_or(*l)
        }
    };
    if !model.carries_band() {
        out.clear();
        out.extend_from_slice(&from.metric);
        out.par_iter_mut()
            .zip(lv.par_iter())
            .enumerate()
            .for_each(|(i, (q, l))| {
                if !model.rigid(i) {
                    *q = q.carried(&at_start(l), dt, model.h[i], model.dim);
                }
            });
        return;
    }
    // The carry and the supports in one walk, a run of particles a task
    // (as `Model::supports_of` of the carried ellipses, bit for bit):
    // the bounds worked out once for each run of equal `h`, the
    // eigenvalues once a particle where nothing is clamped.
    let n = from.carried.len();
    out_carried.resize(n, Metric::default());
    out.resize(n, Metric::default());
    let all_round = out_carried
        .par_chunks_mut(CARRY_RUN)
        .zip(out.par_chunks_mut(CARRY_RUN))
        .enumerate()
        .map(|(r, (cs, qs))| {
            let base = r * CARRY_RUN;
            let mut bounds: Option<(f64, BandBounds)> = None;
            let mut round = true;
            for (k, (c, q)) in cs.iter_mut().zip(qs).enumerate() {
                let i = base + k;
                let h = model.h[i];
                let b = match bounds {
                    Some((hb, b)) if hb == h => b,
                    _ => {
                        let b = BandBounds::new(h, model.band);
                        bounds = Some((h, b));
                        b
                    }
                };
                let was = from.carried[i];
                (*c, *q) = if model.rigid(i) {
                    (was, was.banded(h, model.band, model.dim))
                } else {
                    was.carried_banded(&at_start(&lv[i]), dt, &b, model.dim)
                };
                round &= *q == Metric::round_of(b.round);
            }
            round
        })
        .reduce(|| true, |a, b| a && b);
    if all_round {
        out.clear();
    }
}

/// Particles a task of [`carry_supports`].
const CARRY_RUN: usize = 4096;

/// Whether particle i's density is inside `[0.1, 10] ρ0`, or, for a
/// failed particle (damage `damage`), positive and below `10 ρ0`: an
/// opening crack takes a failed particle's density towards zero.
#[inline]
pub(super) fn dense(model: &Model, i: usize, rho: f64, damage: f64) -> bool {
    let rho0 = model.material(i).rho0;
    let low = if strength::failed(damage) {
        0.0
    } else {
        0.1 * rho0
    };
    rho > low && rho < 10.0 * rho0
}

/// Whether particle i at `x`, `v`, `e`, `rho` (a state's
/// [`State::rho`]) passes the state check ([`CpuSolver::check`]).
#[inline]
pub(super) fn sane(
    model: &Model,
    i: usize,
    x: DVec2,
    v: DVec2,
    e: f64,
    rho: f64,
    damage: f64,
) -> bool {
    x.is_finite()
        && v.is_finite()
        && e.is_finite()
        && dense(model, i, model.density(rho, x), damage)
        && model.in_domain(x)
}

/// Perfect plasticity, radial return (docs/method.md §6): particle i's trial
/// deviatoric stress `s` scaled back onto the yield surface. When the state
/// carries a plastic history the trial is left as it is: the history's
/// update returns it ([`return_with_history`]).
#[inline]
pub(super) fn plastic_return(model: &Model, i: usize, s: Sym) -> Sym {
    if model.history {
        return s;
    }
    let y0 = model.material(i).y0;
    if y0.is_finite() {
        let j = s.von_mises();
        if j > y0 {
            return s.scale(y0 / j);
        }
    }
    s
}

/// The stress update with a plastic history ([`strength::update`]) over a
/// whole state: `out.s` holds the trial stresses and leaves with the
/// returned ones; `out.rho` and `out.e` are where the step ends, `from` the
/// state whose history it starts from, `rate` the strain rates (empty: 0),
/// `t_end` the time `out` is at (a particle failing now fails at it).
/// A failed particle's density is held at or above the density at which
/// its pressure vanishes ([`crate::physics::material::MaterialModel::failed_density_floor`]);
/// so is that of one with a void open ([`strength::void_state`]), whose
/// deviatoric stress drops.
/// Rigid particles keep `from`'s history.
pub(super) fn return_with_history(
    model: &Model,
    from: &State,
    rate: &[f64],
    t_end: f64,
    out: &mut State,
) {
    let State {
        x,
        rho,
        e,
        s,
        eps_p,
        temperature,
        damage,
        failed_at,
        ..
    } = out;
    s.par_iter_mut()
        .zip(rho.par_iter_mut())
        .zip(eps_p.par_iter_mut())
        .zip(temperature.par_iter_mut())
        .zip(damage.par_iter_mut())
        .zip(failed_at.par_iter_mut())
        .enumerate()
        .for_each(|(i, (((((s, rho), ep), t), d), at))| {
            let h = if model.rigid(i) {
                from.history(i)
            } else {
                let mat = model.material(i);
                let r = rate.get(i).copied().unwrap_or(0.0);
                // The density itself (in a body of revolution `rho` is η).
                let (rho_i, e) = (model.density(*rho, x[i]), e[i]);
                let (s_new, h) = strength::update(
                    mat,
                    *s,
                    r,
                    rho_i,
                    || mat.pressure(rho_i, e),
                    from.history(i),
                );
                *s = s_new;
                *at = if strength::failed(h.damage) {
                    if from.failed_at[i] < 0.0 {
                        t_end
                    } else {
                        from.failed_at[i]
                    }
                } else if mat.cavitation.is_finite() {
                    strength::void_state(mat, mat.pressure(rho_i, e), from.failed_at[i])
                } else {
                    from.failed_at[i]
                };
                let void = *at == strength::VOID_OPEN;
                if void {
                    *s = Sym::default();
                }
                if void || strength::failed(h.damage) {
                    let floor = rho_i.max(mat.failed_density_floor(e));
                    *rho = model.state_rho(floor, x[i]);
                }
                h
            };
            (*ep, *t, *d) = (h.eps_p, h.temperature, h.damage);
            if model.rigid(i) {
                *at = from.failed_at[i];
            }
        });
}
