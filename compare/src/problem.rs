//! What a problem is to the comparisons: a system with an energy, a start,
//! a reference solution and default sweep settings ([`Problem`]), and one
//! instance of it over `[0, T]` with its reference end state ([`Setup`]).
//!
//! A user's own system enters every experiment by implementing [`Problem`];
//! the library's problems implement it in [`builtin`](crate::builtin).

use integrator_core::{OdeSystem, Separable};

use crate::counting::{AsOde, AsSeparable, Counting, Counts};
use crate::error::{CompareError, Result};

/// The default work–precision sweep of a problem: the end time and the
/// range of step sizes (from about 100 to about 10⁵ steps is a good start).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Defaults {
    pub t_end: f64,
    pub h_min: f64,
    pub h_max: f64,
}

/// A system the comparisons can run.
///
/// `Kind` says how the harness may treat it, and so which library schemes
/// apply: [`AsSeparable`] for a [`Separable`] Hamiltonian (every library
/// scheme; evaluations counted as force calls), [`AsOde`] for any other
/// [`OdeSystem`] (the Runge–Kutta tables; right-hand sides counted).
///
/// ```
/// use compare::{AsSeparable, Defaults, Problem};
/// use integrator_core::Separable;
///
/// /// A quartic oscillator, H = p²/2 + q⁴/4.
/// #[derive(Clone)]
/// struct Quartic;
/// impl Separable for Quartic {
///     fn dof(&self) -> usize { 1 }
///     fn kinetic(&self, p: &[f64]) -> f64 { 0.5 * p[0] * p[0] }
///     fn potential(&self, q: &[f64]) -> f64 { 0.25 * q[0].powi(4) }
///     fn velocity(&self, p: &[f64], v: &mut [f64]) { v[0] = p[0] }
///     fn force(&self, q: &[f64], f: &mut [f64]) { f[0] = -q[0].powi(3) }
/// }
/// impl Problem for Quartic {
///     type Kind = AsSeparable;
///     fn name(&self) -> String { "quartic".into() }
///     fn energy(&self, z: &[f64]) -> f64 { integrator_core::energy(self, z) }
///     fn start(&self) -> Vec<f64> { vec![1.0, 0.0] }
///     fn reference(&self, z0: &[f64], t_end: f64) -> Result<Vec<f64>, String> {
///         // No closed form: a converged run of a high-order scheme.
///         Ok(integrator_core::problems::reference_solution(self, z0, t_end, 2000.0))
///     }
///     fn defaults(&self) -> Defaults {
///         Defaults { t_end: 10.0, h_min: 1e-3, h_max: 0.1 }
///     }
/// }
/// let setup = compare::Setup::new(Quartic, 10.0).unwrap();
/// assert_eq!(setup.reference.len(), 2);
/// ```
pub trait Problem: OdeSystem + Clone + Send + Sync + Sized + 'static {
    /// [`AsSeparable`] or [`AsOde`].
    type Kind: Kind<Self>;
    /// A short id: the `problem` column of `runs.csv`, directory names.
    fn name(&self) -> String;
    /// A line for titles and reports (default: the name).
    fn description(&self) -> String {
        self.name()
    }
    /// The energy (the Hamiltonian) of a state; the energy error of a run is
    /// `max |E(z) − E(z₀)|/|E(z₀)|` over its steps.
    fn energy(&self, z: &[f64]) -> f64;
    /// The default start state `z₀` (length [`dim`](OdeSystem::dim)).
    fn start(&self) -> Vec<f64>;
    /// The state at `t_end` of the solution from `z0`: an exact flow, or a
    /// computed solution accurate well below the errors compared. An `Err`
    /// says why there is none (e.g. outside the case a formula covers).
    fn reference(&self, z0: &[f64], t_end: f64) -> std::result::Result<Vec<f64>, String>;
    /// The default end time and step range of a sweep.
    fn defaults(&self) -> Defaults;
    /// A natural unit of time, for reports ("T = 62.8319 (10 orbits)"):
    /// `(length, singular name)`; `None` (the default) for none.
    fn period(&self) -> Option<(f64, &'static str)> {
        None
    }
    /// The system as a linear one, `z' = Hz + u` (the gyroscopic problem
    /// and linear problem files): the exact one-step maps of the Gauss
    /// tables, `gaussN-propagator`, apply to it. `None` (the default): not
    /// linear.
    fn linear(&self) -> Option<&integrator_core::linear::LinearHamiltonian> {
        None
    }
    /// The state sizes on which a timed run may step a stack array
    /// `[f64; N]` instead of slices (the library's explicit schemes, the
    /// `logh:` variants and the DOP853 peer; both paths give the same bits).
    /// Only the sizes named here are compiled for this problem: each one is
    /// a copy of every explicit scheme's step (about a minute of build time
    /// per size for a new problem type). The default,
    /// [`StackSizes::NONE`], steps slices; a problem of a fixed size that is
    /// timed names it ([`StackSizes::only`]), as the built-in problems do,
    /// and gets the stack path. A state of another size than the ones named
    /// is still stepped, on the observed run's path, with the same bits.
    const STACK_SIZES: StackSizes = StackSizes::NONE;
    /// The step-size function of the reversible adaptive methods
    /// (`adaptive:ID`, [`adaptive`](crate::adaptive)): `σ = |q|^α` for a
    /// problem whose position is a distance from a centre (Kepler: the
    /// inverse distance as step density, `α = 1`); `None` (the default):
    /// the problem offers no adaptive methods. A constant of the type, not
    /// of an instance, for the same reason as `STACK_SIZES`: the adaptive
    /// variant of every symmetric scheme is compiled only for the problems
    /// that have one.
    const STEP_DENSITY: Option<integrator_core::adaptive::DistancePower> = None;
    /// Whether the potential is negative wherever the problem goes,
    /// `V(q) < 0`, as gravity's `−Σ Gmᵢmⱼ/rᵢⱼ` is: the logarithmic
    /// Hamiltonian of `logh:ID` ([`time_transformed`](crate::time_transformed):
    /// `ds = dt·(−V)`) is defined only there. `false` (the default): no
    /// `logh:` methods, which are then neither offered nor compiled for the
    /// problem (each is a copy of every explicit scheme's step on the
    /// extended system). A start where `V ≥ 0` is still refused at step 0.
    const NEGATIVE_POTENTIAL: bool = false;
    /// The N-body ability for Wisdom–Holman methods (`wh:ID`,
    /// [`wisdom_holman`](crate::wisdom_holman)): the Jacobi split of the
    /// same bodies, masses and `G`, for a problem whose state is the
    /// inertial `[x; p]` with body 0 the central mass. `None` (the
    /// default): no `wh:` methods.
    fn wisdom_holman(&self) -> Option<integrator_core::problems::wisdom_holman::Jacobi> {
        None
    }
    /// The problem as REBOUND's point masses from the state `z` (the
    /// `rebound:` methods, [`rebound`](crate::rebound)); `None` (the
    /// default): REBOUND cannot run it. An `Err` says why this state cannot
    /// be given to it exactly.
    fn rebound_bodies(
        &self,
        z: &[f64],
    ) -> Option<std::result::Result<crate::nbody::Bodies, String>> {
        let _ = z;
        None
    }
}

