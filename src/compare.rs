//! `symlab compare`: the command-line client of the comparison library
//! (the `compare` crate, which documents the experiments, the columns of
//! `runs.csv` and the report). This module parses the flags into a
//! [`compare::mode::Mode`] and its request, calls the library (which
//! resolves the methods, runs the mode and checks what it was given,
//! naming the flags), and draws the progress bar, saves checkpoints and
//! prints what the library returns.
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
use compare::mode::{Mode, ModeRequest, SweepJob, SweepProblem};
use compare::sweep::{Checkpoint, CheckpointSaver};
use compare::sweep_plan::{DEFAULT_TARGET, SweepRequest};
use compare::{CompareError, RowControl};

pub(crate) fn problem_id(s: &str) -> std::result::Result<Builtin, String> {
    Builtin::from_name(s).map_err(|_| {
        format!(
            "the built-in problems are {}",
            Builtin::ALL.map(Builtin::name).join(", ")
        )
    })
}

/// The settings of a work–precision sweep: the same flags, with the same
/// meaning, for `symlab compare` and `symlab design … --compare PROBLEM`
/// (the one place that turns them into the library's [`SweepRequest`]).
#[derive(clap::Args, Clone, Debug, Default)]
pub struct SweepFlags {
    /// End time (default per problem, e.g. 20π = 10 orbits for Kepler).
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    /// Smallest step size of the sweep.
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    pub h_min: Option<f64>,
    /// Largest step size of the sweep.
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    pub h_max: Option<f64>,
    /// Number of step sizes (log-spaced; default 10), also the number of
    /// DOP853 tolerances (default 15, one per decade from 1e-4 to 1e-18).
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub points: Option<usize>,
    /// Timed runs per point (the median is reported), after one warm-up.
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub repeats: Option<usize>,
    /// Error for the time-to-error table (default 1e-8); --peer-study adds
    /// it to its targets 1e-6, 1e-8, 1e-10.
    #[arg(long, value_name = "E", allow_hyphen_values = true)]
    pub target: Option<f64>,
}

impl SweepFlags {
    /// The library's request of these flags (`quick`: a smoke run).
    pub fn request(&self, quick: bool) -> SweepRequest {
        SweepRequest {
            t_end: self.t_end,
            h_min: self.h_min,
            h_max: self.h_max,
            points: self.points,
            repeats: self.repeats,
            target: self.target,
            quick,
            ..SweepRequest::default()
        }
    }
}

#[derive(clap::Args)]
#[command(after_help = compare::mode::HELP)]
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
    /// outer-solar), interp:ID (a `symlab list` table stepped by the
    /// run-time interpreter, as --table files are, so that their times
    /// compare).
    #[arg(long, value_delimiter = ',', value_name = "ID,...")]
    methods: Option<Vec<String>>,
    /// A table file (TOML, as for `symlab check`) to add to the sweep: its
    /// claims are verified exactly, then it is stepped by the run-time
    /// interpreter (rows marked interpreted); `wh:FILE` steps a drift–kick
    /// sequence or composition on the Wisdom–Holman split (outer-solar) as
    /// the row wh:STEM, as the wh: methods are stepped. Repeatable.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["long", "hard", "peer_study", "from"])]
    table: Vec<PathBuf>,
    #[command(flatten)]
    sweep: SweepFlags,
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
    /// The request of the peer study, the long runs or the hard cases (the
    /// first flag of the work-precision sweep given, which they refuse).
    fn mode_request(&self) -> Result<ModeRequest> {
        let request = self.sweep.request(false);
        let sweep_value = request.sweep_only_given().map(str::to_string);
        Ok(ModeRequest {
            problem: self.problem,
            methods: method_ids(self)?,
            steps: self.steps,
            repeats: self.sweep.repeats,
            target: self.sweep.target,
            quick: self.quick,
            sweep_value,
        })
    }
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

/// `--methods`, each id once.
fn method_ids(args: &CompareArgs) -> Result<Option<Vec<String>>> {
    let list = args
        .methods
        .as_deref()
        .map(|l| compare::sweep_plan::method_list("--methods", l));
    Ok(list.transpose()?)
}

/// `symlab compare`: `argv` are the arguments after `compare`, kept in a
/// sweep's checkpoint so that `symlab resume` plans the same sweep.
pub fn run(args: &CompareArgs, argv: &[String]) -> Result<ExitCode> {
    run_or_resume(args, argv, vec![])
}

