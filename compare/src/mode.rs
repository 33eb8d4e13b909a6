//! The modes of a comparison, each one library call: the work–precision
//! sweep ([`work_precision`](crate::work_precision)), the peer study, the
//! long runs and the hard cases ([`Mode`]). A front end maps its flags to a
//! [`Mode`] and a [`ModeRequest`], calls [`peer_study_settings`],
//! [`long`](mod@long) or [`hard`](mod@hard), and prints or writes what they return; the
//! library prints nothing. Messages name the values as the command line's
//! flags (`--steps`, `--methods`), as [`sweep_plan`](crate::sweep_plan)'s do
//! by default.
//!
//! ```
//! use compare::builtin::Builtin;
//! use compare::mode::{ModeRequest, hard};
//!
//! let request = ModeRequest {
//!     problem: Some(Builtin::KeplerHard),
//!     methods: Some(vec!["leapfrog".into(), "dop853".into()]),
//!     quick: true,
//!     ..ModeRequest::default()
//! };
//! let study = hard(&request)?;
//! assert_eq!(study.rows.len(), 1); // leapfrog; dop853 has no step size
//! assert!(study.notes.iter().any(|n| n.starts_with("dop853 skipped")));
//! # Ok::<(), compare::CompareError>(())
//! ```

use std::path::{Path, PathBuf};

use crate::builtin::{self, Builtin};
use crate::error::{CompareError, Result};
use crate::format;
use crate::hard::{self, Case, HardRow};
use crate::long::{self, LongRun, LongSettings};
use crate::long_variable::{self, VariableSettings};
use crate::method::{Fixed, Method};
use crate::peer_study::PeerStudySettings;
use crate::plan::{self, HardSearch, OnSetup};
use crate::problem::{Problem, Setup};
use crate::registry::MethodSpec;
use crate::sweep::{Row, SweepObserver};
use crate::sweep_plan::{FromFile, SweepPlan, SweepRequest, sweep_plan};
use crate::work_precision::{WorkPrecision, work_precision_from};

/// What each mode writes and the columns of `runs.csv`, for the command
/// line's `--help` (`symlab compare --help` prints it after the flags).
pub const HELP: &str = "\
runs.csv columns (one row per run):
  problem            problem id
  method             scheme id (symlab list), gaussN-propagator, dop853, or rebound:NAME
  order              classical order (8 for dop853)
  symplectic         symplectic for this problem (separable problems: for separable H)
  h                  step size (dop853, logh:ID, adaptive:ID: the average step T/steps)
  tol                rtol = atol of dop853 (NaN for fixed-step methods)
  steps              steps taken (dop853: accepted steps)
  error              ‖z(T) − z_ref(T)‖₂/‖z_ref(T)‖₂ (NaN unless status is ok)
  energy_error       max |E − E0|/|E0| over the steps taken
  time_s             median wall time of the timed runs in seconds (NaN unless ok)
  evals              force evaluations (separable problems; wh:ID: interaction kicks), right-hand sides
                     (gyroscopic; a propagator step counts one matrix-vector product),
                     or dop853's own count
  newton_iterations  Newton iterations of the implicit stage solver (0 if explicit)
  fixed_point_iterations
                     fixed-point iterations of the stage solver (its choice when the
                     system has no Jacobian, as the separable problems)
  factorizations     LU factorisations of the stage solver
  status             ok | diverged at step k | solver failed at step k: why |
                     panicked at step k: message (a scheme or problem of your own,
                     through the library; the sweep goes on)

A sweep also writes report.md: the problem, T and the settings; the summary table; the wall
time of each method to reach --target (default 1e-8), fastest first, with steps and
evaluations; the methods that did not reach it and why (smallest error and where); and,
when dop853 ran, our fastest method against it at each decade 1e-2 ... 1e-12.

--peer-study (Kepler e = 0.6 and e = 0.9; --problem kepler or kepler-hard for one) runs
logh:sofroniou-spaletta10, logh:kahan-li8, logh:mclachlan8, adaptive:sofroniou-spaletta10,
adaptive:kahan-li8, sofroniou-spaletta10, kahan-li8, gauss8 and dop853 at 100 and 1000 orbits
(--quick: 1 and 10 orbits, kahan-li8, logh:kahan-li8, adaptive:kahan-li8, dop853) and writes
peer.csv (the runs.csv columns, then t_end; problem kepler or kepler-hard) and peer.md (per
eccentricity, run length and target 1e-6, 1e-8, 1e-10: our fastest method against dop853,
times, ratio, energy errors).

