//! The artificial viscosity (docs/method.md §4): Monaghan's `Π_ij` on the
//! velocity jump, reconstructed to the pair's midpoint where the field is
//! smooth.

use glam::DVec2;

use crate::math::Mat2;

/// The viscosity's damping rate on the grid's shortest waves, in units of
/// `α c_L / h` (docs/method.md §9, "Stability where the damping is
/// strong"): 2.5 on a 1-D lattice at `h = 1.2 Δx` for the linear term;
/// the steel rod's jet into aluminium needs 4 (at 2 it stops).
pub const PREDICTOR_RATE: f64 = 4.0;

/// The weight `c` of the leapfrog's predicted velocity `v_n + c Δt a_n`,
/// which the viscosity and the contact's dashpot see: `1 / (1 + γ Δt)`,
/// `γ = PREDICTOR_RATE α c_L / h` the viscosity's rate on a body's
/// shortest waves (its placed `h`, its material's `c_L`). `c = 1 − O(Δt)`
/// keeps the step second order; a damping seen at it is stable to `γ Δt`
/// of about 3.5 where `c = 1` is stable only to 1. Without viscosity
/// (`α = 0`) it is 1.
#[inline]
pub fn predictor_weight(alpha: f64, c_l: f64, h: f64, dt: f64) -> f64 {
    1.0 / (1.0 + PREDICTOR_RATE * alpha * c_l * dt / h)
}

/// The velocity jump the viscosity sees: `v_ij` less the linear
/// reconstruction of each side to the pair's midpoint, limited (van Leer).
///
/// Plain Monaghan viscosity acts on every approaching pair, so it also damps
/// smooth compression and smears every wave; what survives of a step after
/// one transit is then lost at a contact that cannot pull (the release front
/// reaches the face spread out, and the face opens on its first part). With
/// each side extrapolated to the midpoint by its own velocity gradient
/// `∇v` (pass B), the jump is `O(Δx²)` where the field is smooth and stays
/// whole at a front, where the two sides' slopes disagree and the limiter
/// `φ = 4r/(1+r)²` (`r` the ratio of the projected slopes, 0 when they
/// differ in sign) turns the reconstruction off. The same idea is used for
/// the viscosity of CRKSPH (Frontiere, Raskin & Owen 2017). `x_ij = x_i − x_j`.
#[inline]
pub fn reconstructed_jump(vij: DVec2, xij: DVec2, gv_i: &Mat2, gv_j: &Mat2) -> DVec2 {
    let di = gv_i.mul_vec(xij);
    let dj = gv_j.mul_vec(xij);
    let (si, sj) = (xij.dot(di), xij.dot(dj));
    if si * sj <= 0.0 {
        return vij;
    }
    // 4r/(1+r)² with r = si/sj, in one division.
    let phi = (4.0 * si * sj / ((si + sj) * (si + sj))).min(1.0);
    vij - (di + dj) * (0.5 * phi)
}

/// Monaghan's `Π_ij` (docs/method.md §4) on the jump `w` the viscosity
/// sees, `v` the pair's true velocity jump. Zero for receding pairs
/// unless `release` (the Riemann form), where it acts on them with its
/// linear term alone, on the smaller of `w·x` and `v·x` where they agree
/// in sign and on nothing where they differ: its work on the pair,
/// `Π v·G`, is heat and never negative, and it stays continuous as either
/// jump passes zero (a switch there would follow round-off). A pair that
/// is not `bonded` (a failed particle or an open void in it) is an
/// opening crack, which carries no traction: the Riemann form leaves it
/// alone while it recedes (on approach it acts as on any pair).
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn viscosity_pi(
    alpha: f64,
    beta: f64,
    hij: f64,
    xij: DVec2,
    w: DVec2,
    v: DVec2,
    c_mean: f64,
    rho_mean: f64,
    release: bool,
    bonded: bool,
) -> f64 {
    let mut wx = w.dot(xij);
    let on = if release {
        let vx = v.dot(xij);
        let on = wx * vx > 0.0 && (bonded || vx < 0.0);
        if vx * vx < wx * wx {
            wx = vx;
        }
        on
    } else {
        wx < 0.0
    };
    if !on {
        return 0.0;
    }
    let beta = if wx < 0.0 { beta } else { 0.0 };
    // μ = h w·x / D, Π = (−α c̄ μ + β μ²)/ρ̄, in one division.
    let d = xij.length_squared() + 0.01 * hij * hij;
    let hv = hij * wx;
    hv * (-alpha * c_mean * d + beta * hv) / (d * d * rho_mean)
}

