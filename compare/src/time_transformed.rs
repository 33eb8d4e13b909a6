//! Time-transformed schemes in the comparisons: `logh:ID` steps the
//! logarithmic Hamiltonian of a separable problem
//! ([`integrator_core::time_transform::LogHamiltonian`]) with the explicit
//! scheme `ID`, a fixed step in the fictitious time `s` being a step in `t`
//! that shrinks where `−V` is large (Kepler's pericentre). Symplectic in
//! the extended phase space and time-reversible, with no step-size
//! controller.
//!
//! A run asked for `n` steps of `h` over `[0, T]` takes steps of
//! `Δs = h·(−V(q₀))` (at the start, a step of `h` in `t`) until it reaches
//! `T`, and lands on `T` exactly: when the next step would pass `T`, its
//! `Δs` is found by a bracketed secant iteration (Illinois) on
//! `t(Δs) = T` from the state before it, each trial one step, down to a few
//! ulps of `T`. The row reports the steps actually taken (each trial step
//! of the landing counts its evaluations, not as a step).

use integrator_core::fixed::StepFixed;
use integrator_core::time_transform::LogHamiltonian;
use integrator_core::{Separable, Step};

use crate::counting::{AsSeparable, Counting};
use crate::problem::{Kind, OnSlices, Problem, Stacked};
use crate::stepper::{Outcome, Status, Stepper, Workspace, bare_on_observed};

/// A scheme on the logarithmic Hamiltonian of the problem.
pub struct LogH<M>(pub M);

/// The most steps a time-transformed run may take (10⁸, as the sweeps'
/// limit on fixed steps): a fictitious time that does not advance `t` is a
/// failure, not a hang.
pub const MAX_STEPS: u64 = 100_000_000;

/// How the run steps the extended state: on a `Vec` with the scheme's heap
/// workspace ([`Slices`]), or on a `[f64; N]` with the scheme's carry
/// ([`Fixed`], `integrator_core::fixed`), so that a small problem's state
/// stays in registers as DOP853's stack vectors do. Both give the same bits.
trait Engine<S: Separable> {
    type State: AsRef<[f64]> + AsMut<[f64]> + Clone;
    type Scratch: Clone;
    fn state(&self, w: Vec<f64>) -> Option<Self::State>;
    /// One step of `ds`; `false` if it failed.
    fn step(
        &self,
        sys: &LogHamiltonian<S>,
        ds: f64,
        w: &mut Self::State,
        scratch: &mut Self::Scratch,
        reuse: bool,
    ) -> bool;
}

/// The slice path: any [`Step`] scheme.
struct Slices<'a, M>(&'a M);

impl<S, M> Engine<S> for Slices<'_, M>
where
    S: Separable,
    M: Step<LogHamiltonian<S>>,
    M::Workspace: Clone,
{
    type State = Vec<f64>;
    type Scratch = M::Workspace;
    fn state(&self, w: Vec<f64>) -> Option<Vec<f64>> {
        Some(w)
    }
    #[inline(always)]
    fn step(
        &self,
        sys: &LogHamiltonian<S>,
        ds: f64,
        w: &mut Vec<f64>,
        ws: &mut M::Workspace,
        reuse: bool,
    ) -> bool {
        self.0.step_reusing(sys, 0.0, ds, w, ws, reuse).is_ok()
    }
}

/// The fixed-size path for an extended state of `N` entries.
struct Fixed<'a, M, const N: usize>(&'a M);

impl<S, M, const N: usize> Engine<S> for Fixed<'_, M, N>
where
    S: Separable,
    M: StepFixed<LogHamiltonian<S>, N>,
{
    type State = [f64; N];
    type Scratch = M::Carry;
    fn state(&self, w: Vec<f64>) -> Option<[f64; N]> {
        w.try_into().ok()
    }
    #[inline(always)]
    fn step(
        &self,
        sys: &LogHamiltonian<S>,
        ds: f64,
        w: &mut [f64; N],
        carry: &mut M::Carry,
        reuse: bool,
    ) -> bool {
        self.0.step_fixed(sys, 0.0, ds, w, carry, reuse).is_ok()
    }
}

/// The extended state `(q, t, p, p₀)` of the start `z` in the engine's
/// form, or why there is none (a run failed at step 0).
fn start<S, E>(engine: &E, sys: &LogHamiltonian<S>, z: &[f64]) -> Result<E::State, Status>
where
    S: Separable,
    E: Engine<S>,
{
    let extended = sys.extend(z, 0.0).map_err(|e| Status::SolverFailed {
        step: 0,
        reason: e.to_string(),
    })?;
    engine.state(extended).ok_or_else(|| Status::SolverFailed {
        step: 0,
        reason: "the extended state does not have the fixed size".into(),
    })
}

