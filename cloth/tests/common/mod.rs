//! Shorthands over the one way to run (`Simulation::run` with a `Method`
//! and `RunSettings`) for the tests.
#![allow(dead_code)]

use cloth::{
    CallbackError, Frame, Method, MinimiseSettings, RunError, RunOptions, RunReport, RunSettings,
    Simulation, StageSettings,
};

/// The implicit tables the stage-solver tests were written for (before
/// every implicit table of the library stepped cloth): Gauss–Legendre 2,
/// the midpoint rule, implicit Euler, Gauss–Legendre 3, Radau IIA 3 and the
/// paper's DIRKs.
pub const STAGE_TABLES: &[&str] = &[
    "gauss2",
    "midpoint",
    "implicit-euler",
    "gauss3",
    "radau2a-3",
    "paper-dirk2",
    "paper-dirk4",
];

/// Run the method `id` through its own mechanism with the default solvers.
pub fn run_id<F>(
    sim: &mut Simulation,
    id: &str,
    opts: &RunOptions,
    on_frame: F,
) -> Result<RunReport, RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    sim.run(&Method::parse(id)?, &RunSettings::new(*opts), on_frame)
}

/// Run the method `id` with the minimisation solver's `settings`.
pub fn run_minimise<F>(
    sim: &mut Simulation,
    id: &str,
    opts: &RunOptions,
    settings: MinimiseSettings,
    on_frame: F,
) -> Result<RunReport, RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    let run = RunSettings::new(*opts).with_minimise(settings);
    sim.run(&Method::parse(id)?, &run, on_frame)
}

/// Run the table `id` through the sparse stage solver (a midpoint-family
/// table too), with the given stage settings or the cloth defaults.
pub fn run_stage<F>(
    sim: &mut Simulation,
    id: &str,
    opts: &RunOptions,
    stage: Option<StageSettings>,
    on_frame: F,
) -> Result<RunReport, RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    let method = Method::parse(id)?.through_stage_solver()?;
    let mut run = RunSettings::new(*opts);
    if let Some(stage) = stage {
        run = run.with_stage(stage);
    }
    sim.run(&method, &run, on_frame)
}

/// The stage solver's statistics of a run through it.
pub fn stage_stats(report: &RunReport) -> integrator_core::implicit::Stats {
    match report.solver {
        cloth::SolverStats::Stage(s) => s,
        other => panic!("not a stage-solver run: {other:?}"),
    }
}

/// The minimisation solver's statistics of a run through it.
pub fn minimise_stats(report: &RunReport) -> integrator_core::minimise::Stats {
    match report.solver {
        cloth::SolverStats::Minimise(s, _) => s,
        other => panic!("not a minimisation run: {other:?}"),
    }
}

/// A state off the grid: every coordinate moved by up to 3 % of the
/// spacing, deterministically.
pub fn perturbed(model: &cloth::ClothModel) -> Vec<f64> {
    use integrator_core::Separable;
    let n = model.dof();
    let mut q = model.initial_state()[..n].to_vec();
    let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
    for x in &mut q {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        *x += 0.0005 * ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
    }
    q
}
