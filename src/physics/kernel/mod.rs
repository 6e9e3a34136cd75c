//! Cubic B-spline kernel, support `2h` (docs/method.md §3).

use std::ops::{Div, Mul};

use crate::math::lanes::F4;

/// Smallest singular value of the corrected gradient's matrix `M`
/// accepted (dimensionless: 1 inside a body, ≈ ½ at a face, 0.24–0.29 at
/// a lattice's corner, 0.3–0.44 in a strip two particles thick, for
/// smoothing ratios 1.2–1.5); below it a particle falls back to `L = I`.
/// It bounds `|L| = 1/σ_min` by 10: a chain or zig-zag of debris whose
/// `M` is nearly singular in one direction cannot stiffen its pairs
/// beyond what the step resolves (docs/method.md §5).
pub const CORRECTION_MIN_SINGULAR: f64 = 0.1;

/// Fewest same-body neighbours (partners within `2 h`, mirror images
/// across the axis included) a particle of a 2-D body keeps its corrected
/// gradient with, for the smoothing ratio `ratio = h/Δx`: two fewer than a
/// square lattice's corner has (7 at the default 1.2, so 5). No face,
/// corner or strip two particles thick of a lattice falls below it, while
/// a cluster of up to five particles torn off a body does, however
/// compact (docs/method.md, "Debris"). 0 (no floor) in 1-D.
pub fn debris_neighbours(dim: usize, ratio: f64) -> u32 {
    if dim != 2 || !(ratio.is_finite() && ratio > 0.0) {
        return 0;
    }
    // Beyond 64 the floor (thousands) means no correction anywhere; the
    // bound keeps the count's loop short for any input.
    let ratio = ratio.min(64.0);
    let r2 = 4.0 * ratio * ratio;
    let reach = (2.0 * ratio).ceil() as i64;
    let corner = (0..=reach)
        .flat_map(|i| (0..=reach).map(move |j| (i, j)))
        .filter(|&(i, j)| (i, j) != (0, 0) && ((i * i + j * j) as f64) < r2)
        .count() as u32;
    corner.saturating_sub(2)
}

/// `M⁻¹`, or `None` where `M`'s smallest singular value is below
/// [`CORRECTION_MIN_SINGULAR`] (or `M` is not finite).
#[inline]
pub fn correction_inverse(m: &crate::math::Mat2) -> Option<crate::math::Mat2> {
    if well_conditioned(m, CORRECTION_MIN_SINGULAR) {
        m.inverse(0.0)
    } else {
        None
    }
}

/// Smallest singular value of `M` below which [`fit_inverse`] takes
/// the rank-one pseudo-inverse.
pub const FIT_MIN_SINGULAR: f64 = 1e-3;

/// The inverse the least-squares fit of a linear field to the neighbours
/// takes (the hourglass control's `∇v`, docs/method.md): `M⁻¹` where the
/// smallest singular value is at least [`FIT_MIN_SINGULAR`], else the
/// rank-one pseudo-inverse `Mᵀ/|M|²` (zero for `M = 0`). Unlike
/// [`correction_inverse`] it never falls back to `I`: the fit's residuals
/// stay orthogonal to the fitted field, which is what makes the hourglass
/// control's work heat.
#[inline]
pub fn fit_inverse(m: &crate::math::Mat2) -> crate::math::Mat2 {
    use crate::math::Mat2;
    if well_conditioned(m, FIT_MIN_SINGULAR) {
        if let Some(l) = m.inverse(0.0) {
            return l;
        }
    }
    let f = m.xx * m.xx + m.xy * m.xy + m.yx * m.yx + m.yy * m.yy;
    if f > 0.0 && f.is_finite() {
        Mat2 {
            xx: m.xx / f,
            xy: m.yx / f,
            yx: m.xy / f,
            yy: m.yy / f,
        }
    } else {
        Mat2::ZERO
    }
}

/// Whether the 2×2 matrix `m` has both singular values at least `floor`:
/// with `F = |m|²` (Frobenius) and `D = det m`, `σ_min² = 2D² / (F +
/// √(F² − 4D²))`, a form without the cancellation of `(F − √…)/2`.
#[inline]
pub fn well_conditioned(m: &crate::math::Mat2, floor: f64) -> bool {
    let f = m.xx * m.xx + m.xy * m.xy + m.yx * m.yx + m.yy * m.yy;
    let d = m.det();
    let disc = (f * f - 4.0 * d * d).max(0.0).sqrt();
    // NaN compares false: a non-finite M falls back.
    2.0 * d * d >= floor * floor * (f + disc) && f.is_finite()
}

/// Normalisation `α_d` of the cubic spline in `dim` dimensions.
#[inline]
pub fn alpha(dim: usize, h: f64) -> f64 {
    match dim {
        1 => 2.0 / (3.0 * h),
        2 => 10.0 / (7.0 * std::f64::consts::PI * h * h),
        _ => 1.0 / (std::f64::consts::PI * h * h * h),
    }
}

