//! Phase 2: a [`Request`] checked against its scene and resolved into a
//! [`Job`] — the method, the schedule, the frames to render, the output
//! folder, the model and its reference energy — before anything runs.

use std::path::{Path, PathBuf};
use std::time::Duration;

use cloth::scene::GridError;
use cloth::schedule::{Asked, RunRequest, schedule};
use cloth::study::energy::reference_energy;
use cloth::{EnergyGuard, Method, MinimiseSettings, RunSettings, Scene, Simulation, Solver};

use super::checkpoint::{self, Resumed};
use super::request::{Field, InputError, JobError, Request, SceneSource};

/// A planned run: everything checked, the model built.
pub struct Job {
    pub(crate) request: Request,
    pub(crate) scene: Scene,
    /// The scene's text, kept in checkpoints.
    pub(crate) scene_text: String,
    pub(crate) method: Method,
    /// Frames, substeps, the solvers and the energy guard.
    pub(crate) settings: RunSettings,
    /// Frames to render (sorted).
    pub(crate) renders: Vec<usize>,
    /// Whether a run that fails renders its last good frame (not with
    /// `render = "none"`).
    pub(crate) render_failure: bool,
    pub(crate) dir: PathBuf,
    /// A note for the summary (the frame rate changed for `dt`).
    pub(crate) note: Option<String>,
    pub(crate) sim: Simulation,
    /// The checkpoint interval (`None`: only when the observer stops it).
    pub(crate) every: Option<Duration>,
    /// The run a checkpoint saved, to go on from.
    pub(crate) resumed: Option<Resumed>,
}

