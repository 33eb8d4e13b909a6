//! `symlab compare`: the command-line client of the comparison library
//! (the `compare` crate, which documents the experiments, the columns of
//! `runs.csv` and the report). This module parses and checks the flags —
//! its messages name them — builds the problem and the methods, calls the
//! library and prints what it returns.
//!
//! * `symlab compare --problem P [--methods id,…] [--table FILE]… [--t-end T]
//!   [--h-min H --h-max H --points N] [--repeats R] [--target E] [--out DIR]
//!   [--quick]`, or `--problem-file FILE` for a linear system from a file:
//!   a work–precision sweep ([`compare::work_precision`]).
//! * `--peer-study [--problem kepler|kepler-hard]`: our strongest schemes
//!   (fixed-step, `logh:ID`, `adaptive:ID`) against DOP853 over 100 and 1000
//!   Kepler orbits at e = 0.6 and 0.9 ([`compare::peer_study`]).
//! * `--long --problem kepler|oscillator|henon-heiles [--steps N]`: energy
//!   error over 10⁶ steps of symplectic against non-symplectic pairs
//!   ([`compare::long`]).
//! * `--hard [--problem fpu|kepler-hard|gyroscopic]`: the largest stable
//!   step of every method ([`compare::hard`]).
//! * `--from runs.csv`: the summary of an earlier sweep.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use compare::builtin::Builtin;
use compare::format;
use compare::plan::{self, HardSearch, OnSetup};
use compare::sweep_plan::{FromFile, Names, SweepPlan, SweepRequest, sweep_plan};
use compare::{Method, Problem, Setup};

/// The columns of `runs.csv`, for `--help`.
const HELP: &str = "\
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
generated code, wall times do not). --problem-file FILE.toml runs a linear system
M q'' + G q' + K q = f read from a file (m, g, k, f, q0, p0, t_end, h_min, h_max) against
its exact flow; errors name the file and the field.

--from CSV reads a runs.csv back (fields quoted as RFC 4180 says); a row with a negative
h, error, energy_error or time_s, or a non-finite one where status is ok, is refused
naming its line and column.

Exit status: 0 done, 2 bad input (the message names the flag, file or field); a closed
pipe (symlab compare ... | head) ends the process by SIGPIPE (status 141 in a shell).";

fn problem_id(s: &str) -> std::result::Result<Builtin, String> {
    Builtin::from_name(s).map_err(|_| {
        format!(
            "the built-in problems are {}",
            Builtin::ALL.map(Builtin::name).join(", ")
        )
    })
}

