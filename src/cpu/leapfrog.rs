//! The leapfrog's step on the CPU (docs/method.md §9): one evaluation a
//! step, the rates at its start carried from the step before, the energy
//! sums replayed from the pairs the momentum sums kept.

use rayon::prelude::*;

use crate::cpu::neighbours::Neighbours;
use crate::physics::viscosity;

use super::*;

impl CpuSolver {
    /// One kick–drift–kick step (docs/method.md §9), one evaluation, with the
    /// rates `kn` at the current state (`a_n`, `ė_n`):
    ///
    /// 1. `v_{n+½} = v_n + ½Δt a_n`, `e_{n+½}` likewise, `x_{n+1} = x_n +
    ///    Δt v_{n+½}`;
    /// 2. the kinematic pass at `(x_{n+1}, v_{n+½})` takes `ρ` and `s` from
    ///    `n` to `n+1` (time-centred rates; with the radial return);
    /// 3. EOS and the momentum pass at `n+1`; the viscosity and the
    ///    dashpot see the predicted `v_n + cΔt a_n` (`c` the viscosity's
    ///    [`viscosity::predictor_weight`], 1 without it), the EOS the
    ///    predicted `e_{n+½} + ½Δt ė_n`, the viscosity's reconstruction the
    ///    gradient of the predicted velocities (taken in the walk of 2,
    ///    [`sweep::kinematics_seen`]); the hourglass control sees `v_{n+½}`
    ///    and the walk's gradient of it (`Kinematics::hv`), which keeps it
    ///    stable to twice the damping rate;
    /// 4. `v_{n+1} = v_{n+½} + ½Δt a_{n+1}`; then the energy sums with the
    ///    pair terms of 3 but the work done on `v_{n+1}`
    ///    ([`sweep::energy_replay`]), and `e_{n+1} = e_{n+½} + ½Δt ė_{n+1}`.
    ///
    /// The work of the force at `n+1` over the two half steps around it is
    /// exactly `Δt F·v_{n+1}`; energy booked at any other velocity drifts
    /// one way (docs/performance.md has the measurements). The rates of 3
    /// and 4 are the next step's `a_n`, `ė_n`.
    ///
    /// Returns whether every particle of the new state passes the state
    /// check.
    pub(super) fn leapfrog(&mut self, kn: Rates, dt: f64) -> bool {
        let model = &self.model;
        let st = &self.state;
        let h = 0.5 * dt;
        // 1: the half kick and the drift; ρ and s still at n. The
        // predicted velocity of 3 goes to next.v.
        let mut half = std::mem::take(&mut self.scratch);
        let mut next = std::mem::take(&mut self.spare);
        stage::enter(Stage::Advance, Role::KickDrift);
        kick_drift(model, st, &kn, dt, &mut half, &mut next);
        Self::refresh_lists(
            model,
            &mut self.nb,
            &mut self.list_builds,
            half.frame(),
            Role::Drifted,
        );
        let nb = &self.nb;
        stage::enter(Stage::Kinematics, Role::Next);
        // 2: ρ and s to n+1; the reconstruction's ∇v at the predicted
        // velocities, in the same walk. (A ∇v at n+½ with velocities at n+1
        // mixes two levels: a jump O(Δt) where it should be O(Δx²), which
        // makes the step first order.)
        let mut k = if model.dispersion > 0.0 {
            let seen = Some(&next.v[..]);
            sweep::kinematics_keeping(model, &half, nb, seen, &mut self.disp_kept)
        } else {
            sweep::kinematics_seen(model, &half, nb, &next.v)
        };
        if model.dispersion > 0.0 {
            let c = dispersion::strain_correction(model, &half, nb, &k, &self.disp_kept);
            dispersion::correct_rates(model, &half, &mut k, &c);
        }
        let lv = std::mem::take(&mut k.lv);
        next.x.copy_from_slice(&half.x);
        // ρ and s at n+1, the predicted energy of 3, and the EOS at them.
        let pts = to_next(model, st, (&kn, &k), dt, &half, &mut next);
        // 3: the forces at n+1.
        stage::enter(Stage::Forces, Role::Next);
        let (mut dv, art) = sweep::momentum_keeping(model, &next, nb, &k, &pts, &mut self.kept);
        // The dispersion correction's extra stress and its forces at n+1;
        // its work is booked at v_{n+1} with the energy sums (4).
        let extra = (model.dispersion > 0.0).then(|| {
            let pairs = (&k.l[..], &self.disp_kept);
            let s = dispersion::stress_adjoint(model, &next, nb, pairs, &pts);
            dispersion::add_forces(model, &next, nb, pairs, &s, &mut dv);
            s
        });
        let mirrors = (!model.images.is_empty())
            .then(|| axis::add_momentum(model, &next, nb, &k, &pts, &mut dv));
        // Nothing below reads L but the correction's work (4).
        let extra = extra.map(|s| (s, std::mem::take(&mut k.l)));
        let mut diag = Diagnostics {
            correction_fallback: k.fallback.len(),
            ..Default::default()
        };
        // The contact's normals and areas, as the GPU's forces stage has them.
        let bd = model.contact.then(|| {
            let measure = forces::contact_measure(model, &k);
            let kinematics::Kinematics { surface, .. } = k;
            forces::boundary(model, &next.x, nb, surface, measure)
        });
        if let Some(bd) = &bd {
            stage::enter(Stage::Contact, Role::Next);
            diag.boundary_count = bd.list.len();
            next.entry.clone_from(&st.entry);
            let c = contact::penalty_ahead(model, &next, nb, bd, None, h);
            c.add_forces(model, bd, &mut dv);
            contact::write_entries(&c.entry, &mut next.entry);
        }
        // 4: the second half kick, in place (v_{n+½} is dead after it;
        // next.v keeps the predicted velocity the contact's forces were
        // made at until the booking below), then the work on v_{n+1}.
        half.v.par_iter_mut().enumerate().for_each(|(i, v)| {
            if !model.rigid(i) {
                *v = model.hold(i, *v + model.gravity.map_or(dv[i], |g| dv[i] + g) * h);
            }
        });
        let v_next = &half.v;
        stage::enter(Stage::Forces, Role::Energy);
        let mut de = sweep::energy_replay(model, nb, &self.kept, v_next);
        if let Some((s, l)) = &extra {
            let g = dispersion::gradient(model, &next, nb, (l, &self.disp_kept), v_next);
            dispersion::add_work(model, &next, s, &g, &mut de);
        }
        let mut dissipation_rate = art.at(v_next);
        if let Some(m) = &mirrors {
            dissipation_rate += m.add_energy(model, nb, &pts, v_next, &mut de);
        }
        let mut friction = Vec::new();
        if let Some(bd) = bd {
            stage::enter(Stage::Contact, Role::Book);
            let c = book_contact(model, &next, nb, &bd, (v_next, h), &mut de);
            diag.contact = c.stats;
            friction = c.friction;
        }
        let (heat_rate, spring_rate) = (diag.contact.heat_rate, diag.contact.spring_rate);
        let friction_rate = diag.contact.friction_rate;
        std::mem::swap(&mut next.v, &mut half.v);
        // The walk's gradient is at x_{n+1}, Δt along v_{n+½} from x_n
        // (the carry maps it back: without, a first-order error in
        // every carried support).
        let walked = (&lv[..], dt);
        carry_supports(model, st, walked, dt, &mut next.metric, &mut next.carried);
        stage::enter(Stage::Advance, Role::Finish);
        // The next step's reduction is fused into this walk.
        stage::enter(Stage::Reduce, Role::Step);
        // e at n+1, the CFL step at the new state (cfl_step) and whether
        // it passes the state check ([`CpuSolver::check`], which names
        // the particle when it does not), in one walk.
        let (cfl_dt, sane) = finish_energy(model, &mut next, &half, (&dv, &de), &pts, h);
        next.heat = half.heat + heat_rate * h;
        next.dissipation = half.dissipation + dissipation_rate * h;
        next.spring_work = half.spring_work + spring_rate * h;
        if model.rubs {
            // The slip at n+1 from the rate booked at v_{n+1}, returned
            // onto the Coulomb limit found there.
            next.friction_heat = half.friction_heat + friction_rate * h;
            contact::advance_slip(&half.slip, &friction, h, &mut next.slip);
            contact::return_slip(model, &friction, &mut next);
            diag.contact.stored += contact::slip_stored(&next);
        }
        next.held_impulse.clone_from(&half.held_impulse);
        next.held_work = half.held_work;
        model.book_held(&dv, h, &mut next);
        next.t = st.t + dt;
        next.step = st.step + 1;
        // The next step's size, at the state it starts from.
        diag.cfl_dt = cfl_dt;
        if !model.held.is_empty() {
            diag.held_force = model.held_forces(&dv);
        }
        self.scratch = half;
        self.spare = std::mem::replace(&mut self.state, next);
        let rates = Rates {
            heat_rate,
            spring_rate,
            dissipation_rate,
            friction_rate,
            friction,
            ..Rates::of_motion(dv, de)
        };
        self.current = Some((rates, diag));
        sane
    }
}

