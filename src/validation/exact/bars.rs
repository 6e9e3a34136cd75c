//! 1-D elastic bar impact: the paper's cases 1 and 2 by tracing the
//! wave fronts.

use super::bar_tracer::trace;
pub use super::bar_tracer::{BarId, BarImpact, BarImpactHistory, StressStep};
use crate::physics::material::MaterialModel;

// ---------------------------------------------------------------------------
// 1-D elastic bar impact (docs/method.md §10, cases 1 and 2)
// ---------------------------------------------------------------------------

/// Exact summary of the 1-D impact of two elastic bars (docs/method.md §10, cases
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

/// Exact wave history of the 1-D two-bar impact (docs/method.md §10, cases 1–2),
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
    trace(m1, l1, v1, m2, l2, v2, t_end)
}

/// Exact particle velocity in case 1 of docs/method.md §10 (two equal bars, each
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validation::exact::test_support::*;

    const L: f64 = 5e-3;

    /// docs/method.md §10 case 1: −458.1 MPa, 2L/c_L = 1.7136 µs, rebound ∓10 m/s.
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

    /// docs/method.md §10 case 2: −255.6 MPa, +4.42 m/s, 2L/c_Al = 1.574 µs,
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

    /// docs/method.md §10 case 2, Galilean check: steel at 20 m/s onto aluminium
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
}
