//! Work–precision sweeps: every method over a range of step sizes (or, for
//! the adaptive peer, tolerances), one row per run.
//!
//! Each fixed-step run is made once observed — on the problem's counting
//! wrapper, the energy checked at every step — and then, if it succeeded,
//! once more untimed (warm-up) and `repeats` times timed on the bare system,
//! strictly one after another; the wall time is the median. A run that
//! diverges (a non-finite state, energy or final error) or whose stage
//! solver fails is a row with that status, never `ok`.
//!
//! The columns of `runs.csv` ([`COLUMNS`], one [`Row`] per run):
//!
//! | column | meaning |
//! |---|---|
//! | `problem` | the problem's name |
//! | `method` | the method's id |
//! | `order` | classical order (of the table; 8 for DOP853) |
//! | `symplectic` | symplectic for this problem (separable problems: for separable Hamiltonians) |
//! | `h` | step size; for `dop853`, `logh:ID` and `adaptive:ID` the average step `T/steps` |
//! | `tol` | `rtol = atol` of `dop853`; NaN for fixed-step methods |
//! | `steps` | steps taken (accepted steps for `dop853`) |
//! | `error` | `‖z(T) − z_ref(T)‖₂ / ‖z_ref(T)‖₂`; NaN unless `status` is ok |
//! | `energy_error` | `max |E − E₀|/|E₀|` over the steps taken |
//! | `time_s` | median wall time of the timed runs, seconds; NaN unless ok |
//! | `evals` | force evaluations (separable problems; an RK stage is one), right-hand sides (other systems; a propagator step counts one matrix–vector product), or DOP853's own count |
//! | `newton_iterations` | simplified-Newton iterations of the implicit stage solver (0 for explicit methods) |
//! | `fixed_point_iterations` | fixed-point iterations of the stage solver |
//! | `factorizations` | LU factorisations of the stage solver |
//! | `status` | `ok`, `diverged at step k[: why]`, `solver failed at step k: why`, or — when the scheme or the problem (user code) panicked — `panicked at step k: <message>` (`panicked before the first step: …`, `panicked in a timed run: …`; DOP853: `panicked: …`); the sweep goes on |
//! | `interpreted` | only when a table file ran: `true` for its rows (stepped by a run-time interpreter) |
//!
//! REBOUND's rows (`rebound:NAME…`, [`rebound`](crate::rebound)): `h` is
//! `T/steps`; `tol` is IAS15's `epsilon` or BS's `eps_abs = eps_rel` (NaN
//! for the fixed-step integrators); `order` the classical order in `h` (0
//! for BS, whose order varies); `error` is measured here, against the same
//! reference; `energy_error` is the largest over 100 states sampled evenly
//! by an observed run and the end; `time_s` the median of the timed
//! `sim.integrate` calls, timed inside Python; `evals` and the stage-solver
//! counters are 0 (REBOUND does not count force evaluations).

use std::time::Instant;

use crate::method::{Fixed, Method};
use crate::peer;
use crate::problem::{Family, Problem, Setup};
use crate::stepper::Status;

pub use crate::peer::{PEER_TOLERANCES, tolerance_range, tolerances};
pub use crate::row::{COLUMNS, Row, median};

/// Step counts for the log-spaced step sizes from `h_max` down to `h_min`
/// (`points` of them), each rounded to a whole number of steps over
/// `t_end`, duplicates dropped.
pub fn step_counts(t_end: f64, h_min: f64, h_max: f64, points: usize) -> Vec<u64> {
    let mut out: Vec<u64> = (0..points)
        .map(|i| {
            let f = if points == 1 {
                0.0
            } else {
                i as f64 / (points - 1) as f64
            };
            let h = h_max * (h_min / h_max).powf(f);
            ((t_end / h).round() as u64).max(1)
        })
        .collect();
    out.dedup();
    out
}

