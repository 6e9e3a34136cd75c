//! Adaptive support (docs/method.md, "Supports that follow the
//! deformation"): each particle's kernel is an ellipse, the set of
//! separations `d` with `dᵀ Q d < 4`, `Q` the particle's metric (the
//! inverse square of its smoothing tensor; `I/h²` for the round kernel of
//! smoothing length `h`). The metric is carried with the material: over
//! a step whose velocity gradient is `L` a line element `d` becomes
//! `(I + Δt L) d`, and `Q` becomes `(I + Δt L)⁻ᵀ Q (I + Δt L)⁻¹`, so that
//! a particle keeps the neighbours it had however its neighbourhood is
//! stretched or squeezed, within bounds on the semi-axes.

use glam::DVec2;

use crate::math::Mat2;

/// A symmetric positive-definite 2×2 metric `Q` (m⁻²).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Metric {
    pub xx: f64,
    pub xy: f64,
    pub yy: f64,
}

/// How far the semi-axes may leave the placed `h`: the major up to
/// `STRETCH_MAX h`, the minor down to `h / SQUEEZE_MAX`.
pub const STRETCH_MAX: f64 = 4.0;
pub const SQUEEZE_MAX: f64 = 2.0;

/// The band within which a support stays round (`support_band`,
/// [`Metric::banded`]): the factors on the placed `h` by which its carried
/// ellipse may be drawn out and squeezed before the support follows it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Band {
    pub drawn: f64,
    pub squeezed: f64,
}

impl Band {
    /// No band: the support is the carried ellipse itself.
    pub const NONE: Band = Band {
        drawn: 1.0,
        squeezed: 1.0,
    };

    /// The same factor both ways.
    pub fn uniform(b: f64) -> Band {
        Band {
            drawn: b,
            squeezed: b,
        }
    }

    /// Whether this is no band at all ([`Band::NONE`]).
    pub fn is_none(&self) -> bool {
        *self == Band::NONE
    }
}

/// The default band (`support_band`): round until drawn out or squeezed
/// by 1.5 (docs/method.md, "Round within a band").
pub const DEFAULT_BAND: Band = Band {
    drawn: 1.5,
    squeezed: 1.5,
};

impl Metric {
    /// The round kernel of smoothing length `h`.
    #[inline]
    pub fn round(h: f64) -> Metric {
        Metric::round_of(1.0 / (h * h))
    }

    /// The round metric `k I` (`k = 1/h²`).
    #[inline]
    pub fn round_of(k: f64) -> Metric {
        Metric {
            xx: k,
            xy: 0.0,
            yy: k,
        }
    }

    /// The pair's metric: the mean of the two (the round kernels' `1/h²`
    /// averaged).
    #[inline]
    pub fn mean(&self, o: &Metric) -> Metric {
        Metric {
            xx: 0.5 * (self.xx + o.xx),
            xy: 0.5 * (self.xy + o.xy),
            yy: 0.5 * (self.yy + o.yy),
        }
    }

    /// The mirror image across the axis `x = 0` (bodies of revolution)
    /// or any one line normal to a coordinate axis.
    #[inline]
    pub fn mirror(&self) -> Metric {
        Metric {
            xy: -self.xy,
            ..*self
        }
    }

    /// The mirror image by `m` (across one line or two).
    #[inline]
    pub fn mirrored(&self, m: &crate::math::Mirror) -> Metric {
        if m.shears() {
            self.mirror()
        } else {
            *self
        }
    }

    /// `Q d`.
    #[inline]
    pub fn apply(&self, d: DVec2) -> DVec2 {
        DVec2::new(self.xx * d.x + self.xy * d.y, self.xy * d.x + self.yy * d.y)
    }

    /// `dᵀ Q d`: the squared distance in units of the smoothing length.
    #[inline]
    pub fn quad(&self, d: DVec2) -> f64 {
        d.dot(self.apply(d))
    }

    #[inline]
    pub fn det(&self) -> f64 {
        self.xx * self.yy - self.xy * self.xy
    }

    /// The kernel's normalisation factor `√det Q` (2-D) or `√Q_xx` (1-D):
    /// `1/h^d` of a round kernel.
    #[inline]
    pub fn scale(&self, dim: usize) -> f64 {
        if dim == 1 {
            self.xx.sqrt()
        } else {
            self.det().sqrt()
        }
    }

