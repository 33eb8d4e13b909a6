//! What a method id means: the one place that knows every family of ids,
//! its prefix, its ids, how it resolves on a problem and on which problems
//! it applies.
//!
//! | family | ids | applies to |
//! |---|---|---|
//! | [`Library`](MethodFamily::Library) | `symlab list`'s ids (`gauss2`, `kahan-li8`, …) | every problem (Runge–Kutta tables); the others on separable problems |
//! | [`Propagator`](MethodFamily::Propagator) | `gauss1-propagator` … `gauss3-propagator` | linear problems ([`Problem::linear`]) |
//! | [`WisdomHolman`](MethodFamily::WisdomHolman) | `wh:ID` | N-body problems with a Jacobi split ([`Problem::wisdom_holman`]) |
//! | [`LogH`](MethodFamily::LogH) | `logh:ID` | separable problems with a negative potential ([`Problem::NEGATIVE_POTENTIAL`]) |
//! | [`Adaptive`](MethodFamily::Adaptive), [`AdaptiveImplicit`](MethodFamily::AdaptiveImplicit) | `adaptive:ID`, `adaptive-implicit:ID` | separable problems with a step density ([`Problem::STEP_DENSITY`]) |
//! | [`Dop853`](MethodFamily::Dop853) | `dop853` | every problem (with the `peer` feature) |
//! | [`Rebound`](MethodFamily::Rebound) | `rebound:NAME[:KEY=VALUE…]` | point masses ([`Problem::rebound_bodies`]) |
//! | [`Interpreted`](MethodFamily::Interpreted) | `interp:ID`: a catalogue table of the library stepped by the run-time interpreter | as its form allows |
//! | [`Table`](MethodFamily::Table) | a table file or a verified table: its id is the file's stem | as its form allows |
//!
//! [`MethodFamily::of`] answers "what is this id"; [`resolve`] (behind
//! [`Method::by_id`] and [`Setup::method`]) makes the method of an id on a
//! problem, or says why not; [`ids`] lists the ids a problem's default
//! sweep runs; [`sweep_methods`](crate::plan::sweep_methods) resolves the
//! methods of a sweep for every front end.
//!
//! The one way to resolve and run any method id on any problem:
//!
//! ```
//! use compare::builtin::Builtin;
//! use compare::plan::{OnSetup, with_setup};
//! use compare::registry::MethodFamily;
//! use compare::{Method, Problem, Setup};
//!
//! /// Resolve `id` on the problem and step it 10⁴ times; the error if the
//! /// id does not apply.
//! struct Run<'a>(&'a str);
//! impl OnSetup for Run<'_> {
//!     type Output = Result<f64, String>;
//!     fn run<P: Problem>(self, setup: Setup<P>) -> Self::Output {
//!         let method = setup.method(self.0).map_err(|e| e.to_string())?;
//!         let Method::Fixed(f) = method else {
//!             return Err(format!("{} chooses its own steps", self.0));
//!         };
//!         let n = 10_000;
//!         let h = setup.t_end / n as f64;
//!         let mut z = setup.z0.clone();
//!         let run = compare::observed_caught(&*f.stepper, &setup.sys, &mut z, h, n, true, &mut |_, _, _| true);
//!         assert!(run.status.is_ok(), "{}", run.status.label());
//!         Ok(setup.error(&z))
//!     }
//! }
//!
//! // What an id is, before any problem:
//! assert_eq!(MethodFamily::of("wh:kahan-li8"), Some(MethodFamily::WisdomHolman));
//! assert_eq!(MethodFamily::of("gauss2"), Some(MethodFamily::Library));
//! assert_eq!(MethodFamily::of("nope"), None);
//!
//! // Gauss–Legendre 2 on Kepler e = 0.6 (10 orbits): a small error.
//! let error = with_setup(Builtin::Kepler, Builtin::Kepler.defaults().t_end, true, Run("gauss2"))?
//!     .expect("gauss2 steps kepler");
//! assert!(error < 1e-4, "{error}");
//! // Wisdom–Holman on the outer solar system, which has a Jacobi split.
//! assert!(with_setup(Builtin::OuterSolar, 1e4, true, Run("wh:kahan-li8"))?.is_ok());
//! // ... but not on Kepler, and a splitting cannot step the linear system:
//! // the errors say why and list what applies.
//! let e = with_setup(Builtin::Kepler, 10.0, false, Run("wh:kahan-li8"))?.unwrap_err();
//! assert!(e.starts_with("unknown method 'wh:kahan-li8'; valid methods for kepler: "), "{e}");
//! let e = with_setup(Builtin::Gyroscopic, 1.0, false, Run("leapfrog"))?.unwrap_err();
//! assert!(e.contains("cannot step the gyroscopic problem"), "{e}");
//! # Ok::<(), compare::CompareError>(())
//! ```