/// Run every method: fixed-step methods at each step count, the peer at
/// each tolerance. For each: one observed run on the counting wrapper
/// (error, energy error, evaluations, solver counters), then, if it
/// succeeded, one untimed warm-up run and `repeats` timed runs on the bare
/// system, strictly one after another; the time is their median. REBOUND's
/// methods run the same way in a Python process per run
/// ([`rebound::row`](crate::rebound::row)).
pub fn sweep<P: Problem>(
    setup: &Setup<P>,
    methods: &[Method<P>],
    steps: &[u64],
    tols: &[f64],
    repeats: usize,
) -> Vec<Row> {
    sweep_each(setup, methods.iter(), steps, tols, repeats)
}

/// [`sweep`] over any sequence of methods (a sweep that leaves some out).
pub fn sweep_each<'a, P: Problem>(
    setup: &Setup<P>,
    methods: impl Iterator<Item = &'a Method<P>> + Clone,
    steps: &[u64],
    tols: &[f64],
    repeats: usize,
) -> Vec<Row> {
    sweep_each_from(setup, methods, steps, tols, repeats, Vec::new(), &mut Quiet).rows
}

/// What the front end says after each row of a sweep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowControl {
    Continue,
    /// End the sweep here (the rows so far are returned).
    Stop,
}

/// What a sweep tells its caller while it runs, and asks it. The library
/// draws and prints nothing: a front end draws a bar (`symlab compare`),
/// saves a checkpoint or stops on a signal; Python reports nothing.
pub trait SweepObserver {
    /// A part of a study begins (a leg of the peer study), said in a line.
    fn stage(&mut self, _what: &str) {}
    /// Before the first run: how many rows the sweep makes.
    fn start(&mut self, _rows: usize) {}
    /// A method's runs begin.
    fn method(&mut self, _id: &str) {}
    /// After each row, with every row so far: go on or stop. `fresh` is
    /// false for a row taken from the rows already done (a checkpoint's).
    fn row(&mut self, _rows: &[Row], _fresh: bool) -> RowControl {
        RowControl::Continue
    }
    /// The sweep ended, finished or stopped.
    fn finish(&mut self) {}
}

/// An observer that reports nothing and never stops a sweep.
#[derive(Clone, Copy, Debug, Default)]
pub struct Quiet;

impl SweepObserver for Quiet {}

/// The rows of a sweep, and whether it was stopped before its end.
#[derive(Clone, Debug)]
pub struct Swept {
    pub rows: Vec<Row>,
    pub stopped: bool,
}

/// [`sweep_each`] continuing a sweep that stopped after the rows `done`
/// (a checkpoint's): the runs are made in the same order, those already
/// done are taken from `done` instead of run again, and `observer` is told
/// the progress and asked after every row, with all rows so far, whether
/// to go on (a front end saves a checkpoint there, or stops on a signal).
/// A row of `done` that is not the method this sweep has at its place ends
/// the reuse: from there on the rows are run.
pub fn sweep_each_from<'a, P: Problem>(
    setup: &Setup<P>,
    methods: impl Iterator<Item = &'a Method<P>> + Clone,
    steps: &[u64],
    tols: &[f64],
    repeats: usize,
    done: Vec<Row>,
    observer: &mut dyn SweepObserver,
) -> Swept {
    let total: usize = methods
        .clone()
        .map(|m| match m {
            Method::Fixed(_) => steps.len(),
            Method::Dop853 => tols.len(),
            Method::Rebound(r) => r.points(steps, tols).len(),
        })
        .sum();
    let peer_limit = peer_step_limit(steps);
    observer.start(total);
    let mut rows = Vec::with_capacity(total);
    let mut done = done.into_iter();
    let mut reusing = true;
    // The next row: the saved one where it is this method's, else run.
    let mut next = |rows: &mut Vec<Row>,
                    observer: &mut dyn SweepObserver,
                    id: &str,
                    run: &mut dyn FnMut() -> Row|
     -> bool {
        let saved = if reusing { done.next() } else { None };
        let fresh = !matches!(&saved, Some(row) if row.method == id);
        match saved {
            Some(row) if !fresh => rows.push(row),
            _ => {
                reusing = false;
                rows.push(run());
            }
        }
        observer.row(rows, fresh) == RowControl::Stop
    };
    'sweep: for m in methods {
        observer.method(m.id());
        match m {
            Method::Fixed(f) => {
                for &n in steps {
                    if next(&mut rows, observer, m.id(), &mut || {
                        fixed_run(setup, f, n, repeats)
                    }) {
                        break 'sweep;
                    }
                }
            }
            Method::Dop853 => {
                for &tol in tols {
                    if next(&mut rows, observer, m.id(), &mut || {
                        peer_run(setup, tol, repeats, peer_limit)
                    }) {
                        break 'sweep;
                    }
                }
            }
            Method::Rebound(r) => {
                // An adaptive integrator's first step: the sweep's largest.
                let h_guess = steps
                    .first()
                    .map_or(setup.t_end, |&n| setup.t_end / n as f64);
                for point in r.points(steps, tols) {
                    if next(&mut rows, observer, m.id(), &mut || {
                        crate::rebound::row(setup, r, point, h_guess, repeats)
                    }) {
                        break 'sweep;
                    }
                }
            }
        }
    }
    observer.finish();
    let stopped = rows.len() < total;
    Swept { rows, stopped }
}

