//! `symlab cloth SCENE.toml`: run a cloth scene with any method that steps
//! cloth (explicit library schemes, and the implicit ones through the
//! sparse Newton solver), writing `energy.csv`, an energy plot, OBJ frames
//! and PNG renderings to `out/cloth/<scene-name>/`, and printing a one-screen
//! summary; or, with `--stability`, the largest stable step of each method.

pub(crate) mod energy;
mod growth;
pub(crate) mod render;
mod stability;

use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use cloth::implicit::{self as cloth_implicit};
use cloth::minimise;
use cloth::{FrameStats, RunError, RunOptions, Scene, Simulation, Vec3};
use indicatif::{ProgressBar, ProgressStyle};

/// Arguments of `symlab cloth`.
#[derive(Args, Debug)]
pub struct ClothArgs {
    /// The scene file (TOML; see scenes/ and the cloth crate's documentation).
    pub scene: PathBuf,
    /// The method (default: the scene's): an explicit library scheme
    /// (symplectic-euler-a, stormer-verlet, leapfrog, forest-ruth, …, euler,
    /// rk4), an implicit one (gauss2, implicit-euler, gauss3, radau2a-3
    /// through the sparse stage solver; midpoint, paper-dirk2, paper-dirk4
    /// as energy minimisations), or an energy-conserving comparison scheme
    /// (avf, a minimisation; discrete-gradient).
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

/// The smallest `--tolerance`: a relative energy error below 1e-12 is
/// round-off, which no step size can beat; the search would only halve
/// down to its floor.
const MIN_TOLERANCE: f64 = 1e-12;

/// The range of a run's `--tolerance` (the minimisation solver's ‖∇Φ‖_∞
/// relative to the force scale): the round-off of the force scale is about
/// 1e-16 of it, and a tolerance of the whole scale accepts any guess.
const RUN_TOLERANCE_RANGE: (f64, f64) = (1e-15, 1.0);

/// Shortest and longest `--duration` of a stability trial (s). Below, the
/// trial's step floor `duration/400000` approaches the smallest normal
/// numbers and the search means nothing; above, a trial would be all
/// frames.
const DURATION_RANGE: (f64, f64) = (1e-6, 1e6);

pub fn run(args: &ClothArgs) -> Result<ExitCode> {
    // Library errors print their cause in their own message: pass the
    // message on, not the chain (which would print the cause twice).
    let mut scene = Scene::load(&args.scene).map_err(|e| anyhow!("{e}"))?;
    let file = args.scene.display().to_string();
    if let Some(grid) = &args.grid {
        // Checked against the particle limit before anything is built.
        let (nx, ny) = parse_grid(grid)?;
        regrid(&mut scene, nx, ny);
        scene
            .validate()
            .map_err(|e| anyhow!("--grid {grid}: {}", rename(&e, &file)))?;
    }
    let settings = solver_settings(args)?;
    if args.stability {
        let tolerance = args.tolerance.unwrap_or(0.1);
        if !(tolerance >= MIN_TOLERANCE && tolerance.is_finite()) {
            bail!(
                "--tolerance: must be at least {MIN_TOLERANCE:e} and finite (got {:e}): below that, round-off alone exceeds it",
                tolerance
            );
        }
        if tolerance > BLOWUP {
            bail!(
                "--tolerance: must be at most {BLOWUP} (got {:e}): a run whose relative energy error passes {BLOWUP} has blown up whatever the tolerance",
                tolerance
            );
        }
        let (lo, hi) = DURATION_RANGE;
        if !(args.duration >= lo && args.duration <= hi) {
            bail!(
                "--duration: must be between {lo:e} s and {hi:e} s (got {:e})",
                args.duration
            );
        }
        let methods = match &args.methods {
            Some(list) => {
                let names: Vec<String> = list
                    .split(',')
                    .map(|s| s.trim().to_string())
                    .filter(|s| !s.is_empty())
                    .collect();
                for m in &names {
                    check_method(m, "--methods")?;
                }
                if names.is_empty() {
                    bail!("--methods: no method given");
                }
                names
            }
            None => stability::default_methods(),
        };
        for m in &methods {
            check_applicable(m, &format!("--methods {m}"), &scene, &file, args)?;
        }
        check_solver_applies(args, methods.iter().map(String::as_str))?;
        let dir = output_dir(args, &scene)?;
        return stability::run(
            &scene,
            &file,
            &methods,
            tolerance,
            args.duration,
            &dir,
            settings,
        );
    }
    let method = match &args.method {
        Some(m) => {
            check_method(m, "--method")?;
            m.clone()
        }
        None => scene.simulation.method.clone(),
    };
    let from = match &args.method {
        Some(m) => format!("--method {m}"),
        None => format!("{file}: simulation.method {method}"),
    };
    check_applicable(&method, &from, &scene, &file, args)?;
    check_solver_applies(args, [method.as_str()].into_iter())?;
    let (opts, note) = run_options(&scene, args, &file)?;
    let renders = render_frames(args.render.as_deref(), opts.frames)?;
    // Build the model (proportional to the springs), refusing a scene
    // whose initial state is not finite, naming the field.
    let sim = Simulation::new(&scene).map_err(|e| anyhow!("{}", rename(&e, &file)))?;
    if cloth_implicit::is_implicit(&method) {
        cloth_implicit::check_size(&sim.model).map_err(|e| {
            let from = match (&args.method, &args.grid) {
                (Some(m), _) => format!("--method {m}"),
                (None, Some(g)) => format!("--grid {g}"),
                (None, None) => format!("{file}: simulation.method"),
            };
            anyhow!(
                "{from}: {}",
                e.to_string().trim_start_matches("invalid run options: ")
            )
        })?;
    }
    let e_ref =
        energy::reference_energy_checked(&scene, &sim).map_err(|e| anyhow!("{file}: {e}"))?;
    let dir = output_dir(args, &scene)?;
    let render_failure = args.render.as_deref().map(str::trim) != Some("none");
    simulate(
        sim,
        e_ref,
        &Plan {
            scene: &scene,
            method: &method,
            opts: &opts,
            renders: &renders,
            render_failure,
            obj_every: args.obj_every,
            dir: &dir,
            settings,
        },
        note,
    )
}

/// Refuse, before anything runs, a method that cannot step this scene with
/// this solver ([`minimise::applicable`]: the energy schemes and the
/// local/global solver handle no colliders; the energy schemes are solved
/// with Newton only). A run and `--stability` refuse with the same message;
/// `from` names where the method came from.
fn check_applicable(
    method: &str,
    from: &str,
    scene: &Scene,
    file: &str,
    args: &ClothArgs,
) -> Result<()> {
    let solver = solver_settings(args)?.solver;
    let colliders = !scene.colliders.is_empty();
    minimise::applicable(method, colliders, solver).map_err(|why| {
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
fn check_solver_applies<'a>(
    args: &ClothArgs,
    mut methods: impl Iterator<Item = &'a str> + Clone,
) -> Result<()> {
    let Some(solver) = &args.solver else {
        return Ok(());
    };
    if !methods.clone().any(minimise::is_minimisation) {
        let list: Vec<&str> = methods.by_ref().collect();
        bail!(
            "--solver {solver}: the minimisation solver steps the midpoint family (midpoint, paper-dirk2, paper-dirk4), avf and discrete-gradient; {} {} none of them",
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

fn parse_grid(text: &str) -> Result<(usize, usize)> {
    let parts: Vec<&str> = text.split(['x', 'X', '×']).collect();
    let parse = |s: &str| s.trim().parse::<usize>().ok().filter(|&n| n >= 2);
    let (nx, ny) = match parts.as_slice() {
        [n] => parse(n).map(|n| (n, n)),
        [a, b] => parse(a).zip(parse(b)),
        _ => None,
    }
    .with_context(|| {
        format!("--grid: expected NX×NY with both at least 2, e.g. 64x64 (got \"{text}\")")
    })?;
    if let Some((_, message)) = cloth::scene::grid_too_large(nx, ny) {
        bail!("--grid {text}: {message}");
    }
    Ok((nx, ny))
}

/// The scene at another resolution: pinned edges stay pinned edges, other
/// pins (corners, points) move to the nearest particle at the same place.
fn regrid(scene: &mut Scene, nx: usize, ny: usize) {
    let (nx0, ny0) = (scene.cloth.nx, scene.cloth.ny);
    let old: std::collections::BTreeSet<(usize, usize)> = scene.pins.iter().copied().collect();
    let edges = [
        (0..nx0).all(|i| old.contains(&(i, 0))),
        (0..nx0).all(|i| old.contains(&(i, ny0 - 1))),
        (0..ny0).all(|j| old.contains(&(0, j))),
        (0..ny0).all(|j| old.contains(&(nx0 - 1, j))),
    ];
    let on_full_edge = |&(i, j): &(usize, usize)| {
        (edges[0] && j == 0)
            || (edges[1] && j == ny0 - 1)
            || (edges[2] && i == 0)
            || (edges[3] && i == nx0 - 1)
    };
    let mut pins = std::collections::BTreeSet::new();
    if edges[0] {
        pins.extend((0..nx).map(|i| (i, 0)));
    }
    if edges[1] {
        pins.extend((0..nx).map(|i| (i, ny - 1)));
    }
    if edges[2] {
        pins.extend((0..ny).map(|j| (0, j)));
    }
    if edges[3] {
        pins.extend((0..ny).map(|j| (nx - 1, j)));
    }
    let map =
        |k: usize, n0: usize, n: usize| ((k * (n - 1)) as f64 / (n0 - 1) as f64).round() as usize;
    pins.extend(
        old.iter()
            .filter(|p| !on_full_edge(p))
            .map(|&(i, j)| (map(i, nx0, nx), map(j, ny0, ny))),
    );
    scene.pins = pins.into_iter().collect();
    scene.cloth.nx = nx;
    scene.cloth.ny = ny;
}

/// A method name that can step cloth, or an error listing those that can.
fn check_method(id: &str, flag: &str) -> Result<()> {
    if cloth_implicit::all_methods().contains(&id)
        || id == minimise::DISCRETE_GRADIENT
        || id == minimise::AVERAGE_VECTOR_FIELD
    {
        return Ok(());
    }
    let why = if integrator_core::library::info(id).is_some() {
        "is a library scheme that does not step cloth here"
    } else {
        "is not a known method"
    };
    bail!(
        "{flag}: \"{id}\" {why}; explicit: {}; implicit (sparse Newton): {}; energy-conserving: {}, {}",
        cloth::STEPPABLE.join(", "),
        cloth_implicit::IMPLICIT.join(", "),
        minimise::AVERAGE_VECTOR_FIELD,
        minimise::DISCRETE_GRADIENT
    )
}

/// Frames, substeps and frame rate from the scene and the flags, and a note
/// when the frame rate had to change for --dt. The run they describe is
/// checked against the limits ([`cloth::MAX_FRAMES`], [`cloth::MAX_STEPS`],
/// a normal step size) here, before anything is built, and an error names
/// the flag (or the scene's field) that broke it.
fn run_options(
    scene: &Scene,
    args: &ClothArgs,
    file: &str,
) -> Result<(RunOptions, Option<String>)> {
    let mut opts = RunOptions::from_scene(scene);
    let duration = scene.simulation.frames as f64 / scene.simulation.frame_rate;
    let mut note = None;
    if let Some(k) = args.substeps {
        if k == 0 {
            bail!("--substeps: must be at least 1");
        }
        opts.substeps = k;
    }
    if let Some(h) = args.dt {
        if !(h > 0.0 && h.is_finite()) {
            bail!("--dt: must be a positive step size in seconds (got {h})");
        }
        let rate = opts.frame_rate;
        let per_frame = (1.0 / (rate * h)).round().max(1.0);
        if per_frame.is_nan() || per_frame > cloth::MAX_STEPS as f64 {
            bail!(
                "--dt {h:e}: {per_frame:e} steps per {rate} Hz frame is more than the limit of {} steps in a run",
                cloth::MAX_STEPS
            );
        }
        let k = per_frame as usize;
        opts.substeps = k;
        let exact = 1.0 / (k as f64 * h);
        if (exact - rate).abs() > 1e-9 * rate {
            opts.frame_rate = exact;
            note = Some(format!(
                "frame rate {exact:.4} Hz instead of {rate} Hz so that {k} step{} of h = {h:e} s make a frame",
                if k == 1 { "" } else { "s" }
            ));
            if args.frames.is_none() {
                let frames = (duration * exact).round().max(1.0);
                if frames.is_nan() || frames > cloth::MAX_FRAMES as f64 {
                    bail!(
                        "--dt {h:e}: the scene's {duration} s would be {frames:e} frames of one step, more than the limit of {} frames (give --frames)",
                        cloth::MAX_FRAMES
                    );
                }
                opts.frames = frames as usize;
            }
        }
    }
    if let Some(n) = args.frames {
        opts.frames = n;
    }
    if let Some((what, message)) =
        cloth::scene::run_length_problem(opts.frames, opts.substeps, opts.frame_rate)
    {
        let from = match what {
            "frames" if args.frames.is_some() => "--frames".to_string(),
            "frames" | "substeps" | "frame_rate" if args.dt.is_some() => "--dt".to_string(),
            "substeps" if args.substeps.is_some() => "--substeps".to_string(),
            other => format!("{file}: simulation.{other}"),
        };
        bail!("{from}: {message}");
    }
    Ok((opts, note))
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
    /// The state of the last frame that passed the blow-up check.
    good_state: Vec<f64>,
    /// The frame that failed it, and its relative energy error.
    blown: Option<(FrameStats, f64)>,
}

/// A run has blown up once `|H − H₀|/E_ref` exceeds this (or is not
/// finite): the cloth holds a hundred times the energy of its own fall.
pub const BLOWUP: f64 = 100.0;

/// The callback's way of stopping a run that blew up.
#[derive(Debug)]
struct BlownUp;
impl std::fmt::Display for BlownUp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "the energy error exceeded {BLOWUP}·E_ref")
    }
}
impl std::error::Error for BlownUp {}

/// What a run is asked to do and where its output goes.
struct Plan<'a> {
    scene: &'a Scene,
    method: &'a str,
    opts: &'a RunOptions,
    /// Frames to render (sorted).
    renders: &'a [usize],
    /// Whether a run that fails renders its last good frame (not with
    /// `--render none`).
    render_failure: bool,
    obj_every: usize,
    dir: &'a Path,
    /// The minimisation solver's settings (midpoint family, avf, discrete gradient).
    settings: minimise::Settings,
}

/// `--solver` and `--tolerance` (of a run, not of `--stability`).
fn solver_settings(args: &ClothArgs) -> Result<minimise::Settings> {
    let solver = match args.solver.as_deref() {
        None => minimise::Solver::Newton,
        Some(name) => minimise::Solver::parse(name.trim()).with_context(|| {
            format!(
                "--solver: unknown solver \"{name}\"; expected one of {}",
                minimise::Solver::NAMES.join(", ")
            )
        })?,
    };
    let mut settings = minimise::Settings::new(solver);
    if let (false, Some(t)) = (args.stability, args.tolerance) {
        if !(t > 0.0 && t.is_finite()) {
            bail!("--tolerance: must be a positive finite number (got {t})");
        }
        let (lo, hi) = RUN_TOLERANCE_RANGE;
        if !(lo..=hi).contains(&t) {
            bail!(
                "--tolerance: must be between {lo:e} and {hi} (got {t:e}): below, the residual's round-off alone exceeds it and no solve converges; above, a step is accepted without a solve"
            );
        }
        settings.tolerance = t;
    }
    Ok(settings)
}

fn simulate(
    mut sim: Simulation,
    e_ref: f64,
    plan: &Plan<'_>,
    note: Option<String>,
) -> Result<ExitCode> {
    let Plan {
        scene,
        method,
        opts,
        renders,
        render_failure,
        obj_every,
        dir,
        settings,
    } = *plan;
    let clock = Instant::now();
    let h0 = sim.stats().energy.total();
    let triangles = sim.model.triangles();
    clear_stale(dir)?;
    let frames_dir = dir.join("frames");
    if obj_every > 0 {
        std::fs::create_dir_all(&frames_dir)
            .with_context(|| format!("{}: cannot create the directory", frames_dir.display()))?;
    }
    let bar = if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new(opts.frames as u64);
        if let Ok(style) =
            ProgressStyle::with_template("{bar:30} {pos}/{len} frames  {msg}  [{elapsed} < {eta}]")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        bar
    } else {
        ProgressBar::hidden()
    };
    let mut col = Collected {
        stats: Vec::with_capacity(opts.frames.min(1 << 16) + 1),
        objs: 0,
        kept: BTreeMap::new(),
        good_state: sim.state.clone(),
        blown: None,
    };
    let last = opts.frames;
    let result = minimise::run_any(&mut sim, method, opts, settings, |frame| {
        let k = frame.stats.frame;
        let rel = ((frame.stats.energy.total() - h0) / e_ref).abs();
        if rel.is_nan() || rel > BLOWUP {
            col.blown = Some((frame.stats, rel));
            return Err(Box::new(BlownUp));
        }
        col.good_state.copy_from_slice(frame.state);
        col.stats.push(frame.stats);
        if obj_every > 0 && (k % obj_every == 0 || k == last) {
            let path = frames_dir.join(format!("frame_{k:04}.obj"));
            cloth::write_obj(&path, &frame.positions(), &triangles)?;
            col.objs += 1;
        }
        if renders.binary_search(&k).is_ok() {
            col.kept.insert(k, (frame.stats.time, frame.positions()));
        }
        if k > 0 {
            bar.inc(1);
            bar.set_message(format!("t = {:.3} s", frame.stats.time));
        }
        Ok(())
    });
    bar.finish_and_clear();
    let title = |name: &str| format!("{} — {name}, h = {:.3e} s", scene.name, opts.step_size());
    // The model checks that the initial state is finite and the reference
    // energy is positive and finite, so frame 0 always passes; should it
    // not, that is an error about the scene, not a panic.
    let Some(&good) = col.stats.last() else {
        let why = match (&result, &col.blown) {
            (_, Some((_, rel))) => format!("|H − H₀|/E_ref = {rel:e} at the initial state"),
            (Err(e), None) => e.to_string(),
            (Ok(_), None) => "no frame was recorded".to_string(),
        };
        bail!(
            "{}: the initial state cannot be simulated: {why}",
            scene.name
        );
    };
    let failure = match result {
        Ok((report, solver)) => {
            let mut written = vec!["energy.csv".to_string(), "energy.svg".to_string()];
            energy::write_csv(&dir.join("energy.csv"), &report.frames, e_ref)?;
            energy::plot(
                &dir.join("energy.svg"),
                &report.frames,
                e_ref,
                &title(report.method),
            )?;
            let (names, note_render) = render_kept(scene, &triangles, &col.kept, dir, method)?;
            written.extend(names);
            if let Some(n) = note_render {
                eprintln!("note: {n}");
            }
            let wall = clock.elapsed().as_secs_f64();
            let s = Summary {
                scene,
                sim: &sim,
                method,
                report: &report,
                opts,
                solver: &solver,
                wall,
                e_ref,
                note: note.as_deref(),
                dir,
                objs: col.objs,
                written: &written,
            };
            print!("{}", s.render());
            return Ok(ExitCode::SUCCESS);
        }
        Err(
            err @ (RunError::Diverged { .. } | RunError::Solve { .. } | RunError::Minimise { .. }),
        ) => err.to_string(),
        Err(RunError::Callback { .. }) if col.blown.is_some() => {
            let (bad, rel) = col.blown.expect("checked");
            locate_blowup(&mut sim, method, opts, settings, &col.good_state, good, h0, e_ref)
                .unwrap_or_else(|| {
                    format!(
                        "{}: the cloth blew up between step {} and step {} (t = {} s to {} s): |H − H₀|/E_ref = {} at frame {} (limit {BLOWUP})",
                        method_name(method),
                        good.step,
                        bad.step,
                        good.time,
                        bad.time,
                        show_rel(rel),
                        bad.frame
                    )
                })
        }
        Err(err) => return Err(anyhow!("{err}")),
    };
    // Keep what was good: the frames up to the last good one.
    energy::write_csv(&dir.join("energy.csv"), &col.stats, e_ref)?;
    let mut written = vec!["energy.csv".to_string()];
    if col.stats.len() >= 2 {
        energy::plot(
            &dir.join("energy.svg"),
            &col.stats,
            e_ref,
            &title(&method_name(method)),
        )?;
        written.push("energy.svg".into());
    }
    let positions = sim
        .model
        .positions(&col.good_state[..col.good_state.len() / 2]);
    if obj_every > 0 {
        let path = frames_dir.join(format!("frame_{:04}.obj", good.frame));
        if !path.exists() {
            cloth::write_obj(&path, &positions, &triangles)?;
            col.objs += 1;
        }
    }
    if render_failure {
        col.kept.insert(good.frame, (good.time, positions));
    }
    let (names, note_render) = render_kept(scene, &triangles, &col.kept, dir, method)?;
    written.extend(names);
    if col.objs > 0 {
        written.push(format!("{} OBJ in frames/", col.objs));
    }
    eprintln!("error: {failure}");
    let growth = energy_growth(&col.stats, e_ref);
    eprintln!(
        "  energy up to the last good frame: {}",
        growth::describe(&growth)
    );
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
fn energy_growth(frames: &[FrameStats], e_ref: f64) -> cloth::study::growth::Growth {
    let times: Vec<f64> = frames.iter().map(|f| f.time).collect();
    cloth::study::growth::fit(&times, &energy::relative_errors(frames, e_ref))
}

/// Find the step at which a run blew up, by replaying the frame from the
/// last good state one step at a time with the energy checked after each.
#[allow(clippy::too_many_arguments)]
fn locate_blowup(
    sim: &mut Simulation,
    method: &str,
    opts: &RunOptions,
    settings: minimise::Settings,
    state: &[f64],
    good: FrameStats,
    h0: f64,
    e_ref: f64,
) -> Option<String> {
    sim.state.copy_from_slice(state);
    sim.time = good.time;
    sim.steps = good.step;
    sim.frame = good.frame;
    let replay = RunOptions {
        frames: opts.substeps,
        substeps: 1,
        frame_rate: opts.frame_rate * opts.substeps as f64,
    };
    let mut found = None;
    let result = minimise::run_any(sim, method, &replay, settings, |frame| {
        let rel = ((frame.stats.energy.total() - h0) / e_ref).abs();
        if rel.is_nan() || rel > BLOWUP {
            found = Some((frame.stats, rel));
            return Err(Box::new(BlownUp));
        }
        Ok(())
    });
    match (result, found) {
        (_, Some((at, rel))) => Some(format!(
            "{}: the cloth blew up at step {} (t = {} s, frame {}): |H − H₀|/E_ref = {} (limit {BLOWUP})",
            method_name(method),
            at.step,
            at.time,
            good.frame + 1,
            show_rel(rel)
        )),
        (
            Err(
                err @ (RunError::Diverged { .. }
                | RunError::Solve { .. }
                | RunError::Minimise { .. }),
            ),
            None,
        ) => Some(err.to_string()),
        _ => None,
    }
}

/// A relative energy error for a message: NaN (the energy is ∞ − ∞) said
/// in words.
fn show_rel(rel: f64) -> String {
    if rel.is_nan() {
        "not a number (the energy is no longer finite)".to_string()
    } else {
        format!("{rel:.3e}")
    }
}

/// The scheme's name for a method id.
fn method_name(id: &str) -> String {
    integrator_core::library::info(id).map_or(id.to_string(), |i| i.name.to_string())
}

/// Render the kept frames with one camera fitted to all of them; the names
/// written, and a note when a picture had to be simplified (see
/// [`render::rasterise_checked`]).
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

/// The one-screen summary of a finished run.
struct Summary<'a> {
    scene: &'a Scene,
    sim: &'a Simulation,
    method: &'a str,
    report: &'a cloth::RunReport,
    opts: &'a RunOptions,
    solver: &'a minimise::SolverStats,
    wall: f64,
    e_ref: f64,
    note: Option<&'a str>,
    dir: &'a Path,
    objs: usize,
    written: &'a [String],
}

impl Summary<'_> {
    fn render(&self) -> String {
        use std::fmt::Write;
        let (scene, model, r) = (self.scene, &self.sim.model, self.report);
        let mut s = String::new();
        let (nx, ny) = model.grid();
        let families: Vec<String> = cloth::Family::ALL
            .iter()
            .zip(model.family_counts())
            .filter(|(_, n)| *n > 0)
            .map(|(f, n)| format!("{} {n}", f.name()))
            .collect();
        let _ = writeln!(
            s,
            "cloth: {}{}",
            scene.name,
            scene
                .description
                .as_ref()
                .map_or(String::new(), |d| format!(" — {d}"))
        );
        let _ = writeln!(
            s,
            "  grid         {nx} × {ny} particles ({} free, {} pinned), {} springs ({})",
            model.free_count(),
            model.pinned_count(),
            model.spring_count(),
            families.join(", ")
        );
        let kind = integrator_core::library::info(self.method).map_or(String::new(), |i| {
            format!(
                " — {}, order {}, {}",
                if i.explicit { "explicit" } else { "implicit" },
                i.order,
                if i.symplectic || i.symplectic_separable {
                    "symplectic"
                } else {
                    "not symplectic"
                }
            )
        });
        let _ = writeln!(s, "  method       {} ({}){kind}", self.method, r.method);
        let stab = model.stability();
        // ω_max is 0 when the power iteration finds no positive eigenvalue
        // of M⁻¹K (a cloth deep inside a sphere is unstable tangentially):
        // then there is no linear limit to print.
        let limit = if stab.omega_max > 0.0 && stab.h_max.is_finite() {
            format!(
                "2/ω_max = {:.4e} s, h·ω_max = {:.3}{}",
                stab.h_max,
                r.h * stab.omega_max,
                if stab.converged {
                    String::new()
                } else {
                    format!(
                        " (ω_max a lower bound: {} power iterations, not converged)",
                        stab.iterations
                    )
                }
            )
        } else {
            "2/ω_max n/a (the power iteration found no positive eigenvalue of M⁻¹K)".to_string()
        };
        let _ = writeln!(
            s,
            "  step         h = {:.4e} s ({} per frame at {:.4} Hz); {limit}",
            r.h, self.opts.substeps, self.opts.frame_rate,
        );
        if let Some(note) = self.note {
            let _ = writeln!(s, "               ({note})");
        }
        let simulated =
            r.frames.last().map_or(0.0, |f| f.time) - r.frames.first().map_or(0.0, |f| f.time);
        let _ = writeln!(
            s,
            "  steps        {} over {} frames, {simulated:.4} s simulated",
            r.steps,
            r.frames.len() - 1
        );
        let _ = writeln!(
            s,
            "  wall time    {:.3} s ({:.3} s stepping; the rest is statistics and output)",
            self.wall, r.stepping_seconds
        );
        if simulated > 0.0 {
            let per_frame = r.stepping_seconds / (simulated * 60.0) * 1e3;
            let _ = writeln!(
                s,
                "  per frame    {per_frame:.3} ms of stepping per 60 Hz frame (1/60 s simulated)"
            );
            let _ = writeln!(
                s,
                "  real time    {:.3}× (simulated s / stepping s; {:.3}× with output)",
                simulated / r.stepping_seconds.max(1e-12),
                simulated / self.wall.max(1e-12)
            );
        }
        let rel = energy::relative_errors(&r.frames, self.e_ref);
        let (worst, at) = rel
            .iter()
            .zip(&r.frames)
            .fold((0.0f64, 0.0f64), |(w, t), (e, f)| {
                if e.abs() > w {
                    (e.abs(), f.time)
                } else {
                    (w, t)
                }
            });
        let _ = writeln!(
            s,
            "  energy       max relative error {worst:.3e} (at t = {at:.3} s; |H − H₀|/E_ref, E_ref = {:.4e} J)",
            self.e_ref
        );
        let _ = writeln!(
            s,
            "  growth       {}",
            growth::describe(&energy_growth(&r.frames, self.e_ref))
        );
        let (strain, frame) = r.frames.iter().fold((0.0f64, 0usize), |(m, k), f| {
            if f.max_strain > m {
                (f.max_strain, f.frame)
            } else {
                (m, k)
            }
        });
        let _ = writeln!(s, "  max strain   {:.3} % (frame {frame})", 100.0 * strain);
        if let minimise::SolverStats::Minimise(st, settings) = self.solver {
            let _ = writeln!(
                s,
                "  solver       {} minimisation, tolerance {:e}: {:.2} iterations per step (at most {} in one solve), {:.2} factorisations per step ({} symbolic, {} of an exact Hessian found indefinite), {} line-search halvings, final residual ≤ {:.2e}{}",
                settings.solver.name(),
                settings.tolerance,
                st.iterations_per_step(),
                st.max_iterations,
                st.factorizations_per_step(),
                st.symbolic_factorizations,
                st.indefinite,
                st.backtracks,
                st.max_residual,
                if st.floor_accepts > 0 {
                    format!(
                        "; {} solves stopped at their round-off floor above the tolerance",
                        st.floor_accepts
                    )
                } else {
                    String::new()
                }
            );
        }
        if let minimise::SolverStats::Stage(st) = self.solver {
            let steps = st.steps.max(1) as f64;
            let _ = writeln!(
                s,
                "  newton       {:.2} iterations per step, {} numeric LU ({} symbolic), {} Jacobians, {} failed steps",
                st.newton_iterations as f64 / steps,
                st.factorizations,
                st.symbolic_factorizations,
                st.jacobian_evaluations,
                st.failures
            );
        }
        let mut files = self.written.to_vec();
        if self.objs > 0 {
            files.insert(2, format!("{} OBJ in frames/", self.objs));
        }
        let _ = writeln!(
            s,
            "  output       {}: {}",
            self.dir.display(),
            files.join(", ")
        );
        s
    }
}
