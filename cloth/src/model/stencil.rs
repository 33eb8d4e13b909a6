//! The spring force of the explicit step as stencil loops over the grid.
//!
//! Why: the spring lists ([`Spring`](super::Spring), free–free and
//! free–pinned) are walked one spring at a time with indirect loads and
//! stores, which no compiler vectorises. On the grid every spring family is
//! a fixed offset (`(i, j) → (i + di, j + dj)`, [`super::springs::directions`])
//! with one `k/L` and one rest length, so the same forces come from loops
//! over contiguous runs of particles: positions copied once per evaluation
//! into three coordinate arrays of the whole grid (pinned particles at
//! their fixed places, so pins need no special case), then per direction
//! and row the tension `d·(k/L − k/L·L/|d|)` of every spring of the row into
//! a row buffer, added to the first ends and subtracted from the second.
//! Each of these loops is straight-line arithmetic over slices, which the
//! compiler vectorises; the forces are gathered back to the free particles.
//!
//! The tensions are the same expressions as the list loop's; only the order
//! in which a particle's contributions are summed differs, so the forces
//! agree to round-off (tested against the list loop).
//!
//! With [`Stencil::BANDS`] bands of rows one evaluation splits over threads
//! (rayon): each band accumulates into its own force arrays (a spring of
//! one band may end in the next), summed at the gather. The scratch is
//! allocated with the model; the single-band path allocates nothing, the
//! parallel one only what rayon's job queue takes now and then. That split
//! pays only on very large grids ([`Stencil::PARALLEL_FROM`]): the
//! explicit drift–kick schemes use two threads another way, a whole frame
//! of steps on long-lived workers that each own a band of rows
//! ([`crate::step::banded`]), through [`Stencil::rows`], the same loops
//! restricted to the particles of a band, which computes the springs
//! crossing the band's edges itself so that each particle's force is summed
//! in the same order as here (the same bits).

use std::sync::{Mutex, TryLockError};

use rayon::prelude::*;

use super::Family;

/// One spring direction of the grid with its constants.
#[derive(Clone, Copy, Debug)]
struct Direction {
    di: isize,
    dj: usize,
    kl: f64,
    rest: f64,
}

/// The grid's spring directions, with the scratch of an evaluation.
#[derive(Debug)]
pub(super) struct Stencil {
    nx: usize,
    ny: usize,
    dirs: Vec<Direction>,
    /// Allocated with the model, so that an evaluation allocates nothing.
    /// An evaluation holds the lock; one that finds it held (the same model
    /// evaluated on two threads at once) works in a scratch of its own.
    scratch: Mutex<Scratch>,
}

impl Clone for Stencil {
    fn clone(&self) -> Stencil {
        Stencil {
            nx: self.nx,
            ny: self.ny,
            dirs: self.dirs.clone(),
            scratch: Mutex::new(Scratch::new(self.nx, self.ny)),
        }
    }
}

/// The grid's coordinates, and per band its force arrays and the row
/// buffer of tensions.
#[derive(Debug)]
struct Scratch {
    pos: [Vec<f64>; 3],
    bands: Vec<Band>,
}

#[derive(Debug)]
struct Band {
    force: [Vec<f64>; 3],
    row: [Vec<f64>; 3],
}

impl Scratch {
    fn new(nx: usize, ny: usize) -> Scratch {
        let n = nx * ny;
        let bands = if n >= Stencil::PARALLEL_FROM {
            Stencil::BANDS
        } else {
            1
        };
        Scratch {
            pos: std::array::from_fn(|_| vec![0.0; n]),
            bands: (0..bands)
                .map(|_| Band {
                    force: std::array::from_fn(|_| vec![0.0; n]),
                    row: std::array::from_fn(|_| vec![0.0; nx]),
                })
                .collect(),
        }
    }
}

