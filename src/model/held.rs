//! The clamped and driven regions (`[[bodies.constraints]]`,
//! docs/method.md, "Constraints"): what the integrators do to a held
//! particle's velocity, and what the constraints take and give.

use super::*;

impl Model {
    /// `v` with particle `i`'s held components at its constraint's
    /// velocity (unchanged for a free particle).
    /// A particle on a symmetry plane moves along it too.
    #[inline]
    pub fn hold(&self, i: usize, v: DVec2) -> DVec2 {
        let v = match self.held_of.get(i) {
            Some(&k) if k > 0 => self.held[k as usize - 1].hold(v),
            _ => v,
        };
        self.along_plane(i, v)
    }

    /// The part of an acceleration `a` of particle `i` that moves it: `a`
    /// less its held components (and its component normal to a symmetry
    /// plane it lies on). The leapfrog's compatible kick terms take it,
    /// since a held component's kinetic energy does not change.
    #[inline]
    pub fn moving_part(&self, i: usize, a: DVec2) -> DVec2 {
        let a = match self.held_of.get(i) {
            Some(&k) if k > 0 => a * (DVec2::ONE - self.held[k as usize - 1].mask),
            _ => a,
        };
        self.along_plane(i, a)
    }

    /// `v` of particle `i` without its components normal to the symmetry
    /// planes it lies on (its own mirror image: the
    /// pairs with its neighbours' images cancel that component but for
    /// round-off, which would carry it off the plane); `v` elsewhere.
    #[inline]
    pub(crate) fn along_plane(&self, i: usize, v: DVec2) -> DVec2 {
        match self.on_plane.get(i) {
            Some(&on) if on != 0 => DVec2::new(
                if on & 1 != 0 { 0.0 } else { v.x },
                if on & 2 != 0 { 0.0 } else { v.y },
            ),
            _ => v,
        }
    }

    /// Each constraint's force on its region under the rates `dv`: what
    /// holds its particles' held components against the internal forces
    /// and the body force, `−Σ m (a + g)` over them.
    pub fn held_forces(&self, dv: &[DVec2]) -> Vec<DVec2> {
        let g = self.gravity.unwrap_or(DVec2::ZERO);
        self.held
            .iter()
            .map(|c| {
                c.particles
                    .iter()
                    .map(|&i| -(dv[i] + g) * self.mass[i] * c.mask)
                    .sum()
            })
            .collect()
    }

    /// A kick of `h` with the rates `dv` into `out`: each constraint's
    /// impulse on its region, and the work it does at its velocity.
    pub fn book_held(&self, dv: &[DVec2], h: f64, out: &mut State) {
        for (k, f) in self.held_forces(dv).into_iter().enumerate() {
            let j = f * h;
            out.held_impulse[k] += j;
            out.held_work += j.dot(self.held[k].velocity);
        }
    }

    /// Whether some constraint moves its region (does work).
    pub fn held_moves(&self) -> bool {
        self.held.iter().any(|c| c.velocity * c.mask != DVec2::ZERO)
    }

    /// The constraints of scene body `b`, whose particles are `range`,
    /// placed at `x`.
    pub(super) fn add_held(&mut self, b: &crate::scene::Body, range: Range<usize>, x: &[DVec2]) {
        use crate::scene::Axis;
        for (k, c) in b.constraints.iter().enumerate() {
            let free = |a: Axis| c.free.contains(&a);
            let v = c.velocity.clone().unwrap_or_default();
            let held = Held {
                name: crate::scene::validate::constraint_name(b, k, c),
                mask: DVec2::new(
                    if free(Axis::X) { 0.0 } else { 1.0 },
                    if self.dim < 2 || free(Axis::Y) {
                        0.0
                    } else {
                        1.0
                    },
                ),
                velocity: DVec2::new(
                    v.first().copied().unwrap_or(0.0),
                    v.get(1).copied().unwrap_or(0.0),
                ),
                particles: range.clone().filter(|&i| c.region.contains(x[i])).collect(),
            };
            self.held.push(held);
        }
    }

    /// After the last body: each particle's constraint, and the held
    /// components of the initial velocities at the regions'.
    pub(super) fn finish_held(&mut self, state: &mut State) {
        if self.held.is_empty() {
            return;
        }
        self.held_of = vec![0; self.len()];
        for (k, c) in self.held.iter().enumerate() {
            for &i in &c.particles {
                self.held_of[i] = k as u32 + 1;
                state.v[i] = c.hold(state.v[i]);
            }
        }
        state.held_impulse = vec![DVec2::ZERO; self.held.len()];
    }
}
