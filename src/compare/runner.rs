//! Stepping one method on one problem: the generic inner loop, instantiated
//! once per (scheme, problem) pair by [`library!`], behind the object-safe
//! [`Stepper`] so that the experiments themselves are written once.

use integrator_core::implicit::ImplicitWorkspace;
use integrator_core::library::*;
use integrator_core::linear::{LinearHamiltonian, Propagator};
use integrator_core::scheme::{PrkWorkspace, RkWorkspace, SplitWorkspace};
use integrator_core::{OdeSystem, Separable, Step, check_start};

use super::counting::{AsOde, Counting, Counts};

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Status {
    Ok,
    /// A non-finite state after this step.
    Diverged {
        step: usize,
    },
    /// The implicit stage solve (or the propagator's construction) failed.
    SolverFailed {
        step: usize,
        reason: String,
    },
    /// The observer asked to stop after this step.
    Stopped {
        step: usize,
    },
}

impl Status {
    pub fn is_ok(&self) -> bool {
        matches!(self, Status::Ok)
    }
    /// The `status` column of the CSV files.
    pub fn label(&self) -> String {
        match self {
            Status::Ok => "ok".into(),
            Status::Diverged { step } => format!("diverged at step {step}"),
            Status::SolverFailed { step, reason } => {
                format!("solver failed at step {step}: {reason}")
            }
            Status::Stopped { step } => format!("stopped at step {step}"),
        }
    }
}

/// What one observed run did.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub status: Status,
    /// Evaluations: force (separable problems) or right-hand side (linear);
    /// for a propagator, one matrix–vector product per step.
    pub evals: u64,
    pub newton_iterations: usize,
    pub fixed_point_iterations: usize,
    pub factorizations: usize,
}

/// The workspace features the experiments use: the compensated-summation
/// switch and the implicit solver's counters.
pub trait Workspace {
    fn set_compensated(&mut self, on: bool);
    /// `(newton_iterations, fixed_point_iterations, factorizations)`;
    /// zero for explicit schemes.
    fn solver_counts(&self) -> (usize, usize, usize) {
        (0, 0, 0)
    }
}

impl<const S: usize> Workspace for RkWorkspace<S> {
    fn set_compensated(&mut self, on: bool) {
        self.compensated = on;
    }
}
impl Workspace for SplitWorkspace {
    fn set_compensated(&mut self, on: bool) {
        self.compensated = on;
    }
}
impl<const S: usize> Workspace for PrkWorkspace<S> {
    fn set_compensated(&mut self, on: bool) {
        self.compensated = on;
    }
}
impl Workspace for ImplicitWorkspace {
    fn set_compensated(&mut self, on: bool) {
        self.settings_mut().compensated = on;
    }
    fn solver_counts(&self) -> (usize, usize, usize) {
        let s = self.stats();
        (
            s.newton_iterations,
            s.fixed_point_iterations,
            s.factorizations,
        )
    }
}
/// The propagator's scratch vector: nothing to switch, nothing to count.
impl Workspace for Vec<f64> {
    fn set_compensated(&mut self, _on: bool) {}
}

/// A problem type as the experiments see it: a system with an energy and
/// its counting wrapper.
pub trait System: OdeSystem + Clone + Send + Sync + 'static {
    /// The same system with its evaluations counted.
    type Counted: OdeSystem;
    fn counted(&self) -> Self::Counted;
    fn counts(c: &Self::Counted) -> Counts;
    /// The energy of a state.
    fn energy_of(&self, z: &[f64]) -> f64;
}

macro_rules! separable_system {
    ($($ty:ty),* $(,)?) => {$(
        impl System for $ty {
            type Counted = Counting<$ty>;
            fn counted(&self) -> Counting<$ty> {
                Counting::new(self.clone())
            }
            fn counts(c: &Counting<$ty>) -> Counts {
                c.counts()
            }
            fn energy_of(&self, z: &[f64]) -> f64 {
                integrator_core::energy(self, z)
            }
        }
    )*};
}
use integrator_core::problems::{Fpu, HenonHeiles, Kepler, Oscillator, Pendulum};
separable_system!(Oscillator, Pendulum, Kepler, HenonHeiles, Fpu);

