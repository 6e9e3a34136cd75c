//! Exact answers of the paper's validation cases (METHOD.md §10), computed
//! from the material constants so that tests and validation figures compare
//! against computed, not hard-coded, values.
//!
//! * 1-D elastic bar impact (cases 1 and 2): linear acoustics in uniaxial
//!   strain, waves at `c_L` (METHOD.md §6: "1-D is uniaxial strain … waves
//!   therefore travel at `c_L`, not `c0`"), impedance `Z = ρ0 c_L`. Solved
//!   exactly by tracing the piecewise-constant wave fronts ([`bar_impact`],
//!   [`bar_impact_history`]); the equal-bar point history also in closed form
//!   ([`equal_bars_point_velocity`]).
//! * 1-D elastic–perfectly-plastic rod striking a rigid wall: the elastic
//!   precursor at the Hugoniot elastic limit and the plastic wave behind it,
//!   Rankine–Hugoniot jumps with the material's own EOS ([`rod_on_wall`]).
//! * 2-D quasi-static Hertz line contact of two identical disks in plane
//!   strain (case 3), with the two published choices of the approach constant
//!   `C` that bracket the dynamic answer ([`hertz_disks`]).
//!
//! Conventions (METHOD.md §2): SI units, stress tension positive, so contact
//! stresses are negative.

use crate::physics::material::MaterialModel;
use std::collections::VecDeque;
use std::f64::consts::{FRAC_PI_2, LN_2, PI};

// ---------------------------------------------------------------------------
// 1-D elastic bar impact (METHOD.md §10, cases 1 and 2)
// ---------------------------------------------------------------------------

/// Summary of a 1-D impact of two elastic bars (METHOD.md §10, cases 1–2).
///
/// Bar 1 is on the left moving at `v1`, bar 2 on the right moving at `v2`,
/// `v1 > v2`; first contact at `t = 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BarImpact {
    /// Interface stress right after first contact, Pa, tension positive (so
    /// negative): `−Z1 Z2 (v1 − v2)/(Z1 + Z2)`. When impedances and lengths
    /// differ the interface stress may later step to other levels; see
    /// [`BarImpactHistory::contact_steps`].
    pub contact_stress: f64,
    /// Interface particle velocity right after first contact, m/s:
    /// `(Z1 v1 + Z2 v2)/(Z1 + Z2)` (impedance matching).
    pub interface_velocity: f64,
    /// Time of the final separation of the contact faces, s (the end of the
    /// last contact interval; for the paper's cases there is only one).
    pub separation_time: f64,
    /// Mean (momentum) velocity of bar 1 after the final separation, m/s.
    pub final_velocity_1: f64,
    /// Mean (momentum) velocity of bar 2 after the final separation, m/s.
    pub final_velocity_2: f64,
}

impl BarImpact {
    fn nan() -> Self {
        Self {
            contact_stress: f64::NAN,
            interface_velocity: f64::NAN,
            separation_time: f64::NAN,
            final_velocity_1: f64::NAN,
            final_velocity_2: f64::NAN,
        }
    }
}

/// Which bar of a [`BarImpactHistory`]: `One` is the left bar (initial
/// velocity `v1`), `Two` the right bar (`v2`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BarId {
    One,
    Two,
}

impl BarId {
    fn index(self) -> usize {
        match self {
            BarId::One => 0,
            BarId::Two => 1,
        }
    }
}

/// One level of the piecewise-constant interface stress while the bars are in
/// contact: `stress` (Pa, ≤ 0) on `[t_start, t_end)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StressStep {
    pub t_start: f64,
    pub t_end: f64,
    pub stress: f64,
}

/// A wave front, emitted at one end of a bar at `t_emit`, carrying the stress
/// jump `dsig` (state behind minus state ahead). Its velocity jump follows
/// from the characteristic relations: right-going `dv = −dσ/Z`, left-going
/// `dv = +dσ/Z`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Front {
    t_emit: f64,
    dsig: f64,
}

/// Stress and velocity at one end of a bar.
#[derive(Debug, Clone, Copy, PartialEq)]
struct EndState {
    sig: f64,
    v: f64,
}

/// Direction index: right-going fronts are emitted at the left end and arrive
/// at the right end; left-going ones the reverse.
const RIGHT_GOING: usize = 0;
const LEFT_GOING: usize = 1;
/// End index.
const LEFT_END: usize = 0;
const RIGHT_END: usize = 1;

/// Fronts arriving within this fraction of the shortest transit time `L/c`
/// are treated as simultaneous (e.g. the two release waves of equal bars).
const TIME_TOL: f64 = 1e-9;
/// Stress jumps below this fraction of the first contact stress are dropped.
const PRUNE_TOL: f64 = 1e-12;
/// Safety cap on processed events; exceeding it reports "unresolved" (None)
/// instead of a possibly wrong answer.
const MAX_EVENTS: usize = 400_000;

/// Constants and the complete front log of one bar.
#[derive(Debug, Clone, PartialEq)]
struct BarTrace {
    len: f64,
    c: f64,
    z: f64,
    rho0: f64,
    v0: f64,
    /// Every front ever emitted, `[RIGHT_GOING]` and `[LEFT_GOING]`, in
    /// emission order.
    log: [Vec<Front>; 2],
}

impl BarTrace {
    fn transit(&self) -> f64 {
        self.len / self.c
    }

    /// State `(σ, v)` at local coordinate `x ∈ [0, L]` (0 = left end) and
    /// time `t ≥ 0`: the initial state plus every front that has passed `x`
    /// by `t` (a front is included from the instant it passes).
    fn state(&self, x: f64, t: f64) -> (f64, f64) {
        let mut sig = 0.0;
        let mut v = self.v0;
        let dt_right = x / self.c;
        for f in &self.log[RIGHT_GOING] {
            if f.t_emit + dt_right > t {
                break;
            }
            sig += f.dsig;
            v -= f.dsig / self.z;
        }
        let dt_left = (self.len - x) / self.c;
        for f in &self.log[LEFT_GOING] {
            if f.t_emit + dt_left > t {
                break;
            }
            sig += f.dsig;
            v += f.dsig / self.z;
        }
        (sig, v)
    }
}

/// Full exact history of a 1-D two-bar impact (METHOD.md §10, cases 1–2).
///
/// Local geometry: bar 1 occupies `[−L1, 0]`, bar 2 `[0, L2]` (Lagrangian,
/// small strain), contact face at `x = 0`, first contact at `t = 0`.
#[derive(Debug, Clone, PartialEq)]
pub struct BarImpactHistory {
    /// The summary (same as [`bar_impact`]).
    pub result: BarImpact,
    /// End of the first contact interval, s.
    pub first_separation_time: f64,
    /// Interface stress while in contact, piecewise constant, in time order;
    /// gaps between steps are intervals without contact.
    pub contact_steps: Vec<StressStep>,
    /// The history is exact for `0 ≤ t ≤ valid_until` (infinite when nothing
    /// changes any more).
    pub valid_until: f64,
    bars: [BarTrace; 2],
}

impl BarImpactHistory {
    /// Local coordinate (from the bar's left end) of the point at distance
    /// `d` from the contact face, or None when `d` is outside `[0, L]`.
    fn local_x(&self, bar: BarId, d: f64) -> Option<(usize, f64)> {
        let b = bar.index();
        let len = self.bars[b].len;
        if !(0.0..=len).contains(&d) {
            return None;
        }
        Some(match bar {
            BarId::One => (b, len - d),
            BarId::Two => (b, d),
        })
    }

    fn point_state(&self, bar: BarId, d: f64, t: f64) -> Option<(f64, f64)> {
        if t.is_nan() || t > self.valid_until {
            return None;
        }
        let (b, x) = self.local_x(bar, d)?;
        Some(self.bars[b].state(x, t.max(0.0)))
    }

    /// Exact particle velocity, m/s, at distance `d` (m) from the contact
    /// face inside `bar`, at time `t` (s). Before contact (`t < 0`) the
    /// initial velocity. NaN when `d` is outside the bar or `t` beyond
    /// [`valid_until`](Self::valid_until).
    pub fn point_velocity(&self, bar: BarId, d: f64, t: f64) -> f64 {
        self.point_state(bar, d, t).map_or(f64::NAN, |s| s.1)
    }

    /// Exact axial stress `σ_xx`, Pa (tension positive), at distance `d` from
    /// the contact face inside `bar`, at time `t`; NaN as for
    /// [`point_velocity`](Self::point_velocity).
    pub fn point_stress(&self, bar: BarId, d: f64, t: f64) -> f64 {
        self.point_state(bar, d, t).map_or(f64::NAN, |s| s.0)
    }

    /// Interface (contact) stress at time `t`, Pa: the contact step that
    /// holds `t`, 0 outside contact.
    pub fn interface_stress(&self, t: f64) -> f64 {
        self.contact_steps
            .iter()
            .find(|s| t >= s.t_start && t < s.t_end)
            .map_or(0.0, |s| s.stress)
    }

    /// Mean (momentum) velocity of `bar` at time `t`: the initial velocity
    /// plus the interface impulse delivered up to `t` over the mass per unit
    /// area `ρ0 L`. Falls linearly from `v0` to its final value while the
    /// interface stress is constant (METHOD.md §10, case 1).
    pub fn mean_velocity(&self, bar: BarId, t: f64) -> f64 {
        let impulse: f64 = self
            .contact_steps
            .iter()
            .map(|s| s.stress * (t.min(s.t_end) - s.t_start).max(0.0))
            .sum();
        let tr = &self.bars[bar.index()];
        // The interface traction on bar 1 (outer normal +x) is +σ, on bar 2
        // (outer normal −x) it is −σ.
        let sign = match bar {
            BarId::One => 1.0,
            BarId::Two => -1.0,
        };
        tr.v0 + sign * impulse / (tr.rho0 * tr.len)
    }
}

/// Event-driven wave tracer on piecewise-constant states (method of
/// characteristics for linear acoustics). Fronts are only ever emitted at bar
/// ends and cross the full bar, so each (bar, direction) queue is FIFO.
struct BarSim {
    bars: [BarTrace; 2],
    /// `[bar][LEFT_END | RIGHT_END]`.
    ends: [[EndState; 2]; 2],
    /// Fronts in flight, `[bar][RIGHT_GOING | LEFT_GOING]`.
    flight: [[VecDeque<Front>; 2]; 2],
    prune: f64,
}

impl BarSim {
    fn arrival(&self, b: usize, dir: usize) -> f64 {
        self.flight[b][dir]
            .front()
            .map_or(f64::INFINITY, |f| f.t_emit + self.bars[b].transit())
    }

