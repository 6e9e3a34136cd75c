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
mod tests {
    use super::*;
    use crate::math::Mat2;
    use crate::physics::support::Metric;

    /// The floor is a square lattice's corner count less two: 3, 7, 8 and
    /// 14 corner neighbours at h/Δx = 1, 1.2, 1.5 and 2.
    #[test]
    fn debris_floor_follows_the_corner() {
        let floors: Vec<u32> = [1.0, 1.2, 1.5, 2.0]
            .iter()
            .map(|&r| debris_neighbours(2, r))
            .collect();
        assert_eq!(floors, [1, 5, 6, 12]);
        assert_eq!(debris_neighbours(1, 1.2), 0);
        assert!(debris_neighbours(2, 1e30) > 10_000);
    }

    /// `M_i` of particle `i` among `pts` (unit spacing and volume).
    fn m_of(pts: &[glam::DVec2], i: usize, h: f64) -> Mat2 {
        let mut m = Mat2::default();
        for (j, &xj) in pts.iter().enumerate() {
            let d = xj - pts[i];
            let r = d.length();
            if j == i || r >= 2.0 * h {
                continue;
            }
            let g = -d * (dw(2, r, h) / r);
            m.xx += g.x * d.x;
            m.xy += g.x * d.y;
            m.yx += g.y * d.x;
            m.yy += g.y * d.y;
        }
        m
    }

    /// The correction's guard against the singular values found by
    /// brute force (the smaller of |M u| over unit u): a regular lattice's
    /// faces, corners and a strip two particles thick keep their
    /// correction at smoothing ratios 1.2 to 1.5, and bit for bit (`L` is
    /// `M⁻¹` as before); a zig-zag chain of four, whose determinant alone
    /// passes 1e-3, and a single row fall back.
    #[test]
    fn the_correction_guards_the_smallest_singular_value() {
        let lattice = |nx: i32, ny: i32| -> Vec<glam::DVec2> {
            (0..nx)
                .flat_map(|x| (0..ny).map(move |y| glam::DVec2::new(x as f64, y as f64)))
                .collect()
        };
        let at = |pts: &[glam::DVec2], x: f64, y: f64| {
            pts.iter()
                .position(|p| *p == glam::DVec2::new(x, y))
                .unwrap()
        };
        let sigma_min = |m: &Mat2| {
            (0..20000)
                .map(|k| {
                    let a = k as f64 * std::f64::consts::PI / 20000.0;
                    m.mul_vec(glam::DVec2::new(a.cos(), a.sin())).length()
                })
                .fold(f64::INFINITY, f64::min)
        };
        for ratio in [1.2, 1.5] {
            let block = lattice(12, 12);
            let strip = lattice(25, 2);
            let row = lattice(25, 1);
            let zig: Vec<glam::DVec2> = (0..4)
                .map(|k| glam::DVec2::new(k as f64, 0.3 * (k % 2) as f64))
                .collect();
            let cases = [
                ("corner", &block, at(&block, 0.0, 0.0), true),
                ("face", &block, at(&block, 0.0, 5.0), true),
                ("next to a corner", &block, at(&block, 1.0, 0.0), true),
                ("inside", &block, at(&block, 5.0, 5.0), true),
                ("strip of two", &strip, at(&strip, 12.0, 0.0), true),
                ("row", &row, at(&row, 12.0, 0.0), false),
                ("zig-zag end", &zig, 0, false),
                ("zig-zag middle", &zig, 1, false),
            ];
            for (name, pts, i, keeps) in cases {
                let m = m_of(pts, i, ratio);
                let s = sigma_min(&m);
                let ok = correction_inverse(&m);
                assert_eq!(ok.is_some(), keeps, "{name} at ratio {ratio}: σ_min {s}");
                assert!(
                    s < 1e-12 || well_conditioned(&m, 0.999 * s),
                    "{name}: σ_min {s} just below"
                );
                assert!(
                    !well_conditioned(&m, 1.001 * s + 1e-12),
                    "{name}: σ_min {s} just above"
                );
                if let Some(l) = ok {
                    assert_eq!(l, m.inverse(0.0).unwrap(), "{name}: L is M⁻¹");
                }
            }
            // The zig-zag's middle passes the old determinant floor.
            assert!(m_of(&zig, 1, ratio).det().abs() > 1e-3);
        }
    }

    /// The pair kernel of two support metrics: with two round metrics of
    /// one `h` it is the round kernel; its gradient is the derivative of
    /// `W` in `x_i` (central differences, an anisotropic pair, inside and
    /// outside `q = 1`); swapping the particles flips it; and its support
    /// is the mean metric's ellipse, which reaches beyond the smaller of
    /// the two particles' own.
    #[test]
    fn pair_kernel_of_two_metrics() {
        let h = 1.2e-3;
        let round = Metric::round(h);
        for d in [
            glam::DVec2::new(4e-4, -7e-4),
            glam::DVec2::new(1.5e-3, 1e-3),
        ] {
            for dim in [1, 2] {
                let d = if dim == 1 {
                    glam::DVec2::new(d.x, 0.0)
                } else {
                    d
                };
                let (w0, g0) = w_grad(dim, d, d.length_squared(), 1.0 / h).expect("inside");
                let (w, g, _, _) = w_grad_pair(dim, d, &round, &round).expect("inside");
                assert!((w / w0 - 1.0).abs() < 1e-14, "{w} against {w0}");
                assert!((g - g0).length() < 1e-14 * g0.length(), "{g} against {g0}");
            }
        }
        // Stretched along (0.8, 0.6) and squeezed across, and a rounder one.
        let qi = Metric {
            xx: 0.5e6,
            xy: -0.2e6,
            yy: 0.9e6,
        };
        let qj = Metric {
            xx: 0.6e6,
            xy: 0.0,
            yy: 0.7e6,
        };
        for d in [
            glam::DVec2::new(4e-4, 3e-4),
            glam::DVec2::new(-1.2e-3, 1.5e-3),
            glam::DVec2::new(2.0e-3, 0.5e-3),
        ] {
            let (_, g, q2, _) = w_grad_pair(2, d, &qi, &qj).expect("inside");
            assert!(q2 < 4.0);
            let e = 1e-9;
            let w = |d: glam::DVec2| w_grad_pair(2, d, &qi, &qj).map_or(0.0, |t| t.0);
            let fd = glam::DVec2::new(
                (w(d + glam::DVec2::X * e) - w(d - glam::DVec2::X * e)) / (2.0 * e),
                (w(d + glam::DVec2::Y * e) - w(d - glam::DVec2::Y * e)) / (2.0 * e),
            );
            assert!(
                (g - fd).length() < 1e-6 * g.length(),
                "{g} against {fd} at {d}"
            );
            let (_, gj, _, _) = w_grad_pair(2, -d, &qj, &qi).expect("inside");
            assert_eq!(gj, -g);
        }
        let between = glam::DVec2::new(0.0, 2.2e-3);
        assert!(qi.quad(between) >= 4.0 && qj.quad(between) < 4.0);
        assert!(qi.mean(&qj).quad(between) < 4.0);
        assert!(w_grad_pair(2, between, &qi, &qj).is_some());
        let far = glam::DVec2::new(0.0, 2.3e-3);
        assert!(qi.mean(&qj).quad(far) >= 4.0 && qj.quad(far) < 4.0);
        assert!(w_grad_pair(2, far, &qi, &qj).is_none());
    }

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
