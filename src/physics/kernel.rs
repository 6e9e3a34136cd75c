//! Cubic B-spline kernel, support `2h` (docs/method.md §3).

use std::ops::{Div, Mul};

use crate::math::lanes::F4;

/// Smallest `|det M|` accepted for the corrected gradient's matrix `M`
/// (dimensionless: ≈ I inside a body, ≈ ½ at a face, ≈ ¼ at a corner);
/// below it a particle falls back to `L = I`.
pub const CORRECTION_MIN_DET: f64 = 1e-3;

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
    let q2 = r2 * inv_h * inv_h;
    if q2 >= 4.0 {
        return None;
    }
    let q = q2.sqrt();
    let a = alpha_inv(dim, inv_h);
    // f(q) and (df/dq)/q. Both branches are computed and one is selected:
    // whether a neighbour lies inside q = 1 is a coin toss the branch
    // predictor loses, and the select compiles to blends. The outer form's
    // division is by max(q, 1), the same value wherever it is selected.
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
    Some((a * f, d * (a * inv_h * inv_h * g_q)))
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
mod tests {
    use super::*;

    /// The Hessian is the derivative of `w_grad`'s gradient, checked by
    /// central differences inside and outside `q = 1` in 1-D and 2-D.
    #[test]
    fn hessian_is_the_gradients_derivative() {
        let inv_h = 1.0 / 0.7;
        for dim in [1, 2] {
            for d in [
                glam::DVec2::new(0.31, 0.17),
                glam::DVec2::new(-0.52, 0.61),
                glam::DVec2::new(0.9, -0.65),
                glam::DVec2::new(0.05, 0.0),
            ] {
                let (s, t) = hessian(dim, d.length_squared(), inv_h).unwrap();
                let eps = 1e-6;
                for e in [glam::DVec2::X, glam::DVec2::Y] {
                    let g = |x: glam::DVec2| w_grad(dim, x, x.length_squared(), inv_h).unwrap().1;
                    let fd = (g(d + e * eps) - g(d - e * eps)) / (2.0 * eps);
                    let exact = e * s + d * (t * d.dot(e));
                    assert!(
                        (fd - exact).length() < 1e-6 * (1.0 + exact.length()),
                        "dim {dim} d {d} e {e}: {fd} vs {exact}"
                    );
                }
            }
            assert!(hessian(dim, 4.0 / (inv_h * inv_h), inv_h).is_none());
        }
    }

    /// The lanes' gradient is `w_grad`'s bit for bit in 1-, 2- and 3-D,
    /// inside and outside `q = 1`, at the support's edge, and with
    /// smoothing lengths that differ from lane to lane.
    #[test]
    fn grad_lanes_is_w_grad_bit_for_bit() {
        let inv_h = [1.0 / 0.7, 1.0 / 1.3e-4, 3.0, 1.0 / 2.5e-5];
        for dim in 1..=3 {
            for step in 0..400 {
                // r from 0 to just under 2h, with an irrational spacing so
                // that the values do not land on simple fractions.
                let q: [f64; 4] = std::array::from_fn(|k| {
                    ((step as f64 + 0.25 * k as f64) * 0.004_987_654_3).min(1.999_999)
                });
                let d: [glam::DVec2; 4] = std::array::from_fn(|k| {
                    let r = q[k] / inv_h[k];
                    glam::DVec2::new(0.6 * r, -0.8 * r)
                });
                let q2: [f64; 4] =
                    std::array::from_fn(|k| d[k].length_squared() * inv_h[k] * inv_h[k]);
                let s = grad_lanes(dim, F4::new(q2), F4::new(inv_h)).to_array();
                for k in 0..4 {
                    let (_, g) = w_grad(dim, d[k], d[k].length_squared(), inv_h[k])
                        .expect("inside the support");
                    let lane = d[k] * s[k];
                    assert_eq!(g.x.to_bits(), lane.x.to_bits(), "dim {dim}, q {}", q[k]);
                    assert_eq!(g.y.to_bits(), lane.y.to_bits(), "dim {dim}, q {}", q[k]);
                }
            }
        }
    }

    /// ∫ W dV = 1 in 1-D and 2-D (midpoint rule on a fine grid).
    #[test]
    fn normalised() {
        let h = 0.7;
        let n = 4000;
        let d = 4.0 * h / n as f64;
        let s1: f64 = (0..n)
            .map(|i| w(1, (-2.0 * h + (i as f64 + 0.5) * d).abs(), h) * d)
            .sum();
        assert!((s1 - 1.0).abs() < 1e-6, "1-D integral {s1}");
        let m = 800;
        let d2 = 4.0 * h / m as f64;
        let mut s2 = 0.0;
        for i in 0..m {
            for j in 0..m {
                let x = -2.0 * h + (i as f64 + 0.5) * d2;
                let y = -2.0 * h + (j as f64 + 0.5) * d2;
                s2 += w(2, (x * x + y * y).sqrt(), h) * d2 * d2;
            }
        }
        assert!((s2 - 1.0).abs() < 1e-4, "2-D integral {s2}");
        // The line integral used for the boundary measure.
        let l: f64 = (0..n)
            .map(|i| w(2, (-2.0 * h + (i as f64 + 0.5) * d).abs(), h) * d)
            .sum();
        assert!((l - line_integral_2d(h)).abs() < 1e-6 * l);
        // The pair-loop form agrees with the plain one.
        for k in 0..=50 {
            let d = glam::DVec2::new(0.6, -0.8) * (2.1 * h * k as f64 / 50.0);
            let r = d.length();
            for dim in [1, 2] {
                match w_grad(dim, d, d.length_squared(), 1.0 / h) {
                    None => assert!(r >= 2.0 * h * (1.0 - 1e-15), "cut at {r}"),
                    Some((a, g)) => {
                        let scale = alpha(dim, h);
                        assert!((a - w(dim, r, h)).abs() <= 1e-14 * scale);
                        let exact = if r > 0.0 { d * (dw(dim, r, h) / r) } else { d };
                        assert!((g - exact).length() <= 1e-13 * scale / h, "{r}");
                    }
                }
            }
        }
    }

    /// dW/dr is the derivative of W (central differences), continuous at q = 1, 2.
    #[test]
    fn derivative_matches() {
        let h = 1.3;
        for k in 1..200 {
            let r = k as f64 * 0.0131;
            let e = 1e-6;
            let fd = (w(2, r + e, h) - w(2, r - e, h)) / (2.0 * e);
            assert!(
                (fd - dw(2, r, h)).abs() < 1e-6,
                "r = {r}: {fd} vs {}",
                dw(2, r, h)
            );
        }
        assert_eq!(w(2, 2.0 * h, h), 0.0);
        assert_eq!(dw(2, 2.0 * h, h), 0.0);
    }
}