    fn quiet(&self, b: usize) -> bool {
        self.flight[b][RIGHT_GOING].is_empty() && self.flight[b][LEFT_GOING].is_empty()
    }

    /// Emit a front from the end it starts at; the jump changes that end's
    /// state at once.
    fn emit(&mut self, b: usize, dir: usize, t: f64, dsig: f64) {
        if dsig.is_nan() || dsig.abs() <= self.prune {
            return;
        }
        let z = self.bars[b].z;
        match dir {
            RIGHT_GOING => {
                let e = &mut self.ends[b][LEFT_END];
                e.sig += dsig;
                e.v -= dsig / z;
            }
            _ => {
                let e = &mut self.ends[b][RIGHT_END];
                e.sig += dsig;
                e.v += dsig / z;
            }
        }
        let f = Front { t_emit: t, dsig };
        match self.flight[b][dir].back_mut() {
            Some(last) if last.t_emit == t => last.dsig += dsig,
            _ => self.flight[b][dir].push_back(f),
        }
        let log = &mut self.bars[b].log[dir];
        match log.last_mut() {
            Some(last) if last.t_emit == t => last.dsig += dsig,
            _ => log.push(f),
        }
    }

    /// Absorb every front of (b, dir) arriving by `t_window` into the end
    /// state it arrives at; true if any arrived.
    fn absorb(&mut self, b: usize, dir: usize, t_window: f64) -> bool {
        let mut any = false;
        while self.arrival(b, dir) <= t_window {
            let Some(f) = self.flight[b][dir].pop_front() else {
                break;
            };
            any = true;
            let z = self.bars[b].z;
            if dir == RIGHT_GOING {
                let e = &mut self.ends[b][RIGHT_END];
                e.sig += f.dsig;
                e.v -= f.dsig / z;
            } else {
                let e = &mut self.ends[b][LEFT_END];
                e.sig += f.dsig;
                e.v += f.dsig / z;
            }
        }
        any
    }

    /// Free end: reflect so that the end is stress-free (the reflected front
    /// has the opposite stress jump, the same velocity jump).
    fn free_end(&mut self, b: usize, end: usize, t: f64) {
        let sig = self.ends[b][end].sig;
        let dir = if end == LEFT_END {
            RIGHT_GOING
        } else {
            LEFT_GOING
        };
        self.emit(b, dir, t, -sig);
    }
}

/// Exact summary of the 1-D impact of two elastic bars (METHOD.md §10, cases
/// 1–2): bar 1 (material `m1`, length `l1`, velocity `v1`) on the left, bar 2
/// (`m2`, `l2`, `v2`) on the right, `v1 > v2`, uniaxial strain, waves at
/// `c_L`, impedances `Z = ρ0 c_L`.
///
/// Returns all-NaN fields for input that is not an impact of two physical
/// bars (`v1 ≤ v2`, non-positive or non-finite lengths, densities or
/// impedances) or, in principle, a configuration the tracer could not resolve
/// within its event cap; use [`try_bar_impact`] to get `None` instead.
pub fn bar_impact(
    m1: &MaterialModel,
    l1: f64,
    v1: f64,
    m2: &MaterialModel,
    l2: f64,
    v2: f64,
) -> BarImpact {
    try_bar_impact(m1, l1, v1, m2, l2, v2).unwrap_or_else(BarImpact::nan)
}

/// [`bar_impact`], with `None` for invalid or unresolved input.
pub fn try_bar_impact(
    m1: &MaterialModel,
    l1: f64,
    v1: f64,
    m2: &MaterialModel,
    l2: f64,
    v2: f64,
) -> Option<BarImpact> {
    bar_impact_history(m1, l1, v1, m2, l2, v2, 0.0).map(|h| h.result)
}

/// Exact wave history of the 1-D two-bar impact (METHOD.md §10, cases 1–2),
/// traced at least until `t_end` (s) and at least until the outcome is final.
///
/// Method (why it is exact): in linear acoustics with piecewise-constant
/// initial data the state stays piecewise constant between fronts moving at
/// `±c_L`. Across a right-going front `Δσ = −Z Δv`, across a left-going one
/// `Δσ = +Z Δv`. A free end reflects a front with the opposite stress jump.
/// At the interface the incoming characteristic invariants are
/// `J1 = σ − Z1 v` (bar 1 side) and `J2 = σ + Z2 v` (bar 2 side); in contact
/// both faces share `v* = (J2 − J1)/(Z1 + Z2)` and
/// `σ* = (Z2 J1 + Z1 J2)/(Z1 + Z2)`. The faces are in contact while the gap
/// is closed and `σ* < 0`; when `σ*` would be zero or tensile they separate
/// and each face becomes free (this is exactly when the first release wave
/// returning from a free end unloads the interface, e.g. `2L/c` for equal
/// bars). A
/// separated pair is traced on (with possible re-contact when the gap closes)
/// until re-contact is provably impossible: mean velocities no longer
/// approaching and the gap larger than the largest possible vibration
/// excursion of the free faces (face velocity is periodic with period
/// `2L/c` and averages to the mean velocity). Final mean velocities follow
/// from momentum: the time integral of the interface stress over the contact
/// steps divided by the mass per unit area `ρ0 L`.
///
/// `t_end` should be finite: bars that keep vibrating after separation
/// generate events for ever, so an infinite `t_end` then hits the event cap.
/// The front log grows with `t_end` (a few fronts per `L/c`).
///
/// `None` for invalid input (see [`bar_impact`]) or if the event cap is hit.
pub fn bar_impact_history(
    m1: &MaterialModel,
    l1: f64,
    v1: f64,
    m2: &MaterialModel,
    l2: f64,
    v2: f64,
    t_end: f64,
) -> Option<BarImpactHistory> {
    let pos = |x: f64| x.is_finite() && x > 0.0;
    let valid = pos(l1)
        && pos(l2)
        && pos(m1.rho0)
        && pos(m2.rho0)
        && pos(m1.c_l)
        && pos(m2.c_l)
        && pos(m1.z)
        && pos(m2.z)
        && v1.is_finite()
        && v2.is_finite()
        && v1 > v2
        && !t_end.is_nan();
    if !valid {
        return None;
    }
    let trace = |m: &MaterialModel, len: f64, v0: f64| BarTrace {
        len,
        c: m.c_l,
        z: m.z,
        rho0: m.rho0,
        v0,
        log: [Vec::new(), Vec::new()],
    };
    let (z1, z2) = (m1.z, m2.z);
    let sigma_scale = z1 * z2 * (v1 - v2) / (z1 + z2);
    let mut sim = BarSim {
        bars: [trace(m1, l1, v1), trace(m2, l2, v2)],
        ends: [
            [EndState { sig: 0.0, v: v1 }; 2],
            [EndState { sig: 0.0, v: v2 }; 2],
        ],
        flight: Default::default(),
        prune: PRUNE_TOL * sigma_scale,
    };
    let t_tol = TIME_TOL * sim.bars[0].transit().min(sim.bars[1].transit());
    let v_scale = v1.abs() + v2.abs() + (v1 - v2);
    let v_tol = 1e-12 * v_scale;
    let gap_tol = 4.0 * v_scale * t_tol;
    let periods = [2.0 * sim.bars[0].transit(), 2.0 * sim.bars[1].transit()];
    let masses = [m1.rho0 * l1, m2.rho0 * l2];

    // Interface bookkeeping.
    let mut in_contact = false;
    let mut gap = 0.0_f64;
    let mut t_gap = 0.0_f64;
    let mut sigma_i = 0.0_f64;
    let mut t_sigma = 0.0_f64;
    let mut impulse = 0.0_f64; // ∫ σ_I dt over finished contact steps
    let mut steps: Vec<StressStep> = Vec::new();
    let mut first_contact: Option<(f64, f64)> = None;
    let mut first_sep: Option<f64> = None;
    let mut last_sep = 0.0_f64;
    let mut sep_start = 0.0_f64;
    let mut bmax = [0.0_f64; 2];
    let mut resolved: Option<BarImpact> = None;

    let mean_vel = |impulse: f64| [v1 + impulse / masses[0], v2 - impulse / masses[1]];

    let mut t_now;
    let mut events = 0usize;
    // First contact is an interface event at t = 0 with the gap closed.
    let mut pending_close = true;
    let mut t = 0.0_f64;
    loop {
        if events > MAX_EVENTS {
            return None;
        }
        events += 1;
        let window = t + t_tol;

        // Free ends: bar 1 left, bar 2 right.
        if sim.absorb(0, LEFT_GOING, window) {
            sim.free_end(0, LEFT_END, t);
        }
        if sim.absorb(1, RIGHT_GOING, window) {
            sim.free_end(1, RIGHT_END, t);
        }

        // Interface faces: bar 1 right end, bar 2 left end.
        let vf_before = [sim.ends[0][RIGHT_END].v, sim.ends[1][LEFT_END].v];
        let a1 = sim.absorb(0, RIGHT_GOING, window);
        let a2 = sim.absorb(1, LEFT_GOING, window);
        if a1 || a2 || pending_close {
            if !in_contact {
                gap += (vf_before[1] - vf_before[0]) * (t - t_gap);
                t_gap = t;
                if pending_close {
                    gap = 0.0;
                }
            }
            let f1 = sim.ends[0][RIGHT_END];
            let f2 = sim.ends[1][LEFT_END];
            let j1 = f1.sig - z1 * f1.v;
            let j2 = f2.sig + z2 * f2.v;
            let sig_star = (z2 * j1 + z1 * j2) / (z1 + z2);
            let v_star = (j2 - j1) / (z1 + z2);
            let touching = in_contact || gap <= gap_tol;
            // A contact that would carry no (or tensile) stress is open: the
            // faces then move apart or, at most, together without load.
            let contact = resolved.is_none() && touching && sig_star < -sim.prune;
            if contact {
                sim.emit(0, LEFT_GOING, t, sig_star - f1.sig);
                sim.emit(1, RIGHT_GOING, t, sig_star - f2.sig);
                gap = 0.0;
                if first_contact.is_none() {
                    first_contact = Some((sig_star, v_star));
                }
                if !in_contact {
                    sigma_i = sig_star;
                    t_sigma = t;
                } else if (sig_star - sigma_i).abs() > sim.prune {
                    impulse += sigma_i * (t - t_sigma);
                    steps.push(StressStep {
                        t_start: t_sigma,
                        t_end: t,
                        stress: sigma_i,
                    });
                    sigma_i = sig_star;
                    t_sigma = t;
                }
            } else {
                sim.emit(0, LEFT_GOING, t, -f1.sig);
                sim.emit(1, RIGHT_GOING, t, -f2.sig);
                if in_contact {
                    impulse += sigma_i * (t - t_sigma);
                    steps.push(StressStep {
                        t_start: t_sigma,
                        t_end: t,
                        stress: sigma_i,
                    });
                    sigma_i = 0.0;
                    first_sep.get_or_insert(t);
                    last_sep = t;
                    sep_start = t;
                    gap = gap.max(0.0);
                    t_gap = t;
                    bmax = [0.0; 2];
                }
                let vm = mean_vel(impulse);
                let vf = [sim.ends[0][RIGHT_END].v, sim.ends[1][LEFT_END].v];
                for b in 0..2 {
                    bmax[b] = bmax[b].max((vf[b] - vm[b]).abs());
                }
            }
            in_contact = contact;
        }
        t_now = t;

        // Next event: a front arrival or, while separated and closing, the
        // gap reaching zero.
        let mut t_next = f64::INFINITY;
        for b in 0..2 {
            for dir in 0..2 {
                t_next = t_next.min(sim.arrival(b, dir));
            }
        }
        let vf = [sim.ends[0][RIGHT_END].v, sim.ends[1][LEFT_END].v];
        let mut t_close = f64::INFINITY;
        if !in_contact && resolved.is_none() && vf[0] - vf[1] > v_tol {
            t_close = t_gap + gap.max(0.0) / (vf[0] - vf[1]);
        }
        let closing = t_close <= t_next;
        t_next = t_next.min(t_close);

        // Is the outcome final? Checked on the state that holds on
        // [t_now, t_next).
        if resolved.is_none() && !in_contact {
            let vm = mean_vel(impulse);
            let mut done = vm[1] >= vm[0] - v_tol;
            if done && !(sim.quiet(0) && sim.quiet(1)) {
                let t_check = if t_next.is_finite() { t_next } else { t_now };
                let gap_t = gap + (vf[1] - vf[0]) * (t_check - t_gap);
                let mut excursion = 0.0;
                for b in 0..2 {
                    if sim.quiet(b) {
                        continue;
                    }
                    if t_check - sep_start < periods[b] {
                        done = false;
                    }
                    excursion += bmax[b] * periods[b];
                }
                done = done && gap_t > excursion;
            }
            if done {
                let (contact_stress, interface_velocity) = first_contact?;
                resolved = Some(BarImpact {
                    contact_stress,
                    interface_velocity,
                    separation_time: last_sep,
                    final_velocity_1: vm[0],
                    final_velocity_2: vm[1],
                });
            }
        }

        if resolved.is_some() && (t_next > t_end || t_next.is_infinite()) {
            let valid_until = if t_next.is_finite() {
                t_end.max(t_now)
            } else {
                f64::INFINITY
            };
            let result = resolved?;
            let [b1, b2] = sim.bars;
            return Some(BarImpactHistory {
                result,
                first_separation_time: first_sep.unwrap_or(last_sep),
                contact_steps: steps,
                valid_until,
                bars: [b1, b2],
            });
        }
        if !t_next.is_finite() {
            // Nothing will ever happen again, yet not resolved: cannot occur
            // for valid input, but never loop forever.
            return None;
        }
        pending_close = closing;
        t = t_next;
    }
}