/// Step 1 of [`CpuSolver::leapfrog`]: the half kick of `v` and `e` and the
/// drift of `x` into `half`, the predicted velocity of 3 into `next.v`.
fn kick_drift(model: &Model, st: &State, kn: &Rates, dt: f64, half: &mut State, next: &mut State) {
    let h = 0.5 * dt;
    half.x
        .par_iter_mut()
        .zip(half.v.par_iter_mut())
        .zip(half.e.par_iter_mut())
        .zip(next.v.par_iter_mut())
        .enumerate()
        .for_each(|(i, (((x, v), e), vp))| {
            if model.rigid(i) {
                *v = st.v[i];
                *e = st.e[i];
                *vp = *v;
            } else {
                // The body force kicks the velocity, but its work is
                // the potential's: the compatible term is the internal
                // forces' alone (docs/method.md §9, "Gravity").
                // A held component's kinetic energy does not change: the
                // compatible term takes the moving part alone.
                let a = model.gravity.map_or(kn.dv[i], |g| kn.dv[i] + g);
                *v = model.hold(i, st.v[i] + a * h);
                *e = st.e[i] + kn.de[i] * h + kick_energy(model.moving_part(i, kn.dv[i]), h);
                let c =
                    viscosity::predictor_weight(model.alpha, model.material(i).c_l, model.h[i], dt);
                *vp = model.hold(i, *v + a * ((c - 0.5) * dt));
            }
            *x = st.x[i] + *v * dt;
        });
    half.rho.copy_from_slice(&st.rho);
    half.s.copy_from_slice(&st.s);
    // The step's sums take the supports it starts with; they are
    // carried to n+1 at its end.
    half.metric.clone_from(&st.metric);
    next.metric.clone_from(&st.metric);
    half.heat = st.heat + kn.heat_rate * h;
    half.dissipation = st.dissipation + kn.dissipation_rate * h;
    half.spring_work = st.spring_work + kn.spring_rate * h;
    if model.rubs {
        // The slip at n+½, which the contact at n+1 looks ahead from.
        half.friction_heat = st.friction_heat + kn.friction_rate * h;
        contact::advance_slip(&st.slip, &kn.friction, h, &mut half.slip);
        // The state at n+1 keeps the springs of n until its return.
        next.slip.clone_from(&half.slip);
        next.slip_stiffness.clone_from(&st.slip_stiffness);
        next.sliding.clone_from(&st.sliding);
    }
    half.held_impulse.clone_from(&st.held_impulse);
    half.held_work = st.held_work;
    model.book_held(&kn.dv, h, half);
}