/// `W(r, h)`.
#[inline]
pub fn w(dim: usize, r: f64, h: f64) -> f64 {
    let q = r / h;
    let f = if q < 1.0 {
        1.0 - 1.5 * q * q + 0.75 * q * q * q
    } else if q < 2.0 {
        let t = 2.0 - q;
        0.25 * t * t * t
    } else {
        0.0
    };
    alpha(dim, h) * f
}

/// `∂W/∂r (r, h)` (≤ 0).
#[inline]
pub fn dw(dim: usize, r: f64, h: f64) -> f64 {
    let q = r / h;
    let f = if q < 1.0 {
        -3.0 * q + 2.25 * q * q
    } else if q < 2.0 {
        let t = 2.0 - q;
        -0.75 * t * t
    } else {
        0.0
    };
    alpha(dim, h) * f / h
}

/// `α_d` from `1/h` (the pair loops' form, no division by `h`), for one
/// pair or for four in lanes: one formula, so [`w_grad`] and
/// [`grad_lanes`] round it alike.
#[inline(always)]
fn alpha_inv<T>(dim: usize, inv_h: T) -> T
where
    T: Copy + Mul<Output = T> + Div<f64, Output = T>,
    f64: Mul<T, Output = T>,
{
    use std::f64::consts::PI;
    const A1: f64 = 2.0 / 3.0;
    const A2: f64 = 10.0 / (7.0 * PI);
    match dim {
        1 => A1 * inv_h,
        2 => A2 * inv_h * inv_h,
        _ => inv_h * inv_h * inv_h / PI,
    }
}

/// `W` and `∇_i W` for the separation `d = x_i − x_j` (`r2 = |d|²`) at
/// smoothing length `1/inv_h`, or `None` beyond the support. The pair loops'
/// form: no division by `h`, and none by `r` inside `h`, where
/// `∂W/∂r / r` is a polynomial.
#[inline]
pub fn w_grad(dim: usize, d: glam::DVec2, r2: f64, inv_h: f64) -> Option<(f64, glam::DVec2)> {
    w_grad_q(dim, d, r2, inv_h).map(|(w, g, _)| (w, g))
}

/// [`w_grad`] with `q² = r²/h²` as well.
#[inline]
pub fn w_grad_q(
    dim: usize,
    d: glam::DVec2,
    r2: f64,
    inv_h: f64,
) -> Option<(f64, glam::DVec2, f64)> {
    let q2 = r2 * inv_h * inv_h;
    if q2 >= 4.0 {
        return None;
    }
    let q = q2.sqrt();
    let a = alpha_inv(dim, inv_h);
    let (f, g_q) = spline(q, q2);
    Some((a * f, d * (a * inv_h * inv_h * g_q), q2))
}

/// The spline `f(q)` and `(df/dq)/q` at `q` (`q2 = q²`, `q < 2`). Both
/// branches are computed and one is selected: whether a neighbour lies
/// inside q = 1 is a coin toss the branch predictor loses, and the select
/// compiles to blends. The outer form's division is by max(q, 1), the same
/// value wherever it is selected.
#[inline]
fn spline(q: f64, q2: f64) -> (f64, f64) {
    let t = 2.0 - q;
    let inner = q < 1.0;
    let f = if inner {
        1.0 - 1.5 * q2 + 0.75 * q2 * q
    } else {
        0.25 * t * t * t
    };
    let g_q = if inner {
        -3.0 + 2.25 * q
    } else {
        -0.75 * t * t / q.max(1.0)
    };
    (f, g_q)
}

/// `W`, `∇_i W` and `q²` for the separation `d = x_i − x_j` of two
/// particles with support metrics `qi` and `qj` ([`crate::physics::support`]),
/// or `None` beyond the support, and the normalisation `√det Q` of the
/// pair's metric. The pair's kernel is the spline in the
/// mean metric `Q = ½ (Q_i + Q_j)` (the round kernels' `1/h²` averaged):
/// `q² = dᵀ Q d`, `W = α_d √det Q f(q)`, `∇_i W = α_d √det Q (f'(q)/q) Q d`.
/// It is the same from either particle, and swapping them flips the
/// gradient; two round metrics of one `h` give [`w_grad`]'s kernel.
#[inline]
pub fn w_grad_pair(
    dim: usize,
    d: glam::DVec2,
    qi: &crate::physics::support::Metric,
    qj: &crate::physics::support::Metric,
) -> Option<(f64, glam::DVec2, f64, f64)> {
    let m = qi.mean(qj);
    let qd = m.apply(d);
    let q2 = d.dot(qd);
    if q2 >= 4.0 {
        return None;
    }
    let q = q2.sqrt();
    let a = alpha_inv(dim, 1.0) * m.scale(dim);
    let (f, g_q) = spline(q, q2);
    Some((a * f, qd * (a * g_q), q2, m.scale(dim)))
}