/// The step that would pass `t_end`, made to land on it: a full step of
/// `ds` where that does not pass `t_end`, else the fictitious step
/// `σ ∈ (0, ds)` with `t(σ) = t_end`, found by the Illinois method (a
/// secant that keeps the root bracketed) from the state before the step.
/// Each trial starts from that state and scratch, without reuse (as a
/// plain `step`); `saved` is a buffer for that state. `false` if a trial
/// diverged.
fn land<S, E>(
    engine: &E,
    sys: &LogHamiltonian<S>,
    ds: f64,
    t_end: f64,
    w: &mut E::State,
    ws: &mut E::Scratch,
    saved: &mut E::State,
) -> bool
where
    S: Separable,
    E: Engine<S>,
{
    let n = sys.inner.dof();
    let t = w.as_ref()[n];
    saved.clone_from(w);
    let saved = &*saved;
    let ws0 = ws.clone();
    let trial = |sigma: f64, w: &mut E::State, ws: &mut E::Scratch| -> f64 {
        w.clone_from(saved);
        *ws = ws0.clone();
        if engine.step(sys, sigma, w, ws, false) {
            w.as_ref()[n]
        } else {
            f64::NAN
        }
    };
    let t_full = trial(ds, w, ws);
    if t_full.is_nan() || t_full <= t_end {
        return t_full.is_finite();
    }
    let (mut lo, mut f_lo) = (0.0, t - t_end);
    let (mut hi, mut f_hi) = (ds, t_full - t_end);
    let mut side = 0i8;
    let tol = 4.0 * f64::EPSILON * t_end.abs();
    for _ in 0..100 {
        let sigma = hi - f_hi * (hi - lo) / (f_hi - f_lo);
        let sigma = if sigma > lo && sigma < hi {
            sigma
        } else {
            0.5 * (lo + hi)
        };
        let f = trial(sigma, w, ws) - t_end;
        if !f.is_finite() {
            return false;
        }
        if f.abs() <= tol || hi - lo <= f64::EPSILON * ds {
            break;
        }
        if f > 0.0 {
            hi = sigma;
            f_hi = f;
            if side == 1 {
                f_lo *= 0.5;
            }
            side = 1;
        } else {
            lo = sigma;
            f_lo = f;
            if side == -1 {
                f_hi *= 0.5;
            }
            side = -1;
        }
    }
    true
}

/// `n` steps of the run as `(status, steps taken)`; `z` (`[q; p]` of the
/// problem) is updated in place, `observe(step, t, z)` sees the restricted
/// state after each step (and the start).
fn run<S, E>(
    engine: &E,
    sys: &LogHamiltonian<S>,
    ws: &mut E::Scratch,
    z: &mut [f64],
    t_end: f64,
    h: f64,
    mut observe: impl FnMut(usize, f64, &[f64]) -> bool,
) -> (Status, u64)
where
    S: Separable,
    E: Engine<S>,
{
    let n = sys.inner.dof();
    let mut w = match start(engine, sys, z) {
        Ok(w) => w,
        Err(status) => return (status, 0),
    };
    let ds = h * (-sys.inner.potential(&z[..n]));
    if !observe(0, 0.0, z) {
        return (Status::Stopped { step: 0 }, 0);
    }
    let restrict = |w: &[f64], z: &mut [f64]| {
        z[..n].copy_from_slice(&w[..n]);
        z[n..].copy_from_slice(&w[n + 1..2 * n + 1]);
    };
    let mut saved = w.clone();
    let mut k: u64 = 0;
    while w.as_ref()[n] < t_end {
        if k >= MAX_STEPS {
            return (
                Status::SolverFailed {
                    step: k as usize,
                    reason: format!(
                        "t = {} after {MAX_STEPS} steps of s; T not reached",
                        w.as_ref()[n]
                    ),
                },
                k,
            );
        }
        let t = w.as_ref()[n];
        // dt/ds = 1/(T(p) + p₀) now: near T, guard against passing it.
        let rate = 1.0 / (sys.inner.kinetic(&w.as_ref()[n + 1..2 * n + 1]) + w.as_ref()[2 * n + 1]);
        if !(rate.is_finite() && rate > 0.0) {
            return (Status::Diverged { step: k as usize }, k);
        }
        let stepped = if t + 2.0 * ds * rate < t_end {
            engine.step(sys, ds, &mut w, ws, k > 0)
        } else {
            land(engine, sys, ds, t_end, &mut w, ws, &mut saved)
        };
        if !stepped {
            return (
                Status::Diverged {
                    step: k as usize + 1,
                },
                k,
            );
        }
        k += 1;
        let wr = w.as_ref();
        if wr.iter().any(|x| !x.is_finite()) || wr[n] <= t {
            return (Status::Diverged { step: k as usize }, k);
        }
        restrict(wr, z);
        if !observe(k as usize, wr[n], z) {
            return (Status::Stopped { step: k as usize }, k);
        }
    }
    restrict(w.as_ref(), z);
    (Status::Ok, k)
}