impl System for LinearHamiltonian {
    type Counted = Counting<LinearHamiltonian, AsOde>;
    fn counted(&self) -> Self::Counted {
        Counting::new(self.clone())
    }
    fn counts(c: &Self::Counted) -> Counts {
        c.counts()
    }
    fn energy_of(&self, z: &[f64]) -> f64 {
        self.energy(z)
    }
}

/// One method on problems of type `P`.
pub trait Stepper<P: System>: Send + Sync {
    /// `n` steps of size `h` from `z` (at `t = 0`) on the counting wrapper,
    /// calling `observe(step, t, z)` before the first step and after each;
    /// `observe` returning `false` stops the run. `compensated` switches
    /// compensated summation (the workspaces' default is on).
    fn observed(
        &self,
        sys: &P,
        z: &mut [f64],
        h: f64,
        n: usize,
        compensated: bool,
        observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
    ) -> Outcome;
    /// The same run on the bare system, no observer, default settings: what
    /// is timed. `false` if it failed or ended non-finite.
    fn bare(&self, sys: &P, z: &mut [f64], h: f64, n: usize) -> bool;
}

/// The loop of [`integrate`](integrator_core::integrate), with the
/// workspace in the caller's hands and an observer that may stop it.
fn drive<S, M>(
    m: &M,
    sys: &S,
    ws: &mut M::Workspace,
    z: &mut [f64],
    h: f64,
    n: usize,
    mut observe: impl FnMut(usize, f64, &[f64]) -> bool,
) -> Status
where
    S: OdeSystem + ?Sized,
    M: Step<S>,
{
    if let Err(e) = check_start(sys, z, h) {
        return Status::SolverFailed {
            step: 0,
            reason: e.to_string(),
        };
    }
    if !observe(0, 0.0, z) {
        return Status::Stopped { step: 0 };
    }
    for k in 0..n {
        let t = k as f64 * h;
        if let Err(e) = m.step_reusing(sys, t, h, z, ws, k > 0) {
            return Status::SolverFailed {
                step: k + 1,
                reason: e.to_string(),
            };
        }
        if z.iter().any(|x| !x.is_finite()) {
            return Status::Diverged { step: k + 1 };
        }
        if !observe(k + 1, (k + 1) as f64 * h, z) {
            return Status::Stopped { step: k + 1 };
        }
    }
    Status::Ok
}

/// A library scheme (a zero-sized `butcher!` type) as a [`Stepper`].
pub struct Lib<M>(pub M);

impl<M, P> Stepper<P> for Lib<M>
where
    P: System,
    M: Step<P> + Step<P::Counted> + Send + Sync,
    <M as Step<P>>::Workspace: Workspace,
    <M as Step<P::Counted>>::Workspace: Workspace,
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
        let counted = sys.counted();
        let mut ws = Step::<P::Counted>::workspace(&self.0, &counted);
        ws.set_compensated(compensated);
        let status = drive(&self.0, &counted, &mut ws, z, h, n, observe);
        let counts = P::counts(&counted);
        let (newton_iterations, fixed_point_iterations, factorizations) = ws.solver_counts();
        Outcome {
            status,
            evals: counts.force + counts.rhs,
            newton_iterations,
            fixed_point_iterations,
            factorizations,
        }
    }

    fn bare(&self, sys: &P, z: &mut [f64], h: f64, n: usize) -> bool {
        let mut ws = Step::<P>::workspace(&self.0, sys);
        for k in 0..n {
            if self
                .0
                .step_reusing(sys, k as f64 * h, h, z, &mut ws, k > 0)
                .is_err()
            {
                return false;
            }
        }
        z.iter().all(|x| x.is_finite())
    }
}

