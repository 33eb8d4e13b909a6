//! The cost of the exact Kepler drift per call, and of a Wisdom–Holman step
//! on the outer solar system, for comparison with REBOUND's WHFast
//! (`reb_integrator_whfast_kepler_solver`, timed on the same orbits and
//! steps by `compare/peers/rebound_kepler_bench.py`).
//!
//! `cargo bench -p integrator-core --bench kepler`. Orbits: GM = 1, a = 1
//! (period P = 2π), e = 0.05, 0.5, 0.9, starting at true anomaly 1; a
//! hyperbola with e = 1.5, a = −1 (steps in units of 1/n). Steps P/400 (about
//! a Wisdom–Holman step of 10 days on Jupiter, P/433), P/20 (the
//! Wisdom–Holman regime's long end) and 3P (reduced by whole periods
//! first). Each call drifts the same starting state, so the cost does not
//! wander with the phase.

use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use integrator_core::kepler::{KeplerSolver, LANES, drift};
use integrator_core::problems::OuterSolarSystem;
use integrator_core::problems::wisdom_holman::GradientKick;
use integrator_core::problems::wisdom_holman::{DemocraticHeliocentric, Jacobi, WarmJacobi};
use integrator_core::scheme::SplitWorkspace;
use integrator_core::sequence::Sequence;
use integrator_core::simd::{Level, Simd};
use integrator_core::split::Split;

