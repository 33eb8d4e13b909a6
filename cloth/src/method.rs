//! Every method that steps cloth, with its facts: the one place that knows
//! what an id is.
//!
//! A [`Method`] is parsed once from its id ([`Method::parse`]) and says how
//! it steps ([`Mechanism`]), its order, whether it is symplectic or
//! symmetric, and what it conserves. The library's schemes come from the
//! library's one scheme list (`integrator_core::for_each_scheme!`: one list
//! of `id => type` per kind), so a table added there steps cloth with no
//! edit here; the two energy-conserving comparison schemes, which have no
//! table, are added here.
//!
//! ```
//! use cloth::{Mechanism, Method};
//!
//! let gauss2 = Method::parse("gauss2")?;
//! assert_eq!(gauss2.mechanism(), Mechanism::StageSolver);
//! assert_eq!((gauss2.order(), gauss2.symplectic()), (4, true));
//! let avf = Method::parse("avf")?;
//! assert_eq!((avf.kind(), avf.mechanism().describe()), ("implicit", "energy minimisation"));
//! assert_eq!(avf.order(), 2);
//! assert!(Method::parse("verlet").unwrap_err().to_string().contains("stormer-verlet"));
//! # Ok::<(), cloth::MethodError>(())
//! ```
//!
//! Running a method's scheme type is the steppers' business
//! ([`crate::step::dispatch`]); this module knows only the facts.

use integrator_core::library::*;
use integrator_core::{Info, Scheme};

/// How a method steps cloth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mechanism {
    /// An explicit scheme's own step, specialised to its table.
    Explicit,
    /// An implicit Runge–Kutta table or pair through the sparse stage
    /// solver (simplified Newton on the model's sparse Jacobian).
    StageSolver,
    /// Successive energy minimisations (Newton or local/global).
    Minimisation(Minimised),
    /// Gonzalez's discrete gradient (Newton with a sparse LU).
    DiscreteGradient,
    /// RATTLE on the inextensible cloth's constraint manifold: simplified
    /// Newton on the multipliers with a sparse Cholesky of `G·M⁻¹·Gᵀ`
    /// ([`crate::step::rattle`]).
    Constrained,
}

impl Mechanism {
    /// In words, for a summary: "explicit step", "sparse stage solver",
    /// "energy minimisation" or "discrete gradient (Newton)".
    pub fn describe(self) -> &'static str {
        match self {
            Mechanism::Explicit => "explicit step",
            Mechanism::StageSolver => "sparse stage solver",
            Mechanism::Minimisation(_) => "energy minimisation",
            Mechanism::DiscreteGradient => "discrete gradient (Newton)",
            Mechanism::Constrained => "constraint solve: simplified Newton, sparse Cholesky",
        }
    }
}

/// What a minimisation step minimises.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Minimised {
    /// A composition of implicit midpoint steps of sizes `bᵢh`
    /// ([`Info::midpoint_weights`], decided by `butcher!` on the exact table).
    Midpoint(&'static [f64]),
    /// The average vector field step.
    AverageVectorField,
}

/// What a method conserves exactly (up to the solver's tolerance), beyond
/// what every method here conserves (the linear momentum of a cloth
/// without pins or colliders is conserved by every Runge–Kutta method).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Conserves {
    /// Nothing exactly.
    Nothing,
    /// The symplectic form: no energy drift, a bounded energy error.
    SymplecticForm,
    /// The energy.
    Energy,
    /// The energy and the angular momentum.
    EnergyMomentum,
}

impl Conserves {
    /// In words, for a summary.
    pub fn describe(self) -> &'static str {
        match self {
            Conserves::Nothing => "not symplectic",
            Conserves::SymplecticForm => "symplectic",
            Conserves::Energy => "energy-conserving, not symplectic",
            Conserves::EnergyMomentum => "energy- and momentum-conserving, not symplectic",
        }
    }
}

/// A method that steps cloth and its facts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Method {
    id: &'static str,
    name: &'static str,
    mechanism: Mechanism,
    order: usize,
    symmetric: bool,
    conserves: Conserves,
    info: Option<&'static Info>,
}

/// Why a method id was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MethodError {
    #[error("unknown method \"{0}\"; {list}", list = Method::listing())]
    Unknown(String),
    #[error("method \"{0}\" is a library scheme that does not step cloth; {list}", list = Method::listing())]
    NotSteppable(String),
    #[error(
        "method \"{0}\" is implicit: it steps cloth through its own solver (`cloth::Simulation::run`), not as an explicit scheme"
    )]
    Implicit(String),
}

