//! RATTLE on an inextensible scene: per-frame stepping time and where it
//! went, the energy error, the constraint residuals.
//!
//! `cargo run --release -p cloth --example rattle_probe -- SCENE.toml [substeps] [frames] [seq|par] [refactor_every] [marks|fresh]`
//! (`par`: both cores for the per-edge loops and the factorisation;
//! `fresh`: a variable-step frame tried again starts afresh instead of
//! from the marks, `RattleSettings::rewind`).

use cloth::{Method, RunSettings, Scene, Simulation, SolverStats};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let scene = Scene::load(
        args.get(1)
            .map_or("scenes/paper64-inextensible.toml", |s| s),
    )?;
    let mut scene = scene;
    if let Some(s) = args.get(2) {
        scene.simulation.substeps = s.parse()?;
    }
    if let Some(f) = args.get(3) {
        scene.simulation.frames = f.parse()?;
    }
    let parallel = args.get(4).is_some_and(|s| s == "par");
    let mut sim = Simulation::new(&scene)?;
    let mut settings = RunSettings::from_scene(&scene);
    settings.solvers.rattle.parallel = parallel;
    if let Some(k) = args.get(5) {
        settings.solvers.rattle.refactor_every = k.parse()?;
    }
    settings.solvers.rattle.rewind = args.get(6).is_none_or(|s| s != "fresh");
    let n = 3 * sim.model.free_count();
    let (mut worst_g, mut worst_v) = (0.0f64, 0.0f64);
    let report = sim.run(&Method::parse("rattle")?, &settings, |f| {
        worst_g = worst_g.max(f.model.constraint_residual(&f.state[..n]).unwrap());
        worst_v = worst_v.max(f.model.constraint_velocity_residual(f.state).unwrap());
        if std::env::var("PROBE_TRACE").is_ok() {
            let e = f.stats.energy;
            let p = &f.state[n..];
            let vmax = p.iter().fold(0.0f64, |m, x| m.max(x.abs())) * f.model.inverse_mass();
            println!(
                "frame {} t {:.4} kinetic {:.5e} potential {:.5e} total {:.5e} vmax {:.3e}",
                f.stats.frame,
                f.stats.time,
                e.kinetic,
                e.potential(),
                e.total(),
                vmax
            );
        }
        Ok(())
    })?;
    let e0 = report.frames[0].energy.total();
    let span = report
        .frames
        .iter()
        .map(|f| (f.energy.total() - e0).abs())
        .fold(0.0, f64::max);
    let frames = (report.frames.len() - 1) as f64;
    println!(
        "{}: {} × {} free {}, constraints {}, h = {:.4e} s ({} per frame), parallel {parallel}",
        scene.name,
        scene.cloth.nx,
        scene.cloth.ny,
        sim.model.free_count(),
        sim.model.constraint_count(),
        report.h,
        scene.simulation.substeps
    );
    println!(
        "  stepping {:.3} ms per frame over {} frames, rewind {}",
        1e3 * report.stepping_seconds / frames,
        frames,
        settings.solvers.rattle.rewind
    );
    if let Some(v) = &report.variable {
        println!(
            "  variable step: {} steps kept, {} not kept, {} frames tried more than once",
            report.steps, v.discarded_steps, v.redone
        );
    }
    if let SolverStats::Constrained(s) = report.solver {
        let t = s.seconds;
        println!(
            "  per frame: forces {:.3} ms, constraints {:.3} ms, factorize {:.3} ms, solve {:.3} ms",
            1e3 * t.forces / frames,
            1e3 * t.constraints / frames,
            1e3 * t.factorize / frames,
            1e3 * t.solve / frames
        );
        println!(
            "  iterations per step {:.2} (max {}), Cholesky {}, LU {}, pcg {} (failed {}), max residual {:.2e} (tol {:.2e})",
            s.iterations_per_step(),
            s.max_iterations,
            s.factorizations,
            s.lu_factorizations,
            s.pcg_iterations,
            s.pcg_failures,
            s.max_residual,
            cloth::CONSTRAINT_TOLERANCE
        );
    }
    println!(
        "  max |H − H0| = {span:.3e} J (H0 = {e0:.4e}); frame residuals g {worst_g:.2e}, Gv {worst_v:.2e}"
    );
    Ok(())
}
