//! The Gauss–Legendre 2 propagator on a linear gyroscopic system: per-step
//! cost against a plain dense matrix–vector product of the same size, and
//! the one-time cost of forming the propagator.
//!
//! `cargo bench -p integrator-core --bench linear`. The target: on the
//! 1000-dof system (state 2000) a GL2 step costs at most twice a dense
//! matvec.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use faer::linalg::matmul::matmul;
use faer::{Accum, ColMut, ColRef, Mat, Par};
use integrator_core::library::GaussLegendre2;
use integrator_core::linear::{Propagator, gyroscopic};
use integrator_core::{OdeSystem, Step};

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("linear");
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(2));
    group.sample_size(20);
    for dof in [100usize, 1000] {
        let d = 2 * dof;
        let sys = gyroscopic(dof, 1, 1e4).expect("generator");
        let h = 1e-3;
        let (p, q) = (&GaussLegendre2::STABILITY_P, &GaussLegendre2::STABILITY_Q);
        let prop = Propagator::new(&sys, h, p, q).expect("propagator");
        let z0: Vec<f64> = (0..d).map(|i| (0.37 * i as f64).sin()).collect();

        // A plain dense matvec y = A x of the same size (A = Φ, column-major).
        let a: Mat<f64> = prop.matrix().to_owned();
        let mut y = vec![0.0; d];
        group.bench_with_input(BenchmarkId::new("dense_matvec", dof), &dof, |b, _| {
            b.iter(|| {
                matmul(
                    ColMut::from_slice_mut(&mut y).as_mat_mut(),
                    Accum::Replace,
                    a.as_ref(),
                    ColRef::from_slice(black_box(&z0)).as_mat(),
                    1.0,
                    Par::Seq,
                );
                black_box(&y);
            })
        });

        let mut z = z0.clone();
        let mut scratch = prop.workspace();
        group.bench_with_input(BenchmarkId::new("gl2_step", dof), &dof, |b, _| {
            b.iter(|| {
                prop.step(black_box(&mut z), &mut scratch);
            })
        });

        // The same step through the generic `Step` trait (as `integrate` calls it).
        let mut z = z0.clone();
        let mut ws = Step::workspace(&prop, &sys);
        group.bench_with_input(BenchmarkId::new("gl2_step_trait", dof), &dof, |b, _| {
            b.iter(|| Step::step(&prop, &sys, 0.0, h, black_box(&mut z), &mut ws).expect("step"))
        });

        // One right-hand-side evaluation Hz + u (an explicit stage costs this).
        let mut dz = vec![0.0; d];
        group.bench_with_input(BenchmarkId::new("rhs", dof), &dof, |b, _| {
            b.iter(|| sys.rhs(0.0, black_box(&z0), &mut dz))
        });

        group.bench_with_input(BenchmarkId::new("gl2_build", dof), &dof, |b, _| {
            b.iter(|| Propagator::new(black_box(&sys), h, p, q).expect("propagator"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