/// Append `rows` to a checkpoint's payload exactly (doubles as bits).
pub fn encode_rows(e: &mut integrator_core::checkpoint::Encoder, rows: &[Row]) {
    e.usize(rows.len());
    for r in rows {
        e.str(&r.problem)
            .str(&r.method)
            .str(r.family.name())
            .usize(r.order)
            .bool(r.symplectic)
            .f64(r.h)
            .f64(r.tol)
            .u64(r.steps)
            .f64(r.error)
            .f64(r.energy_error)
            .f64(r.time_s)
            .u64(r.evals)
            .usize(r.newton_iterations)
            .usize(r.fixed_point_iterations)
            .usize(r.factorizations)
            .str(&r.status)
            .bool(r.interpreted);
    }
}

/// Read back what [`encode_rows`] wrote.
pub fn decode_rows(
    d: &mut integrator_core::checkpoint::Decoder<'_>,
) -> std::result::Result<Vec<Row>, integrator_core::checkpoint::CheckpointError> {
    let n = d.usize("rows")?;
    let mut rows = Vec::with_capacity(n.min(1 << 16));
    for _ in 0..n {
        let problem = d.str("row.problem")?.to_string();
        let method = d.str("row.method")?.to_string();
        let family_name = d.str("row.family")?;
        let family = Family::from_name(family_name)
            .ok_or_else(|| d.error(format!("row.family: unknown family \"{family_name}\"")))?;
        rows.push(Row {
            problem,
            method,
            family,
            order: d.usize("row.order")?,
            symplectic: d.bool("row.symplectic")?,
            h: d.f64("row.h")?,
            tol: d.f64("row.tol")?,
            steps: d.u64("row.steps")?,
            error: d.f64("row.error")?,
            energy_error: d.f64("row.energy_error")?,
            time_s: d.f64("row.time_s")?,
            evals: d.u64("row.evals")?,
            newton_iterations: d.usize("row.newton_iterations")?,
            fixed_point_iterations: d.usize("row.fixed_point_iterations")?,
            factorizations: d.usize("row.factorizations")?,
            status: d.str("row.status")?.to_string(),
            interpreted: d.bool("row.interpreted")?,
        });
    }
    Ok(rows)
}

/// A stopped sweep as its checkpoint holds it: the caller's arguments
/// (the command line's, after `compare`, from which a resumed sweep is
/// planned again) and the rows done, exactly.
#[derive(Clone, Debug)]
pub struct Checkpoint {
    pub argv: Vec<String>,
    pub rows: Vec<Row>,
}

/// The most arguments a checkpoint is read back with.
const MAX_ARGUMENTS: usize = 1000;

impl Checkpoint {
    /// Write the checkpoint of a sweep (`argv` and `rows`) to `path`,
    /// atomically ([`integrator_core::checkpoint::write`]).
    pub fn write(
        path: &std::path::Path,
        argv: &[String],
        rows: &[Row],
    ) -> std::result::Result<(), integrator_core::checkpoint::CheckpointError> {
        let mut e = integrator_core::checkpoint::Encoder::new();
        e.usize(argv.len());
        for a in argv {
            e.str(a);
        }
        encode_rows(&mut e, rows);
        integrator_core::checkpoint::write(
            path,
            integrator_core::checkpoint::Kind::Compare,
            &e.finish(),
        )
    }