impl<P, M> Stepper<P> for LogH<M>
where
    P: Problem<Kind = AsSeparable> + Separable,
    M: Step<LogHamiltonian<P>>
        + Step<LogHamiltonian<Counting<P>>>
        + StepFixed<LogHamiltonian<P>, 4>
        + StepFixed<LogHamiltonian<P>, 6>
        + StepFixed<LogHamiltonian<P>, 38>
        + Send
        + Sync,
    <M as Step<LogHamiltonian<P>>>::Workspace: Clone,
    <M as Step<LogHamiltonian<Counting<P>>>>::Workspace: Workspace + Clone,
{
    fn observed(
        &self,
        sys: &P,
        z: &mut [f64],
        h: f64,
        n: usize,
        compensated: bool,
        observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
    ) -> Outcome {
        let counted = LogHamiltonian::new(<P::Kind as Kind<P>>::counted(sys));
        let mut ws = Step::<LogHamiltonian<Counting<P>>>::workspace(&self.0, &counted);
        ws.set_compensated(compensated);
        let (status, steps) = run(
            &Slices(&self.0),
            &counted,
            &mut ws,
            z,
            h * n as f64,
            h,
            observe,
        );
        Outcome {
            status,
            evals: counted.inner.counts().force,
            newton_iterations: 0,
            fixed_point_iterations: 0,
            factorizations: 0,
            steps: Some(steps),
        }
    }

    /// Timed on the fixed-size path where the extended state has 4, 6 or
    /// 38 entries (the oscillator and pendulum, Kepler and Hénon–Heiles,
    /// the outer solar system) and the problem has the stack path of its own
    /// size ([`Problem::STACK_SIZES`]); on slices for a problem that names
    /// no size, on the observed run's path for a size it did not name.
    fn bare(&self, sys: &P, z: &mut [f64], h: f64, n: usize) -> bool {
        let logh = LogHamiltonian::new(sys.clone());
        let t_end = h * n as f64;
        // The extended state has two entries more than `P`'s: only the
        // sizes `P` names in `Problem::STACK_SIZES` are compiled.
        let ext = 2 * Separable::dof(&logh);
        if OnSlices::<P>::ON {
            let mut ws = Step::<LogHamiltonian<P>>::workspace(&self.0, &logh);
            let (status, _) = run(&Slices(&self.0), &logh, &mut ws, z, t_end, h, |_, _, _| {
                true
            });
            return status.is_ok() && z.iter().all(|x| x.is_finite());
        }
        let (status, _) = match ext {
            4 if Stacked::<P, 2>::ON => run_fixed::<P, M, 4>(&self.0, &logh, z, t_end, h),
            6 if Stacked::<P, 4>::ON => run_fixed::<P, M, 6>(&self.0, &logh, z, t_end, h),
            38 if Stacked::<P, 36>::ON => run_fixed::<P, M, 38>(&self.0, &logh, z, t_end, h),
            // A size `P` did not name: the observed run's path.
            _ => return bare_on_observed(self, sys, z, h, n),
        };
        status.is_ok() && z.iter().all(|x| x.is_finite())
    }
}

/// An unobserved run on the fixed-size path (compensated, as the slice
/// path's default workspace).
fn run_fixed<S, M, const N: usize>(
    m: &M,
    sys: &LogHamiltonian<S>,
    z: &mut [f64],
    t_end: f64,
    h: f64,
) -> (Status, u64)
where
    S: Separable,
    M: StepFixed<LogHamiltonian<S>, N>,
{
    let mut carry = m.carry(true);
    run(
        &Fixed::<M, N>(m),
        sys,
        &mut carry,
        z,
        t_end,
        h,
        |_, _, _| true,
    )
}
