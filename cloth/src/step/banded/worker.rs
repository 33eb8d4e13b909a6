//! One band's share of a frame of banded steps: its flows over its rows,
//! the force of its rows between two barriers.

use std::ops::Range;

use super::barrier::{PoisonOnPanic, SpinBarrier};
use super::grid::Positions;
use crate::model::ClothModel;
use integrator_core::Part;
use integrator_core::sequence::Sequence;

/// What every worker of a frame shares.
pub(super) struct Frame<'a> {
    pub model: &'a ClothModel,
    pub seq: &'a Sequence,
    pub h: f64,
    pub steps: usize,
    pub positions: &'a Positions,
    pub barrier: &'a SpinBarrier,
    pub start: Phase,
    /// Particle id → free index, or `u32::MAX` when pinned.
    pub free_of: &'a [u32],
    pub free_count: usize,
}

/// Where the stepping stands between two flows; the same in every worker.
#[derive(Clone, Copy, Debug)]
pub(super) struct Phase {
    /// The position buffer that holds the current positions.
    pub cur: usize,
    /// The last flow was a drift: the next one (a drift again, across a
    /// step boundary) updates the current buffer in place.
    pub after_drift: bool,
    /// The band's force arrays hold the force at the current positions.
    pub force_valid: bool,
}