#[derive(clap::Args)]
#[command(after_help = HELP)]
pub struct CompareArgs {
    /// The problem: oscillator, gyroscopic, kepler, kepler-hard,
    /// henon-heiles, fpu, pendulum or outer-solar (the Sun and five outer
    /// planets, HLW I.2.3, over 10⁵ days).
    #[arg(long, value_parser = problem_id, value_name = "PROBLEM")]
    problem: Option<Builtin>,
    /// A linear system M q'' + G q' + K q = f from a TOML file (fields m,
    /// g, k, f, q0, p0, and optionally t_end, h_min, h_max, name), with its
    /// exact flow as the reference.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["problem", "long", "hard", "peer_study", "from"])]
    problem_file: Option<PathBuf>,
    /// Comma-separated method ids (default: every method that applies):
    /// `symlab list` ids, gaussN-propagator (gyroscopic), dop853,
    /// rebound:NAME (REBOUND through Python, e.g. rebound:whfast:corrector=11;
    /// outer-solar, kepler, kepler-hard; see below),
    /// logh:ID (an explicit separable scheme on the logarithmic
    /// Hamiltonian), adaptive:ID and adaptive-implicit:ID (a symmetric
    /// scheme, explicit or implicit, under a reversible step-size controller
    /// with the inverse distance as step density: kepler, kepler-hard),
    /// wh:ID (a drift–kick sequence or composition on the Wisdom–Holman
    /// split, Kepler flows and interaction kicks, or a processed method of
    /// the catalogue, e.g. wh:leapfrog-c11, its corrector at output only:
    /// outer-solar).
    #[arg(long, value_delimiter = ',', value_name = "ID,...")]
    methods: Option<Vec<String>>,
    /// A table file (TOML, as for `symlab check`) to add to the sweep: its
    /// claims are verified exactly, then it is stepped by the run-time
    /// interpreter (rows marked interpreted). Repeatable.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["long", "hard", "peer_study", "from"])]
    table: Vec<PathBuf>,
    /// End time (default per problem, e.g. 20π = 10 orbits for Kepler).
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    t_end: Option<f64>,
    /// Smallest step size of the sweep.
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    h_min: Option<f64>,
    /// Largest step size of the sweep.
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    h_max: Option<f64>,
    /// Number of step sizes (log-spaced; default 10), also the number of
    /// DOP853 tolerances (default 15, one per decade from 1e-4 to 1e-18).
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    points: Option<usize>,
    /// Timed runs per point (the median is reported), after one warm-up.
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    repeats: Option<usize>,
    /// Error for the time-to-error table (default 1e-8); --peer-study adds
    /// it to its targets 1e-6, 1e-8, 1e-10.
    #[arg(long, value_name = "E", allow_hyphen_values = true)]
    target: Option<f64>,
    /// Output directory (default out/compare/<problem>/, out/compare/hard/).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// A smoke run of a few seconds: few points, few methods, one repeat.
    #[arg(long)]
    quick: bool,
    /// Long runs: energy error of symplectic vs non-symplectic pairs over
    /// 10⁶ steps (kepler, oscillator, henon-heiles); on kepler-hard,
    /// logh:kahan-li8, adaptive:kahan-li8 and dop853 over 10⁴ orbits at
    /// equal work; on outer-solar, the --methods named (default
    /// wh:leapfrog, wh:kahan-li8, kahan-li8, stormer-verlet) at Jupiter's
    /// period / 20 over 10⁷ days.
    #[arg(long, conflicts_with = "hard")]
    long: bool,
    /// Steps of the long runs (default 10⁶, on outer-solar 10⁷ days; at
    /// most 10⁷).
    #[arg(long, value_name = "N", requires = "long", allow_hyphen_values = true)]
    steps: Option<u64>,
    /// Hard cases: the largest stable step of each method on stiff FPU,
    /// Kepler e = 0.9 and a stiff gyroscopic system.
    #[arg(long)]
    hard: bool,
    /// Read an existing runs.csv instead of running: print its summary and
    /// time-to-error table (with --target).
    #[arg(long, value_name = "CSV", conflicts_with_all = ["hard", "long", "problem"])]
    from: Option<PathBuf>,
    /// Run-length study against the peer on Kepler (e = 0.6 and 0.9, or
    /// the one --problem names): strong fixed-step, time-transformed and
    /// reversible adaptive schemes and DOP853 at 100 and 1000 orbits;
    /// writes peer.csv and peer.md (default directory out/compare/peer/).
    #[arg(long, conflicts_with_all = ["hard", "long", "from"])]
    peer_study: bool,
    /// Of a work-precision sweep: write a checkpoint (DIR/checkpoint.symlab)
    /// after a row once DURATION of wall time has passed since the last
    /// (e.g. 30s, 5m, 0: after every row, off; default 60s), from which
    /// `symlab resume DIR` continues without running the finished rows
    /// again. SIGINT and SIGTERM write one and stop (exit 130, 143).
    #[arg(long, value_name = "DURATION", value_parser = integrator_core::checkpoint::parse_every)]
    checkpoint_every: Option<integrator_core::checkpoint::Every>,
}

impl CompareArgs {
    /// `--target`, default 1e-8.
    fn target(&self) -> f64 {
        self.target.unwrap_or(1e-8)
    }
}

/// `--NAME`'s value if it is a finite, normal number > 0.
fn positive(name: &str, x: f64) -> Result<f64> {
    Ok(compare::sweep_plan::positive(&format!("--{name}"), x)?)
}

fn out_dir(args: &CompareArgs, default: &str) -> Result<PathBuf> {
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join("compare").join(default));
    std::fs::create_dir_all(&dir).with_context(|| {
        if args.out.is_some() {
            format!("--out {}: cannot create the directory", dir.display())
        } else {
            format!("creating {}", dir.display())
        }
    })?;
    Ok(dir)
}

