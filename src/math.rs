//! Small 2×2 tensors for the 2-D (and, with zero y, the 1-D) solver.

pub mod cells;
pub mod lanes;

use glam::DVec2;

/// Lower and upper corners of the box around `points` (infinite, inside
/// out, when there are none).
pub fn bounds<'a>(points: impl IntoIterator<Item = &'a DVec2>) -> (DVec2, DVec2) {
    points.into_iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

/// The circumference `2π r` of the circle at radius `r`: what a point of
/// the r–z plane of a body of revolution stands for (a particle's ring
/// mass is it times its mass per unit thickness, `η = 2π r ρ`).
#[inline]
pub fn circumference(r: f64) -> f64 {
    2.0 * std::f64::consts::PI * r
}

/// The mirror image of a point or a velocity: `(r, z) → (−r, z)`.
#[inline]
pub fn mirror(x: DVec2) -> DVec2 {
    DVec2::new(-x.x, x.y)
}

/// A mirror image across lines normal to the coordinate axes: the axis
/// of a body of revolution (`r = 0`), a symmetry plane (`[[symmetry]]`),
/// or both at once (the image across the corner they make). Positions
/// reflect across each line; vectors reverse each component a line is
/// normal to; a tensor's off-diagonal entries reverse across one line
/// (`P T P` with `P = diag(−1, 1)` or `diag(1, −1)`) and not across two
/// (`P = −I`): [`Mirror::shears`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mirror {
    /// Which coordinates the image reverses.
    pub flip: [bool; 2],
    /// Where each reversed coordinate's line lies, m.
    pub at: [f64; 2],
}

impl Mirror {
    /// The axis `r = 0` of a body of revolution.
    pub const AXIS: Mirror = Mirror {
        flip: [true, false],
        at: [0.0, 0.0],
    };

    /// The reflection across the line where coordinate `axis` is `at`.
    pub fn across(axis: usize, at: f64) -> Mirror {
        let mut m = Mirror {
            flip: [false; 2],
            at: [0.0; 2],
        };
        m.flip[axis] = true;
        m.at[axis] = at;
        m
    }

    /// The images a particle has across `axis` (a body of revolution's)
    /// and `planes` (each reversing its own coordinate): each mirror's,
    /// then each pair's composition (the corner's), axis first.
    pub fn images(axis: Option<Mirror>, planes: &[Mirror]) -> Vec<Mirror> {
        let lines: Vec<Mirror> = axis.into_iter().chain(planes.iter().copied()).collect();
        let mut out = lines.clone();
        if let [a, b] = lines[..] {
            out.push(a.then(&b));
        }
        out
    }

    /// This image reflected again across `o`'s lines (lines normal to
    /// other axes than this one's).
    pub fn then(&self, o: &Mirror) -> Mirror {
        let mut m = *self;
        for k in 0..2 {
            if o.flip[k] {
                m.flip[k] = true;
                m.at[k] = o.at[k];
            }
        }
        m
    }

    /// The mirror image of a point.
    #[inline]
    pub fn point(&self, x: DVec2) -> DVec2 {
        // Through 0 the image is the plain negation ([`mirror`]'s bits).
        let r = |k: usize, c: f64| match (self.flip[k], self.at[k]) {
            (false, _) => c,
            (true, 0.0) => -c,
            (true, a) => 2.0 * a - c,
        };
        DVec2::new(r(0, x.x), r(1, x.y))
    }

    /// The mirror image of a vector (a velocity, a force).
    #[inline]
    pub fn vector(&self, v: DVec2) -> DVec2 {
        let s = |k: usize, c: f64| if self.flip[k] { -c } else { c };
        DVec2::new(s(0, v.x), s(1, v.y))
    }

    /// Whether the image reverses a tensor's off-diagonal entries (across
    /// one line, not across two).
    #[inline]
    pub fn shears(&self) -> bool {
        self.flip[0] != self.flip[1]
    }

    /// The mirror image of a tensor.
    #[inline]
    pub fn mat(&self, m: &Mat2) -> Mat2 {
        if self.shears() {
            mirror_mat(m)
        } else {
            *m
        }
    }

    /// The mirror image of a symmetric tensor.
    #[inline]
    pub fn sym(&self, s: &Sym) -> Sym {
        if self.shears() {
            mirror_sym(s)
        } else {
            *s
        }
    }

    /// Whether `x` lies within `reach` of every line of the image (an
    /// image lies at least that far from its particle's neighbours).
    #[inline]
    pub fn within(&self, x: DVec2, reach: f64) -> bool {
        (0..2).all(|k| !self.flip[k] || (x[k] - self.at[k]).abs() < reach)
    }
}

/// The mirror image of a tensor `T`: `P T P` with `P = diag(−1, 1)`.
#[inline]
pub fn mirror_mat(m: &Mat2) -> Mat2 {
    Mat2 {
        xx: m.xx,
        xy: -m.xy,
        yx: -m.yx,
        yy: m.yy,
    }
}

