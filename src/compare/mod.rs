//! `symlab compare`: research comparisons of the scheme library (and the
//! ode_solvers peer) on the test problems.
//!
//! # Work–precision sweeps
//!
//! `symlab compare --problem P [--methods id,…] [--t-end T] [--h-min H
//! --h-max H --points N] [--repeats R] [--target E] [--out DIR] [--quick]`
//!
//! Every method (default: every library scheme that can step the problem;
//! on the linear gyroscopic problem the Runge–Kutta tables plus the exact
//! one-step maps `gaussN-propagator`; on Kepler also DOP853) runs at `N`
//! log-spaced step sizes from `h-max` down to `h-min` (each rounded to a
//! whole number of steps over `[0, T]`), to the fixed end time `T`. The
//! adaptive peer `dop853` sweeps `rtol = atol` from 1e-4 to 1e-18 instead,
//! one per decade (`--points N`: N of them; `--quick`: 4), down to where
//! round-off stops its error from falling (see [`sweep::tolerances`]).
//! Each run is made once observed — on a counting wrapper of the system,
//! the energy checked at every step — and then, if it succeeded, once more
//! untimed (warm-up) and `R` times timed on the bare system, strictly one
//! after another; the wall time is the median. A run that diverges or whose
//! stage solver fails is recorded with its status, not an error.
//!
//! Output in `DIR` (default `out/compare/<problem>/`):
//!
//! * `runs.csv`, one row per run, columns:
//!
//! | column | meaning |
//! |---|---|
//! | `problem` | problem id |
//! | `method` | scheme id (`symlab list`), `gaussN-propagator`, or `dop853` |
//! | `order` | classical order (of the table; 8 for DOP853) |
//! | `symplectic` | symplectic for this problem (separable problems: for separable Hamiltonians) |
//! | `h` | step size; for `dop853` the average step `T/steps` |
//! | `tol` | `rtol = atol` of `dop853`; NaN for fixed-step methods |
//! | `steps` | steps taken (accepted steps for `dop853`) |
//! | `error` | `‖z(T) − z_ref(T)‖₂ / ‖z_ref(T)‖₂`; NaN unless `status` is ok |
//! | `energy_error` | `max |E − E₀|/|E₀|` over the steps taken |
//! | `time_s` | median wall time of the timed runs, seconds; NaN unless ok |
//! | `evals` | force evaluations (separable problems; an RK stage is one), right-hand sides (gyroscopic; a propagator step counts one matrix–vector product), or DOP853's own count |
//! | `newton_iterations` | simplified-Newton iterations of the implicit stage solver (0 for explicit methods) |
//! | `fixed_point_iterations` | fixed-point iterations of the stage solver (its choice without a Jacobian, as for the separable problems) |
//! | `factorizations` | LU factorisations of the stage solver |
//! | `status` | `ok`, `diverged at step k`, or `solver failed at step k: why` |
//!
//! * `error_vs_time.svg`, `error_vs_evals.svg`: log–log, one line per
//!   method; the same split by family (`…_explicit-rk`, `…_splitting`,
//!   `…_implicit`) with readable legends.
//! * A printed summary (fitted order, best error, time to `--target`) and
//!   the wall time of each method to reach relative error `--target`
//!   (default 1e-8), interpolated from the sweep ([`time_to_error`]).
//! * `report.md` ([`report::sweep_report`]): the problem, `T` and the sweep
//!   settings; the summary as a Markdown table (method, order, symplectic,
//!   ok runs, fitted slope, min error, best energy error, time to target);
//!   "Wall time to reach relative error E over T, fastest first" (rank,
//!   method, symplectic, time in ms, interpolated steps and evaluations);
//!   "Did not reach E within the sweep", each method with the reason in
//!   words (its smallest error and where: `at 10⁶ steps`, or for DOP853
//!   `at rtol = atol = …`; failed runs; or already below E at its cheapest
//!   run); and, when DOP853 ran, "Peer: DOP853 against our fastest method":
//!   for each decade 1e-2 … 1e-12 that either side reaches, our fastest
//!   method and its time, DOP853's time, their ratio and the faster side,
//!   with the verdict computed from those rows.
//!
//! The references: exact flows (oscillator, pendulum, Kepler), the matrix
//! exponential (gyroscopic), Sofroniou–Spaletta order 10 with tiny steps
//! (Hénon–Heiles, FPU; trustworthy for Hénon–Heiles up to `T ≈ 10`).
//!
//! # The peer over longer runs
//!
//! `symlab compare --peer-study [--methods id,…] [--repeats R] [--target E]
//! [--out DIR] [--quick]` (Kepler e = 0.6 only; not with `--hard`, `--long`,
//! `--from` or the sweep settings): kahan-li8, sofroniou-spaletta10,
//! mclachlan8, kahan-li6, yoshida6, rk4, gauss3 and dop853 at T = 10, 100
//! and 1000 orbits (period 2π), each a sweep as above with step counts of
//! its own (200–10⁵, 2000–10⁶, 2·10⁴–10⁶: from 20 steps per orbit, at most
//! 10⁶ per run) and DOP853 at `rtol = atol` = 1e-4 … 1e-18, one per decade
//! (over 1000 orbits it reaches 1e-8 only near 1e-16).
//! Five timed runs per point by default (the median; the close calls need
//! it). `--quick`: 1 and 10 orbits, 4 step counts and tolerances,
//! kahan-li8, rk4 and dop853, one timed run.
//! Writes (default directory `out/compare/peer/`) `peer.csv`, the columns
//! of `runs.csv` followed by `t_end`, and `peer.md`: for each run length
//! and target 1e-6, 1e-8, 1e-10 (and `--target`) our fastest method against
//! DOP853 — times, ratio, the faster side, and the max energy error of the
//! cheapest run of each that reaches the target — then per run length
//! every method's time to each target and its smallest error. See
//! [`peer_study`].
//!
//! # Long runs
//!
//! `symlab compare --long --problem kepler|oscillator|henon-heiles [--steps N]`:
//! `N` steps (default 10⁶, at most 10⁷) of h = 0.01 for leapfrog vs heun,
//! forest-ruth vs rk4 and gauss2 vs rk4, each with and without compensated
//! summation, in parallel. `long.csv` (`problem, method, order, symplectic,
//! compensated, h, step, t, energy_error`: the largest relative energy error
//! within log-spaced windows of steps, 20 per decade), `long_fit.csv` (the
//! fitted growth exponents), `long_energy.svg`.
//!
//! # Hard cases
//!
//! `symlab compare --hard [--problem fpu|kepler-hard|gyroscopic] [--methods …]`:
//! the largest stable step of every method on the stiff FPU chain (ω = 50,
//! T = 10), Kepler with e = 0.9 (T = 10 orbits) and a stiff gyroscopic
//! system (`gyroscopic(10, 1, 1e4)`, T = 1), by bisection in parallel across
//! methods; see [`hard`] for the criterion. `hard.csv`, `hard.md` (default
//! directory `out/compare/hard/`).

