//! `symlab cloth SCENE.toml`: run a cloth scene with any method that steps
//! cloth (explicit library schemes, the implicit ones through the sparse
//! stage solver, the midpoint family and the energy-conserving schemes as
//! minimisations), writing `energy.csv`, an energy plot, OBJ frames and PNG
//! renderings to `out/cloth/<scene-name>/`, and printing a one-screen
//! summary; or, with `--stability`, the largest stable step of each method.
//!
//! This module parses the flags, shows progress, formats and writes: the
//! runs, the energy guard, the blow-up replay, the reference energy and the
//! regridding are the cloth crate's.

mod checkpoint;
pub(crate) mod energy;
mod render;
mod stability;
mod summary;

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use cloth::scene::GridError;
use cloth::schedule::{Asked, RunRequest, schedule};
use cloth::study::energy::{reference_energy, relative_errors};
use cloth::study::growth::Growth;
use cloth::study::stability::{StabilityError, StabilitySettings};
use cloth::{
    EnergyGuard, FrameStats, Method, MinimiseSettings, RunError, RunOptions, RunReport,
    RunSettings, Scene, Simulation, Solver, Vec3,
};
use indicatif::{ProgressBar, ProgressStyle};

use summary::Summary;

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
    /// Steps per frame (default: the scene's).
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
    #[arg(long, value_name = "DURATION", value_parser = checkpoint::parse_every)]
    pub checkpoint_every: Option<checkpoint::Every>,
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

/// `symlab cloth`: `argv` are the arguments after `cloth`, kept in the
/// checkpoint so that `symlab resume` plans the same run.
pub fn run(args: &ClothArgs, argv: &[String]) -> Result<ExitCode> {
    run_or_resume(args, argv, None)
}

/// A run, fresh or continued from `resumed` (whose scene text replaces the
/// file's: the run goes on with the scene it started with).
fn run_or_resume(
    args: &ClothArgs,
    argv: &[String],
    resumed: Option<checkpoint::Resumed>,
) -> Result<ExitCode> {
    let file = args.scene.display().to_string();
    let (scene, scene_text) = match &resumed {
        Some(r) => (
            scene_from_text(args, &r.scene_file, &r.scene_text)?,
            r.scene_text.clone(),
        ),
        None => {
            let scene = load_scene(args, &file)?;
            let text = std::fs::read_to_string(&args.scene)
                .with_context(|| format!("{file}: cannot read the scene again"))?;
            (scene, text)
        }
    };
    let settings = minimise_settings(args)?;
    if args.stability {
        return run_stability(args, &scene, &file, settings);
    }
    let (method, from) = match &args.method {
        Some(m) => (parse_method(m, "--method")?, format!("--method {m}")),
        None => {
            // The scene's method was checked when the scene was read.
            let m = Method::parse(&scene.simulation.method)
                .map_err(|e| anyhow!("{file}: simulation.method: {e}"))?;
            (m, format!("{file}: simulation.method {}", m.id()))
        }
    };
    check_applicable(&method, &from, &scene, &file, settings.solver)?;
    check_solver_applies(args, &[method])?;
    let (opts, note) = run_options(&scene, args, &file)?;
    let renders = render_frames(args.render.as_deref(), opts.frames)?;
    // Build the model (proportional to the springs), refusing a scene
    // whose initial state is not finite, naming the field.
    let sim = Simulation::new(&scene).map_err(|e| anyhow!("{}", rename(&e, &file)))?;
    if !method.explicit() {
        cloth::step::stage::check_size(&sim.model).map_err(|e| {
            let from = match (&args.method, &args.grid) {
                (Some(m), _) => format!("--method {m}"),
                (None, Some(g)) => format!("--grid {g}"),
                (None, None) => format!("{file}: simulation.method"),
            };
            anyhow!("{from}: {e}")
        })?;
    }
    let e_ref = reference_energy(&scene, &sim).map_err(|e| anyhow!("{file}: {e}"))?;
    let dir = output_dir(args, &scene)?;
    let render_failure = args.render.as_deref().map(str::trim) != Some("none");
    let every = checkpoint::interval(args.checkpoint_every, &method)?;
    let saving = checkpoint::Saving {
        argv: argv.to_vec(),
        scene_file: file.clone(),
        scene_text,
        every,
    };
    simulate(
        sim,
        &saving,
        resumed,
        &Plan {
            scene: &scene,
            method,
            settings: RunSettings::new(opts)
                .with_minimise(settings)
                .with_guard(EnergyGuard::new(e_ref)),
            renders: &renders,
            render_failure,
            obj_every: args.obj_every,
            dir: &dir,
            note,
        },
    )
}

