//! Drift–kick schemes on the spring model stepped in bands of grid rows,
//! on two threads for a whole frame ([`BandedStepper`]).
//!
//! Why: a scheme's own step ([`SchemeStepper`](super::SchemeStepper))
//! calls the model's force once per kick on the state `[q; p]`, so the
//! only place for threads is inside the force, where handing each
//! evaluation to a second thread and back costs more than it saves
//! (docs/results/cloth-springs.md). Here the stepper holds the state in arrays over
//! the grid (positions `x, y, z` with the pinned particles in place, in two
//! buffers; momenta; the carried rounding errors of the compensated
//! updates) from [`enter`](super::ClothStepper::enter) to
//! [`leave`](super::ClothStepper::leave), and runs the frame's steps
//! ([`steps`](super::ClothStepper::steps)) on long-lived workers, one per
//! band of rows, started once with the stepper and kept awake between
//! frames (`crew.rs`, which says why); `enter` and `leave` copy each band's
//! particles on its own thread too. Every
//! worker applies every flow of the [`Sequence`] to its own rows; before a
//! force evaluation the workers meet at a spinning barrier (the force
//! reads the neighbour rows' positions), and nowhere else (`grid`).
//! Springs crossing a band's edge are computed by both bands they touch,
//! each for its own particles, so that no force is summed across threads
//! and each particle's force is summed in one fixed order: the same bits
//! on one thread or two, and the same bits as
//! [`Separable::force`](integrator_core::Separable::force) (the stencil
//! kernel, one band, plus weight and colliders), so that a library
//! drift–kick sequence steps to the bit as its own step does.
//!
//! `worker.rs` holds a band's share of a frame (flows, force, the
//! non-finite check), `grid.rs` the shared position buffers and why the
//! one barrier per force suffices, `barrier.rs` the barrier, `crew.rs` the
//! threads, `sequence.rs` the flows by method id.

mod barrier;
mod crew;
mod grid;
mod sequence;
mod worker;

use std::ops::Range;

pub use integrator_core::sequence::Sequence;
pub use sequence::sequence_of;

use super::{ClothStepper, Halt, Halted, SolverStats, StepError};
use crate::model::ClothModel;
use barrier::SpinBarrier;
use crew::Crew;
use grid::Positions;
use worker::{Band, Frame, Phase};

/// Which explicit runs step in bands ([`BandedStepper`]); the others run
/// the scheme's own step ([`SchemeStepper`](super::SchemeStepper)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Banding {
    /// None.
    Off,
    /// Drift–kick schemes ([`sequence_of`]) on grids of at least
    /// [`BANDED_FROM`] particles, on [`BANDS`] threads where the machine
    /// has as many cores ([`std::thread::available_parallelism`]).
    #[default]
    Auto,
    /// Drift–kick schemes on this many bands and threads (at least one, at
    /// most one per row), whatever the grid and the machine: for tests and
    /// benchmarks.
    Threads(usize),
}

/// Bands (and threads) of [`Banding::Auto`]: this project's machines have
/// two cores.
pub const BANDS: usize = 2;

/// The fewest particles [`Banding::Auto`] steps in bands. Measured
/// (docs/results/cloth-springs.md; `benches/springs.rs`, group `frame`, a frame of
/// 64 steps on an idle two-core machine): two threads against the
/// scheme's own step gained 1.03–1.17× at 16² (within the noise; a frame
/// there is a few hundred microseconds, against 66–98 µs to start and join
/// the second worker, then started once per frame, and a barrier per
/// force), 1.19–1.82× at 32², 1.50–2.42× at 64² and 1.56–2.19× at 128².
/// With the second core busy they lose at every size.
pub const BANDED_FROM: usize = 32 * 32;

impl Banding {
    /// The bands to step `model` in, or `None` for the scheme's own step.
    pub fn bands(self, model: &ClothModel) -> Option<usize> {
        let rows = model.grid().1;
        match self {
            Banding::Off => None,
            Banding::Threads(n) => Some(n.clamp(1, rows)),
            Banding::Auto => {
                let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
                let bands = BANDS.min(cores).min(rows);
                (bands > 1 && model.particle_count() >= BANDED_FROM).then_some(bands)
            }
        }
    }
}

/// A drift–kick sequence stepped in bands of rows on one thread per band
/// (see the [module documentation](self)).
pub struct BandedStepper {
    seq: Sequence,
    nx: usize,
    /// The rows of each band.
    rows: Vec<Range<usize>>,
    /// Particle id → free index, or `u32::MAX` when pinned.
    free_of: Vec<u32>,
    free_count: usize,
    /// Two position buffers ([`Phase::cur`] the current one).
    pos: [[Vec<f64>; 3]; 2],
    phase: Phase,
    /// Each band's own arrays.
    own: Vec<Own>,
    barrier: SpinBarrier,
    /// The threads of the bands after the first (the calling thread works
    /// the first), started with the stepper and kept for its life
    /// (`crew.rs` says why).
    crew: Crew,
}