/// The state sizes with a stack-array path in timed runs
/// ([`Problem::STACK_SIZES`]): a set of 2, 4, 6, 12 and 36, the sizes of
/// the built-in problems (36: the outer solar system). A run on a state of
/// another size, or of a size not in the set, steps slices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StackSizes(u8);

impl StackSizes {
    /// Every size with a stack path.
    pub const ALL: StackSizes = StackSizes(0b1_1111);
    /// None: timed runs step slices.
    pub const NONE: StackSizes = StackSizes(0);
    /// The sizes with a stack path, in [`StackSizes::ALL`]'s bit order.
    pub const SIZES: [usize; 5] = [2, 4, 6, 12, 36];

    /// The one size `n`; a size without a stack path is a compile-time
    /// error where the set is a constant (`const STACK_SIZES`).
    pub const fn only(n: usize) -> StackSizes {
        let mut i = 0;
        while i < Self::SIZES.len() {
            if Self::SIZES[i] == n {
                return StackSizes(1 << i);
            }
            i += 1;
        }
        panic!("a stack path exists for state sizes 2, 4, 6, 12 and 36 only")
    }

    /// Whether the set is empty (timed runs step slices).
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Whether `n` is in the set.
    pub const fn contains(self, n: usize) -> bool {
        let mut i = 0;
        while i < Self::SIZES.len() {
            if Self::SIZES[i] == n {
                return self.0 & (1 << i) != 0;
            }
            i += 1;
        }
        false
    }
}

/// `Stacked::<P, N>::ON`: whether `P` has the stack path of size `N`. A
/// constant of the instance, so that a branch `if Stacked::<P, N>::ON` of a
/// size `P` lacks is dropped before code generation, with the step code it
/// would instantiate (the point of [`Problem::STACK_SIZES`]).
/// `Adaptable::<P>::ON`: whether `P` has a step density
/// ([`Problem::STEP_DENSITY`]), a constant of the instance like
/// [`Stacked`]'s.
pub(crate) struct Adaptable<P>(std::marker::PhantomData<P>);

