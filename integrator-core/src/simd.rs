//! Eight doubles side by side, for the Wisdom–Holman kernels of up to eight
//! planets ([`crate::problems::wisdom_holman`], [`crate::kepler`]), and the
//! one switch that says which instruction set the vector kernels of the
//! workspace run on ([`level`], capped by `SYMLAB_SIMD`).
//!
//! One trait, [`F8`], with three implementations that give the same bits:
//! [`Avx512`] (one AVX-512 register, where the processor has AVX-512F),
//! [`Avx2`] (two 256-bit registers, where it has AVX2) and [`Portable`]
//! (an array of eight, compiled for the build's baseline: SSE2 on x86-64,
//! NEON on aarch64, whatever the target has elsewhere).
//!
//! # Same bits on every one
//!
//! Every operation of the trait is one IEEE operation per lane (addition,
//! subtraction, multiplication, division, square root, which round the
//! same at every vector width), a comparison, a select, or a move of lanes;
//! no multiply–add is fused (Rust contracts nothing, and the AVX-512 and
//! AVX2 code use no FMA instruction: their functions enable `avx512f` or
//! `avx2` only, never `fma`), and the sums across lanes
//! ([`F8::suffix_sum`]) add in one fixed order on all three. A kernel
//! written once against the trait therefore gives the same bits on each
//! (tested in `tests/simd_lanes.rs`, every variant this processor has
//! against the portable one).
//!
//! # Why `std::arch` and not `pulp`
//!
//! `pulp` (in the tree through faer) dispatches one kernel to x86-64 V3/V4
//! and aarch64 NEON, but its vectors are as wide as the instruction set's
//! register (four doubles on AVX2, two on NEON) and its masks are vectors:
//! the kernels here are laid out one planet a lane across a fixed eight,
//! rotate the lanes by arbitrary indices to meet every pair of planets
//! ([`F8::permute`]) and keep their per-lane bookkeeping in `u8` masks
//! (stopping tests, brackets). Those are AVX-512's own forms, and on AVX2
//! they are two `vpermps` and a blend, a `movemask`; written by hand they
//! stay one trait with three small implementations, where `pulp` would
//! have meant rewriting every kernel around a width that changes with the
//! instruction set. The portable implementation is what aarch64 runs (its
//! NEON is the target's baseline, so the arrays are compiled for it).
//!
//! Lane masks are `u8` (bit `l` for lane `l`), the AVX-512 mask register's
//! own form.
//!
//! The lanes are internal to the crate (an `Avx512` value must never exist
//! on a processor without AVX-512F, an `Avx2` one without AVX2); the public
//! face is [`Level`], [`level`], the choice [`Simd`] of the splits and
//! [`KeplerSolver::drift_lanes8`](crate::kepler::KeplerSolver::drift_lanes8).

// Lane loops index several arrays at once.
#![allow(clippy::needless_range_loop)]

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU8, Ordering};

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