--long writes long.csv (problem,method,order,symplectic,compensated,h,step,t,energy_error),
long_fit.csv and long_energy.svg; on kepler-hard it runs logh:kahan-li8, adaptive:kahan-li8
and dop853 over 10⁴ orbits (--quick: 100) at equal work (about 4000 force evaluations per
orbit each; dop853 at the tolerance nearest to that, in calls of 100 orbits), h being the
mean step; on outer-solar it runs the --methods named (default wh:leapfrog, wh:kahan-li8,
kahan-li8, stormer-verlet) at h = Jupiter's period / 20 over 10⁷ days (--quick: 1000 steps);
--hard writes hard.csv and hard.md.

rebound:NAME[:KEY=VALUE...] in --methods (outer-solar, kepler, kepler-hard) runs REBOUND's
integrator NAME through its Python package (not a dependency: `pip install rebound==5.2.2`;
$SYMLAB_PYTHON names the interpreter, default python3), one process per run, from the same
initial state; its rows are rebound:..., errors measured against the same reference, time that
of sim.integrate. NAME: whfast (corrector=0|3|5|7|11|17, kernel=, coordinates=), whckl, whckm,
whckc, whfast512 (AVX-512), saba1-4, sabacm1-4, sabacl1-4, saba-10-4, saba-8-6-4, saba-10-6-4,
sabah-8-4-4, sabah-8-6-4, sabah-10-6-4, leapfrog (order=2|4|6|8), mercurius, ias15 and bs
(tolerances swept). Without Python or rebound they are left out and the run says how to
install it.

--table FILE.toml (repeatable) adds a table file: its claims are verified exactly (a false
claim or a malformed file: exit 2), then it is stepped by the run-time interpreter; its
rows carry one more column, interpreted = true (errors and evaluations compare with
generated code, wall times do not). --table wh:FILE.toml steps the file (a drift–kick
sequence or composition, with its corrector if it has one) on the Wisdom–Holman split
(outer-solar) as the row wh:STEM, as the wh: methods are stepped, so its times compare with
theirs and it is not marked interpreted. --problem-file FILE.toml runs a linear system
M q'' + G q' + K q = f read from a file (m, g, k, f, q0, p0, t_end, h_min, h_max) against
its exact flow; errors name the file and the field.

--from CSV reads a runs.csv back (fields quoted as RFC 4180 says); a row with a negative
h, error, energy_error or time_s, or a non-finite one where status is ok, is refused
naming its line and column.

Exit status: 0 done, 2 bad input (the message names the flag, file or field); a closed
pipe (symlab compare ... | head) ends the process by SIGPIPE (status 141 in a shell).";

/// What a comparison runs: the mode of `symlab compare`'s flags.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// A work–precision sweep of one problem (`--problem`, `--problem-file`).
    Sweep,
    /// Our schemes against DOP853 over long Kepler runs (`--peer-study`).
    PeerStudy,
    /// The energy error over 10⁶ steps and more (`--long`).
    Long,
    /// The largest stable step of each method (`--hard`).
    Hard,
}

impl Mode {
    /// The mode the command line's flags select (none of them: a sweep).
    pub fn of_flags(peer_study: bool, hard: bool, long: bool) -> Mode {
        if peer_study {
            Mode::PeerStudy
        } else if hard {
            Mode::Hard
        } else if long {
            Mode::Long
        } else {
            Mode::Sweep
        }
    }
}

/// What a caller asks of the peer study, the long runs or the hard cases;
/// `None` takes the mode's default.
#[derive(Clone, Debug, Default)]
pub struct ModeRequest {
    pub problem: Option<Builtin>,
    /// Method ids, each once.
    pub methods: Option<Vec<String>>,
    /// Steps of the long runs.
    pub steps: Option<u64>,
    /// Timed runs per point of the peer study.
    pub repeats: Option<usize>,
    /// A target error the peer study adds to its own.
    pub target: Option<f64>,
    /// A smoke run of a few seconds.
    pub quick: bool,
    /// The first value of the work–precision sweep the caller gave, as it
    /// names it (`--t-end`, `--h-min`, `--h-max`, `--points`): these modes
    /// refuse it.
    pub sweep_value: Option<String>,
}

