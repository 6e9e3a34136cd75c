//! The artificial stress against the tensile instability (docs/method.md,
//! "Tension"): the stress of a particle in tension, the kernel-ratio weight
//! of a pair, and the close-pair gate; each also in lanes of four pairs for
//! the CPU's sweep.

use crate::math::lanes::F4;
use crate::math::Sym;
use crate::physics::kernel;

/// Artificial stress (Gray, Monaghan & Swift 2001): `−ε σ̄/ρ²` of each
/// tensile principal value `σ̄` of σ, on its principal axis.
///
/// Written without the principal angle: with both principal values
/// tensile it is `−ε σ/ρ²` (in plane), with one (`a > 0 ≥ b`) it is
/// `−ε a/ρ² P_a` with the projector `P_a = (σ − b I)/(a − b)`, and with
/// none it is zero. No trigonometry, and exact where the two principal
/// values meet.
#[inline]
pub fn artificial_stress(eps: f64, sigma: &Sym, rho: f64) -> Sym {
    let m = 0.5 * (sigma.xx + sigma.yy);
    let d = 0.5 * (sigma.xx - sigma.yy);
    let rad = (d * d + sigma.xy * sigma.xy).sqrt();
    let (a, b) = (m + rad, m - rad);
    let k = -eps / (rho * rho);
    if b > 0.0 {
        Sym {
            xx: k * sigma.xx,
            yy: k * sigma.yy,
            xy: k * sigma.xy,
            zz: 0.0,
        }
    } else if a > 0.0 {
        let s = k * a / (a - b);
        Sym {
            xx: s * (sigma.xx - b),
            yy: s * (sigma.yy - b),
            xy: s * sigma.xy,
            zz: 0.0,
        }
    } else {
        Sym::default()
    }
}

/// The artificial stress's pair weight `f^n`, `f = W(r)/W(Δp)` at `h_ij`
/// (the kernel's normalisation cancels, so only the spline's shape is
/// evaluated), from `r² = |x_ij|²`, `Δp` and `h_ij`. `n = 4`, the usual
/// choice, is two squarings.
#[inline]
pub fn art_weight(r2: f64, dp: f64, hij: f64, n: f64) -> f64 {
    let q2 = r2 / (hij * hij);
    let qd = dp / hij;
    let f = kernel::shape(q2.sqrt(), q2) / kernel::shape(qd, qd * qd);
    if n == 4.0 {
        let f2 = f * f;
        f2 * f2
    } else {
        f.powf(n)
    }
}

/// The share of the local spacing at and below which
/// [`ArtPairs::Close`](crate::scene::ArtPairs::Close)'s gate is fully open ([`close_gate`]).
pub const CLOSE_FULL: f64 = 0.95;

/// The gate's slope in `u = (r/s)²`: from 0 at `u = 1` to 1 at
/// `u = CLOSE_FULL²`.
const CLOSE_SLOPE: f64 = 1.0 / (1.0 - CLOSE_FULL * CLOSE_FULL);

/// The close-pair gate of the artificial stress ([`ArtPairs::Close`](crate::scene::ArtPairs::Close)): 0
/// for a pair at or beyond its local spacing `s = κ V̄^(1/d)` (`V̄` the
/// pair's mean particle volume `m/ρ`, so `s` follows the local strain;
/// `κ²` the smaller of the pair's [`Model::close_scales`](crate::model::Model::close_scales), 1 on a square
/// lattice), rising linearly in `(r/s)²` to 1 at `r = CLOSE_FULL s`. A
/// smoothly strained lattice keeps its nearest neighbours at `s` and sees
/// none of the term; the zig-zag clumping of the tensile instability
/// brings every other pair inside it.
#[inline]
pub fn close_gate(r2: f64, vol: f64, k2: f64, dim: usize) -> f64 {
    let s2 = if dim == 1 { vol * vol } else { vol } * k2;
    ((1.0 - r2 / s2) * CLOSE_SLOPE).clamp(0.0, 1.0)
}

/// [`close_gate`] for four pairs, one to a lane (bit-identical).
#[inline(always)]
pub fn close_gate_lanes(r2: F4, vol: F4, k2: F4, dim: usize) -> F4 {
    let s2 = if dim == 1 { vol * vol } else { vol } * k2;
    ((1.0 - r2 / s2) * CLOSE_SLOPE)
        .min(F4::splat(1.0))
        .max(F4::splat(0.0))
}