/// The first flag of the work-precision sweep that was given, if any (the
/// other modes refuse them).
fn sweep_flag(args: &CompareArgs) -> Option<&'static str> {
    [
        (args.t_end.is_some(), "t-end"),
        (args.h_min.is_some(), "h-min"),
        (args.h_max.is_some(), "h-max"),
        (args.points.is_some(), "points"),
    ]
    .into_iter()
    .find_map(|(set, name)| set.then_some(name))
}

fn method_ids(args: &CompareArgs) -> Result<Option<Vec<String>>> {
    let Some(list) = &args.methods else {
        return Ok(None);
    };
    let mut out: Vec<String> = Vec::new();
    for m in list {
        let m = m.trim();
        if m.is_empty() {
            bail!("--methods has an empty entry (ids are separated by single commas)");
        }
        if !out.iter().any(|x| x == m) {
            out.push(m.to_string());
        }
    }
    Ok(Some(out))
}

/// `symlab compare`: `argv` are the arguments after `compare`, kept in a
/// sweep's checkpoint so that `symlab resume` plans the same sweep.
pub fn run(args: &CompareArgs, argv: &[String]) -> Result<ExitCode> {
    run_or_resume(args, argv, None)
}

/// The saved rows of a stopped sweep.
struct Resumed {
    rows: Vec<compare::Row>,
}

/// What a sweep's checkpoints hold beside its rows.
struct Saving<'a> {
    argv: &'a [String],
    every: Option<std::time::Duration>,
    done: Vec<compare::Row>,
}

fn run_or_resume(
    args: &CompareArgs,
    argv: &[String],
    resumed: Option<Resumed>,
) -> Result<ExitCode> {
    let start = Instant::now();
    let every = match args.checkpoint_every {
        None => Some(integrator_core::checkpoint::DEFAULT_EVERY),
        Some(integrator_core::checkpoint::Every::Off) => None,
        Some(integrator_core::checkpoint::Every::After(d)) => Some(d),
    };
    if args.checkpoint_every.is_some()
        && (args.peer_study || args.hard || args.long || args.from.is_some())
    {
        bail!(
            "--checkpoint-every: only work-precision sweeps (--problem, --problem-file) are checkpointed"
        );
    }
    let saving = Saving {
        argv,
        every,
        done: resumed.map(|r| r.rows).unwrap_or_default(),
    };
    if let Some(t) = args.target {
        positive("target", t)?;
    }
    if args.repeats == Some(0) {
        bail!("--repeats must be at least 1");
    }
    if let Some(path) = &args.from {
        let rows = compare::output::read_runs(path)?;
        if rows.is_empty() {
            bail!("{}: no runs", path.display());
        }
        print!("{}", compare::output::summary(&rows, args.target()));
        print!(
            "{}",
            compare::output::time_to_error_table(&rows, args.target(), &path.display().to_string())
        );
        return Ok(ExitCode::SUCCESS);
    }
    if args.peer_study {
        peer_study(args)?;
    } else if args.hard {
        hard_cases(args)?;
    } else if args.long {
        long_runs(args)?;
    } else if let Some(path) = &args.problem_file {
        if args.steps.is_some() {
            bail!("--steps belongs to --long");
        }
        let file = compare::linear_file::load(path)?;
        let field =
            |given: bool, name: &str| given.then(|| format!("{}: field {name}", path.display()));
        let from_file = FromFile {
            t_end: field(file.given.t_end, "t_end"),
            h_min: field(file.given.h_min, "h_min"),
            h_max: field(file.given.h_max, "h_max"),
        };
        let plan = sweep_plan(&request(args, from_file), file.defaults)?;
        let setup = file.setup(plan.t_end)?;
        if let Some(code) = sweep_problem(args, &plan, setup, None, saving)? {
            return Ok(code);
        }
    } else {
        let Some(problem) = args.problem else {
            bail!(
                "--problem is required: oscillator, gyroscopic, kepler, kepler-hard, henon-heiles, fpu or pendulum (or --problem-file FILE)"
            );
        };
        if let Some(code) = work_precision(args, problem, saving)? {
            return Ok(code);
        }
    }
    println!("done in {:.1} s", start.elapsed().as_secs_f64());
    Ok(ExitCode::SUCCESS)
}