/// An error naming the value `name`.
fn given(name: &str, why: String) -> CompareError {
    CompareError::Given {
        names: vec![name.to_string()],
        why,
    }
}

/// The peer study's settings for `request`: e = 0.6 and 0.9 (or the one
/// `problem` names), its methods (`dop853` kept), its repeats and targets.
pub fn peer_study_settings(request: &ModeRequest) -> Result<PeerStudySettings> {
    if let Some(p) = request.problem
        && !matches!(p, Builtin::Kepler | Builtin::KeplerHard)
    {
        return Err(given(
            "--problem",
            format!(
                "--peer-study runs on kepler (e = 0.6) and kepler-hard (e = 0.9) only, not on {}",
                p.name()
            ),
        ));
    }
    let steps = request.steps.map(|_| "--steps".to_string());
    if let Some(name) = request.sweep_value.clone().or(steps) {
        return Err(given(
            &name,
            format!(
                "{name} does not apply to --peer-study: it runs 100 and 1000 orbits with step ranges of its own"
            ),
        ));
    }
    let mut settings = if request.quick {
        PeerStudySettings::quick()
    } else {
        PeerStudySettings::full()
    };
    match request.problem {
        Some(Builtin::Kepler) => settings.eccentricities = vec![0.6],
        Some(Builtin::KeplerHard) => settings.eccentricities = vec![0.9],
        _ => {}
    }
    if let Some(r) = request.repeats {
        if r > 100 {
            return Err(given(
                "--repeats",
                format!("--repeats must be at most 100, got {r}"),
            ));
        }
        settings.repeats = r;
    }
    if let Some(ids) = &request.methods {
        if !ids.iter().any(|m| m == "dop853") {
            return Err(given(
                "--methods",
                "--peer-study compares against dop853: keep it in --methods".into(),
            ));
        }
        settings.methods = ids.clone();
    }
    if let Some(t) = request.target {
        settings = settings.with_target(t);
        settings.energy_target = t;
    }
    Ok(settings)
}

/// What the long runs return: the runs, the line that says what ran, and
/// the default directory of their files.
pub struct LongStudy {
    pub title: String,
    pub runs: Vec<LongRun>,
    /// The directory name under `out/compare/` by default.
    pub dir: String,
}

impl LongStudy {
    /// The energy errors' growth, one line per run ([`long::summary`]).
    pub fn summary(&self) -> String {
        long::summary(&self.runs)
    }

    /// Write `long.csv`, `long_fit.csv` and `long_energy.svg` into `dir`;
    /// their paths.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        long::write(dir, &self.runs)?;
        Ok(["long.csv", "long_fit.csv", "long_energy.svg"]
            .into_iter()
            .map(|f| dir.join(f))
            .collect())
    }
}

/// The long runs of `request.problem`: on kepler-hard, logh:kahan-li8,
/// adaptive:kahan-li8 and DOP853 over 10⁴ orbits (quick: 100) at equal
/// work ([`long_variable`]); on outer-solar, the methods named (default
/// [`plan::OUTER_SOLAR_LONG_METHODS`]) at Jupiter's period / 20; on kepler,
/// oscillator and henon-heiles, the symplectic/non-symplectic pairs of
/// [`long::PAIRS`] over 10⁶ steps (quick: 10⁴).
pub fn long(request: &ModeRequest) -> Result<LongStudy> {
    let Some(problem) = request.problem else {
        return Err(given(
            "--problem",
            "--long needs --problem kepler, kepler-hard, oscillator, henon-heiles or outer-solar"
                .into(),
        ));
    };
    if problem == Builtin::KeplerHard {
        return long_variable(request);
    }
    if problem == Builtin::OuterSolar {
        return long_outer_solar(request);
    }
    if request.methods.is_some() {
        return Err(given(
            "--methods",
            "--long compares fixed pairs (leapfrog/heun, forest-ruth/rk4, gauss2/rk4); --methods does not apply".into(),
        ));
    }
    refuse_sweep_value(request)?;
    let settings = plan::long_settings(request.steps, request.quick);
    let n = long_steps(settings)?;
    let t = n as f64 * settings.h;
    if !matches!(
        problem,
        Builtin::Kepler | Builtin::Oscillator | Builtin::HenonHeiles
    ) {
        return Err(given(
            "--problem",
            format!(
                "--long runs on kepler, kepler-hard, oscillator or henon-heiles (and on outer-solar, with the methods named), not on {}",
                problem.name()
            ),
        ));
    }
    /// The symplectic/non-symplectic pairs on one problem, whatever its type.
    struct Pairs(LongSettings);
    impl OnSetup for Pairs {
        type Output = Result<Vec<LongRun>>;
        fn run<P: Problem>(self, setup: Setup<P>) -> Self::Output {
            let methods = long::pair_methods(&setup.sys)?;
            long::run(&setup, &methods, self.0)
        }
    }
    let runs = plan::with_setup(problem, t, false, Pairs(settings))??;
    Ok(LongStudy {
        title: format!(
            "{}: {n} steps of h = {} (T = {t})",
            problem.description(),
            settings.h
        ),
        runs,
        dir: problem.name().to_string(),
    })
}

