//! The error at T = 10⁵ days of `wh:leapfrog` and `wh:whckl-c17` on the
//! outer solar system at h = 2 days, as `symlab compare` times them (the
//! drifts merged across steps, the corrector at the ends), on both
//! implementations of the lanes: a check of the rounding-error floor.
use integrator_core::problems::wisdom_holman::Jacobi;
use integrator_core::problems::{OuterSolarSystem, reference_solution};
use integrator_core::processed::Processed;
use integrator_core::scheme::SplitWorkspace;
use integrator_core::sequence::Sequence;
use integrator_core::simd::Simd;
use integrator_core::split::Split;

fn rel_dist(a: &[f64], b: &[f64]) -> f64 {
    let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
    let r: f64 = b.iter().map(|y| y * y).sum();
    (d / r).sqrt()
}

fn main() {
    let sys = OuterSolarSystem;
    let z0 = sys.initial_state();
    let t = 1e5;
    let reference = reference_solution(&sys, &z0, t, 0.2);
    for simd in [Simd::Auto, Simd::Portable] {
        let split = Jacobi::outer_solar().with_simd(simd);
        for id in ["leapfrog", "whckl-c17"] {
            let file = tableau::catalogue::load(id).unwrap();
            let kernel = match &file.table {
                tableau::Table::Splitting(s) => Sequence::from_splitting(s),
                tableau::Table::Composition(c) => Sequence::from_splitting(&c.to_splitting()),
                _ => unreachable!(),
            };
            let chi = file
                .corrector
                .as_ref()
                .map(Sequence::from_splitting)
                .unwrap_or_else(|| Sequence::new([]));
            let method = Processed::new(kernel, chi);
            for h in [2.0, 10.0] {
                let n = (t / h) as usize;
                let mut w = vec![0.0; z0.len()];
                split.from_inertial(&z0, &mut w).unwrap();
                let mut ws = SplitWorkspace::new(split.buffer_len());
                method.enter(&split, h, &mut w, &mut ws).unwrap();
                method
                    .kernel()
                    .steps_merged(&split, h, n, &mut w, &mut ws)
                    .unwrap();
                let mut out = vec![0.0; w.len()];
                method.output(&split, h, &w, &mut out, &mut ws).unwrap();
                let mut z = vec![0.0; w.len()];
                split.to_inertial(&out, &mut z).unwrap();
                let de = (split.energy(&z) - split.energy(&z0)) / split.energy(&z0);
                println!(
                    "{simd:?} {id} h = {h}: error {:.3e}, dE/E {:.3e}",
                    rel_dist(&z, &reference),
                    de
                );
            }
        }
    }
}
