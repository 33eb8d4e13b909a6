//! The least time of 100 Wisdom–Holman steps (h = 10 days, outer solar
//! system) over many tries, per step: robust to a loaded machine (a try
//! that was preempted is slower, never faster). `cargo run --release -p
//! integrator-core --example wh_min_time`.
use std::hint::black_box;
use std::time::Instant;

use integrator_core::problems::OuterSolarSystem;
use integrator_core::problems::wisdom_holman::{DemocraticHeliocentric, Jacobi};
use integrator_core::simd::Simd;

fn least(mut f: impl FnMut()) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..20_000 {
        let t = Instant::now();
        f();
        best = best.min(t.elapsed().as_secs_f64());
    }
    best
}

fn main() {
    let z0 = OuterSolarSystem.initial_state();
    for simd in [Simd::Auto, Simd::Portable] {
        let jac = Jacobi::outer_solar().with_simd(simd);
        let mut w = vec![0.0; 36];
        jac.from_inertial(&z0, &mut w).unwrap();
        let step = least(|| jac.integrate(black_box(10.0), 100, &mut w).unwrap()) / 100.0;
        let kep = least(|| {
            for _ in 0..100 {
                jac.kepler_flow(black_box(10.0), &mut w).unwrap()
            }
        }) / 100.0;
        let kick = least(|| {
            for _ in 0..100 {
                jac.interaction_kick(black_box(1e-3), &mut w).unwrap()
            }
        }) / 100.0;
        let dh = DemocraticHeliocentric::outer_solar().with_simd(simd);
        let mut u = vec![0.0; 36];
        dh.from_inertial(&z0, &mut u).unwrap();
        let dstep = least(|| dh.integrate(black_box(10.0), 100, &mut u).unwrap()) / 100.0;
        println!(
            "{simd:?}: Jacobi step {:.1} ns (Kepler {:.1}, kick {:.1}); democratic step {:.1} ns",
            step * 1e9,
            kep * 1e9,
            kick * 1e9,
            dstep * 1e9
        );
    }
}
