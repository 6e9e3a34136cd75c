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
