//! Eight doubles side by side, for the Wisdom–Holman kernels of up to eight
//! planets ([`crate::problems::wisdom_holman`], [`crate::kepler`]): one
//! trait, [`F8`], with two implementations that give the same bits —
//! [`Avx512`] (one AVX-512 register, where the processor has AVX-512F) and
//! [`Portable`] (an array of eight, which the compiler keeps in whatever
//! vector registers the build has).
//!
//! # Same bits on both
//!
//! Every operation of the trait is one IEEE operation per lane (addition,
//! subtraction, multiplication, division, square root, which round the
//! same at every vector width), a comparison, a select, or a move of lanes;
//! no multiply–add is fused (Rust contracts nothing, and the AVX-512 code
//! uses no FMA instruction), and the sums across lanes
//! ([`F8::suffix_sum`]) add in one fixed order on both. A kernel written once against the
//! trait therefore gives the same bits on either (tested in
//! `tests/simd_lanes.rs`).
//!
//! Lane masks are `u8` (bit `l` for lane `l`), the AVX-512 mask register's
//! own form.
//!
//! The lanes are internal to the crate (an `Avx512` value must never exist
//! on a processor without AVX-512F); the public face is the choice
//! [`Simd`] of the splits and [`KeplerSolver::drift_lanes8`](crate::kepler::KeplerSolver::drift_lanes8).

// Lane loops index several arrays at once.
#![allow(clippy::needless_range_loop)]

/// The lanes of [`F8`].
pub(crate) const W: usize = 8;

/// Eight doubles, lane-wise IEEE arithmetic (see the [module
/// documentation](self)).
pub(crate) trait F8: Copy {
    fn splat(x: f64) -> Self;
    fn from_array(a: [f64; W]) -> Self;
    fn to_array(self) -> [f64; W];
    fn add(self, b: Self) -> Self;
    fn sub(self, b: Self) -> Self;
    fn mul(self, b: Self) -> Self;
    fn div(self, b: Self) -> Self;
    fn sqrt(self) -> Self;
    fn abs(self) -> Self;
    /// `−a` (the sign bit flipped, as Rust's `-`).
    fn neg(self) -> Self;
    /// Rust's `f64::max`: the other argument where one is NaN.
    fn max(self, b: Self) -> Self;
    /// `a < b` per lane (false where either is NaN).
    fn lt(self, b: Self) -> u8;
    /// `a <= b` per lane (false where either is NaN).
    fn le(self, b: Self) -> u8;
    /// `a == b` per lane (false where either is NaN).
    fn eq(self, b: Self) -> u8;
    /// `a` where the mask's bit is set, else `b`.
    fn select(m: u8, a: Self, b: Self) -> Self;
    /// Lane `l` of the result is lane `idx[l]` of `a` (`idx[l] < 8`).
    fn permute(self, idx: &[u64; W]) -> Self;
    /// The lanes of `3·count` consecutive doubles `(x, y, z)` per lane,
    /// `count ≤ 8`, as three vectors (lanes from `count` on are 0).
    fn load3(src: &[f64], count: usize) -> [Self; 3];
    /// [`load3`](F8::load3)'s inverse: the first `count` lanes of `v`
    /// into `3·count` consecutive doubles.
    fn store3(v: &[Self; 3], dst: &mut [f64], count: usize);

    /// Per lane, whether the value is finite (`|a| < ∞`).
    #[inline(always)]
    fn finite(self) -> u8 {
        self.abs().lt(Self::splat(f64::INFINITY))
    }
    /// Lane `l` of the result is `Σ_{k ≥ l} aₖ`, summed in three rounds
    /// (by one lane, then two, then four).
    #[inline(always)]
    fn suffix_sum(self) -> Self {
        let z = Self::splat(0.0);
        let s = self.add(Self::select(
            0x7f,
            self.permute(&[1, 2, 3, 4, 5, 6, 7, 7]),
            z,
        ));
        let s = s.add(Self::select(0x3f, s.permute(&[2, 3, 4, 5, 6, 7, 7, 7]), z));
        s.add(Self::select(0x0f, s.permute(&[4, 5, 6, 7, 7, 7, 7, 7]), z))
    }
}

/// The mask of the first `count` lanes.
#[inline(always)]
pub(crate) fn first(count: usize) -> u8 {
    if count >= W {
        0xff
    } else {
        ((1u16 << count) - 1) as u8
    }
}

