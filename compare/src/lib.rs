//! The comparison harness as a library: any scheme on any problem.
//!
//! A *problem* is a system with an energy, a start, a reference solution
//! and default sweep settings ([`Problem`]); the library's test problems
//! implement it ([`builtin`]), and so can yours. A *method* is anything
//! that implements [`Step`](integrator_core::Step) for the problem — a
//! `butcher!` scheme declared in your crate ([`Method::scheme`]), one of
//! the library's by id ([`Method::by_id`]), a table file stepped by the
//! run-time interpreters ([`Method::table_file`]) — or the adaptive peer
//! DOP853 ([`Method::dop853`]). The experiments run any list of methods on
//! one problem:
//!
//! * [`work_precision`]: a sweep over step sizes (tolerances for the peer),
//!   every run observed on a counting wrapper of the system (error at `T`,
//!   max energy error, evaluations, stage-solver counters), then timed as
//!   the median of repeats after a warm-up, strictly one run at a time;
//!   [`WorkPrecision::write`] leaves `runs.csv`, log–log plots and
//!   `report.md`;
//! * [`long::run`]: 10⁶ steps and more, the energy error's growth exponent;
//!   [`long_variable::run`]: the same for the time-transformed and adaptive
//!   methods next to DOP853 over 10⁴ orbits of Kepler e = 0.9 at equal work;
//! * [`hard::run_case`]: the largest stable step by bisection;
//! * `rebound:NAME` methods ([`rebound`]): REBOUND's integrators (WHFast,
//!   its kernels and correctors, SABA, IAS15, …) through its Python package,
//!   one process per run, beside ours in the same sweep on the problems that
//!   are point masses (the outer solar system, Kepler);
//! * [`peer_study::run`]: our schemes (fixed-step, time-transformed,
//!   reversible adaptive) against DOP853 over 100 and 1000 Kepler orbits at
//!   e = 0.6 and 0.9.
//!
//! What a method id means (`gauss2`, `wh:ID`, `logh:ID`, `adaptive:ID`,
//! `rebound:NAME`, `dop853`, `gaussN-propagator`, table files) is decided in
//! one place, the [`registry`]: each family's prefix, ids, resolution and
//! the problems it applies to; its module docs show the one way to resolve
//! and run any id on any problem. [`plan::sweep_methods`] resolves the
//! methods of a sweep for every front end, and [`mode`] runs each mode of
//! `symlab compare` (sweep, peer study, long runs, hard cases) as one call
//! that returns data; the library prints nothing.
//!
//! The modules are arranged in rooms that import only downwards, with no
//! circle: the base ([`error`](CompareError), [`guard`], [`counting`],
//! [`format`](mod@format), [`plot`]); problems ([`Problem`], [`builtin`],
//! [`linear_file`], [`nbody`]); run loops and their data ([`stepper`],
//! [`peer`], [`row`]); methods ([`Method`], [`library`], [`adaptive`],
//! [`time_transformed`], [`processed`], [`interpreted`],
//! [`wisdom_holman`], [`rebound`], then the [`registry`] over them);
//! output ([`output`], [`report`]); studies ([`sweep`], [`work_precision`],
//! [`long`], [`long_variable`], [`hard`], [`peer_study`], [`plan`],
//! [`sweep_plan`], [`mode`], [`paper_oscillator`]).
//!
//! [`paper_oscillator`] is the oscillator experiment of the paper's
//! section 5 (six schemes against the closed form), which `symlab paper`
//! reports on.
//!
//! The reports print numbers through [`format`](mod@format), one set of formatters
//! with one marker ([`format::MISSING`]) for a value that is not there.
//!
//! ```no_run
//! use compare::{Method, SweepSettings, Problem, Setup, work_precision};
//! use integrator_core::butcher;
//! use integrator_core::problems::Kepler;
//!
//! butcher! {
//!     /// Yoshida's order-4 triple jump.
//!     pub MyTripleJump {
//!         let x = 1/(2 - cbrt(2));
//!         claims: [symplectic, symmetric, order = 4],
//!         compose: [x, 1 - 2*x, x],
//!     }
//! }
//!
//! let kepler = Kepler { e: 0.6 };
//! let setup = Setup::new(kepler.clone(), kepler.defaults().t_end)?;
//! let methods = vec![
//!     Method::scheme("my-triple-jump", MyTripleJump),
//!     Method::by_id("kahan-li8", &kepler)?,
//!     Method::dop853()?,
//! ];
//! let settings = SweepSettings::new(kepler.defaults(), setup.t_end);
//! let result = work_precision(&setup, &methods, &settings)?;
//! result.write(std::path::Path::new("out/my-comparison"))?;
//! print!("{}", result.summary());
//! # Ok::<(), compare::CompareError>(())
//! ```
//!
//! Errors are [`CompareError`] values naming the setting, the problem, the
//! method or the file; a run that diverges or whose stage solver fails at
//! step k is not an error but a row whose `status` says so. So is a run
//! whose scheme or problem — your code — panics: the panic is caught
//! ([`guard`]), the row's status is `panicked at step k: <message>`, and the
//! sweep goes on with the next run.