/// The sweep request of the flags; `from_file` names the defaults a
/// problem file set.
fn request(args: &CompareArgs, from_file: FromFile) -> SweepRequest {
    SweepRequest {
        t_end: args.t_end,
        h_min: args.h_min,
        h_max: args.h_max,
        points: args.points,
        repeats: args.repeats,
        target: args.target,
        quick: args.quick,
        names: Names::default(),
        from_file,
    }
}

fn plan(args: &CompareArgs, defaults: compare::Defaults) -> Result<SweepPlan> {
    Ok(sweep_plan(&request(args, FromFile::default()), defaults)?)
}

fn resolve<P: Problem>(
    args: &CompareArgs,
    setup: &Setup<P>,
    builtin: Option<Builtin>,
) -> Result<Vec<Method<P>>> {
    let ids = match method_ids(args)? {
        Some(ids) => ids,
        // With table files and no --methods: the tables beside a few
        // references (the quick set), not the whole library.
        None if args.quick || !args.table.is_empty() => plan::table_references(builtin),
        None => plan::default_methods(setup, builtin),
    };
    let mut methods: Vec<Method<P>> = ids
        .iter()
        .map(|id| setup.method(id))
        .collect::<compare::Result<_>>()?;
    for path in &args.table {
        let m = Method::table_file(path)?;
        if methods.iter().any(|x| x.id() == m.id()) {
            bail!(
                "--table {}: the method id '{}' (the file name) is taken; rename the file",
                path.display(),
                m.id()
            );
        }
        methods.push(m);
    }
    Ok(methods)
}

/// A sweep's outcome: `Some(status)` when a signal stopped it.
type Stopped = Option<ExitCode>;

fn work_precision(args: &CompareArgs, problem: Builtin, saving: Saving<'_>) -> Result<Stopped> {
    if args.steps.is_some() {
        bail!("--steps belongs to --long");
    }
    let plan = plan(args, problem.defaults())?;
    /// The sweep of one built-in problem, whatever its type.
    struct Sweep<'a> {
        args: &'a CompareArgs,
        plan: &'a SweepPlan,
        problem: Builtin,
        saving: Saving<'a>,
    }
    impl OnSetup for Sweep<'_> {
        type Output = Result<Stopped>;
        fn run<P: Problem>(self, setup: Setup<P>) -> Result<Stopped> {
            sweep_problem(self.args, self.plan, setup, Some(self.problem), self.saving)
        }
    }
    let sweep = Sweep {
        args,
        plan: &plan,
        problem,
        saving,
    };
    plan::with_setup(problem, plan.t_end, true, sweep)?
}

/// The progress bar of a sweep: on a terminal only.
fn sweep_bar() -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(0);
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg} [{elapsed}]")
    {
        bar.set_style(style);
    }
    bar
}

/// What the command line does while a sweep runs: the bar (on a
/// terminal), each stage's line on standard output and, for a sweep that
/// saves, a checkpoint every `every` and at a signal, and the stop at a
/// signal.
struct SweepFront<'a> {
    bar: indicatif::ProgressBar,
    saving: Option<SweepSaving<'a>>,
    /// A checkpoint that could not be written (the sweep stops).
    failed: Option<anyhow::Error>,
    /// The rows the last checkpoint holds.
    saved_rows: Option<usize>,
}

/// Where and how often a sweep saves its checkpoint.
struct SweepSaving<'a> {
    ckpt: &'a Path,
    argv: &'a [String],
    every: Option<std::time::Duration>,
    last: Instant,
}

impl<'a> SweepFront<'a> {
    fn new(saving: Option<SweepSaving<'a>>) -> Self {
        SweepFront {
            bar: sweep_bar(),
            saving,
            failed: None,
            saved_rows: None,
        }
    }
}