mod counting;
mod hard;
mod long;
mod output;
mod peer;
mod peer_study;
mod problem;
mod report;
mod runner;
mod sweep;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use integrator_core::linear::LinearHamiltonian;

use problem::{Method, Problem, ProblemId, Setup};

// The paper report's API: load a runs.csv, rank the methods by the time to
// reach an error.
#[allow(unused_imports)]
pub use output::{read_runs, time_to_error};
#[allow(unused_imports)]
pub use sweep::Row;

/// The columns of `runs.csv`, for `--help`.
const HELP: &str = "\
runs.csv columns (one row per run):
  problem            problem id
  method             scheme id (symlab list), gaussN-propagator, or dop853
  order              classical order (8 for dop853)
  symplectic         symplectic for this problem (separable problems: for separable H)
  h                  step size (dop853: average step T/steps)
  tol                rtol = atol of dop853 (NaN for fixed-step methods)
  steps              steps taken (dop853: accepted steps)
  error              ‖z(T) − z_ref(T)‖₂/‖z_ref(T)‖₂ (NaN unless status is ok)
  energy_error       max |E − E0|/|E0| over the steps taken
  time_s             median wall time of the timed runs in seconds (NaN unless ok)
  evals              force evaluations (separable problems), right-hand sides
                     (gyroscopic; a propagator step counts one matrix-vector product),
                     or dop853's own count
  newton_iterations  Newton iterations of the implicit stage solver (0 if explicit)
  fixed_point_iterations
                     fixed-point iterations of the stage solver (its choice when the
                     system has no Jacobian, as the separable problems)
  factorizations     LU factorisations of the stage solver
  status             ok | diverged at step k | solver failed at step k: why

