//! Four f64 lanes: the pair passes evaluate four pairs of a row at once,
//! one to a lane.
//!
//! Each operation is the IEEE operation of the one-pair code applied to
//! every lane, so lane code that repeats the one-pair code's operations in
//! its order gives bit-identical results. There is no fused multiply–add
//! here on purpose: it would round differently. With AVX (the host-CPU
//! build of `.cargo/config.toml` on current x86) a value is one 256-bit
//! register; elsewhere it is an array the compiler vectorises as it can.

use std::ops::{Add, Div, Mul, Sub};

/// Pairs a lane value holds.
pub const LANES: usize = 4;

// SAFETY (every unsafe block of this module): each is an AVX intrinsic on
// registers or on a local array of four f64, and the module is compiled
// only where AVX is enabled (the `cfg`), so none can fault.
#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
#[allow(clippy::undocumented_unsafe_blocks)]
mod imp {
    use std::arch::x86_64::*;

    /// Four f64 in one AVX register.
    #[derive(Clone, Copy, Debug)]
    pub struct F4(pub(super) __m256d);

    /// A lane mask (all bits set where true), from a comparison.
    #[derive(Clone, Copy, Debug)]
    pub struct M4(__m256d);

    impl F4 {
        #[inline(always)]
        pub fn new(a: [f64; 4]) -> F4 {
            F4(unsafe { _mm256_loadu_pd(a.as_ptr()) })
        }
        #[inline(always)]
        pub fn splat(x: f64) -> F4 {
            F4(unsafe { _mm256_set1_pd(x) })
        }
        #[inline(always)]
        pub fn to_array(self) -> [f64; 4] {
            let mut a = [0.0; 4];
            unsafe { _mm256_storeu_pd(a.as_mut_ptr(), self.0) };
            a
        }
        /// `f64::min` where neither lane is NaN.
        #[inline(always)]
        pub fn min(self, o: F4) -> F4 {
            F4(unsafe { _mm256_min_pd(self.0, o.0) })
        }
        /// `f64::max` where neither lane is NaN.
        #[inline(always)]
        pub fn max(self, o: F4) -> F4 {
            F4(unsafe { _mm256_max_pd(self.0, o.0) })
        }
        #[inline(always)]
        pub fn sqrt(self) -> F4 {
            F4(unsafe { _mm256_sqrt_pd(self.0) })
        }
        #[inline(always)]
        pub fn lt(self, o: F4) -> M4 {
            M4(unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        pub fn eq(self, o: F4) -> M4 {
            M4(unsafe { _mm256_cmp_pd::<_CMP_EQ_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        pub fn le(self, o: F4) -> M4 {
            M4(unsafe { _mm256_cmp_pd::<_CMP_LE_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        pub fn ge(self, o: F4) -> M4 {
            M4(unsafe { _mm256_cmp_pd::<_CMP_GE_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        pub(super) fn add(self, o: F4) -> F4 {
            F4(unsafe { _mm256_add_pd(self.0, o.0) })
        }
        #[inline(always)]
        pub(super) fn sub(self, o: F4) -> F4 {
            F4(unsafe { _mm256_sub_pd(self.0, o.0) })
        }
        #[inline(always)]
        pub(super) fn mul(self, o: F4) -> F4 {
            F4(unsafe { _mm256_mul_pd(self.0, o.0) })
        }
        #[inline(always)]
        pub(super) fn div(self, o: F4) -> F4 {
            F4(unsafe { _mm256_div_pd(self.0, o.0) })
        }
    }

    /// The 4×4 transpose: lane k of result c is lane c of `r[k]` (eight
    /// shuffles).
    #[inline(always)]
    pub fn transpose(r: [F4; 4]) -> [F4; 4] {
        unsafe {
            let (t0, t1) = (
                _mm256_unpacklo_pd(r[0].0, r[1].0),
                _mm256_unpackhi_pd(r[0].0, r[1].0),
            );
            let (t2, t3) = (
                _mm256_unpacklo_pd(r[2].0, r[3].0),
                _mm256_unpackhi_pd(r[2].0, r[3].0),
            );
            [
                F4(_mm256_permute2f128_pd::<0x20>(t0, t2)),
                F4(_mm256_permute2f128_pd::<0x20>(t1, t3)),
                F4(_mm256_permute2f128_pd::<0x31>(t0, t2)),
                F4(_mm256_permute2f128_pd::<0x31>(t1, t3)),
            ]
        }
    }

    impl M4 {
        #[inline(always)]
        pub fn or(self, o: M4) -> M4 {
            M4(unsafe { _mm256_or_pd(self.0, o.0) })
        }
        #[inline(always)]
        pub fn and(self, o: M4) -> M4 {
            M4(unsafe { _mm256_and_pd(self.0, o.0) })
        }
        /// Bit k set where lane k is.
        #[inline(always)]
        pub fn bits(self) -> u32 {
            unsafe { _mm256_movemask_pd(self.0) as u32 }
        }
        /// `t` where the mask is set, `f` elsewhere.
        #[inline(always)]
        pub fn select(self, t: F4, f: F4) -> F4 {
            F4(unsafe { _mm256_blendv_pd(f.0, t.0, self.0) })
        }
    }
}

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
mod imp {
    /// Four f64.
    #[derive(Clone, Copy, Debug)]
    pub struct F4(pub(super) [f64; 4]);

    /// A lane mask, from a comparison.
    #[derive(Clone, Copy, Debug)]
    pub struct M4([bool; 4]);

    #[inline(always)]
    fn map(f: impl FnMut(usize) -> f64) -> F4 {
        F4(std::array::from_fn(f))
    }

    impl F4 {
        #[inline(always)]
        pub fn new(a: [f64; 4]) -> F4 {
            F4(a)
        }
        #[inline(always)]
        pub fn splat(x: f64) -> F4 {
            F4([x; 4])
        }
        #[inline(always)]
        pub fn to_array(self) -> [f64; 4] {
            self.0
        }
        /// `f64::min` where neither lane is NaN.
        #[inline(always)]
        pub fn min(self, o: F4) -> F4 {
            map(|k| self.0[k].min(o.0[k]))
        }
        /// `f64::max` where neither lane is NaN.
        #[inline(always)]
        pub fn max(self, o: F4) -> F4 {
            map(|k| self.0[k].max(o.0[k]))
        }
        #[inline(always)]
        pub fn sqrt(self) -> F4 {
            map(|k| self.0[k].sqrt())
        }
        #[inline(always)]
        pub fn lt(self, o: F4) -> M4 {
            M4(std::array::from_fn(|k| self.0[k] < o.0[k]))
        }
        #[inline(always)]
        pub fn eq(self, o: F4) -> M4 {
            M4(std::array::from_fn(|k| self.0[k] == o.0[k]))
        }
        #[inline(always)]
        pub fn le(self, o: F4) -> M4 {
            M4(std::array::from_fn(|k| self.0[k] <= o.0[k]))
        }
        #[inline(always)]
        pub fn ge(self, o: F4) -> M4 {
            M4(std::array::from_fn(|k| self.0[k] >= o.0[k]))
        }
        #[inline(always)]
        pub(super) fn add(self, o: F4) -> F4 {
            map(|k| self.0[k] + o.0[k])
        }
        #[inline(always)]
        pub(super) fn sub(self, o: F4) -> F4 {
            map(|k| self.0[k] - o.0[k])
        }
        #[inline(always)]
        pub(super) fn mul(self, o: F4) -> F4 {
            map(|k| self.0[k] * o.0[k])
        }
        #[inline(always)]
        pub(super) fn div(self, o: F4) -> F4 {
            map(|k| self.0[k] / o.0[k])
        }
    }

    /// The 4×4 transpose: lane k of result c is lane c of `r[k]`.
    #[inline(always)]
    pub fn transpose(r: [F4; 4]) -> [F4; 4] {
        std::array::from_fn(|c| F4(std::array::from_fn(|k| r[k].0[c])))
    }

    impl M4 {
        #[inline(always)]
        pub fn or(self, o: M4) -> M4 {
            M4(std::array::from_fn(|k| self.0[k] || o.0[k]))
        }
        #[inline(always)]
        pub fn and(self, o: M4) -> M4 {
            M4(std::array::from_fn(|k| self.0[k] && o.0[k]))
        }
        /// Bit k set where lane k is.
        #[inline(always)]
        pub fn bits(self) -> u32 {
            (0..4).map(|k| (self.0[k] as u32) << k).sum()
        }
        /// `t` where the mask is set, `f` elsewhere.
        #[inline(always)]
        pub fn select(self, t: F4, f: F4) -> F4 {
            map(|k| if self.0[k] { t.0[k] } else { f.0[k] })
        }
    }
}

use imp::transpose;
pub use imp::{F4, M4};

/// Four rows of four, as four columns: column c holds entry c of every row
/// (four loads and a transpose).
#[inline(always)]
pub fn columns(r: [&[f64; 4]; 4]) -> [F4; 4] {
    transpose([
        F4::new(*r[0]),
        F4::new(*r[1]),
        F4::new(*r[2]),
        F4::new(*r[3]),
    ])
}

impl F4 {
    /// `f(k)` in lane k: a gather.
    #[inline(always)]
    pub fn gather(f: impl FnMut(usize) -> f64) -> F4 {
        F4::new(std::array::from_fn(f))
    }
}

macro_rules! binary {
    ($tr:ident, $f:ident) => {
        impl $tr for F4 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: F4) -> F4 {
                F4::$f(self, o)
            }
        }
        impl $tr<f64> for F4 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: f64) -> F4 {
                F4::$f(self, F4::splat(o))
            }
        }
        impl $tr<F4> for f64 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: F4) -> F4 {
                F4::$f(F4::splat(self), o)
            }
        }
    };
}

binary!(Add, add);
binary!(Sub, sub);
binary!(Mul, mul);
binary!(Div, div);

#[cfg(test)]
mod tests {
    use super::*;

    /// Every operation equals the scalar one bit for bit, lane by lane,
    /// on values that round differently under a fused multiply–add.
    #[test]
    fn lanes_match_scalar_arithmetic() {
        let a = [1.0 / 3.0, -2.5e-7, 7.0e12, 0.1];
        let b = [3.0, 1.0 / 7.0, -1.0e-3, 0.2];
        let c = [0.3, 5.0, 2.0, -0.7];
        let (fa, fb, fc) = (F4::new(a), F4::new(b), F4::new(c));
        let got = (fa * fb + fc).to_array();
        let div = (fa / fb - fc).to_array();
        let min = fa.min(fb).to_array();
        let max = fa.max(fb).to_array();
        let root = fc.max(F4::splat(0.0)).sqrt().to_array();
        let sel = fa.le(fb).or(fa.ge(F4::splat(0.1))).select(fa, fc);
        for k in 0..LANES {
            assert_eq!(got[k].to_bits(), (a[k] * b[k] + c[k]).to_bits());
            assert_eq!(div[k].to_bits(), (a[k] / b[k] - c[k]).to_bits());
            assert_eq!(min[k], a[k].min(b[k]));
            assert_eq!(max[k], a[k].max(b[k]));
            assert_eq!(root[k].to_bits(), c[k].max(0.0).sqrt().to_bits());
            let want = if a[k] <= b[k] || a[k] >= 0.1 {
                a[k]
            } else {
                c[k]
            };
            assert_eq!(sel.to_array()[k], want);
        }
        assert_eq!((2.0 - fb).to_array()[1], 2.0 - b[1]);
        assert_eq!(fa.lt(fb).bits(), 0b1011);
        assert_eq!(fa.le(fa).bits(), 0b1111);
        assert_eq!(fa.eq(F4::new([a[0], 0.0, a[2], 0.0])).bits(), 0b0101);
        let rows = [a, b, c, [4.0, 5.0, 6.0, 7.0]];
        let cols = columns([&rows[0], &rows[1], &rows[2], &rows[3]]);
        for (col, f) in cols.iter().enumerate() {
            assert_eq!(f.to_array(), [a[col], b[col], c[col], 4.0 + col as f64]);
        }
    }
}
