//! Brouwer's law experiment: energy error of Gauss–Legendre 2 on Kepler
//! over many steps, with and without compensated summation.
use integrator_core::implicit::ImplicitWorkspace;
use integrator_core::library::GaussLegendre2;
use integrator_core::problems::Kepler;
use integrator_core::{Step, energy};

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let e = args.first().copied().unwrap_or(0.0);
    let n = args.get(1).copied().unwrap_or(1e6) as usize;
    let h = args.get(2).copied().unwrap_or(1e-3);
    let k = Kepler { e };
    for comp in [true, false] {
        let z0 = k.initial_state();
        let mut z = z0.clone();
        let mut ws: ImplicitWorkspace = GaussLegendre2.workspace(&k);
        ws.settings_mut().compensated = comp;
        let e0 = energy(&k, &z);
        let mut next = 10usize;
        let mut out = Vec::new();
        let mut maxerr: f64 = 0.0;
        for i in 1..=n {
            GaussLegendre2.step(&k, 0.0, h, &mut z, &mut ws).unwrap();
            let err = (energy(&k, &z) - e0).abs();
            maxerr = maxerr.max(err);
            if i == next {
                out.push((i, err, maxerr));
                next = (next as f64 * 1.5) as usize;
            }
        }
        println!("compensated={comp}");
        for (i, err, m) in out {
            println!("{i:>9} {err:.3e} {m:.3e}");
        }
        println!("{:?}", ws.stats());
    }
}