A sweep also writes report.md: the problem, T and the settings; the summary table; the wall
time of each method to reach --target (default 1e-8), fastest first, with steps and
evaluations; the methods that did not reach it and why (smallest error and where); and,
when dop853 ran, our fastest method against it at each decade 1e-2 ... 1e-12.

--peer-study (Kepler e = 0.6) runs kahan-li8, sofroniou-spaletta10, mclachlan8, kahan-li6,
yoshida6, rk4, gauss3 and dop853 at 10, 100 and 1000 orbits (--quick: 1 and 10) and writes
peer.csv (the runs.csv columns, then t_end) and peer.md (per run length and target 1e-6,
1e-8, 1e-10: our fastest method against dop853, times, ratio, energy errors).

--long writes long.csv (problem,method,order,symplectic,compensated,h,step,t,energy_error),
long_fit.csv and long_energy.svg; --hard writes hard.csv and hard.md.";

#[derive(clap::Args)]
#[command(after_help = HELP)]
pub struct CompareArgs {
    /// The problem.
    #[arg(long, value_enum)]
    problem: Option<ProblemId>,
    /// Comma-separated method ids (default: every method that applies).
    #[arg(long, value_delimiter = ',', value_name = "ID,...")]
    methods: Option<Vec<String>>,
    /// End time (default per problem, e.g. 20π = 10 orbits for Kepler).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    t_end: Option<f64>,
    /// Smallest step size of the sweep.
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    h_min: Option<f64>,
    /// Largest step size of the sweep.
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    h_max: Option<f64>,
    /// Number of step sizes (log-spaced; default 10), also the number of
    /// DOP853 tolerances (default 15, one per decade from 1e-4 to 1e-18).
    #[arg(long, value_name = "N")]
    points: Option<usize>,
    /// Timed runs per point (the median is reported), after one warm-up.
    #[arg(long, value_name = "R")]
    repeats: Option<usize>,
    /// Error for the time-to-error table (default 1e-8); --peer-study adds
    /// it to its targets 1e-6, 1e-8, 1e-10.
    #[arg(long, value_name = "E", allow_negative_numbers = true)]
    target: Option<f64>,
    /// Output directory (default out/compare/<problem>/, out/compare/hard/).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// A smoke run of a few seconds: few points, few methods, one repeat.
    #[arg(long)]
    quick: bool,
    /// Long runs: energy error of symplectic vs non-symplectic pairs over
    /// 10⁶ steps (kepler, oscillator, henon-heiles).
    #[arg(long, conflicts_with = "hard")]
    long: bool,
    /// Steps of the long runs (default 10⁶, at most 10⁷).
    #[arg(long, value_name = "N", requires = "long")]
    steps: Option<u64>,
    /// Hard cases: the largest stable step of each method on stiff FPU,
    /// Kepler e = 0.9 and a stiff gyroscopic system.
    #[arg(long)]
    hard: bool,
    /// Read an existing runs.csv instead of running: print its summary and
    /// time-to-error table (with --target).
    #[arg(long, value_name = "CSV", conflicts_with_all = ["hard", "long", "problem"])]
    from: Option<PathBuf>,
    /// Run-length study against the peer on Kepler (e = 0.6): strong
    /// schemes and DOP853 at 10, 100 and 1000 orbits; writes peer.csv and
    /// peer.md (default directory out/compare/peer/).
    #[arg(long, conflicts_with_all = ["hard", "long", "from"])]
    peer_study: bool,
}

impl CompareArgs {
    /// `--target`, default 1e-8.
    fn target(&self) -> f64 {
        self.target.unwrap_or(1e-8)
    }
}