impl Job {
    /// The output folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

/// Check `request` and build its run; nothing is written but the output
/// folder (created and probed for writing).
pub fn plan(request: &Request) -> Result<Job, JobError> {
    let (scene, text) = load(request)?;
    plan_with(request, scene, text, None)
}

/// The scene of `request` and its text.
pub(crate) fn load(request: &Request) -> Result<(Scene, String), JobError> {
    match &request.scene {
        SceneSource::File(path) => {
            let scene = Scene::load(path).map_err(|e| JobError::Scene(e.to_string()))?;
            let scene = regrid(request, scene)?;
            let text = std::fs::read_to_string(path)
                .map_err(|e| JobError::io(path, "cannot read the scene again", e))?;
            Ok((scene, text))
        }
        SceneSource::Text { name, text } => Ok((from_text(request, name, text)?, text.clone())),
    }
}

/// The scene a checkpoint saved (or given as text), at the request's grid.
pub(crate) fn from_text(request: &Request, name: &str, text: &str) -> Result<Scene, JobError> {
    let scene = Scene::from_toml(text, name).map_err(|e| JobError::Scene(e.to_string()))?;
    regrid(request, scene)
}

/// The plan of `request` on `scene`, fresh or continuing `resumed`.
pub(crate) fn plan_with(
    request: &Request,
    scene: Scene,
    scene_text: String,
    resumed: Option<Resumed>,
) -> Result<Job, JobError> {
    let file = request.scene.file_name();
    let minimise = minimise_settings(request)?;
    let (method, from) = match &request.method {
        Some(m) => (
            Method::parse(m).map_err(|e| InputError::field(Field::Method, e.to_string()))?,
            Source::Field(Field::Method, m.clone()),
        ),
        None => {
            // The scene's method was checked when the scene was read.
            let m = Method::parse(&scene.simulation.method)
                .map_err(|e| InputError::scene(&file, Some("simulation.method"), e.to_string()))?;
            (m, Source::Scene(m.id().to_string()))
        }
    };
    applicable(&method, &from, &scene, &file, minimise.solver)?;
    solver_applies(request.solver.as_deref(), std::slice::from_ref(&method))?;
    // The run's length is checked before anything is built, except the
    // steps per frame of `substeps = "auto"`, which need the model.
    run_options(&scene, None, request, &file)?;
    // Build the model (proportional to the springs), refusing a scene
    // whose initial state is not finite, naming the field.
    let sim = Simulation::new(&scene).map_err(|e| JobError::Scene(rename(&e, &file)))?;
    let (options, note) = run_options(&scene, Some(&sim.model), request, &file)?;
    let renders = render_frames(request.render.as_deref(), options.frames)?;
    if !method.explicit() {
        cloth::step::stage::check_size(&sim.model).map_err(|e| {
            let e = e.to_string();
            match (&request.method, &request.grid) {
                (Some(m), _) => InputError::field_value(Field::Method, m, e),
                (None, Some(g)) => InputError::field_value(Field::Grid, g, e),
                (None, None) => InputError::scene(&file, Some("simulation.method"), e),
            }
        })?;
    }
    let e_ref = reference_energy(&scene, &sim)
        .map_err(|e| InputError::scene(&file, None, e.to_string()))?;
    let dir = output_dir(request, &scene)?;
    let render_failure = request.render.as_deref().map(str::trim) != Some("none");
    let every = checkpoint::interval(request.checkpoint_every, &method)?;
    let variable = scene.simulation.variable;
    Ok(Job {
        request: request.clone(),
        scene,
        scene_text,
        method,
        settings: RunSettings::new(options)
            .with_variable(variable)
            .with_minimise(minimise)
            .with_guard(EnergyGuard::new(e_ref)),
        renders,
        render_failure,
        dir,
        note,
        sim,
        every,
        resumed,
    })
}

/// Where a method came from, for messages.
pub(crate) enum Source {
    /// A request field and the id given.
    Field(Field, String),
    /// The scene's `simulation.method` (the id).
    Scene(String),
}

/// `grid`, if given.
fn regrid(request: &Request, mut scene: Scene) -> Result<Scene, JobError> {
    if let Some(grid) = &request.grid {
        let (nx, ny) = cloth::scene::parse_grid(grid).map_err(|e| match e {
            GridError::Syntax(_) => InputError::field(Field::Grid, e.to_string()),
            GridError::TooLarge(_) => InputError::field_value(Field::Grid, grid, e.to_string()),
        })?;
        cloth::scene::regrid(&mut scene, nx, ny);
        scene.validate().map_err(|e| {
            InputError::field_value(Field::Grid, grid, rename(&e, &request.scene.file_name()))
        })?;
    }
    Ok(scene)
}

/// Refuse, before anything runs, a method that cannot step this scene with
/// this solver ([`cloth::step::minimise::applicable`]: the energy schemes
/// and the local/global solver handle no colliders; the energy schemes are
/// solved with Newton only). A run and the stability study refuse with the
/// same message.
pub(crate) fn applicable(
    method: &Method,
    from: &Source,
    scene: &Scene,
    file: &str,
    solver: Solver,
) -> Result<(), InputError> {
    let colliders = !scene.colliders.is_empty();
    cloth::step::minimise::applicable(method, colliders, solver).map_err(|why| {
        if let Some(why) = why.strip_prefix("solver: ") {
            let at = if colliders {
                format!(" ({file}: colliders)")
            } else {
                String::new()
            };
            InputError::field_value(Field::Solver, solver.name(), format!("{why}{at}"))
        } else {
            let why = why.strip_prefix("method: ").unwrap_or(&why);
            let message = format!("{why} ({file}: colliders)");
            match from {
                Source::Field(f, id) => InputError::field_value(*f, id, message),
                Source::Scene(id) => {
                    InputError::scene(file, Some(&format!("simulation.method {id}")), message)
                }
            }
        }
    })
}

/// `solver` is the minimisation solver's: refused when none of the
/// methods is solved by minimisation, rather than silently ignored.
pub(crate) fn solver_applies(solver: Option<&str>, methods: &[Method]) -> Result<(), InputError> {
    let Some(solver) = solver else {
        return Ok(());
    };
    if !methods.iter().any(Method::minimises) {
        let list: Vec<&str> = methods.iter().map(Method::id).collect();
        return Err(InputError::field_value(
            Field::Solver,
            solver,
            format!(
                "the minimisation solver steps the midpoint family ({}), avf and discrete-gradient; {} {} none of them",
                Method::ids(|m| m.midpoint_weights().is_some()).join(", "),
                list.join(", "),
                if list.len() == 1 { "is" } else { "are" }
            ),
        ));
    }
    Ok(())
}

/// A scene error as the user's file names it: the model names the scene by
/// its `name`, the user knows the file.
pub(crate) fn rename(e: &cloth::SceneError, file: &str) -> String {
    match e {
        cloth::SceneError::Field { field, message, .. } => format!("{file}: {field}: {message}"),
        other => other.to_string(),
    }
}

/// Frames, substeps and frame rate from the scene and the request
/// ([`cloth::schedule`], checked against the run limits before anything is
/// built), and a note when the frame rate had to change for `dt`; an error
/// names the field (or the scene's) that broke the limits.
/// With the `model`, a scene's `substeps = "auto"` is resolved on it
/// ([`cloth::schedule::schedule_for`]) and the note says what was chosen
/// and why.
fn run_options(
    scene: &Scene,
    model: Option<&cloth::ClothModel>,
    request: &Request,
    file: &str,
) -> Result<(cloth::RunOptions, Option<String>), InputError> {
    let asked = RunRequest {
        frames: request.frames,
        substeps: request.substeps,
        dt: request.dt,
    };
    let planned = match model {
        Some(model) => cloth::schedule::schedule_for(scene, model, &asked).map(|(p, _)| p),
        None => schedule(scene, &asked),
    };
    let plan = planned.map_err(|e| match (e.asked, request.dt) {
        (Asked::Frames, _) => InputError::field(Field::Frames, e.message),
        (Asked::Substeps, _) => InputError::field(Field::Substeps, e.message),
        (Asked::Dt, Some(h)) if h > 0.0 && h.is_finite() => {
            InputError::field_value(Field::Dt, format!("{h:e}"), e.message)
        }
        (Asked::Dt, _) => InputError::field(Field::Dt, e.message),
        (Asked::Scene(field), _) => {
            InputError::scene(file, Some(&format!("simulation.{field}")), e.message)
        }
    })?;
    Ok((plan.options, plan.note))
}

/// The frames to render: the list given, or first, middle and last.
fn render_frames(spec: Option<&str>, frames: usize) -> Result<Vec<usize>, InputError> {
    let mut out: Vec<usize> = match spec.map(str::trim) {
        None => vec![0, frames / 2, frames],
        Some("none") | Some("") => Vec::new(),
        Some(list) => {
            let mut v = Vec::new();
            for item in list.split(',') {
                let n: usize = item.trim().parse().map_err(|e| {
                    InputError::field(
                        Field::Render,
                        format!(
                            "\"{}\" is not a frame number (expected e.g. 0,150,300 or none): {e}",
                            item.trim()
                        ),
                    )
                })?;
                if n > frames {
                    return Err(InputError::field(
                        Field::Render,
                        format!("frame {n} is after the last frame ({frames})"),
                    ));
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

/// The output folder, created and probed for writing.
pub(crate) fn output_dir(request: &Request, scene: &Scene) -> Result<PathBuf, JobError> {
    let dir = match &request.out {
        Some(d) => d.clone(),
        None => Path::new("out").join("cloth").join(file_safe(&scene.name)),
    };
    std::fs::create_dir_all(&dir).map_err(|e| {
        InputError::field(
            Field::Out,
            format!("cannot create the output directory {}: {e}", dir.display()),
        )
    })?;
    integrator_core::checkpoint::check_writable(&dir)?;
    Ok(dir)
}

/// `solver` and `tolerance` (of a run, not of the stability study, whose
/// tolerance is the energy error's).
fn minimise_settings(request: &Request) -> Result<MinimiseSettings, InputError> {
    let mut settings = MinimiseSettings::new(solver(request.solver.as_deref())?);
    if let Some(t) = request.tolerance {
        settings = settings
            .with_tolerance(t)
            .map_err(|why| InputError::field(Field::Tolerance, why.to_string()))?;
    }
    Ok(settings)
}

/// The minimisation solver named (default Newton).
pub(crate) fn solver(name: Option<&str>) -> Result<Solver, InputError> {
    match name {
        None => Ok(Solver::Newton),
        Some(name) => Solver::parse(name.trim()).ok_or_else(|| {
            InputError::field(
                Field::Solver,
                format!(
                    "unknown solver \"{name}\"; expected one of {}",
                    Solver::NAMES.join(", ")
                ),
            )
        }),
    }
}

/// The job that continues the run whose checkpoint is `path` in `dir`
/// (its payload already read, a cloth one): the saved request and scene,
/// writing into `dir` (the folder may have moved since).
pub fn resume(dir: &Path, path: &Path, payload: &[u8]) -> Result<Job, JobError> {
    let (mut request, text, resumed) = checkpoint::decode(path, payload)?;
    request.out = Some(dir.to_path_buf());
    let SceneSource::Text { name, .. } = &request.scene else {
        unreachable!("decode_request makes a text source")
    };
    let name = name.clone();
    request.scene = SceneSource::Text {
        name: name.clone(),
        text: text.clone(),
    };
    let scene = from_text(&request, &name, &text)?;
    plan_with(&request, scene, text, Some(resumed))
}