/// Exact particle velocity in case 1 of METHOD.md §10 (two equal bars, each
/// of length `l`, wave speed `c`, impacting at `±v0`): bar 1 occupies
/// `[−l, 0]` and moves at `+v0` (to the right, towards the contact face at
/// `x = 0`); the point is at distance `d ∈ [0, l]` from the contact face;
/// `t` is measured from first contact.
///
/// `+v0` until the compressive front arrives at `d/c`, 0 in the compressed
/// state until the release reflected from the free end arrives at
/// `(2l − d)/c`, then `−v0` for ever (the bars separate stress-free at
/// `2l/c`). Values switch at the arrival instants. The point of bar 2 at the
/// same distance moves with the opposite sign. NaN for `d` outside `[0, l]`.
pub fn equal_bars_point_velocity(c: f64, l: f64, v0: f64, d: f64, t: f64) -> f64 {
    if !(0.0..=l).contains(&d) {
        return f64::NAN;
    }
    if t < d / c {
        v0
    } else if t < (2.0 * l - d) / c {
        0.0
    } else {
        -v0
    }
}

// ---------------------------------------------------------------------------
// 2-D quasi-static Hertz line contact of two identical disks (METHOD.md §10,
// case 3)
// ---------------------------------------------------------------------------

/// Approach constant `C` of Johnson (1985) for a disk in diametral
/// compression (METHOD.md §10, case 3): the softer end of the bracket.
pub const HERTZ_C_JOHNSON: f64 = 1.0;

/// Approach constant `C = 1 + 2 ln 2 − (3 − 4ν)/(4(1 − ν))` for a free disk
/// loaded at the contact and held by its own inertia (METHOD.md §10, case 3):
/// the stiffer end of the bracket, ≈ 1.742 for steel.
pub fn hertz_c_inertia(nu: f64) -> f64 {
    1.0 + 2.0 * LN_2 - (3.0 - 4.0 * nu) / (4.0 * (1.0 - nu))
}

/// Plane-strain modulus `E' = E/(1 − ν²)` (METHOD.md §10, case 3).
pub fn plane_strain_modulus(mat: &MaterialModel) -> f64 {
    mat.e / (1.0 - mat.nu * mat.nu)
}

/// Contact half-width `a = sqrt(4 P R/(π E'))` of two identical disks of
/// radius `radius` pressed with force `force` per unit thickness (N/m).
pub fn hertz_half_width(mat: &MaterialModel, radius: f64, force: f64) -> f64 {
    (4.0 * force.max(0.0) * radius / (PI * plane_strain_modulus(mat))).sqrt()
}

/// Result of the quasi-static Hertz impact of two identical disks (METHOD.md
/// §10, case 3), per unit thickness.
#[derive(Debug, Clone, PartialEq)]
pub struct HertzImpact {
    /// Peak contact force per unit thickness, N/m.
    pub peak_force: f64,
    /// Contact duration, s.
    pub contact_time: f64,
    /// Peak approach of the two centres `δ = 2 δ1`, m.
    pub max_approach: f64,
    /// Force history `(t, P)` over the contact (s, N/m), from `(0, 0)` to
    /// `(contact_time, 0)`, symmetric about the peak (elastic, so unloading
    /// retraces loading); denser near the start and end of contact.
    pub curve: Vec<(f64, f64)>,
}

impl HertzImpact {
    /// Contact force at time `t` by linear interpolation of
    /// [`curve`](Self::curve) (relative error ~1e-5 near the peak); 0
    /// outside the contact.
    pub fn force_at(&self, t: f64) -> f64 {
        let c = &self.curve;
        if c.len() < 2 || !(t > c[0].0 && t < c[c.len() - 1].0) {
            return 0.0;
        }
        let i = c.partition_point(|p| p.0 <= t).clamp(1, c.len() - 1);
        let (t0, p0) = c[i - 1];
        let (t1, p1) = c[i];
        if t1 > t0 {
            p0 + (p1 - p0) * (t - t0) / (t1 - t0)
        } else {
            p1
        }
    }
}

/// The line-contact law of two identical disks, in the dimensionless force
/// `p = P/(π E' R)`: `a/R = 2 sqrt(p)`, hence `ln(4R/a) = ln 2 − ½ ln p` and
/// the approach of the centres `δ = 2 δ1 = 2 R p (A − ln p)` with
/// `A = 2 ln 2 − C`. Monotone for `p < exp(A − 1)` (far beyond any elastic
/// load), which bounds the valid range.
#[derive(Debug, Clone, Copy)]
struct HertzLine {
    e_prime: f64,
    radius: f64,
    a: f64,
}

impl HertzLine {
    fn new(mat: &MaterialModel, radius: f64, c: f64) -> Option<Self> {
        let e_prime = plane_strain_modulus(mat);
        let ok = e_prime.is_finite()
            && e_prime > 0.0
            && radius.is_finite()
            && radius > 0.0
            && c.is_finite();
        ok.then_some(Self {
            e_prime,
            radius,
            a: 2.0 * LN_2 - c,
        })
    }

    fn force_scale(&self) -> f64 {
        PI * self.e_prime * self.radius
    }

    /// `δ(p)`, m.
    fn approach_of_p(&self, p: f64) -> f64 {
        if p > 0.0 {
            2.0 * self.radius * p * (self.a - p.ln())
        } else {
            0.0
        }
    }

    /// Inverse of [`approach_of_p`](Self::approach_of_p): solve
    /// `q + ln(A − q) = ln(δ/2R)` for `q = ln p` (the log form stays well
    /// conditioned as `p → 0`, where δ → 0 like `p ln(1/p)`).
    fn p_of_approach(&self, delta: f64) -> Option<f64> {
        if delta <= 0.0 {
            return Some(0.0);
        }
        solve_log_equation(1.0, self.a, (delta / (2.0 * self.radius)).ln()).map(f64::exp)
    }

    /// The dimensionless stored energy is `W(p) = p² (A − ½ − ln p)`, the
    /// exact integral `U = ∫ P dδ = π E' R² W(p)`; this inverts it by solving
    /// `2q + ln(A − ½ − q) = ln W` for `q = ln p`.
    fn p_of_w(&self, w: f64) -> Option<f64> {
        if w.is_nan() || w <= 0.0 {
            return None;
        }
        solve_log_equation(2.0, self.a - 0.5, w.ln()).map(f64::exp)
    }
}

/// Solve `k q + ln(β − q) = target` on the increasing branch
/// `q < q_max = β − 1/k` (safeguarded Newton). None when `target` is at or
/// above the branch maximum (no monotone solution: the load is beyond the
/// range of the line-contact law) or not finite.
fn solve_log_equation(k: f64, beta: f64, target: f64) -> Option<f64> {
    let q_max = beta - 1.0 / k;
    let h = |q: f64| k * q + (beta - q).ln();
    if !target.is_finite() || target >= h(q_max) {
        return None;
    }
    // Lower bracket: h(q) < target.
    let mut step = 1.0;
    let mut lo = (target / k).min(q_max) - step;
    let mut guard = 0;
    while h(lo) >= target {
        step *= 2.0;
        lo -= step;
        guard += 1;
        if guard > 200 {
            return None;
        }
    }
    let mut hi = q_max;
    // Fixed-point estimate as the start, clamped into the bracket.
    let mut q = ((target - (beta - lo).ln()) / k).clamp(lo, hi);
    for _ in 0..200 {
        let f = h(q) - target;
        if f < 0.0 {
            lo = q;
        } else {
            hi = q;
        }
        let d = k - 1.0 / (beta - q);
        let mut qn = q - f / d;
        if !(qn > lo && qn < hi) {
            qn = 0.5 * (lo + hi);
        }
        if (qn - q).abs() <= 1e-15 * (1.0 + q.abs()) || hi - lo <= 1e-15 * (1.0 + q.abs()) {
            return Some(qn);
        }
        q = qn;
    }
    Some(q)
}