/// Where a pair's artificial stress may only heat (`work = "heat"`,
/// docs/method.md, "Only heat"): the share of the term it takes, from `vr =
/// v_ij · (R f^n γ) G_ij` (twice the term's work on the pair, heat where
/// negative) and `scale = HEAT_SPEED c̄_ij |(R f^n γ) G_ij|`, `c̄_ij` the
/// pair's mean sound speed. None while the pair recedes along the term's
/// force or rests; all of it once it closes along the force at
/// `HEAT_SPEED c̄_ij`; linear in `v_ij` between. The share is a continuous
/// function of the velocities, so round-off in a pair nearly at rest moves
/// it by round-off: a share read from the direction of `v_ij` alone turned
/// on round-off there, and runs lost their mirror symmetry.
#[inline]
pub fn heat_share(vr: f64, scale: f64) -> f64 {
    if scale > 0.0 {
        ((0.0 - vr) / scale).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The closing speed along the artificial stress's force, as a fraction of
/// the pair's mean sound speed, at which [`heat_share`] gives the whole
/// term (about 50 m/s in steel).
pub const HEAT_SPEED: f64 = 0.01;

/// [`heat_share`] for four pairs, one to a lane (bit-identical).
#[inline(always)]
pub fn heat_share_lanes(vr: F4, scale: F4) -> F4 {
    let share = ((F4::splat(0.0) - vr) / scale)
        .min(F4::splat(1.0))
        .max(F4::splat(0.0));
    F4::splat(0.0).lt(scale).select(share, F4::splat(0.0))
}

/// [`art_weight`] for four pairs, one to a lane: the same operations in
/// the same order (bit-identical); lanes outside the support hold values
/// for the caller to drop.
#[inline(always)]
pub fn art_weight_lanes(r2: F4, dp: F4, hij: F4, n: f64) -> F4 {
    let q2 = r2 / (hij * hij);
    let qd = dp / hij;
    let f = kernel::shape_lanes(q2.sqrt(), q2) / kernel::shape_lanes(qd, qd * qd);
    if n == 4.0 {
        let f2 = f * f;
        f2 * f2
    } else {
        F4::new(f.to_array().map(|f| f.powf(n)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Sym;
    use crate::physics::kernel;

    /// The close-pair gate: shut at and beyond the local spacing `V̄^(1/d)`,
    /// open fully from `CLOSE_FULL` of it in, linear in `(r/s)²` between,
    /// in 1-D (`s = V̄`) and 2-D (`s = √V̄`).
    #[test]
    fn close_gate_opens_inside_the_local_spacing() {
        for (dim, vol, s) in [(1, 2.0e-5, 2.0e-5), (2, 4.0e-10, 2.0e-5)] {
            let g = |r: f64| close_gate(r * r, vol, 1.0, dim);
            assert_eq!(g(s), 0.0);
            assert_eq!(g(1.5 * s), 0.0);
            assert_eq!(g(CLOSE_FULL * s * (1.0 - 1e-12)), 1.0);
            assert_eq!(g(0.5 * s), 1.0);
            let r = 0.975 * s;
            let want = (1.0 - 0.975f64.powi(2)) / (1.0 - CLOSE_FULL * CLOSE_FULL);
            assert!((g(r) - want).abs() < 1e-12, "{} against {want}", g(r));
            assert!(g(0.99 * s) > 0.0 && g(0.99 * s) < g(0.98 * s));
            // κ² scales the spacing: shut beyond κ s.
            assert_eq!(close_gate((0.91 * s).powi(2), vol, 0.81, dim), 0.0);
            assert_eq!(close_gate((0.85 * s).powi(2), vol, 0.81, dim), 1.0);
        }
    }

    /// The artificial stress without the principal angle is the angle
    /// form's (rotate to principal axes, keep `−ε σ̄/ρ²` of the tensile
    /// values, rotate back) on stresses with no, one and two tensile
    /// principal values, and where the two principal values meet.
    #[test]
    fn artificial_stress_is_the_principal_axes_form() {
        let angle_form = |eps: f64, s: &Sym, rho: f64| {
            let (a, b, th) = s.principal();
            let k = |v: f64| if v > 0.0 { -eps * v / (rho * rho) } else { 0.0 };
            Sym::from_principal(k(a), k(b), th)
        };
        let mut seen = [0usize; 3];
        for i in 0..400 {
            let u = |m: f64| ((i as f64 * m).fract() - 0.5) * 2.0e9;
            let mut s = Sym {
                xx: u(0.618_033_988_7),
                yy: u(0.414_213_562_3),
                xy: u(0.732_050_807_6) * 0.5,
                zz: u(0.236_067_977_5),
            };
            if i % 50 == 0 {
                (s.yy, s.xy) = (s.xx, 0.0);
            }
            let (a, b, _) = s.principal();
            seen[(a > 0.0) as usize + (b > 0.0) as usize] += 1;
            let (got, want) = (
                artificial_stress(0.3, &s, 7850.0),
                angle_form(0.3, &s, 7850.0),
            );
            let scale = 0.3 * 2.0e9 / (7850.0f64 * 7850.0);
            for (g, w) in [(got.xx, want.xx), (got.yy, want.yy), (got.xy, want.xy)] {
                assert!(
                    (g - w).abs() <= 1e-12 * scale,
                    "{s:?}: {got:?} against {want:?}"
                );
            }
            assert_eq!(got.zz, 0.0);
        }
        assert!(seen.iter().all(|&n| n > 50), "sign patterns {seen:?}");
    }

    /// The pair weight is `(W(r)/W(Δp))^n` from the kernel itself, inside
    /// and outside `q = 1`, with `n = 4` by squarings and other `n` by
    /// powers.
    #[test]
    fn art_weight_is_the_kernel_ratio() {
        let (dp, h) = (1.0e-5, 1.2e-5);
        for r in [0.0, 0.3e-5, 1.0e-5, 1.3e-5, 2.2e-5, 2.39e-5] {
            for n in [4.0, 3.5, 1.0] {
                let want = (kernel::w(2, r, h) / kernel::w(2, dp, h)).powf(n);
                let got = art_weight(r * r, dp, h, n);
                assert!((got - want).abs() <= 1e-13 * want.max(1.0), "r {r} n {n}");
            }
        }
        assert!((art_weight(dp * dp, dp, h, 4.0) - 1.0).abs() < 1e-14);
    }
}