/// A band's arrays over its rows' particles: momenta, the carried rounding
/// errors of momenta and positions, the force, which particles are free
/// (1.0) or pinned (0.0), and the row buffer of tensions.
struct Own {
    p: [Vec<f64>; 3],
    ep: [Vec<f64>; 3],
    eq: [Vec<f64>; 3],
    f: [Vec<f64>; 3],
    free: Vec<f64>,
    row: [Vec<f64>; 3],
    /// The band's first non-finite step in the last frame.
    bad: Option<worker::NonFinite>,
}

/// The bands' arrays as the crew's threads take them, each its own (no
/// lock and no allocation per frame: a frame allocates nothing,
/// `tests/banded_no_alloc.rs`).
struct PerBand(*mut Own);

// SAFETY: each thread takes only its own band's arrays (`get`).
unsafe impl Sync for PerBand {}

impl PerBand {
    /// # Safety
    /// `i` is a band of the stepper, and only one thread takes it while
    /// the returned borrow lives.
    #[allow(clippy::mut_from_ref)]
    unsafe fn get(&self, i: usize) -> &mut Own {
        // SAFETY: by the caller's promise.
        unsafe { &mut *self.0.add(i) }
    }
}

/// Three arrays as slices.
fn slices(a: &mut [Vec<f64>; 3]) -> [&mut [f64]; 3] {
    a.each_mut().map(|v| v.as_mut_slice())
}

impl Own {
    fn band(&mut self, rows: Range<usize>) -> Band<'_> {
        Band {
            rows,
            p: slices(&mut self.p),
            ep: slices(&mut self.ep),
            eq: slices(&mut self.eq),
            f: slices(&mut self.f),
            free: &self.free,
            row: &mut self.row,
        }
    }
}

impl BandedStepper {
    /// `seq` on `model` in `bands` bands of rows (clamped to 1 ..= rows),
    /// at the model's initial positions until [`enter`](ClothStepper::enter).
    pub fn new(seq: Sequence, model: &ClothModel, bands: usize) -> BandedStepper {
        let (nx, ny) = model.grid();
        let n = nx * ny;
        let cut = |bands: usize| -> Vec<Range<usize>> {
            let per = ny.div_ceil(bands);
            (0..bands)
                .map(|b| (b * per).min(ny)..((b + 1) * per).min(ny))
                .filter(|r| !r.is_empty())
                .collect()
        };
        let mut rows = cut(bands.clamp(1, ny));
        // Where a thread cannot be started, one band: the same bits, on
        // one core.
        let crew = Crew::new(rows.len()).unwrap_or_else(|_| {
            rows = cut(1);
            Crew::alone()
        });
        let free_of: Vec<u32> = (0..n)
            .map(|id| {
                let (i, j) = model.grid_index(id);
                model.free_index(i, j).map_or(u32::MAX, |k| k as u32)
            })
            .collect();
        let start = model.positions(&model.initial_state()[..3 * model.free_count()]);
        let coords = |c: usize| -> Vec<f64> { start.iter().map(|x| x[c]).collect() };
        let own = rows
            .iter()
            .map(|r| {
                let len = r.len() * nx;
                let zeros = || std::array::from_fn(|_| vec![0.0; len]);
                let ids = &free_of[r.start * nx..r.end * nx];
                Own {
                    p: zeros(),
                    ep: zeros(),
                    eq: zeros(),
                    f: zeros(),
                    free: ids
                        .iter()
                        .map(|&k| if k == u32::MAX { 0.0 } else { 1.0 })
                        .collect(),
                    row: std::array::from_fn(|_| vec![0.0; nx]),
                    bad: None,
                }
            })
            .collect();
        BandedStepper {
            seq,
            nx,
            free_count: model.free_count(),
            free_of,
            pos: std::array::from_fn(|_| std::array::from_fn(coords)),
            phase: Phase {
                cur: 0,
                after_drift: false,
                force_valid: false,
            },
            own,
            barrier: SpinBarrier::new(rows.len()),
            crew,
            rows,
        }
    }

    /// The bands (threads) it steps in.
    pub fn bands(&self) -> usize {
        self.rows.len()
    }