/// A sweep's value given to the long runs: refused.
fn refuse_sweep_value(request: &ModeRequest) -> Result<()> {
    match &request.sweep_value {
        Some(name) => Err(given(
            name,
            format!("{name} belongs to the work-precision sweep, not to --long (use --steps)"),
        )),
        None => Ok(()),
    }
}

/// The steps of long runs if [`plan::LONG_STEPS`] holds them.
fn long_steps(settings: LongSettings) -> Result<u64> {
    let n = settings.steps;
    if !plan::LONG_STEPS.contains(&n) {
        return Err(given(
            "--steps",
            format!(
                "--steps must be between {} and 10^7, got {n}",
                plan::LONG_STEPS.start()
            ),
        ));
    }
    Ok(n)
}

/// `--long --problem kepler-hard`: logh:kahan-li8, adaptive:kahan-li8 and
/// DOP853 over 10⁴ orbits (quick: 100) at equal evaluations per orbit.
fn long_variable(request: &ModeRequest) -> Result<LongStudy> {
    if request.methods.is_some() {
        return Err(given(
            "--methods",
            "--long on kepler-hard compares logh:kahan-li8, adaptive:kahan-li8 and dop853; --methods does not apply".into(),
        ));
    }
    let steps = request.steps.map(|_| "--steps".to_string());
    if let Some(name) = request.sweep_value.clone().or(steps) {
        return Err(given(
            &name,
            format!("{name} does not apply to --long on kepler-hard (10⁴ orbits, --quick 100)"),
        ));
    }
    if !cfg!(feature = "peer") {
        return Err(given(
            "--long",
            "--long on kepler-hard runs dop853, which needs the `peer` feature".into(),
        ));
    }
    let settings = if request.quick {
        VariableSettings::quick()
    } else {
        VariableSettings::full()
    };
    let runs = long_variable::run(settings)?;
    Ok(LongStudy {
        title: format!(
            "Kepler e = {}: {} orbits at about {} force evaluations per orbit each",
            settings.e, settings.orbits, settings.evals_per_orbit
        ),
        runs,
        dir: Builtin::KeplerHard.name().to_string(),
    })
}

/// `--long --problem outer-solar`: the named methods (default
/// [`plan::OUTER_SOLAR_LONG_METHODS`]) at Jupiter's period / 20 over 10⁷
/// days, the energy error's growth fitted.
fn long_outer_solar(request: &ModeRequest) -> Result<LongStudy> {
    refuse_sweep_value(request)?;
    let settings = plan::outer_solar_long_settings(request.steps, request.quick);
    let n = long_steps(settings)?;
    let t = n as f64 * settings.h;
    let setup = builtin::outer_solar(t, false)?;
    let ids = request.methods.clone().unwrap_or_else(|| {
        plan::OUTER_SOLAR_LONG_METHODS
            .iter()
            .map(|s| s.to_string())
            .collect()
    });
    let mut methods = Vec::new();
    for id in &ids {
        let named = |why: String| given("--methods", format!("--methods {id}: {why}"));
        match setup.method(id).map_err(|e| named(e.to_string()))? {
            Method::Fixed(f) => methods.push(f),
            Method::Dop853 | Method::Rebound(_) => {
                return Err(named(
                    "--long runs this library's fixed-step methods".into(),
                ));
            }
        }
    }
    let runs = long::run(&setup, &methods, settings)?;
    Ok(LongStudy {
        title: format!(
            "{}: {n} steps of h = {} days (T = {t:.4e} days)",
            Builtin::OuterSolar.description(),
            format::plain(settings.h)
        ),
        runs,
        dir: Builtin::OuterSolar.name().to_string(),
    })
}

