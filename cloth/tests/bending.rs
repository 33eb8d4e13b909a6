//! The isometric bending energy of the inextensible sheet
//! (`material.bending`, `cloth::model` `bending.rs`): its gradient and
//! Hessian against difference quotients, zero on any flat placement, the
//! continuum value `½·B·∫(κ₁ + κ₂)² dA` on a sheet rolled into a cylinder
//! (converging as the grid is refined), the energy inside `H` and the
//! force inside the model's force, and the scene field's defaults and
//! refusals.

use cloth::{ClothModel, DEFAULT_BENDING, Scene, SceneError};
use integrator_core::Separable;

/// An `n × n` inextensible 1 m sheet with bending `b` (N·m; `None`: the
/// field left out), hanging from its top edge when `pinned`.
fn sheet(n: usize, bending: Option<f64>, pinned: bool) -> Scene {
    let bending = bending.map_or(String::new(), |b| format!("bending = {b:e}"));
    let pins = if pinned { "edges = [\"top\"]" } else { "" };
    Scene::from_toml(
        &format!(
            r#"
            gravity = [0.0, -9.81, 0.0]
            [cloth]
            width = 1.0
            height = 1.0
            nx = {n}
            ny = {n}
            plane = "vertical"
            [material]
            density = 0.01378
            stretch = "inextensible"
            shear = 0.002
            {bending}
            [pins]
            {pins}
            [simulation]
            substeps = 4
            frames = 1
            method = "rattle"
        "#
        ),
        "bending.toml",
    )
    .unwrap()
}

