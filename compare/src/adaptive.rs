//! Reversible adaptive stepping in the comparisons: `adaptive:ID` steps a
//! symmetric library scheme `ID` under the integrating reversible
//! controller (Hairer–Söderlind 2005), `adaptive-implicit:ID` under the
//! implicit symmetric rule `h = ε·(σ(yₙ) + σ(yₙ₊₁))/2` (Hairer 1997), both
//! from [`integrator_core::adaptive`], with the problem's step density
//! ([`Problem::STEP_DENSITY`]: the inverse distance for Kepler).
//!
//! A run asked for `n` steps of `h` over `[0, T]` takes `ε = h/σ(y₀)` (at
//! the start, a step of `h` in `t`, as `logh:ID` does) and lands on `T`
//! exactly (the last step cut); the row reports the steps actually taken.
//! The implicit rule's evaluations include every iteration of its step
//! size.

use integrator_core::adaptive::{Controller, Reversible};
use integrator_core::library::*;
use integrator_core::{Scheme, Separable, Step};

use crate::counting::{AsOde, AsSeparable, Counting};
use crate::error::{CompareError, Result};
use crate::method::{Fixed, Method, family_of, symplectic_for};
use crate::problem::{Adaptable, ByKind, Kind, Problem};
use crate::stepper::{Outcome, Status, Stepper, Workspace};

/// A symmetric scheme under a reversible controller.
pub struct Adaptive<M> {
    pub scheme: M,
    pub controller: Controller,
}

/// The prefixes of the two controllers.
pub const PREFIXES: [(&str, Controller); 2] = [
    ("adaptive:", Controller::Integrating),
    ("adaptive-implicit:", Controller::Implicit),
];

#[allow(clippy::too_many_arguments)]
fn run<P, S, M>(
    a: &Adaptive<M>,
    problem: &P,
    sys: &S,
    ws: &mut <M as Step<S>>::Workspace,
    z: &mut [f64],
    h: f64,
    n: usize,
    observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
) -> (Status, u64)
where
    P: Problem,
    S: integrator_core::OdeSystem + Separable,
    M: Step<S> + Copy,
{
    let Some(density) = P::STEP_DENSITY else {
        return (
            Status::SolverFailed {
                step: 0,
                reason: format!("the {} problem has no step density", problem.name()),
            },
            0,
        );
    };
    let r = Reversible {
        scheme: a.scheme,
        density,
        controller: a.controller,
    };
    use integrator_core::adaptive::StepDensity;
    let sigma = density.sigma(sys, z);
    let eps = h / sigma;
    if !observe(0, 0.0, z) {
        return (Status::Stopped { step: 0 }, 0);
    }
    let mut k = 0usize;
    let mut stopped = false;
    let result = r.integrate_in(sys, z, 0.0, h * n as f64, eps, ws, |t, z| {
        k += 1;
        if observe(k, t, z) {
            true
        } else {
            stopped = true;
            false
        }
    });
    match result {
        Ok(run) if stopped => (Status::Stopped { step: k }, run.steps),
        Ok(run) => (Status::Ok, run.steps),
        Err(integrator_core::adaptive::AdaptiveError::Diverged { step, .. }) => (
            Status::Diverged {
                step: step as usize,
            },
            step,
        ),
        Err(e) => (
            Status::SolverFailed {
                step: k + 1,
                reason: e.to_string(),
            },
            k as u64,
        ),
    }
}

impl<P, M> Stepper<P> for Adaptive<M>
where
    P: Problem<Kind = AsSeparable> + Separable,
    M: Step<P> + Step<Counting<P>> + Copy + Send + Sync,
    <M as Step<Counting<P>>>::Workspace: Workspace,
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
        let counted = <P::Kind as Kind<P>>::counted(sys);
        let mut ws = Step::<Counting<P>>::workspace(&self.scheme, &counted);
        ws.set_compensated(compensated);
        let (status, steps) = run(self, sys, &counted, &mut ws, z, h, n, observe);
        let counts = counted.counts();
        let (newton_iterations, fixed_point_iterations, factorizations) = ws.solver_counts();
        Outcome {
            status,
            evals: counts.force + counts.rhs,
            newton_iterations,
            fixed_point_iterations,
            factorizations,
            steps: Some(steps),
        }
    }

    fn bare(&self, sys: &P, z: &mut [f64], h: f64, n: usize) -> bool {
        let mut ws = Step::<P>::workspace(&self.scheme, sys);
        let (status, _) = run(self, sys, sys, &mut ws, z, h, n, &mut |_, _, _| true);
        status.is_ok() && z.iter().all(|x| x.is_finite())
    }
}