fn positive(name: &str, x: f64) -> Result<f64> {
    if !(x.is_finite() && x > 0.0) {
        bail!("--{name} must be a finite number > 0, got {x}");
    }
    Ok(x)
}

fn out_dir(args: &CompareArgs, default: &str) -> Result<PathBuf> {
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join("compare").join(default));
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    Ok(dir)
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

pub fn run(args: &CompareArgs) -> Result<ExitCode> {
    let start = Instant::now();
    if let Some(t) = args.target {
        positive("target", t)?;
    }
    if args.repeats == Some(0) {
        bail!("--repeats must be at least 1");
    }
    if let Some(path) = &args.from {
        let rows = read_runs(path)?;
        if rows.is_empty() {
            bail!("{}: no runs", path.display());
        }
        print!("{}", output::summary(&rows, args.target()));
        print!(
            "{}",
            output::time_to_error_table(&rows, args.target(), &path.display().to_string())
        );
        return Ok(ExitCode::SUCCESS);
    }
    if args.peer_study {
        peer_study::run(args)?;
    } else if args.hard {
        hard_cases(args)?;
    } else if args.long {
        long_runs(args)?;
    } else {
        let Some(problem) = args.problem else {
            bail!(
                "--problem is required: oscillator, gyroscopic, kepler, kepler-hard, henon-heiles, fpu or pendulum"
            );
        };
        work_precision(args, problem)?;
    }
    println!("done in {:.1} s", start.elapsed().as_secs_f64());
    Ok(ExitCode::SUCCESS)
}

/// The validated sweep parameters.
struct Plan {
    t_end: f64,
    h_min: f64,
    h_max: f64,
    points: usize,
    /// DOP853's tolerances.
    tolerances: usize,
    repeats: usize,
}

fn plan(args: &CompareArgs, problem: ProblemId) -> Result<Plan> {
    let (t_def, hmin_def, hmax_def) = problem.defaults();
    let t_end = positive("t-end", args.t_end.unwrap_or(t_def))?;
    let h_min = positive(
        "h-min",
        args.h_min.unwrap_or(if args.quick {
            t_def / 10_000.0
        } else {
            hmin_def
        }),
    )?;
    let h_max = positive("h-max", args.h_max.unwrap_or(hmax_def.min(t_end)))?;
    if h_min > h_max {
        bail!("--h-min ({h_min}) must not exceed --h-max ({h_max})");
    }
    if h_max > t_end {
        bail!("--h-max ({h_max}) exceeds the end time --t-end ({t_end})");
    }
    if t_end / h_min > 1e8 {
        bail!(
            "--h-min {h_min} over --t-end {t_end} is {:.1e} steps per run; at most 1e8",
            t_end / h_min
        );
    }
    let points = args.points.unwrap_or(if args.quick { 4 } else { 10 });
    if !(1..=200).contains(&points) {
        bail!("--points must be between 1 and 200, got {points}");
    }
    let repeats = args.repeats.unwrap_or(if args.quick { 1 } else { 3 });
    if repeats > 100 {
        bail!("--repeats must be at most 100, got {repeats}");
    }
    let tolerances = args.points.unwrap_or(if args.quick {
        4
    } else {
        sweep::PEER_TOLERANCES
    });
    Ok(Plan {
        t_end,
        h_min,
        h_max,
        points,
        tolerances,
        repeats,
    })
}

fn quick_methods(problem: ProblemId) -> Vec<String> {
    let ids: &[&str] = match problem {
        ProblemId::Gyroscopic => &["rk4", "gauss2", "gauss2-propagator"],
        ProblemId::Kepler | ProblemId::KeplerHard if cfg!(feature = "peer") => {
            &["leapfrog", "forest-ruth", "rk4", "gauss2", "dop853"]
        }
        _ => &["leapfrog", "forest-ruth", "rk4", "gauss2"],
    };
    ids.iter().map(|s| s.to_string()).collect()
}