/// The exact one-step map `z ← R(hH)z + φ` of a Runge–Kutta table on the
/// linear system ([`Propagator`]), built for each `h` (its construction is
/// part of the timed run). One matrix–vector product per step, counted as
/// one evaluation.
pub struct PropagatorStepper {
    pub p: Vec<f64>,
    pub q: Vec<f64>,
}

impl Stepper<LinearHamiltonian> for PropagatorStepper {
    fn observed(
        &self,
        sys: &LinearHamiltonian,
        z: &mut [f64],
        h: f64,
        n: usize,
        _compensated: bool,
        observe: &mut dyn FnMut(usize, f64, &[f64]) -> bool,
    ) -> Outcome {
        let (status, steps) = match Propagator::new(sys, h, &self.p, &self.q) {
            Ok(prop) => {
                let mut ws = prop.workspace();
                let mut steps = 0;
                let status = drive(&prop, sys, &mut ws, z, h, n, |k, t, z| {
                    steps = k;
                    observe(k, t, z)
                });
                (status, steps as u64)
            }
            Err(e) => (
                Status::SolverFailed {
                    step: 0,
                    reason: e.to_string(),
                },
                0,
            ),
        };
        Outcome {
            status,
            evals: steps,
            newton_iterations: 0,
            fixed_point_iterations: 0,
            factorizations: 0,
        }
    }

    fn bare(&self, sys: &LinearHamiltonian, z: &mut [f64], h: f64, n: usize) -> bool {
        let Ok(prop) = Propagator::new(sys, h, &self.p, &self.q) else {
            return false;
        };
        let mut ws = prop.workspace();
        for _ in 0..n {
            prop.step(z, &mut ws);
        }
        z.iter().all(|x| x.is_finite())
    }
}

/// Declares the library by id: which schemes step any `OdeSystem` (`rk`:
/// Runge–Kutta tables, explicit and implicit) and which only separable
/// Hamiltonians (`separable`: drift–kick sequences, compositions, explicit
/// pairs, and the implicit pair, which steps `Hamiltonian`s — all our
/// Hamiltonian problems are separable). Emits the id lists and the two
/// constructors; `tests::library_lists_cover_the_registry` checks the lists
/// against `REGISTRY`.
macro_rules! library {
    (
        rk: [$($rid:literal => $rty:ident),* $(,)?],
        separable: [$($sid:literal => $sty:ident),* $(,)?] $(,)?
    ) => {
        /// Ids of the Runge–Kutta tables (they step every `OdeSystem`).
        pub const RK_IDS: &[&str] = &[$($rid),*];
        /// Ids of the schemes that step separable Hamiltonians only.
        pub const SEPARABLE_IDS: &[&str] = &[$($sid),*];

        /// Any library scheme on a separable problem, `None` for an id not
        /// in the library.
        pub fn separable_stepper<P>(id: &str) -> Option<Box<dyn Stepper<P>>>
        where
            P: System<Counted = Counting<P>> + Separable,
        {
            Some(match id {
                $($rid => Box::new(Lib($rty)),)*
                $($sid => Box::new(Lib($sty)),)*
                _ => return None,
            })
        }

        /// A Runge–Kutta table on the linear system, `None` for any other id.
        pub fn linear_stepper(id: &str) -> Option<Box<dyn Stepper<LinearHamiltonian>>> {
            Some(match id {
                $($rid => Box::new(Lib($rty)),)*
                _ => return None,
            })
        }
    };
}

