//! The explicit force kernel (stencil loops over the grid, the springs'
//! contributions summed in another order) against the spring lists'
//! force (`force_and_scale`): the same forces to round-off, on grids with
//! pins along an edge, at two corners and none, with and without bend
//! springs, square and not, a collider, and grids large enough for the
//! parallel bands (256² particles and more).

use crate::common::perturbed;
use cloth::{ClothModel, Scene};
use integrator_core::Separable;

fn scene(nx: usize, ny: usize, pins: &str, bend: bool, collider: bool) -> Scene {
    let bend = if bend { "bend = 1.5" } else { "" };
    let collider = if collider {
        "[[colliders]]\ntype = \"sphere\"\ncenter = [0.5, -0.6, 0.5]\nradius = 0.5\nstiffness = 1.0e4\nskin = 0.01\n"
    } else {
        ""
    };
    let text = format!(
        r#"
gravity = [0.0, -9.81, 0.0]
[cloth]
width = 1.0
height = 0.8
nx = {nx}
ny = {ny}
[material]
density = 0.1
stretch = 50.0
shear = 10.0
{bend}
[pins]
{pins}
[simulation]
substeps = 10
frames = 1
method = "leapfrog"
{collider}"#
    );
    Scene::from_toml(&text, "stencil.toml").unwrap()
}

#[test]
fn the_stencil_force_is_the_spring_lists_force_to_round_off() {
    let cases = [
        (9, 7, "edges = [\"top\"]", false, false),
        (
            12,
            12,
            "corners = [\"top-left\", \"top-right\"]",
            true,
            false,
        ),
        (5, 16, "", true, true),
        (40, 30, "edges = [\"top\"]", true, true),
        (64, 64, "edges = [\"top\"]", false, false),
        (70, 50, "corners = [\"top-left\"]", true, false),
        // Two bands on two threads (from 256² particles).
        (300, 220, "edges = [\"top\"]", true, true),
        (
            257,
            259,
            "corners = [\"top-left\", \"top-right\"]",
            true,
            false,
        ),
    ];
    for (nx, ny, pins, bend, collider) in cases {
        let model = ClothModel::new(&scene(nx, ny, pins, bend, collider)).unwrap();
        let q = perturbed(&model);
        let mut lists = vec![0.0; q.len()];
        let scale = model.force_and_scale(&q, &mut lists);
        let mut stencil = vec![f64::NAN; q.len()];
        model.force(&q, &mut stencil);
        let worst = lists
            .iter()
            .zip(&stencil)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        // A particle sums at most 12 spring tensions and its weight, each
        // at most `scale`: reordering the sum moves it by a few ulps of it.
        assert!(
            worst <= 16.0 * f64::EPSILON * scale,
            "{nx}×{ny}, pins {pins}: differs by {worst:e} (scale {scale:e}, {:.1} ε·scale)",
            worst / (f64::EPSILON * scale)
        );
        // The comparison means something: the springs pull with forces far
        // above the tolerance (the state is off the grid).
        let pull = lists.iter().fold(0.0f64, |m, f| m.max(f.abs()));
        assert!(pull > 1e6 * 16.0 * f64::EPSILON * scale, "{pull:e}");
        println!(
            "{nx}×{ny}: largest difference {:.2e} ε·scale",
            worst / (f64::EPSILON * scale)
        );
    }
}

/// Two threads evaluating one model at once (the second finds the
/// scratch taken and works in its own) get what one thread gets.
#[test]
fn concurrent_evaluations_of_one_model_agree() {
    let model = ClothModel::new(&scene(300, 220, "edges = [\"top\"]", true, false)).unwrap();
    let q = perturbed(&model);
    let mut alone = vec![0.0; q.len()];
    model.force(&q, &mut alone);
    std::thread::scope(|s| {
        let runs: Vec<_> = (0..4)
            .map(|_| {
                s.spawn(|| {
                    let mut out = vec![0.0; q.len()];
                    for _ in 0..20 {
                        model.force(&q, &mut out);
                    }
                    out
                })
            })
            .collect();
        for r in runs {
            assert_eq!(r.join().unwrap(), alone);
        }
    });
}