/// Approach of the two centres `δ = 2 δ1` (m) of identical disks under the
/// contact force `force` (N/m), `δ1 = (P/(π E'))[2 ln(4R/a) − C]` (METHOD.md
/// §10, case 3). None outside the monotone range of the law or for invalid
/// input.
pub fn hertz_approach(mat: &MaterialModel, radius: f64, c: f64, force: f64) -> Option<f64> {
    let line = HertzLine::new(mat, radius, c)?;
    if force.is_nan() || force < 0.0 {
        return None;
    }
    let p = force / line.force_scale();
    (p < (line.a - 1.0).exp()).then(|| line.approach_of_p(p))
}

/// Contact force (N/m) of identical disks at centre approach `approach` (m):
/// the numerical inverse of [`hertz_approach`]; 0 for no overlap. None beyond
/// the monotone range of the law or for invalid input.
pub fn hertz_force(mat: &MaterialModel, radius: f64, c: f64, approach: f64) -> Option<f64> {
    let line = HertzLine::new(mat, radius, c)?;
    if approach.is_nan() {
        return None;
    }
    Some(line.p_of_approach(approach)? * line.force_scale())
}

/// Number of curve intervals on each half (loading, unloading).
const HERTZ_HALF_SAMPLES: usize = 400;

/// Quasi-static Hertz impact of two identical elastic disks in plane strain
/// (METHOD.md §10, case 3): radius `radius` (m), closing speed
/// `closing_speed` (m/s, i.e. each disk at half of it), approach constant `c`
/// ([`HERTZ_C_JOHNSON`] or [`hertz_c_inertia`]).
///
/// Model: `m* δ̈ = −P(δ)`, `δ(0) = 0`, `δ̇(0) = V`, `m* = ρ π R²/2`, with
/// `P(δ)` the inverse of `δ = 2 (P/(π E'))[2 ln(4R/a) − C]`. The peak follows
/// from energy, `½ m* V² = ∫0^δmax P dδ`, whose integral is closed-form in
/// `p = P/(πE'R)`; the contact time `2 ∫ dδ/δ̇` is integrated in
/// `p = p_max sin²φ`, which removes the inverse-square-root singularity at the
/// turning point (and the logarithmic one at `p → 0`), by tanh–sinh
/// quadrature to ~1e-12.
///
/// Returns NaN fields and an empty curve for invalid input (non-positive
/// radius, speed or density) or a load beyond the range of the law; see
/// [`try_hertz_disks`].
pub fn hertz_disks(mat: &MaterialModel, radius: f64, closing_speed: f64, c: f64) -> HertzImpact {
    try_hertz_disks(mat, radius, closing_speed, c).unwrap_or(HertzImpact {
        peak_force: f64::NAN,
        contact_time: f64::NAN,
        max_approach: f64::NAN,
        curve: Vec::new(),
    })
}

/// [`hertz_disks`], with `None` for invalid input.
pub fn try_hertz_disks(
    mat: &MaterialModel,
    radius: f64,
    closing_speed: f64,
    c: f64,
) -> Option<HertzImpact> {
    let line = HertzLine::new(mat, radius, c)?;
    let v = closing_speed;
    if !(v.is_finite() && v > 0.0 && mat.rho0.is_finite() && mat.rho0 > 0.0) {
        return None;
    }
    let m_star = 0.5 * mat.rho0 * PI * radius * radius;
    // ½ m* V² = π E' R² W(p_max).
    let w_max = m_star * v * v / (2.0 * line.force_scale() * radius);
    let p_max = line.p_of_w(w_max)?;
    let a = line.a;
    let b_minus_lnpm = a - 0.5 - p_max.ln();
    // dt/dφ = [4 R p_max sqrt(B − ln p_max)/V] · sinφ (A − 1 − ln p)/sqrt(Q),
    // Q = (W_max − W)/(p_max² cos²φ), written to stay accurate at both ends.
    let prefactor = 4.0 * radius * p_max * b_minus_lnpm.sqrt() / v;
    let integrand = |phi: f64| -> f64 {
        let sin = phi.sin();
        if sin <= 0.0 {
            return 0.0;
        }
        let s = sin * sin;
        let c2 = {
            let cos = (FRAC_PI_2 - phi).sin();
            cos * cos
        };
        let ln_s = 2.0 * sin.ln();
        // s² ln(s)/cos²φ, with ln(s) = ln(1 − cos²φ) near φ = π/2.
        let tail = if c2 <= 0.0 {
            -s * s
        } else if s < 0.5 {
            s * s * ln_s / c2
        } else {
            s * s * (-c2).ln_1p() / c2
        };
        let q = b_minus_lnpm * (1.0 + s) + tail;
        let ln_p = p_max.ln() + ln_s;
        prefactor * sin * (a - 1.0 - ln_p) / q.sqrt()
    };
    let n = HERTZ_HALF_SAMPLES;
    let mut half = Vec::with_capacity(n + 1);
    half.push((0.0, 0.0));
    let mut t_acc = 0.0;
    for i in 1..=n {
        let phi0 = FRAC_PI_2 * (i - 1) as f64 / n as f64;
        let phi1 = FRAC_PI_2 * i as f64 / n as f64;
        t_acc += tanh_sinh(&integrand, phi0, phi1, 1e-13);
        let sin = phi1.sin();
        half.push((t_acc, line.force_scale() * p_max * sin * sin));
    }
    let t_half = t_acc;
    let contact_time = 2.0 * t_half;
    let peak_force = line.force_scale() * p_max;
    if !(contact_time.is_finite() && contact_time > 0.0) {
        return None;
    }
    // Exact symmetry: the last point of the loading half is the peak.
    if let Some(last) = half.last_mut() {
        *last = (t_half, peak_force);
    }
    let mut curve = half.clone();
    curve.extend(
        half.iter()
            .rev()
            .skip(1)
            .map(|&(t, p)| (contact_time - t, p)),
    );
    if let Some(last) = curve.last_mut() {
        *last = (contact_time, 0.0);
    }
    Some(HertzImpact {
        peak_force,
        contact_time,
        max_approach: line.approach_of_p(p_max),
        curve,
    })
}

/// A single disk at speed `speed` on a rigid frictionless wall (METHOD.md
/// §8.5): the same force history as two identical disks at closing speed
/// `2 speed`; `max_approach` is then the approach of the disk centre to the
/// wall, `δ1 = δ/2`.
pub fn hertz_disk_on_wall(mat: &MaterialModel, radius: f64, speed: f64, c: f64) -> HertzImpact {
    let mut h = hertz_disks(mat, radius, 2.0 * speed, c);
    h.max_approach *= 0.5;
    h
}

// ---------------------------------------------------------------------------
// 1-D elastic–plastic rod on a rigid wall: elastic precursor and plastic wave
// ---------------------------------------------------------------------------

/// A uniform state of a rod in uniaxial strain (METHOD.md §6), behind one of
/// the waves of [`rod_on_wall`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodState {
    /// Axial stress `σ_xx`, Pa, tension positive (METHOD.md §2).
    pub stress: f64,
    /// Particle velocity towards the wall, m/s.
    pub velocity: f64,
    /// Density, kg/m³.
    pub density: f64,
    /// Specific internal energy, J/kg (all of it: the EOS's energy is the
    /// total work of the stress, deviatoric part included, as in the
    /// solver's energy equation, METHOD.md §4).
    pub energy: f64,
    /// Pressure `p(ρ, e)` of the material's EOS, Pa.
    pub pressure: f64,
}

/// The two-wave answer of an elastic–perfectly-plastic rod striking a rigid
/// wall ([`rod_on_wall`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoWaveImpact {
    /// Behind the elastic precursor: the Hugoniot elastic limit (HEL).
    pub hel: RodState,
    /// Lagrangian speed of the precursor (relative to the undeformed rod),
    /// m/s: it reaches the material at distance `D` from the struck end
    /// (measured at t = 0) at `D / elastic_speed`. Equals `c_L` to first
    /// order.
    pub elastic_speed: f64,
    /// Behind the plastic wave: at rest against the wall, deviator held at
    /// yield.
    pub plastic: RodState,
    /// Lagrangian speed of the plastic wave, m/s (the bulk speed
    /// `sqrt(K/ρ0)` to first order, more as the EOS stiffens).
    pub plastic_speed: f64,
}

/// The acoustic (small-strain) Hugoniot elastic limit in uniaxial strain,
/// `σ_HEL = (K + 4G/3) Y0/(2G)` (METHOD.md §6: the deviator reaches the von
/// Mises limit `|s_xx| = 2Y0/3` at the strain `Y0/(2G)`), Pa, as a positive
/// magnitude. ≈ 1.04 GPa for the steel of Table 1 with Y0 = 600 MPa.
pub fn acoustic_hel(mat: &MaterialModel) -> f64 {
    mat.m * mat.y0 / (2.0 * mat.g)
}

/// Stress and energy of the state at density `rho` reached from state `a`
/// (stress `sigma_a`, engineering strain `eps_a`, energy `e_a`) through a
/// single jump, with deviatoric stress `s_xx`: the Rankine–Hugoniot energy
/// jump `e − e_a = (σ + σ_a)(ε − ε_a)/(2ρ0)` together with
/// `σ = −p(ρ, e) + s_xx`. The EOS is linear in `e`
/// (`p = p(ρ, 0) + Γ0 ρ e`, METHOD.md §6), so the pair solves in closed form.
fn jump_state(
    mat: &MaterialModel,
    rho: f64,
    s_xx: f64,
    sigma_a: f64,
    eps_a: f64,
    e_a: f64,
) -> (f64, f64) {
    let eps = mat.rho0 / rho - 1.0;
    let w = (eps - eps_a) / (2.0 * mat.rho0);
    let g = mat.gamma0 * rho;
    let p0 = mat.pressure(rho, 0.0);
    let sigma = (-p0 - g * e_a - g * sigma_a * w + s_xx) / (1.0 + g * w);
    let e = e_a + (sigma + sigma_a) * w;
    (sigma, e)
}