impl<P: Problem> Adaptable<P> {
    pub(crate) const ON: bool = P::STEP_DENSITY.is_some();
}

/// `OnSlices::<P>::ON`: whether `P` names no stack size, so that its
/// timed runs step slices; a constant of the instance like [`Stacked`]'s
/// (a problem that names sizes has no separate slice copy of the timed
/// loop: a state of another size takes the observed run's path).
pub(crate) struct OnSlices<P>(std::marker::PhantomData<P>);

impl<P: Problem> OnSlices<P> {
    pub(crate) const ON: bool = P::STACK_SIZES.is_empty();
}

pub(crate) struct Stacked<P, const N: usize>(std::marker::PhantomData<P>);

impl<P: Problem, const N: usize> Stacked<P, N> {
    pub(crate) const ON: bool = P::STACK_SIZES.contains(N);
}

/// How the harness treats a problem type: the counting wrapper it runs the
/// observed runs on, and which of the two kinds it is — which decides the
/// library schemes and table forms that can step it (the method families
/// ask through [`Kind::by_kind`]). Implemented by the two markers
/// [`AsSeparable`] and [`AsOde`]; a problem names one as its
/// [`Problem::Kind`].
pub trait Kind<P>: Sized + 'static {
    /// `P` with its evaluations counted.
    type Counted: OdeSystem;
    /// Symplectic claims for separable Hamiltonians apply to `P`.
    const SEPARABLE: bool;
    /// Wrap a copy of the system.
    fn counted(p: &P) -> Self::Counted;
    fn counts(c: &Self::Counted) -> Counts;
    /// `f` for `P` as what it is: [`ByKind::separable`] for a separable
    /// Hamiltonian, [`ByKind::ode`] for any other `OdeSystem`.
    fn by_kind<F: ByKind<P>>(f: F) -> F::Output;
}

/// A computation that needs to know which [`Kind`] a problem type is (a
/// method family building a stepper: only a separable problem takes a
/// splitting), handed the problem type with the bounds of its kind.
pub trait ByKind<P> {
    type Output;
    /// For a separable Hamiltonian.
    fn separable(self) -> Self::Output
    where
        P: Problem<Kind = AsSeparable> + Separable;
    /// For an `OdeSystem` only.
    fn ode(self) -> Self::Output
    where
        P: Problem<Kind = AsOde>;
}

/// `P`'s counting wrapper.
pub type Counted<P> = <<P as Problem>::Kind as Kind<P>>::Counted;

impl<P: Problem<Kind = AsSeparable> + Separable> Kind<P> for AsSeparable {
    type Counted = Counting<P>;
    const SEPARABLE: bool = true;
    fn counted(p: &P) -> Counting<P> {
        Counting::new(p.clone())
    }
    fn counts(c: &Counting<P>) -> Counts {
        c.counts()
    }
    fn by_kind<F: ByKind<P>>(f: F) -> F::Output {
        f.separable()
    }
}

impl<P: Problem<Kind = AsOde>> Kind<P> for AsOde {
    type Counted = Counting<P, AsOde>;
    const SEPARABLE: bool = false;
    fn counted(p: &P) -> Counting<P, AsOde> {
        Counting::new(p.clone())
    }
    fn counts(c: &Counting<P, AsOde>) -> Counts {
        c.counts()
    }
    fn by_kind<F: ByKind<P>>(f: F) -> F::Output {
        f.ode()
    }
}

/// Set a problem up with a panic in its code caught: an error naming the
/// problem's type and the panic's message.
fn caught_setup<P>(f: impl FnOnce() -> Result<Setup<P>>) -> Result<Setup<P>> {
    crate::guard::catch(f).unwrap_or_else(|message| {
        Err(CompareError::problem(
            std::any::type_name::<P>(),
            format!("panicked while setting up (start, energy or reference): {message}"),
        ))
    })
}

/// A problem instance: the system, its start, the end time `T` and the
/// reference state at `T` (empty for runs judged by the energy alone).
#[derive(Clone, Debug)]
pub struct Setup<P> {
    /// The `problem` column of the CSV files (default: [`Problem::name`]).
    pub name: String,
    pub description: String,
    pub sys: P,
    pub z0: Vec<f64>,
    pub t_end: f64,
    /// The reference state at `t_end`; empty for a setup made with
    /// [`Setup::energy_only`].
    pub reference: Vec<f64>,
    /// `E(z0)`.
    pub e0: f64,
}

impl<P: Problem> Setup<P> {
    /// The problem from its default start to `t_end`, with its reference
    /// end state. Errors name what is wrong: a non-positive or non-finite
    /// `t_end`, a start or a reference of the wrong length or not finite, a
    /// non-finite energy.
    ///
    /// The problem's own code (its start, energy, reference) runs here; a
    /// panic in it is caught and returned as an error naming the problem.
    pub fn new(sys: P, t_end: f64) -> Result<Self> {
        caught_setup(|| {
            let z0 = sys.start();
            Self::reference_from(sys, z0, t_end)
        })
    }