impl Stencil {
    /// Row bands evaluated in parallel where the grid is large enough to
    /// pay for the threads' hand-over (two: this project's machines have
    /// two cores; more bands would cost the extra force arrays' sum).
    pub(super) const BANDS: usize = 2;
    /// Below this many particles one thread does all the rows of an
    /// evaluation. Measured (docs/results/cloth-springs.md): at 64² the hand-over
    /// of the three parallel phases (positions, bands, gather) to rayon's
    /// second thread cost more than it saved; at 128² the force alone
    /// gained 1.27×, but whole steps lost (the second thread goes to sleep
    /// during the drift and is woken for every force). So two threads are
    /// used only from 256² on, where a band is four times the work; that
    /// size was not measured. The drift–kick schemes do not come here for
    /// their threads: they step in bands on workers that live for a frame
    /// ([`crate::step::banded`], from
    /// [`BANDED_FROM`](crate::step::banded::BANDED_FROM) particles); this
    /// split serves every other caller of the model's force (the
    /// Runge–Kutta tables, the explicit pairs' own steps when banding is
    /// off, the solvers).
    pub(super) const PARALLEL_FROM: usize = 256 * 256;

    /// The stencil of an `nx × ny` grid: `dirs` as
    /// [`directions`](super::springs::directions) gives them, with the
    /// stiffness `k` of each family (`k/L` is formed as the spring lists
    /// form it).
    pub(super) fn new(
        nx: usize,
        ny: usize,
        dirs: &[(isize, isize, Family, f64)],
        stiffness: impl Fn(Family) -> f64,
    ) -> Stencil {
        let dirs = dirs
            .iter()
            .map(|&(di, dj, family, rest)| Direction {
                di,
                dj: dj as usize,
                kl: stiffness(family) / rest,
                rest,
            })
            .collect();
        Stencil {
            nx,
            ny,
            dirs,
            scratch: Mutex::new(Scratch::new(nx, ny)),
        }
    }

    /// The springs' force on every free particle plus `weight`, into `out`
    /// (`[fx, fy, fz]` per free particle): `free_index` maps a particle id
    /// to its free index or [`super::PINNED`], `start` holds the pinned
    /// particles' positions, `q` the free ones'.
    pub(super) fn force(
        &self,
        q: &[f64],
        out: &mut [f64],
        free_index: &[u32],
        free_ids: &[u32],
        start: &[nalgebra::Vector3<f64>],
        weight: [f64; 3],
    ) {
        let mut own;
        let mut guard = match self.scratch.try_lock() {
            Ok(g) => Some(g),
            // A panic elsewhere left the scratch mid-evaluation: it is
            // rewritten from the start, so it is as good as new.
            Err(TryLockError::Poisoned(p)) => Some(p.into_inner()),
            Err(TryLockError::WouldBlock) => None,
        };
        let scratch = match guard.as_deref_mut() {
            Some(s) => s,
            None => {
                own = Scratch::new(self.nx, self.ny);
                &mut own
            }
        };
        let Scratch { pos, bands } = scratch;
        // Small grids never touch rayon (its pool starts threads on first
        // use, which allocates).
        let used = if bands.len() == 1 || rayon::current_num_threads() == 1 {
            1
        } else {
            bands.len()
        };
        // The grid's positions, pinned particles where they stay; in two
        // halves on two threads where the bands are.
        let q3 = q.as_chunks::<3>().0;
        let scatter = |k0: usize, px: &mut [f64], py: &mut [f64], pz: &mut [f64]| {
            let ids = &free_index[k0..k0 + px.len()];
            for (k, &f) in ids.iter().enumerate() {
                let x = if f == super::PINNED {
                    let s = &start[k0 + k];
                    [s.x, s.y, s.z]
                } else {
                    q3[f as usize]
                };
                (px[k], py[k], pz[k]) = (x[0], x[1], x[2]);
            }
        };
        let [px, py, pz] = pos;
        if used == 1 {
            scatter(0, px, py, pz);
        } else {
            let mid = px.len() / 2;
            let (px0, px1) = px.split_at_mut(mid);
            let (py0, py1) = py.split_at_mut(mid);
            let (pz0, pz1) = pz.split_at_mut(mid);
            rayon::join(|| scatter(0, px0, py0, pz0), || scatter(mid, px1, py1, pz1));
        }
        let pos = [&px[..], &py[..], &pz[..]];
        if used == 1 {
            self.band(&pos, 0..self.ny, &mut bands[0]);
        } else {
            bands.par_iter_mut().enumerate().for_each(|(b, buf)| {
                self.band(&pos, self.band_rows(b, used), buf);
            });
        }
        // Gather to the free particles, with the weight: each band's force
        // where it wrote (the particle ids of the rows its springs start in
        // and reach).
        let nx = self.nx;
        let mut written: [std::ops::Range<usize>; Self::BANDS] = std::array::from_fn(|_| 0..0);
        for (b, w) in written.iter_mut().enumerate().take(used) {
            let rows = self.written(&self.band_rows(b, used));
            *w = rows.start * nx..rows.end * nx;
        }
        let bands = &bands[..used];
        let gather = |f3: &mut [[f64; 3]], ids: &[u32]| {
            for (f, &id) in f3.iter_mut().zip(ids) {
                let id = id as usize;
                let mut g = weight;
                for (band, w) in bands.iter().zip(&written) {
                    if w.contains(&id) {
                        g[0] += band.force[0][id];
                        g[1] += band.force[1][id];
                        g[2] += band.force[2][id];
                    }
                }
                *f = g;
            }
        };
        let f3 = &mut out.as_chunks_mut::<3>().0[..free_ids.len()];
        if used == 1 {
            gather(f3, free_ids);
        } else {
            let mid = f3.len() / 2;
            let (f0, f1) = f3.split_at_mut(mid);
            let (i0, i1) = free_ids.split_at(mid);
            rayon::join(|| gather(f0, i0), || gather(f1, i1));
        }
    }

