//! Measurement probe: `cargo run --release -p cloth --example minimise_probe -- SCENE METHOD SOLVER FRAMES [SUBSTEPS] [TOL]`
//! prints per-frame energy drift, max strain, and the solver counters.
use cloth::step::minimise::Stats;
use cloth::{
    Method, MinimiseSettings, RunOptions, RunSettings, Scene, Simulation, Solver, SolverStats,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().collect();
    let scene = Scene::load(&a[1])?;
    let method = Method::parse(&a[2])?;
    let solver = Solver::parse(&a[3]).ok_or("solver")?;
    let frames: usize = a[4].parse()?;
    let substeps: usize = a.get(5).map(|s| s.parse()).transpose()?.unwrap_or(1);
    let mut settings = MinimiseSettings::new(solver);
    if let Some(t) = a.get(6) {
        settings.tolerance = t.parse()?;
    }
    let mut sim = Simulation::new(&scene)?;
    let st = sim.model.stability();
    println!(
        "2/omega_max = {:.4e} s ({:.0} steps per 60 Hz frame)",
        st.h_max,
        (1.0 / (60.0 * st.h_max)).ceil()
    );
    let opts = RunOptions {
        frames,
        substeps,
        frame_rate: 60.0,
    };
    let e0 = sim.stats().energy.total();
    let scale = sim.model.particle_mass() * sim.model.free_count() as f64 * 9.81;
    let every = (frames / 20).max(1);
    let mut worst: f64 = 0.0;
    let run = RunSettings::new(opts).with_minimise(settings);
    let result = sim.run(&method, &run, |f| {
        worst = worst.max(((f.stats.energy.total() - e0) / scale).abs());
        if f.stats.frame % every == 0 {
            println!(
                "frame {:5} t {:7.3} E {:+.6e} dE/scale {:+.3e} strain {:.4} |P| {:.3e}",
                f.stats.frame,
                f.stats.time,
                f.stats.energy.total(),
                (f.stats.energy.total() - e0) / scale,
                f.stats.max_strain,
                f.stats.momentum.norm()
            );
        }
        Ok(())
    });
    let report = result?;
    let s = match report.solver {
        SolverStats::Minimise(s, _) => s,
        _ => Stats::default(),
    };
    println!("max |dE|/(M g 1 m) = {worst:.3e}");
    println!(
        "{} {}: {:.3} ms/frame, {:.2} it/step, max it {}, fact/step {:.2}, backtracks {}, roundoff steps {}, floor accepts {}, max residual {:.2e}, factor {:.3} s of {:.3} s",
        report.method,
        solver.name(),
        1e3 * report.stepping_seconds / frames as f64,
        s.iterations_per_step(),
        s.max_iterations,
        s.factorizations_per_step(),
        s.backtracks,
        s.roundoff_steps,
        s.floor_accepts,
        s.max_residual,
        s.factor_seconds,
        report.stepping_seconds
    );
    Ok(())
}