    /// Read back the `payload` of the checkpoint file `path`.
    pub fn read(
        path: &std::path::Path,
        payload: &[u8],
    ) -> std::result::Result<Self, integrator_core::checkpoint::CheckpointError> {
        let mut d = integrator_core::checkpoint::Decoder::new(path, payload);
        let n = d.usize("arguments")?;
        if n > MAX_ARGUMENTS {
            return Err(d.error(format!("arguments: {n} of them")));
        }
        let argv = (0..n)
            .map(|_| d.str("arguments").map(str::to_string))
            .collect::<std::result::Result<Vec<_>, _>>()?;
        let rows = decode_rows(&mut d)?;
        d.end()?;
        Ok(Checkpoint { argv, rows })
    }
}

/// Saves a sweep's [`Checkpoint`] as its rows come (for a
/// [`SweepObserver`] of a front end): after a fresh row once `every` of
/// wall time has passed since the last save, and when the sweep is
/// stopping.
pub struct CheckpointSaver {
    path: std::path::PathBuf,
    argv: Vec<String>,
    every: Option<std::time::Duration>,
    last: std::time::Instant,
    /// The rows the last checkpoint written holds.
    pub saved_rows: Option<usize>,
}

impl CheckpointSaver {
    /// Save to `path` every `every` (`None`: only when stopping).
    pub fn new(
        path: &std::path::Path,
        argv: &[String],
        every: Option<std::time::Duration>,
    ) -> Self {
        CheckpointSaver {
            path: path.to_path_buf(),
            argv: argv.to_vec(),
            every,
            last: std::time::Instant::now(),
            saved_rows: None,
        }
    }

    /// After a row (`fresh`: run now, not read back from a checkpoint):
    /// save the `rows` when due or when `stopping`.
    pub fn row(
        &mut self,
        rows: &[Row],
        fresh: bool,
        stopping: bool,
    ) -> std::result::Result<(), integrator_core::checkpoint::CheckpointError> {
        if !fresh {
            return Ok(());
        }
        if stopping || self.every.is_some_and(|d| self.last.elapsed() >= d) {
            Checkpoint::write(&self.path, &self.argv, rows)?;
            self.saved_rows = Some(rows.len());
            self.last = std::time::Instant::now();
        }
        Ok(())
    }
}

/// One fixed-step run of `n` steps over `[0, t_end]`.
pub fn fixed_run<P: Problem>(setup: &Setup<P>, f: &Fixed<P>, n: u64, repeats: usize) -> Row {
    let h_asked = setup.t_end / n as f64;
    let mut z = setup.z0.clone();
    let mut energy_error: f64 = 0.0;
    // A state whose energy overflows has diverged even while it is finite.
    let outcome = crate::stepper::observed_caught(
        &*f.stepper,
        &setup.sys,
        &mut z,
        h_asked,
        n as usize,
        true,
        &mut |_, _, z| {
            let e = setup.energy_error(z);
            energy_error = energy_error.max(e);
            e.is_finite()
        },
    );
    let h = h_asked;
    // A time-transformed method takes the steps it needs: its row reports
    // them and their average length.
    let (n, h) = match outcome.steps {
        Some(k) if k > 0 => (k, setup.t_end / k as f64),
        _ => (n, h),
    };
    let mut status = match outcome.status {
        Status::Stopped { step } => format!("diverged at step {step}: the energy is not finite"),
        ref s => s.label(),
    };
    let mut error = f64::NAN;
    let mut time_s = f64::NAN;
    if outcome.status.is_ok() {
        error = setup.error(&z);
        if !error.is_finite() {
            status = format!("diverged at step {n}: the error at T is not finite");
        } else {
            let steps_asked = (setup.t_end / h_asked).round() as usize;
            let bare = || {
                let mut w = setup.z0.clone();
                crate::stepper::bare_caught(&*f.stepper, &setup.sys, &mut w, h_asked, steps_asked)
            };
            let mut fine = bare();
            let mut times = Vec::with_capacity(repeats);
            for _ in 0..repeats {
                if !matches!(fine, Ok(true)) {
                    break;
                }
                let mut w = setup.z0.clone();
                let start = Instant::now();
                fine = crate::stepper::bare_caught(
                    &*f.stepper,
                    &setup.sys,
                    &mut w,
                    h_asked,
                    steps_asked,
                );
                times.push(start.elapsed().as_secs_f64());
                std::hint::black_box(&w);
            }
            match fine {
                Ok(true) => time_s = median(times),
                Ok(false) => {}
                Err(message) => status = format!("panicked in a timed run: {message}"),
            }
        }
    }
    if status != "ok" {
        error = f64::NAN;
    }
    Row {
        problem: setup.name.clone(),
        method: f.id.clone(),
        family: f.family,
        order: f.order,
        symplectic: f.symplectic,
        h,
        tol: f64::NAN,
        steps: n,
        error,
        energy_error,
        time_s,
        evals: outcome.evals,
        newton_iterations: outcome.newton_iterations,
        fixed_point_iterations: outcome.fixed_point_iterations,
        factorizations: outcome.factorizations,
        status,
        interpreted: f.interpreted,
    }
}