/// The scene file, at the `--grid` resolution if one is given (checked
/// against the particle limit before anything is built).
fn load_scene(args: &ClothArgs, file: &str) -> Result<Scene> {
    // Library errors print their cause in their own message: pass the
    // message on, not the chain (which would print the cause twice).
    let scene = Scene::load(&args.scene).map_err(|e| anyhow!("{e}"))?;
    regrid(args, scene, file)
}

/// The scene a checkpoint saved, as [`load_scene`] reads a file.
fn scene_from_text(args: &ClothArgs, file: &str, text: &str) -> Result<Scene> {
    let scene = Scene::from_toml(text, file).map_err(|e| anyhow!("{e}"))?;
    regrid(args, scene, file)
}

/// `--grid`, if given.
fn regrid(args: &ClothArgs, mut scene: Scene, file: &str) -> Result<Scene> {
    if let Some(grid) = &args.grid {
        let (nx, ny) = cloth::scene::parse_grid(grid).map_err(|e| match e {
            GridError::Syntax(_) => anyhow!("--grid: {e}"),
            GridError::TooLarge(_) => anyhow!("--grid {grid}: {e}"),
        })?;
        cloth::scene::regrid(&mut scene, nx, ny);
        scene
            .validate()
            .map_err(|e| anyhow!("--grid {grid}: {}", rename(&e, file)))?;
    }
    Ok(scene)
}

/// `--stability`: its flags checked, then the search.
fn run_stability(
    args: &ClothArgs,
    scene: &Scene,
    file: &str,
    settings: MinimiseSettings,
) -> Result<ExitCode> {
    let study = StabilitySettings {
        duration: args.duration,
        tolerance: args
            .tolerance
            .unwrap_or(StabilitySettings::default().tolerance),
        minimise: settings,
        ..StabilitySettings::default()
    };
    study.check().map_err(|e| match e {
        StabilityError::Setting { field, message } => {
            anyhow!("--{}: {message}", field.replace('_', "-"))
        }
        other => anyhow!("--stability: {other}"),
    })?;
    let methods = match &args.methods {
        Some(list) => {
            let names: Vec<&str> = list
                .split(',')
                .map(str::trim)
                .filter(|s| !s.is_empty())
                .collect();
            if names.is_empty() {
                bail!("--methods: no method given");
            }
            names
                .iter()
                .map(|m| parse_method(m, "--methods"))
                .collect::<Result<Vec<_>>>()?
        }
        None => stability::default_methods(),
    };
    for m in &methods {
        check_applicable(m, &format!("--methods {m}"), scene, file, settings.solver)?;
    }
    check_solver_applies(args, &methods)?;
    let dir = output_dir(args, scene)?;
    let ids: Vec<String> = methods.iter().map(|m| m.id().to_string()).collect();
    stability::run(scene, file, &ids, &study, &dir)
}

/// A method id that steps cloth, or an error naming the flag and listing
/// those that do.
fn parse_method(id: &str, flag: &str) -> Result<Method> {
    Method::parse(id).map_err(|e| anyhow!("{flag}: {e}"))
}

/// Refuse, before anything runs, a method that cannot step this scene with
/// this solver ([`cloth::step::minimise::applicable`]: the energy schemes
/// and the local/global solver handle no colliders; the energy schemes are
/// solved with Newton only). A run and `--stability` refuse with the same
/// message; `from` names where the method came from.
fn check_applicable(
    method: &Method,
    from: &str,
    scene: &Scene,
    file: &str,
    solver: Solver,
) -> Result<()> {
    let colliders = !scene.colliders.is_empty();
    cloth::step::minimise::applicable(method, colliders, solver).map_err(|why| {
        if let Some(why) = why.strip_prefix("solver: ") {
            anyhow!(
                "--solver {}: {why}{}",
                solver.name(),
                if colliders {
                    format!(" ({file}: colliders)")
                } else {
                    String::new()
                }
            )
        } else {
            let why = why.strip_prefix("method: ").unwrap_or(&why);
            anyhow!("{from}: {why} ({file}: colliders)")
        }
    })
}