fn default_methods<P: Problem>(problem: ProblemId) -> Vec<String> {
    let kepler = matches!(problem, ProblemId::Kepler | ProblemId::KeplerHard);
    P::all_methods(problem)
        .into_iter()
        .filter(|m| kepler || m != "dop853")
        .collect()
}

fn resolve<P: Problem>(args: &CompareArgs, problem: ProblemId) -> Result<Vec<Method<P>>> {
    let ids = match method_ids(args)? {
        Some(ids) => ids,
        None if args.quick => quick_methods(problem),
        None => default_methods::<P>(problem),
    };
    ids.iter().map(|id| P::method(id, problem)).collect()
}

fn work_precision(args: &CompareArgs, problem: ProblemId) -> Result<()> {
    if args.steps.is_some() {
        bail!("--steps belongs to --long");
    }
    let plan = plan(args, problem)?;
    let t = plan.t_end;
    match problem {
        ProblemId::Oscillator => sweep_problem(args, &plan, problem::oscillator(t, true)),
        ProblemId::Pendulum => sweep_problem(args, &plan, problem::pendulum(t, true)),
        ProblemId::Kepler | ProblemId::KeplerHard => {
            sweep_problem(args, &plan, problem::kepler(problem, t, true))
        }
        ProblemId::HenonHeiles => sweep_problem(args, &plan, problem::henon_heiles(t, true)),
        ProblemId::Fpu => sweep_problem(args, &plan, problem::fpu(t, true)),
        ProblemId::Gyroscopic => {
            sweep_problem(args, &plan, problem::gyroscopic(10, 1, 10.0, t, true)?)
        }
    }
}

fn sweep_problem<P: Problem>(args: &CompareArgs, plan: &Plan, setup: Setup<P>) -> Result<()> {
    let problem = setup.id;
    let methods = resolve::<P>(args, problem)?;
    let dir = out_dir(args, problem.name())?;
    let steps = sweep::step_counts(plan.t_end, plan.h_min, plan.h_max, plan.points);
    let tols = sweep::tolerances(plan.tolerances);
    println!(
        "{}: T = {}, {} methods, {} step sizes from h = {:.3e} to {:.3e} ({}–{} steps), {} timed run(s) each",
        problem.description(),
        plan.t_end,
        methods.len(),
        steps.len(),
        plan.t_end / steps[0] as f64,
        plan.t_end / *steps.last().expect("at least one") as f64,
        steps[0],
        steps.last().expect("at least one"),
        plan.repeats
    );
    let rows = sweep::sweep(&setup, &methods, &steps, &tols, plan.repeats);
    output::write_csv(&dir.join("runs.csv"), &rows)?;
    let evals_label = if std::any::TypeId::of::<P>() == std::any::TypeId::of::<LinearHamiltonian>()
    {
        "right-hand-side evaluations (propagator: matrix–vector products)"
    } else {
        "force evaluations"
    };
    let title = format!("{}, T = {:.4}", problem.description(), plan.t_end);
    let files = if rows.iter().any(|r| r.ok()) {
        output::plots(&dir, &rows, &title, evals_label)?
    } else {
        vec![]
    };
    let target = args.target();
    print!("{}", output::summary(&rows, target));
    let what = format!("{}, T = {:.4}", problem.description(), plan.t_end);
    print!("{}", output::time_to_error_table(&rows, target, &what));
    let over = run_length(problem, plan.t_end);
    let head = report_head(problem, plan, &methods, &steps, &tols);
    let md = report::sweep_report(
        &format!("Work–precision sweep: {}", problem.description()),
        &head,
        &rows,
        target,
        &over,
    );
    std::fs::write(dir.join("report.md"), md)
        .with_context(|| format!("writing {}", dir.join("report.md").display()))?;
    println!(
        "wrote {} ({} rows)",
        dir.join("runs.csv").display(),
        rows.len()
    );
    for f in files {
        println!("wrote {}", dir.join(f).display());
    }
    println!("wrote {}", dir.join("report.md").display());
    Ok(())
}