pub mod adaptive;
pub mod builtin;
pub mod counting;
mod error;
pub mod format;
pub mod guard;
pub mod hard;
pub mod interpreted;
pub mod library;
pub mod linear_file;
pub mod long;
pub mod long_variable;
mod method;
pub mod mode;
pub mod nbody;
pub mod output;
pub mod paper_oscillator;
pub mod peer;
pub mod peer_study;
pub mod plan;
pub mod plot;
mod problem;
pub mod processed;
pub mod rebound;
pub mod registry;
pub mod report;
pub mod row;
pub mod stepper;
pub mod sweep;
pub mod sweep_plan;
pub mod time_transformed;
pub mod versus;
pub mod wisdom_holman;
mod work_precision;

pub use counting::{AsOde, AsSeparable, Counting, Counts};
pub use error::{CompareError, Result};
pub use method::{Fixed, Method, family_of};
pub use problem::{ByKind, Counted, Defaults, Family, Kind, Problem, Setup, StackSizes};
pub use stepper::{
    FixedSizeStepper, Outcome, Status, StepStepper, Stepper, Workspace, bare_caught,
    observed_caught,
};
pub use sweep::{Quiet, Row, RowControl, SweepObserver};
pub use work_precision::{
    MAX_SWEEP_STEPS, SweepSettings, WorkPrecision, work_precision, work_precision_from,
};

/// The README's Rust examples, compiled and run as doctests so that the
/// documentation a user reads first cannot go stale. They live here, in the
/// crate that sees every other (the comparison example needs this one).
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct ReadmeDoctests;

/// The guide's chapters (`guide/src/`), each compiled and run as doctests in
/// the same way: every Rust block of the guide is a test. The cloth chapter's
/// hook is in the `cloth` crate, which this one does not depend on.
#[cfg(doctest)]
#[doc = include_str!("../../guide/src/introduction.md")]
pub struct GuideIntroduction;
#[cfg(doctest)]
#[doc = include_str!("../../guide/src/check.md")]
pub struct GuideCheck;
#[cfg(doctest)]
#[doc = include_str!("../../guide/src/butcher.md")]
pub struct GuideButcher;
#[cfg(doctest)]
#[doc = include_str!("../../guide/src/compare.md")]
pub struct GuideCompare;
#[cfg(doctest)]
#[doc = include_str!("../../guide/src/split.md")]
pub struct GuideSplit;
#[cfg(doctest)]
#[doc = include_str!("../../guide/src/python.md")]
pub struct GuidePython;
#[cfg(doctest)]
#[doc = include_str!("../../guide/src/paper.md")]
pub struct GuidePaper;
#[cfg(doctest)]
#[doc = include_str!("../../guide/src/hostile.md")]
pub struct GuideHostile;
#[cfg(doctest)]
#[doc = include_str!("../../guide/src/adding-a-scheme.md")]
pub struct GuideAddingAScheme;
#[cfg(doctest)]
#[doc = include_str!("../../guide/src/long-runs.md")]
pub struct GuideLongRuns;
