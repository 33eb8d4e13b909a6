//! Does faer's parallel factorisation pay for the Newton minimisation?
//! `cargo run --release -p cloth --example minimise_par -- SCENE FRAMES SUBSTEPS [THREADS]`
//! steps the scene's cloth with the midpoint rule through
//! `integrator_core::minimise::MidpointStepper`, once with `Par::Seq` and
//! once with `Par::rayon(THREADS)` (default 2), alternately (twice each),
//! from the same start, and prints ms per frame and the time in numeric
//! factorisations of each.
use std::time::Instant;

use cloth::{Scene, Simulation};
use faer::Par;
use integrator_core::minimise::{MidpointSettings, MidpointStepper};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().collect();
    let scene = Scene::load(&a[1])?;
    let frames: usize = a[2].parse()?;
    let substeps: usize = a[3].parse()?;
    let threads: usize = a.get(4).map(|s| s.parse()).transpose()?.unwrap_or(2);
    let h = 1.0 / (60.0 * substeps as f64);
    for round in 0..2 {
        for (name, par) in [("seq", Par::Seq), ("rayon", Par::rayon(threads))] {
            let sim = Simulation::new(&scene)?;
            let mut z = sim.state.clone();
            let mut stepper =
                MidpointStepper::with_par(&sim.model, MidpointSettings::default(), par)?;
            let clock = Instant::now();
            for _ in 0..frames * substeps {
                stepper.step(&sim.model, &[1.0], h, &mut z)?;
            }
            let s = clock.elapsed().as_secs_f64();
            let st = stepper.stats();
            println!(
                "round {round} {name:5}: {:.2} ms/frame, factorisations {:.3} s ({} of them, {:.2} ms each), {:.2} it/step",
                1e3 * s / frames as f64,
                st.factor_seconds,
                st.factorizations,
                1e3 * st.factor_seconds / st.factorizations.max(1) as f64,
                st.iterations_per_step()
            );
        }
    }
    Ok(())
}