use integrator_core::library::info;

use crate::error::{CompareError, Result};
use crate::interpreted::VerifiedTable;
use crate::method::{Fixed, Method};
use crate::problem::{Family, Kind, Problem, Setup};
use crate::stepper::PropagatorStepper;
use crate::{adaptive, library, rebound, wisdom_holman};

/// A family of method ids.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MethodFamily {
    /// The scheme library (`symlab list`): `butcher!` types by id.
    Library,
    /// The exact one-step maps of the Gauss tables on a linear system.
    Propagator,
    /// `wh:ID`: a splitting or processed method on the Wisdom–Holman split.
    WisdomHolman,
    /// `logh:ID`: an explicit separable scheme on the logarithmic Hamiltonian.
    LogH,
    /// `adaptive:ID`: a symmetric scheme under the integrating reversible
    /// controller.
    Adaptive,
    /// `adaptive-implicit:ID`: under the implicit symmetric rule.
    AdaptiveImplicit,
    /// `dop853`: the adaptive peer from ode_solvers.
    Dop853,
    /// `rebound:NAME`: REBOUND's integrators through its Python package.
    Rebound,
    /// `interp:ID`: the library's catalogue table `ID`, verified as a table
    /// file is and stepped by the same run-time interpreter as table files
    /// and designs, so that a table file's wall time has a library method
    /// to compare with on equal terms (generated code and the interpreter
    /// differ in speed, not in steps: their errors and evaluations agree).
    Interpreted,
    /// A table file or a verified table, stepped by the run-time
    /// interpreters; its id is the file's stem (not an id of the registry).
    Table,
}

impl MethodFamily {
    /// Every family, in the order [`resolve`] tries them and [`ids`] lists
    /// them.
    pub const ALL: [MethodFamily; 10] = [
        MethodFamily::Library,
        MethodFamily::Propagator,
        MethodFamily::WisdomHolman,
        MethodFamily::LogH,
        MethodFamily::Adaptive,
        MethodFamily::AdaptiveImplicit,
        MethodFamily::Dop853,
        MethodFamily::Rebound,
        MethodFamily::Interpreted,
        MethodFamily::Table,
    ];