library! {
    rk: [
        "euler" => ExplicitEuler,
        "heun" => Heun,
        "rk4" => Rk4,
        "rk38" => Rk38,
        "implicit-euler" => ImplicitEuler,
        "midpoint" => ImplicitMidpoint,
        "gauss1" => GaussLegendre1,
        "gauss2" => GaussLegendre2,
        "gauss3" => GaussLegendre3,
        "radau2a-2" => RadauIIA2,
        "radau2a-3" => RadauIIA3,
        "lobatto3a-2" => LobattoIIIA2,
        "lobatto3a-3" => LobattoIIIA3,
        "lobatto3b-2" => LobattoIIIB2,
        "lobatto3b-3" => LobattoIIIB3,
        "lobatto3c-2" => LobattoIIIC2,
        "lobatto3c-3" => LobattoIIIC3,
        "lobatto3cstar-2" => LobattoIIICStar2,
        "paper-dirk2" => PaperDirk2,
        "paper-dirk4" => PaperDirk4,
    ],
    separable: [
        "symplectic-euler-a" => SymplecticEulerA,
        "symplectic-euler-b" => SymplecticEulerB,
        "stormer-verlet" => StormerVerlet,
        "lobatto3a3b-3" => LobattoIIIAIIIB3,
        "lobatto3c3cstar-2" => LobattoIIICIIICStar2,
        "leapfrog" => Leapfrog,
        "ruth3" => Ruth3,
        "forest-ruth" => ForestRuth,
        "candy-rozmus4" => CandyRozmus4,
        "mclachlan-atela2" => McLachlanAtela2,
        "mclachlan-atela3" => McLachlanAtela3,
        "mclachlan-atela4" => McLachlanAtela4,
        "mclachlan-atela5" => McLachlanAtela5,
        "calvo-sanz-serna4" => CalvoSanzSerna4,
        "mclachlan4" => McLachlan4,
        "yoshida4" => Yoshida4,
        "yoshida6" => Yoshida6,
        "kahan-li6" => KahanLi6,
        "kahan-li8" => KahanLi8,
        "mclachlan8" => McLachlan8,
        "sofroniou-spaletta10" => SofroniouSpaletta10,
    ],
}

/// The Gauss tables whose propagators are offered on the linear system, as
/// `(id, P, Q)` of their stability functions.
pub fn propagator_tables() -> Vec<(&'static str, Vec<f64>, Vec<f64>)> {
    vec![
        (
            "gauss1-propagator",
            GaussLegendre1::STABILITY_P.to_vec(),
            GaussLegendre1::STABILITY_Q.to_vec(),
        ),
        (
            "gauss2-propagator",
            GaussLegendre2::STABILITY_P.to_vec(),
            GaussLegendre2::STABILITY_Q.to_vec(),
        ),
        (
            "gauss3-propagator",
            GaussLegendre3::STABILITY_P.to_vec(),
            GaussLegendre3::STABILITY_Q.to_vec(),
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use integrator_core::library::REGISTRY;

    #[test]
    fn library_lists_cover_the_registry() {
        let mut all: Vec<&str> = RK_IDS.iter().chain(SEPARABLE_IDS).copied().collect();
        let mut registry: Vec<&str> = REGISTRY.iter().map(|(id, _)| *id).collect();
        all.sort_unstable();
        registry.sort_unstable();
        assert_eq!(all, registry);
        for (id, info) in REGISTRY {
            assert_eq!(
                RK_IDS.contains(id),
                info.form == "rk",
                "{id}: form {}",
                info.form
            );
        }
    }

    #[test]
    fn observed_and_bare_runs_agree() {
        let sys = Kepler { e: 0.3 };
        let z0 = sys.initial_state();
        for id in ["leapfrog", "rk4", "gauss2"] {
            let s = separable_stepper::<Kepler>(id).unwrap();
            let mut a = z0.clone();
            let out = s.observed(&sys, &mut a, 0.01, 100, true, &mut |_, _, _| true);
            assert!(out.status.is_ok(), "{id}");
            assert!(out.evals > 0);
            let mut b = z0.clone();
            assert!(s.bare(&sys, &mut b, 0.01, 100));
            assert_eq!(a, b, "{id}");
        }
    }
}
