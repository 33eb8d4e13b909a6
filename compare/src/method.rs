//! The methods of a comparison: fixed-step schemes behind a [`Stepper`],
//! the adaptive peer DOP853, and REBOUND's integrators (`rebound:NAME`).
//!
//! A scheme enters by value ([`Method::scheme`]: any `butcher!` type, the
//! user's or the library's), by id ([`Method::by_id`]: `symlab list`'s ids,
//! a problem's own methods, `dop853`), from a table file
//! ([`Method::table_file`], stepped by the run-time interpreters), or as any
//! [`Stepper`] ([`Method::stepper`]).

use integrator_core::library::info;
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

    /// A library scheme by id (`symlab list`), if it can step `P`.
    pub fn library(id: &str) -> Option<Self> {
        let stepper = <P::Kind as Kind<P>>::library(id)?;
        let i = info(id)?;
        Some(Method::Fixed(Fixed {
            id: id.to_string(),
            order: i.order,
            symplectic: symplectic_for::<P>(i.symplectic, i.symplectic_separable),
            family: family_of(i),
            interpreted: false,
            stepper,
        }))
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

    /// The method `id` for `sys`: the problem's own methods first, then the
    /// scheme library, then `dop853` and `rebound:NAME`. The error says why
    /// not: an unknown id (listing the valid ones), a scheme that cannot step
    /// this kind of system, a propagator off the linear problem, a REBOUND
    /// method on a problem that is not point masses.
    pub fn by_id(id: &str, sys: &P) -> Result<Self> {
        Self::by_id_named(id, sys, &sys.name())
    }

    /// [`by_id`](Method::by_id) with the problem called `problem` in the
    /// errors: a [`Setup`](crate::Setup)'s name, which for a user's problem
    /// file is the file's, not the type's (every linear system is a
    /// `LinearHamiltonian`, whose own name is `gyroscopic`).
    pub fn by_id_named(id: &str, sys: &P, problem: &str) -> Result<Self> {
        if let Some(m) = sys.special_method(id) {
            return m;
        }
        if let Some(m) = Self::library(id) {
            return Ok(m);
        }
        if let Some(base) = id.strip_prefix("logh:") {
            return Self::logh_named(base, problem);
        }
        for (prefix, controller) in crate::adaptive::PREFIXES {
            if let Some(base) = id.strip_prefix(prefix) {
                return crate::adaptive::method(prefix, controller, base, sys, problem);
            }
        }
        if id == "dop853" {
            return Self::dop853();
        }
        if id.starts_with("rebound:") {
            return crate::rebound::method(id, sys, problem).map(Method::Rebound);
        }
        if id.ends_with("-propagator") && crate::library::is_propagator(id) {
            return Err(CompareError::method(
                id,
                format!(
                    "method '{id}' is the exact one-step map of a Gauss table on a linear system z' = Hz + u; \
                     it applies to the linear (gyroscopic) problems only, not to {problem}"
                ),
            ));
        }
        if let Some(i) = info(id) {
            // In the library but not for this kind of system.
            let why = if i.form == "prk" && !i.explicit {
                "it is an implicit partitioned pair, which steps Hamiltonian systems H(q, p) given by their gradients"
            } else {
                "it is symplectic only for separable Hamiltonians H = T(p) + V(q) and steps only systems that implement `Separable`"
            };
            return Err(CompareError::method(
                id,
                format!(
                    "method '{id}' ({}) cannot step the {problem} problem: {why}; this problem is an OdeSystem only. \
                     Use a Runge–Kutta table (e.g. gauss2){}",
                    i.form,
                    if sys.special_ids().is_empty() {
                        String::new()
                    } else {
                        format!(" or one of {}", sys.special_ids().join(", "))
                    }
                ),
            ));
        }
        Err(CompareError::method(
            id,
            format!(
                "unknown method '{id}'; valid methods for {problem}: {}{}",
                Self::ids(sys).join(", "),
                if sys.rebound_bodies(&sys.start()).is_some() {
                    "; and REBOUND's through Python, rebound:NAME (e.g. rebound:whfast)"
                } else {
                    ""
                }
            ),
        ))
    }

    /// `wh:BASE` on a user's N-body problem: the library splitting `BASE`
    /// stepped on the Wisdom–Holman (Jacobi) split `split` of the problem,
    /// whose state is the inertial `[x; p]` (see
    /// [`wisdom_holman`](crate::wisdom_holman)).
    pub fn wisdom_holman(
        id: &str,
        split: &integrator_core::problems::wisdom_holman::Jacobi,
    ) -> Result<Self> {
        crate::wisdom_holman::method(id, split)
    }

    /// `logh:BASE`: the explicit separable library scheme `BASE` on the
    /// logarithmic Hamiltonian of the problem (see
    /// [`time_transformed`](crate::time_transformed)).
    pub fn logh(base: &str, sys: &P) -> Result<Self> {
        Self::logh_named(base, &sys.name())
    }

    /// [`logh`](Method::logh) with the problem called `problem` in errors.
    fn logh_named(base: &str, problem: &str) -> Result<Self> {
        let id = format!("logh:{base}");
        if let Some(stepper) = <P::Kind as Kind<P>>::logh(base) {
            let i = info(base).expect("library ids are in the registry");
            return Ok(Method::Fixed(Fixed {
                id,
                order: i.order,
                // Symplectic in the extended phase space (q, t; p, p₀).
                symplectic: i.symplectic_separable,
                family: Family::Splitting,
                interpreted: false,
                stepper,
            }));
        }
        let why = if !<P::Kind as Kind<P>>::SEPARABLE {
            format!(
                "method '{id}': the logarithmic Hamiltonian needs a separable H = T(p) + V(q); the {problem} problem is an OdeSystem only"
            )
        } else if let Some(i) = info(base) {
            format!(
                "method '{id}': '{base}' is {} {} scheme; logh: takes an explicit scheme for separable Hamiltonians \
                 (a drift–kick sequence, a composition or an explicit pair): {}",
                if i.explicit {
                    "an explicit"
                } else {
                    "an implicit"
                },
                i.form,
                crate::library::EXPLICIT_SEPARABLE_IDS.join(", ")
            )
        } else {
            format!(
                "method '{id}': unknown base method '{base}'; logh: takes one of {}",
                crate::library::EXPLICIT_SEPARABLE_IDS.join(", ")
            )
        };
        Err(CompareError::method(&id, why))
    }

    /// Every id [`by_id`](Method::by_id) accepts for `sys`.
    pub fn ids(sys: &P) -> Vec<String> {
        let mut v: Vec<String> = <P::Kind as Kind<P>>::library_ids()
            .into_iter()
            .map(str::to_string)
            .collect();
        v.extend(sys.special_ids());
        if cfg!(feature = "peer") {
            v.push("dop853".into());
        }
        v
    }
}