/// `T = 628.3185` (and the orbits of period 2π on Kepler).
fn run_length(problem: ProblemId, t_end: f64) -> String {
    let orbits = t_end / (2.0 * std::f64::consts::PI);
    if matches!(problem, ProblemId::Kepler | ProblemId::KeplerHard) {
        format!("T = {t_end:.4} ({orbits:.4} orbits)").replace(".0000 orbits", " orbits")
    } else {
        format!("T = {t_end:.4}")
    }
}

/// The head of `report.md`: the problem, the run length, the sweep.
fn report_head<P: Problem>(
    problem: ProblemId,
    plan: &Plan,
    methods: &[Method<P>],
    steps: &[u64],
    tols: &[f64],
) -> Vec<String> {
    let fixed = methods
        .iter()
        .filter(|m| matches!(m, Method::Fixed(_)))
        .count();
    let peer = methods.iter().any(|m| matches!(m, Method::Dop853));
    let first = steps[0];
    let last = *steps.last().expect("at least one");
    let mut head = vec![
        format!(
            "Problem: {} (`{}`), {}; relative error ‖z(T) − z_ref(T)‖₂/‖z_ref(T)‖₂ at the end",
            problem.description(),
            problem.name(),
            run_length(problem, plan.t_end)
        ),
        format!(
            "Sweep: {fixed} fixed-step method(s) at {} step counts from {first} to {last} \
             (h = {:.3e} … {:.3e}, log-spaced)",
            steps.len(),
            plan.t_end / first as f64,
            plan.t_end / last as f64
        ),
    ];
    if peer {
        head.push(format!(
            "Peer: dop853 (ode_solvers) at {} tolerances rtol = atol from {:.0e} to {:.0e} (log-spaced)",
            tols.len(),
            tols[0],
            tols.last().expect("at least one")
        ));
    }
    head.push(format!(
        "Timing: median of {} timed run(s) after one warm-up, one run at a time; {}",
        plan.repeats,
        if cfg!(debug_assertions) {
            "a debug build, so the times are not representative"
        } else {
            "a release build"
        }
    ));
    head.push("Data: runs.csv and the error_vs_*.svg plots in this directory".into());
    head
}

fn long_runs(args: &CompareArgs) -> Result<()> {
    let Some(problem) = args.problem else {
        bail!("--long needs --problem kepler, oscillator or henon-heiles");
    };
    if args.methods.is_some() {
        bail!(
            "--long compares fixed pairs (leapfrog/heun, forest-ruth/rk4, gauss2/rk4); --methods does not apply"
        );
    }
    for (set, name) in [
        (args.t_end.is_some(), "t-end"),
        (args.h_min.is_some(), "h-min"),
        (args.h_max.is_some(), "h-max"),
        (args.points.is_some(), "points"),
    ] {
        if set {
            bail!("--{name} belongs to the work-precision sweep, not to --long (use --steps)");
        }
    }
    let n = args
        .steps
        .unwrap_or(if args.quick { 10_000 } else { 1_000_000 });
    if !(1000..=10_000_000).contains(&n) {
        bail!("--steps must be between 1000 and 10^7, got {n}");
    }
    let h = 0.01;
    let t = n as f64 * h;
    let runs = match problem {
        ProblemId::Kepler => long::run(&problem::kepler(problem, t, false), h, n)?,
        ProblemId::Oscillator => long::run(&problem::oscillator(t, false), h, n)?,
        ProblemId::HenonHeiles => long::run(&problem::henon_heiles(t, false), h, n)?,
        other => bail!(
            "--long runs on kepler, oscillator or henon-heiles, not on {}",
            other.name()
        ),
    };
    let dir = out_dir(args, problem.name())?;
    long::write(&dir, &runs)?;
    println!("{}: {n} steps of h = {h} (T = {t})", problem.description());
    print!("{}", long::summary(&runs));
    for f in ["long.csv", "long_fit.csv", "long_energy.svg"] {
        println!("wrote {}", dir.join(f).display());
    }
    Ok(())
}

