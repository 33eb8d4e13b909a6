//! The grid's positions as the workers of a banded frame share them: two
//! buffers of three coordinate arrays over all particles (pinned ones at
//! their fixed places), one of them current.
//!
//! Who reads and writes what, which is what makes the raw pointers sound:
//! a worker writes only its own rows, in a drift; a force reads the current
//! buffer everywhere its band's springs reach, only after a barrier that
//! every worker reaches after its drifts. A drift after a kick reads the
//! current buffer and writes the other one, which then becomes current: the
//! last reads of the other buffer were forces before the barrier that
//! preceded the current buffer's force, so all are done. A drift right
//! after a drift (two steps meeting, `D … D | D … D`) updates the current
//! buffer in place: it was written by the drift just before, and no force
//! has read it since. So no reader ever overlaps a writer, with one barrier
//! per force evaluation and none per drift.

use std::ops::Range;

/// Raw views of the two position buffers, shared by the workers of one
/// frame (the buffers are borrowed mutably for the frame's length).
pub(super) struct Positions {
    ptr: [[*mut f64; 3]; 2],
    len: usize,
    nx: usize,
}

// SAFETY: the workers' accesses follow the protocol of the module
// documentation: no write overlaps another access.
unsafe impl Sync for Positions {}

impl Positions {
    pub(super) fn new(buffers: &mut [[Vec<f64>; 3]; 2], nx: usize) -> Positions {
        let len = buffers[0][0].len();
        assert!(buffers.iter().flatten().all(|b| b.len() == len));
        let [a, b] = buffers;
        let [a0, a1, a2] = a;
        let [b0, b1, b2] = b;
        Positions {
            ptr: [
                [a0.as_mut_ptr(), a1.as_mut_ptr(), a2.as_mut_ptr()],
                [b0.as_mut_ptr(), b1.as_mut_ptr(), b2.as_mut_ptr()],
            ],
            len,
            nx,
        }
    }

    /// Buffer `buf` over the whole grid.
    ///
    /// # Safety
    /// No worker writes buffer `buf` while the slices live.
    pub(super) unsafe fn all(&self, buf: usize) -> [&[f64]; 3] {
        // SAFETY: in bounds; no writer, by the caller's promise.
        self.ptr[buf].map(|p| unsafe { std::slice::from_raw_parts(p, self.len) })
    }

    /// Rows `rows` of buffer `buf`.
    ///
    /// # Safety
    /// No worker writes those rows of buffer `buf` while the slices live.
    pub(super) unsafe fn rows(&self, buf: usize, rows: Range<usize>) -> [&[f64]; 3] {
        let (start, len) = self.cut(rows);
        // SAFETY: in bounds (`cut`); no writer, by the caller's promise.
        self.ptr[buf].map(|p| unsafe { std::slice::from_raw_parts(p.add(start), len) })
    }

    /// Rows `rows` of buffer `buf`, to write.
    ///
    /// # Safety
    /// No other access to those rows of buffer `buf` while the slices live.
    #[allow(clippy::mut_from_ref)]
    pub(super) unsafe fn rows_mut(&self, buf: usize, rows: Range<usize>) -> [&mut [f64]; 3] {
        let (start, len) = self.cut(rows);
        // SAFETY: in bounds (`cut`); exclusive, by the caller's promise.
        self.ptr[buf].map(|p| unsafe { std::slice::from_raw_parts_mut(p.add(start), len) })
    }

    fn cut(&self, rows: Range<usize>) -> (usize, usize) {
        let (start, end) = (rows.start * self.nx, rows.end * self.nx);
        assert!(start <= end && end <= self.len, "rows out of the grid");
        (start, end - start)
    }
}