    /// The eigenvalues `(λ_large, λ_small)` and the unit eigenvector of
    /// the large one.
    #[inline]
    fn eigen(&self) -> (f64, f64, DVec2) {
        let (a, b, _) = self.eigenvalues();
        // The eigenvector of `a`: (xy, a − xx) or (a − yy, xy), whichever
        // is longer (both vanish only where Q is round).
        let u = DVec2::new(self.xy, a - self.xx);
        let w = DVec2::new(a - self.yy, self.xy);
        let e = if u.length_squared() >= w.length_squared() {
            u
        } else {
            w
        };
        let e = e.try_normalize().unwrap_or(DVec2::X);
        (a, b, e)
    }

    /// The eigenvalues `(λ_large, λ_small)` and half their difference.
    #[inline]
    fn eigenvalues(&self) -> (f64, f64, f64) {
        let m = 0.5 * (self.xx + self.yy);
        let d = 0.5 * (self.xx - self.yy);
        let rad = (d * d + self.xy * self.xy).sqrt();
        (m + rad, m - rad, rad)
    }

    /// The smallest `λ` with `Q − λ P` singular, `P` another metric: how
    /// far `Q` has shrunk from `P` along its worst direction (`dᵀ Q d ≥ λ
    /// dᵀ P d` for every `d`; 1 for equal metrics, below 1 where some
    /// semi-axis has grown past `P`'s along it).
    #[inline]
    pub fn least_ratio(&self, p: &Metric) -> f64 {
        // det(Q − λP) = det P λ² − b λ + det Q.
        let a = p.det();
        let b = self.xx * p.yy + self.yy * p.xx - 2.0 * self.xy * p.xy;
        let c = self.det();
        let disc = (b * b - 4.0 * a * c).max(0.0);
        // The smaller root, in the form that does not cancel.
        2.0 * c / (b + disc.sqrt())
    }

    /// The largest eigenvalue (the inverse square of the minor semi-axis).
    #[inline]
    pub fn largest(&self) -> f64 {
        self.eigen().0
    }

    /// The semi-axes `(h_minor, h_major)` of the smoothing ellipse.
    #[inline]
    pub fn axes(&self) -> (f64, f64) {
        let (a, b, _) = self.eigen();
        (1.0 / a.sqrt(), 1.0 / b.max(f64::MIN_POSITIVE).sqrt())
    }

    /// The ellipse with semi-axes `minor` along the unit vector `e` and
    /// `major` across it.
    pub fn with_axes(minor: f64, major: f64, e: DVec2) -> Metric {
        Metric::from_eigen(1.0 / (minor * minor), 1.0 / (major * major), e)
    }

    /// The metric with eigenvalues `a` (along `e`) and `b`.
    #[inline]
    fn from_eigen(a: f64, b: f64, e: DVec2) -> Metric {
        let k = a - b;
        Metric {
            xx: b + k * e.x * e.x,
            xy: k * e.x * e.y,
            yy: b + k * e.y * e.y,
        }
    }

    /// Carried over a step: `(I + Δt L)⁻ᵀ Q (I + Δt L)⁻¹`, `L` the
    /// velocity gradient (`L_αβ = ∂v_α/∂x_β`), then held to the bounds
    /// around the placed smoothing length `h0` ([`Metric::bounded`]). In
    /// 1-D only `Q_xx` moves.
    pub fn carried(&self, l: &Mat2, dt: f64, h0: f64, dim: usize) -> Metric {
        self.moved(l, dt, dim).bounded(h0, dim)
    }

    /// Carried over a step, unbounded.
    fn moved(&self, l: &Mat2, dt: f64, dim: usize) -> Metric {
        let a = Mat2 {
            xx: 1.0 + dt * l.xx,
            xy: dt * l.xy,
            yx: dt * l.yx,
            yy: 1.0 + dt * l.yy,
        };
        if dim == 1 {
            let k = self.xx / (a.xx * a.xx);
            return Metric { xx: k, ..*self };
        }
        let Some(inv) = a.inverse(0.0) else {
            return *self;
        };
        // B = A⁻¹; Q' = Bᵀ Q B.
        let (b11, b12, b21, b22) = (inv.xx, inv.xy, inv.yx, inv.yy);
        // Q B, column by column.
        let qb11 = self.xx * b11 + self.xy * b21;
        let qb21 = self.xy * b11 + self.yy * b21;
        let qb12 = self.xx * b12 + self.xy * b22;
        let qb22 = self.xy * b12 + self.yy * b22;
        Metric {
            xx: b11 * qb11 + b21 * qb21,
            xy: b11 * qb12 + b21 * qb22,
            yy: b12 * qb12 + b22 * qb22,
        }
    }

