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
            let q2: [f64; 4] = std::array::from_fn(|k| d[k].length_squared() * inv_h[k] * inv_h[k]);
            let s = grad_lanes(dim, F4::new(q2), F4::new(inv_h)).to_array();
            for k in 0..4 {
                let (_, g) =
                    w_grad(dim, d[k], d[k].length_squared(), inv_h[k]).expect("inside the support");
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