impl compare::SweepObserver for SweepFront<'_> {
    fn stage(&mut self, what: &str) {
        self.bar.suspend(|| println!("{what}"));
    }
    fn start(&mut self, rows: usize) {
        self.bar.set_length(rows as u64);
        self.bar.set_position(0);
    }
    fn method(&mut self, id: &str) {
        self.bar.set_message(id.to_string());
    }
    fn row(&mut self, rows: &[compare::Row], fresh: bool) -> compare::RowControl {
        self.bar.inc(1);
        let Some(saving) = self.saving.as_mut().filter(|_| fresh) else {
            return compare::RowControl::Continue;
        };
        let signal = crate::signals::requested();
        if signal.is_some() || saving.every.is_some_and(|d| saving.last.elapsed() >= d) {
            match save(saving.ckpt, saving.argv, rows) {
                Ok(()) => self.saved_rows = Some(rows.len()),
                Err(e) => {
                    self.failed = Some(e);
                    return compare::RowControl::Stop;
                }
            }
            saving.last = Instant::now();
        }
        if signal.is_some() {
            compare::RowControl::Stop
        } else {
            compare::RowControl::Continue
        }
    }
    fn finish(&mut self) {
        self.bar.finish_and_clear();
    }
}

fn sweep_problem<P: Problem>(
    args: &CompareArgs,
    plan: &SweepPlan,
    setup: Setup<P>,
    builtin: Option<Builtin>,
    saving: Saving<'_>,
) -> Result<Stopped> {
    let methods = resolve(args, &setup, builtin)?;
    let dir = out_dir(args, &setup.name)?;
    integrator_core::checkpoint::check_writable(&dir)?;
    let ckpt = dir.join(integrator_core::checkpoint::FILE_NAME);
    let resuming = !saving.done.is_empty();
    if !resuming {
        integrator_core::checkpoint::remove(&ckpt)?;
    }
    let steps = plan.settings.step_counts(plan.t_end);
    println!(
        "{}: T = {}, {} methods, {} step sizes from h = {:.3e} to {:.3e} ({}–{} steps), {} timed run(s) each",
        setup.description,
        format::plain(plan.t_end),
        methods.len(),
        steps.len(),
        plan.t_end / steps[0] as f64,
        plan.t_end / *steps.last().expect("at least one") as f64,
        steps[0],
        steps.last().expect("at least one"),
        plan.settings.repeats
    );
    if resuming {
        println!(
            "resuming: {} rows done are not run again",
            saving.done.len()
        );
    }
    crate::signals::install();
    let mut front = SweepFront::new(Some(SweepSaving {
        ckpt: &ckpt,
        argv: saving.argv,
        every: saving.every,
        last: Instant::now(),
    }));
    let (result, stopped) =
        compare::work_precision_from(&setup, &methods, &plan.settings, saving.done, &mut front)?;
    let SweepFront {
        failed, saved_rows, ..
    } = front;
    if let Some(e) = failed {
        return Err(e);
    }
    if stopped {
        let sig = crate::signals::requested().unwrap_or(15);
        let total = result.methods.len();
        println!(
            "stopped by {} after {} rows ({} methods planned)",
            crate::signals::name(sig),
            result.rows.len(),
            total
        );
        if saved_rows == Some(result.rows.len()) {
            println!(
                "checkpoint {} — continue with: symlab resume {}",
                ckpt.display(),
                dir.display()
            );
        }
        return Ok(Some(ExitCode::from(crate::signals::exit_status(sig))));
    }
    let files = result.write(&dir)?;
    integrator_core::checkpoint::remove(&ckpt)?;
    print!("{}", result.summary());
    if result.rows.iter().any(|r| r.interpreted) {
        println!(
            "interpreted: rows of table files are stepped by the run-time interpreter; their errors and \
             evaluations compare with generated code, their times do not (see report.md)"
        );
    }
    for f in files {
        if f.ends_with("runs.csv") {
            println!("wrote {} ({} rows)", f.display(), result.rows.len());
        } else {
            println!("wrote {}", f.display());
        }
    }
    Ok(None)
}

