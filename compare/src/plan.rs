//! What a comparison runs when its caller does not say: which system a
//! built-in problem is, the default and quick method lists, the settings of
//! a quick sweep, the hard cases' search and the long runs' step counts.
//! These are the choices `symlab compare` makes for the flags it is not
//! given; they live here so that a Rust caller gets the same comparison.

use std::ops::RangeInclusive;

use crate::builtin::{self, Builtin};
use crate::error::{CompareError, Result};
use crate::long::LongSettings;
use crate::method::Method;
use crate::problem::{Defaults, Problem, Setup};
use crate::registry::MethodSpec;
use crate::sweep::PEER_TOLERANCES;

/// A computation over a problem of any type, for [`with_setup`]: a
/// built-in problem's setup is a different type for each problem, so the
/// caller's work is a generic method rather than a closure.
pub trait OnSetup {
    type Output;
    fn run<P: Problem>(self, setup: Setup<P>) -> Self::Output;
}

/// The built-in `problem` over `[0, t_end]` (with its reference solution
/// where `with_reference`), handed to `f`. The one place that says which
/// system each [`Builtin`] is; the gyroscopic problem is
/// `linear::gyroscopic(10, 1, 10.0)` (10 degrees of freedom, seed 1,
/// frequency spread 10).
pub fn with_setup<F: OnSetup>(
    problem: Builtin,
    t_end: f64,
    with_reference: bool,
    f: F,
) -> Result<F::Output> {
    let r = with_reference;
    Ok(match problem {
        Builtin::Oscillator => f.run(builtin::oscillator(t_end, r)?),
        Builtin::Pendulum => f.run(builtin::pendulum(t_end, r)?),
        Builtin::Kepler | Builtin::KeplerHard => {
            f.run(builtin::kepler(problem == Builtin::KeplerHard, t_end, r)?)
        }
        Builtin::HenonHeiles => f.run(builtin::henon_heiles(t_end, r)?),
        Builtin::Fpu => f.run(builtin::fpu(t_end, r)?),
        Builtin::OuterSolar => f.run(builtin::outer_solar(t_end, r)?),
        Builtin::Gyroscopic => f.run(builtin::gyroscopic(10, 1, 10.0, t_end, r)?),
    })
}

/// The problems on which DOP853 is compared by default: Kepler and the
/// outer solar system (elsewhere it runs when asked for).
pub fn peer_by_default(problem: Option<Builtin>) -> bool {
    matches!(
        problem,
        Some(Builtin::Kepler | Builtin::KeplerHard | Builtin::OuterSolar)
    )
}

/// The methods of a quick run on `problem`: a few references (with the
/// peer where it is compared and built).
pub fn quick_methods(problem: Builtin) -> Vec<String> {
    let ids: &[&str] = match problem {
        Builtin::Gyroscopic => &["rk4", "gauss2", "gauss2-propagator"],
        Builtin::Kepler | Builtin::KeplerHard if cfg!(feature = "peer") => {
            &["leapfrog", "forest-ruth", "rk4", "gauss2", "dop853"]
        }
        Builtin::OuterSolar if cfg!(feature = "peer") => {
            &["stormer-verlet", "kahan-li8", "logh:kahan-li8", "dop853"]
        }
        _ => &["leapfrog", "forest-ruth", "rk4", "gauss2"],
    };
    ids.iter().map(|s| s.to_string()).collect()
}

/// The references run beside table files when no method is named: the
/// quick set of a built-in problem, RK4 and Gauss–Legendre 2 on a problem
/// file — a table is compared with a few known methods, not the library.
pub fn table_references(problem: Option<Builtin>) -> Vec<String> {
    match problem {
        Some(b) => quick_methods(b),
        None => vec!["rk4".into(), "gauss2".into()],
    }
}

/// Every method that applies to `setup`; the peer only where
/// [`peer_by_default`].
pub fn default_methods<P: Problem>(setup: &Setup<P>, problem: Option<Builtin>) -> Vec<String> {
    let peer = peer_by_default(problem);
    setup
        .method_ids()
        .into_iter()
        .filter(|m| peer || m != "dop853")
        .collect()
}

/// The methods of a sweep of `setup` (the built-in problem `builtin`, if it
/// is one), as every front end resolves them: those `named` in order, else
/// the defaults — with `quick` or with methods `added`, the
/// [`table_references`]; else [`default_methods`] — then those `added` (the
/// command line's `--table` files). Two with the same id are refused
/// ([`CompareError::DuplicateMethod`], whose `index` is the second's place
/// among the named or the added).
///
/// ```
/// use compare::builtin::kepler;
/// use compare::plan::sweep_methods;
/// use compare::registry::MethodSpec;
///
/// let setup = kepler(false, 62.8, false)?;
/// let named = vec![MethodSpec::Id("gauss2".into()), MethodSpec::Id("logh:kahan-li8".into())];
/// let methods = sweep_methods(&setup, None, Some(named), vec![], false)?;
/// assert_eq!(methods.len(), 2);
/// let twice = vec![MethodSpec::Id("rk4".into()), MethodSpec::Id("rk4".into())];
/// let e = sweep_methods(&setup, None, Some(twice), vec![], false).err().unwrap();
/// assert!(e.to_string().contains("'rk4' appears twice"));
/// # Ok::<(), compare::CompareError>(())
/// ```
pub fn sweep_methods<P: Problem>(
    setup: &Setup<P>,
    builtin: Option<Builtin>,
    named: Option<Vec<MethodSpec<P>>>,
    added: Vec<MethodSpec<P>>,
    quick: bool,
) -> Result<Vec<Method<P>>> {
    let named = match named {
        Some(named) => named,
        None => {
            // With tables and no methods named: the tables beside a few
            // references (the quick set), not the whole library.
            let ids = if quick || !added.is_empty() {
                table_references(builtin)
            } else {
                default_methods(setup, builtin)
            };
            ids.into_iter().map(MethodSpec::Id).collect()
        }
    };
    let named = named.into_iter().enumerate().map(|(i, m)| (i, false, m));
    let added = added.into_iter().enumerate().map(|(i, m)| (i, true, m));
    let mut methods: Vec<Method<P>> = Vec::new();
    for (index, added, spec) in named.chain(added) {
        let m = spec.resolve(setup)?;
        if methods.iter().any(|x| x.id() == m.id()) {
            return Err(CompareError::DuplicateMethod {
                id: m.id().to_string(),
                index,
                added,
            });
        }
        methods.push(m);
    }
    Ok(methods)
}