/// Step 2's second half: `ρ` and `s` at n+1 (with the radial return and
/// a plastic history's), the predicted energy of 3, into `next`; and the
/// stress points at them (in the same walk, or, with a plastic history,
/// after its return).
fn to_next(
    model: &Model,
    st: &State,
    (kn, k): (&Rates, &kinematics::Kinematics),
    dt: f64,
    half: &State,
    next: &mut State,
) -> Vec<StressPoint> {
    let h = 0.5 * dt;
    let to_next = |i: usize, e: &mut f64, rho: &mut f64, s: &mut Sym| {
        if model.rigid(i) {
            (*e, *rho, *s) = (half.e[i], half.rho[i], half.s[i]);
            return;
        }
        // The predicted energy takes back the first half kick's
        // compatible term, which the second is expected to return.
        *e = half.e[i] + kn.de[i] * h - kick_energy(model.moving_part(i, kn.dv[i]), h);
        *rho = density_after(half.rho[i], k.drho[i], dt);
        *s = plastic_return(model, i, half.s[i].add_scaled(&k.ds[i], dt));
    };
    let walk = next
        .e
        .par_iter_mut()
        .zip(next.rho.par_iter_mut())
        .zip(next.s.par_iter_mut())
        .enumerate();
    if model.history {
        walk.for_each(|(i, ((e, rho), s))| to_next(i, e, rho, s));
        return_with_history(model, st, &k.rate, st.t + dt, next);
        eos_and_stress_with(model, next, &k.fallback)
    } else {
        let debris = k.debris_flags(model);
        walk.map(|(i, ((e, rho), s))| {
            to_next(i, e, rho, s);
            let at = (*rho, next.x[i]);
            if debris.get(i).copied().unwrap_or(false) {
                kinematics::debris_point(model, i, at, *e)
            } else {
                stress_point(model, i, at, *e, s, 0.0)
            }
        })
        .collect()
    }
}