/// The mirror image of a symmetric tensor (the `rz` entry reversed).
#[inline]
pub fn mirror_sym(s: &Sym) -> Sym {
    Sym { xy: -s.xy, ..*s }
}

/// A general 2×2 matrix, row-major names: `m[α][β]` = `aβ`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Mat2 {
    pub xx: f64,
    pub xy: f64,
    pub yx: f64,
    pub yy: f64,
}

impl Mat2 {
    pub const IDENTITY: Mat2 = Mat2 {
        xx: 1.0,
        xy: 0.0,
        yx: 0.0,
        yy: 1.0,
    };
    pub const ZERO: Mat2 = Mat2 {
        xx: 0.0,
        xy: 0.0,
        yx: 0.0,
        yy: 0.0,
    };

    /// `a ⊗ b`, i.e. `(a ⊗ b)_{αβ} = a_α b_β`.
    #[inline]
    pub fn outer(a: DVec2, b: DVec2) -> Mat2 {
        Mat2 {
            xx: a.x * b.x,
            xy: a.x * b.y,
            yx: a.y * b.x,
            yy: a.y * b.y,
        }
    }

    #[inline]
    pub fn mul_vec(&self, v: DVec2) -> DVec2 {
        DVec2::new(self.xx * v.x + self.xy * v.y, self.yx * v.x + self.yy * v.y)
    }

    #[inline]
    pub fn det(&self) -> f64 {
        self.xx * self.yy - self.xy * self.yx
    }

    #[inline]
    pub fn trace(&self) -> f64 {
        self.xx + self.yy
    }

    /// The inverse, or `None` when `|det| <= tiny` or not finite.
    #[inline]
    pub fn inverse(&self, tiny: f64) -> Option<Mat2> {
        let d = self.det();
        if !d.is_finite() || d.abs() <= tiny {
            return None;
        }
        let r = 1.0 / d;
        Some(Mat2 {
            xx: self.yy * r,
            xy: -self.xy * r,
            yx: -self.yx * r,
            yy: self.xx * r,
        })
    }

    /// The velocity gradient `G` taken at positions `c·v` ahead of where
    /// it is wanted, mapped back there: `∂v/∂x₀ = G (I + c ∂v/∂x₀)`, so
    /// `G₀ = (I − cG)⁻¹ G = (G − c det G · I) / det(I − cG)`, with
    /// `det(I − cG) = 1 − c tr G + c² det G` (Cayley–Hamilton). Exact for
    /// an affine field. `None` where `det(I − cG) ≤ 0`: the motion over
    /// `c` would have folded the neighbourhood, and no gradient maps it.
    #[inline]
    pub fn gradient_behind(&self, c: f64) -> Option<Mat2> {
        let cd = c * self.det();
        let den = 1.0 - c * self.trace() + c * cd;
        (den > 0.0).then(|| {
            let r = 1.0 / den;
            Mat2 {
                xx: (self.xx - cd) * r,
                xy: self.xy * r,
                yx: self.yx * r,
                yy: (self.yy - cd) * r,
            }
        })
    }

    /// `self · bᵀ`.
    #[inline]
    pub fn mul_transpose(&self, b: &Mat2) -> Mat2 {
        Mat2 {
            xx: self.xx * b.xx + self.xy * b.xy,
            xy: self.xx * b.yx + self.xy * b.yy,
            yx: self.yx * b.xx + self.yy * b.xy,
            yy: self.yx * b.yx + self.yy * b.yy,
        }
    }

    #[inline]
    pub fn scale(&self, s: f64) -> Mat2 {
        Mat2 {
            xx: self.xx * s,
            xy: self.xy * s,
            yx: self.yx * s,
            yy: self.yy * s,
        }
    }
}

impl std::ops::Add for Mat2 {
    type Output = Mat2;
    #[inline]
    fn add(self, o: Mat2) -> Mat2 {
        Mat2 {
            xx: self.xx + o.xx,
            xy: self.xy + o.xy,
            yx: self.yx + o.yx,
            yy: self.yy + o.yy,
        }
    }
}

impl std::ops::Sub for Mat2 {
    type Output = Mat2;
    #[inline]
    fn sub(self, o: Mat2) -> Mat2 {
        Mat2 {
            xx: self.xx - o.xx,
            xy: self.xy - o.xy,
            yx: self.yx - o.yx,
            yy: self.yy - o.yy,
        }
    }
}

impl std::ops::AddAssign for Mat2 {
    #[inline]
    fn add_assign(&mut self, o: Mat2) {
        *self = *self + o;
    }
}

impl std::ops::SubAssign for Mat2 {
    #[inline]
    fn sub_assign(&mut self, o: Mat2) {
        *self = *self - o;
    }
}