/// `--solver` is the minimisation solver's: refused when none of the
/// methods is solved by minimisation, rather than silently ignored.
fn check_solver_applies(args: &ClothArgs, methods: &[Method]) -> Result<()> {
    let Some(solver) = &args.solver else {
        return Ok(());
    };
    if !methods.iter().any(Method::minimises) {
        let list: Vec<&str> = methods.iter().map(Method::id).collect();
        bail!(
            "--solver {solver}: the minimisation solver steps the midpoint family ({}), avf and discrete-gradient; {} {} none of them",
            Method::ids(|m| m.midpoint_weights().is_some()).join(", "),
            list.join(", "),
            if list.len() == 1 { "is" } else { "are" }
        );
    }
    Ok(())
}

/// A scene error as the user's file names it: the model names the scene by
/// its `name`, the user knows the file.
fn rename(e: &cloth::SceneError, file: &str) -> String {
    match e {
        cloth::SceneError::Field { field, message, .. } => format!("{file}: {field}: {message}"),
        other => other.to_string(),
    }
}

/// Frames, substeps and frame rate from the scene and the flags
/// ([`cloth::schedule`], checked against the run limits before anything is
/// built), and a note when the frame rate had to change for --dt; an error
/// names the flag (or the scene's field) that broke the limits.
fn run_options(
    scene: &Scene,
    args: &ClothArgs,
    file: &str,
) -> Result<(RunOptions, Option<String>)> {
    let request = RunRequest {
        frames: args.frames,
        substeps: args.substeps,
        dt: args.dt,
    };
    let plan = schedule(scene, &request).map_err(|e| {
        let from = match (e.asked, args.dt) {
            (Asked::Frames, _) => "--frames".to_string(),
            (Asked::Substeps, _) => "--substeps".to_string(),
            (Asked::Dt, Some(h)) if h > 0.0 && h.is_finite() => format!("--dt {h:e}"),
            (Asked::Dt, _) => "--dt".to_string(),
            (Asked::Scene(field), _) => format!("{file}: simulation.{field}"),
        };
        anyhow!("{from}: {}", e.message)
    })?;
    Ok((plan.options, plan.note))
}

/// The frames to render: the list given, or first, middle and last.
fn render_frames(spec: Option<&str>, frames: usize) -> Result<Vec<usize>> {
    let mut out: Vec<usize> = match spec.map(str::trim) {
        None => vec![0, frames / 2, frames],
        Some("none") | Some("") => Vec::new(),
        Some(list) => {
            let mut v = Vec::new();
            for item in list.split(',') {
                let n: usize = item.trim().parse().with_context(|| {
                    format!(
                        "--render: \"{}\" is not a frame number (expected e.g. 0,150,300 or none)",
                        item.trim()
                    )
                })?;
                if n > frames {
                    bail!("--render: frame {n} is after the last frame ({frames})");
                }
                v.push(n);
            }
            v
        }
    };
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

/// A name that is safe as a directory name.
fn file_safe(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' || c == '.' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || s.chars().all(|c| c == '.') {
        "cloth".to_string()
    } else {
        s
    }
}

fn output_dir(args: &ClothArgs, scene: &Scene) -> Result<PathBuf> {
    let dir = match &args.out {
        Some(d) => d.clone(),
        None => Path::new("out").join("cloth").join(file_safe(&scene.name)),
    };
    std::fs::create_dir_all(&dir).with_context(|| {
        format!(
            "--out: cannot create the output directory {}",
            dir.display()
        )
    })?;
    checkpoint::check_writable(&dir)?;
    Ok(dir)
}