/// The id of the average vector field scheme
/// ([`integrator_core::minimise::AvfStepper`], the cloth's integrals in
/// [`ClothModel::avf_force`](crate::ClothModel::avf_force)), solved as a minimisation. Conserves energy
/// and linear momentum; not symplectic.
pub const AVERAGE_VECTOR_FIELD: &str = "avf";

/// The id of Gonzalez's energy–momentum conserving discrete gradient.
pub const DISCRETE_GRADIENT: &str = "discrete-gradient";

/// The id of RATTLE, the constrained Störmer–Verlet step of the
/// inextensible cloth (`material.stretch = "inextensible"`).
pub const RATTLE: &str = "rattle";

impl Method {
    /// A library scheme, its mechanism read off its facts: explicit, a
    /// composition of midpoint steps (a minimisation), or the stage solver.
    const fn of(id: &'static str, info: &'static Info) -> Method {
        let mechanism = if info.explicit {
            Mechanism::Explicit
        } else if let Some(w) = info.midpoint_weights {
            Mechanism::Minimisation(Minimised::Midpoint(w))
        } else {
            Mechanism::StageSolver
        };
        let symplectic = info.symplectic || info.symplectic_separable;
        Method {
            id,
            name: info.name,
            mechanism,
            order: info.order,
            symmetric: info.symmetric,
            conserves: if symplectic {
                Conserves::SymplecticForm
            } else {
                Conserves::Nothing
            },
            info: Some(info),
        }
    }

    /// The average vector field scheme ([`AVERAGE_VECTOR_FIELD`]): implicit,
    /// symmetric, second order, energy-conserving.
    pub const AVF: Method = Method {
        id: AVERAGE_VECTOR_FIELD,
        name: "Average vector field (discrete gradient as minimisation), energy-conserving",
        mechanism: Mechanism::Minimisation(Minimised::AverageVectorField),
        order: 2,
        symmetric: true,
        conserves: Conserves::Energy,
        info: None,
    };

    /// Gonzalez's discrete gradient ([`DISCRETE_GRADIENT`]): implicit,
    /// symmetric, second order, conserves energy and angular momentum.
    pub const GONZALEZ: Method = Method {
        id: DISCRETE_GRADIENT,
        name: "Discrete gradient (Gonzalez 1996), energy-momentum",
        mechanism: Mechanism::DiscreteGradient,
        order: 2,
        symmetric: true,
        conserves: Conserves::EnergyMomentum,
        info: None,
    };

    /// RATTLE ([`RATTLE`]): the Lobatto IIIA–IIIB pair with two stages
    /// (Störmer–Verlet) applied to the constrained Hamiltonian system of the
    /// inextensible cloth. Implicit in the multipliers (a constraint solve
    /// per step); symplectic on the constraint manifold, symmetric
    /// (time-reversible), order 2 (Leimkuhler & Skeel 1994; Jay 1996).
    /// Steps only inextensible scenes, which only it steps.
    pub const RATTLE: Method = Method {
        id: RATTLE,
        name: "RATTLE (constrained Störmer–Verlet, Lobatto IIIA–IIIB s = 2)",
        mechanism: Mechanism::Constrained,
        order: 2,
        symmetric: true,
        conserves: Conserves::SymplecticForm,
        info: None,
    };

