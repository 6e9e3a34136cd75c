//! The exact 1-D two-bar impact's engine: an event-driven tracer of the
//! piecewise-constant wave fronts ([`super::bar_impact_history`] says why
//! it is exact).

use std::collections::VecDeque;

use crate::physics::material::MaterialModel;

mod interface;
use interface::{Interface, Tolerances};

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
pub(super) struct BarTrace {
    pub(super) len: f64,
    c: f64,
    z: f64,
    pub(super) rho0: f64,
    pub(super) v0: f64,
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
    pub(super) fn state(&self, x: f64, t: f64) -> (f64, f64) {
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

/// The history of two valid bars (checked by the caller) traced to at
/// least `t_end`; `None` when the event cap is hit.
pub(super) fn trace(
    m1: &MaterialModel,
    l1: f64,
    v1: f64,
    m2: &MaterialModel,
    l2: f64,
    v2: f64,
    t_end: f64,
) -> Option<BarImpactHistory> {
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

    let mut iface = Interface {
        z: [z1, z2],
        v0: [v1, v2],
        masses,
        periods,
        tol: Tolerances {
            v: v_tol,
            gap: gap_tol,
        },
        in_contact: false,
        gap: 0.0,
        t_gap: 0.0,
        sigma_i: 0.0,
        t_sigma: 0.0,
        impulse: 0.0,
        steps: Vec::new(),
        first_contact: None,
        first_sep: None,
        last_sep: 0.0,
        sep_start: 0.0,
        bmax: [0.0; 2],
        resolved: None,
    };
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
        iface.event(&mut sim, t, window, pending_close);
        let t_now = t;

        // Next event: a front arrival or, while separated and closing, the
        // gap reaching zero.
        let mut t_next = f64::INFINITY;
        for b in 0..2 {
            for dir in 0..2 {
                t_next = t_next.min(sim.arrival(b, dir));
            }
        }
        let t_close = iface.closes_at(&sim);
        let closing = t_close <= t_next;
        t_next = t_next.min(t_close);
        iface.resolve(&sim, t_now, t_next)?;

        if iface.resolved.is_some() && (t_next > t_end || t_next.is_infinite()) {
            let valid_until = if t_next.is_finite() {
                t_end.max(t_now)
            } else {
                f64::INFINITY
            };
            let result = iface.resolved?;
            let [b1, b2] = sim.bars;
            return Some(BarImpactHistory {
                result,
                first_separation_time: iface.first_sep.unwrap_or(iface.last_sep),
                contact_steps: iface.steps,
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

/// Summary of a 1-D impact of two elastic bars (docs/method.md §10, cases 1–2).
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
    pub(super) fn nan() -> Self {
        Self {
            contact_stress: f64::NAN,
            interface_velocity: f64::NAN,
            separation_time: f64::NAN,
            final_velocity_1: f64::NAN,
            final_velocity_2: f64::NAN,
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

/// Full exact history of a 1-D two-bar impact (docs/method.md §10, cases 1–2).
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
    pub(super) bars: [BarTrace; 2],
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
    /// interface stress is constant (docs/method.md §10, case 1).
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
