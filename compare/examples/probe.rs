//! A work–precision sweep on Kepler (e given) without the CLI, for quick
//! method exploration: `cargo run --release -p compare --example probe --
//! E ORBITS MIN_STEPS MAX_STEPS POINTS REPEATS ID,ID,...` prints the time to
//! 1e-6, 1e-8 and 1e-10 of each method and DOP853.

use compare::report::duel;
use compare::{Method, output, sweep};
use integrator_core::problems::Kepler;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    if a.len() != 7 {
        return Err("usage: probe E ORBITS MIN_STEPS MAX_STEPS POINTS REPEATS ID,ID,...".into());
    }
    let e: f64 = a[0].parse()?;
    let orbits: f64 = a[1].parse()?;
    let (lo, hi): (f64, f64) = (a[2].parse()?, a[3].parse()?);
    let points: usize = a[4].parse()?;
    let repeats: usize = a[5].parse()?;
    let sys = Kepler { e };
    let t_end = orbits * 2.0 * std::f64::consts::PI;
    let setup = compare::Setup::new(sys, t_end)?;
    let methods: Vec<Method<Kepler>> = a[6]
        .split(',')
        .map(|id| Method::by_id(id, &sys))
        .collect::<Result<_, _>>()?;
    let steps = sweep::step_counts(t_end, t_end / hi, t_end / lo, points);
    let rows = sweep::sweep(
        &setup,
        &methods,
        &steps,
        &sweep::tolerances(sweep::PEER_TOLERANCES),
        repeats,
    );
    for target in [1e-6, 1e-8, 1e-10] {
        let r = output::reach(&rows, target);
        print!("e={e} orbits={orbits} target {target:.0e}:");
        for x in &r {
            print!(" {}={:.3}ms", x.method, x.time_s * 1e3);
        }
        if let Some(d) = duel(&rows, target)
            && let (Some(o), Some(p)) = (&d.ours, &d.peer)
        {
            print!("  | best ours/dop853 = {:.2}", o.time_s / p.time_s);
        }
        println!();
    }
    Ok(())
}