/// The Hessian of `W` for the separation `d` (`r2 = |d|²`) at smoothing
/// length `1/inv_h`, as `(s, t)` with `∇∇W = s I + t d dᵀ`, or `None` beyond
/// the support. `s` is `(∂W/∂r)/r` (the factor of [`w_grad`]) and `t` is
/// `(∂s/∂r)/r`; both are continuous at `q = 1`, where the cubic spline's
/// second derivative is. The spring's normals move with this
/// (docs/method.md, "The spring as the gradient of its stored energy").
#[inline]
pub fn hessian(dim: usize, r2: f64, inv_h: f64) -> Option<(f64, f64)> {
    let q2 = r2 * inv_h * inv_h;
    if q2 >= 4.0 || q2 == 0.0 {
        return None;
    }
    let q = q2.sqrt();
    let a = alpha_inv(dim, inv_h);
    let ih2 = inv_h * inv_h;
    let (g_q, dg_q) = if q < 1.0 {
        (-3.0 + 2.25 * q, 2.25 / q)
    } else {
        let t = 2.0 - q;
        (-0.75 * t * t / q, 0.75 * t * (2.0 + q) / (q2 * q))
    };
    Some((a * ih2 * g_q, a * ih2 * ih2 * dg_q))
}

/// The gradient of [`w_grad`] for four pairs from `q2 = r²/h²`, one to a
/// lane: `s` with `∇W = d s`. The same operations in the same order as
/// [`w_grad`] (bit-identical), its branch on `q < 1` a select; lanes with
/// `q2 ≥ 4` hold values for the caller to drop. `W` itself is left out:
/// the passes that run in lanes do not use it.
#[inline(always)]
pub fn grad_lanes(dim: usize, q2: F4, inv_h: F4) -> F4 {
    let q = q2.sqrt();
    let a = alpha_inv(dim, inv_h);
    let t = 2.0 - q;
    let inner = q.lt(F4::splat(1.0));
    let g_q = inner.select(-3.0 + 2.25 * q, -0.75 * t * t / q.max(F4::splat(1.0)));
    a * inv_h * inv_h * g_q
}

/// The metric part of [`w_grad_pair`] for four partners `js` of particle
/// `i`, one to a lane, at separations `(dx, dy)`: `q²`, the vector `Q d`
/// the gradient lies along, and the kernel's normalisation `√det Q` of
/// the pair's mean metric `Q`. The same operations in the same order
/// (bit-identical).
#[inline(always)]
pub fn pair_metric_lanes(
    dim: usize,
    metric: &[crate::physics::support::Metric],
    i: usize,
    js: &[usize; 4],
    dx: F4,
    dy: F4,
) -> (F4, F4, F4, F4) {
    let qi = &metric[i];
    let mxx = 0.5 * (qi.xx + F4::gather(|k| metric[js[k]].xx));
    let mxy = 0.5 * (qi.xy + F4::gather(|k| metric[js[k]].xy));
    let myy = 0.5 * (qi.yy + F4::gather(|k| metric[js[k]].yy));
    let (qdx, qdy) = (mxx * dx + mxy * dy, mxy * dx + myy * dy);
    let q2 = dx * qdx + dy * qdy;
    let scale = if dim == 1 {
        mxx.sqrt()
    } else {
        (mxx * myy - mxy * mxy).sqrt()
    };
    (q2, qdx, qdy, scale)
}

/// The factor of [`w_grad_pair`]'s gradient for four pairs, `α_d s
/// (f'(q)/q)` with `s` their normalisations ([`pair_metric_lanes`]), so
/// that `∇_i W` is `Q d` times it (bit-identical).
#[inline(always)]
pub fn grad_pair_lanes(dim: usize, q2: F4, scale: F4) -> F4 {
    let q = q2.sqrt();
    let a = alpha_inv(dim, 1.0) * scale;
    let t = 2.0 - q;
    let inner = q.lt(F4::splat(1.0));
    let g_q = inner.select(-3.0 + 2.25 * q, -0.75 * t * t / q.max(F4::splat(1.0)));
    a * g_q
}

/// The cubic spline's shape `f(q)` (`W = α_d f`) inside the support
/// (`q < 2`), from `q` and `q²`.
#[inline]
pub fn shape(q: f64, q2: f64) -> f64 {
    if q < 1.0 {
        1.0 - 1.5 * q2 + 0.75 * q2 * q
    } else {
        let t = 2.0 - q;
        0.25 * t * t * t
    }
}

/// [`shape`] for four values of `q`, one to a lane (bit-identical, the
/// branch a select).
#[inline(always)]
pub fn shape_lanes(q: F4, q2: F4) -> F4 {
    let t = 2.0 - q;
    q.lt(F4::splat(1.0))
        .select(1.0 - 1.5 * q2 + 0.75 * q2 * q, 0.25 * t * t * t)
}

/// The 2-D kernel integrated along a straight line through its centre,
/// `∫ W dx = 15 / (7 π h)`: the numerator of the kernel measure of a boundary
/// line (docs/method.md §8.4, contact area).
#[inline]
pub fn line_integral_2d(h: f64) -> f64 {
    15.0 / (7.0 * std::f64::consts::PI * h)
}

#[cfg(test)]
mod tests;