fn hard_methods<P: Problem>(
    args: &CompareArgs,
    problem: ProblemId,
    notes: &mut Vec<String>,
    name: &str,
) -> Result<Vec<problem::Fixed<P>>> {
    let ids = match method_ids(args)? {
        Some(ids) => ids,
        None if args.quick => match problem {
            ProblemId::Gyroscopic => {
                vec!["rk4".into(), "gauss2".into(), "gauss2-propagator".into()]
            }
            _ => vec!["leapfrog".into(), "rk4".into(), "gauss2".into()],
        },
        None => P::all_methods(problem)
            .into_iter()
            .filter(|m| m != "dop853")
            .collect(),
    };
    let mut out = Vec::new();
    for id in ids {
        match P::method(&id, problem) {
            Ok(Method::Fixed(f)) => out.push(f),
            Ok(Method::Dop853) => notes.push(format!(
                "dop853 skipped on {name}: adaptive, it has no step size"
            )),
            Err(e) if args.methods.is_some() && !e.to_string().starts_with("unknown") => {
                notes.push(format!("{id} skipped on {name}: {e}"))
            }
            Err(e) => return Err(e),
        }
    }
    Ok(out)
}

fn hard_cases(args: &CompareArgs) -> Result<()> {
    for (set, name) in [
        (args.t_end.is_some(), "t-end"),
        (args.h_min.is_some(), "h-min"),
        (args.h_max.is_some(), "h-max"),
        (args.points.is_some(), "points"),
    ] {
        if set {
            bail!("--{name} belongs to the work-precision sweep, not to --hard");
        }
    }
    if let Some(p) = args.problem
        && !matches!(
            p,
            ProblemId::Fpu | ProblemId::KeplerHard | ProblemId::Gyroscopic
        )
    {
        bail!(
            "--hard covers fpu, kepler-hard and gyroscopic, not {}",
            p.name()
        );
    }
    let wanted = |p: ProblemId| args.problem.is_none_or(|q| q == p);
    let (tolerance, floor) = if args.quick {
        (0.05, 1e-4)
    } else {
        (0.01, 1e-6)
    };
    let mut rows = Vec::new();
    let mut notes = vec![];
    if wanted(ProblemId::Fpu) {
        let name = "fpu (ω = 50)";
        let setup = problem::fpu(10.0, false);
        let omega = setup.sys.omega;
        notes.push(format!("{name}: T = 10, h·ω_max with ω_max = {omega}"));
        let methods = hard_methods(args, ProblemId::Fpu, &mut notes, name)?;
        let case = hard::Case {
            name,
            setup,
            h0: 0.01,
            omega_max: Some(omega),
        };
        rows.extend(hard::run_case(&case, &methods, tolerance, floor));
    }
    if wanted(ProblemId::KeplerHard) {
        let name = "kepler (e = 0.9)";
        let t = 20.0 * std::f64::consts::PI;
        notes.push(format!(
            "{name}: T = 20π (10 orbits); no single frequency, so no h·ω_max"
        ));
        let methods = hard_methods(args, ProblemId::KeplerHard, &mut notes, name)?;
        let case = hard::Case {
            name,
            setup: problem::kepler(ProblemId::KeplerHard, t, false),
            h0: 0.01,
            omega_max: None,
        };
        rows.extend(hard::run_case(&case, &methods, tolerance, floor));
    }
    if wanted(ProblemId::Gyroscopic) {
        let name = "gyroscopic (n = 10, spread 1e4)";
        let setup = problem::gyroscopic(10, 1, 1e4, 1.0, false)?;
        let omega = problem::omega_max(&setup.sys);
        notes.push(format!(
            "{name}: gyroscopic(10, seed 1, spread 1e4), q(0) = 0, p(0) = 1, T = 1, ω_max = {omega:.2} (power iteration)"
        ));
        let methods = hard_methods(args, ProblemId::Gyroscopic, &mut notes, name)?;
        let case = hard::Case {
            name,
            setup,
            h0: 1e-4,
            omega_max: Some(omega),
        };
        rows.extend(hard::run_case(&case, &methods, tolerance, floor));
    }
    let dir = out_dir(args, "hard")?;
    hard::write(&dir, &rows, &notes)?;
    print!("{}", hard::markdown(&rows, &notes));
    println!("wrote {}", dir.join("hard.csv").display());
    println!("wrote {}", dir.join("hard.md").display());
    Ok(())
}
