//! `symlab cloth SCENE.toml`: the command-line client of the cloth job
//! ([`jobs::cloth`], which plans the run, guards its energy, replays a
//! blow-up, writes `energy.csv`, the energy plot, OBJ frames, PNG renderings
//! and checkpoints, and composes the summary). This module reads the flags
//! into the job's request, draws the progress bar, turns SIGINT and SIGTERM
//! into a stop, and prints the outcome.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use integrator_core::checkpoint::{Every, parse_every};
use jobs::cloth::equal_stretch::EqualStretchRequest;
use jobs::cloth::stability::StabilityRequest;
use jobs::cloth::{Job, Observer, Outcome, Request, SceneSource, Stop};

/// Arguments of `symlab cloth`.
#[derive(Args, Debug)]
pub struct ClothArgs {
    /// The scene file (TOML; see scenes/ and the cloth crate's documentation).
    pub scene: PathBuf,
    /// The method (default: the scene's): any id of `symlab list` — an
    /// explicit scheme (symplectic-euler-a, stormer-verlet, leapfrog,
    /// forest-ruth, …, euler, rk4) steps directly, an implicit table or pair
    /// (gauss2, implicit-euler, radau2a-3, lobatto3a3b-4, …) through the
    /// sparse stage solver, the midpoint family (midpoint, gauss1,
    /// paper-dirk2, paper-dirk4) as energy minimisations — or an
    /// energy-conserving comparison scheme (avf, a minimisation;
    /// discrete-gradient).
    #[arg(long, value_name = "NAME", allow_hyphen_values = true)]
    pub method: Option<String>,
    /// Frames to simulate after the initial one (default: the scene's; at
    /// most 10⁶, and at most 10⁹ steps in all).
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = count_parser(0))]
    pub frames: Option<usize>,
    /// Steps per frame (default: the scene's); under a variable step
    /// (`simulation.step = "variable"`, the default of an inextensible
    /// scene) the fewest a frame may take.
    #[arg(long, value_name = "K", conflicts_with = "dt", allow_hyphen_values = true, value_parser = count_parser(1))]
    pub substeps: Option<usize>,
    /// The step size in seconds instead of --substeps: the frame is split
    /// into round(1/(frame_rate·H)) steps and the frame rate adjusted
    /// slightly so that the step is exactly H (one step per frame when H is
    /// longer than a frame).
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    pub dt: Option<f64>,
    /// Output directory (default: out/cloth/<scene-name>/, apart from
    /// `symlab paper`'s out/paper/).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write an OBJ file every N frames (and always the last); 0: none.
    #[arg(long, value_name = "N", default_value_t = 10, allow_hyphen_values = true, value_parser = count_parser(0))]
    pub obj_every: usize,
    /// Frames to render as PNG, comma-separated (default: first, middle and
    /// last), or "none".
    #[arg(long, value_name = "FRAME,FRAME,...", allow_hyphen_values = true)]
    pub render: Option<String>,
    /// Override the resolution: NX×NY particles, e.g. 64x64 (the scene is
    /// otherwise unchanged: same size, material and pins); at most 2²²
    /// particles (2048 × 2048).
    #[arg(long, value_name = "NXxNY", allow_hyphen_values = true)]
    pub grid: Option<String>,
    /// Instead of a run: the largest stable step of each method, by bisection
    /// on h over --duration simulated seconds ("stable": the run finishes,
    /// no NaN, Newton converges, and the relative energy error stays within
    /// --tolerance at every frame), beside the linear estimate 2/ω_max;
    /// writes stability.csv.
    #[arg(long)]
    pub stability: bool,
    /// Instead of a run, on an inextensible scene: the spring model against
    /// the constrained one at equal stretch. The warp and weft become
    /// stretch springs (Störmer–Verlet at substeps = "auto"), their
    /// stiffness found by trials so that no warp or weft edge stretches by
    /// more than 1 % at any step of the run; then both models (RATTLE
    /// without and with the scene's bending) are run --frames frames
    /// (default: the scene's) and timed. Prints a table, writes
    /// equal_stretch.csv.
    #[arg(
        long,
        conflicts_with_all = [
            "stability", "method", "substeps", "dt", "tolerance", "solver",
            "render", "obj_every", "checkpoint_every",
        ]
    )]
    pub equal_stretch: bool,
    /// Of a run of the midpoint family (midpoint, paper-dirk2, paper-dirk4),
    /// avf or discrete-gradient: the minimisation solver's convergence
    /// tolerance, ‖∇Φ‖_∞ relative to the force scale (default 1e-12; 1e-15
    /// to 1). With
    /// --stability: the largest relative energy error |H − H₀|/E_ref a
    /// stable run may show (default 0.1).
    #[arg(long, value_name = "X", allow_hyphen_values = true)]
    pub tolerance: Option<f64>,
    /// The solver of the midpoint family's steps, each an energy
    /// minimisation: newton (exact or PSD-projected Hessian, line search, sparse
    /// Cholesky; the default) or local-global (Liu et al. 2013; no colliders).
    /// Also used by --stability's trials of those methods; refused when no
    /// method of the run is a minimisation.
    #[arg(long, value_name = "NAME", allow_hyphen_values = true)]
    pub solver: Option<String>,
    /// With --stability: simulated seconds per trial run (1e-6 to 1e6).
    #[arg(
        long,
        value_name = "T",
        default_value_t = 1.0,
        requires = "stability",
        allow_hyphen_values = true
    )]
    pub duration: f64,
    /// With --stability: the methods to test, comma-separated (default: the
    /// explicit symplectic ones, euler, rk4, gauss2, midpoint, implicit-euler).
    #[arg(
        long,
        value_name = "NAME,NAME,...",
        requires = "stability",
        allow_hyphen_values = true
    )]
    pub methods: Option<String>,
    /// Write a checkpoint (DIR/checkpoint.symlab, atomically) every
    /// DURATION of wall-clock time, from which `symlab resume DIR`
    /// continues the run to the same bits: e.g. 30s, 5m, 1h, 0 (after every
    /// frame) or off. Default 60s; SIGINT and SIGTERM always write one and
    /// stop (exit 130, 143). RATTLE runs (inextensible scenes) only, for now.
    #[arg(long, value_name = "DURATION", value_parser = parse_every)]
    pub checkpoint_every: Option<Every>,
}