/// Remove what an earlier run left that this one may not overwrite:
/// `frames/frame_*.obj` and `render_*.png`.
fn clear_stale(dir: &Path) -> Result<()> {
    let remove = |d: &Path, prefix: &str, ext: &str| -> Result<()> {
        let Ok(entries) = std::fs::read_dir(d) else {
            return Ok(());
        };
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.starts_with(prefix) && name.ends_with(ext) && entry.path().is_file() {
                std::fs::remove_file(entry.path()).with_context(|| {
                    format!("{}: cannot remove the old file", entry.path().display())
                })?;
            }
        }
        Ok(())
    };
    remove(&dir.join("frames"), "frame_", ".obj")?;
    remove(dir, "render_", ".png")
}

/// What the frame callback collects.
struct Collected {
    stats: Vec<FrameStats>,
    objs: usize,
    /// Positions of the frames to render, with their time.
    kept: BTreeMap<usize, (f64, Vec<Vec3>)>,
}

/// What a run is asked to do and where its output goes.
struct Plan<'a> {
    scene: &'a Scene,
    method: Method,
    /// Frames, substeps, the solvers and the energy guard.
    settings: RunSettings,
    /// Frames to render (sorted).
    renders: &'a [usize],
    /// Whether a run that fails renders its last good frame (not with
    /// `--render none`).
    render_failure: bool,
    obj_every: usize,
    dir: &'a Path,
    /// A note for the summary (the frame rate changed for `--dt`).
    note: Option<String>,
}

/// `--solver` and `--tolerance` (of a run, not of `--stability`).
fn minimise_settings(args: &ClothArgs) -> Result<MinimiseSettings> {
    let solver = match args.solver.as_deref() {
        None => Solver::Newton,
        Some(name) => Solver::parse(name.trim()).with_context(|| {
            format!(
                "--solver: unknown solver \"{name}\"; expected one of {}",
                Solver::NAMES.join(", ")
            )
        })?,
    };
    let mut settings = MinimiseSettings::new(solver);
    if let (false, Some(t)) = (args.stability, args.tolerance) {
        settings = settings
            .with_tolerance(t)
            .map_err(|why| anyhow!("--tolerance: {why}"))?;
    }
    Ok(settings)
}

/// The progress bar: on a terminal only.
fn progress_bar(frames: usize) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(frames as u64);
    if let Ok(style) =
        ProgressStyle::with_template("{bar:30} {pos}/{len} frames  {msg}  [{elapsed} < {eta}]")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// Run the plan, writing OBJ frames and keeping the frames to render as