    /// The prefix of the family's ids, for the families that have one.
    pub fn prefix(self) -> Option<&'static str> {
        match self {
            MethodFamily::WisdomHolman => Some(wisdom_holman::PREFIX),
            MethodFamily::LogH => Some(LOGH),
            MethodFamily::Adaptive => Some(adaptive::PREFIXES[0].0),
            MethodFamily::AdaptiveImplicit => Some(adaptive::PREFIXES[1].0),
            MethodFamily::Rebound => Some(REBOUND),
            MethodFamily::Interpreted => Some(INTERP),
            _ => None,
        }
    }

    /// The family's ids as a pattern, for listings and help.
    pub fn pattern(self) -> &'static str {
        match self {
            MethodFamily::Library => "ID",
            MethodFamily::Propagator => "gaussN-propagator",
            MethodFamily::WisdomHolman => "wh:ID",
            MethodFamily::LogH => "logh:ID",
            MethodFamily::Adaptive => "adaptive:ID",
            MethodFamily::AdaptiveImplicit => "adaptive-implicit:ID",
            MethodFamily::Dop853 => "dop853",
            MethodFamily::Rebound => "rebound:NAME[:KEY=VALUE...]",
            MethodFamily::Interpreted => "interp:ID",
            MethodFamily::Table => "FILE.toml",
        }
    }

    /// What the family is and where it applies, in a line.
    pub fn about(self) -> &'static str {
        match self {
            MethodFamily::Library => {
                "a scheme of the library (symlab list): Runge–Kutta tables on every problem, the others on separable ones"
            }
            MethodFamily::Propagator => {
                "the exact one-step map of a Gauss table on a linear system z' = Hz + u"
            }
            MethodFamily::WisdomHolman => {
                "a splitting or processed method on the Wisdom–Holman split of an N-body problem"
            }
            MethodFamily::LogH => {
                "an explicit separable scheme on the logarithmic Hamiltonian (separable problems with a negative potential)"
            }
            MethodFamily::Adaptive => {
                "a symmetric scheme under the integrating reversible step-size controller (problems with a step density)"
            }
            MethodFamily::AdaptiveImplicit => {
                "a symmetric scheme under the implicit symmetric step-size rule (problems with a step density)"
            }
            MethodFamily::Dop853 => "the adaptive peer DOP853 (ode_solvers), tolerances swept",
            MethodFamily::Rebound => {
                "REBOUND's integrator NAME through its Python package (problems of point masses)"
            }
            MethodFamily::Interpreted => {
                "a catalogue table of the library (symlab list), stepped by the run-time interpreter as table files are, so that their times compare"
            }
            MethodFamily::Table => {
                "a table file, verified exactly, stepped by the run-time interpreter"
            }
        }
    }

    /// The family of `id`, from its form alone (no problem needed): `None`
    /// for an id that no family has. A table's id (its file's stem) is not
    /// an id of the registry.
    pub fn of(id: &str) -> Option<MethodFamily> {
        if let Some(f) = Self::ALL
            .into_iter()
            .find(|f| f.prefix().is_some_and(|p| id.starts_with(p)))
        {
            return Some(f);
        }
        if id == DOP853 {
            Some(MethodFamily::Dop853)
        } else if library::is_propagator(id) {
            Some(MethodFamily::Propagator)
        } else if info(id).is_some() {
            Some(MethodFamily::Library)
        } else {
            None
        }
    }

    /// Whether the family has methods for `sys` (some of its ids resolve).
    pub fn applies<P: Problem>(self, sys: &P) -> bool {
        let separable = <P::Kind as Kind<P>>::SEPARABLE;
        match self {
            MethodFamily::Library | MethodFamily::Interpreted | MethodFamily::Table => true,
            MethodFamily::Propagator => sys.linear().is_some(),
            MethodFamily::WisdomHolman => sys.wisdom_holman().is_some(),
            MethodFamily::LogH => separable && P::NEGATIVE_POTENTIAL,
            MethodFamily::Adaptive | MethodFamily::AdaptiveImplicit => {
                separable && P::STEP_DENSITY.is_some()
            }
            MethodFamily::Dop853 => cfg!(feature = "peer"),
            MethodFamily::Rebound => sys.rebound_bodies(&sys.start()).is_some(),
        }
    }

    /// The family's ids that a default sweep of `sys` runs (empty for the
    /// families run only when named: `logh:`, `adaptive:`, `rebound:`,
    /// `interp:`, tables).
    pub fn ids<P: Problem>(self, sys: &P) -> Vec<String> {
        if !self.applies(sys) {
            return vec![];
        }
        match self {
            MethodFamily::Library => library::ids::<P>()
                .into_iter()
                .map(str::to_string)
                .collect(),
            MethodFamily::Propagator => library::propagator_tables()
                .into_iter()
                .map(|(id, _, _)| id.to_string())
                .collect(),
            MethodFamily::WisdomHolman => wisdom_holman::ids(),
            MethodFamily::Dop853 => vec![DOP853.into()],
            _ => vec![],
        }
    }
}

/// The prefix of the time-transformed methods.
const LOGH: &str = "logh:";
/// The prefix of REBOUND's methods.
const REBOUND: &str = "rebound:";
/// The prefix of the library's tables stepped by the interpreter.
pub const INTERP: &str = "interp:";
/// The peer's id.
const DOP853: &str = "dop853";

/// Every id the default sweep of `sys` runs, family by family: the library
/// schemes that step it, its propagators or `wh:` methods where it has
/// them, and `dop853` when the `peer` feature is on.
pub fn ids<P: Problem>(sys: &P) -> Vec<String> {
    MethodFamily::ALL
        .into_iter()
        .flat_map(|f| f.ids(sys))
        .collect()
}

