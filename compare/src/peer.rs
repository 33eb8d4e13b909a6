//! The peer: DOP853 (Hairer's explicit Runge–Kutta 8(5,3) with step-size
//! control) from the `ode_solvers` crate, measured in the same run as our
//! schemes (feature `peer`, on by default).
//!
//! Output: `OutputType::Sparse`, one stored state per accepted step. The
//! crate's only way to get end-only output is `Dense` with `dx = t_end`, and
//! in DOP853 dense output costs three extra right-hand-side evaluations per
//! step (the interpolant's coefficients) — 15 instead of 12 — whereas a
//! stored state is a copy of `2n` numbers. The last stored state is the state
//! at `t_end` (the controller shortens the last step to land on it), and the
//! stored states give the energy error at every accepted step.

/// Tolerances of the peer, log-spaced from 1e-4 to 1e-18 (one per decade
/// for [`PEER_TOLERANCES`] points). ode_solvers checks no lower limit (its
/// error estimate is scaled by `atol + rtol·|y|`), and on Kepler the runs
/// finish down to 1e-20 at least (measured over 100 and 1000 orbits; from
/// 1e-15 down no step is rejected). The error still falls about tenfold per
/// decade of tolerance at 1e-15 and levels off near 1e-17 as round-off takes
/// over: 1e-15 alone would cut DOP853 off above its best (over 100 orbits
/// 4.9e-10 at 1e-15, 6.6e-11 at 1e-16, 1.7e-11 at 1e-17).
pub fn tolerances(points: usize) -> Vec<f64> {
    tolerance_range(points, 4, 18)
}

/// The default number of peer tolerances: one per decade of [`tolerances`].
pub const PEER_TOLERANCES: usize = 15;

/// `points` tolerances log-spaced from `10^-from` to `10^-to`.
pub fn tolerance_range(points: usize, from: i32, to: i32) -> Vec<f64> {
    (0..points)
        .map(|i| {
            let f = if points == 1 {
                0.0
            } else {
                i as f64 / (points - 1) as f64
            };
            10f64.powf(-(from as f64) - (to - from) as f64 * f)
        })
        .collect()
}

/// What one DOP853 run did.
#[derive(Clone, Debug)]
pub struct PeerOutcome {
    /// `None` when the solver stopped with an error (its message), or the
    /// state at `t_end`.
    pub end: Result<Vec<f64>, String>,
    /// The largest `|E − E₀|/|E₀|` over the accepted steps.
    pub energy_error: f64,
    /// Right-hand-side evaluations (the solver's own count).
    pub evals: u64,
    pub accepted: u64,
    /// Wall time of the call (construction and integration), seconds.
    pub seconds: f64,
}

#[cfg(feature = "peer")]
mod imp {
    use std::time::Instant;

    use integrator_core::OdeSystem;
    use ode_solvers::{DVector, Dop853, OutputType, SVector};

    use super::PeerOutcome;
    use crate::problem::{Problem, Setup, Stacked};

