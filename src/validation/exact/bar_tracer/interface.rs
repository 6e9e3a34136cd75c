//! The tracer's interface between the bars: whether the faces touch, the
//! gap while they do not, the stress steps while they do, and the outcome
//! once it is final.

use super::*;

/// The tracer's tolerances: on velocities and on the gap.
pub(super) struct Tolerances {
    pub(super) v: f64,
    pub(super) gap: f64,
}

/// The interface's bookkeeping: whether the faces touch, the gap while
/// they do not, the stress steps while they do, and the outcome once it is
/// final.
pub(super) struct Interface {
    /// Each bar's impedance, initial velocity, mass and period `2L/c`.
    pub(super) z: [f64; 2],
    pub(super) v0: [f64; 2],
    pub(super) masses: [f64; 2],
    pub(super) periods: [f64; 2],
    pub(super) tol: Tolerances,
    pub(super) in_contact: bool,
    pub(super) gap: f64,
    pub(super) t_gap: f64,
    pub(super) sigma_i: f64,
    pub(super) t_sigma: f64,
    /// `∫ σ_I dt` over finished contact steps.
    pub(super) impulse: f64,
    pub(super) steps: Vec<StressStep>,
    pub(super) first_contact: Option<(f64, f64)>,
    pub(super) first_sep: Option<f64>,
    pub(super) last_sep: f64,
    pub(super) sep_start: f64,
    pub(super) bmax: [f64; 2],
    pub(super) resolved: Option<BarImpact>,
}

impl Interface {
    /// The bars' mean velocities after the impulse so far.
    pub(super) fn mean_velocities(&self) -> [f64; 2] {
        [
            self.v0[0] + self.impulse / self.masses[0],
            self.v0[1] - self.impulse / self.masses[1],
        ]
    }

    /// The interface's event at `t`: the fronts arriving at the faces
    /// (within `window`) or the gap closing (`pending_close`), answered by
    /// a contact or by free faces.
    pub(super) fn event(&mut self, sim: &mut BarSim, t: f64, window: f64, pending_close: bool) {
        let [z1, z2] = self.z;
        let gap_tol = self.tol.gap;
        // Interface faces: bar 1 right end, bar 2 left end.
        let vf_before = [sim.ends[0][RIGHT_END].v, sim.ends[1][LEFT_END].v];
        let a1 = sim.absorb(0, RIGHT_GOING, window);
        let a2 = sim.absorb(1, LEFT_GOING, window);
        if a1 || a2 || pending_close {
            if !self.in_contact {
                self.gap += (vf_before[1] - vf_before[0]) * (t - self.t_gap);
                self.t_gap = t;
                if pending_close {
                    self.gap = 0.0;
                }
            }
            let f1 = sim.ends[0][RIGHT_END];
            let f2 = sim.ends[1][LEFT_END];
            let j1 = f1.sig - z1 * f1.v;
            let j2 = f2.sig + z2 * f2.v;
            let sig_star = (z2 * j1 + z1 * j2) / (z1 + z2);
            let v_star = (j2 - j1) / (z1 + z2);
            let touching = self.in_contact || self.gap <= gap_tol;
            // A contact that would carry no (or tensile) stress is open: the
            // faces then move apart or, at most, together without load.
            let contact = self.resolved.is_none() && touching && sig_star < -sim.prune;
            if contact {
                sim.emit(0, LEFT_GOING, t, sig_star - f1.sig);
                sim.emit(1, RIGHT_GOING, t, sig_star - f2.sig);
                self.gap = 0.0;
                if self.first_contact.is_none() {
                    self.first_contact = Some((sig_star, v_star));
                }
                if !self.in_contact {
                    self.sigma_i = sig_star;
                    self.t_sigma = t;
                } else if (sig_star - self.sigma_i).abs() > sim.prune {
                    self.impulse += self.sigma_i * (t - self.t_sigma);
                    self.steps.push(StressStep {
                        t_start: self.t_sigma,
                        t_end: t,
                        stress: self.sigma_i,
                    });
                    self.sigma_i = sig_star;
                    self.t_sigma = t;
                }
            } else {
                sim.emit(0, LEFT_GOING, t, -f1.sig);
                sim.emit(1, RIGHT_GOING, t, -f2.sig);
                if self.in_contact {
                    self.impulse += self.sigma_i * (t - self.t_sigma);
                    self.steps.push(StressStep {
                        t_start: self.t_sigma,
                        t_end: t,
                        stress: self.sigma_i,
                    });
                    self.sigma_i = 0.0;
                    self.first_sep.get_or_insert(t);
                    self.last_sep = t;
                    self.sep_start = t;
                    self.gap = self.gap.max(0.0);
                    self.t_gap = t;
                    self.bmax = [0.0; 2];
                }
                let vm = self.mean_velocities();
                let vf = [sim.ends[0][RIGHT_END].v, sim.ends[1][LEFT_END].v];
                for b in 0..2 {
                    self.bmax[b] = self.bmax[b].max((vf[b] - vm[b]).abs());
                }
            }
            self.in_contact = contact;
        }
    }

    /// When the gap closes, while the faces are apart and closing and the
    /// outcome is open (infinite otherwise).
    pub(super) fn closes_at(&self, sim: &BarSim) -> f64 {
        let vf = [sim.ends[0][RIGHT_END].v, sim.ends[1][LEFT_END].v];
        if !self.in_contact && self.resolved.is_none() && vf[0] - vf[1] > self.tol.v {
            self.t_gap + self.gap.max(0.0) / (vf[0] - vf[1])
        } else {
            f64::INFINITY
        }
    }

    /// Whether the outcome is final, checked on the state that holds on
    /// `[t_now, t_next)`; `None` where no contact ever happened.
    pub(super) fn resolve(&mut self, sim: &BarSim, t_now: f64, t_next: f64) -> Option<()> {
        let v_tol = self.tol.v;
        let vf = [sim.ends[0][RIGHT_END].v, sim.ends[1][LEFT_END].v];
        if self.resolved.is_none() && !self.in_contact {
            let vm = self.mean_velocities();
            let mut done = vm[1] >= vm[0] - v_tol;
            if done && !(sim.quiet(0) && sim.quiet(1)) {
                let t_check = if t_next.is_finite() { t_next } else { t_now };
                let gap_t = self.gap + (vf[1] - vf[0]) * (t_check - self.t_gap);
                let mut excursion = 0.0;
                for b in 0..2 {
                    if sim.quiet(b) {
                        continue;
                    }
                    if t_check - self.sep_start < self.periods[b] {
                        done = false;
                    }
                    excursion += self.bmax[b] * self.periods[b];
                }
                done = done && gap_t > excursion;
            }
            if done {
                let (contact_stress, interface_velocity) = self.first_contact?;
                self.resolved = Some(BarImpact {
                    contact_stress,
                    interface_velocity,
                    separation_time: self.last_sep,
                    final_velocity_1: vm[0],
                    final_velocity_2: vm[1],
                });
            }
        }
        Some(())
    }
}
