//! The energy guard and the domain: what stops a run that went unstable.

use super::*;

impl Model {
    /// The energy guard: the total energy (kinetic + internal, dashpot heat
    /// included, + stored penalty energy) may not exceed [`ENERGY_GROWTH`]
    /// times its value at the first state (where bodies built overlapping
    /// on a coarse lattice already hold penalty energy), plus a floor of
    /// [`ENERGY_FLOOR`] `Σ m c_L²`: the energy of a motion at 1e-5 c_L, far
    /// above the round-off energy of bodies at rest (1e-17 of it in f32)
    /// and far below any impact's. The method conserves the total
    /// (docs/method.md §4; the discrete spring loses a little), so energy grown
    /// by half was made by the time integration going unstable: the run
    /// stops instead of finishing with answers that look right and energy
    /// many times the start's. Energy lost by half is as sure a sign: a
    /// blow-up that drives particles to large negative internal energies
    /// (an unstable damping, for one) can leave the total far below the
    /// start while the motion looks tame, so the guard is a band,
    /// [`Model::energy_lower`] below. Both solvers check each state at the start
    /// of the step that leaves it, with the evaluation they make there
    /// anyway. Not watched when a rigid body moves (it does work on what it
    /// pushes), nor where a constraint drives a region, nor under gravity
    /// (a body released at rest starts with no energy for the band to
    /// scale with, and draws it from its height).
    pub fn guards_energy(model: &Model) -> bool {
        model.gravity.is_none()
            && !model.held_moves()
            && !model
                .bodies
                .iter()
                .any(|b| b.rigid && b.velocity0 != DVec2::ZERO)
    }

    /// The deformable particles' potential energy in the body force,
    /// `−Σ m g·(x − x₀)` (zero as placed; 0 without gravity).
    pub fn potential_energy(&self, st: &State) -> f64 {
        let Some(g) = self.gravity else {
            return 0.0;
        };
        let mx: DVec2 = (0..self.len())
            .filter(|&i| !self.rigid(i))
            .map(|i| st.x[i] * self.mass[i])
            .sum();
        -g.dot(mx - self.gravity_ref)
    }

    /// The guard's limit from the total energy `e0` of the first state.
    pub fn energy_limit(&self, e0: f64) -> f64 {
        ENERGY_GROWTH * e0 + self.energy_floor
    }

    /// The initial total energy the upper `limit` was set from
    /// ([`Model::energy_limit`] inverted).
    fn energy_initial(&self, limit: f64) -> f64 {
        (limit - self.energy_floor) / ENERGY_GROWTH
    }

    /// The guard's lower bound for the upper `limit`: the initial total
    /// less as much as the upper bound allows it to grow, `(2 − G) e0 −
    /// floor` (half the initial, less the floor).
    pub fn energy_lower(&self, limit: f64) -> f64 {
        (2.0 - ENERGY_GROWTH) * self.energy_initial(limit) - self.energy_floor
    }

    /// The guard's bound on the internal energy the deformable particles
    /// hold below zero, `owed = Σ m min(e_i, 0)`: as much as the lower
    /// band lets the total lose, `−((G − 1) e0 + floor)`.
    ///
    /// Where the ledger closes (both integrators book their energy
    /// compatibly, docs/method.md §9) a blow-up leaves the total where it
    /// was and shows here instead: the motion a local instability makes is
    /// paid from the internal energy of the particles it drives, which
    /// then hold far below zero what no solid holds (the rubber rings
    /// past the leapfrog's limit for the hourglass control: 2.9 times the
    /// initial energy; rings that rebound intact hold 0.09 of it there,
    /// the penetration runs at most 0.011).
    pub fn energy_owed_bound(&self, limit: f64) -> f64 {
        -((ENERGY_GROWTH - 1.0) * self.energy_initial(limit) + self.energy_floor)
    }