/// The methods of the hard cases: every fixed-step method that applies
/// (DOP853 has no step size to search), or a few references when `quick`.
pub fn hard_methods<P: Problem>(setup: &Setup<P>, problem: Builtin, quick: bool) -> Vec<String> {
    if quick {
        let ids: &[&str] = match problem {
            Builtin::Gyroscopic => &["rk4", "gauss2", "gauss2-propagator"],
            _ => &["leapfrog", "rk4", "gauss2"],
        };
        return ids.iter().map(|s| s.to_string()).collect();
    }
    setup
        .method_ids()
        .into_iter()
        .filter(|m| m != "dop853")
        .collect()
}

/// The sweep settings a caller does not give: step sizes (and DOP853
/// tolerances) and timed repeats, for a full run or a quick one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SweepDefaults {
    /// Step sizes of the sweep.
    pub points: usize,
    /// Tolerances of DOP853.
    pub tolerances: usize,
    /// Timed runs per point.
    pub repeats: usize,
}

impl SweepDefaults {
    /// Ten step sizes, one DOP853 tolerance per decade, three repeats.
    pub const FULL: SweepDefaults = SweepDefaults {
        points: 10,
        tolerances: PEER_TOLERANCES,
        repeats: 3,
    };
    /// A smoke run of a few seconds: four points, one repeat.
    pub const QUICK: SweepDefaults = SweepDefaults {
        points: 4,
        tolerances: 4,
        repeats: 1,
    };

    pub fn of(quick: bool) -> SweepDefaults {
        if quick { Self::QUICK } else { Self::FULL }
    }
}

/// The smallest step of a quick sweep: 10⁴ steps over the problem's own
/// end time, so that a quick run takes seconds on every problem.
pub fn quick_h_min(defaults: Defaults) -> f64 {
    defaults.t_end / 10_000.0
}

/// The largest-stable-step search of the hard cases: the relative width
/// of the bracket at which the bisection stops, and the smallest step it
/// tries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HardSearch {
    pub tolerance: f64,
    pub floor: f64,
}

impl HardSearch {
    /// To 1 % of the step, down to 10⁻⁶.
    pub const FULL: HardSearch = HardSearch {
        tolerance: 0.01,
        floor: 1e-6,
    };
    /// To 5 %, down to 10⁻⁴.
    pub const QUICK: HardSearch = HardSearch {
        tolerance: 0.05,
        floor: 1e-4,
    };

    pub fn of(quick: bool) -> HardSearch {
        if quick { Self::QUICK } else { Self::FULL }
    }
}

/// The step counts a long run may be asked for: from 10³ (the growth fit
/// needs a few decades of windows) to 10⁷ (minutes per method).
pub const LONG_STEPS: RangeInclusive<u64> = 1000..=10_000_000;

/// The long runs' step: `h = 0.01` on every problem they cover.
pub const LONG_H: f64 = 0.01;

/// The long runs' settings: `steps` steps, by default 10⁶ (10⁴ when
/// `quick`), of [`LONG_H`].
pub fn long_settings(steps: Option<u64>, quick: bool) -> LongSettings {
    let steps = steps.unwrap_or(if quick { 10_000 } else { 1_000_000 });
    LongSettings { h: LONG_H, steps }
}

/// The outer solar system's long-run step: Jupiter's period over 20 (about
/// 216.6 days), the step of long planetary integrations.
pub const OUTER_SOLAR_LONG_H: f64 = 4332.59 / 20.0;

/// The outer solar system's long runs: `steps` steps of
/// [`OUTER_SOLAR_LONG_H`], by default 10⁷ days (about 27 000 years;
/// when `quick`, the fewest steps a long run takes, [`LONG_STEPS`]' start:
/// 1000 steps, about 2.2·10⁵ days).
pub fn outer_solar_long_settings(steps: Option<u64>, quick: bool) -> LongSettings {
    let default = if quick {
        *LONG_STEPS.start()
    } else {
        (1e7 / OUTER_SOLAR_LONG_H).ceil() as u64
    };
    let steps = steps.unwrap_or(default);
    LongSettings {
        h: OUTER_SOLAR_LONG_H,
        steps,
    }
}

/// The methods of the outer solar system's long runs when none are named:
/// Wisdom–Holman (the classical map and a near-integrable splitting) beside
/// the best plain splitting and Störmer–Verlet.
pub const OUTER_SOLAR_LONG_METHODS: &[&str] =
    &["wh:leapfrog", "wh:kahan-li8", "kahan-li8", "stormer-verlet"];