/// DOP853's step limit in a sweep whose fixed-step runs take `steps`: ten
/// times the largest of them, between 10⁴ and 10⁷. A peer that needs far
/// more steps than our finest run is not a comparison at that tolerance,
/// and without a bound an absurd end time (T = 10¹⁵ on Kepler) keeps it
/// stepping for minutes per tolerance.
pub fn peer_step_limit(steps: &[u64]) -> u32 {
    let most = steps.iter().copied().max().unwrap_or(0);
    most.saturating_mul(10).clamp(10_000, 10_000_000) as u32
}

/// One DOP853 run at `rtol = atol = tol`: the first call gives the error
/// and counts (and warms up), then `repeats` timed calls.
///
/// `max_steps` bounds DOP853's accepted steps (see [`peer_step_limit`]); a
/// run that needs more is a row whose status says so.
pub fn peer_run<P: Problem>(setup: &Setup<P>, tol: f64, repeats: usize, max_steps: u32) -> Row {
    let first = match crate::guard::catch(|| peer::dop853(setup, tol, max_steps)) {
        Ok(first) => first,
        Err(message) => peer::PeerOutcome {
            end: Err(format!("panicked: {message}")),
            energy_error: f64::NAN,
            evals: 0,
            accepted: 0,
            seconds: f64::NAN,
        },
    };
    let mut row = Row {
        problem: setup.name.clone(),
        method: "dop853".into(),
        family: Family::Peer,
        order: 8,
        symplectic: false,
        h: f64::NAN,
        tol,
        steps: 0,
        error: f64::NAN,
        energy_error: f64::NAN,
        time_s: f64::NAN,
        evals: 0,
        newton_iterations: 0,
        fixed_point_iterations: 0,
        factorizations: 0,
        status: String::new(),
        interpreted: false,
    };
    row.steps = first.accepted;
    row.evals = first.evals;
    row.energy_error = first.energy_error;
    row.h = if first.accepted > 0 {
        setup.t_end / first.accepted as f64
    } else {
        f64::NAN
    };
    match &first.end {
        Ok(z) if !(setup.error(z).is_finite() && first.energy_error.is_finite()) => {
            row.status = format!(
                "diverged at step {}: the error or the energy is not finite",
                first.accepted
            );
        }
        Ok(z) => {
            row.error = setup.error(z);
            row.status = "ok".into();
            let times: std::result::Result<Vec<f64>, String> = (0..repeats)
                .map(|_| crate::guard::catch(|| peer::dop853(setup, tol, max_steps).seconds))
                .collect();
            match times {
                Ok(times) => row.time_s = median(times),
                Err(message) => {
                    row.error = f64::NAN;
                    row.status = format!("panicked in a timed run: {message}");
                }
            }
        }
        Err(e) if e.starts_with("panicked: ") => row.status = e.clone(),
        Err(e) => row.status = format!("solver failed: {e}"),
    }
    row
}
