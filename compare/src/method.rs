//! The methods of a comparison: fixed-step schemes behind a [`Stepper`],
//! the adaptive peer DOP853, and REBOUND's integrators (`rebound:NAME`).
//!
//! A scheme enters by value ([`Method::scheme`]: any `butcher!` type, the
//! user's or the library's), by id ([`Method::by_id`]: every id of the
//! [`registry`](crate::registry)), from a table file
//! ([`Method::table_file`], stepped by the run-time interpreters), or as any
//! [`Stepper`] ([`Method::stepper`]).

use integrator_core::{Scheme, Step};

use crate::error::{CompareError, Result};
use crate::problem::{Counted, Family, Kind, Problem};
use crate::stepper::{StepStepper, Stepper, Workspace};

/// A fixed-step method: facts for the CSV and its stepper.
pub struct Fixed<P> {
    pub id: String,
    pub order: usize,
    /// Symplectic for this problem (for separable problems: for separable
    /// Hamiltonians).
    pub symplectic: bool,
    pub family: Family,
    /// Stepped by a run-time interpreter (a table file): its errors and
    /// evaluation counts compare with generated code, its wall times do not.
    pub interpreted: bool,
    pub stepper: Box<dyn Stepper<P>>,
}

/// A method of a comparison.
pub enum Method<P> {
    Fixed(Fixed<P>),
    /// DOP853 from ode_solvers (adaptive; tolerances are swept).
    Dop853,
    /// A REBOUND integrator through its Python package
    /// ([`rebound`](crate::rebound)): step counts or tolerances are swept,
    /// one process per run.
    Rebound(crate::rebound::ReboundMethod),
}

/// The symplecticity that matters for problems of type `P`: for separable
/// Hamiltonians when `P` is one, for every Hamiltonian otherwise.
pub(crate) fn symplectic_for<P: Problem>(general: bool, separable: bool) -> bool {
    if <P::Kind as Kind<P>>::SEPARABLE {
        separable
    } else {
        general
    }
}

/// The family of a `butcher!` scheme from its facts.
pub fn family_of(info: &integrator_core::Info) -> Family {
    if !info.explicit {
        Family::Implicit
    } else if info.form == "rk" {
        Family::ExplicitRk
    } else {
        Family::Splitting
    }
}

impl<P: Problem> Method<P> {
    pub fn id(&self) -> &str {
        match self {
            Method::Fixed(f) => &f.id,
            Method::Dop853 => "dop853",
            Method::Rebound(r) => &r.id,
        }
    }

    /// Any scheme that steps the problem, under the id `id`: a `butcher!`
    /// type declared anywhere (its order and symplecticity are the verified
    /// constants of its table).
    ///
    /// ```
    /// use compare::{Method, builtin};
    /// use integrator_core::butcher;
    /// use integrator_core::problems::Kepler;
    ///
    /// butcher! {
    ///     /// The Störmer–Verlet drift–kick–drift sequence.
    ///     pub MyVerlet {
    ///         claims: [symplectic, symmetric, order = 2],
    ///         drift: [1/2, 1/2],
    ///         kick: [1],
    ///     }
    /// }
    /// let m = Method::<Kepler>::scheme("my-verlet", MyVerlet);
    /// assert_eq!(m.id(), "my-verlet");
    /// ```
    pub fn scheme<M>(id: impl Into<String>, scheme: M) -> Self
    where
        M: Scheme + Step<P> + Step<Counted<P>> + Send + Sync,
        <M as Step<P>>::Workspace: Workspace,
        <M as Step<Counted<P>>>::Workspace: Workspace,
    {
        let info = M::INFO;
        Method::Fixed(Fixed {
            id: id.into(),
            order: info.order,
            symplectic: symplectic_for::<P>(info.symplectic, info.symplectic_separable),
            family: family_of(&info),
            interpreted: false,
            stepper: Box::new(StepStepper(scheme)),
        })
    }

    /// Any stepper, with the facts the CSV reports about it.
    pub fn stepper(
        id: impl Into<String>,
        order: usize,
        symplectic: bool,
        family: Family,
        stepper: Box<dyn Stepper<P>>,
    ) -> Self {
        Method::Fixed(Fixed {
            id: id.into(),
            order,
            symplectic,
            family,
            interpreted: false,
            stepper,
        })
    }

    /// The ode_solvers peer DOP853, or why this build has none.
    pub fn dop853() -> Result<Self> {
        if cfg!(feature = "peer") {
            Ok(Method::Dop853)
        } else {
            Err(CompareError::method(
                "dop853",
                "method 'dop853' needs the `peer` feature (on by default); this build has it off",
            ))
        }
    }
}