#[cfg(target_arch = "x86_64")]
pub(crate) use avx2::Avx2;

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::{F8, Portable, W};
    use std::arch::x86_64::*;

    /// Eight doubles in two AVX registers (lanes 0–3, 4–7). Only ever
    /// constructed inside functions compiled with `avx2` and called after
    /// `is_x86_feature_detected!("avx2")`; every method is inlined into
    /// them.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Avx2(__m256d, __m256d);

    /// The lanes of mask `m` as two vectors of all-ones / all-zeros lanes
    /// (the form `blendv` reads).
    #[inline(always)]
    fn lanes(m: u8) -> (__m256d, __m256d) {
        // SAFETY: AVX2 integer intrinsics; see the impl below.
        unsafe {
            let bits = _mm256_set1_epi64x(m as i64);
            let lo = _mm256_setr_epi64x(1, 2, 4, 8);
            let hi = _mm256_setr_epi64x(16, 32, 64, 128);
            (
                _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(bits, lo), lo)),
                _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(bits, hi), hi)),
            )
        }
    }

    /// The `u8` mask of two comparison results.
    #[inline(always)]
    fn bits(lo: __m256d, hi: __m256d) -> u8 {
        // SAFETY: AVX intrinsics; see the impl below.
        unsafe { (_mm256_movemask_pd(lo) | (_mm256_movemask_pd(hi) << 4)) as u8 }
    }

    /// Four lanes of the permute of `lo | hi` by the four indices `idx`
    /// (each `< 8`): both halves permuted by `idx mod 4` (a 64-bit lane is
    /// the pair of 32-bit lanes `2i, 2i + 1`, moved as they are: no
    /// arithmetic touches them), the one the index names kept.
    #[inline(always)]
    fn permute_half(lo: __m256d, hi: __m256d, idx: __m256i) -> __m256d {
        // SAFETY: AVX2 intrinsics; see the impl below.
        unsafe {
            let i = _mm256_and_si256(idx, _mm256_set1_epi64x(7));
            let two = _mm256_slli_epi64::<1>(_mm256_and_si256(i, _mm256_set1_epi64x(3)));
            let pair = _mm256_or_si256(
                two,
                _mm256_slli_epi64::<32>(_mm256_add_epi64(two, _mm256_set1_epi64x(1))),
            );
            let from_lo = _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(lo), pair));
            let from_hi = _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(hi), pair));
            let take_hi = _mm256_castsi256_pd(_mm256_cmpgt_epi64(i, _mm256_set1_epi64x(3)));
            _mm256_blendv_pd(from_lo, from_hi, take_hi)
        }
    }

    // SAFETY (every `unsafe` block below): these are AVX and AVX2
    // intrinsics; an `Avx2` exists only in code that runs after the
    // processor was found to have AVX2 (see the type's documentation).
    // Loads and stores read and write arrays of eight.
    impl F8 for Avx2 {
        #[inline(always)]
        fn splat(x: f64) -> Self {
            let v = unsafe { _mm256_set1_pd(x) };
            Avx2(v, v)
        }
        #[inline(always)]
        fn from_array(a: [f64; W]) -> Self {
            unsafe {
                Avx2(
                    _mm256_loadu_pd(a.as_ptr()),
                    _mm256_loadu_pd(a.as_ptr().add(4)),
                )
            }
        }
        #[inline(always)]
        fn to_array(self) -> [f64; W] {
            let mut out = [0.0; W];
            unsafe {
                _mm256_storeu_pd(out.as_mut_ptr(), self.0);
                _mm256_storeu_pd(out.as_mut_ptr().add(4), self.1);
            }
            out
        }
        #[inline(always)]
        fn add(self, b: Self) -> Self {
            unsafe { Avx2(_mm256_add_pd(self.0, b.0), _mm256_add_pd(self.1, b.1)) }
        }
        #[inline(always)]
        fn sub(self, b: Self) -> Self {
            unsafe { Avx2(_mm256_sub_pd(self.0, b.0), _mm256_sub_pd(self.1, b.1)) }
        }
        #[inline(always)]
        fn mul(self, b: Self) -> Self {
            unsafe { Avx2(_mm256_mul_pd(self.0, b.0), _mm256_mul_pd(self.1, b.1)) }
        }
        #[inline(always)]
        fn div(self, b: Self) -> Self {
            unsafe { Avx2(_mm256_div_pd(self.0, b.0), _mm256_div_pd(self.1, b.1)) }
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            unsafe { Avx2(_mm256_sqrt_pd(self.0), _mm256_sqrt_pd(self.1)) }
        }
        #[inline(always)]
        fn abs(self) -> Self {
            unsafe {
                let sign = _mm256_set1_pd(-0.0);
                Avx2(
                    _mm256_andnot_pd(sign, self.0),
                    _mm256_andnot_pd(sign, self.1),
                )
            }
        }
        #[inline(always)]
        fn neg(self) -> Self {
            unsafe {
                let sign = _mm256_set1_pd(-0.0);
                Avx2(_mm256_xor_pd(self.0, sign), _mm256_xor_pd(self.1, sign))
            }
        }
        #[inline(always)]
        fn max(self, b: Self) -> Self {
            // `a > b ? a : b`, and `a` where `b` is NaN (as the others).
            unsafe {
                let half = |a: __m256d, b: __m256d| {
                    let gt = _mm256_cmp_pd::<_CMP_GT_OQ>(a, b);
                    let bnan = _mm256_cmp_pd::<_CMP_UNORD_Q>(b, b);
                    _mm256_blendv_pd(b, a, _mm256_or_pd(gt, bnan))
                };
                Avx2(half(self.0, b.0), half(self.1, b.1))
            }
        }
        #[inline(always)]
        fn lt(self, b: Self) -> u8 {
            unsafe {
                bits(
                    _mm256_cmp_pd::<_CMP_LT_OQ>(self.0, b.0),
                    _mm256_cmp_pd::<_CMP_LT_OQ>(self.1, b.1),
                )
            }
        }
        #[inline(always)]
        fn le(self, b: Self) -> u8 {
            unsafe {
                bits(
                    _mm256_cmp_pd::<_CMP_LE_OQ>(self.0, b.0),
                    _mm256_cmp_pd::<_CMP_LE_OQ>(self.1, b.1),
                )
            }
        }
        #[inline(always)]
        fn eq(self, b: Self) -> u8 {
            unsafe {
                bits(
                    _mm256_cmp_pd::<_CMP_EQ_OQ>(self.0, b.0),
                    _mm256_cmp_pd::<_CMP_EQ_OQ>(self.1, b.1),
                )
            }
        }
        #[inline(always)]
        fn select(m: u8, a: Self, b: Self) -> Self {
            let (lo, hi) = lanes(m);
            unsafe {
                Avx2(
                    _mm256_blendv_pd(b.0, a.0, lo),
                    _mm256_blendv_pd(b.1, a.1, hi),
                )
            }
        }
        #[inline(always)]
        fn permute(self, idx: &[u64; W]) -> Self {
            unsafe {
                let lo = _mm256_loadu_si256(idx.as_ptr().cast());
                let hi = _mm256_loadu_si256(idx.as_ptr().add(4).cast());
                Avx2(
                    permute_half(self.0, self.1, lo),
                    permute_half(self.0, self.1, hi),
                )
            }
        }
        #[inline(always)]
        fn load3(src: &[f64], count: usize) -> [Self; 3] {
            // Once per kernel call (the loops keep the lanes in
            // registers): the portable gather is cheap enough.
            Portable::load3(src, count).map(|p| Self::from_array(p.0))
        }
        #[inline(always)]
        fn store3(v: &[Self; 3], dst: &mut [f64], count: usize) {
            Portable::store3(&v.map(|x| Portable(x.to_array())), dst, count)
        }
    }
}