    /// The rows a band starting springs in `rows` writes: its own and the
    /// rows its springs reach below it.
    fn written(&self, rows: &std::ops::Range<usize>) -> std::ops::Range<usize> {
        rows.start..(rows.end + self.reach()).min(self.ny)
    }

    /// The rows of band `b` of `bands`.
    fn band_rows(&self, b: usize, bands: usize) -> std::ops::Range<usize> {
        let per = self.ny.div_ceil(bands);
        (b * per).min(self.ny)..((b + 1) * per).min(self.ny)
    }

    /// The springs of the band of rows `rows` (those that start there),
    /// into `buf.force` (zeroed first over the rows they reach).
    fn band(&self, pos: &[&[f64]; 3], rows: std::ops::Range<usize>, buf: &mut Band) {
        let nx = self.nx;
        let written = self.written(&rows);
        let Band { force, row } = buf;
        let [fx, fy, fz] = force;
        let cut = written.start * nx..written.end * nx;
        let force = [&mut fx[cut.clone()], &mut fy[cut.clone()], &mut fz[cut]];
        self.rows(pos, rows, written, force, row);
    }

    /// The rows any spring reaches beyond the row it starts in (2 with bend
    /// springs, 1 without, 0 with stretch along rows only).
    pub(super) fn reach(&self) -> usize {
        self.dirs.iter().map(|d| d.dj).max().unwrap_or(0)
    }