    /// The problem from `z0` to `t_end`, with its reference end state.
    pub fn from_start(sys: P, z0: Vec<f64>, t_end: f64) -> Result<Self> {
        caught_setup(|| Self::reference_from(sys, z0, t_end))
    }

    fn reference_from(sys: P, z0: Vec<f64>, t_end: f64) -> Result<Self> {
        let mut s = Self::energy_only_from(sys, z0, t_end)?;
        let reference = s.sys.reference(&s.z0, t_end).map_err(|why| {
            CompareError::problem(&s.name, format!("no reference solution: {why}"))
        })?;
        s.check_state("the reference end state", &reference)?;
        s.reference = reference;
        Ok(s)
    }

    /// The problem from its default start over `[0, t_end]` without a
    /// reference (long runs and stability searches judge by the energy
    /// alone; a computed reference over 10⁴ time units would cost more than
    /// the runs).
    pub fn energy_only(sys: P, t_end: f64) -> Result<Self> {
        caught_setup(|| {
            let z0 = sys.start();
            Self::energy_only_from(sys, z0, t_end)
        })
    }

    fn energy_only_from(sys: P, z0: Vec<f64>, t_end: f64) -> Result<Self> {
        let name = sys.name();
        if !(t_end.is_finite() && t_end > 0.0) {
            return Err(CompareError::setting(
                "t_end",
                format!("the end time must be a finite number > 0, got {t_end}"),
            ));
        }
        let mut s = Setup {
            description: sys.description(),
            name,
            sys,
            z0,
            t_end,
            reference: vec![],
            e0: f64::NAN,
        };
        // The length first: the problem's own energy may index the state.
        s.check_state("the start state", &s.z0)?;
        let e0 = s.sys.energy(&s.z0);
        s.e0 = e0;
        if !e0.is_finite() {
            return Err(CompareError::problem(
                &s.name,
                format!("the energy of the start state is {e0}"),
            ));
        }
        Ok(s)
    }

    fn check_state(&self, what: &str, z: &[f64]) -> Result<()> {
        let dim = self.sys.dim();
        if z.len() != dim {
            return Err(CompareError::problem(
                &self.name,
                format!(
                    "{what} has {} components, the system has dimension {dim}",
                    z.len()
                ),
            ));
        }
        if let Some(i) = z.iter().position(|x| !x.is_finite()) {
            return Err(CompareError::problem(
                &self.name,
                format!("{what} has a non-finite component z[{i}] = {}", z[i]),
            ));
        }
        Ok(())
    }

    /// Rename the instance (the `problem` column and the titles).
    pub fn named(mut self, name: impl Into<String>, description: impl Into<String>) -> Self {
        self.name = name.into();
        self.description = description.into();
        self
    }

    /// `|E(z) − E₀| / |E₀|` (relative to the smallest positive f64 when
    /// `E₀ = 0`).
    pub fn energy_error(&self, z: &[f64]) -> f64 {
        (self.sys.energy(z) - self.e0).abs() / self.e0.abs().max(f64::MIN_POSITIVE)
    }

    /// `‖z − z_ref‖₂ / ‖z_ref‖₂` at `t_end`; NaN without a reference.
    pub fn error(&self, z: &[f64]) -> f64 {
        if self.reference.len() != z.len() {
            return f64::NAN;
        }
        let d: f64 = z
            .iter()
            .zip(&self.reference)
            .map(|(a, b)| (a - b) * (a - b))
            .sum();
        let r: f64 = self.reference.iter().map(|b| b * b).sum();
        (d / r.max(f64::MIN_POSITIVE)).sqrt()
    }
}

/// The kind of a method, for plots split by family.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    ExplicitRk,
    Splitting,
    Implicit,
    Peer,
    /// REBOUND's integrators (`rebound:NAME`), run through its Python package.
    Rebound,
}

impl Family {
    pub fn name(self) -> &'static str {
        match self {
            Family::ExplicitRk => "explicit-rk",
            Family::Splitting => "splitting",
            Family::Implicit => "implicit",
            Family::Peer => "peer",
            Family::Rebound => "rebound",
        }
    }
    /// The family [`name`](Self::name) names.
    pub fn from_name(name: &str) -> Option<Family> {
        [
            Family::ExplicitRk,
            Family::Splitting,
            Family::Implicit,
            Family::Peer,
            Family::Rebound,
        ]
        .into_iter()
        .find(|f| f.name() == name)
    }
}