/// they come, and checkpoints as `saving` says; then the output of a
/// finished run and its summary, of a run that blew up, or of a run a
/// signal stopped. `resumed`: continue the run a checkpoint saved.
fn simulate(
    mut sim: Simulation,
    saving: &checkpoint::Saving,
    resumed: Option<checkpoint::Resumed>,
    plan: &Plan<'_>,
) -> Result<ExitCode> {
    let clock = Instant::now();
    let triangles = sim.model.triangles();
    let ckpt_path = plan.dir.join(cloth::checkpoint::FILE_NAME);
    if resumed.is_none() {
        clear_stale(plan.dir)?;
        // A new run in this folder supersedes an older run's checkpoint.
        checkpoint::remove(&ckpt_path)?;
    }
    let frames_dir = plan.dir.join("frames");
    // From here on the loop polls for SIGINT and SIGTERM between frames.
    crate::signals::install();
    if plan.obj_every > 0 {
        std::fs::create_dir_all(&frames_dir)
            .with_context(|| format!("{}: cannot create the directory", frames_dir.display()))?;
    }
    let opts = plan.settings.options;
    let bar = progress_bar(opts.frames);
    let (col, state, wall_before) = match resumed {
        Some(r) => {
            bar.inc(r.state.frame as u64);
            let col = Collected {
                stats: r.state.frames.clone(),
                objs: r.objs,
                kept: r.kept,
            };
            (col, Some(r.state), r.wall)
        }
        None => {
            let col = Collected {
                stats: Vec::with_capacity(opts.frames.min(1 << 16) + 1),
                objs: 0,
                kept: BTreeMap::new(),
            };
            (col, None, 0.0)
        }
    };
    let col = RefCell::new(col);
    let mut control = checkpoint::Control::new(saving, &ckpt_path, &col, wall_before);
    let every = plan.obj_every;
    let result = sim.run_controlled(
        &plan.method,
        &plan.settings,
        state.as_ref(),
        &mut control,
        |frame| {
            let mut col = col.borrow_mut();
            let k = frame.stats.frame;
            col.stats.push(frame.stats);
            if every > 0 && (k % every == 0 || k == opts.frames) {
                let path = frames_dir.join(format!("frame_{k:04}.obj"));
                cloth::write_obj(&path, &frame.positions(), &triangles)?;
                col.objs += 1;
            }
            if plan.renders.binary_search(&k).is_ok() {
                col.kept.insert(k, (frame.stats.time, frame.positions()));
            }
            if k > 0 {
                bar.inc(1);
                bar.set_message(format!("t = {:.3} s", frame.stats.time));
            }
            Ok(())
        },
    );
    bar.finish_and_clear();
    let wall = wall_before + clock.elapsed().as_secs_f64();
    let report_note = control.note();
    let saved_frame = control.saved_frame;
    let col = col.into_inner();
    // The model checks that the initial state is finite, so frame 0 always
    // reaches the callback; should it not, that is an error about the
    // scene, not a panic.
    let Some(&good) = col.stats.last() else {
        let why = match &result {
            Err(e) => e.to_string(),
            Ok(_) => "no frame was recorded".to_string(),
        };
        bail!(
            "{}: the initial state cannot be simulated: {why}",
            plan.scene.name
        );
    };
    if let Some(n) = report_note {
        eprintln!("note: {n}");
    }
    match result {
        Ok(report) => {
            let code = finished(plan, &sim, &report, &triangles, &col, wall)?;
            // The run is complete: nothing is left to resume.
            checkpoint::remove(&ckpt_path)?;
            Ok(code)
        }
        Err(RunError::Stopped { frame, time }) => {
            checkpoint::stopped(plan, &col, saved_frame, &ckpt_path, frame, time, wall)
        }
        Err(err) if err.is_blowup() => {
            blown_up(plan, &sim, &err, good, &triangles, &frames_dir, col)
        }
        Err(err) => Err(anyhow!("{err}")),
    }
}

/// The energy plot's title.
fn title(plan: &Plan<'_>, name: &str) -> String {
    format!(
        "{} — {name}, h = {:.3e} s",
        plan.scene.name,
        plan.settings.options.step_size()
    )
}

/// A finished run: energy.csv, the energy plot, the renderings, and the
/// summary.
fn finished(
    plan: &Plan<'_>,
    sim: &Simulation,
    report: &RunReport,
    triangles: &[[usize; 3]],
    col: &Collected,
    wall: f64,
) -> Result<ExitCode> {
    let e_ref = guard_reference(plan);
    let mut written = vec!["energy.csv".to_string(), "energy.svg".to_string()];
    cloth::write_energy_csv(plan.dir.join("energy.csv"), &report.frames, e_ref)?;
    energy::plot(
        &plan.dir.join("energy.svg"),
        &report.frames,
        e_ref,
        &title(plan, report.method),
    )?;
    let (names, note_render) =
        render_kept(plan.scene, triangles, &col.kept, plan.dir, plan.method.id())?;
    written.extend(names);
    if let Some(n) = note_render {
        eprintln!("note: {n}");
    }
    let s = Summary {
        scene: plan.scene,
        model: &sim.model,
        method: &plan.method,
        report,
        opts: &plan.settings.options,
        wall,
        e_ref,
        note: plan.note.as_deref(),
        dir: plan.dir,
        objs: col.objs,
        written: &written,
    };
    print!("{}", s.render());
    Ok(ExitCode::SUCCESS)
}

/// What a run that stopped early keeps of its energy: `energy.csv`, and
/// with two frames or more the plot; the names written.
fn energy_files(plan: &Plan<'_>, stats: &[FrameStats]) -> Result<Vec<String>> {
    let e_ref = guard_reference(plan);
    cloth::write_energy_csv(plan.dir.join("energy.csv"), stats, e_ref)?;
    let mut written = vec!["energy.csv".to_string()];
    if stats.len() >= 2 {
        energy::plot(
            &plan.dir.join("energy.svg"),
            stats,
            e_ref,
            &title(plan, plan.method.name()),
        )?;
        written.push("energy.svg".into());
    }
    Ok(written)
}