/// A deterministic pseudo-random number in [−1, 1) (a 64-bit LCG).
fn noise(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

/// The initial positions moved by up to `amp` (m) in every coordinate:
/// a bent, twisted state.
fn perturbed(model: &ClothModel, amp: f64, seed: u64) -> Vec<f64> {
    let mut s = seed;
    let z = model.initial_state();
    z[..3 * model.free_count()]
        .iter()
        .map(|x| x + amp * noise(&mut s))
        .collect()
}

fn bending_gradient(model: &ClothModel, q: &[f64]) -> Vec<f64> {
    let mut f = vec![0.0; q.len()];
    model.add_bending_force(q, &mut f);
    f.iter().map(|x| -x).collect()
}

#[test]
fn gradient_matches_central_differences() {
    let model = ClothModel::new(&sheet(7, Some(DEFAULT_BENDING), true)).unwrap();
    let q = perturbed(&model, 0.05, 1);
    let grad = bending_gradient(&model, &q);
    let scale = grad.iter().fold(0.0f64, |m, g| m.max(g.abs()));
    assert!(scale > 0.0, "a bent sheet has a bending force");
    let eps = 1e-5;
    let mut worst: f64 = 0.0;
    for k in 0..q.len() {
        let (mut a, mut b) = (q.clone(), q.clone());
        a[k] += eps;
        b[k] -= eps;
        let fd = (model.bending_energy(&a) - model.bending_energy(&b)) / (2.0 * eps);
        worst = worst.max((fd - grad[k]).abs());
    }
    // The energy is quadratic: the central quotient is exact but for the
    // round-off of the energies, ε·E/eps ≈ 1e-16·E/1e-5.
    assert!(
        worst <= 1e-7 * scale,
        "largest |∂E/∂q − quotient| = {worst:e} against a gradient of {scale:e}"
    );
}

#[test]
fn hessian_matches_difference_quotients_of_the_gradient() {
    let model = ClothModel::new(&sheet(6, Some(DEFAULT_BENDING), true)).unwrap();
    let n = model.free_count();
    let mut k = vec![0.0; n * n];
    for (r, c, v) in model.bending_hessian_entries() {
        k[r * n + c] += v;
    }
    let kmax = k.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(kmax > 0.0);
    let q = perturbed(&model, 0.05, 2);
    let eps = 1e-4;
    let mut worst: f64 = 0.0;
    let mut applied = vec![0.0; 3 * n];
    for col in 0..3 * n {
        let (mut a, mut b) = (q.clone(), q.clone());
        a[col] += eps;
        b[col] -= eps;
        let (ga, gb) = (bending_gradient(&model, &a), bending_gradient(&model, &b));
        // The same column through `bending_hessian_apply`.
        let mut unit = vec![0.0; 3 * n];
        unit[col] = 1.0;
        model.bending_hessian_apply(&unit, &mut applied);
        for row in 0..3 * n {
            let fd = (ga[row] - gb[row]) / (2.0 * eps);
            // K ⊗ I₃: coordinate d of particle p couples only to coordinate d.
            let exact = if row % 3 == col % 3 {
                k[(row / 3) * n + col / 3]
            } else {
                0.0
            };
            worst = worst.max((fd - exact).abs());
            assert!(
                (applied[row] - exact).abs() <= 1e-12 * kmax,
                "K·e_{col} row {row}: {} against the assembled {exact}",
                applied[row]
            );
        }
    }
    assert!(
        worst <= 1e-8 * kmax,
        "largest |∂²E − quotient| = {worst:e} against K's largest entry {kmax:e}"
    );
    // Symmetric and positive semidefinite on the vectors tried.
    for r in 0..n {
        for c in 0..n {
            assert!((k[r * n + c] - k[c * n + r]).abs() <= 1e-14 * kmax);
        }
    }
}

#[test]
fn energy_is_zero_on_any_flat_placement() {
    let b = DEFAULT_BENDING;
    let model = ClothModel::new(&sheet(9, Some(b), false)).unwrap();
    let q0 = model.initial_state()[..3 * model.free_count()].to_vec();
    let start = model.bending_energy(&q0);
    assert!(
        start.abs() <= 1e-20 * 0.5 * b,
        "the flat start: {start:e} J"
    );
    // Any affine image of the rest plane is flat: a rotation, a shear in
    // the plane, a stretch, a translation. The stencil rows have linear
    // precision, so each row vanishes up to round-off.
    let (c, s) = (0.6f64.cos(), 0.6f64.sin());
    let maps: [[[f64; 4]; 3]; 3] = [
        [[c, -s, 0.0, 3.0], [s, c, 0.0, -2.0], [0.0, 0.0, 1.0, 7.0]],
        [
            [1.0, 0.4, 0.0, 0.0],
            [0.0, 1.3, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ],
        [
            [0.3, 0.5, 0.2, 1.0],
            [-0.7, 0.1, 0.9, 0.0],
            [0.2, 0.8, -0.4, -5.0],
        ],
    ];
    // The energy of a curvature of 1/m over the sheet, ½·B·1 m²: the
    // scale against which the flat energy must be round-off.
    let curved = 0.5 * b;
    for (k, m) in maps.iter().enumerate() {
        let q: Vec<f64> = q0
            .chunks(3)
            .flat_map(|x| {
                (0..3).map(move |r| m[r][0] * x[0] + m[r][1] * x[1] + m[r][2] * x[2] + m[r][3])
            })
            .collect();
        let e = model.bending_energy(&q);
        assert!(
            e.abs() <= 1e-20 * curved,
            "flat placement {k}: E = {e:e} J against {curved:e} J for a curvature of 1/m"
        );
    }
}

/// The sheet rolled into a cylinder of radius `r` about an axis along its
/// height (arc length kept: an isometry), its energy.
fn rolled(n: usize, b: f64, r: f64) -> f64 {
    let model = ClothModel::new(&sheet(n, Some(b), false)).unwrap();
    let dx = 1.0 / (n - 1) as f64;
    let mut q = vec![0.0; 3 * model.free_count()];
    for j in 0..n {
        for i in 0..n {
            let k = model.free_index(i, j).unwrap();
            let s = i as f64 * dx;
            q[3 * k] = r * (s / r).sin();
            q[3 * k + 1] = -(j as f64) * dx;
            q[3 * k + 2] = r * (1.0 - (s / r).cos());
        }
    }
    model.bending_energy(&q)
}

#[test]
fn rolled_cylinder_approaches_the_continuum_energy() {
    // ½·B·∫(κ₁ + κ₂)² dA with κ₁ = 1/R, κ₂ = 0 over the 1 m² sheet.
    let (b, r) = (DEFAULT_BENDING, 0.5);
    let continuum = 0.5 * b / (r * r);
    let mut last = f64::INFINITY;
    let mut errors = Vec::new();
    for n in [9, 17, 33, 65] {
        let e = rolled(n, b, r);
        let rel = (e - continuum).abs() / continuum;
        errors.push((n, rel));
        assert!(
            rel < last,
            "the error must fall as the grid is refined: {errors:?}"
        );
        last = rel;
        // The interior vertices carry the energy of their areas,
        // (n − 2)²·h²: against that part of the sheet the error is the
        // discretisation's alone, O(h²).
        let h = 1.0 / (n - 1) as f64;
        let inner = continuum * ((n - 2) as f64 * h).powi(2);
        let rel_inner = (e - inner).abs() / inner;
        // Measured: 0.166·(h/R)² at 9² (chords for arcs, the stencil's own
        // truncation).
        assert!(
            rel_inner < 0.2 * (h / r).powi(2),
            "{n}²: E = {e:e} J, the interior's continuum value {inner:e} J, relative error {rel_inner:e}, (h/R)² = {:e}",
            (h / r).powi(2)
        );
    }
    // The missing half-cell strip along the boundary: 1 − (63/64)² = 3.1 %
    // at 65².
    assert!(last < 0.035, "errors by grid: {errors:?}");
}

#[test]
fn bending_enters_the_energy_and_the_force() {
    let model = ClothModel::new(&sheet(6, Some(1e-3), true)).unwrap();
    let q = perturbed(&model, 0.05, 3);
    let mut z = q.clone();
    z.extend(std::iter::repeat_n(0.0, q.len()));
    let e = model.energy(&z);
    assert!(e.bending > 0.0);
    assert_eq!(e.bending, model.bending_energy(&q));
    assert_eq!(
        e.potential(),
        e.springs + e.gravity + e.colliders + e.bending
    );
    assert_eq!(Separable::potential(&model, &q), e.potential());
    // The model's force (the RATTLE kicks') is −∇ of its potential.
    let mut f = vec![0.0; q.len()];
    Separable::force(&model, &q, &mut f);
    let mut no_bend = vec![0.0; q.len()];
    let scene0 = sheet(6, Some(0.0), true);
    Separable::force(&ClothModel::new(&scene0).unwrap(), &q, &mut no_bend);
    let diff = f
        .iter()
        .zip(&no_bend)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(diff > 0.0, "the bending force is in the model's force");
    let eps = 1e-6;
    let scale = f.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for k in 0..q.len() {
        let (mut a, mut b) = (q.clone(), q.clone());
        a[k] += eps;
        b[k] -= eps;
        let fd =
            -(Separable::potential(&model, &a) - Separable::potential(&model, &b)) / (2.0 * eps);
        assert!(
            (fd - f[k]).abs() <= 1e-5 * scale,
            "component {k}: force {} against −∂V/∂q {fd}",
            f[k]
        );
    }
}

#[test]
fn bending_rate_brackets_and_bounds() {
    let model = ClothModel::new(&sheet(16, Some(DEFAULT_BENDING), true)).unwrap();
    let rate = model.bending_rate().unwrap();
    assert!(rate.estimate > 0.0 && rate.estimate <= rate.bound * (1.0 + 1e-12));
    // The discrete biharmonic's top mode on the infinite grid, the
    // checkerboard: K = 64·B/h² per particle (rows of √(B/h²)·(−4, 1, 1, 1,
    // 1)), ω = √(64·B/(h²·m)); the sheet's edges and pins can only lower
    // it, and the checkerboard start brings the estimate close.
    let h = 1.0 / 15.0;
    let approx = (64.0 * DEFAULT_BENDING / (h * h) / model.particle_mass()).sqrt();
    assert!(
        rate.estimate <= approx * (1.0 + 1e-12) && rate.estimate > 0.95 * approx,
        "estimate {} against √(64·B/(h²·m)) = {approx}",
        rate.estimate
    );
    assert!(rate.bound / rate.estimate < 1.1, "{rate:?}");
    assert!(
        ClothModel::new(&sheet(16, Some(0.0), true))
            .unwrap()
            .bending_rate()
            .is_none()
    );
}

fn field_of(e: SceneError) -> String {
    e.field().unwrap_or("").to_string()
}

#[test]
fn scene_field_defaults_and_refusals() {
    assert_eq!(sheet(5, None, true).material.bending, DEFAULT_BENDING);
    assert_eq!(sheet(5, Some(0.0), true).material.bending, 0.0);
    let off = ClothModel::new(&sheet(5, Some(0.0), true)).unwrap();
    assert_eq!(off.bending_stiffness(), 0.0);
    assert_eq!(
        ClothModel::new(&sheet(5, None, true))
            .unwrap()
            .bending_stiffness(),
        DEFAULT_BENDING
    );
    let base = |bending: &str, stretch: &str| {
        let method = if stretch.contains("inextensible") {
            "rattle"
        } else {
            "stormer-verlet"
        };
        Scene::from_toml(
            &format!(
                r#"
                [cloth]
                width = 1.0
                height = 1.0
                nx = 4
                ny = 4
                [material]
                density = 0.1
                stretch = {stretch}
                {bending}
                [pins]
                edges = ["top"]
                [simulation]
                substeps = 4
                frames = 1
                method = "{method}"
            "#
            ),
            "bad.toml",
        )
    };
    for bad in [
        "bending = -1e-6",
        "bending = nan",
        "bending = inf",
        "bending = \"soft\"",
    ] {
        let err = base(bad, "\"inextensible\"").unwrap_err();
        assert_eq!(field_of(err), "material.bending", "{bad}");
    }
    // A spring cloth takes no isometric bending (its `bend` springs bend
    // it), and without the field has none.
    let err = base("bending = 1e-6", "10.0").unwrap_err();
    let msg = err.to_string();
    assert_eq!(field_of(err), "material.bending");
    assert!(msg.contains("inextensible"), "{msg}");
    let springs = base("", "10.0").unwrap();
    assert_eq!(springs.material.bending, 0.0);
    assert_eq!(ClothModel::new(&springs).unwrap().bending_stiffness(), 0.0);
    assert_eq!(base("bending = 0", "10.0").unwrap().material.bending, 0.0);
    // A hand-edited scene is checked again when the model is built.
    let mut edited = base("", "10.0").unwrap();
    edited.material.bending = 1e-6;
    assert_eq!(
        field_of(ClothModel::new(&edited).unwrap_err()),
        "material.bending"
    );
}