/// Whether this processor has AVX-512F (whatever the cap: see [`level`]).
#[inline]
pub fn has_avx512() -> bool {
    Level::Avx512.available()
}

/// An instruction set the vector kernels of the workspace run on, lowest
/// first (the order of [`Ord`] is the order of the cap).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Level {
    /// The build's baseline (SSE2 on x86-64, NEON on aarch64).
    Portable,
    /// AVX2, 256-bit registers (x86-64).
    Avx2,
    /// AVX-512F, 512-bit registers (x86-64).
    Avx512,
}

impl Level {
    /// Every level, lowest first.
    pub const ALL: [Level; 3] = [Level::Portable, Level::Avx2, Level::Avx512];

    /// The level's name, as `SYMLAB_SIMD` spells it.
    pub fn name(self) -> &'static str {
        match self {
            Level::Portable => "portable",
            Level::Avx2 => "avx2",
            Level::Avx512 => "avx512",
        }
    }

    /// Whether this processor has the instruction set (the portable level:
    /// always).
    pub fn available(self) -> bool {
        match self {
            Level::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Level::Avx2 => std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(target_arch = "x86_64")]
            Level::Avx512 => std::arch::is_x86_feature_detected!("avx512f"),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }
}

impl std::fmt::Display for Level {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Level {
    type Err = SimdEnvError;
    /// `avx512`, `avx2` or `portable`, in any case, around spaces.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim();
        Level::ALL
            .into_iter()
            .find(|l| l.name().eq_ignore_ascii_case(t))
            .ok_or_else(|| SimdEnvError {
                value: s.to_string(),
            })
    }
}

/// The environment variable that caps the SIMD level: see [`env_cap`].
pub const ENV: &str = "SYMLAB_SIMD";

/// A value of `SYMLAB_SIMD` that names no level.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "SYMLAB_SIMD={value:?} is not a SIMD level: write avx512, avx2 or portable, or leave it unset for the best this processor has"
)]
pub struct SimdEnvError {
    /// What the variable held.
    pub value: String,
}

/// The cap `SYMLAB_SIMD` sets, read once per process: `avx512`, `avx2` or
/// `portable` (any case) caps every vector kernel of the workspace at that
/// level — the Wisdom–Holman lanes and their register loop, the Kepler
/// lanes, the cloth stencil and the banded cloth steps — so that the AVX2
/// and portable paths can be tested and measured on a processor that has
/// more (the bits do not change: see the [module documentation](self)).
/// Unset or empty: no cap. A cap above what the processor has changes
/// nothing (the processor's best runs).
///
/// Any other value is an error here, for a front end to report before it
/// runs anything. The kernels themselves, which cannot return it, refuse
/// such a value: they write one line to standard error naming it and run
/// on the portable level (a cap that was meant but misspelt is then still
/// a cap, and a slow one, never the silent full speed).
pub fn env_cap() -> Result<Option<Level>, SimdEnvError> {
    static CAP: OnceLock<Result<Option<Level>, SimdEnvError>> = OnceLock::new();
    CAP.get_or_init(|| match std::env::var_os(ENV) {
        None => Ok(None),
        Some(v) => {
            let s = v.to_string_lossy();
            if s.trim().is_empty() {
                Ok(None)
            } else {
                s.parse().map(Some)
            }
        }
    })
    .clone()
}