/// Write the sweep's checkpoint: its arguments and rows so far.
fn save(path: &Path, argv: &[String], rows: &[compare::Row]) -> Result<()> {
    let mut e = integrator_core::checkpoint::Encoder::new();
    e.usize(argv.len());
    for a in argv {
        e.str(a);
    }
    compare::sweep::encode_rows(&mut e, rows);
    integrator_core::checkpoint::write(
        path,
        integrator_core::checkpoint::Kind::Compare,
        &e.finish(),
    )?;
    Ok(())
}

/// The arguments of `symlab compare`, for reading a checkpoint's back.
#[derive(clap::Parser)]
#[command(name = "symlab compare")]
struct Stored {
    #[command(flatten)]
    args: CompareArgs,
}

/// `symlab resume DIR` of a sweep: `payload` read from `path` in `dir`.
pub fn resume(dir: &Path, path: &Path, payload: &[u8]) -> Result<ExitCode> {
    let mut d = integrator_core::checkpoint::Decoder::new(path, payload);
    let n = d.usize("arguments")?;
    if n > 1000 {
        return Err(d.error(format!("arguments: {n} of them")).into());
    }
    let argv = (0..n)
        .map(|_| d.str("arguments").map(str::to_string))
        .collect::<Result<Vec<_>, _>>()?;
    let rows = compare::sweep::decode_rows(&mut d)?;
    d.end()?;
    use clap::Parser as _;
    let mut args = Stored::try_parse_from(
        std::iter::once("symlab compare".to_string()).chain(argv.iter().cloned()),
    )
    .map_err(|e| {
        anyhow::anyhow!(
            "{}: the saved arguments `symlab compare {}` do not parse: {}",
            path.display(),
            argv.join(" "),
            e.to_string().trim()
        )
    })?
    .args;
    args.out = Some(dir.to_path_buf());
    run_or_resume(&args, &argv, Some(Resumed { rows }))
}

fn peer_study(args: &CompareArgs) -> Result<()> {
    if let Some(p) = args.problem
        && !matches!(p, Builtin::Kepler | Builtin::KeplerHard)
    {
        bail!(
            "--peer-study runs on kepler (e = 0.6) and kepler-hard (e = 0.9) only, not on {}",
            p.name()
        );
    }
    if let Some(name) = sweep_flag(args).or(args.steps.map(|_| "steps")) {
        bail!(
            "--{name} does not apply to --peer-study: it runs 100 and 1000 orbits with step ranges of its own"
        );
    }
    let mut settings = if args.quick {
        compare::peer_study::PeerStudySettings::quick()
    } else {
        compare::peer_study::PeerStudySettings::full()
    };
    match args.problem {
        Some(Builtin::Kepler) => settings.eccentricities = vec![0.6],
        Some(Builtin::KeplerHard) => settings.eccentricities = vec![0.9],
        _ => {}
    }
    if let Some(r) = args.repeats {
        if r > 100 {
            bail!("--repeats must be at most 100, got {r}");
        }
        settings.repeats = r;
    }
    if let Some(ids) = method_ids(args)? {
        if !ids.iter().any(|m| m == "dop853") {
            bail!("--peer-study compares against dop853: keep it in --methods");
        }
        settings.methods = ids;
    }
    if let Some(t) = args.target {
        settings = settings.with_target(t);
        settings.energy_target = t;
    }
    let dir = out_dir(args, "peer")?;
    let mut front = SweepFront::new(None);
    let study = compare::peer_study::run(settings, &mut front)?;
    for n in &study.notes {
        eprintln!("note: {n}");
    }
    study.write(&dir)?;
    print!("{}", study.verdict());
    println!(
        "wrote {} ({} rows)",
        dir.join("peer.csv").display(),
        study.rows().0.len()
    );
    println!("wrote {}", dir.join("peer.md").display());
    Ok(())
}

