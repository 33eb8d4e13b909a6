//! The banded stepper allocates nothing per step nor per frame: a frame of
//! one step and a frame of 200 allocate nothing, on one band or two (the
//! second band's thread is started once, with the stepper). Counted on the test's own thread, which works the first
//! band (the second band's worker runs the same code on its thread); see
//! `no_alloc.rs` for why only one thread is counted.

use cloth::step::{BandedStepper, ClothStepper, sequence_of};
use cloth::{ClothModel, Scene};

mod counting;
use counting::allocations;

#[test]
fn a_frame_allocates_the_same_whatever_its_steps() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/sphere.toml"
    ))
    .unwrap();
    let scene = Scene::from_toml(&text, "sphere.toml").unwrap();
    let model = ClothModel::new(&scene).unwrap();
    let h = scene.simulation.step_size();
    let time = |_| 0.0;
    for bands in [1, 2] {
        for id in ["leapfrog", "stormer-verlet", "forest-ruth"] {
            let seq = sequence_of(id).unwrap();
            let mut stepper = BandedStepper::new(seq, &model, bands);
            let mut z = model.initial_state();
            let mut frame = |steps: usize| {
                allocations(|| {
                    stepper.enter(&model, 0.0, &mut z);
                    stepper.steps(&model, &time, h, steps, &mut z).unwrap();
                    stepper.leave(&model, 0.0, &mut z);
                })
            };
            frame(1); // the first frame may start what lives on (thread-locals)
            let (one, many) = (frame(1), frame(200));
            assert_eq!((one, many), (0, 0), "{id} in {bands} bands");
        }
    }
}