    /// The system in the crate's vector types (`rhs` of the problem: for a
    /// separable one, one velocity and one force evaluation).
    struct Peer<'a, P>(&'a P);

    impl<P: OdeSystem, const N: usize> ode_solvers::System<f64, SVector<f64, N>> for Peer<'_, P> {
        fn system(&self, t: f64, y: &SVector<f64, N>, dy: &mut SVector<f64, N>) {
            self.0.rhs(t, y.as_slice(), dy.as_mut_slice());
        }
    }

    impl<P: OdeSystem> ode_solvers::System<f64, DVector<f64>> for Peer<'_, P> {
        fn system(&self, t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
            self.0.rhs(t, y.as_slice(), dy.as_mut_slice());
        }
    }

    /// DOP853 on `setup` with `rtol = atol = tol`, default controller
    /// settings, at most `max_steps` steps (the solver's own limit). Stack vectors for the state sizes of
    /// the built-in problems (2, 4, 12, 36), heap vectors otherwise (the solver
    /// is generic over nalgebra's dimension types, which this crate does not
    /// name; hence a macro for the one body).
    pub fn dop853<P: Problem>(setup: &Setup<P>, tol: f64, max_steps: u32) -> PeerOutcome {
        macro_rules! run {
            ($y0:expr) => {{
                let start = Instant::now();
                let t = setup.t_end;
                let mut solver = Dop853::from_param(
                    Peer(&setup.sys),
                    0.0,
                    t,
                    t, // dx: unused with sparse output
                    $y0,
                    tol,
                    tol,
                    0.9,   // safety factor (default)
                    0.0,   // beta (default)
                    0.333, // fac_min (default)
                    6.0,   // fac_max (default)
                    t,     // h_max (default: the whole interval)
                    0.0,   // h = 0: initial step chosen by the solver
                    max_steps,
                    1000, // stiffness test interval (default)
                    OutputType::Sparse,
                );
                let result = solver.integrate();
                let seconds = start.elapsed().as_secs_f64();
                let states = solver.y_out();
                let energy_error = states
                    .iter()
                    .map(|y| setup.energy_error(y.as_slice()))
                    .fold(0.0, f64::max);
                match result {
                    Ok(stats) => {
                        let end = states
                            .last()
                            .map(|y| y.as_slice().to_vec())
                            .unwrap_or_default();
                        let end = if end.iter().all(|x| x.is_finite()) {
                            Ok(end)
                        } else {
                            Err("the solution diverged (non-finite state)".to_string())
                        };
                        PeerOutcome {
                            end,
                            energy_error,
                            evals: stats.num_eval as u64,
                            accepted: stats.accepted_steps as u64,
                            seconds,
                        }
                    }
                    Err(e) => PeerOutcome {
                        end: Err(e.to_string()),
                        energy_error,
                        evals: 0,
                        accepted: states.len().saturating_sub(1) as u64,
                        seconds,
                    },
                }
            }};
        }
        let z0 = &setup.z0;
        // Stack vectors only for the sizes the problem names
        // (`Problem::STACK_SIZES`): the others are not compiled.
        match z0.len() {
            2 if Stacked::<P, 2>::ON => run!(SVector::<f64, 2>::from_column_slice(z0)),
            4 if Stacked::<P, 4>::ON => run!(SVector::<f64, 4>::from_column_slice(z0)),
            12 if Stacked::<P, 12>::ON => run!(SVector::<f64, 12>::from_column_slice(z0)),
            36 if Stacked::<P, 36>::ON => run!(SVector::<f64, 36>::from_column_slice(z0)),
            _ => run!(DVector::<f64>::from_column_slice(z0)),
        }
    }
    /// DOP853 on `sys` from `z0` over `[0, t_end]` (`rtol = atol = tol`,
    /// default controller), `observe(t, z)` called at every accepted step
    /// after the run; `(accepted steps, evaluations)` or the solver's error.
    pub fn dop853_observed<P: Problem>(
        sys: &P,
        z0: &[f64],
        t_end: f64,
        tol: f64,
        max_steps: u32,
        observe: &mut dyn FnMut(f64, &[f64]),
    ) -> Result<(u64, u64), String> {
        macro_rules! run {
            ($y0:expr) => {{
                let mut solver = Dop853::from_param(
                    Peer(sys),
                    0.0,
                    t_end,
                    t_end,
                    $y0,
                    tol,
                    tol,
                    0.9,
                    0.0,
                    0.333,
                    6.0,
                    t_end,
                    0.0,
                    max_steps,
                    1000,
                    OutputType::Sparse,
                );
                let stats = solver.integrate().map_err(|e| e.to_string())?;
                for (t, y) in solver.x_out().iter().zip(solver.y_out()).skip(1) {
                    observe(*t, y.as_slice());
                }
                Ok((stats.accepted_steps as u64, stats.num_eval as u64))
            }};
        }
        match z0.len() {
            4 if Stacked::<P, 4>::ON => run!(SVector::<f64, 4>::from_column_slice(z0)),
            _ => run!(DVector::<f64>::from_column_slice(z0)),
        }
    }
}
#[cfg(feature = "peer")]
pub use imp::{dop853, dop853_observed};

/// Without the `peer` feature there is no DOP853.
#[cfg(not(feature = "peer"))]
pub fn dop853_observed<P: crate::problem::Problem>(
    _sys: &P,
    _z0: &[f64],
    _t_end: f64,
    _tol: f64,
    _max_steps: u32,
    _observe: &mut dyn FnMut(f64, &[f64]),
) -> Result<(u64, u64), String> {
    Err("the peer is not available (the `peer` feature is off)".into())
}

/// Without the `peer` feature there is no DOP853: every run says so.
#[cfg(not(feature = "peer"))]
pub fn dop853<P: crate::problem::Problem>(
    _setup: &crate::problem::Setup<P>,
    _tol: f64,
    _max_steps: u32,
) -> PeerOutcome {
    PeerOutcome {
        end: Err("the peer is not available (the `peer` feature is off)".into()),
        energy_error: f64::NAN,
        evals: 0,
        accepted: 0,
        seconds: f64::NAN,
    }
}