/// `--long --problem kepler-hard`: logh:kahan-li8, adaptive:kahan-li8 and
/// DOP853 over 10⁴ orbits (--quick: 100) at equal evaluations per orbit.
fn long_variable(args: &CompareArgs) -> Result<()> {
    if args.methods.is_some() {
        bail!(
            "--long on kepler-hard compares logh:kahan-li8, adaptive:kahan-li8 and dop853; --methods does not apply"
        );
    }
    if let Some(name) = sweep_flag(args).or(args.steps.map(|_| "steps")) {
        bail!("--{name} does not apply to --long on kepler-hard (10⁴ orbits, --quick 100)");
    }
    if !cfg!(feature = "peer") {
        bail!("--long on kepler-hard runs dop853, which needs the `peer` feature");
    }
    let settings = if args.quick {
        compare::long_variable::VariableSettings::quick()
    } else {
        compare::long_variable::VariableSettings::full()
    };
    let runs = compare::long_variable::run(settings)?;
    let dir = out_dir(args, "kepler-hard")?;
    compare::long::write(&dir, &runs)?;
    println!(
        "Kepler e = {}: {} orbits at about {} force evaluations per orbit each",
        settings.e, settings.orbits, settings.evals_per_orbit
    );
    print!("{}", compare::long::summary(&runs));
    for f in ["long.csv", "long_fit.csv", "long_energy.svg"] {
        println!("wrote {}", dir.join(f).display());
    }
    Ok(())
}

/// `--long --problem outer-solar`: the named methods (default
/// [`plan::OUTER_SOLAR_LONG_METHODS`]) at Jupiter's period / 20 over 10⁷
/// days, the energy error's growth fitted.
fn long_outer_solar(args: &CompareArgs) -> Result<()> {
    if let Some(name) = sweep_flag(args) {
        bail!("--{name} belongs to the work-precision sweep, not to --long (use --steps)");
    }
    let settings = plan::outer_solar_long_settings(args.steps, args.quick);
    let n = settings.steps;
    if !plan::LONG_STEPS.contains(&n) {
        bail!(
            "--steps must be between {} and 10^7, got {n}",
            plan::LONG_STEPS.start()
        );
    }
    let t = n as f64 * settings.h;
    let setup = compare::builtin::outer_solar(t, false)?;
    let ids = method_ids(args)?.unwrap_or_else(|| {
        plan::OUTER_SOLAR_LONG_METHODS
            .iter()
            .map(|s| s.to_string())
            .collect()
    });
    let mut methods = Vec::new();
    for id in &ids {
        match setup
            .method(id)
            .with_context(|| format!("--methods {id}"))?
        {
            Method::Fixed(f) => methods.push(f),
            Method::Dop853 | Method::Rebound(_) => {
                bail!("--methods {id}: --long runs this library's fixed-step methods")
            }
        }
    }
    let runs = compare::long::run(&setup, &methods, settings)?;
    let dir = out_dir(args, "outer-solar")?;
    compare::long::write(&dir, &runs)?;
    println!(
        "{}: {n} steps of h = {} days (T = {t:.4e} days)",
        Builtin::OuterSolar.description(),
        format::plain(settings.h)
    );
    print!("{}", compare::long::summary(&runs));
    for f in ["long.csv", "long_fit.csv", "long_energy.svg"] {
        println!("wrote {}", dir.join(f).display());
    }
    Ok(())
}