    /// The tensions of the springs that start in rows `starts`, accumulated
    /// at both ends into `force` (zeroed first), but only at particles in
    /// rows `writes`: `force[c][k]` belongs to particle `writes.start·nx +
    /// k`. [`band_body`](Self::band_body) compiled for the level
    /// [`integrator_core::simd::level`] picks (the widest vectors the CPU
    /// has — AVX-512, AVX2, else the target's baseline, SSE2 on x86-64 —
    /// under the cap of `SYMLAB_SIMD`): the same loops, so the same bits on
    /// every path (vector square roots and divisions round as the scalar
    /// ones do, Rust never fuses a multiply and an add on its own, and no
    /// path enables `fma`).
    ///
    /// Each particle's contributions are summed in one fixed order
    /// (direction by direction, in each the spring it ends before the one
    /// it starts, or for springs along a row the one it starts first),
    /// whatever `starts` and `writes` are, as long as `starts` holds every
    /// spring reaching `writes`: so a band of rows that computes the
    /// springs crossing its edges itself ([`crate::step::banded`]) gets
    /// its particles' forces to the bit as one pass over the whole grid.
    pub(super) fn rows(
        &self,
        pos: &[&[f64]; 3],
        starts: std::ops::Range<usize>,
        writes: std::ops::Range<usize>,
        force: [&mut [f64]; 3],
        row: &mut [Vec<f64>; 3],
    ) {
        use integrator_core::simd::{Level, level};
        match level() {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `level` picks AVX-512 only where the CPU has AVX-512F.
            Level::Avx512 => unsafe { self.rows_avx512(pos, starts, writes, force, row) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `level` picks AVX2 only where the CPU has AVX2.
            Level::Avx2 => unsafe { self.rows_avx2(pos, starts, writes, force, row) },
            _ => self.band_body(pos, starts, writes, force, row),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn rows_avx512(
        &self,
        pos: &[&[f64]; 3],
        starts: std::ops::Range<usize>,
        writes: std::ops::Range<usize>,
        force: [&mut [f64]; 3],
        row: &mut [Vec<f64>; 3],
    ) {
        self.band_body(pos, starts, writes, force, row)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn rows_avx2(
        &self,
        pos: &[&[f64]; 3],
        starts: std::ops::Range<usize>,
        writes: std::ops::Range<usize>,
        force: [&mut [f64]; 3],
        row: &mut [Vec<f64>; 3],
    ) {
        self.band_body(pos, starts, writes, force, row)
    }

    /// The loops of [`rows`](Self::rows): per direction and starting row,
    /// the tension `d·(k/L − k/L·L/|d|)` of every spring of the row into the
    /// row buffer, added to the first ends and subtracted from the second
    /// (each where it lies in `writes`).
    #[inline(always)]
    fn band_body(
        &self,
        pos: &[&[f64]; 3],
        starts: std::ops::Range<usize>,
        writes: std::ops::Range<usize>,
        force: [&mut [f64]; 3],
        row: &mut [Vec<f64>; 3],
    ) {
        let nx = self.nx;
        let [fx, fy, fz] = force;
        for c in [&mut *fx, &mut *fy, &mut *fz] {
            c.fill(0.0);
        }
        let base = writes.start * nx;
        let [tx, ty, tz] = row;
        let [px, py, pz] = *pos;
        for d in &self.dirs {
            // Starting columns whose partner column exists.
            let i0 = (-d.di).max(0) as usize;
            let i1 = nx - d.di.max(0) as usize;
            if i0 >= i1 {
                continue;
            }
            let len = i1 - i0;
            let off = d.dj * nx;
            let (kl, klr) = (d.kl, d.kl * d.rest);
            // Rows whose springs start in `starts` and end in the grid with
            // an end in `writes`.
            let j0 = starts.start.max(writes.start.saturating_sub(d.dj));
            let j1 = starts.end.min(writes.end).min(self.ny.saturating_sub(d.dj));
            for j in j0..j1 {
                let a = j * nx + i0;
                let b = (a + off).wrapping_add_signed(d.di);
                let (tx, ty, tz) = (&mut tx[..len], &mut ty[..len], &mut tz[..len]);
                let (ax, ay, az) = (&px[a..a + len], &py[a..a + len], &pz[a..a + len]);
                let (bx, by, bz) = (&px[b..b + len], &py[b..b + len], &pz[b..b + len]);
                for i in 0..len {
                    let (dx, dy, dz) = (bx[i] - ax[i], by[i] - ay[i], bz[i] - az[i]);
                    let l = (dx * dx + dy * dy + dz * dz).sqrt();
                    let s = kl - klr / l;
                    (tx[i], ty[i], tz[i]) = (dx * s, dy * s, dz * s);
                }
                if j >= writes.start {
                    let a = a - base;
                    add(&mut fx[a..a + len], tx);
                    add(&mut fy[a..a + len], ty);
                    add(&mut fz[a..a + len], tz);
                }
                if j + d.dj < writes.end {
                    let b = b - base;
                    sub(&mut fx[b..b + len], tx);
                    sub(&mut fy[b..b + len], ty);
                    sub(&mut fz[b..b + len], tz);
                }
            }
        }
    }
}

#[inline(always)]
fn add(f: &mut [f64], t: &[f64]) {
    for (f, t) in f.iter_mut().zip(t) {
        *f += t;
    }
}

#[inline(always)]
fn sub(f: &mut [f64], t: &[f64]) {
    for (f, t) in f.iter_mut().zip(t) {
        *f -= t;
    }
}
