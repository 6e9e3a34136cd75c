//! Surface offsets of particles given without an outline (a particles
//! file): the distance from each particle to its body's surface, found
//! from the particles themselves (docs/method.md §8.3).
//!
//! A particle at distance `d` inside a flat surface, in a body of uniform
//! particle volumes, has the kernel volume fraction
//! `ψ = Σ_j V_j W_ij = F(d)` (itself included), `F` the kernel's integral
//! over the half-space in front of the surface: `F(0) = ½`, `F(2h) = 1`.
//! The offset is `F⁻¹(ψ_i)`, less the bias of the lattice sum at a face
//! (so that a lattice's particles, half a spacing inside a flat face, get
//! half a spacing back); on a curved face it follows the curvature the
//! particles draw, at the kernel's scale. Where fewer neighbours than a half space surround a particle
//! (`ψ < ½`, a convex corner), the offset is 0: the particle is on the
//! surface.

use glam::DVec2;

use crate::math::cells::CellList;
use crate::physics::kernel;

/// Steps of the table of `F` over `[0, 2h]`.
const STEPS: usize = 400;

/// `F(d)`, the kernel (`h`, `dim` 1 or 2) integrated over the half-space
/// beyond a plane at distance `d` behind its centre, tabulated at
/// `d_k = 2h k / STEPS` as `(d_k, F(d_k))`: `F = ½ + ∫_0^d L(s) ds`, `L`
/// the kernel integrated over the line (2-D) or point (1-D) at distance
/// `s` from the centre, summed interval by interval by Simpson's rule.
/// The integrands are piecewise cubic, so the error is far below the
/// estimate's own.
fn fraction_table(h: f64, dim: usize) -> Vec<(f64, f64)> {
    let simpson = |f: &dyn Fn(f64) -> f64, a: f64, b: f64, n: usize| {
        let step = (b - a) / n as f64;
        let mut sum = f(a) + f(b);
        for k in 1..n {
            sum += f(a + k as f64 * step) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        sum * step / 3.0
    };
    let line = |s: f64| -> f64 {
        if dim == 1 {
            kernel::w(1, s, h)
        } else {
            let half = (4.0 * h * h - s * s).max(0.0).sqrt();
            2.0 * simpson(
                &|y: f64| kernel::w(2, (s * s + y * y).sqrt(), h),
                0.0,
                half,
                200,
            )
        }
    };
    let step = 2.0 * h / STEPS as f64;
    let mut table = Vec::with_capacity(STEPS + 1);
    let mut f = 0.5;
    table.push((0.0, f));
    for k in 0..STEPS {
        let a = k as f64 * step;
        f += simpson(&line, a, a + step, 2);
        table.push((a + step, f));
    }
    table
}

/// `F(d)` from the table, linear between its entries.
fn fraction_at(table: &[(f64, f64)], d: f64) -> f64 {
    let k = table
        .partition_point(|&(dk, _)| dk < d)
        .clamp(1, table.len() - 1);
    let (d0, f0) = table[k - 1];
    let (d1, f1) = table[k];
    f0 + (f1 - f0) * (d - d0) / (d1 - d0)
}

/// The offset `F⁻¹(ψ)` from the table (linear between its entries): 0
/// below `F(0) = ½`, `2h` above `F(2h)`.
fn offset_of(psi: f64, table: &[(f64, f64)]) -> f64 {
    if psi <= table[0].1 {
        return 0.0;
    }
    let last = table[table.len() - 1];
    if psi >= last.1 {
        return last.0;
    }
    let k = table.partition_point(|&(_, f)| f < psi);
    let (d0, f0) = table[k - 1];
    let (d1, f1) = table[k];
    d0 + (d1 - d0) * (psi - f0) / (f1 - f0)
}

/// `ψ` of a particle of a square lattice of spacing `s` filling the half
/// space beyond a face half a spacing behind it: a lattice's face
/// particle. The lattice sum exceeds `F(s/2)` by about 0.02 at
/// `h = 1.2 s` (the face cuts the kernel, so the sum's errors no longer
/// cancel as they do inside), which alone would put a face particle
/// 0.08 s too deep.
fn lattice_face_fraction(s: f64, h: f64, dim: usize) -> f64 {
    let reach = (2.0 * h / s).ceil() as i64 + 1;
    let (rows, vol) = if dim == 1 {
        (0..1, s)
    } else {
        (-reach..reach + 1, s * s)
    };
    let mut psi = 0.0;
    for j in rows {
        for i in 0..=reach {
            let r = DVec2::new(i as f64, j as f64).length() * s;
            psi += vol * kernel::w(dim, r, h);
        }
    }
    psi
}

/// Each particle's surface offset from its kernel volume fraction among
/// `x` (one body's particles, volumes `vol`, smoothing length `h`). The
/// lattice sum's bias at a face (`lattice_face_fraction`, at the median
/// spacing) is taken off `ψ`, so that a lattice's face particles come out
/// half a spacing in.
pub fn offsets(x: &[DVec2], vol: &[f64], h: f64, dim: usize) -> Vec<f64> {
    let table = fraction_table(h, dim);
    let mut sides: Vec<f64> = vol
        .iter()
        .map(|&v| if dim == 1 { v } else { v.sqrt() })
        .collect();
    sides.sort_by(f64::total_cmp);
    let s = sides[sides.len() / 2];
    let bias = lattice_face_fraction(s, h, dim) - fraction_at(&table, 0.5 * s);
    let cells = CellList::build(x, 2.0 * h);
    (0..x.len())
        .map(|i| {
            let mut psi = 0.0;
            cells.for_each_near(x[i], dim, |j| {
                psi += vol[j] * kernel::w(dim, x[i].distance(x[j]), h);
            });
            offset_of(psi - bias, &table)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `F` runs from ½ at the face to 1 at the support's edge, in 1-D
    /// and 2-D.
    #[test]
    fn the_half_space_fraction_spans_half_to_one() {
        for dim in [1, 2] {
            let h = 1.3e-4;
            let table = fraction_table(h, dim);
            assert_eq!(table[0], (0.0, 0.5));
            assert!((table[STEPS].1 - 1.0).abs() < 1e-9);
            assert!(table.windows(2).all(|w| w[1].1 > w[0].1), "increasing");
            assert!((fraction_at(&table, 2.0 * h) - 1.0).abs() < 1e-9);
        }
    }

    /// A square block on the square lattice: the particles of a face get
    /// half a spacing, within 2 % of the spacing; the interior ones more
    /// than h; a corner one less than a face one.
    #[test]
    fn a_blocks_faces_are_half_a_spacing_in() {
        let dx = 1e-4;
        let h = 1.3 * dx;
        let n = 20;
        let x: Vec<DVec2> = (0..n * n)
            .map(|k| DVec2::new((k % n) as f64 + 0.5, (k / n) as f64 + 0.5) * dx)
            .collect();
        let o = offsets(&x, &vec![dx * dx; x.len()], h, 2);
        let at = |i: usize, j: usize| o[j * n + i];
        for k in 4..n - 4 {
            assert!((at(0, k) - 0.5 * dx).abs() < 0.02 * dx, "face {}", at(0, k));
            assert!((at(k, n - 1) - 0.5 * dx).abs() < 0.02 * dx);
        }
        // Deep inside, far from any contact.
        assert!(at(n / 2, n / 2) > h, "interior {}", at(n / 2, n / 2));
        assert!(at(0, 0) < at(0, n / 2));
        // 1-D: a segment's end particle, half a spacing in.
        let x: Vec<DVec2> = (0..30)
            .map(|k| DVec2::new((k as f64 + 0.5) * dx, 0.0))
            .collect();
        let o = offsets(&x, &vec![dx; 30], h, 1);
        assert!((o[0] - 0.5 * dx).abs() < 0.02 * dx, "end {}", o[0]);
    }
}