/// What the hard cases return: a row per method and case, and the notes
/// (each case's line, the methods skipped and why).
pub struct HardStudy {
    pub rows: Vec<HardRow>,
    pub notes: Vec<String>,
}

impl HardStudy {
    /// The report `hard.md` holds.
    pub fn markdown(&self) -> String {
        hard::markdown(&self.rows, &self.notes)
    }

    /// Write `hard.csv` and `hard.md` into `dir`; their paths.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        hard::write(dir, &self.rows, &self.notes)?;
        Ok(vec![dir.join("hard.csv"), dir.join("hard.md")])
    }
}

/// The hard cases (stiff FPU, Kepler e = 0.9, a stiff gyroscopic system,
/// or the one `request.problem` names): the largest stable step of every
/// fixed-step method that applies (or of those named; one that does not
/// apply to a case is skipped with a note).
pub fn hard(request: &ModeRequest) -> Result<HardStudy> {
    if let Some(name) = &request.sweep_value {
        return Err(given(
            name,
            format!("{name} belongs to the work-precision sweep, not to --hard"),
        ));
    }
    if let Some(p) = request.problem
        && !matches!(p, Builtin::Fpu | Builtin::KeplerHard | Builtin::Gyroscopic)
    {
        return Err(given(
            "--problem",
            format!(
                "--hard covers fpu, kepler-hard and gyroscopic, not {}",
                p.name()
            ),
        ));
    }
    let wanted = |p: Builtin| request.problem.is_none_or(|q| q == p);
    let mut study = HardStudy {
        rows: Vec::new(),
        notes: Vec::new(),
    };
    if wanted(Builtin::Fpu) {
        hard_case(request, hard::fpu_case()?, Builtin::Fpu, &mut study)?;
    }
    if wanted(Builtin::KeplerHard) {
        hard_case(
            request,
            hard::kepler_case()?,
            Builtin::KeplerHard,
            &mut study,
        )?;
    }
    if wanted(Builtin::Gyroscopic) {
        let case = hard::gyroscopic_case()?;
        hard_case(request, case, Builtin::Gyroscopic, &mut study)?;
    }
    Ok(study)
}

/// One hard case into `study`.
fn hard_case<P: Problem>(
    request: &ModeRequest,
    case: Case<P>,
    problem: Builtin,
    study: &mut HardStudy,
) -> Result<()> {
    let HardSearch { tolerance, floor } = HardSearch::of(request.quick);
    study.notes.push(case.note.clone());
    let methods = hard_methods(request, &case.setup, problem, &mut study.notes, case.name)?;
    study
        .rows
        .extend(hard::run_case(&case, &methods, tolerance, floor)?);
    Ok(())
}

/// The fixed-step methods of a hard case: those named (one that does not
/// apply is skipped with a note; an unknown id is an error), else
/// [`plan::hard_methods`].
fn hard_methods<P: Problem>(
    request: &ModeRequest,
    setup: &Setup<P>,
    problem: Builtin,
    notes: &mut Vec<String>,
    name: &str,
) -> Result<Vec<Fixed<P>>> {
    let ids = match &request.methods {
        Some(ids) => ids.clone(),
        None => plan::hard_methods(setup, problem, request.quick),
    };
    let mut out = Vec::new();
    for id in ids {
        match setup.method(&id) {
            Ok(Method::Fixed(f)) => out.push(f),
            Ok(Method::Dop853) => notes.push(format!(
                "dop853 skipped on {name}: adaptive, it has no step size"
            )),
            Ok(Method::Rebound(r)) => notes.push(format!(
                "{} skipped on {name}: REBOUND runs in the work-precision sweep only",
                r.id
            )),
            Err(e) if request.methods.is_some() && !e.to_string().starts_with("unknown") => {
                notes.push(format!("{id} skipped on {name}: {e}"))
            }
            Err(e) => return Err(e),
        }
    }
    Ok(out)
}

