//! The force loop, the Jacobian values and whole steps allocate nothing
//! (counted by a global allocator, on the test's own thread only: the test
//! harness's main thread allocates now and then while a test runs, which
//! made the count flaky; the scene is small enough that the force kernel
//! runs on the calling thread).

use cloth::{ClothModel, Scene};
use integrator_core::library::{StormerVerlet, SymplecticEulerA};
use integrator_core::{Separable, Step};

mod counting;
use counting::allocations;

#[test]
fn forces_jacobians_and_steps_do_not_allocate() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/sphere.toml"
    ))
    .unwrap();
    let scene = Scene::from_toml(&text, "sphere.toml").unwrap();
    let model = ClothModel::new(&scene).unwrap();
    let mut z = model.initial_state();
    let n = model.dof();
    let mut f = vec![0.0; n];
    let mut values = vec![0.0; model.force_jacobian_nnz()];
    let mut ws_se = SymplecticEulerA.workspace(&model);
    let mut ws_sv = StormerVerlet.workspace(&model);
    let h = scene.simulation.step_size();
    let count = allocations(|| {
        model.force(&z[..n], &mut f);
        model.velocity(&z[n..], &mut f);
        model.force_jacobian_values(&z[..n], &mut values);
        for _ in 0..10 {
            SymplecticEulerA
                .step(&model, 0.0, h, &mut z, &mut ws_se)
                .unwrap();
            StormerVerlet
                .step(&model, 0.0, h, &mut z, &mut ws_sv)
                .unwrap();
        }
        let _ = model.energy(&z);
        let _ = model.max_strain(&z[..n]);
    });
    assert_eq!(count, 0);
}