fn long_runs(args: &CompareArgs) -> Result<()> {
    let Some(problem) = args.problem else {
        bail!(
            "--long needs --problem kepler, kepler-hard, oscillator, henon-heiles or outer-solar"
        );
    };
    if problem == Builtin::KeplerHard {
        return long_variable(args);
    }
    if problem == Builtin::OuterSolar {
        return long_outer_solar(args);
    }
    if args.methods.is_some() {
        bail!(
            "--long compares fixed pairs (leapfrog/heun, forest-ruth/rk4, gauss2/rk4); --methods does not apply"
        );
    }
    if let Some(name) = sweep_flag(args) {
        bail!("--{name} belongs to the work-precision sweep, not to --long (use --steps)");
    }
    let settings = plan::long_settings(args.steps, args.quick);
    let n = settings.steps;
    if !plan::LONG_STEPS.contains(&n) {
        bail!(
            "--steps must be between {} and 10^7, got {n}",
            plan::LONG_STEPS.start()
        );
    }
    let t = n as f64 * settings.h;
    if !matches!(
        problem,
        Builtin::Kepler | Builtin::Oscillator | Builtin::HenonHeiles
    ) {
        bail!(
            "--long runs on kepler, kepler-hard, oscillator or henon-heiles (and on outer-solar, with the methods named), not on {}",
            problem.name()
        );
    }
    /// The symplectic/non-symplectic pairs on one problem, whatever its type.
    struct Pairs(compare::long::LongSettings);
    impl OnSetup for Pairs {
        type Output = compare::Result<Vec<compare::long::LongRun>>;
        fn run<P: Problem>(self, setup: Setup<P>) -> Self::Output {
            let methods = compare::long::pair_methods(&setup.sys)?;
            compare::long::run(&setup, &methods, self.0)
        }
    }
    let runs = plan::with_setup(problem, t, false, Pairs(settings))??;
    let dir = out_dir(args, problem.name())?;
    compare::long::write(&dir, &runs)?;
    println!(
        "{}: {n} steps of h = {} (T = {t})",
        problem.description(),
        settings.h
    );
    print!("{}", compare::long::summary(&runs));
    for f in ["long.csv", "long_fit.csv", "long_energy.svg"] {
        println!("wrote {}", dir.join(f).display());
    }
    Ok(())
}

fn hard_methods<P: Problem>(
    args: &CompareArgs,
    setup: &Setup<P>,
    problem: Builtin,
    notes: &mut Vec<String>,
    name: &str,
) -> Result<Vec<compare::Fixed<P>>> {
    let ids = match method_ids(args)? {
        Some(ids) => ids,
        None => plan::hard_methods(setup, problem, args.quick),
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
            Err(e) if args.methods.is_some() && !e.to_string().starts_with("unknown") => {
                notes.push(format!("{id} skipped on {name}: {e}"))
            }
            Err(e) => return Err(e.into()),
        }
    }
    Ok(out)
}

fn hard_cases(args: &CompareArgs) -> Result<()> {
    if let Some(name) = sweep_flag(args) {
        bail!("--{name} belongs to the work-precision sweep, not to --hard");
    }
    if let Some(p) = args.problem
        && !matches!(p, Builtin::Fpu | Builtin::KeplerHard | Builtin::Gyroscopic)
    {
        bail!(
            "--hard covers fpu, kepler-hard and gyroscopic, not {}",
            p.name()
        );
    }
    let wanted = |p: Builtin| args.problem.is_none_or(|q| q == p);
    let HardSearch { tolerance, floor } = HardSearch::of(args.quick);
    let mut rows = Vec::new();
    let mut notes = vec![];
    fn one<P: Problem>(
        args: &CompareArgs,
        case: compare::hard::Case<P>,
        problem: Builtin,
        rows: &mut Vec<compare::hard::HardRow>,
        notes: &mut Vec<String>,
        (tolerance, floor): (f64, f64),
    ) -> Result<()> {
        notes.push(case.note.clone());
        let methods = hard_methods(args, &case.setup, problem, notes, case.name)?;
        rows.extend(compare::hard::run_case(&case, &methods, tolerance, floor)?);
        Ok(())
    }
    let search = (tolerance, floor);
    if wanted(Builtin::Fpu) {
        let case = compare::hard::fpu_case()?;
        one(args, case, Builtin::Fpu, &mut rows, &mut notes, search)?;
    }
    if wanted(Builtin::KeplerHard) {
        let case = compare::hard::kepler_case()?;
        one(
            args,
            case,
            Builtin::KeplerHard,
            &mut rows,
            &mut notes,
            search,
        )?;
    }
    if wanted(Builtin::Gyroscopic) {
        let case = compare::hard::gyroscopic_case()?;
        one(
            args,
            case,
            Builtin::Gyroscopic,
            &mut rows,
            &mut notes,
            search,
        )?;
    }
    let dir = out_dir(args, "hard")?;
    compare::hard::write(&dir, &rows, &notes)?;
    print!("{}", compare::hard::markdown(&rows, &notes));
    println!("wrote {}", dir.join("hard.csv").display());
    println!("wrote {}", dir.join("hard.md").display());
    Ok(())
}