/// Step 4's end: `e` at n+1 from the energy rates `de` (the kick `dv`'s
/// compatible term taken back), the CFL step at the new state (cfl_step)
/// and whether it passes the state check ([`CpuSolver::check`], which
/// names the particle when it does not), in one walk.
fn finish_energy(
    model: &Model,
    next: &mut State,
    half: &State,
    (dv, de): (&[DVec2], &[f64]),
    pts: &[StressPoint],
    h: f64,
) -> (f64, bool) {
    next.e
        .par_iter_mut()
        .enumerate()
        .map(|(i, e)| {
            let (x, v, rho) = (next.x[i], next.v[i], next.rho[i]);
            if model.rigid(i) {
                // Checked too: a rigid body may leave the domain.
                return (f64::INFINITY, sane(model, i, x, v, *e, rho, 0.0));
            }
            *e = half.e[i] + de[i] * h - kick_energy(model.moving_part(i, dv[i]), h);
            let hs = support_h(model, &next.metric, i);
            let dt = material::cfl_step(model.cfl, hs, pts[i].c, v.length());
            (
                dt,
                sane(
                    model,
                    i,
                    x,
                    v,
                    *e,
                    rho,
                    next.damage.get(i).copied().unwrap_or(0.0),
                ),
            )
        })
        .reduce(|| (f64::INFINITY, true), |a, b| (a.0.min(b.0), a.1 && b.1))
}

/// The density a step later at the rate `drho = −ρ tr ∇v` held over it:
/// `ρ exp(Δt drho/ρ)`, so that `ln ρ` and the deviatoric stress, both
/// advanced by `Δt` times the same strain rate, keep the uniaxial identity
/// `s_zz − s_xx = 2G ln(ρ/ρ0)` to round-off (the forward step `ρ + Δt
/// drho` lost `½(Δt tr ∇v)²` of `ln ρ` a step; docs/method.md §9). Its
/// twin is `density_after` in kinematics.wgsl.
#[inline]
fn density_after(rho: f64, drho: f64, dt: f64) -> f64 {
    rho + rho * (drho / rho * dt).exp_m1()
}

/// The leapfrog's compatible energy (docs/method.md §9): what a half kick
/// by `a` over `h = ½Δt` adds to a particle's internal energy, `−½(h a)²`
/// where the kick starts from the velocity its work was booked at (the
/// first half kick, from `v_n`), and minus that where it ends there (the
/// second, to `v_{n+1}`).
///
/// The energy sums book each half kick's work at one end of it, but the
/// kinetic energy changes by the work at its mean velocity; the two
/// differ by `½ |h a|²` a half kick, `⅛Δt² (|a_n|² − |a_{n+1}|²)` a step.
/// At a fixed step these cancel from step to step, but where the step
/// shrinks or grows they do not, and the ledger drifts by what is left.
/// Booked, `Σ m (½v² + e)` changes by what the contact books alone.
#[inline]
fn kick_energy(a: DVec2, h: f64) -> f64 {
    -0.5 * (a * h).length_squared()
}

/// The contact's forces at `next` again (the same bits), their heat and
/// spring power booked at the velocities `v` (v_{n+1}); the heat goes to
/// `de`.
fn book_contact(
    model: &Model,
    next: &State,
    nb: &Neighbours,
    bd: &forces::Boundary,
    (v, h): (&[DVec2], f64),
    de: &mut [f64],
) -> contact::ContactForces {
    let c = contact::penalty_ahead(model, next, nb, bd, Some(v), h);
    for (k, &i) in bd.list.iter().enumerate() {
        let i = i as usize;
        if !model.rigid(i) {
            de[i] += c.heat[k] / model.mass[i];
        }
    }
    c
}