/// Exit code of a run that blew up or whose Newton iteration failed.
const EXIT_RUN_FAILED: u8 = 1;

/// A clap value parser for a whole number of at least `min`, whose errors
/// say what was expected (clap names the flag): `--frames -1` is "must be
/// a whole number ≥ 0", not "unexpected argument '-1'".
fn count_parser(min: usize) -> impl Fn(&str) -> Result<usize, String> + Clone {
    move |text: &str| {
        let t = text.trim();
        match t.parse::<usize>() {
            Ok(n) if n >= min => Ok(n),
            Ok(n) => Err(format!("must be at least {min} (got {n})")),
            Err(_) if t.parse::<i128>().is_ok_and(|n| n < 0) || t.starts_with('-') => {
                Err(format!("must be a whole number ≥ {min}, not negative"))
            }
            Err(_) if !t.is_empty() && t.chars().all(|c| c.is_ascii_digit()) => Err(format!(
                "too large (the largest is {}; runs are limited to {} frames and {} steps)",
                usize::MAX,
                cloth::MAX_FRAMES,
                cloth::MAX_STEPS
            )),
            Err(_) => Err(format!("expected a whole number ≥ {min}")),
        }
    }
}

/// `symlab cloth`.
pub fn run(args: &ClothArgs) -> Result<ExitCode> {
    let scene = SceneSource::File(args.scene.clone());
    if args.equal_stretch {
        let table = jobs::cloth::equal_stretch::run(&EqualStretchRequest {
            scene,
            grid: args.grid.clone(),
            frames: args.frames,
            out: args.out.clone(),
        })?;
        print!("{table}");
        return Ok(ExitCode::SUCCESS);
    }
    if args.stability {
        let methods = args.methods.as_ref().map(|list| {
            list.split(',')
                .map(str::trim)
                .filter(|s| !s.is_empty())
                .map(str::to_string)
                .collect()
        });
        let table = jobs::cloth::stability::run(&StabilityRequest {
            scene,
            grid: args.grid.clone(),
            out: args.out.clone(),
            methods,
            duration: args.duration,
            tolerance: args.tolerance,
            solver: args.solver.clone(),
        })?;
        print!("{table}");
        return Ok(ExitCode::SUCCESS);
    }
    let request = Request {
        method: args.method.clone(),
        frames: args.frames,
        substeps: args.substeps,
        dt: args.dt,
        grid: args.grid.clone(),
        out: args.out.clone(),
        obj_every: args.obj_every,
        render: args.render.clone(),
        tolerance: args.tolerance,
        solver: args.solver.clone(),
        checkpoint_every: args.checkpoint_every,
        ..Request::new(scene)
    };
    run_job(jobs::cloth::plan(&request)?)
}

/// `symlab resume DIR` of a cloth run.
pub fn resume(dir: &std::path::Path, path: &std::path::Path, payload: &[u8]) -> Result<ExitCode> {
    run_job(jobs::cloth::resume(dir, path, payload)?)
}

/// Run a planned job with the bar and the signals, and print its outcome.
fn run_job(job: Job) -> Result<ExitCode> {
    // From here on the loop polls for SIGINT and SIGTERM between frames.
    crate::signals::install();
    let mut front = Front { bar: None };
    let outcome = job.run(&mut front)?;
    let note = |n: &String| eprintln!("note: {n}");
    match outcome {
        Outcome::Finished { summary, notes, .. } => {
            notes.iter().for_each(note);
            print!("{summary}");
            Ok(ExitCode::SUCCESS)
        }
        Outcome::BlownUp {
            error,
            lines,
            notes,
        } => {
            eprintln!("error: {error}");
            lines.iter().for_each(|l| eprintln!("{l}"));
            notes.iter().for_each(note);
            Ok(ExitCode::from(EXIT_RUN_FAILED))
        }
        Outcome::Stopped { text, notes, .. } => {
            notes.iter().for_each(note);
            print!("{text}");
            let sig = crate::signals::requested().unwrap_or(15);
            Ok(ExitCode::from(crate::signals::exit_status(sig)))
        }
    }
}

/// The command line's observer: the bar (on a terminal), and a stop when a
/// signal came.
struct Front {
    bar: Option<ProgressBar>,
}

impl Observer for Front {
    fn start(&mut self, frames: usize, done: usize) {
        if !std::io::stderr().is_terminal() {
            return;
        }
        let bar = ProgressBar::new(frames as u64);
        if let Ok(style) =
            ProgressStyle::with_template("{bar:30} {pos}/{len} frames  {msg}  [{elapsed} < {eta}]")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.inc(done as u64);
        self.bar = Some(bar);
    }
    fn frame(&mut self, frame: &cloth::Frame<'_>) {
        if let (Some(bar), true) = (&self.bar, frame.stats.frame > 0) {
            bar.inc(1);
            bar.set_message(format!("t = {:.3} s", frame.stats.time));
        }
    }
    fn stop_requested(&mut self) -> Option<Stop> {
        crate::signals::requested().map(|sig| Stop {
            reason: crate::signals::name(sig).to_string(),
        })
    }
    fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}