fn run_or_resume(args: &CompareArgs, argv: &[String], done: Vec<compare::Row>) -> Result<ExitCode> {
    use integrator_core::checkpoint::{DEFAULT_EVERY, Every};
    let start = Instant::now();
    let every = match args.checkpoint_every {
        None => Some(DEFAULT_EVERY),
        Some(Every::Off) => None,
        Some(Every::After(d)) => Some(d),
    };
    let mode = Mode::of_flags(args.peer_study, args.hard, args.long);
    if args.checkpoint_every.is_some() && (mode != Mode::Sweep || args.from.is_some()) {
        bail!(
            "--checkpoint-every: only work-precision sweeps (--problem, --problem-file) are checkpointed"
        );
    }
    if let Some(t) = args.sweep.target {
        compare::sweep_plan::positive("--target", t)?;
    }
    if args.sweep.repeats == Some(0) {
        bail!("--repeats must be at least 1");
    }
    if let Some(path) = &args.from {
        print!(
            "{}",
            compare::output::summary_of_file(path, args.sweep.target.unwrap_or(DEFAULT_TARGET))?
        );
        return Ok(ExitCode::SUCCESS);
    }
    match mode {
        Mode::PeerStudy => {
            let settings = compare::mode::peer_study_settings(&args.mode_request()?)?;
            let dir = out_dir(args, "peer")?;
            let study = compare::peer_study::run(settings, &mut SweepFront::new(None))?;
            for n in &study.notes {
                eprintln!("note: {n}");
            }
            study.write(&dir)?;
            print!("{}", study.verdict());
            let rows = study.rows().0.len();
            println!("wrote {} ({rows} rows)", dir.join("peer.csv").display());
            println!("wrote {}", dir.join("peer.md").display());
        }
        Mode::Hard => {
            let study = compare::mode::hard(&args.mode_request()?)?;
            let dir = out_dir(args, "hard")?;
            let files = study.write(&dir)?;
            print!("{}", study.markdown());
            files.iter().for_each(|f| println!("wrote {}", f.display()));
        }
        Mode::Long => {
            let study = compare::mode::long(&args.mode_request()?)?;
            let dir = out_dir(args, &study.dir)?;
            let files = study.write(&dir)?;
            println!("{}", study.title);
            print!("{}", study.summary());
            files.iter().for_each(|f| println!("wrote {}", f.display()));
        }
        Mode::Sweep => {
            if let Some(code) = sweep(args, argv, every, done)? {
                return Ok(code);
            }
        }
    }
    println!("done in {:.1} s", start.elapsed().as_secs_f64());
    Ok(ExitCode::SUCCESS)
}

/// A sweep's outcome: `Some(status)` when a signal stopped it.
type Stopped = Option<ExitCode>;

/// A work-precision sweep of `--problem` or `--problem-file`: planned and
/// its methods resolved by the library, its rows saved here as they come.
fn sweep(
    args: &CompareArgs,
    argv: &[String],
    every: Option<std::time::Duration>,
    done: Vec<compare::Row>,
) -> Result<Stopped> {
    if args.steps.is_some() {
        bail!("--steps belongs to --long");
    }
    let problem = match (&args.problem_file, args.problem) {
        (Some(path), _) => SweepProblem::File(path.clone()),
        (None, Some(problem)) => SweepProblem::Builtin(problem),
        (None, None) => bail!(
            "--problem is required: oscillator, gyroscopic, kepler, kepler-hard, henon-heiles, fpu or pendulum (or --problem-file FILE)"
        ),
    };
    let job = SweepJob {
        problem,
        request: args.sweep.request(args.quick),
        methods: method_ids(args)?,
        tables: args.table.clone(),
    };
    let sweep = compare::mode::prepare_sweep(job).map_err(|e| match e {
        CompareError::DuplicateMethod {
            id,
            index,
            added: true,
        } => anyhow::anyhow!(
            "--table {}: the method id '{id}' (the file name) is taken; rename the file",
            args.table[index].display()
        ),
        e => e.into(),
    })?;
    let dir = out_dir(args, sweep.name())?;
    integrator_core::checkpoint::check_writable(&dir)?;
    let ckpt = dir.join(integrator_core::checkpoint::FILE_NAME);
    let resuming = !done.is_empty();
    if !resuming {
        integrator_core::checkpoint::remove(&ckpt)?;
    }
    println!("{}", sweep.headline());
    if resuming {
        println!("resuming: {} rows done are not run again", done.len());
    }
    crate::signals::install();
    let saver = CheckpointSaver::new(&ckpt, argv, every);
    let mut front = SweepFront::new(Some(saver));
    let (result, stopped) = sweep.run(done, &mut front)?;
    if let Some(e) = front.failed {
        return Err(e);
    }
    if stopped {
        let sig = crate::signals::requested().unwrap_or(15);
        println!(
            "stopped by {} after {} rows ({} methods planned)",
            crate::signals::name(sig),
            result.rows.len(),
            result.methods.len()
        );
        if front.saver.and_then(|s| s.saved_rows) == Some(result.rows.len()) {
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
    print!("{}", result.wrote(&files));
    Ok(None)
}

/// What the command line does while a sweep runs: the bar (on a
/// terminal), each stage's line on standard output and, for a sweep that
/// saves, its checkpoints and the stop at a signal.
struct SweepFront {
    bar: indicatif::ProgressBar,
    saver: Option<CheckpointSaver>,
    /// A checkpoint that could not be written (the sweep stops).
    failed: Option<anyhow::Error>,
}

impl SweepFront {
    /// The bar is drawn on a terminal only.
    fn new(saver: Option<CheckpointSaver>) -> Self {
        use std::io::IsTerminal;
        let bar = if std::io::stderr().is_terminal() {
            let bar = indicatif::ProgressBar::new(0);
            if let Ok(style) =
                indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg} [{elapsed}]")
            {
                bar.set_style(style);
            }
            bar
        } else {
            indicatif::ProgressBar::hidden()
        };
        SweepFront {
            bar,
            saver,
            failed: None,
        }
    }
}

impl compare::SweepObserver for SweepFront {
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
    fn row(&mut self, rows: &[compare::Row], fresh: bool) -> RowControl {
        self.bar.inc(1);
        let Some(saver) = self.saver.as_mut().filter(|_| fresh) else {
            return RowControl::Continue;
        };
        let stopping = crate::signals::requested().is_some();
        if let Err(e) = saver.row(rows, fresh, stopping) {
            self.failed = Some(e.into());
            return RowControl::Stop;
        }
        if stopping {
            RowControl::Stop
        } else {
            RowControl::Continue
        }
    }
    fn finish(&mut self) {
        self.bar.finish_and_clear();
    }
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
    let Checkpoint { argv, rows } = Checkpoint::read(path, payload)?;
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
    run_or_resume(&args, &argv, rows)
}