    /// Every method that steps cloth: the library's explicit schemes, its
    /// implicit tables and pairs, then [`Method::AVF`], [`Method::GONZALEZ`]
    /// and [`Method::RATTLE`].
    pub fn all() -> &'static [Method] {
        ALL
    }

    /// The method named `id` (a catalogue id as `symlab list` prints it,
    /// `avf`, `discrete-gradient` or `rattle`).
    pub fn parse(id: &str) -> Result<Method, MethodError> {
        let id = id.trim();
        match ALL.iter().find(|m| m.id == id) {
            Some(m) => Ok(*m),
            None if integrator_core::library::info(id).is_some() => {
                Err(MethodError::NotSteppable(id.to_string()))
            }
            None => Err(MethodError::Unknown(id.to_string())),
        }
    }

    /// The ids of the methods of one mechanism, in [`Method::all`]'s order.
    pub fn ids(pick: impl Fn(&Method) -> bool) -> Vec<&'static str> {
        ALL.iter().filter(|m| pick(m)).map(|m| m.id).collect()
    }

    /// "explicit: …; implicit (stage solver): …; …", for error messages.
    pub fn listing() -> String {
        let group = |m: &Method| match m.mechanism {
            Mechanism::Explicit => 0,
            Mechanism::StageSolver => 1,
            Mechanism::Minimisation(Minimised::Midpoint(_)) => 2,
            Mechanism::Constrained => 4,
            _ => 3,
        };
        let names = [
            "explicit",
            "implicit (sparse Newton stage solver)",
            "midpoint family (energy minimisation)",
            "energy-conserving",
            "constrained (inextensible scenes)",
        ];
        names
            .iter()
            .enumerate()
            .map(|(k, name)| format!("{name}: {}", Method::ids(|m| group(m) == k).join(", ")))
            .collect::<Vec<_>>()
            .join("; ")
    }

    /// The id (as `symlab list` prints it).
    pub fn id(&self) -> &'static str {
        self.id
    }
    /// The scheme's name.
    pub fn name(&self) -> &'static str {
        self.name
    }
    pub fn mechanism(&self) -> Mechanism {
        self.mechanism
    }
    /// The classical order.
    pub fn order(&self) -> usize {
        self.order
    }
    /// Symplectic (for separable Hamiltonians at least, which a cloth is).
    pub fn symplectic(&self) -> bool {
        self.conserves == Conserves::SymplecticForm
    }
    pub fn symmetric(&self) -> bool {
        self.symmetric
    }
    pub fn conserves(&self) -> Conserves {
        self.conserves
    }
    /// Explicit: no solver.
    pub fn explicit(&self) -> bool {
        self.mechanism == Mechanism::Explicit
    }
    /// The library's facts of the scheme (`None` for `avf`,
    /// `discrete-gradient` and `rattle`, which have no table of their own
    /// in the library's scheme list).
    pub fn info(&self) -> Option<&'static Info> {
        self.info
    }
    /// Solved by minimisation or the discrete gradient's Newton: the
    /// methods that `--solver` and [`MinimiseSettings`](crate::MinimiseSettings)
    /// concern.
    pub fn minimises(&self) -> bool {
        matches!(
            self.mechanism,
            Mechanism::Minimisation(_) | Mechanism::DiscreteGradient
        )
    }
    /// The composition weights of a midpoint-family method.
    pub fn midpoint_weights(&self) -> Option<&'static [f64]> {
        match self.mechanism {
            Mechanism::Minimisation(Minimised::Midpoint(w)) => Some(w),
            _ => None,
        }
    }
    /// "explicit" or "implicit" ([`Mechanism::describe`] says how).
    pub fn kind(&self) -> &'static str {
        if self.explicit() {
            "explicit"
        } else {
            "implicit"
        }
    }
    /// The same table through the sparse stage solver instead of the
    /// minimisation (a midpoint-family method; for comparisons). Other
    /// methods are returned unchanged, except the energy schemes, which
    /// have no table and are refused.
    pub fn through_stage_solver(self) -> Result<Method, MethodError> {
        match self.mechanism {
            Mechanism::Minimisation(Minimised::Midpoint(_)) => Ok(Method {
                mechanism: Mechanism::StageSolver,
                ..self
            }),
            Mechanism::Minimisation(_) | Mechanism::DiscreteGradient | Mechanism::Constrained => {
                Err(MethodError::NotSteppable(self.id.to_string()))
            }
            _ => Ok(self),
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.id)
    }
}

impl std::str::FromStr for Method {
    type Err = MethodError;
    fn from_str(s: &str) -> Result<Method, MethodError> {
        Method::parse(s)
    }
}

/// Generates [`Method::all`]'s list from the library's scheme list
/// (`integrator_core::for_each_scheme!`, the one place that lists them). The dispatch of a method to its
/// scheme type is generated from the same lists in
/// [`crate::step::dispatch`].
macro_rules! cloth_facts {
    (
        explicit_rk: [$($e_id:literal => $e_ty:ident),* $(,)?],
        implicit_rk: [$($i_id:literal => $i_ty:ident),* $(,)?],
        explicit_pairs: [$($x_id:literal => $x_ty:ident),* $(,)?],
        splittings: [$($s_id:literal => $s_ty:ident),* $(,)?],
        implicit_pairs: [$($p_id:literal => $p_ty:ident),* $(,)?] $(,)?
    ) => {
        /// Every method: the separable (symplectic) explicit schemes first,
        /// then the explicit Runge–Kutta tables, the implicit tables and
        /// pairs, and the two energy schemes.
        static ALL: &[Method] = &[
            $(Method::of($x_id, &<$x_ty as Scheme>::INFO),)*
            $(Method::of($s_id, &<$s_ty as Scheme>::INFO),)*
            $(Method::of($e_id, &<$e_ty as Scheme>::INFO),)*
            $(Method::of($i_id, &<$i_ty as Scheme>::INFO),)*
            $(Method::of($p_id, &<$p_ty as Scheme>::INFO),)*
            Method::AVF,
            Method::GONZALEZ,
            Method::RATTLE,
        ];
    };
}

integrator_core::for_each_scheme!(cloth_facts);
