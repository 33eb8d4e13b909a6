//! A midpoint step as minimisation (`integrator_core::minimise`) allocates
//! nothing once its stepper is built: Newton's scratch, the Hessian values
//! and the sparse Cholesky's factor and workspace are all allocated up
//! front (counted by a global allocator; this binary has a single test so
//! that nothing else allocates meanwhile).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use cloth::{ClothModel, Scene};
use integrator_core::minimise::{MidpointSettings, MidpointStepper};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn midpoint_minimisation_steps_do_not_allocate() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/sphere.toml"
    ))
    .unwrap();
    let scene = Scene::from_toml(&text, "sphere.toml").unwrap();
    let model = ClothModel::new(&scene).unwrap();
    let mut z = model.initial_state();
    let x = 1.0 / (2.0 - 2f64.cbrt());
    let h = 1.0 / 240.0;
    // A first stepper's first step meets what the process initialises once
    // (faer's and std's lazily built globals, measured 490 allocations);
    // a stepper built afterwards allocates nothing from its first step on.
    {
        let mut first = MidpointStepper::new(&model, MidpointSettings::default()).unwrap();
        first.step(&model, &[1.0], h, &mut z.clone()).unwrap();
    }
    let mut stepper = MidpointStepper::new(&model, MidpointSettings::default()).unwrap();
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    for _ in 0..10 {
        stepper.step(&model, &[1.0], h, &mut z).unwrap();
        stepper
            .step(&model, &[x, 1.0 - 2.0 * x, x], h, &mut z)
            .unwrap();
    }
    let count = ALLOCATIONS.load(Ordering::SeqCst) - before;
    assert!(stepper.stats().factorizations > 0);
    assert!(stepper.stats().iterations > 20);
    assert_eq!(
        count, 0,
        "{count} allocations in 20 steps (the first included)"
    );
}
