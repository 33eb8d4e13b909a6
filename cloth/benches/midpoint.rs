//! Cost of one Newton midpoint step on the paper's sheet at 64 × 64
//! (`scenes/paper64.toml`), solved as an energy minimisation
//! ([`integrator_core::minimise::MidpointStepper`], sparse Cholesky). Each
//! sample starts from the same state, 0.1 s into the fall, with the
//! stepper's memory (starting guess, kept factor) forgotten, so every
//! iteration is one cold step of size 1/240 s (four steps per 60 Hz frame):
//! the symbolic analysis is done once, outside the timing, as in a run.

use std::hint::black_box;

use cloth::{ClothModel, Scene};
use criterion::{Criterion, criterion_group, criterion_main};
use integrator_core::library::StormerVerlet;
use integrator_core::minimise::{MidpointSettings, MidpointStepper};
use integrator_core::{Separable, Step};

fn midpoint(c: &mut Criterion) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/paper64.toml");
    let scene = Scene::load(path).expect("scenes/paper64.toml");
    let model = ClothModel::new(&scene).expect("paper64 model");
    // 0.1 s of fall with an explicit scheme well inside its limit.
    let mut z = model.initial_state();
    let h_explicit = 0.5 * model.stability_at(&z[..model.dof()], 200).h_max;
    let steps = (0.1 / h_explicit).ceil() as usize;
    let h = 0.1 / steps as f64;
    let mut ws = StormerVerlet.workspace(&model);
    for _ in 0..steps {
        StormerVerlet.step(&model, 0.0, h, &mut z, &mut ws).unwrap();
    }
    let z0 = z.clone();
    let tau = 1.0 / 240.0;
    let mut stepper = MidpointStepper::new(&model, MidpointSettings::default()).unwrap();
    let mut group = c.benchmark_group("newton-midpoint");
    group.sample_size(10);
    group.bench_function("64x64", |b| {
        b.iter(|| {
            stepper.reset();
            z.copy_from_slice(&z0);
            stepper
                .midpoint_step(&model, tau, black_box(&mut z))
                .unwrap();
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(5));
    targets = midpoint
}
criterion_main!(benches);