/// The cap [`set_cap`] put in place of `SYMLAB_SIMD`'s: 0 none (the
/// variable's holds), [`NO_CAP`] (after [`lift_cap`]), else 1 + the level
/// (`Level as u8`).
static CAP_OVERRIDE: AtomicU8 = AtomicU8::new(0);
/// [`CAP_OVERRIDE`]'s "no cap at all".
const NO_CAP: u8 = 0xff;
/// [`level`] resolved: 0 not yet, else 1 + the level.
static RESOLVED: AtomicU8 = AtomicU8::new(0);

/// Put `cap` in place of `SYMLAB_SIMD`'s cap for the rest of the process
/// (`Some(level)`: at most `level`; `None`: back to `SYMLAB_SIMD`'s), for
/// tests and benchmarks that run one variant after another in one process.
/// Kernels already running finish on the level they started on; the
/// variants give the same bits, so a kernel that a concurrent call moves
/// to another level computes the same numbers.
pub fn set_cap(cap: Option<Level>) {
    CAP_OVERRIDE.store(cap.map_or(0, |l| 1 + l as u8), Ordering::SeqCst);
    RESOLVED.store(0, Ordering::SeqCst);
}

/// Lift every cap, `SYMLAB_SIMD`'s included, for the rest of the process
/// (until the next [`set_cap`]): the kernels run on the best the processor
/// has.
pub fn lift_cap() {
    CAP_OVERRIDE.store(NO_CAP, Ordering::SeqCst);
    RESOLVED.store(0, Ordering::SeqCst);
}

/// The best level this processor has.
pub fn detected() -> Level {
    Level::ALL
        .into_iter()
        .rev()
        .find(|l| l.available())
        .unwrap_or(Level::Portable)
}

/// The level the vector kernels run on: the best this processor has,
/// capped by [`set_cap`] or else by `SYMLAB_SIMD` ([`env_cap`]; a value
/// it does not know: the portable level, said once on standard error).
/// Resolved once and kept (until the next [`set_cap`]).
pub fn level() -> Level {
    let r = RESOLVED.load(Ordering::Relaxed);
    if r != 0 {
        return Level::ALL[(r - 1) as usize];
    }
    let cap = match CAP_OVERRIDE.load(Ordering::SeqCst) {
        NO_CAP => None,
        0 => match env_cap() {
            Ok(cap) => cap,
            Err(e) => {
                static SAID: std::sync::Once = std::sync::Once::new();
                SAID.call_once(|| eprintln!("symlab: {e}; running the portable kernels"));
                Some(Level::Portable)
            }
        },
        c => Some(Level::ALL[(c - 1) as usize]),
    };
    let l = cap.map_or(detected(), |c| c.min(detected()));
    RESOLVED.store(1 + l as u8, Ordering::Relaxed);
    l
}

/// Which implementation of the eight-lane kernels a Wisdom–Holman split
/// uses for up to eight planets: the same bits on every one (see the
/// [module documentation](self)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Simd {
    /// [`level`]: the best the processor has, under the cap of
    /// `SYMLAB_SIMD` or [`set_cap`].
    #[default]
    Auto,
    /// AVX-512 where the processor has it, else the best it has (whatever
    /// the cap: asked for by name).
    Avx512,
    /// AVX2 where the processor has it, else the portable arrays (whatever
    /// the cap).
    Avx2,
    /// The portable arrays, compiled for the build's baseline.
    Portable,
}

impl Simd {
    /// The level the kernels run on: the one asked for, as far as the
    /// processor has it ([`Simd::Auto`]: [`level`]).
    #[inline]
    pub fn level(self) -> Level {
        match self {
            Simd::Auto => level(),
            Simd::Avx512 => detected(),
            Simd::Avx2 => Level::Avx2.min(detected()),
            Simd::Portable => Level::Portable,
        }
    }

    /// Whether the kernels run on AVX-512 (asked and available).
    #[inline]
    pub fn avx512(self) -> bool {
        self.level() == Level::Avx512
    }
}

impl From<Level> for Simd {
    /// The choice that runs `level` (where the processor has it).
    fn from(level: Level) -> Self {
        match level {
            Level::Portable => Simd::Portable,
            Level::Avx2 => Simd::Avx2,
            Level::Avx512 => Simd::Avx512,
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

/// Run `k` on the implementation of the level `simd` resolves to.
#[inline]
pub(crate) fn dispatch<K: Kernel>(simd: Simd, k: K) -> K::Out {
    match simd.level() {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: resolved to AVX-512 only where the processor has AVX-512F.
        Level::Avx512 => unsafe { on_avx512(k) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: resolved to AVX2 only where the processor has AVX2.
        Level::Avx2 => unsafe { on_avx2(k) },
        _ => k.run::<Portable>(),
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
    k.run::<Avx2>()
}