/// A band's own arrays: its rows of the grid's momenta, their carried
/// rounding errors and those of the positions, its force, and which of
/// its particles are free (1.0) or pinned (0.0).
pub(super) struct Band<'a> {
    pub rows: Range<usize>,
    pub p: [&'a mut [f64]; 3],
    pub ep: [&'a mut [f64]; 3],
    pub eq: [&'a mut [f64]; 3],
    pub f: [&'a mut [f64]; 3],
    pub free: &'a [f64],
    pub row: &'a mut [Vec<f64>; 3],
}

/// The first step of a frame that left a non-finite value in a band: the
/// step (from 0), the smallest index of such a value in `z = [q; p]`, and
/// the value.
pub(super) type NonFinite = (usize, usize, f64);

/// Run the frame's steps on `band`; returns the phase at the end (the same
/// in every worker) and the band's first non-finite step, if any. The
/// barriers: one before every force evaluation (the drifts of all bands
/// are done). None is needed before a drift: a drift writes the buffer
/// that is not current (or, right after another drift, the current one
/// again), which no worker reads until after the next barrier (see
/// [`super::grid`]).
pub(super) fn run(frame: &Frame<'_>, band: Band<'_>) -> (Phase, Option<NonFinite>) {
    let _poison = PoisonOnPanic(frame.barrier);
    // The flows' loops compiled for the level `integrator_core::simd::level`
    // picks: the widest vectors the CPU has, under the cap of `SYMLAB_SIMD`.
    use integrator_core::simd::{Level, level};
    match level() {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `level` picks AVX-512 only where the CPU has AVX-512F.
        Level::Avx512 => unsafe { run_avx512(frame, band) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `level` picks AVX2 only where the CPU has AVX2.
        Level::Avx2 => unsafe { run_avx2(frame, band) },
        _ => run_body(frame, band),
    }
}

/// [`run_body`] with the flows' loops compiled for AVX-512 (the same bits:
/// no fused multiply–adds, as on every path).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn run_avx512(frame: &Frame<'_>, band: Band<'_>) -> (Phase, Option<NonFinite>) {
    run_body(frame, band)
}

/// [`run_body`] for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_avx2(frame: &Frame<'_>, band: Band<'_>) -> (Phase, Option<NonFinite>) {
    run_body(frame, band)
}

#[inline(always)]
fn run_body(frame: &Frame<'_>, mut band: Band<'_>) -> (Phase, Option<NonFinite>) {
    let Frame {
        model,
        seq,
        h,
        positions,
        barrier,
        ..
    } = *frame;
    let mut phase = frame.start;
    let colliders = model.has_colliders();
    // With colliders the force arrays hold the weight already.
    let w = if colliders {
        [0.0; 3]
    } else {
        model.weight().into()
    };
    let inv = model.inverse_mass();
    let rows = band.rows.clone();
    let mut first_bad = None;
    for step in 0..frame.steps {
        let mut bad = false;
        for &(part, c) in seq.ops() {
            let hc = h * c;
            match part {
                // A kick: the flow of the forces.
                Part::B => {
                    if !phase.force_valid {
                        barrier.wait();
                        // SAFETY: past the barrier no worker writes the
                        // current buffer (see `grid`).
                        let pos = unsafe { positions.all(phase.cur) };
                        let [fx, fy, fz] = &mut band.f;
                        model.band_springs(&pos, rows.clone(), [fx, fy, fz], band.row);
                        if colliders {
                            // SAFETY: as above.
                            let own = unsafe { positions.rows(phase.cur, rows.clone()) };
                            let [fx, fy, fz] = &mut band.f;
                            model.band_colliders(own, band.free, [fx, fy, fz]);
                        }
                        phase.force_valid = true;
                    }
                    bad |= kick(hc, w, band.free, &band.f, &mut band.p, &mut band.ep);
                    phase.after_drift = false;
                }
                // A drift: the flow of the kinetic energy.
                Part::A => {
                    if phase.after_drift {
                        // SAFETY: only this worker writes its rows; the
                        // current buffer's are read by no one until the
                        // next barrier.
                        let q = unsafe { positions.rows_mut(phase.cur, rows.clone()) };
                        bad |= drift_in_place(hc, inv, &band.p, &mut band.eq, q);
                    } else {
                        // SAFETY: the other buffer is read by no one until
                        // the next barrier, and only this worker writes its
                        // rows.
                        let (src, dst) = unsafe {
                            (
                                positions.rows(phase.cur, rows.clone()),
                                positions.rows_mut(1 - phase.cur, rows.clone()),
                            )
                        };
                        bad |= drift(hc, inv, &band.p, &mut band.eq, src, dst);
                        phase.cur = 1 - phase.cur;
                    }
                    phase.after_drift = true;
                    phase.force_valid = false;
                }
            }
        }
        if bad && first_bad.is_none() {
            first_bad = locate(frame, &band, phase.cur).map(|(i, v)| (step, i, v));
        }
    }
    (phase, first_bad)
}

/// `p += h·c·F` with the carried rounding error `e` (as the library's
/// split steps: `inc = e + hc·F`), `F = (w + f)·free`, so that pinned
/// particles keep `p = 0`. Whether a new `p` is not finite.
#[inline(always)]
fn kick(
    hc: f64,
    w: [f64; 3],
    free: &[f64],
    f: &[&mut [f64]; 3],
    p: &mut [&mut [f64]; 3],
    e: &mut [&mut [f64]; 3],
) -> bool {
    let n = free.len();
    let mut bad = false;
    for c in 0..3 {
        let (f, p, e, w) = (&f[c][..n], &mut p[c][..n], &mut e[c][..n], w[c]);
        for i in 0..n {
            let g = (w + f[i]) * free[i];
            let inc = e[i] + hc * g;
            let new = p[i] + inc;
            e[i] = (p[i] - new) + inc;
            p[i] = new;
            bad |= !new.is_finite();
        }
    }
    bad
}

/// `dst = src + h·c·M⁻¹p` with the carried rounding error `e` (the
/// velocity `M⁻¹p` formed first, as [`Separable::velocity`]
/// (integrator_core::Separable::velocity) forms it). Pinned particles
/// (`p = 0`) stay where they are, to the bit. Whether a new position is not
/// finite.
#[inline(always)]
fn drift(
    hc: f64,
    inv: f64,
    p: &[&mut [f64]; 3],
    e: &mut [&mut [f64]; 3],
    src: [&[f64]; 3],
    dst: [&mut [f64]; 3],
) -> bool {
    let mut bad = false;
    for (c, dst) in dst.into_iter().enumerate() {
        let n = dst.len();
        let (p, e, src) = (&p[c][..n], &mut e[c][..n], &src[c][..n]);
        for i in 0..n {
            let inc = e[i] + hc * (inv * p[i]);
            let new = src[i] + inc;
            e[i] = (src[i] - new) + inc;
            dst[i] = new;
            bad |= !new.is_finite();
        }
    }
    bad
}

/// [`drift`] with the positions updated in place.
#[inline(always)]
fn drift_in_place(
    hc: f64,
    inv: f64,
    p: &[&mut [f64]; 3],
    e: &mut [&mut [f64]; 3],
    q: [&mut [f64]; 3],
) -> bool {
    let mut bad = false;
    for (c, q) in q.into_iter().enumerate() {
        let n = q.len();
        let (p, e) = (&p[c][..n], &mut e[c][..n]);
        for i in 0..n {
            let inc = e[i] + hc * (inv * p[i]);
            let new = q[i] + inc;
            e[i] = (q[i] - new) + inc;
            q[i] = new;
            bad |= !new.is_finite();
        }
    }
    bad
}

/// The smallest index in `z = [q; p]` of a non-finite value of the band's
/// free particles, with the value.
fn locate(frame: &Frame<'_>, band: &Band<'_>, cur: usize) -> Option<(usize, f64)> {
    // SAFETY: only this worker writes its rows.
    let q = unsafe { frame.positions.rows(cur, band.rows.clone()) };
    let nx = frame.model.grid().0;
    let base = band.rows.start * nx;
    let mut found: Option<(usize, f64)> = None;
    let ids = frame.free_of[base..base + band.free.len()]
        .iter()
        .enumerate();
    for (k, &free) in ids.filter(|(_, f)| **f != u32::MAX) {
        let free = free as usize;
        for (c, (q, p)) in q.iter().zip(&band.p).enumerate() {
            for (index, value) in [
                (3 * free + c, q[k]),
                (3 * (frame.free_count + free) + c, p[k]),
            ] {
                if !value.is_finite() && found.is_none_or(|(i, _)| index < i) {
                    found = Some((index, value));
                }
            }
        }
    }
    found
}