/// The symmetric library schemes, which the reversible controllers accept:
/// those whose verified `INFO.symmetric` says so, in the library's order.
pub fn symmetric_ids() -> Vec<&'static str> {
    integrator_core::library::REGISTRY
        .iter()
        .filter(|(_, info)| info.symmetric)
        .map(|(id, _)| *id)
        .collect()
}

/// Generates [`stepper`] from the library's one scheme list
/// (`integrator_core::for_each_scheme!`): an id whose scheme is symmetric
/// becomes an adaptive stepper, any other `None`.
macro_rules! symmetric {
    ($($group:ident: [$($id:literal => $ty:ident),* $(,)?]),* $(,)?) => {
        /// The library scheme `id` under `controller`, with its facts, if it
        /// is symmetric; `None` for any other id.
        pub fn stepper<P>(id: &str, controller: Controller) -> Option<(Box<dyn Stepper<P>>, integrator_core::Info)>
        where
            P: Problem<Kind = AsSeparable> + Separable,
        {
            Some(match id {
                $($($id if <$ty as Scheme>::INFO.symmetric => (
                    Box::new(Adaptive { scheme: $ty, controller }) as Box<dyn Stepper<P>>,
                    <$ty as Scheme>::INFO,
                ),)*)*
                _ => return None,
            })
        }
    };
}

integrator_core::for_each_scheme!(symmetric);

/// `adaptive:BASE` / `adaptive-implicit:BASE` for the problem type `P`
/// (named `problem` in messages), or why not: a problem that is not
/// separable or has no step density, an unknown base, a base that is not
/// symmetric.
pub fn method<P: Problem>(
    prefix: &str,
    controller: Controller,
    base: &str,
    problem: &str,
) -> Result<Method<P>> {
    let id = format!("{prefix}{base}");
    let err = |why: String| Err(CompareError::method(&id, format!("method '{id}': {why}")));
    if !<P::Kind as Kind<P>>::SEPARABLE {
        return err(format!(
            "the reversible controllers take the problem's step density; the {problem} problem is an OdeSystem only"
        ));
    }
    if P::STEP_DENSITY.is_none() {
        return err(format!(
            "the {problem} problem has no step density (adaptive steps apply to kepler and kepler-hard, whose density is the inverse distance)"
        ));
    }
    match stepper_for::<P>(base, controller) {
        Some((stepper, i)) => Ok(Method::Fixed(Fixed {
            id,
            order: i.order,
            symplectic: symplectic_for::<P>(i.symplectic, i.symplectic_separable),
            family: family_of(&i),
            interpreted: false,
            stepper,
        })),
        None => match integrator_core::library::info(base) {
            Some(i) if !i.symmetric => err(format!(
                "'{base}' is not symmetric: reversible step-size control needs a symmetric method; symmetric ones: {}",
                symmetric_ids().join(", ")
            )),
            _ => err(format!(
                "unknown base method '{base}'; {prefix} takes one of {}",
                symmetric_ids().join(", ")
            )),
        },
    }
}

/// The symmetric scheme `id` under `controller` as a stepper of `P`, with
/// its facts: `None` if `id` is not symmetric or `P` is not separable.
fn stepper_for<P: Problem>(
    id: &str,
    controller: Controller,
) -> Option<(Box<dyn Stepper<P>>, integrator_core::Info)> {
    struct Symmetric<'a>(&'a str, Controller);
    impl<P: Problem> ByKind<P> for Symmetric<'_> {
        type Output = Option<(Box<dyn Stepper<P>>, integrator_core::Info)>;
        fn separable(self) -> Self::Output
        where
            P: Problem<Kind = AsSeparable> + Separable,
        {
            // A constant of `P`: for a problem without a step density the
            // adaptive variants of the symmetric schemes are not compiled.
            if Adaptable::<P>::ON {
                stepper(self.0, self.1)
            } else {
                None
            }
        }
        fn ode(self) -> Self::Output
        where
            P: Problem<Kind = AsOde>,
        {
            None
        }
    }
    <P::Kind as Kind<P>>::by_kind(Symmetric(id, controller))
}

/// The symmetric scheme `id` under `controller` on a separable problem.
pub fn adaptive_stepper<P>(
    id: &str,
    controller: Controller,
) -> Option<(Box<dyn Stepper<P>>, integrator_core::Info)>
where
    P: Problem<Kind = AsSeparable> + Separable,
{
    stepper(id, controller)
}