    /// Whether the state has left the guard's band under the upper
    /// `limit`: its total energy `e`, or the internal energy `owed` its
    /// particles hold below zero ([`Model::energy_owed_bound`]).
    pub fn energy_outside(&self, limit: f64, e: f64, owed: f64) -> bool {
        e > limit || e < self.energy_lower(limit) || owed < self.energy_owed_bound(limit)
    }

    /// The quantity of an energy-guard message (both backends) under
    /// `limit`, for the total energy `e` and the energy below zero `owed`
    /// of a state outside the band, and the value it names.
    pub fn energy_quantity(&self, limit: f64, e: f64, owed: f64) -> (String, f64) {
        let e0 = self.energy_initial(limit);
        if e > limit {
            let q = format!("total energy (over {ENERGY_GROWTH} times the initial {e0:.4e})");
            (q, e)
        } else if e < self.energy_lower(limit) {
            let low = 2.0 - ENERGY_GROWTH;
            (
                format!("total energy (below {low} times the initial {e0:.4e})"),
                e,
            )
        } else {
            let share = ENERGY_GROWTH - 1.0;
            let q = format!(
                "internal energy held below zero (over {share} times the initial energy {e0:.4e})"
            );
            (q, owed)
        }
    }

    /// The internal energy the deformable particles of `state` hold below
    /// zero, `Σ m min(e_i, 0)` ([`Model::energy_owed_bound`]).
    pub fn energy_owed(&self, state: &State) -> f64 {
        (0..self.len())
            .filter(|&i| !self.rigid(i))
            .map(|i| self.mass[i] * state.e[i].min(0.0))
            .sum()
    }

    /// The particle an energy-guard message names for the total `e` under
    /// `limit`: the deformable one with the most specific energy `½ v² +
    /// e` (where a growth shows first), or the least where energy was lost
    /// or is held below zero.
    pub fn guarded_particle(&self, state: &State, limit: f64, e: f64) -> usize {
        let sign = if e <= limit { -1.0 } else { 1.0 };
        (0..self.len())
            .filter(|&i| !self.rigid(i))
            .map(|i| (i, sign * (0.5 * state.v[i].length_squared() + state.e[i])))
            .fold((0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a })
            .0
    }

    /// The domain: the bodies' initial bounding box grown on every side by
    /// the larger of its largest side and `T (|v|max + c_L,max)`, with `T`
    /// the end time, `|v|max` the largest initial speed and `c_L,max` the
    /// largest longitudinal wave speed at rest. Nothing in a sound run gets
    /// there: a particle must outrun the fastest wave for the whole run to
    /// leave, so one that does was flung out by an instability. Stopping
    /// then beats computing a particle alone in space, where the GPU's f32
    /// positions lose their precision too.
    pub fn domain_of(model: &Model, state: &State, end_time: f64) -> [DVec2; 2] {
        let (lo, hi) = crate::math::bounds(&state.x);
        let v_max = state.v.iter().map(|v| v.length()).fold(0.0, f64::max);
        let c_max = model
            .bodies
            .iter()
            .map(|b| b.material.c_l)
            .fold(0.0, f64::max);
        let extent = (hi - lo).max_element();
        let margin = extent.max(end_time * (v_max + c_max));
        [lo - DVec2::splat(margin), hi + DVec2::splat(margin)]
    }

    /// Whether `x` lies in the domain ([`Model::domain_of`]).
    #[inline]
    pub fn in_domain(&self, x: DVec2) -> bool {
        let [lo, hi] = self.domain;
        x.cmpge(lo).all() && x.cmple(hi).all()
    }

    /// The quantity and value that name a particle at `x` outside the
    /// domain in an instability message: the coordinate that is out and
    /// the interval it left (both backends).
    pub fn outside_domain(&self, x: DVec2) -> (String, f64) {
        let [lo, hi] = self.domain;
        let (axis, value, a, b) = if x.x < lo.x || x.x > hi.x {
            ("x", x.x, lo.x, hi.x)
        } else {
            ("y", x.y, lo.y, hi.y)
        };
        (
            format!("position {axis} (outside the domain [{a:e}, {b:e}] m)"),
            value,
        )
    }
}
