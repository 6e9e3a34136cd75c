//! Cubic B-spline kernel, support `2h` (METHOD.md §3).

use crate::cpu::lanes::F4;

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
    let a = match dim {
        1 => (2.0 / 3.0) * inv_h,
        2 => 10.0 / (7.0 * std::f64::consts::PI) * inv_h * inv_h,
        _ => inv_h * inv_h * inv_h / std::f64::consts::PI,
    };
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

/// The gradient of [`w_grad`] for four pairs from `q2 = r²/h²`, one to a
/// lane: `s` with `∇W = d s`. The same operations in the same order as
/// [`w_grad`] (bit-identical), its branch on `q < 1` a select; lanes with
/// `q2 ≥ 4` hold values for the caller to drop. `W` itself is left out:
/// the passes that run in lanes do not use it.
#[inline(always)]
pub fn grad_lanes(dim: usize, q2: F4, inv_h: F4) -> F4 {
    let q = q2.sqrt();
    let a = match dim {
        1 => (2.0 / 3.0) * inv_h,
        2 => 10.0 / (7.0 * std::f64::consts::PI) * inv_h * inv_h,
        _ => inv_h * inv_h * inv_h / std::f64::consts::PI,
    };
    let t = 2.0 - q;
    let inner = q.lt(F4::splat(1.0));
    let g_q = inner.select(-3.0 + 2.25 * q, -0.75 * t * t / q.max(F4::splat(1.0)));
    a * inv_h * inv_h * g_q
}

/// The 2-D kernel integrated along a straight line through its centre,
/// `∫ W dx = 15 / (7 π h)`: the numerator of the kernel measure of a boundary
/// line (METHOD.md §8.4, contact area).
#[inline]
pub fn line_integral_2d(h: f64) -> f64 {
    15.0 / (7.0 * std::f64::consts::PI * h)
}

#[cfg(test)]
mod tests {
    use super::*;

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