#[cfg(test)]
mod tests {
    use super::*;

    const H: f64 = 1.2e-4;
    const C: f64 = 5000.0;
    const RHO: f64 = 7850.0;

    /// Receding pairs: nothing in Monaghan's form; in the Riemann form the
    /// linear term, which holds the pair back as it holds an approaching
    /// one apart. Approaching pairs: the same in both forms, bit for bit.
    #[test]
    fn riemann_form_damps_receding_pairs() {
        let x = DVec2::new(1.0e-4, 0.3e-4);
        let v = DVec2::new(2.0, 0.5);
        assert!(v.dot(x) > 0.0);
        let pi = |w: DVec2, release| viscosity_pi(0.75, 0.75, H, x, w, w, C, RHO, release, true);
        assert_eq!(pi(v, false), 0.0);
        let mu = H * v.dot(x) / (x.length_squared() + 0.01 * H * H);
        let linear = -0.75 * C * mu / RHO;
        assert!(linear < 0.0);
        assert!(
            (pi(v, true) / linear - 1.0).abs() < 1e-14,
            "{}",
            pi(v, true)
        );
        // Approaching: the linear term the same size, plus the quadratic.
        assert!(pi(-v, true) > -linear);
        assert_eq!(pi(-v, true).to_bits(), pi(-v, false).to_bits());
    }

    /// A pair with a failed particle or an open void is an opening crack:
    /// the Riemann form leaves it alone while it recedes, and on approach
    /// acts on it as on a bonded pair, bit for bit.
    #[test]
    fn an_opening_crack_takes_no_release_damping() {
        let x = DVec2::new(1.0e-4, 0.3e-4);
        let v = DVec2::new(2.0, 0.5);
        let pi = |w: DVec2, bonded| viscosity_pi(0.75, 0.75, H, x, w, w, C, RHO, true, bonded);
        assert!(pi(v, true) < 0.0);
        assert_eq!(pi(v, false), 0.0);
        assert!(pi(-v, false) > 0.0);
        assert_eq!(pi(-v, false).to_bits(), pi(-v, true).to_bits());
    }

    /// Its work on the pair, `Π v·G` with `G` along `−x`, is heat
    /// (`Π v·x ≤ 0`) whatever jump the reconstruction leaves, and it is
    /// zero where the jump seen and the true one disagree in sign.
    #[test]
    fn riemann_work_is_heat() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let (mut acted, mut shut) = (0, 0);
        for _ in 0..10_000 {
            let x = DVec2::new(next(), next()) * 2.0 * H;
            let v = DVec2::new(next(), next()) * 50.0;
            let w = v * (1.0 + next()) + DVec2::new(next(), next()) * 20.0;
            let pi = viscosity_pi(0.75, 0.75, H, x, w, v, C, RHO, true, true);
            assert!(pi * v.dot(x) <= 0.0, "{x} {v} {w}: {pi}");
            let (wx, vx) = (w.dot(x), v.dot(x));
            if wx * vx < 0.0 {
                assert_eq!(pi, 0.0);
                shut += 1;
            } else if pi != 0.0 {
                acted += 1;
                // Never more than the true jump would give.
                let full = viscosity_pi(0.75, 0.75, H, x, v, v, C, RHO, true, true);
                if vx * vx < wx * wx {
                    assert_eq!(pi.to_bits(), full.to_bits());
                } else {
                    assert!(pi.abs() <= full.abs());
                }
            }
        }
        assert!(acted > 5_000 && shut > 500, "{acted} {shut}");
    }

    /// Continuous where the true jump passes zero with the seen one
    /// finite: a pair that round-off moves across it moves Π by as
    /// little.
    #[test]
    fn riemann_form_is_continuous_at_the_switch() {
        let x = DVec2::new(1.0e-4, 0.0);
        let w = DVec2::new(3.0, 0.0);
        let pi =
            |vx: f64| viscosity_pi(0.75, 0.75, H, x, w, DVec2::new(vx, 1.0), C, RHO, true, true);
        let scale = pi(3.0).abs();
        for vx in [1e-9, 1e-12, -1e-12, -1e-9] {
            assert!(pi(vx).abs() < 1e-8 * scale, "{vx}: {}", pi(vx));
        }
    }
}