fn state(a: f64, e: f64, nu: f64) -> ([f64; 3], [f64; 3]) {
    let p = a * (1.0 - e * e);
    let r = p / (1.0 + e * nu.cos());
    let w = (1.0 / p).sqrt();
    (
        [r * nu.cos(), r * nu.sin(), 0.1 * r],
        [-w * nu.sin(), w * (e + nu.cos()), 0.0],
    )
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("kepler_drift");
    group.warm_up_time(Duration::from_millis(300));
    group.measurement_time(Duration::from_secs(1));
    let cases = [
        ("e0.05", 1.0, 0.05),
        ("e0.5", 1.0, 0.5),
        ("e0.9", 1.0, 0.9),
        ("hyperbolic_e1.5", -1.0, 1.5),
    ];
    for (name, a, e) in cases {
        let (x0, v0) = state(a, e, 1.0);
        for (label, h) in [
            ("P/400", 2.0 * PI / 400.0),
            ("P/20", 2.0 * PI / 20.0),
            ("3P", 3.0 * 2.0 * PI),
        ] {
            group.bench_with_input(BenchmarkId::new(name, label), &h, |b, &h| {
                b.iter(|| {
                    let (mut x, mut v) = (x0, v0);
                    drift(1.0, black_box(h), &mut x, &mut v).unwrap();
                    black_box((x, v))
                })
            });
        }
    }
    group.finish();

    // `drift_lanes`: four orbits at once, steps P/400 (one evaluation, the
    // regime of a Wisdom–Holman step on the outer solar system) and P/20
    // (divide by 4 for the cost of one drift): four copies of e = 0.05,
    // and the four orbits above side by side; each beside the same four
    // drifts one by one (`_scalar`).
    let mut group = c.benchmark_group("kepler_drift_lanes");
    group.warm_up_time(Duration::from_millis(300));
    group.measurement_time(Duration::from_secs(1));
    let solver = KeplerSolver::default();
    let same = [state(1.0, 0.05, 1.0); LANES];
    let mixed = cases.map(|(_, a, e)| state(a, e, 1.0));
    for (label, orbits) in [("4x_e0.05", same), ("mixed", mixed)] {
        let x0 = orbits.map(|o| o.0);
        let v0 = orbits.map(|o| o.1);
        for (step, h) in [("P/400", 2.0 * PI / 400.0), ("P/20", 2.0 * PI / 20.0)] {
            group.bench_with_input(BenchmarkId::new(label, step), &h, |b, &h| {
                b.iter(|| {
                    let (mut x, mut v) = (x0, v0);
                    solver
                        .drift_lanes(&[1.0; LANES], black_box(h), &mut x, &mut v, LANES)
                        .unwrap();
                    black_box((x, v))
                })
            });
            // The same four drifts one by one, for the comparison.
            group.bench_with_input(
                BenchmarkId::new(format!("{label}_scalar"), step),
                &h,
                |b, &h| {
                    b.iter(|| {
                        let (mut x, mut v) = (x0, v0);
                        for l in 0..LANES {
                            solver
                                .drift(1.0, black_box(h), &mut x[l], &mut v[l])
                                .unwrap();
                        }
                        black_box((x, v))
                    })
                },
            );
        }
    }
    group.finish();

    // 100 Wisdom–Holman steps (merged: per step five drifts and a kick),
    // outer solar system, h = 10 days, in the split's own coordinates:
    // divide by 100 for the cost of a step.
    let mut group = c.benchmark_group("wisdom_holman_step");
    group.warm_up_time(Duration::from_millis(300));
    group.measurement_time(Duration::from_secs(2));
    let z0 = OuterSolarSystem.initial_state();
    let jac = Jacobi::outer_solar();
    let mut w = vec![0.0; 36];
    jac.from_inertial(&z0, &mut w).unwrap();
    group.bench_function("jacobi_100_steps_h10", |b| {
        b.iter(|| jac.integrate(black_box(10.0), 100, &mut w).unwrap())
    });
    // At 600 days (a seventh of Jupiter's period, near the step that gives
    // 1e-4 over 10⁵ days), where the drifts take two evaluations.
    jac.from_inertial(&z0, &mut w).unwrap();
    group.bench_function("jacobi_100_steps_h600", |b| {
        b.iter(|| jac.integrate(black_box(600.0), 100, &mut w).unwrap())
    });
    let dh = DemocraticHeliocentric::outer_solar();
    let mut w = vec![0.0; 36];
    dh.from_inertial(&z0, &mut w).unwrap();
    group.bench_function("democratic_heliocentric_100_steps_h10", |b| {
        b.iter(|| dh.integrate(black_box(10.0), 100, &mut w).unwrap())
    });
    // The same on the portable lanes (the fallback where the processor has
    // no AVX-512; the same bits), for the ratio in the same run.
    let jac = Jacobi::outer_solar().with_simd(Simd::Portable);
    let mut w = vec![0.0; 36];
    jac.from_inertial(&z0, &mut w).unwrap();
    group.bench_function("jacobi_100_steps_h10_portable", |b| {
        b.iter(|| jac.integrate(black_box(10.0), 100, &mut w).unwrap())
    });
    let dh = DemocraticHeliocentric::outer_solar().with_simd(Simd::Portable);
    let mut w = vec![0.0; 36];
    dh.from_inertial(&z0, &mut w).unwrap();
    group.bench_function("democratic_heliocentric_100_steps_h10_portable", |b| {
        b.iter(|| dh.integrate(black_box(10.0), 100, &mut w).unwrap())
    });
    group.finish();

    // The parts of a Jacobi step on their own (100 of each), on both
    // implementations of the lanes.
    let mut group = c.benchmark_group("wisdom_holman_parts");
    group.warm_up_time(Duration::from_millis(300));
    group.measurement_time(Duration::from_secs(1));
    for (label, simd) in [("auto", Simd::Auto), ("portable", Simd::Portable)] {
        let jac = Jacobi::outer_solar().with_simd(simd);
        let mut w0 = vec![0.0; 36];
        jac.from_inertial(&z0, &mut w0).unwrap();
        let mut w = w0.clone();
        group.bench_function(format!("jacobi_kepler_100_h10_{label}"), |b| {
            b.iter(|| {
                for _ in 0..100 {
                    jac.kepler_flow(black_box(10.0), &mut w).unwrap();
                }
            })
        });
        let mut w = w0.clone();
        group.bench_function(format!("jacobi_kepler_100_h600_{label}"), |b| {
            b.iter(|| {
                for _ in 0..100 {
                    jac.kepler_flow(black_box(600.0), &mut w).unwrap();
                }
            })
        });
        let mut w = w0.clone();
        group.bench_function(format!("jacobi_kick_100_h10_{label}"), |b| {
            b.iter(|| {
                for _ in 0..100 {
                    jac.interaction_kick(black_box(1e-3), &mut w).unwrap();
                }
            })
        });
    }
    group.finish();

    // Every SIMD level this processor has, by name (whatever
    // `SYMLAB_SIMD` says; the same bits on each): 100 steps of the Jacobi
    // split at 10 and 600 days, of WHCKM's kernel (the exact modified
    // kick, in the registers' loop) and of the democratic heliocentric
    // split.
    let mut group = c.benchmark_group("wisdom_holman_levels");
    group.warm_up_time(Duration::from_millis(300));
    group.measurement_time(Duration::from_secs(2));
    for level in Level::ALL.into_iter().filter(|l| l.available()) {
        let simd = Simd::from(level);
        let jac = Jacobi::outer_solar().with_simd(simd);
        let mut w0 = vec![0.0; 36];
        jac.from_inertial(&z0, &mut w0).unwrap();
        for h in [10.0, 600.0] {
            let mut w = w0.clone();
            group.bench_function(format!("jacobi_100_steps_h{h}_{level}"), |b| {
                b.iter(|| jac.integrate(black_box(h), 100, &mut w).unwrap())
            });
        }
        let whckm = Jacobi::outer_solar()
            .with_simd(simd)
            .with_gradient_kick(GradientKick::Exact);
        let mut w = w0.clone();
        group.bench_function(format!("whckm_run_100_h10_{level}"), |b| {
            b.iter(|| {
                let mut k = 0;
                while k < 100 {
                    k += whckm.kick_drift_run(black_box(10.0), 1e-2, 10.0, 10.0, 100 - k, &mut w);
                    if k < 100 {
                        whckm.interaction_kick_modified(10.0, 1e-2, &mut w).unwrap();
                        whckm.kepler_flow(10.0, &mut w).unwrap();
                        k += 1;
                    }
                }
            })
        });
        let dh = DemocraticHeliocentric::outer_solar().with_simd(simd);
        let mut w = vec![0.0; 36];
        dh.from_inertial(&z0, &mut w).unwrap();
        group.bench_function(
            format!("democratic_heliocentric_100_steps_h10_{level}"),
            |b| b.iter(|| dh.integrate(black_box(10.0), 100, &mut w).unwrap()),
        );
    }
    group.finish();

    // The Kepler solver's warm start at long steps: 100 leapfrog steps
    // merged across steps (`Sequence::steps_merged`, as compare's timed
    // `wh:` runs), the run's history carried from one batch to the next,
    // warm start off and on, at the level `SYMLAB_SIMD` allows. Each
    // batch is a fresh run from the same state with a fresh history, as
    // compare's timed runs (a state carried over millions of steps this
    // long would wander off). Jupiter's drift is long (outside the lanes'
    // short-step path) from about 1100 days; below that the two are the
    // same code.
    let mut group = c.benchmark_group("wisdom_holman_warm");
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(2));
    let seq = Sequence::from_catalogue("leapfrog").unwrap();
    for h in [500.0, 1000.0, 1500.0, 2000.0] {
        for warm in [false, true] {
            let jac = Jacobi::outer_solar().with_kepler_warm_start(warm);
            let mut w0 = vec![0.0; 36];
            jac.from_inertial(&z0, &mut w0).unwrap();
            let mut ws = SplitWorkspace::new(jac.buffer_len());
            let label = if warm { "warm" } else { "cold" };
            group.bench_function(format!("leapfrog_100_steps_h{h}_{label}"), |b| {
                b.iter(|| {
                    let mut w = w0.clone();
                    let run = WarmJacobi::new(&jac);
                    seq.steps_merged(&run, black_box(h), 100, &mut w, &mut ws)
                        .unwrap();
                    black_box(w)
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
