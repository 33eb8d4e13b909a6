//! Cost of one step per spring: symplectic Euler and Störmer–Verlet, in
//! both library forms (`stormer-verlet`, the Lobatto IIIA–IIIB pair,
//! kick–drift–kick, which evaluates the force twice per step; `leapfrog`,
//! drift–kick–drift, once, reusing the last velocity), on n × n grids with
//! all three spring families. The throughput is in springs, so criterion's
//! `thrpt` is springs per second: ns/spring = 10⁹/thrpt. Also the force
//! evaluation alone: the stencil kernel (on the default rayon pool, and on
//! one thread) and the spring lists it replaced (`force_and_scale`, which
//! walks them one spring at a time and tracks the force scale besides).
//!
//! Group `frame/<scheme>`: a frame of [`FRAME`] steps as the run loop takes
//! it, per iteration, with the throughput in springs × steps (so again
//! ns/spring/step = 10⁹/thrpt): `own` is the scheme's own step on one
//! thread (the stencil kernel, today's path), `banded-1` and `banded-2` the
//! banded stepper (`cloth::step::banded`) on one band and on two bands on
//! two threads, `enter`, the steps and `leave` included.

use std::hint::black_box;

use cloth::step::{BandedStepper, ClothStepper, sequence_of};
use cloth::{ClothModel, Scene};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use integrator_core::library::{Leapfrog, StormerVerlet, SymplecticEulerA};
use integrator_core::{Scheme, Separable, Step};

fn scene(n: usize) -> Scene {
    let text = format!(
        r#"
gravity = [0.0, -9.81, 0.0]
[cloth]
width = 1.0
height = 1.0
nx = {n}
ny = {n}
[material]
density = 0.1
stretch = 50.0
shear = 10.0
bend = 1.0
[pins]
edges = ["top"]
[simulation]
substeps = 100
frames = 1
method = "stormer-verlet"
"#
    );
    Scene::from_toml(&text, "bench.toml").expect("bench scene")
}

/// A state a few steps into the fall, so that springs are not at rest.
fn state(model: &ClothModel, h: f64) -> Vec<f64> {
    let mut z = model.initial_state();
    let mut ws = StormerVerlet.workspace(model);
    for _ in 0..20 {
        StormerVerlet.step(model, 0.0, h, &mut z, &mut ws).unwrap();
    }
    z
}

fn bench_step<S: Step<ClothModel> + Scheme>(c: &mut Criterion, scheme: S, id: &str) {
    let mut group = c.benchmark_group(format!("step/{id}"));
    for n in [32, 64, 128] {
        let scene = scene(n);
        let model = ClothModel::new(&scene).unwrap();
        let h = 0.5
            * model
                .stability_at(&model.initial_state()[..model.dof()], 200)
                .h_max;
        let mut z = state(&model, h);
        let mut ws = scheme.workspace(&model);
        scheme.step(&model, 0.0, h, &mut z, &mut ws).unwrap();
        group.throughput(Throughput::Elements(model.active_spring_count() as u64));
        group.bench_function(BenchmarkId::from_parameter(format!("{n}x{n}")), |b| {
            b.iter(|| {
                // Valid reuse: z is what the previous step left.
                scheme
                    .step_reusing(&model, 0.0, h, black_box(&mut z), &mut ws, true)
                    .unwrap();
            })
        });
    }
    group.finish();
}

/// Steps per iteration of the `frame` group.
const FRAME: usize = 64;

fn bench_frame<S: Step<ClothModel> + Scheme>(c: &mut Criterion, scheme: S, id: &str) {
    let mut group = c.benchmark_group(format!("frame/{id}"));
    // 16²: where two threads stop paying (`BANDED_FROM`).
    for n in [16, 32, 64, 128] {
        let scene = scene(n);
        let model = ClothModel::new(&scene).unwrap();
        let h = 0.5
            * model
                .stability_at(&model.initial_state()[..model.dof()], 200)
                .h_max;
        let z0 = state(&model, h);
        group.throughput(Throughput::Elements(
            (model.active_spring_count() * FRAME) as u64,
        ));
        let mut z = z0.clone();
        let mut ws = scheme.workspace(&model);
        let mut reuse = false;
        group.bench_function(BenchmarkId::new("own", format!("{n}x{n}")), |b| {
            b.iter(|| {
                for _ in 0..FRAME {
                    scheme
                        .step_reusing(&model, 0.0, h, black_box(&mut z), &mut ws, reuse)
                        .unwrap();
                    reuse = true;
                }
            })
        });
        for bands in [1, 2] {
            let seq = sequence_of(id).expect("a drift–kick scheme");
            let mut stepper = BandedStepper::new(seq, &model, bands);
            let mut z = z0.clone();
            let time = |_| 0.0;
            group.bench_function(
                BenchmarkId::new(format!("banded-{bands}"), format!("{n}x{n}")),
                |b| {
                    b.iter(|| {
                        stepper.enter(&model, 0.0, &mut z);
                        stepper.steps(&model, &time, h, FRAME, &mut z).unwrap();
                        stepper.leave(&model, 0.0, black_box(&mut z));
                    })
                },
            );
        }
    }
    group.finish();
}

fn frames(c: &mut Criterion) {
    bench_frame(c, SymplecticEulerA, "symplectic-euler-a");
    bench_frame(c, StormerVerlet, "stormer-verlet");
}

fn springs(c: &mut Criterion) {
    bench_step(c, SymplecticEulerA, "symplectic-euler-a");
    bench_step(c, StormerVerlet, "stormer-verlet");
    bench_step(c, Leapfrog, "leapfrog");
    let mut group = c.benchmark_group("force");
    for n in [32, 64, 128] {
        let model = ClothModel::new(&scene(n)).unwrap();
        let z = state(&model, 1e-5);
        let mut f = vec![0.0; model.dof()];
        group.throughput(Throughput::Elements(model.active_spring_count() as u64));
        group.bench_function(BenchmarkId::from_parameter(format!("{n}x{n}")), |b| {
            b.iter(|| model.force(black_box(&z[..model.dof()]), &mut f))
        });
        // The stencil kernel on one thread (a rayon pool of one).
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        group.bench_function(
            BenchmarkId::from_parameter(format!("{n}x{n}-one-thread")),
            |b| one.install(|| b.iter(|| model.force(black_box(&z[..model.dof()]), &mut f))),
        );
        // The spring lists walked one spring at a time (the kernel before
        // the stencil, with the force scale's bookkeeping on top).
        group.bench_function(
            BenchmarkId::from_parameter(format!("{n}x{n}-spring-lists")),
            |b| b.iter(|| model.force_and_scale(black_box(&z[..model.dof()]), &mut f)),
        );
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2));
    targets = springs, frames
}
criterion_main!(benches);