/// `E_ref` of the plan's energy guard.
fn guard_reference(plan: &Plan<'_>) -> f64 {
    plan.settings.guard.map_or(1.0, |g| g.e_ref)
}

/// A run that blew up (a non-finite state, a failed solve, or the energy
/// guard; the simulation is at the last good frame): keep what was good —
/// energy.csv, the plot, the last good frame as OBJ and PNG — and say what
/// happened and how the energy grew before.
fn blown_up(
    plan: &Plan<'_>,
    sim: &Simulation,
    err: &RunError,
    good: FrameStats,
    triangles: &[[usize; 3]],
    frames_dir: &Path,
    mut col: Collected,
) -> Result<ExitCode> {
    let e_ref = guard_reference(plan);
    let dir = plan.dir;
    let mut written = energy_files(plan, &col.stats)?;
    let positions = sim.model.positions(&sim.state[..sim.state.len() / 2]);
    if plan.obj_every > 0 {
        let path = frames_dir.join(format!("frame_{:04}.obj", good.frame));
        if !path.exists() {
            cloth::write_obj(&path, &positions, triangles)?;
            col.objs += 1;
        }
    }
    if plan.render_failure {
        col.kept.insert(good.frame, (good.time, positions));
    }
    let (names, note_render) =
        render_kept(plan.scene, triangles, &col.kept, dir, plan.method.id())?;
    written.extend(names);
    if col.objs > 0 {
        written.push(format!("{} OBJ in frames/", col.objs));
    }
    eprintln!("error: {err}");
    let growth = energy_growth(&col.stats, e_ref);
    eprintln!("  energy up to the last good frame: {growth}");
    if growth.exponential() {
        eprintln!(
            "  the energy was growing exponentially before the run stopped (see energy.svg): the method is unstable at this step, whatever the solver"
        );
    }
    eprintln!(
        "  output up to the last good frame, {} (t = {:.4} s), was written to {}: {}; nothing after it",
        good.frame,
        good.time,
        dir.display(),
        written.join(", ")
    );
    if let Some(n) = note_render {
        eprintln!("note: {n}");
    }
    Ok(ExitCode::from(EXIT_RUN_FAILED))
}

/// The fitted growth of the relative energy error over `frames`.
fn energy_growth(frames: &[FrameStats], e_ref: f64) -> Growth {
    let times: Vec<f64> = frames.iter().map(|f| f.time).collect();
    cloth::study::growth::fit(&times, &relative_errors(frames, e_ref))
}

/// Render the kept frames with one camera fitted to all of them; the names
/// written, and a note when a picture had to be simplified (see
/// [`cloth::render::Picture::simplified`]).
fn render_kept(
    scene: &Scene,
    triangles: &[[usize; 3]],
    kept: &BTreeMap<usize, (f64, Vec<Vec3>)>,
    dir: &Path,
    method: &str,
) -> Result<(Vec<String>, Option<String>)> {
    if kept.is_empty() {
        return Ok((Vec::new(), None));
    }
    let all: Vec<Vec3> = kept.values().flat_map(|(_, p)| p.iter().copied()).collect();
    let stage = render::Stage::for_grid(scene.colliders.clone(), triangles, scene.cloth.nx);
    let camera = render::Camera::fit(&all, &scene.colliders);
    drop(all);
    let mut names = Vec::new();
    let mut notes = Vec::new();
    for (k, (t, positions)) in kept {
        let name = format!("render_{k:04}.png");
        let caption = format!("{} · {method} · frame {k} · t = {t:.3} s", scene.name);
        if let Some(n) =
            render::render_png_noted(&dir.join(&name), &stage, &camera, positions, &caption)?
        {
            notes.push(format!("{name}: {n}"));
        }
        names.push(name);
    }
    Ok((names, (!notes.is_empty()).then(|| notes.join("; "))))
}

/// `symlab resume DIR` of a cloth run.
pub fn resume(dir: &Path, path: &Path, payload: &[u8]) -> Result<ExitCode> {
    checkpoint::resume(dir, path, payload)
}