/// Eight doubles in an array: the [`F8`] of any processor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Portable(pub(crate) [f64; W]);

impl Portable {
    #[inline(always)]
    fn map2(self, b: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        let mut out = [0.0; W];
        for l in 0..W {
            out[l] = f(self.0[l], b.0[l]);
        }
        Portable(out)
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        let mut out = [0.0; W];
        for l in 0..W {
            out[l] = f(self.0[l]);
        }
        Portable(out)
    }
    #[inline(always)]
    fn mask(self, b: Self, f: impl Fn(f64, f64) -> bool) -> u8 {
        let mut m = 0u8;
        for l in 0..W {
            m |= (f(self.0[l], b.0[l]) as u8) << l;
        }
        m
    }
}

impl F8 for Portable {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Portable([x; W])
    }
    #[inline(always)]
    fn from_array(a: [f64; W]) -> Self {
        Portable(a)
    }
    #[inline(always)]
    fn to_array(self) -> [f64; W] {
        self.0
    }
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        self.map2(b, |x, y| x + y)
    }
    #[inline(always)]
    fn sub(self, b: Self) -> Self {
        self.map2(b, |x, y| x - y)
    }
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        self.map2(b, |x, y| x * y)
    }
    #[inline(always)]
    fn div(self, b: Self) -> Self {
        self.map2(b, |x, y| x / y)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(f64::sqrt)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        self.map(f64::abs)
    }
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|x| -x)
    }
    #[inline(always)]
    fn max(self, b: Self) -> Self {
        // Spelled out (not `f64::max`, whose choice between ±0 is left
        // open): the AVX-512 form below, lane by lane.
        self.map2(b, |x, y| if y.is_nan() || x > y { x } else { y })
    }
    #[inline(always)]
    fn lt(self, b: Self) -> u8 {
        self.mask(b, |x, y| x < y)
    }
    #[inline(always)]
    fn le(self, b: Self) -> u8 {
        self.mask(b, |x, y| x <= y)
    }
    #[inline(always)]
    fn eq(self, b: Self) -> u8 {
        self.mask(b, |x, y| x == y)
    }
    #[inline(always)]
    fn select(m: u8, a: Self, b: Self) -> Self {
        let mut out = [0.0; W];
        for l in 0..W {
            out[l] = if m >> l & 1 == 1 { a.0[l] } else { b.0[l] };
        }
        Portable(out)
    }
    #[inline(always)]
    fn permute(self, idx: &[u64; W]) -> Self {
        let mut out = [0.0; W];
        for l in 0..W {
            out[l] = self.0[(idx[l] & 7) as usize];
        }
        Portable(out)
    }
    #[inline(always)]
    fn load3(src: &[f64], count: usize) -> [Self; 3] {
        let mut out = [[0.0; W]; 3];
        for l in 0..count.min(W) {
            for k in 0..3 {
                out[k][l] = src[3 * l + k];
            }
        }
        out.map(Portable)
    }
    #[inline(always)]
    fn store3(v: &[Self; 3], dst: &mut [f64], count: usize) {
        for l in 0..count.min(W) {
            for k in 0..3 {
                dst[3 * l + k] = v[k].0[l];
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use avx512::Avx512;

#[cfg(target_arch = "x86_64")]
mod avx512 {
    use super::{F8, W};
    use std::arch::x86_64::*;

    /// Eight doubles in one AVX-512 register. Only ever constructed inside
    /// functions compiled with `avx512f` and called after
    /// `is_x86_feature_detected!("avx512f")`; every method is inlined into
    /// them.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Avx512(__m512d);

    /// [`F8::store3`]'s permutes: for output vector `j` (elements
    /// `e = 8j … 8j + 7`, `e = 3l + k`), the indices into `x | y` (`l` for
    /// `k = 0`, `8 + l` for `k = 1`), the indices into `z`, and the mask of
    /// the elements taken from `z`.
    const STORE: [([u64; W], [u64; W], u8); 3] = {
        let mut out = [([0u64; W], [0u64; W], 0u8); 3];
        let mut j = 0;
        while j < 3 {
            let mut i = 0;
            while i < W {
                let e = 8 * j + i;
                let (l, k) = ((e / 3) as u64, e % 3);
                if k == 0 {
                    out[j].0[i] = l;
                } else if k == 1 {
                    out[j].0[i] = 8 + l;
                } else {
                    out[j].1[i] = l;
                    out[j].2 |= 1 << i;
                }
                i += 1;
            }
            j += 1;
        }
        out
    };

    /// [`F8::load3`]'s permutes: for coordinate `k`, lane `l` takes
    /// element `e = 3l + k` of the 24 loaded, from `a | b` (`e < 16`) or
    /// from `c` (`e − 16`, the mask's lanes).
    const LOAD: [([u64; W], [u64; W], u8); 3] = {
        let mut out = [([0u64; W], [0u64; W], 0u8); 3];
        let mut k = 0;
        while k < 3 {
            let mut l = 0;
            while l < W {
                let e = (3 * l + k) as u64;
                if e < 16 {
                    out[k].0[l] = e;
                } else {
                    out[k].1[l] = e - 16;
                    out[k].2 |= 1 << l;
                }
                l += 1;
            }
            k += 1;
        }
        out
    };

    #[inline(always)]
    fn index(idx: &[u64; W]) -> __m512i {
        // SAFETY: an unaligned load of 64 bytes from an array of 64 bytes.
        unsafe { _mm512_loadu_si512(idx.as_ptr().cast()) }
    }

    // SAFETY (every `unsafe` block below): these are AVX-512F intrinsics;
    // an `Avx512` exists only in code that runs after the processor was
    // found to have AVX-512F (see the type's documentation). Loads and
    // stores are masked to the slice's length.
    impl F8 for Avx512 {
        #[inline(always)]
        fn splat(x: f64) -> Self {
            Avx512(unsafe { _mm512_set1_pd(x) })
        }
        #[inline(always)]
        fn from_array(a: [f64; W]) -> Self {
            Avx512(unsafe { _mm512_loadu_pd(a.as_ptr()) })
        }
        #[inline(always)]
        fn to_array(self) -> [f64; W] {
            let mut out = [0.0; W];
            unsafe { _mm512_storeu_pd(out.as_mut_ptr(), self.0) };
            out
        }
        #[inline(always)]
        fn add(self, b: Self) -> Self {
            Avx512(unsafe { _mm512_add_pd(self.0, b.0) })
        }
        #[inline(always)]
        fn sub(self, b: Self) -> Self {
            Avx512(unsafe { _mm512_sub_pd(self.0, b.0) })
        }
        #[inline(always)]
        fn mul(self, b: Self) -> Self {
            Avx512(unsafe { _mm512_mul_pd(self.0, b.0) })
        }
        #[inline(always)]
        fn div(self, b: Self) -> Self {
            Avx512(unsafe { _mm512_div_pd(self.0, b.0) })
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            Avx512(unsafe { _mm512_sqrt_pd(self.0) })
        }
        #[inline(always)]
        fn abs(self) -> Self {
            Avx512(unsafe { _mm512_abs_pd(self.0) })
        }
        #[inline(always)]
        fn neg(self) -> Self {
            unsafe {
                let sign = _mm512_set1_epi64(i64::MIN);
                Avx512(_mm512_castsi512_pd(_mm512_xor_si512(
                    _mm512_castpd_si512(self.0),
                    sign,
                )))
            }
        }
        #[inline(always)]
        fn max(self, b: Self) -> Self {
            // `a > b ? a : b`, and `a` where `b` is NaN.
            unsafe {
                let gt = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(self.0, b.0);
                let bnan = _mm512_cmp_pd_mask::<_CMP_UNORD_Q>(b.0, b.0);
                Avx512(_mm512_mask_blend_pd(gt | bnan, b.0, self.0))
            }
        }
        #[inline(always)]
        fn lt(self, b: Self) -> u8 {
            unsafe { _mm512_cmp_pd_mask::<_CMP_LT_OQ>(self.0, b.0) }
        }
        #[inline(always)]
        fn le(self, b: Self) -> u8 {
            unsafe { _mm512_cmp_pd_mask::<_CMP_LE_OQ>(self.0, b.0) }
        }
        #[inline(always)]
        fn eq(self, b: Self) -> u8 {
            unsafe { _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(self.0, b.0) }
        }
        #[inline(always)]
        fn select(m: u8, a: Self, b: Self) -> Self {
            Avx512(unsafe { _mm512_mask_blend_pd(m, b.0, a.0) })
        }
        #[inline(always)]
        fn permute(self, idx: &[u64; W]) -> Self {
            Avx512(unsafe { _mm512_permutexvar_pd(index(idx), self.0) })
        }
        #[inline(always)]
        fn load3(src: &[f64], count: usize) -> [Self; 3] {
            let n = (3 * count.min(W)).min(src.len());
            let p = src.as_ptr();
            unsafe {
                // Masked loads touch only the lanes below `n`; the pointers
                // past the end are formed with wrapping arithmetic.
                let a = _mm512_maskz_loadu_pd(super::first(n), p);
                let b = _mm512_maskz_loadu_pd(super::first(n.saturating_sub(8)), p.wrapping_add(8));
                let c =
                    _mm512_maskz_loadu_pd(super::first(n.saturating_sub(16)), p.wrapping_add(16));
                let mut out = [_mm512_setzero_pd(); 3];
                for (k, o) in out.iter_mut().enumerate() {
                    let (ab, ci, from_c) = &LOAD[k];
                    let t = _mm512_permutex2var_pd(a, index(ab), b);
                    *o = _mm512_mask_permutexvar_pd(t, *from_c, index(ci), c);
                }
                // Lanes from `count` on are 0 (the loads were masked, but
                // the permutes may have picked a neighbour's coordinate).
                let keep = super::first(count.min(W));
                out.map(|v| Avx512(_mm512_maskz_mov_pd(keep, v)))
            }
        }
        #[inline(always)]
        fn store3(v: &[Self; 3], dst: &mut [f64], count: usize) {
            let n = (3 * count.min(W)).min(dst.len());
            let p = dst.as_mut_ptr();
            let (x, y, z) = (v[0].0, v[1].0, v[2].0);
            unsafe {
                // Output element e = 3l + k. Vector j holds e = 8j … 8j + 7;
                // each element's lane l and coordinate k are fixed, so the
                // vector is a permute of x and y (indices 0…7 and 8…15)
                // completed from z.
                for j in 0..3usize {
                    let (xy, zi, from_z) = &STORE[j];
                    let t = _mm512_permutex2var_pd(x, index(xy), y);
                    let o = _mm512_mask_permutexvar_pd(t, *from_z, index(zi), z);
                    _mm512_mask_storeu_pd(
                        p.wrapping_add(8 * j),
                        super::first(n.saturating_sub(8 * j)),
                        o,
                    );
                }
            }
        }
    }
}

/// Whether this processor runs the [`Avx512`] kernels.
#[inline]
pub fn has_avx512() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx512f")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Which implementation of the eight-lane kernels a Wisdom–Holman split
/// uses for up to eight planets: the same bits either way (see the
/// [module documentation](self)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Simd {
    /// AVX-512 where the processor has it, else [`Simd::Portable`].
    #[default]
    Auto,
    /// The portable arrays (compiled for AVX2 where the processor has it).
    Portable,
}

impl Simd {
    /// Whether the kernels run on AVX-512 (asked and available).
    #[inline]
    pub fn avx512(self) -> bool {
        !matches!(Avx512Or::pick(self), Avx512Or::Portable)
    }
}

/// The implementation a kernel runs on: [`Simd`] resolved on this
/// processor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Avx512Or {
    #[cfg(target_arch = "x86_64")]
    Avx512,
    Portable,
}

impl Avx512Or {
    #[inline]
    pub(crate) fn pick(simd: Simd) -> Self {
        match simd {
            #[cfg(target_arch = "x86_64")]
            Simd::Auto if has_avx512() => Avx512Or::Avx512,
            _ => Avx512Or::Portable,
        }
    }
}

/// A kernel written once against [`F8`], run by [`dispatch`] on the
/// implementation that [`Simd`] picks (`run` must be `#[inline(always)]`,
/// so that it is compiled for the instruction set of its caller).
pub(crate) trait Kernel {
    type Out;
    fn run<V: F8>(self) -> Self::Out;
}

/// Run `k` on AVX-512 where `simd` and the processor allow it, else on the
/// portable lanes (compiled for AVX2 where the processor has it).
#[inline]
pub(crate) fn dispatch<K: Kernel>(simd: Simd, k: K) -> K::Out {
    match Avx512Or::pick(simd) {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: picked only where the processor has AVX-512F.
        Avx512Or::Avx512 => unsafe { on_avx512(k) },
        Avx512Or::Portable => {
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the processor has AVX2 (checked just above).
                return unsafe { on_avx2(k) };
            }
            k.run::<Portable>()
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn on_avx512<K: Kernel>(k: K) -> K::Out {
    k.run::<Avx512>()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn on_avx2<K: Kernel>(k: K) -> K::Out {
    k.run::<Portable>()
}