    /// `n` steps of `h` on the bands' workers (the calling thread works
    /// the first band); the first step that left a non-finite value.
    fn run(&mut self, model: &ClothModel, h: f64, n: usize) -> Option<worker::NonFinite> {
        let BandedStepper {
            seq,
            nx,
            rows,
            free_of,
            free_count,
            pos,
            phase,
            own,
            barrier,
            crew,
        } = self;
        let nx = *nx;
        let positions = Positions::new(pos, nx);
        let frame = Frame {
            model,
            seq,
            h,
            steps: n,
            positions: &positions,
            barrier,
            start: *phase,
            free_of,
            free_count: *free_count,
        };
        let bands = PerBand(own.as_mut_ptr());
        let end = crew.run(&|i| {
            // SAFETY: thread `i` alone works band `i` (`i < own.len()`:
            // the crew has one thread per band).
            let own = unsafe { bands.get(i) };
            let (end, bad) = worker::run(&frame, own.band(rows[i].clone()));
            own.bad = bad;
            end
        });
        // The first bad step, and its smallest index, over the bands.
        let bad = own
            .iter_mut()
            .filter_map(|o| o.bad.take())
            .min_by_key(|&(step, index, _)| (step, index));
        *phase = end;
        bad
    }
}

/// The state `z` as the bands write it back, each its own particles'
/// entries.
struct Out(*mut f64);

// SAFETY: the bands write disjoint entries (`BandedStepper::leave`).
unsafe impl Sync for Out {}

impl Out {
    /// # Safety
    /// `i` is in bounds and no other thread accesses entry `i`.
    unsafe fn write(&self, i: usize, v: f64) {
        // SAFETY: by the caller's promise.
        unsafe { *self.0.add(i) = v }
    }
}

/// The work of one band between frames, given the free index of each of
/// its particles (`u32::MAX` for a pinned one), its own arrays and its rows
/// of the current positions.
type BandWork<'a> = dyn Fn(&[u32], &mut Own, [&mut [f64]; 3]) + Sync + 'a;

impl BandedStepper {
    /// `f` on every band, each on its own thread.
    fn each_band(&mut self, f: &BandWork<'_>) {
        let positions = Positions::new(&mut self.pos, self.nx);
        let (cur, nx, rows, free_of) = (self.phase.cur, self.nx, &self.rows, &self.free_of);
        let bands = PerBand(self.own.as_mut_ptr());
        self.crew.run(&|b| {
            // SAFETY: thread `b` alone works band `b`.
            let own = unsafe { bands.get(b) };
            // SAFETY: each band writes only its own rows, and nothing
            // else reads the buffer meanwhile.
            let pos = unsafe { positions.rows_mut(cur, rows[b].clone()) };
            let ids = &free_of[rows[b].start * nx..rows[b].end * nx];
            f(ids, own, pos);
        });
    }
}

impl ClothStepper for BandedStepper {
    /// The free particles' `q` and `p` into the grid arrays, each band's
    /// by its own thread.
    fn enter(&mut self, _model: &ClothModel, _t: f64, z: &mut [f64]) {
        let (q, p) = z.split_at(3 * self.free_count);
        self.each_band(&|ids, own, pos| {
            for (i, &k) in ids.iter().enumerate() {
                if k != u32::MAX {
                    let k = k as usize;
                    for c in 0..3 {
                        pos[c][i] = q[3 * k + c];
                        own.p[c][i] = p[3 * k + c];
                    }
                }
            }
        });
    }

    /// One step, in the grid arrays (between `enter` and `leave`; the run
    /// loop calls [`steps`](ClothStepper::steps), which also reports a
    /// non-finite value).
    fn step(
        &mut self,
        model: &ClothModel,
        _t: f64,
        h: f64,
        _z: &mut [f64],
    ) -> Result<(), StepError> {
        self.run(model, h, 1);
        Ok(())
    }

    /// The steps of a frame on the bands' workers, started once. A step
    /// that leaves a non-finite value stops nothing (the workers finish
    /// the frame, the run discards it); it is reported with the smallest
    /// index in `[q; p]` of such a value right after that step and the value.
    fn steps(
        &mut self,
        model: &ClothModel,
        _t: &dyn Fn(usize) -> f64,
        h: f64,
        n: usize,
        _z: &mut [f64],
    ) -> Result<(), Halt> {
        match self.run(model, h, n) {
            None => Ok(()),
            Some((done, index, value)) => Err(Halt {
                done,
                why: Halted::NonFinite { index, value },
            }),
        }
    }

    /// The grid arrays back into `z`, each band's by its own thread.
    fn leave(&mut self, _model: &ClothModel, _t: f64, z: &mut [f64]) {
        let n = self.free_count;
        assert!(z.len() >= 6 * n, "the state of the stepper's model");
        let out = Out(z.as_mut_ptr());
        self.each_band(&|ids, own, pos| {
            for (i, &k) in ids.iter().enumerate() {
                if k != u32::MAX {
                    let k = k as usize;
                    for (c, (q, p)) in pos.iter().zip(&own.p).enumerate() {
                        // SAFETY: in bounds (`k < n`); each free particle
                        // lies in one band, so no two threads write the
                        // same entries.
                        unsafe {
                            out.write(3 * k + c, q[i]);
                            out.write(3 * (n + k) + c, p[i]);
                        }
                    }
                }
            }
        });
    }

    fn stats(&self) -> SolverStats {
        SolverStats::None
    }
}