    /// The support of a carried metric (`self`, the image of the placed
    /// disk of radius `2 h0` under the material's deformation) within the
    /// band `band` (docs/method.md, "Supports that follow the
    /// deformation"): round, `I/h0²` exactly, while no semi-axis of the
    /// carried ellipse exceeds `band.drawn h0` or falls below `h0 /
    /// band.squeezed`; beyond the band a semi-axis `s` becomes `s /
    /// band.drawn` (drawn out) or `s × band.squeezed` (squeezed), so the
    /// support follows the deformation by what exceeds the band, and
    /// continuously. The carried eigenvalue `λ = 1/s²` maps to `λ
    /// drawn²` or `λ / squeezed²`, and a spectral map of a 2×2 symmetric
    /// matrix is affine in it, `α I + β Q`, so no eigenvector is formed.
    pub fn banded(&self, h0: f64, band: Band, dim: usize) -> Metric {
        self.banded_in(&BandBounds::new(h0, band), None, dim)
    }

    /// [`Metric::banded`] with the bounds of its `h0` and band worked
    /// out, and the metric's [`Metric::eigenvalues`] where they are known.
    #[inline]
    fn banded_in(&self, k: &BandBounds, eig: Option<(f64, f64, f64)>, dim: usize) -> Metric {
        let (round, d2, s2) = (k.round, k.d2, k.s2);
        let map = |l: f64| {
            if l * d2 < round {
                l * d2
            } else if l > round * s2 {
                l / s2
            } else {
                round
            }
        };
        if dim == 1 {
            let k = map(self.xx);
            return if k == round {
                Metric::round_of(round)
            } else {
                Metric { xx: k, ..*self }
            };
        }
        let (l1, l2, rad) = eig.unwrap_or_else(|| self.eigenvalues());
        let (k1, k2) = (map(l1), map(l2));
        if k1 == round && k2 == round {
            return Metric::round_of(round);
        }
        // α + β λ_k = k_k for both eigenvalues; a round carried metric
        // (equal eigenvalues) maps to a multiple of itself.
        let (alpha, beta) = if rad > 0.0 {
            let beta = (k1 - k2) / (l1 - l2);
            (k1 - beta * l1, beta)
        } else {
            (0.0, k1 / l1)
        };
        Metric {
            xx: alpha + beta * self.xx,
            xy: beta * self.xy,
            yy: alpha + beta * self.yy,
        }
    }

    /// Held to the bounds: semi-axes within `[h0/SQUEEZE_MAX,
    /// STRETCH_MAX h0]`. Unchanged (bit for bit) inside them.
    pub fn bounded(&self, h0: f64, dim: usize) -> Metric {
        self.bounded_band(h0, Band::NONE, dim)
    }

    /// Held to the bounds widened by the band (a carried metric whose
    /// [`Metric::banded`] support is to keep within the bounds): semi-axes
    /// within `[h0/(SQUEEZE_MAX band.squeezed), STRETCH_MAX band.drawn h0]`.
    pub fn bounded_band(&self, h0: f64, band: Band, dim: usize) -> Metric {
        self.bounded_in(&BandBounds::new(h0, band), dim).0
    }

    /// [`Metric::bounded_band`] with its bounds worked out, and the
    /// eigenvalues of the result where it is the metric unchanged.
    #[inline]
    fn bounded_in(&self, k: &BandBounds, dim: usize) -> (Metric, Option<(f64, f64, f64)>) {
        let (lo, hi) = (k.lo, k.hi);
        if dim == 1 {
            let xx = self.xx.clamp(lo, hi);
            return (Metric { xx, ..*self }, None);
        }
        // The eigenvector only where the metric is clamped.
        let eig = self.eigenvalues();
        let (a, b, _) = eig;
        if a <= hi && b >= lo {
            return (*self, Some(eig));
        }
        let (a, b, e) = self.eigen();
        (
            Metric::from_eigen(a.clamp(lo, hi), b.clamp(lo, hi), e),
            None,
        )
    }

