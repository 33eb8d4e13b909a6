//! The model: forces are the exact negative gradient of the potential, the
//! sparse Jacobian is the derivative of the forces, output helpers agree
//! with the state, and the stability estimate matches a dense eigensolver.

use cloth::{ClothModel, Scene};
use integrator_core::Separable;
use nalgebra::{DMatrix, SymmetricEigen};

/// A small scene with every term: three families, pins of each kind,
/// gravity, a sphere and a plane the perturbed cloth reaches into.
const FULL: &str = r#"
gravity = [0.3, -9.81, 0.2]

[cloth]
width = 1.0
height = 0.8
nx = 6
ny = 5
origin = [-0.5, 0.1, -0.4]
plane = "horizontal"
prestretch = 1.05

[material]
density = 0.3
stretch = 40.0
shear = 7.0
bend = 0.9

[pins]
corners = ["top-left"]
points = [[3, 0], [5, 4]]

[[colliders]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 0.3
stiffness = 2e4
skin = 0.05

[[colliders]]
type = "plane"
point = [0.0, 0.1, 0.0]
normal = [0.1, 1.0, 0.0]
stiffness = 5e3
skin = 0.01

[simulation]
substeps = 10
frames = 1
method = "leapfrog"
"#;

fn model() -> ClothModel {
    ClothModel::new(&Scene::from_toml(FULL, "full.toml").unwrap()).unwrap()
}

/// A deterministic pseudo-random sequence in [-1, 1).
fn noise(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// The initial positions perturbed by up to `amp` in each coordinate.
fn perturbed(m: &ClothModel, amp: f64, seed: u64) -> Vec<f64> {
    let z = m.initial_state();
    let mut r = noise(seed);
    z[..m.dof()].iter().map(|x| x + amp * r()).collect()
}

/// Which particles are in contact, in the skin, or free of the colliders:
/// the test must cover the cubic ramp, the quadratic part and no contact.
fn contact_kinds(m: &ClothModel, q: &[f64]) -> (usize, usize) {
    let mut deep = 0;
    let mut skin = 0;
    for x in q.chunks(3) {
        let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
        let d = 0.3 - r;
        if d > 0.05 {
            deep += 1;
        } else if d > 0.0 {
            skin += 1;
        }
    }
    let _ = m;
    (deep, skin)
}

#[test]
fn force_is_the_negative_gradient_of_the_potential() {
    let m = model();
    assert_eq!(m.free_count(), 30 - 3);
    let q = perturbed(&m, 0.08, 1);
    let (deep, skin) = contact_kinds(&m, &q);
    assert!(
        deep > 0 && skin > 0,
        "deep {deep}, skin {skin}: adjust the test scene"
    );
    let mut f = vec![0.0; m.dof()];
    m.force(&q, &mut f);
    let fmax = f.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let eps = 1e-6;
    let mut qq = q.clone();
    let mut worst: f64 = 0.0;
    for i in 0..m.dof() {
        qq[i] = q[i] + eps;
        let vp = m.potential(&qq);
        qq[i] = q[i] - eps;
        let vm = m.potential(&qq);
        qq[i] = q[i];
        let fd = -(vp - vm) / (2.0 * eps);
        worst = worst.max((fd - f[i]).abs() / fmax);
    }
    eprintln!("deep {deep}, skin {skin}: max |F_fd − F|/max|F| = {worst:e}");
    assert!(worst < 1e-6, "max |F_fd − F|/max|F| = {worst:e}");
}

/// Dense `∂F/∂q` from the sparse pattern and values.
fn dense_jacobian(m: &ClothModel, q: &[f64]) -> DMatrix<f64> {
    let pattern = m.force_jacobian_pattern();
    let mut values = vec![f64::NAN; pattern.len()];
    m.force_jacobian_values(q, &mut values);
    let mut j = DMatrix::zeros(m.dof(), m.dof());
    for (&(r, c), v) in pattern.iter().zip(&values) {
        j[(r, c)] += v;
    }
    j
}

#[test]
fn the_sparse_jacobian_is_the_derivative_of_the_force() {
    let m = model();
    let q = perturbed(&m, 0.08, 2);
    let j = dense_jacobian(&m, &q);
    let jmax = j.amax();
    let eps = 1e-6;
    let mut qq = q.clone();
    let (mut fp, mut fm) = (vec![0.0; m.dof()], vec![0.0; m.dof()]);
    let mut worst: f64 = 0.0;
    for c in 0..m.dof() {
        qq[c] = q[c] + eps;
        m.force(&qq, &mut fp);
        qq[c] = q[c] - eps;
        m.force(&qq, &mut fm);
        qq[c] = q[c];
        for r in 0..m.dof() {
            let fd = (fp[r] - fm[r]) / (2.0 * eps);
            worst = worst.max((fd - j[(r, c)]).abs() / jmax);
        }
    }
    eprintln!("max |J_fd − J|/max|J| = {worst:e}");
    assert!(worst < 1e-6, "max |J_fd − J|/max|J| = {worst:e}");
    // −∇²V is symmetric.
    assert!((&j - j.transpose()).amax() <= 1e-12 * jmax);
}

#[test]
fn the_jacobian_pattern_is_in_compressed_column_order() {
    let m = model();
    let pattern = m.force_jacobian_pattern();
    assert_eq!(pattern.len(), m.force_jacobian_nnz());
    assert_eq!(pattern.len() % 9, 0);
    for w in pattern.windows(2) {
        let ((r0, c0), (r1, c1)) = (w[0], w[1]);
        assert!(
            c0 < c1 || (c0 == c1 && r0 < r1),
            "not sorted: {:?} then {:?}",
            w[0],
            w[1]
        );
    }
    assert!(pattern.iter().all(|&(r, c)| r < m.dof() && c < m.dof()));
}

#[test]
fn positions_triangles_strain_and_momentum() {
    let m = model();
    let z = m.initial_state();
    let (q, p) = z.split_at(m.dof());
    let x = m.positions(q);
    assert_eq!(x.len(), 30);
    // Pinned (3, 0) stays where the grid puts it.
    let pin = x[3];
    assert!((pin - nalgebra::Vector3::new(-0.5 + 3.0 * 0.2 * 1.05, 0.1, -0.4)).norm() < 1e-12);
    // Prestretch 1.05: every spring strained by 5 %.
    assert!((m.max_strain(q) - 0.05).abs() < 1e-12);
    assert_eq!(m.momentum(p), nalgebra::Vector3::zeros());
    let tris = m.triangles();
    assert_eq!(tris.len(), 2 * 5 * 4);
    assert!(tris.iter().flatten().all(|&i| i < 30));
    // Counter-clockwise about u × v = x × z = −y for a horizontal sheet.
    let [a, b, c] = tris[0];
    let n = (x[b] - x[a]).cross(&(x[c] - x[a]));
    assert!(n.y < 0.0);
    assert_eq!(m.free_index(3, 0), None);
    assert_eq!(m.free_index(1, 0), Some(0));
    assert_eq!(m.free_particle(m.free_index(4, 2).unwrap()), 2 * 6 + 4);
    assert_eq!(m.family_counts(), [5 * 5 + 6 * 4, 2 * 5 * 4, 4 * 5 + 6 * 3]);
}

#[test]
fn obj_output_round_trips() {
    let m = model();
    let z = m.initial_state();
    let x = m.positions(&z[..m.dof()]);
    let tris = m.triangles();
    let path = std::env::temp_dir().join(format!("cloth-test-{}.obj", std::process::id()));
    cloth::write_obj(&path, &x, &tris).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).ok();
    let v: Vec<Vec<f64>> = text
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| l.split(' ').map(|t| t.parse().unwrap()).collect())
        .collect();
    let f: Vec<Vec<usize>> = text
        .lines()
        .filter_map(|l| l.strip_prefix("f "))
        .map(|l| l.split(' ').map(|t| t.parse().unwrap()).collect())
        .collect();
    assert_eq!(v.len(), x.len());
    assert_eq!(f.len(), tris.len());
    for (a, b) in v.iter().zip(&x) {
        assert_eq!(a.as_slice(), b.as_slice());
    }
    assert_eq!(f[0], vec![tris[0][0] + 1, tris[0][1] + 1, tris[0][2] + 1]);
    let err = cloth::write_obj("/nonexistent/dir/x.obj", &x, &tris).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("/nonexistent/dir/x.obj: cannot write"),
        "{err}"
    );
}

#[test]
fn the_stability_estimate_matches_a_dense_eigensolver() {
    let scene = Scene::from_toml(FULL, "full.toml").unwrap();
    let m = ClothModel::new(&scene).unwrap();
    let q = perturbed(&m, 0.01, 3);
    let k = -dense_jacobian(&m, &q) * m.inverse_mass();
    let eig = SymmetricEigen::new(k);
    let lmax = eig.eigenvalues.iter().copied().fold(f64::MIN, f64::max);
    let st = m.stability_at(&q, 5000);
    let rel = (st.omega_max - lmax.sqrt()).abs() / lmax.sqrt();
    assert!(
        rel < 1e-4,
        "power iteration ω = {}, dense ω = {}",
        st.omega_max,
        lmax.sqrt()
    );
    assert!(st.omega_bound >= lmax.sqrt() * (1.0 - 1e-12));
    assert!((st.h_max - 2.0 / st.omega_max).abs() < 1e-15 * st.h_max.max(1.0));
}