/// The method `id` for `sys`, called `problem` in the errors. The error
/// says why not: an unknown id (listing the valid ones), a scheme that
/// cannot step this kind of system, a propagator off the linear problem, a
/// REBOUND method on a problem that is not point masses.
pub fn resolve<P: Problem>(id: &str, sys: &P, problem: &str) -> Result<Method<P>> {
    if sys.linear().is_some()
        && let Some(m) = propagator(id)
    {
        return Ok(m);
    }
    if let Some(split) = sys.wisdom_holman()
        && id.starts_with(wisdom_holman::PREFIX)
    {
        return wisdom_holman::method(id, &split);
    }
    if let Some(m) = Method::library(id) {
        return Ok(m);
    }
    if let Some(base) = id.strip_prefix(LOGH) {
        return logh(base, problem);
    }
    for (prefix, controller) in adaptive::PREFIXES {
        if let Some(base) = id.strip_prefix(prefix) {
            return adaptive::method::<P>(prefix, controller, base, problem);
        }
    }
    if id == DOP853 {
        return Method::dop853();
    }
    if id.starts_with(REBOUND) {
        return rebound::method(id, sys, problem).map(Method::Rebound);
    }
    if let Some(base) = id.strip_prefix(INTERP) {
        return interp(base);
    }
    if library::is_propagator(id) {
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
        let own: Vec<String> = [MethodFamily::Propagator, MethodFamily::WisdomHolman]
            .into_iter()
            .flat_map(|f| f.ids(sys))
            .collect();
        return Err(CompareError::method(
            id,
            format!(
                "method '{id}' ({}) cannot step the {problem} problem: {why}; this problem is an OdeSystem only. \
                 Use a Runge–Kutta table (e.g. gauss2){}",
                i.form,
                if own.is_empty() {
                    String::new()
                } else {
                    format!(" or one of {}", own.join(", "))
                }
            ),
        ));
    }
    Err(CompareError::method(
        id,
        format!(
            "unknown method '{id}'; valid methods for {problem}: {}{}",
            ids(sys).join(", "),
            if MethodFamily::Rebound.applies(sys) {
                "; and REBOUND's through Python, rebound:NAME (e.g. rebound:whfast)"
            } else {
                ""
            }
        ),
    ))
}

/// The propagator `id` (a linear problem's), `None` for any other id.
fn propagator<P: Problem>(id: &str) -> Option<Method<P>> {
    let (pid, p, q) = library::propagator_tables()
        .into_iter()
        .find(|(pid, _, _)| *pid == id)?;
    let base = pid.trim_end_matches("-propagator");
    let i = info(base)?;
    Some(Method::Fixed(Fixed {
        id: pid.to_string(),
        order: i.order,
        symplectic: i.symplectic,
        family: Family::Implicit,
        interpreted: false,
        stepper: Box::new(PropagatorStepper { p, q }),
    }))
}

/// `interp:BASE`: the catalogue's table `BASE` verified as a table file is
/// ([`VerifiedTable::from_verdict`]: every claim decided exactly) and
/// stepped by the interpreters ([`Method::interpreted`]), as the row
/// `interp:BASE`. Whether its form steps the problem is the interpreter's
/// to say, as for a table file.
fn interp<P: Problem>(base: &str) -> Result<Method<P>> {
    let id = format!("{INTERP}{base}");
    if tableau::catalogue::find(base).is_none() {
        // The catalogue's own message lists the closest ids.
        let why = tableau::catalogue::load(base).err().map(|e| e.message);
        return Err(CompareError::method(
            &id,
            format!(
                "method '{id}': '{base}' is not a table of the library's catalogue{}",
                why.map(|w| format!("; {w}")).unwrap_or_default()
            ),
        ));
    }
    let source = tableau::verdict::Source::Builtin(base);
    let verdict = tableau::verdict::check(&source, &tableau::verdict::Options::default())?;
    let table = VerifiedTable::from_verdict(format!("builtin:{base}").into(), id.clone(), verdict)
        .map_err(|why| CompareError::method(&id, format!("method '{id}': {why}")))?;
    Method::interpreted(&table)
}

/// `logh:BASE` on problems of type `P`, called `problem` in errors.
fn logh<P: Problem>(base: &str, problem: &str) -> Result<Method<P>> {
    let id = format!("{LOGH}{base}");
    if let Some(stepper) = library::logh::<P>(base) {
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
    } else if !P::NEGATIVE_POTENTIAL && library::EXPLICIT_SEPARABLE_IDS.contains(&base) {
        format!(
            "method '{id}': the logarithmic Hamiltonian (ds = dt·(−V)) needs a potential that is negative \
             wherever the problem goes, as gravity's is; the {problem} problem does not declare one \
             (Problem::NEGATIVE_POTENTIAL)"
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
            library::EXPLICIT_SEPARABLE_IDS.join(", ")
        )
    } else {
        format!(
            "method '{id}': unknown base method '{base}'; logh: takes one of {}",
            library::EXPLICIT_SEPARABLE_IDS.join(", ")
        )
    };
    Err(CompareError::method(&id, why))
}