/// The problem of a sweep: a built-in one, or a linear system from a file
/// ([`linear_file`](crate::linear_file)).
#[derive(Clone, Debug)]
pub enum SweepProblem {
    Builtin(Builtin),
    File(PathBuf),
}

/// A work–precision sweep as a caller asks for it.
#[derive(Clone, Debug)]
pub struct SweepJob {
    pub problem: SweepProblem,
    /// The settings given (a problem file's own defaults are named as its
    /// fields in messages).
    pub request: SweepRequest,
    /// Method ids, each once (`None`: the defaults, see
    /// [`plan::sweep_methods`]).
    pub methods: Option<Vec<String>>,
    /// Table files added to the methods (`wh:PATH`: on the problem's
    /// Wisdom–Holman split; see [`MethodSpec::table`]).
    pub tables: Vec<PathBuf>,
}

/// A sweep ready to run: its problem set up (with its reference), its
/// settings planned and its methods resolved, whatever the problem's type.
pub trait PreparedSweep {
    /// The problem's name (the `problem` column, the default directory).
    fn name(&self) -> &str;
    /// The line that says what the sweep runs.
    fn headline(&self) -> String;
    /// Run it, continuing after the rows `done` (see
    /// [`work_precision_from`]).
    fn run(
        self: Box<Self>,
        done: Vec<Row>,
        observer: &mut dyn SweepObserver,
    ) -> Result<(WorkPrecision, bool)>;
}

struct Prepared<P: Problem> {
    setup: Setup<P>,
    plan: SweepPlan,
    methods: Vec<Method<P>>,
}

impl<P: Problem> PreparedSweep for Prepared<P> {
    fn name(&self) -> &str {
        &self.setup.name
    }
    fn headline(&self) -> String {
        self.plan
            .headline(&self.setup.description, self.methods.len())
    }
    fn run(
        self: Box<Self>,
        done: Vec<Row>,
        observer: &mut dyn SweepObserver,
    ) -> Result<(WorkPrecision, bool)> {
        work_precision_from(
            &self.setup,
            &self.methods,
            &self.plan.settings,
            done,
            observer,
        )
    }
}

/// Plan the sweep of `job`: the settings (with the problem's or the
/// file's defaults), the setup and the methods ([`plan::sweep_methods`]).
pub fn prepare_sweep(job: SweepJob) -> Result<Box<dyn PreparedSweep>> {
    struct Prepare {
        plan: SweepPlan,
        builtin: Option<Builtin>,
        methods: Option<Vec<String>>,
        tables: Vec<PathBuf>,
        quick: bool,
    }
    impl OnSetup for Prepare {
        type Output = Result<Box<dyn PreparedSweep>>;
        fn run<P: Problem>(self, setup: Setup<P>) -> Self::Output {
            let named = self
                .methods
                .map(|ids| ids.into_iter().map(MethodSpec::Id).collect());
            let added = self.tables.into_iter().map(MethodSpec::table).collect();
            let methods = plan::sweep_methods(&setup, self.builtin, named, added, self.quick)?;
            Ok(Box::new(Prepared {
                setup,
                plan: self.plan,
                methods,
            }))
        }
    }
    let quick = job.request.quick;
    match &job.problem {
        SweepProblem::File(path) => {
            let file = crate::linear_file::load(path)?;
            let field = |given: bool, name: &str| {
                given.then(|| format!("{}: field {name}", path.display()))
            };
            let request = SweepRequest {
                from_file: FromFile {
                    t_end: field(file.given.t_end, "t_end"),
                    h_min: field(file.given.h_min, "h_min"),
                    h_max: field(file.given.h_max, "h_max"),
                },
                ..job.request
            };
            let plan = sweep_plan(&request, file.defaults)?;
            let setup = file.setup(plan.t_end)?;
            let prepare = Prepare {
                plan,
                builtin: None,
                methods: job.methods,
                tables: job.tables,
                quick,
            };
            prepare.run(setup)
        }
        &SweepProblem::Builtin(problem) => {
            let plan = sweep_plan(&job.request, problem.defaults())?;
            let t_end = plan.t_end;
            let prepare = Prepare {
                plan,
                builtin: Some(problem),
                methods: job.methods,
                tables: job.tables,
                quick,
            };
            plan::with_setup(problem, t_end, true, prepare)?
        }
    }
}