/// Exact plane-wave answer of a 1-D elastic–plastic rod (uniaxial
/// strain, METHOD.md §6) striking a rigid wall (METHOD.md §8.5) at speed
/// `v0` > 0: a two-wave structure running from the wall into the rod.
///
/// * **Elastic precursor.** The rod is compressed elastically until the von
///   Mises stress reaches `Y0`. With the solver's hypoelastic law in 1-D,
///   `ṡ_xx = (4/3) G ε̇_xx` and `ε̇_xx = −ρ̇/ρ`, so
///   `s_xx = −(4/3) G ln(ρ/ρ0)`; yield (`J = (3/2)|s_xx| = Y0`) is at
///   `ρ_H = ρ0 exp(Y0/(2G))`. The HEL stress is `σ_H = −p(ρ_H, e_H) − 2Y0/3`
///   with the Rankine–Hugoniot energy from rest. Jump conditions in
///   Lagrangian form for a wave running away from the wall (speed `W`
///   relative to the undeformed rod, engineering strain `ε = ρ0/ρ − 1`,
///   Δ = behind − ahead): `Δσ = ρ0 W Δv` and `Δv = W Δε`, so
///   `W_e = sqrt(σ_H/(ρ0 ε_H))` and `v_H = v0 + W_e ε_H`. To first order
///   this is [`acoustic_hel`], `c_L` and `u_HEL = σ_HEL/(ρ0 c_L)` (≈ 22.7 m/s
///   for the steel of Table 1).
/// * **Plastic wave.** Behind it the rod is at rest against the wall and the
///   deviator stays at yield, `σ = −p(ρ, e) − 2Y0/3` (the radial return
///   holds `s_xx = −2Y0/3` while compression grows). With a Johnson–Cook
///   strength without rate term or heating (`C = 0`, Taylor–Quinney 0),
///   `Y0 = A` and the deviator behind is `−⅔ q(ρ)` with `q` the hardened
///   flow stress at the compression ρ: under monotonic uniaxial compression
///   `q + 3G ε_p = 2G ln(ρ/ρ0)` and `q = A + B ε_pⁿ`. The wave is still a
///   shock when this `σ(ε)` is convex (linear hardening with a linear EOS
///   is). From the HEL state the
///   jump conditions give `(σ_H − σ_F)(ε_H − ε_F) = ρ0 v_H²`, with `σ_F`
///   from the EOS and the energy jump (`jump_state`); this one equation in
///   `ε_F` is solved by bisection, then `W_p = v_H/(ε_H − ε_F)`. For a weak
///   plastic wave `W_p` tends to the bulk speed `sqrt(K/ρ0)` (divided by
///   `1 + ε_H`); the Mie–Grüneisen EOS stiffens with compression, so it is a
///   little faster.
///
/// `None` when there is no two-wave structure: an elastic material (no
/// yield stress or no shear modulus), a strength with a rate term or
/// heating, `v0` not above the HEL particle
/// velocity (the rod stays elastic), or a plastic wave at least as fast as
/// the precursor (an overdriven single shock).
pub fn rod_on_wall(mat: &MaterialModel, v0: f64) -> Option<TwoWaveImpact> {
    let (rho0, y0, g) = (mat.rho0, mat.y0, mat.g);
    if !(y0.is_finite() && y0 > 0.0 && g > 0.0 && v0.is_finite() && v0 > 0.0) {
        return None;
    }
    if let Some(jc) = &mat.strength {
        // The answer is exact for a strength that depends on the plastic
        // strain alone: no rate term, no heating.
        if jc.c != 0.0 || mat.taylor_quinney != 0.0 {
            return None;
        }
    }
    let s_yield = -2.0 * y0 / 3.0;
    // The deviator on the yield surface at density ρ: constant for perfect
    // plasticity; with hardening the return from the virgin state at the
    // equivalent strain ⅔ ln(ρ/ρ0), path-independent under monotonic
    // compression (docs/method.md, "Strength and failure").
    let deviator = |rho: f64| match &mat.strength {
        None => s_yield,
        Some(jc) => {
            let q_trial = 2.0 * g * (rho / rho0).ln();
            -2.0 / 3.0 * (q_trial - 3.0 * g * jc.return_increment(q_trial, g, 0.0, 1.0))
        }
    };

    // Elastic precursor from rest.
    let rho_h = rho0 * (y0 / (2.0 * g)).exp();
    let eps_h = rho0 / rho_h - 1.0;
    let (sig_h, e_h) = jump_state(mat, rho_h, s_yield, 0.0, 0.0, 0.0);
    let w_e = (sig_h / (rho0 * eps_h)).sqrt();
    let v_h = v0 + w_e * eps_h;
    if !(w_e.is_finite() && v_h > 0.0) {
        return None;
    }
    let hel = RodState {
        stress: sig_h,
        velocity: v_h,
        density: rho_h,
        energy: e_h,
        pressure: mat.pressure(rho_h, e_h),
    };

    // Plastic wave: bring the HEL state to rest.
    let target = rho0 * v_h * v_h;
    let excess = |eps: f64| {
        let rho = rho0 / (1.0 + eps);
        let (sig, _) = jump_state(mat, rho, deviator(rho), sig_h, eps_h, e_h);
        (sig_h - sig) * (eps_h - eps) - target
    };
    // Bracket from the acoustic estimate Δε ≈ v_H/c0, widened until the
    // Rayleigh line carries enough momentum (ε > −1 always: ρ finite).
    let mut step = v_h / mat.c0;
    let mut lo = eps_h - step;
    while excess(lo) < 0.0 {
        step *= 2.0;
        lo = eps_h - step;
        if lo <= -0.99 {
            return None;
        }
    }
    let mut hi = eps_h;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if excess(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let eps_f = 0.5 * (lo + hi);
    let rho_f = rho0 / (1.0 + eps_f);
    let (sig_f, e_f) = jump_state(mat, rho_f, deviator(rho_f), sig_h, eps_h, e_h);
    let w_p = v_h / (eps_h - eps_f);
    if !(w_p.is_finite() && w_p > 0.0 && w_p < w_e) {
        return None;
    }
    Some(TwoWaveImpact {
        hel,
        elastic_speed: w_e,
        plastic: RodState {
            stress: sig_f,
            velocity: 0.0,
            density: rho_f,
            energy: e_f,
            pressure: mat.pressure(rho_f, e_f),
        },
        plastic_speed: w_p,
    })
}

// ---------------------------------------------------------------------------
// A free circular ring's flexural modes (the colliding rubber rings of Gray,
// Monaghan & Swift 2001)
// ---------------------------------------------------------------------------

/// Period (s) of the in-plane flexural mode `n ≥ 2` of a free circular ring
/// of radii `inner` < `outer`, in plane strain (METHOD.md §6: 2-D is plane
/// strain, so the bending modulus is `E' = E/(1 − ν²)`); `n = 2` is the
/// ovalling mode.
///
/// Thin-ring theory (inextensional bending of the mid-line, Hoppe 1871;
/// Love, *Mathematical Theory of Elasticity*, §293): with mean radius
/// `R = (inner + outer)/2`, thickness `t = outer − inner`, bending stiffness
/// per unit depth `D = E' t³/12` and mass per unit length and depth `ρ0 t`,
///
/// ```text
/// ω_n² = D n² (n² − 1)² / (ρ0 t R⁴ (n² + 1))
/// ```
///
/// It neglects shear deformation and rotary inertia, which lower the
/// frequency of a thick ring (by a few per cent for n = 2 at t/R ≈ 0.3), and
/// holds for small amplitude. NaN for `n < 2` (rigid-body modes) or radii
/// that do not make a ring.
pub fn ring_flexural_period(mat: &MaterialModel, inner: f64, outer: f64, n: u32) -> f64 {
    if n < 2 || !(inner > 0.0 && outer > inner && outer.is_finite()) {
        return f64::NAN;
    }
    let r = 0.5 * (inner + outer);
    let t = outer - inner;
    let d = plane_strain_modulus(mat) * t.powi(3) / 12.0;
    let n2 = f64::from(n * n);
    let omega2 = d * n2 * (n2 - 1.0).powi(2) / (mat.rho0 * t * r.powi(4) * (n2 + 1.0));
    2.0 * PI / omega2.sqrt()
}

/// `∫_a^b f` by tanh–sinh (double-exponential) quadrature, refined by halving
/// the step until two levels agree to `rel_tol`. Nodes never touch the
/// endpoints and cluster there doubly exponentially, so integrable endpoint
/// singularities (here `φ ln φ`) cost nothing extra.
fn tanh_sinh<F: Fn(f64) -> f64>(f: &F, a: f64, b: f64, rel_tol: f64) -> f64 {
    let half = 0.5 * (b - a);
    if half <= 0.0 {
        return 0.0;
    }
    const T_MAX: f64 = 4.0;
    // Contribution of the node pair at ±t (or the centre at t = 0).
    let pair = |t: f64| -> f64 {
        let u = FRAC_PI_2 * t.sinh();
        let cu = u.cosh();
        let w = half * FRAC_PI_2 * t.cosh() / (cu * cu);
        if w.is_nan() || w <= 0.0 {
            return 0.0;
        }
        // Distance of the node from the nearer endpoint, accurate for large u.
        let d = 2.0 * half / (1.0 + (2.0 * u).exp());
        if t == 0.0 {
            return w * f(a + half);
        }
        if d.is_nan() || d <= 0.0 {
            return 0.0;
        }
        w * (f(a + d) + f(b - d))
    };
    let mut h = 1.0;
    let mut sum = pair(0.0);
    let mut k = 1.0;
    while k * h <= T_MAX {
        sum += pair(k * h);
        k += 1.0;
    }
    let mut estimate = h * sum;
    for _ in 0..10 {
        h *= 0.5;
        let mut k = 1.0;
        while k * h <= T_MAX {
            sum += pair(k * h);
            k += 2.0;
        }
        let next = h * sum;
        let done = (next - estimate).abs() <= rel_tol * next.abs();
        estimate = next;
        if done {
            break;
        }
    }
    estimate
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear-EOS material from `(ρ0, c0, G)`, derived constants as in
    /// METHOD.md §6 (K = ρ0 c0², E = 9KG/(3K+G), c_L = sqrt((K + 4G/3)/ρ0)).
    fn material(rho0: f64, c0: f64, g: f64) -> MaterialModel {
        let k = rho0 * c0 * c0;
        let e = 9.0 * k * g / (3.0 * k + g);
        let nu = (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g));
        let m = k + 4.0 * g / 3.0;
        let c_l = (m / rho0).sqrt();
        MaterialModel {
            rho0,
            c0,
            s: 0.0,
            gamma0: 0.0,
            linear: true,
            g,
            y0: f64::INFINITY,
            k,
            e,
            nu,
            c_l,
            z: rho0 * c_l,
            m,
            strength: None,
            failure: None,
            spall: f64::INFINITY,
            specific_heat: 0.0,
            taylor_quinney: 0.0,
        }
    }

    fn steel() -> MaterialModel {
        material(7850.0, 4580.0, 77e9)
    }

    fn aluminium() -> MaterialModel {
        material(2790.0, 5330.0, 25e9)
    }

    /// Relative closeness to a printed figure.
    fn close(x: f64, expected: f64, rel: f64) -> bool {
        ((x - expected) / expected).abs() <= rel
    }

    /// Absolute closeness to a printed figure in its last digit.
    fn near(x: f64, expected: f64, abs: f64) -> bool {
        (x - expected).abs() <= abs
    }

    const L: f64 = 5e-3;

    /// METHOD.md §10 case 1: −458.1 MPa, 2L/c_L = 1.7136 µs, rebound ∓10 m/s.
    #[test]
    fn equal_steel_bars() {
        let s = steel();
        let r = bar_impact(&s, L, 10.0, &s, L, -10.0);
        println!("case 1: {r:?}");
        assert!(near(r.contact_stress / 1e6, -458.1, 0.05), "{r:?}");
        assert!(near(r.interface_velocity, 0.0, 1e-12), "{r:?}");
        assert!(near(r.separation_time * 1e6, 1.7136, 0.00005), "{r:?}");
        assert!(close(r.separation_time, 2.0 * L / s.c_l, 1e-12));
        assert!(near(r.final_velocity_1, -10.0, 1e-9), "{r:?}");
        assert!(near(r.final_velocity_2, 10.0, 1e-9), "{r:?}");
    }

    /// METHOD.md §10 case 2: −255.6 MPa, +4.42 m/s, 2L/c_Al = 1.574 µs,
    /// aluminium +18.84 m/s, steel mean −0.25 m/s.
    #[test]
    fn steel_on_aluminium() {
        let (s, a) = (steel(), aluminium());
        let h = bar_impact_history(&s, L, 10.0, &a, L, -10.0, 3e-6).expect("resolved");
        let r = h.result;
        println!("case 2: {r:?}, steps {:?}", h.contact_steps);
        assert!(near(r.contact_stress / 1e6, -255.6, 0.05), "{r:?}");
        assert!(near(r.interface_velocity, 4.42, 0.005), "{r:?}");
        assert!(near(r.separation_time * 1e6, 1.574, 0.0005), "{r:?}");
        assert!(close(r.separation_time, 2.0 * L / a.c_l, 1e-12));
        assert_eq!(h.first_separation_time, r.separation_time);
        assert_eq!(h.contact_steps.len(), 1, "a single stress level");
        assert!(near(r.final_velocity_2, 18.84, 0.005), "{r:?}");
        assert!(near(r.final_velocity_1, -0.25, 0.005), "{r:?}");
        // Momentum is conserved.
        let p0 = s.rho0 * L * 10.0 - a.rho0 * L * 10.0;
        let p1 = s.rho0 * L * r.final_velocity_1 + a.rho0 * L * r.final_velocity_2;
        assert!((p1 - p0).abs() <= 1e-12 * s.rho0 * L * 10.0);
        // Aluminium ends uniform at its mean velocity; steel keeps a pulse.
        let t = 3.0e-6;
        for i in 0..=10 {
            let d = L * i as f64 / 10.0;
            let va = h.point_velocity(BarId::Two, d, t);
            assert!(near(va, r.final_velocity_2, 1e-9), "Al at d = {d}: {va}");
        }
    }

    /// Energy: elastic bars, so kinetic + strain energy is conserved; after
    /// separation the steel bar's trapped pulse holds the missing energy.
    #[test]
    fn energy_conservation_in_history() {
        let (s, a) = (steel(), aluminium());
        let t_end = 5e-6;
        let h = bar_impact_history(&s, L, 10.0, &a, L, -10.0, t_end).expect("resolved");
        let energy = |m: &MaterialModel, bar: BarId, t: f64| {
            let n = 20_000;
            let dx = L / n as f64;
            (0..n)
                .map(|i| {
                    let d = (i as f64 + 0.5) * dx;
                    let v = h.point_velocity(bar, d, t);
                    let sig = h.point_stress(bar, d, t);
                    0.5 * m.rho0 * v * v * dx + 0.5 * sig * sig / m.m * dx
                })
                .sum::<f64>()
        };
        let e0 = 0.5 * (s.rho0 + a.rho0) * L * 100.0;
        for &t in &[0.3e-6, 1.0e-6, 2.0e-6, 4.9e-6] {
            let e = energy(&s, BarId::One, t) + energy(&a, BarId::Two, t);
            assert!(close(e, e0, 1e-3), "t = {t}: {e} vs {e0}");
        }
    }

    /// METHOD.md §10 case 2, Galilean check: steel at 20 m/s onto aluminium
    /// at rest gives the same stress and timing, velocities shifted by +10.
    #[test]
    fn galilean_invariance() {
        let (s, a) = (steel(), aluminium());
        let r = bar_impact(&s, L, 10.0, &a, L, -10.0);
        let g = bar_impact(&s, L, 20.0, &a, L, 0.0);
        println!("galilean: {g:?}");
        assert!(close(g.contact_stress, r.contact_stress, 1e-12));
        assert!(close(g.separation_time, r.separation_time, 1e-12));
        assert!(near(
            g.interface_velocity,
            r.interface_velocity + 10.0,
            1e-9
        ));
        assert!(near(g.final_velocity_1, r.final_velocity_1 + 10.0, 1e-9));
        assert!(near(g.final_velocity_2, r.final_velocity_2 + 10.0, 1e-9));
        // Same for equal bars.
        let e = bar_impact(&s, L, 20.0, &s, L, 0.0);
        assert!(near(e.contact_stress / 1e6, -458.1, 0.05));
        assert!(near(e.final_velocity_1, 0.0, 1e-9));
        assert!(near(e.final_velocity_2, 20.0, 1e-9));
    }

    /// Aluminium on the left, steel on the right: the mirror of case 2.
    #[test]
    fn mirrored_case_2() {
        let (s, a) = (steel(), aluminium());
        let r = bar_impact(&a, L, 10.0, &s, L, -10.0);
        assert!(near(r.contact_stress / 1e6, -255.6, 0.05));
        assert!(near(r.interface_velocity, -4.42, 0.005));
        assert!(near(r.separation_time * 1e6, 1.574, 0.0005));
        assert!(near(r.final_velocity_1, -18.84, 0.005));
        assert!(near(r.final_velocity_2, 0.25, 0.005));
    }

    /// Case 1 point history, closed form vs the wave tracer, and the
    /// linear fall of the bar-average velocity.
    #[test]
    fn equal_bars_point_history() {
        let s = steel();
        let c = s.c_l;
        let h = bar_impact_history(&s, L, 10.0, &s, L, -10.0, 4e-6).expect("resolved");
        for i in 0..=20 {
            let d = L * i as f64 / 20.0;
            for j in 0..400 {
                let t = 4e-6 * (j as f64 + 0.37) / 400.0;
                let exact = equal_bars_point_velocity(c, L, 10.0, d, t);
                let traced = h.point_velocity(BarId::One, d, t);
                assert!(
                    near(traced, exact, 1e-9),
                    "d {d} t {t}: {traced} vs {exact}"
                );
                let traced2 = h.point_velocity(BarId::Two, d, t);
                assert!(near(traced2, -exact, 1e-9));
            }
        }
        let b = 0.25 * L;
        assert_eq!(equal_bars_point_velocity(c, L, 10.0, b, 0.99 * b / c), 10.0);
        assert_eq!(equal_bars_point_velocity(c, L, 10.0, b, 1.01 * b / c), 0.0);
        let t_back = (2.0 * L - b) / c;
        assert_eq!(equal_bars_point_velocity(c, L, 10.0, b, 0.99 * t_back), 0.0);
        assert_eq!(
            equal_bars_point_velocity(c, L, 10.0, b, 1.01 * t_back),
            -10.0
        );
        assert!(equal_bars_point_velocity(c, L, 10.0, 2.0 * L, 0.0).is_nan());
        // Mean velocity falls linearly from +10 to −10 m/s over 2L/c.
        let ts = 2.0 * L / c;
        for k in 0..=10 {
            let t = ts * k as f64 / 10.0;
            let vm = h.mean_velocity(BarId::One, t);
            assert!(near(vm, 10.0 - 20.0 * k as f64 / 10.0, 1e-9), "{t}: {vm}");
        }
        assert!(near(h.interface_stress(0.5 * ts) / 1e6, -458.1, 0.05));
        assert_eq!(h.interface_stress(1.1 * ts), 0.0);
    }

    /// A short bar onto a long bar of the same material: the striker stops,
    /// the target carries the whole momentum away (classic result), and a
    /// general case with unequal impedances and lengths conserves momentum
    /// and energy.
    #[test]
    fn unequal_lengths() {
        let s = steel();
        let r = bar_impact(&s, L, 10.0, &s, 2.0 * L, 0.0);
        println!("short on long: {r:?}");
        assert!(near(r.final_velocity_1, 0.0, 1e-9));
        assert!(near(r.final_velocity_2, 5.0, 1e-9));
        assert!(close(r.separation_time, 2.0 * L / s.c_l, 1e-12));

        let a = aluminium();
        for &(l1, l2) in &[
            (L, 3.0 * L),
            (3.0 * L, L),
            (0.7 * L, 1.9 * L),
            (2.3 * L, 0.4 * L),
        ] {
            for &(m1, m2) in &[(s, a), (a, s)] {
                let h = bar_impact_history(&m1, l1, 7.0, &m2, l2, -3.0, 0.0).expect("resolved");
                let r = h.result;
                let p0 = m1.rho0 * l1 * 7.0 - m2.rho0 * l2 * 3.0;
                let p1 = m1.rho0 * l1 * r.final_velocity_1 + m2.rho0 * l2 * r.final_velocity_2;
                assert!((p1 - p0).abs() <= 1e-9 * p0.abs().max(1.0));
                // Elastic: the rigid-body kinetic energy cannot grow.
                let k0 = 0.5 * (m1.rho0 * l1 * 49.0 + m2.rho0 * l2 * 9.0);
                let k1 = 0.5
                    * (m1.rho0 * l1 * r.final_velocity_1.powi(2)
                        + m2.rho0 * l2 * r.final_velocity_2.powi(2));
                assert!(k1 <= k0 * (1.0 + 1e-12), "{l1} {l2}: {k1} > {k0}");
                assert!(r.final_velocity_2 >= r.final_velocity_1 - 1e-9);
                assert!(h.contact_steps.iter().all(|s| s.stress < 0.0));
            }
        }
    }

    /// Random configurations (deterministic generator): every one resolves,
    /// conserves momentum, and conserves kinetic + strain energy at all times
    /// of the traced history; the interface is never tensile.
    #[test]
    fn random_bars_conserve() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut recontacts = 0;
        for _ in 0..200 {
            let m1 = material(
                1000.0 + 9000.0 * rnd(),
                2000.0 + 5000.0 * rnd(),
                80e9 * rnd(),
            );
            let m2 = material(
                1000.0 + 9000.0 * rnd(),
                2000.0 + 5000.0 * rnd(),
                80e9 * rnd(),
            );
            let (l1, l2) = (L * (0.1 + 3.0 * rnd()), L * (0.1 + 3.0 * rnd()));
            let v2 = 20.0 * (rnd() - 0.5);
            let v1 = v2 + 0.1 + 20.0 * rnd();
            let t_end = 6.0 * (l1 / m1.c_l).max(l2 / m2.c_l);
            let h = bar_impact_history(&m1, l1, v1, &m2, l2, v2, t_end).expect("resolved");
            let r = h.result;
            let (w1, w2) = (m1.rho0 * l1, m2.rho0 * l2);
            let p0 = w1 * v1 + w2 * v2;
            let p1 = w1 * r.final_velocity_1 + w2 * r.final_velocity_2;
            assert!((p1 - p0).abs() <= 1e-9 * (w1 * v1.abs() + w2 * v2.abs()));
            assert!(r.final_velocity_2 >= r.final_velocity_1 - 1e-9);
            assert!(h.contact_steps.iter().all(|s| s.stress < 0.0));
            if h.contact_steps
                .windows(2)
                .any(|w| w[1].t_start > w[0].t_end)
            {
                recontacts += 1;
            }
            let e0 = 0.5 * (w1 * v1 * v1 + w2 * v2 * v2);
            let energy = |m: &MaterialModel, len: f64, bar: BarId, t: f64| {
                let n = 40000;
                let dx = len / n as f64;
                (0..n)
                    .map(|i| {
                        let d = (i as f64 + 0.5) * dx;
                        let v = h.point_velocity(bar, d, t);
                        let sig = h.point_stress(bar, d, t);
                        0.5 * (m.rho0 * v * v + sig * sig / m.m) * dx
                    })
                    .sum::<f64>()
            };
            for k in 1..6 {
                let t = t_end * k as f64 / 6.0 + 1e-3 * t_end * rnd();
                let e = energy(&m1, l1, BarId::One, t) + energy(&m2, l2, BarId::Two, t);
                assert!(close(e, e0, 2e-3), "t = {t}: {e} vs {e0}");
                // The interface never overlaps: stress-free faces when apart.
                if h.interface_stress(t) == 0.0 {
                    assert!(
                        h.point_stress(BarId::One, 0.0, t).abs() < 1e-3 * r.contact_stress.abs()
                    );
                    assert!(
                        h.point_stress(BarId::Two, 0.0, t).abs() < 1e-3 * r.contact_stress.abs()
                    );
                }
            }
        }
        println!("random bars: {recontacts} of 200 re-contact");
    }

    #[test]
    fn invalid_bar_input() {
        let s = steel();
        assert!(try_bar_impact(&s, L, -1.0, &s, L, 1.0).is_none());
        assert!(try_bar_impact(&s, 0.0, 1.0, &s, L, 0.0).is_none());
        assert!(bar_impact(&s, L, 1.0, &s, L, 1.0).contact_stress.is_nan());
    }

    /// METHOD.md §6 derived constants and the §10 case-3 inputs.
    #[test]
    fn steel_constants() {
        let s = steel();
        assert!(close(s.e, 199.8e9, 5e-4));
        assert!(near(s.nu, 0.298, 5e-4));
        assert!(close(plane_strain_modulus(&s), 219.3e9, 5e-4));
        let c = hertz_c_inertia(s.nu);
        println!("C_inertia(steel) = {c}");
        assert!(near(c, 1.742, 5e-4));
    }

    /// METHOD.md §10 case 3: peak 1.161 (C = 1) to 1.224 MN/m (C ≈ 1.742),
    /// contact time 8.71 to 8.30 µs.
    #[test]
    fn hertz_bracket() {
        let s = steel();
        let r = 5e-3;
        let soft = hertz_disks(&s, r, 10.0, HERTZ_C_JOHNSON);
        let stiff = hertz_disks(&s, r, 10.0, hertz_c_inertia(s.nu));
        println!(
            "Hertz C=1: peak {:.6} MN/m, t_c {:.6} us, delta_max {:.6e} m",
            soft.peak_force / 1e6,
            soft.contact_time * 1e6,
            soft.max_approach
        );
        println!(
            "Hertz C=C_inertia: peak {:.6} MN/m, t_c {:.6} us, delta_max {:.6e} m",
            stiff.peak_force / 1e6,
            stiff.contact_time * 1e6,
            stiff.max_approach
        );
        assert!(close(soft.peak_force, 1.161e6, 2e-3));
        assert!(close(soft.contact_time, 8.71e-6, 2e-3));
        assert!(close(stiff.peak_force, 1.224e6, 2e-3));
        assert!(close(stiff.contact_time, 8.30e-6, 2e-3));
        // And to the printed digits.
        assert!(near(soft.peak_force / 1e6, 1.161, 0.0005));
        assert!(near(stiff.peak_force / 1e6, 1.224, 0.0005));
        assert!(near(soft.contact_time * 1e6, 8.71, 0.005));
        assert!(near(stiff.contact_time * 1e6, 8.30, 0.005));
    }

    /// Curve shape: ≥ 200 points, from (0, 0) to (t_c, 0), monotone times,
    /// symmetric about the peak, and its impulse `∫P dt = 2 m* V` (the
    /// relative velocity reverses).
    #[test]
    fn hertz_curve() {
        let s = steel();
        let (r, v) = (5e-3, 10.0);
        let h = hertz_disks(&s, r, v, hertz_c_inertia(s.nu));
        let c = &h.curve;
        assert!(c.len() >= 200);
        assert_eq!(c[0], (0.0, 0.0));
        assert_eq!(c[c.len() - 1], (h.contact_time, 0.0));
        assert!(c.windows(2).all(|w| w[1].0 > w[0].0));
        let n = c.len();
        for i in 0..n {
            let (t, p) = c[i];
            let (tm, pm) = c[n - 1 - i];
            assert!(near(t + tm, h.contact_time, 1e-15));
            assert_eq!(p, pm);
        }
        let peak = c.iter().map(|p| p.1).fold(0.0, f64::max);
        assert_eq!(peak, h.peak_force);
        assert!(near(c[n / 2].0, 0.5 * h.contact_time, 1e-18));
        let impulse: f64 = c
            .windows(2)
            .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
            .sum();
        let m_star = 0.5 * s.rho0 * PI * r * r;
        assert!(close(impulse, 2.0 * m_star * v, 1e-4), "{impulse}");
        assert!(close(h.force_at(0.5 * h.contact_time), h.peak_force, 1e-12));
        assert_eq!(h.force_at(-1.0), 0.0);
        assert_eq!(h.force_at(2.0 * h.contact_time), 0.0);
    }

    /// Energy: ½ m* V² = ∫0^δmax P(δ) dδ with P(δ) from the numerical
    /// inversion (independent of the closed form), and the inversion is
    /// consistent with the forward law.
    #[test]
    fn hertz_energy_and_inversion() {
        let s = steel();
        let (r, v) = (5e-3, 10.0);
        for c in [HERTZ_C_JOHNSON, hertz_c_inertia(s.nu)] {
            let h = hertz_disks(&s, r, v, c);
            let dmax = h.max_approach;
            let back = hertz_approach(&s, r, c, h.peak_force).expect("in range");
            assert!(close(back, dmax, 1e-14));
            for &f in &[1e-6, 1.0, 1e3, 1e6, 2e6] {
                let d = hertz_approach(&s, r, c, f).expect("in range");
                let p = hertz_force(&s, r, c, d).expect("in range");
                assert!(close(p, f, 1e-12), "{f}: {p}");
            }
            assert_eq!(hertz_force(&s, r, c, 0.0), Some(0.0));
            assert_eq!(hertz_force(&s, r, c, -1e-9), Some(0.0));
            // Simpson on δ ∈ [0, δmax]; refine near 0 with δ = δmax u².
            let n = 40000;
            let g = |u: f64| {
                let d = dmax * u * u;
                hertz_force(&s, r, c, d).unwrap_or(f64::NAN) * 2.0 * dmax * u
            };
            let hstep = 1.0 / n as f64;
            let mut sum = g(0.0) + g(1.0);
            for i in 1..n {
                let w = if i % 2 == 1 { 4.0 } else { 2.0 };
                sum += w * g(i as f64 * hstep);
            }
            let work = sum * hstep / 3.0;
            let m_star = 0.5 * s.rho0 * PI * r * r;
            let kinetic = 0.5 * m_star * v * v;
            println!("C = {c}: work {work} J/m, kinetic {kinetic} J/m");
            assert!(close(work, kinetic, 1e-8), "{work} vs {kinetic}");
        }
    }

    /// Independent check of the quadrature: integrate m* δ̈ = −P(δ) with RK4
    /// and locate the return to δ = 0 by interpolation.
    #[test]
    fn hertz_ode_cross_check() {
        let s = steel();
        let (r, v) = (5e-3, 10.0);
        let m_star = 0.5 * s.rho0 * PI * r * r;
        for c in [HERTZ_C_JOHNSON, hertz_c_inertia(s.nu)] {
            let h = hertz_disks(&s, r, v, c);
            let acc = |d: f64| -hertz_force(&s, r, c, d).unwrap_or(f64::NAN) / m_star;
            let dt = h.contact_time / 20_000.0;
            let (mut t, mut d, mut u) = (0.0, 0.0, v);
            let mut p_peak: f64 = 0.0;
            loop {
                let (k1d, k1u) = (u, acc(d));
                let (k2d, k2u) = (u + 0.5 * dt * k1u, acc(d + 0.5 * dt * k1d));
                let (k3d, k3u) = (u + 0.5 * dt * k2u, acc(d + 0.5 * dt * k2d));
                let (k4d, k4u) = (u + dt * k3u, acc(d + dt * k3d));
                let dn = d + dt / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
                let un = u + dt / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
                if dn <= 0.0 && t > 0.0 {
                    let tc = t + dt * d / (d - dn);
                    println!("C = {c}: ODE t_c {tc:e}, quadrature {:e}", h.contact_time);
                    assert!(close(tc, h.contact_time, 1e-4));
                    assert!(near(un, -v, 1e-3 * v));
                    break;
                }
                t += dt;
                d = dn;
                u = un;
                p_peak = p_peak.max(-acc(d) * m_star);
                assert!(t < 2.0 * h.contact_time);
            }
            assert!(close(p_peak, h.peak_force, 1e-6));
        }
    }

    /// The rubber ring of Gray, Monaghan & Swift (2001): E = 1e7 Pa,
    /// ν = 0.3975, ρ0 = 1, radii 3 and 4 cm. By hand: E' = 1e7/(1 − 0.3975²)
    /// = 1.18766e7 Pa, D/(ρ0 t) = E' t²/12 = 98.972 m⁴/s², R⁴ = 0.035⁴, so
    /// ω2 = sqrt(98.972/0.035⁴ · 36/5) = 21 791 rad/s, T2 = 288.33 µs. The
    /// period scales as R²/t and as n⁻³ for large n.
    #[test]
    fn ring_ovalling_period() {
        let k: f64 = 1e7 / (3.0 * (1.0 - 2.0 * 0.3975));
        let g = 1e7 / (2.0 * (1.0 + 0.3975));
        let rubber = material(1.0, k.sqrt(), g);
        assert!(close(rubber.e, 1e7, 1e-12) && close(rubber.nu, 0.3975, 1e-12));
        let t2 = ring_flexural_period(&rubber, 0.03, 0.04, 2);
        assert!(close(t2, 288.33e-6, 1e-4), "T2 = {t2:e}");
        // Twice as thick about the same mean radius: half the period.
        let thick = ring_flexural_period(&rubber, 0.025, 0.045, 2);
        assert!(close(thick, 0.5 * t2, 1e-12));
        // ω_n ∝ n(n² − 1)/sqrt(n² + 1): 2·3/√5 for n = 2, 3·8/√10 for n = 3.
        let t3 = ring_flexural_period(&rubber, 0.03, 0.04, 3);
        let ratio = (24.0 / 10f64.sqrt()) / (6.0 / 5f64.sqrt());
        assert!(close(t2 / t3, ratio, 1e-12));
        assert!(ring_flexural_period(&rubber, 0.03, 0.04, 1).is_nan());
        assert!(ring_flexural_period(&rubber, 0.04, 0.03, 2).is_nan());
    }

    /// METHOD.md §8.5: a disk at V on a rigid wall equals two disks at 2V.
    #[test]
    fn hertz_wall() {
        let s = steel();
        let w = hertz_disk_on_wall(&s, 5e-3, 5.0, HERTZ_C_JOHNSON);
        let d = hertz_disks(&s, 5e-3, 10.0, HERTZ_C_JOHNSON);
        assert_eq!(w.peak_force, d.peak_force);
        assert_eq!(w.contact_time, d.contact_time);
        assert_eq!(w.max_approach, 0.5 * d.max_approach);
    }

    #[test]
    fn hertz_invalid_input() {
        let s = steel();
        assert!(try_hertz_disks(&s, 5e-3, 0.0, 1.0).is_none());
        assert!(try_hertz_disks(&s, -5e-3, 10.0, 1.0).is_none());
        assert!(try_hertz_disks(&s, 5e-3, 1e12, 1.0).is_none());
        assert!(hertz_disks(&s, 5e-3, f64::NAN, 1.0).peak_force.is_nan());
    }

    /// The steel of METHOD.md §6 Table 1 with its Mie–Grüneisen EOS and
    /// Y0 = 600 MPa, as the scenes write it.
    fn steel_mg_plastic() -> MaterialModel {
        MaterialModel::new(&crate::scene::Material {
            shear_modulus: Some(77e9),
            yield_stress: Some(600e6),
            ..crate::scene::Material::basic(
                7850.0,
                crate::scene::Eos::MieGruneisen {
                    c0: 4580.0,
                    s: 1.49,
                    gamma0: 2.02,
                },
            )
        })
    }

    /// Steel at 100 m/s on a rigid wall: the HEL is the acoustic
    /// `(K + 4G/3) Y0/(2G)` ≈ 1.04 GPa, with `u_HEL` ≈ 22.7 m/s and the
    /// precursor at `c_L`, to first order in the strain at yield (3.9e-3):
    /// the EOS's curvature and Grüneisen term put the exact HEL 0.8 % above
    /// the acoustic one (1.049 GPa), the precursor 0.5 % above `c_L`;
    /// the plastic wave runs a little faster than the bulk speed (the EOS
    /// stiffens) and slower than the precursor.
    #[test]
    fn rod_on_wall_steel_at_100() {
        let m = steel_mg_plastic();
        let r = rod_on_wall(&m, 100.0).expect("two waves");
        println!("steel rod on a wall at 100 m/s: {r:?}");
        let hel = acoustic_hel(&m);
        assert!(near(hel / 1e9, 1.04, 0.005), "{hel:e}");
        assert!(close(-r.hel.stress, hel, 1e-2));
        assert!(close(100.0 - r.hel.velocity, hel / m.z, 1e-2));
        assert!(near(100.0 - r.hel.velocity, 22.7, 0.2));
        assert!(close(r.elastic_speed, m.c_l, 1e-2));
        let bulk = (m.k / m.rho0).sqrt();
        assert!(r.plastic_speed > bulk && r.plastic_speed < 1.05 * bulk);
        assert!(r.plastic_speed < r.elastic_speed);
        // Roughly σ_H − ρ0 W_p v_H: about −3.9 GPa.
        assert!(r.plastic.stress < -3.5e9 && r.plastic.stress > -4.5e9);
        assert!(r.plastic.density > r.hel.density && r.plastic.energy > r.hel.energy);
    }

    /// The solution satisfies what it was solved from, independently
    /// re-evaluated: the EOS with the deviator at yield, and the
    /// Rankine–Hugoniot mass, momentum and energy jumps across both waves
    /// (Lagrangian form).
    #[test]
    fn rod_on_wall_jump_conditions() {
        let m = steel_mg_plastic();
        for v0 in [30.0, 100.0, 300.0] {
            let r = rod_on_wall(&m, v0).expect("two waves");
            let eps = |s: &RodState| m.rho0 / s.density - 1.0;
            let (h, f) = (r.hel, r.plastic);
            let y = 2.0 * m.y0 / 3.0;
            for s in [&h, &f] {
                assert!(close(s.stress, -m.pressure(s.density, s.energy) - y, 1e-12));
                assert!(close(s.pressure, m.pressure(s.density, s.energy), 1e-15));
            }
            // Precursor, from rest at v0.
            let (we, wp) = (r.elastic_speed, r.plastic_speed);
            assert!(close(h.stress, m.rho0 * we * (h.velocity - v0), 1e-12));
            assert!(close(h.velocity - v0, we * eps(&h), 1e-12));
            assert!(close(h.energy, 0.5 * h.stress * eps(&h) / m.rho0, 1e-12));
            // Plastic wave, to rest.
            assert_eq!(f.velocity, 0.0);
            assert!(close(f.stress - h.stress, -m.rho0 * wp * h.velocity, 1e-9));
            assert!(close(-h.velocity, wp * (eps(&f) - eps(&h)), 1e-9));
            let de = 0.5 * (f.stress + h.stress) * (eps(&f) - eps(&h)) / m.rho0;
            assert!(close(f.energy - h.energy, de, 1e-9));
            // The yield point from the hypoelastic law: (4/3) G ln(ρ_H/ρ0) = 2Y0/3.
            assert!(close(4.0 / 3.0 * m.g * (h.density / m.rho0).ln(), y, 1e-12));
        }
    }

    /// A linear EOS without Grüneisen term makes the stress a function of
    /// strain only, `σ(ε) = K ε/(1 + ε) − 2Y0/3`, and the plastic jump a
    /// quadratic: with `x = ε_F − ε_H`, `b = 1 + ε_H`, `a = ρ0 v_H²/K`,
    /// `x = b (a − sqrt(a² + 4a))/2`. The bisection meets the closed form;
    /// a weak plastic wave runs at the local plastic wave speed
    /// `sqrt(σ'(ε_H)/ρ0) = c0/(1 + ε_H)`.
    #[test]
    fn rod_on_wall_linear_closed_form() {
        let mut m = material(7850.0, 4580.0, 77e9);
        m.y0 = 600e6;
        let mu_h = (m.y0 / (2.0 * m.g)).exp() - 1.0;
        let eps_h = 1.0 / (1.0 + mu_h) - 1.0;
        let sig_h = -m.k * mu_h - 2.0 * m.y0 / 3.0;
        let w_e = (sig_h / (m.rho0 * eps_h)).sqrt();
        for v0 in [25.0, 100.0, 400.0] {
            let r = rod_on_wall(&m, v0).expect("two waves");
            assert!(close(r.hel.stress, sig_h, 1e-12));
            assert!(close(r.elastic_speed, w_e, 1e-12));
            let v_h = v0 + w_e * eps_h;
            assert!(close(r.hel.velocity, v_h, 1e-10));
            let (a, b) = (m.rho0 * v_h * v_h / m.k, 1.0 + eps_h);
            let x = b * (a - (a * a + 4.0 * a).sqrt()) / 2.0;
            let eps_f = m.rho0 / r.plastic.density - 1.0;
            assert!(
                close(eps_f - eps_h, x, 1e-10),
                "{v0}: {} vs {x}",
                eps_f - eps_h
            );
            assert!(close(r.plastic_speed, -v_h / x, 1e-10));
        }
        let u_hel = -w_e * eps_h;
        let weak = rod_on_wall(&m, u_hel * (1.0 + 1e-5)).expect("two waves");
        let local = m.c0 / (1.0 + eps_h);
        assert!(
            close(weak.plastic_speed, local, 1e-6),
            "{}",
            weak.plastic_speed
        );
    }

    /// No two-wave structure: elastic materials, impacts below the HEL,
    /// an overdriven plastic shock, bad speeds.
    #[test]
    fn rod_on_wall_outside_its_range() {
        let m = steel_mg_plastic();
        assert!(rod_on_wall(&steel(), 100.0).is_none(), "no yield stress");
        assert!(rod_on_wall(&m, 20.0).is_none(), "below u_HEL");
        assert!(rod_on_wall(&m, 23.0).is_some(), "just above u_HEL");
        assert!(rod_on_wall(&m, 5000.0).is_none(), "overdriven");
        assert!(rod_on_wall(&m, -100.0).is_none());
        assert!(rod_on_wall(&m, f64::NAN).is_none());
    }
}