impl<P: Problem> Method<P> {
    /// The method `id` for `sys` ([`resolve`]): the library's schemes, the
    /// problem's propagators or `wh:` methods, `logh:`, `adaptive:`,
    /// `dop853` and `rebound:NAME`. The error says why not: an unknown id
    /// (listing the valid ones), a scheme that cannot step this kind of
    /// system, a propagator off the linear problem, a REBOUND method on a
    /// problem that is not point masses.
    pub fn by_id(id: &str, sys: &P) -> Result<Self> {
        resolve(id, sys, &sys.name())
    }

    /// [`by_id`](Method::by_id) with the problem called `problem` in the
    /// errors: a [`Setup`]'s name, which for a user's problem file is the
    /// file's, not the type's (every linear system is a
    /// `LinearHamiltonian`, whose own name is `gyroscopic`).
    pub fn by_id_named(id: &str, sys: &P, problem: &str) -> Result<Self> {
        resolve(id, sys, problem)
    }

    /// `wh:BASE` on a user's N-body problem: the library splitting `BASE`
    /// stepped on the Wisdom–Holman (Jacobi) split `split` of the problem,
    /// whose state is the inertial `[x; p]` (see
    /// [`wisdom_holman`](crate::wisdom_holman)).
    pub fn wisdom_holman(
        id: &str,
        split: &integrator_core::problems::wisdom_holman::Jacobi,
    ) -> Result<Self> {
        wisdom_holman::method(id, split)
    }

    /// `logh:BASE`: the explicit separable library scheme `BASE` on the
    /// logarithmic Hamiltonian of the problem (see
    /// [`time_transformed`](crate::time_transformed)).
    pub fn logh(base: &str, sys: &P) -> Result<Self> {
        logh(base, &sys.name())
    }

    /// Every id the default sweep of `sys` runs ([`ids`]); [`by_id`](Method::by_id)
    /// accepts these and the ids of the families run only when named.
    pub fn ids(sys: &P) -> Vec<String> {
        ids(sys)
    }
}

impl<P: Problem> Setup<P> {
    /// The method with this id for this problem ([`resolve`]). The error
    /// lists the valid ids.
    pub fn method(&self, id: &str) -> Result<Method<P>> {
        resolve(id, &self.sys, &self.name)
    }

    /// Every method id that a default sweep of this problem runs ([`ids`]:
    /// library schemes, the problem's propagators or `wh:` methods, and
    /// `dop853` when the `peer` feature is on).
    pub fn method_ids(&self) -> Vec<String> {
        ids(&self.sys)
    }
}

/// A method as a caller names it, before there is a problem to resolve it
/// on: an id of the registry, a table file, a verified table, or any
/// method built already (a `butcher!` scheme of the caller's).
pub enum MethodSpec<P> {
    Id(String),
    /// A table file, verified exactly when the methods are resolved.
    File(std::path::PathBuf),
    Table(Box<VerifiedTable>),
    /// A table file stepped on the Wisdom–Holman split of an N-body problem
    /// ([`wisdom_holman::table_method`]): the method `wh:STEM`.
    WisdomHolmanFile(std::path::PathBuf),
    Method(Method<P>),
}

impl<P: Problem> MethodSpec<P> {
    /// A table file as the command line names it: `wh:PATH` (the prefix of
    /// the Wisdom–Holman ids) for the file on the problem's Wisdom–Holman
    /// split, any other path for the file stepped by the interpreters. (A
    /// file whose name begins with `wh:` is named `./wh:…`.)
    pub fn table(path: std::path::PathBuf) -> Self {
        match path
            .to_str()
            .and_then(|s| s.strip_prefix(wisdom_holman::PREFIX))
        {
            Some(rest) => MethodSpec::WisdomHolmanFile(rest.into()),
            None => MethodSpec::File(path),
        }
    }

    /// The method on `setup`.
    pub fn resolve(self, setup: &Setup<P>) -> Result<Method<P>> {
        match self {
            MethodSpec::Id(id) => setup.method(&id),
            MethodSpec::File(path) => Method::table_file(&path),
            MethodSpec::WisdomHolmanFile(path) => {
                let Some(split) = setup.sys.wisdom_holman() else {
                    return Err(CompareError::TableFile {
                        path,
                        why: format!(
                            "{}FILE steps a table on the Wisdom–Holman split of an N-body problem; {} has none",
                            wisdom_holman::PREFIX,
                            setup.name
                        ),
                    });
                };
                wisdom_holman::table_method(&crate::interpreted::verify(&path)?, &split)
            }
            MethodSpec::Table(t) => Method::interpreted(&t),
            MethodSpec::Method(m) => Ok(m),
        }
    }
}