/// A symmetric in-plane stress-like tensor plus its out-of-plane `zz`
/// component (plane strain carries `s_zz`; docs/method.md §6).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Sym {
    pub xx: f64,
    pub yy: f64,
    pub xy: f64,
    pub zz: f64,
}

impl Sym {
    #[inline]
    pub fn mul_vec(&self, v: DVec2) -> DVec2 {
        DVec2::new(self.xx * v.x + self.xy * v.y, self.xy * v.x + self.yy * v.y)
    }

    /// `s : s` over all three dimensions.
    #[inline]
    pub fn ddot(&self) -> f64 {
        self.xx * self.xx + self.yy * self.yy + self.zz * self.zz + 2.0 * self.xy * self.xy
    }

    /// Von Mises equivalent of a deviatoric tensor, `sqrt(3/2 s:s)`.
    #[inline]
    pub fn von_mises(&self) -> f64 {
        (1.5 * self.ddot()).sqrt()
    }

    #[inline]
    pub fn scale(&self, k: f64) -> Sym {
        Sym {
            xx: self.xx * k,
            yy: self.yy * k,
            xy: self.xy * k,
            zz: self.zz * k,
        }
    }

    #[inline]
    pub fn add_scaled(&self, o: &Sym, k: f64) -> Sym {
        Sym {
            xx: self.xx + o.xx * k,
            yy: self.yy + o.yy * k,
            xy: self.xy + o.xy * k,
            zz: self.zz + o.zz * k,
        }
    }

    /// In-plane principal values and the angle of the first principal axis.
    pub fn principal(&self) -> (f64, f64, f64) {
        let m = 0.5 * (self.xx + self.yy);
        let r = (0.25 * (self.xx - self.yy).powi(2) + self.xy * self.xy).sqrt();
        let th = 0.5 * (2.0 * self.xy).atan2(self.xx - self.yy);
        (m + r, m - r, th)
    }

    /// Rebuild an in-plane tensor from principal values and the first axis' angle.
    pub fn from_principal(a: f64, b: f64, th: f64) -> Sym {
        let (s, c) = th.sin_cos();
        Sym {
            xx: a * c * c + b * s * s,
            yy: a * s * s + b * c * c,
            xy: (a - b) * s * c,
            zz: 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_and_principal() {
        let m = Mat2 {
            xx: 2.0,
            xy: 1.0,
            yx: 0.5,
            yy: 3.0,
        };
        let inv = m.inverse(1e-12).unwrap();
        let v = DVec2::new(0.3, -1.7);
        let back = inv.mul_vec(m.mul_vec(v));
        assert!((back - v).length() < 1e-14);
        let s = Sym {
            xx: 3.0,
            yy: -1.0,
            xy: 2.0,
            zz: 0.0,
        };
        let (a, b, th) = s.principal();
        let r = Sym::from_principal(a, b, th);
        assert!((r.xx - s.xx).abs() < 1e-12 && (r.yy - s.yy).abs() < 1e-12);
        assert!((r.xy - s.xy).abs() < 1e-12);
    }

    /// `G = A (I + cA)⁻¹`, the gradient of `v = A x₀` at `x₀ + c v`, maps
    /// back to `A`; a step that folds the neighbourhood maps to nothing.
    #[test]
    fn gradient_behind_inverts_the_drift() {
        let a = Mat2 {
            xx: -0.3,
            xy: 0.7,
            yx: 0.2,
            yy: 0.45,
        };
        for c in [0.0, 0.01, 0.3, -0.2] {
            let f = Mat2 {
                xx: 1.0 + c * a.xx,
                xy: c * a.xy,
                yx: c * a.yx,
                yy: 1.0 + c * a.yy,
            };
            // G = A F⁻¹ (F = I + cA): the rows of A against F⁻¹'s columns.
            let fi = f.inverse(1e-12).unwrap();
            let g = Mat2 {
                xx: a.xx * fi.xx + a.xy * fi.yx,
                xy: a.xx * fi.xy + a.xy * fi.yy,
                yx: a.yx * fi.xx + a.yy * fi.yx,
                yy: a.yx * fi.xy + a.yy * fi.yy,
            };
            let b = g.gradient_behind(c).unwrap();
            let err = (b.xx - a.xx).abs() + (b.xy - a.xy).abs() + (b.yx - a.yx).abs();
            assert!(err + (b.yy - a.yy).abs() < 1e-14, "c {c}: {b:?}");
        }
        assert_eq!(a.gradient_behind(0.0), Some(a));
        // Stretching at 2/s, looked back over 0.5 s: det(I − cG) = 0.
        let s = Mat2 {
            xx: 2.0,
            xy: 0.0,
            yx: 0.0,
            yy: 0.0,
        };
        assert_eq!(s.gradient_behind(0.5), None);
        assert!(s.gradient_behind(0.49).is_some());
    }
}