    /// Carried over a step as [`Metric::carried`], held to the bounds
    /// widened by the band ([`Metric::bounded_band`]), and the support
    /// [`Metric::banded`] gives it, in one: the bounds of `h0` and the band worked out once
    /// (`k`, for every particle of that `h0`), the eigenvalues once where
    /// the carried metric is not clamped. The same bits as the two.
    #[inline]
    pub fn carried_banded(
        &self,
        l: &Mat2,
        dt: f64,
        k: &BandBounds,
        dim: usize,
    ) -> (Metric, Metric) {
        let (c, eig) = self.moved(l, dt, dim).bounded_in(k, dim);
        (c, c.banded_in(k, eig, dim))
    }
}

/// What [`Metric::bounded_band`] and [`Metric::banded`] work out of the
/// placed smoothing length `h0` and the band: the bounds on the carried
/// eigenvalues, the round support's `1/h0²` and the band's squares.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BandBounds {
    lo: f64,
    hi: f64,
    /// `1/h0²`, as [`Metric::round`] has it.
    pub round: f64,
    d2: f64,
    s2: f64,
}

impl BandBounds {
    pub fn new(h0: f64, band: Band) -> BandBounds {
        BandBounds {
            lo: 1.0 / (STRETCH_MAX * band.drawn * h0).powi(2),
            hi: (SQUEEZE_MAX * band.squeezed / h0).powi(2),
            round: 1.0 / (h0 * h0),
            d2: band.drawn * band.drawn,
            s2: band.squeezed * band.squeezed,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A round metric is `1/h²`; its semi-axes are `h`.
    #[test]
    fn round_metric() {
        let q = Metric::round(2.0);
        assert_eq!(q.quad(DVec2::new(2.0, 0.0)), 1.0);
        assert_eq!(q.axes(), (2.0, 2.0));
        assert_eq!(q.scale(2), 0.25);
    }

    /// Carried through a uniform stretch, a rotation and a shear, the
    /// ellipse is the image of the round kernel: every material line
    /// element keeps its length in the metric.
    #[test]
    fn the_metric_follows_the_material() {
        let h = 1.2e-3;
        let q0 = Metric::round(h);
        for l in [
            Mat2 {
                xx: 1e4,
                xy: 0.0,
                yx: 0.0,
                yy: -5e3,
            },
            Mat2 {
                xx: 0.0,
                xy: 3e4,
                yx: -3e4,
                yy: 0.0,
            },
            Mat2 {
                xx: 0.0,
                xy: 2e4,
                yx: 0.0,
                yy: 0.0,
            },
        ] {
            let dt = 1e-6;
            let q = q0.carried(&l, dt, h, 2);
            for d in [DVec2::new(1e-3, 0.0), DVec2::new(3e-4, -7e-4)] {
                let moved = d + DVec2::new(l.xx * d.x + l.xy * d.y, l.yx * d.x + l.yy * d.y) * dt;
                let (a, b) = (q.quad(moved), q0.quad(d));
                assert!((a / b - 1.0).abs() < 1e-12, "{l:?}: {a} against {b}");
            }
        }
    }

    /// The least ratio of two metrics: 1 for equal ones, the growth of a
    /// semi-axis (as `1/growth²`) for an ellipse stretched along it,
    /// whatever the directions.
    #[test]
    fn least_ratio_of_two_metrics() {
        let e = DVec2::new(0.6, 0.8);
        let p = Metric::with_axes(0.5, 2.0, e);
        assert!((p.least_ratio(&p) - 1.0).abs() < 1e-12);
        let q = Metric::with_axes(0.5, 2.4, e);
        assert!((q.least_ratio(&p) - 1.0 / 1.44).abs() < 1e-12);
        let turned = Metric::with_axes(0.5, 2.0, DVec2::new(-0.8, 0.6));
        // Turned a quarter: the minor axis now lies along the old major.
        assert!((p.least_ratio(&turned) - 1.0 / 16.0).abs() < 1e-12);
        assert!((Metric::round(1.0).least_ratio(&Metric::round(2.0)) - 4.0).abs() < 1e-12);
    }

    /// Within the band a support is round to the bit; beyond it each
    /// semi-axis is the carried one over (or times) the band, along the
    /// carried axes, and the map is continuous at the band's edges.
    #[test]
    fn banded_supports() {
        let h = 2.0e-4;
        let e = DVec2::new(0.6, 0.8);
        for (minor, major) in [(0.7, 1.4), (1.0, 1.0), (2.0 / 3.0, 1.5)] {
            let c = Metric::with_axes(minor * h, major * h, e);
            assert_eq!(
                c.banded(h, Band::uniform(1.5), 2),
                Metric::round(h),
                "{minor} {major}"
            );
        }
        for (minor, major) in [(0.4, 1.2), (0.9, 3.0), (0.3, 6.0)] {
            let q = Metric::with_axes(minor * h, major * h, e).banded(h, Band::uniform(1.5), 2);
            let k = |s: f64| {
                if s > 1.5 {
                    s / 1.5
                } else if s < 1.0 / 1.5 {
                    s * 1.5
                } else {
                    1.0
                }
            };
            let (lo, hi) = q.axes();
            assert!((lo / (k(minor) * h) - 1.0).abs() < 1e-12, "{minor}: {lo}");
            assert!((hi / (k(major) * h) - 1.0).abs() < 1e-12, "{major}: {hi}");
            // Along the carried axes: the minor axis along e.
            assert!((q.quad(e) * (k(minor) * h).powi(2) - 1.0).abs() < 1e-9);
        }
        // Continuous across the edge, to the size of the step taken.
        for s in [1.5, 1.0 / 1.5] {
            let a = Metric::with_axes(h, s * (1.0 - 1e-9) * h, e).banded(h, Band::uniform(1.5), 2);
            let b = Metric::with_axes(h, s * (1.0 + 1e-9) * h, e).banded(h, Band::uniform(1.5), 2);
            assert!((a.xx - b.xx).abs() + (a.xy - b.xy).abs() < 1e-8 * a.xx);
        }
        // 1-D: only Q_xx.
        let q = Metric {
            xx: 1.0 / (3.0 * h).powi(2),
            xy: 0.0,
            yy: 0.0,
        }
        .banded(h, Band::uniform(1.5), 1);
        assert!((q.xx * (2.0 * h).powi(2) - 1.0).abs() < 1e-12);
        assert_eq!(
            Metric::round(h).banded(h, Band::uniform(1.5), 1),
            Metric::round(h)
        );
    }

    /// A band wider for squeezing: a support squeezed to 0.6 h stays round
    /// in the band (1.5, 2) and follows beyond 0.5 h by the factor 2; one
    /// drawn out follows beyond 1.5 h by 1.5.
    #[test]
    fn banded_supports_squeezed_and_drawn_out_apart() {
        let h = 2.0e-4;
        let e = DVec2::new(0.6, 0.8);
        let band = Band {
            drawn: 1.5,
            squeezed: 2.0,
        };
        assert_eq!(
            Metric::with_axes(0.6 * h, 1.4 * h, e).banded(h, band, 2),
            Metric::round(h)
        );
        let (lo, hi) = Metric::with_axes(0.4 * h, 1.0 * h, e)
            .banded(h, band, 2)
            .axes();
        assert!((lo / (0.8 * h) - 1.0).abs() < 1e-12 && (hi / h - 1.0).abs() < 1e-12);
        let (lo, hi) = Metric::with_axes(0.4 * h, 3.0 * h, e)
            .banded(h, band, 2)
            .axes();
        assert!((lo / (0.8 * h) - 1.0).abs() < 1e-12 && (hi / (2.0 * h) - 1.0).abs() < 1e-12);
        // The bounds of the carried ellipse widen by each side's factor.
        let q = Metric::from_eigen(1.0 / (0.05 * h).powi(2), 1.0 / (100.0 * h).powi(2), e)
            .bounded_band(h, band, 2);
        let (lo, hi) = q.axes();
        assert!((lo / (h / (SQUEEZE_MAX * 2.0)) - 1.0).abs() < 1e-12);
        assert!((hi / (STRETCH_MAX * 1.5 * h) - 1.0).abs() < 1e-12);
    }

    /// Past the bounds the semi-axes are held, along the same axes.
    #[test]
    fn bounded_semi_axes() {
        let h = 1.0;
        let e = DVec2::new(0.6, 0.8);
        let q = Metric::from_eigen(100.0, 1e-4, e).bounded(h, 2);
        let (lo, hi) = q.axes();
        assert!((lo - h / SQUEEZE_MAX).abs() < 1e-12 && (hi - STRETCH_MAX * h).abs() < 1e-12);
        assert!((q.quad(e) - (SQUEEZE_MAX / h).powi(2)).abs() < 1e-9);
        let inside = Metric::from_eigen(2.0, 0.5, e);
        assert_eq!(inside.bounded(h, 2), inside);
    }
}
