//! The linear Hamiltonian model `M q̈ + G q̇ + K q = f` as `z' = Hz + u`
//! (paper eqs. (11)–(12)), its exact flow and Runge–Kutta propagators.

use faer::Mat;
use integrator_core::library::{
    GaussLegendre1, GaussLegendre2, GaussLegendre3, LobattoIIIA3, RadauIIA2, Rk4,
};
use integrator_core::linear::{LinearError, LinearHamiltonian, Propagator, gyroscopic};
use integrator_core::{OdeSystem, Scheme, Step, integrate};

fn err_of(r: Result<LinearHamiltonian, LinearError>) -> LinearError {
    match r {
        Ok(_) => panic!("the model was accepted"),
        Err(e) => e,
    }
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().map(|x| x.abs()).fold(0.0, f64::max)
}

/// `out = A x` for a faer matrix.
fn apply(a: faer::MatRef<'_, f64>, x: &[f64]) -> Vec<f64> {
    (0..a.nrows())
        .map(|i| (0..a.ncols()).map(|j| a[(i, j)] * x[j]).sum())
        .collect()
}

/// A deterministic, non-special state.
fn state(dim: usize, phase: f64) -> Vec<f64> {
    (0..dim).map(|i| (1.3 * i as f64 + phase).sin()).collect()
}

const M2: [[f64; 2]; 2] = [[2.0, 0.3], [0.3, 1.0]];
const G2: [[f64; 2]; 2] = [[0.0, 0.7], [-0.7, 0.0]];
const K2: [[f64; 2]; 2] = [[3.0, -1.0], [-1.0, 2.0]];
const F2: [f64; 2] = [0.1, -0.2];

#[test]
fn accepts_a_valid_model() {
    let sys = LinearHamiltonian::from_rows(&M2, &G2, &K2, &F2).unwrap();
    assert_eq!(sys.dof(), 2);
    assert_eq!(sys.dim(), 4);
    let vv: Vec<Vec<f64>> = M2.iter().map(|r| r.to_vec()).collect();
    let gg: Vec<Vec<f64>> = G2.iter().map(|r| r.to_vec()).collect();
    let kk: Vec<Vec<f64>> = K2.iter().map(|r| r.to_vec()).collect();
    let sys2 = LinearHamiltonian::from_rows(&vv, &gg, &kk, &F2).unwrap();
    assert_eq!(sys.matrix(), sys2.matrix());
    // and from faer matrices
    let m = Mat::from_fn(2, 2, |i, j| M2[i][j]);
    let g = Mat::from_fn(2, 2, |i, j| G2[i][j]);
    let k = Mat::from_fn(2, 2, |i, j| K2[i][j]);
    let sys3 = LinearHamiltonian::new(m.as_ref(), g.as_ref(), k.as_ref(), &F2).unwrap();
    assert_eq!(sys.matrix(), sys3.matrix());
}

#[test]
fn refuses_non_symmetric_mass() {
    let m = [[2.0, 0.3], [0.2, 1.0]];
    let e = err_of(LinearHamiltonian::from_rows(&m, &G2, &K2, &F2));
    assert!(
        matches!(e, LinearError::NotSymmetric { matrix: "M", .. }),
        "{e:?}"
    );
    assert!(e.to_string().starts_with("M is not symmetric"), "{e}");
}

#[test]
fn refuses_non_symmetric_stiffness() {
    let k = [[3.0, -1.0], [-1.5, 2.0]];
    let e = err_of(LinearHamiltonian::from_rows(&M2, &G2, &k, &F2));
    assert!(
        matches!(e, LinearError::NotSymmetric { matrix: "K", .. }),
        "{e:?}"
    );
    assert!(e.to_string().starts_with("K is not symmetric"), "{e}");
}

#[test]
fn refuses_gyroscopic_matrix_that_is_not_skew() {
    let g = [[0.0, 0.7], [0.7, 0.0]];
    let e = err_of(LinearHamiltonian::from_rows(&M2, &g, &K2, &F2));
    assert!(matches!(e, LinearError::NotSkew { .. }), "{e:?}");
    assert!(e.to_string().starts_with("G is not skew-symmetric"), "{e}");
    // a nonzero diagonal is not skew either
    let g = [[0.1, 0.7], [-0.7, 0.0]];
    let e = err_of(LinearHamiltonian::from_rows(&M2, &g, &K2, &F2));
    assert!(
        matches!(e, LinearError::NotSkew { i: 0, j: 0, .. }),
        "{e:?}"
    );
}

#[test]
fn refuses_singular_or_indefinite_mass() {
    let singular = [[1.0, 2.0], [2.0, 4.0]];
    let e = err_of(LinearHamiltonian::from_rows(&singular, &G2, &K2, &F2));
    assert!(
        matches!(
            e,
            LinearError::NotPositiveDefinite { .. } | LinearError::SingularMass { .. }
        ),
        "{e:?}"
    );
    assert!(e.to_string().starts_with("M is "), "{e}");
    assert!(e.to_string().contains("positive definite"), "{e}");

    let zero = [[0.0, 0.0], [0.0, 0.0]];
    let e = err_of(LinearHamiltonian::from_rows(&zero, &G2, &K2, &F2));
    assert!(
        e.to_string().starts_with("M is not positive definite"),
        "{e}"
    );

    let indefinite = [[1.0, 0.0], [0.0, -1.0]];
    let e = err_of(LinearHamiltonian::from_rows(&indefinite, &G2, &K2, &F2));
    assert_eq!(e, LinearError::NotPositiveDefinite { pivot: 1 });
    assert_eq!(
        e.to_string(),
        "M is not positive definite: its Cholesky factorisation fails at pivot 1"
    );

    // singular to working precision: the last Cholesky pivot is round-off
    let nearly = [[1.0, 1.0], [1.0, 1.0 + f64::EPSILON]];
    let e = err_of(LinearHamiltonian::from_rows(&nearly, &G2, &K2, &F2));
    assert!(matches!(e, LinearError::SingularMass { .. }), "{e:?}");
    assert!(
        e.to_string()
            .starts_with("M is singular to working precision"),
        "{e}"
    );
}

#[test]
fn refuses_mismatched_sizes() {
    let k3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let k3: Vec<&[f64]> = k3.iter().map(|r| r.as_slice()).collect();
    let m: Vec<&[f64]> = M2.iter().map(|r| r.as_slice()).collect();
    let g: Vec<&[f64]> = G2.iter().map(|r| r.as_slice()).collect();
    let e = err_of(LinearHamiltonian::from_rows(&m, &g, &k3, &F2));
    assert_eq!(
        e,
        LinearError::ShapeMismatch {
            matrix: "K",
            rows: 3,
            cols: 3,
            n: 2
        }
    );
    assert_eq!(e.to_string(), "K is 3×3, but M is 2×2: K must be 2×2");

    let g23: Vec<&[f64]> = vec![&[0.0, 1.0, 0.0], &[-1.0, 0.0, 0.0]];
    let e = err_of(LinearHamiltonian::from_rows(&m, &g23, &g, &F2));
    assert_eq!(e.to_string(), "G is 2×3, but M is 2×2: G must be 2×2");

    let m23: Vec<&[f64]> = vec![&[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0]];
    let e = err_of(LinearHamiltonian::from_rows(&m23, &g, &g, &F2));
    assert_eq!(e.to_string(), "M is 2×3, but it must be square");

    let e = err_of(LinearHamiltonian::from_rows(
        &M2,
        &G2,
        &K2,
        &[1.0, 2.0, 3.0],
    ));
    assert_eq!(
        e.to_string(),
        "f has length 3, but M is 2×2: f must have length 2"
    );

    let ragged: Vec<Vec<f64>> = vec![vec![1.0, 0.0], vec![0.0]];
    let gv: Vec<Vec<f64>> = G2.iter().map(|r| r.to_vec()).collect();
    let e = err_of(LinearHamiltonian::from_rows(&gv, &gv, &ragged, &F2));
    assert!(
        e.to_string().starts_with("K has rows of different lengths"),
        "{e}"
    );

    let empty: [[f64; 0]; 0] = [];
    let e = err_of(LinearHamiltonian::from_rows(&empty, &empty, &empty, &[]));
    assert_eq!(e, LinearError::Empty);
}

#[test]
fn refuses_non_finite_entries() {
    let k = [[3.0, f64::NAN], [f64::NAN, 2.0]];
    let e = err_of(LinearHamiltonian::from_rows(&M2, &G2, &k, &F2));
    assert!(
        matches!(e, LinearError::NonFinite { matrix: "K", .. }),
        "{e:?}"
    );
    assert!(
        e.to_string().starts_with("K[") && e.to_string().ends_with("= NaN is not finite"),
        "{e}"
    );
    let e = err_of(LinearHamiltonian::from_rows(
        &M2,
        &G2,
        &K2,
        &[0.0, f64::INFINITY],
    ));
    assert_eq!(e.to_string(), "f[1] = inf is not finite");
}

/// `M q̈ + G q̇ + K q − f` at a state `z`, with `q̇`, `ṗ` from `z' = Hz + u`
/// and `q̈ = (d/dt) q̇ = H_qq q̇ + H_qp ṗ` (the q-rows of `H` applied to `z'`).
fn second_order_residual(
    sys: &LinearHamiltonian,
    h: faer::MatRef<'_, f64>,
    z: &[f64],
) -> (Vec<f64>, f64) {
    let n = sys.dof();
    let mut dz = apply(h, z);
    for i in 0..n {
        dz[n + i] += sys.force()[i];
    }
    let qd = &dz[..n];
    let ddz = apply(h, &dz); // z'' = H z' (u constant)
    let qdd = &ddz[..n];
    let (mq, gq, kq) = (
        apply(sys.mass(), qdd),
        apply(sys.gyroscopic(), qd),
        apply(sys.stiffness(), &z[..n]),
    );
    let res: Vec<f64> = (0..n)
        .map(|i| mq[i] + gq[i] + kq[i] - sys.force()[i])
        .collect();
    let scale = max_abs(&mq) + max_abs(&gq) + max_abs(&kq) + max_abs(sys.force());
    (res, scale)
}

#[test]
fn first_order_form_reproduces_the_second_order_equation() {
    let sys = gyroscopic(6, 11, 5.0).unwrap();
    let n = sys.dof();
    // the generator's G is far from zero, so the sign of GM⁻¹G/4 matters
    assert!(sys.gyroscopic().norm_max() > 0.05);
    for phase in [0.0, 0.4, 2.0] {
        let z = state(2 * n, phase);
        let (res, scale) = second_order_residual(&sys, sys.matrix(), &z);
        assert!(
            max_abs(&res) < 1e-13 * scale,
            "residual {res:?}, scale {scale}"
        );

        // z' = Hz + u is what rhs returns, and the jacobian is H
        let mut dz = vec![0.0; 2 * n];
        sys.rhs(0.0, &z, &mut dz);
        let mut hz = apply(sys.matrix(), &z);
        for i in 0..n {
            hz[n + i] += sys.force()[i];
        }
        assert!(max_abs_diff(&dz, &hz) < 1e-14 * max_abs(&hz));
        let mut jac = vec![0.0; 4 * n * n];
        assert!(sys.jacobian(0.0, &z, &mut jac));
        assert_eq!(jac[2 * n + 1], sys.matrix()[(1, 1)]);
        assert_eq!(jac[(2 * n) * (n + 1)], sys.matrix()[(n + 1, 0)]);
    }

    // p = M q̇ + Gq/2: q̇ = M⁻¹(p − Gq/2)
    let z = state(2 * n, 0.3);
    let (q, p) = z.split_at(n);
    let gq = apply(sys.gyroscopic(), q);
    let w: Vec<f64> = (0..n).map(|i| p[i] - 0.5 * gq[i]).collect();
    let qd = apply(sys.mass_inverse(), &w);
    let mut dz = vec![0.0; 2 * n];
    sys.rhs(0.0, &z, &mut dz);
    assert!(max_abs_diff(&dz[..n], &qd) < 1e-13 * max_abs(&qd));

    // The paper's B = GM⁻¹G/4 − K is the right sign: with the other sign,
    // −GM⁻¹G/4 − K, the residual is exactly −GM⁻¹Gq/2, which is not small
    // when the gyroscopic coupling is strong.
    let sys = LinearHamiltonian::from_rows(
        &[[2.0, 0.3, 0.0], [0.3, 1.0, 0.1], [0.0, 0.1, 1.5]],
        &[[0.0, 3.0, -1.0], [-3.0, 0.0, 2.0], [1.0, -2.0, 0.0]],
        &[[3.0, -1.0, 0.0], [-1.0, 2.0, -0.5], [0.0, -0.5, 1.0]],
        &[0.1, -0.2, 0.3],
    )
    .unwrap();
    let n = sys.dof();
    let z = state(2 * n, 0.0);
    let (res, scale) = second_order_residual(&sys, sys.matrix(), &z);
    assert!(
        max_abs(&res) < 1e-13 * scale,
        "residual {res:?}, scale {scale}"
    );
    let q = &z[..n];
    let gmg_q = apply(
        sys.gyroscopic(),
        &apply(sys.mass_inverse(), &apply(sys.gyroscopic(), q)),
    );
    let mut wrong = sys.matrix().to_owned();
    let gmg = Mat::from_fn(n, n, |i, j| {
        let e: Vec<f64> = (0..n).map(|l| if l == j { 1.0 } else { 0.0 }).collect();
        apply(
            sys.gyroscopic(),
            &apply(sys.mass_inverse(), &apply(sys.gyroscopic(), &e)),
        )[i]
    });
    for i in 0..n {
        for j in 0..n {
            wrong[(n + i, j)] -= 0.5 * gmg[(i, j)];
        }
    }
    let (res, scale) = second_order_residual(&sys, wrong.as_ref(), &z);
    let expected: Vec<f64> = gmg_q.iter().map(|x| -0.5 * x).collect();
    assert!(
        max_abs(&expected) > 0.1 * scale,
        "{expected:?}, scale {scale}"
    );
    assert!(
        max_abs_diff(&res, &expected) < 1e-12 * scale,
        "{res:?} vs {expected:?}"
    );
}

#[test]
fn exact_solution_satisfies_the_second_order_equation() {
    // Finite differences of the exact flow: M q̈ + G q̇ + K q = f.
    let sys = gyroscopic(5, 3, 3.0).unwrap();
    let n = sys.dof();
    let z0 = state(2 * n, 1.0);
    let (t, d) = (0.7, 1e-3);
    let zm = sys.exact(&z0, t - d).unwrap();
    let z = sys.exact(&z0, t).unwrap();
    let zp = sys.exact(&z0, t + d).unwrap();
    let qd: Vec<f64> = (0..n).map(|i| (zp[i] - zm[i]) / (2.0 * d)).collect();
    let qdd: Vec<f64> = (0..n)
        .map(|i| (zp[i] - 2.0 * z[i] + zm[i]) / (d * d))
        .collect();
    let (mq, gq, kq) = (
        apply(sys.mass(), &qdd),
        apply(sys.gyroscopic(), &qd),
        apply(sys.stiffness(), &z[..n]),
    );
    let res: Vec<f64> = (0..n)
        .map(|i| mq[i] + gq[i] + kq[i] - sys.force()[i])
        .collect();
    let scale = max_abs(&mq) + max_abs(&gq) + max_abs(&kq) + max_abs(sys.force());
    // O(d²ω⁴) truncation plus O(ε/d²) round-off
    assert!(
        max_abs(&res) < 1e-4 * scale,
        "residual {res:?}, scale {scale}"
    );
    // and z(0) is z0
    let z_at_0 = sys.exact(&z0, 0.0).unwrap();
    assert!(max_abs_diff(&z_at_0, &z0) < 1e-15);
}

#[test]
fn energy_matches_the_original_variables_and_is_conserved_by_the_exact_flow() {
    let sys = gyroscopic(6, 5, 20.0).unwrap();
    let n = sys.dof();
    let z0 = state(2 * n, 0.2);
    // E = ½ (p − Gq/2)ᵀM⁻¹(p − Gq/2) + ½ qᵀKq − qᵀf
    let (q, p) = z0.split_at(n);
    let gq = apply(sys.gyroscopic(), q);
    let w: Vec<f64> = (0..n).map(|i| p[i] - 0.5 * gq[i]).collect();
    let mw = apply(sys.mass_inverse(), &w);
    let kq = apply(sys.stiffness(), q);
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let e = 0.5 * dot(&w, &mw) + 0.5 * dot(q, &kq) - dot(q, sys.force());
    let e0 = sys.energy(&z0);
    assert!((e - e0).abs() < 1e-13 * e0.abs().max(1.0), "{e} vs {e0}");
    // ½ zᵀSz − zᵀ(Ju), S = −JH
    let s = sys.energy_matrix();
    let quad = dot(&z0, &apply(s.as_ref(), &z0));
    assert!((0.5 * quad - dot(q, sys.force()) - e0).abs() < 1e-13 * e0.abs().max(1.0));
    for i in 0..2 * n {
        for j in 0..2 * n {
            assert_eq!(s[(i, j)], s[(j, i)], "S is not symmetric at ({i}, {j})");
        }
    }

    for t in [0.1, 1.0, 7.5, 30.0] {
        let z = sys.exact(&z0, t).unwrap();
        let drift = (sys.energy(&z) - e0).abs() / e0.abs();
        assert!(drift < 1e-11, "energy drift {drift:e} at t = {t}");
    }
    // without force too, and the force matters
    let free = sys.with_force(&vec![0.0; n]).unwrap();
    assert!((free.energy(&z0) - e0).abs() > 1e-6);
    let z = free.exact(&z0, 3.0).unwrap();
    assert!((free.energy(&z) - free.energy(&z0)).abs() < 1e-11 * free.energy(&z0).abs());
}

/// The largest relative energy error over `steps` steps of `z ← Φz + φ`,
/// sampled every 100 steps.
fn energy_drift(
    sys: &LinearHamiltonian,
    phi: faer::MatRef<'_, f64>,
    offset: &[f64],
    steps: usize,
) -> f64 {
    let mut z = state(sys.dim(), 0.5);
    let e0 = sys.energy(&z);
    let mut worst: f64 = 0.0;
    for k in 0..steps {
        z = apply(phi, &z);
        for (zi, oi) in z.iter_mut().zip(offset) {
            *zi += oi;
        }
        if k % 100 == 99 {
            worst = worst.max((sys.energy(&z) - e0).abs() / e0.abs());
        }
    }
    worst
}

#[test]
fn gauss_legendre_propagators_conserve_the_energy_over_ten_thousand_steps() {
    // Frequencies 1 … 100, h·ω_max = 2: far from the asymptotic regime.
    let forced = gyroscopic(10, 7, 100.0).unwrap();
    let free = forced.with_force(&[0.0; 10]).unwrap();
    let (h, steps) = (0.02, 10_000);
    let s = free.energy_matrix();
    let s_norm = s.norm_max();
    let ev = s.self_adjoint_eigenvalues(faer::Side::Lower).unwrap();
    let kappa = ev[ev.len() - 1] / ev[0];
    // Round-off scale: a relative error ε·κ(S) per step in the worst
    // direction, accumulated linearly; the propagators stay 100× below.
    let round_off = steps as f64 * f64::EPSILON * kappa / 100.0;
    let table: [(&str, &[f64], &[f64]); 3] = [
        (
            "gauss1",
            &GaussLegendre1::STABILITY_P,
            &GaussLegendre1::STABILITY_Q,
        ),
        (
            "gauss2",
            &GaussLegendre2::STABILITY_P,
            &GaussLegendre2::STABILITY_Q,
        ),
        (
            "gauss3",
            &GaussLegendre3::STABILITY_P,
            &GaussLegendre3::STABILITY_Q,
        ),
    ];
    for sys in [&free, &forced] {
        // The exact flow exp(hH), rounded to doubles and stepped the same
        // way, is the yardstick for what round-off does.
        let (exact_phi, exact_offset) = sys.flow(h);
        let exact_drift = energy_drift(sys, exact_phi.as_ref(), &exact_offset, steps);
        assert!(exact_drift < round_off, "exact flow: {exact_drift:e}");
        for (name, p, q) in table {
            let prop = Propagator::new(sys, h, p, q).unwrap();
            // Φ is S-orthogonal: ΦᵀSΦ = S
            let phi = prop.matrix();
            let sphi = Mat::from_fn(20, 20, |i, j| {
                (0..20).map(|l| s[(i, l)] * phi[(l, j)]).sum::<f64>()
            });
            let mut dev: f64 = 0.0;
            for i in 0..20 {
                for j in 0..20 {
                    let x: f64 = (0..20).map(|l| phi[(l, i)] * sphi[(l, j)]).sum();
                    dev = dev.max((x - s[(i, j)]).abs());
                }
            }
            assert!(dev < 1e-11 * s_norm, "{name}: ΦᵀSΦ − S = {dev:e}");

            let drift = energy_drift(sys, phi, prop.offset(), steps);
            assert!(
                drift < round_off && drift < 2.0 * exact_drift,
                "{name}: relative energy error {drift:e} (exact flow {exact_drift:e}, round-off scale {round_off:e})"
            );

            // and `step` is that same map
            let mut z = state(20, 0.5);
            let mut scratch = prop.workspace();
            prop.step(&mut z, &mut scratch);
            let mut y = apply(phi, &state(20, 0.5));
            for (yi, oi) in y.iter_mut().zip(prop.offset()) {
                *yi += oi;
            }
            assert!(max_abs_diff(&z, &y) < 1e-13 * max_abs(&y));
        }
    }

    // Not so for non-symplectic schemes: RK4 and Radau IIA lose energy.
    for (name, p, q) in [
        ("rk4", &Rk4::STABILITY_P[..], &Rk4::STABILITY_Q[..]),
        (
            "radau2a-2",
            &RadauIIA2::STABILITY_P[..],
            &RadauIIA2::STABILITY_Q[..],
        ),
    ] {
        let prop = Propagator::new(&free, h, p, q).unwrap();
        let mut z = state(20, 0.5);
        let e0 = free.energy(&z);
        let mut scratch = prop.workspace();
        for _ in 0..steps {
            prop.step(&mut z, &mut scratch);
        }
        let loss = (e0 - free.energy(&z)) / e0;
        assert!(loss > 1e-3, "{name}: relative energy loss {loss:e}");
    }
}

/// `(order, P, Q, step counts)`.
type Case<'a> = (usize, &'a [f64], &'a [f64], &'a [usize]);

/// `‖z_N − z(T)‖_∞ / ‖z(T)‖_∞` after `N` steps.
fn global_error(sys: &LinearHamiltonian, p: &[f64], q: &[f64], t_end: f64, steps: usize) -> f64 {
    let z0 = state(sys.dim(), 0.9);
    let exact = sys.exact(&z0, t_end).unwrap();
    let prop = Propagator::new(sys, t_end / steps as f64, p, q).unwrap();
    let mut z = z0;
    let mut scratch = prop.workspace();
    for _ in 0..steps {
        prop.step(&mut z, &mut scratch);
    }
    max_abs_diff(&z, &exact) / max_abs(&exact)
}

#[test]
fn propagators_converge_at_order_two_s_with_and_without_forcing() {
    // The forcing is integrated at the method's order.
    let forced = gyroscopic(6, 21, 4.0).unwrap();
    assert!(max_abs(forced.force()) > 0.1);
    let free = forced.with_force(&[0.0; 6]).unwrap();
    let table: [Case; 4] = [
        (
            2,
            &GaussLegendre1::STABILITY_P,
            &GaussLegendre1::STABILITY_Q,
            &[32, 64, 128, 256],
        ),
        (
            4,
            &GaussLegendre2::STABILITY_P,
            &GaussLegendre2::STABILITY_Q,
            &[16, 32, 64, 128],
        ),
        (
            6,
            &GaussLegendre3::STABILITY_P,
            &GaussLegendre3::STABILITY_Q,
            &[8, 16, 32, 64],
        ),
        (
            4,
            &Rk4::STABILITY_P,
            &Rk4::STABILITY_Q,
            &[128, 256, 512, 1024],
        ),
    ];
    for (order, p, q, steps) in table {
        for sys in [&free, &forced] {
            let errs: Vec<f64> = steps
                .iter()
                .map(|&n| global_error(sys, p, q, 2.0, n))
                .collect();
            for w in errs.windows(2) {
                let observed = (w[0] / w[1]).log2();
                assert!(
                    (observed - order as f64).abs() < 0.35,
                    "order {order}: errors {errs:?}, observed {observed:.2}"
                );
            }
        }
    }
}

#[test]
fn propagator_agrees_with_the_explicit_scheme_it_describes() {
    // RK4 steps any OdeSystem; its propagator must be the same map,
    // forcing included.
    let sys = gyroscopic(5, 2, 3.0).unwrap();
    let h = 0.05;
    let prop = Propagator::new(&sys, h, &Rk4::STABILITY_P, &Rk4::STABILITY_Q).unwrap();
    let z0 = state(10, 0.1);
    let mut a = z0.clone();
    integrate(&Rk4, &sys, &mut a, 0.0, h, 40, |_, _, _| {}).unwrap();
    let mut b = z0.clone();
    prop.integrate(&sys, &mut b, 0.0, 40, |_, _, _| {}).unwrap();
    assert!(max_abs_diff(&a, &b) < 1e-12 * max_abs(&a), "{a:?} vs {b:?}");
    // the generic runner with the propagator as a scheme
    let mut c = z0.clone();
    let mut seen = 0;
    integrate(&prop, &sys, &mut c, 0.0, h, 40, |k, _, _| seen = k).unwrap();
    assert_eq!(seen, 40);
    assert_eq!(b, c);
}

#[test]
fn propagator_refusals() {
    let sys = LinearHamiltonian::from_rows(&M2, &G2, &K2, &F2).unwrap();
    let p = GaussLegendre2::STABILITY_P;
    let q = GaussLegendre2::STABILITY_Q;
    assert_eq!(
        Propagator::new(&sys, 0.0, &p, &q).unwrap_err(),
        LinearError::StepSize(0.0)
    );
    assert!(matches!(
        Propagator::new(&sys, f64::NAN, &p, &q).unwrap_err(),
        LinearError::StepSize(_)
    ));
    let e = Propagator::new(&sys, 0.1, &[2.0, 1.0], &q).unwrap_err();
    assert_eq!(
        e.to_string(),
        "P(0) = 2, but a stability function R = P/Q has P(0) = Q(0) = 1"
    );
    let e = Propagator::new(&sys, 0.1, &p, &[]).unwrap_err();
    assert_eq!(e, LinearError::EmptyPolynomial { which: "Q" });

    // H = [[0, 1], [1, 0]] (M = 1, K = −1) has eigenvalues ±1; implicit
    // Euler (Q(x) = 1 − x) has its pole at hλ = 1.
    let unstable = LinearHamiltonian::from_rows(&[[1.0]], &[[0.0]], &[[-1.0]], &[0.0]).unwrap();
    let e = Propagator::new(&unstable, 1.0, &[1.0], &[1.0, -1.0]).unwrap_err();
    assert!(
        matches!(e, LinearError::SingularDenominator { h: 1.0, .. }),
        "{e:?}"
    );
    assert!(Propagator::new(&unstable, 0.5, &[1.0], &[1.0, -1.0]).is_ok());

    let prop = Propagator::new(&sys, 0.1, &p, &q).unwrap();
    assert!(prop.check_step(0.1).is_ok());
    assert_eq!(
        prop.check_step(0.2).unwrap_err().to_string(),
        "the propagator was built for h = 0.1, but was asked to step h = 0.2"
    );
}

#[test]
fn stepping_with_another_h_is_an_error() {
    let sys = LinearHamiltonian::from_rows(&M2, &G2, &K2, &F2).unwrap();
    let prop = Propagator::new(
        &sys,
        0.1,
        &GaussLegendre1::STABILITY_P,
        &GaussLegendre1::STABILITY_Q,
    )
    .unwrap();
    let mut z = vec![1.0, 0.0, 0.0, 0.0];
    let err = integrate(&prop, &sys, &mut z, 0.0, 0.2, 1, |_, _, _| {}).unwrap_err();
    assert_eq!(
        err.to_string(),
        "step 1 (from t = 0) failed: this stepper was prepared for h = 0.1, but the step asked for h = 0.2"
    );
    assert_eq!(
        z,
        [1.0, 0.0, 0.0, 0.0],
        "a refused step leaves the state alone"
    );
}

#[test]
fn generator_is_deterministic_and_has_the_requested_spread() {
    let a = gyroscopic(8, 42, 1e4).unwrap();
    let b = gyroscopic(8, 42, 1e4).unwrap();
    let c = gyroscopic(8, 43, 1e4).unwrap();
    assert_eq!(a.matrix(), b.matrix());
    assert_eq!(a.force(), b.force());
    assert_ne!(a.matrix(), c.matrix());

    for (seed, spread) in [(1, 1.0), (2, 10.0), (3, 1e4)] {
        let sys = gyroscopic(8, seed, spread).unwrap();
        let h = sys.matrix().to_owned();
        let eig = h.eigenvalues().unwrap();
        let (mut lo, mut hi) = (f64::INFINITY, 0.0_f64);
        for l in &eig {
            assert!(
                l.re.abs() < 1e-9 * spread,
                "eigenvalue {l:?} is not imaginary"
            );
            lo = lo.min(l.im.abs());
            hi = hi.max(l.im.abs());
        }
        assert!(
            lo >= 0.78 * (1.0 - 1e-9) && hi <= (spread + 0.25) * (1.0 + 1e-9),
            "[{lo}, {hi}]"
        );
        assert!(hi / lo > 0.5 * spread, "spread {} for {spread}", hi / lo);
    }

    assert!(matches!(
        gyroscopic(0, 1, 10.0),
        Err(LinearError::Parameter { name: "n", .. })
    ));
    assert!(matches!(
        gyroscopic(3, 1, 0.5),
        Err(LinearError::Parameter { name: "spread", .. })
    ));
}

#[test]
fn stage_solver_steps_a_stiff_gyroscopic_system_far_beyond_the_explicit_limit() {
    // Frequencies 1 … 10⁴ and h = 0.01: h·ω_max = 100. Newton on the exact
    // Jacobian solves the (linear) stage equations in one iteration; what
    // is left is the round-off floor of an ill-conditioned stage matrix,
    // which the solver must recognise as convergence, not as divergence —
    // also for Lobatto IIIA, whose first stage is explicit (Z₁ = 0 exactly).
    // The Jacobian is constant: one evaluation and one factorisation serve
    // the whole run.
    let sys = gyroscopic(10, 1, 1e4)
        .unwrap()
        .with_force(&[0.0; 10])
        .unwrap();
    let h = 0.01;
    let steps = 100;
    // q(0) = 0, p(0) = 1, as `symlab compare --hard` starts it.
    let z0: Vec<f64> = (0..20).map(|i| if i < 10 { 0.0 } else { 1.0 }).collect();
    let e0 = sys.energy(&z0);
    fn run<M: Step<LinearHamiltonian> + Scheme>(
        m: &M,
        sys: &LinearHamiltonian,
        z0: &[f64],
        h: f64,
        steps: usize,
        e0: f64,
    ) -> (Vec<f64>, f64, M::Workspace) {
        let mut z = z0.to_vec();
        let mut ws = m.workspace(sys);
        let mut worst: f64 = 0.0;
        for k in 0..steps {
            m.step(sys, k as f64 * h, h, &mut z, &mut ws)
                .unwrap_or_else(|e| panic!("{} at step {k}: {e}", M::INFO.name));
            worst = worst.max((sys.energy(&z) - e0).abs() / e0.abs());
        }
        (z, worst, ws)
    }
    let exact = |p: &[f64], q: &[f64]| {
        let prop = Propagator::new(&sys, h, p, q).unwrap();
        let mut b = z0.clone();
        prop.integrate(&sys, &mut b, 0.0, steps, |_, _, _| {})
            .unwrap();
        b
    };
    // Gauss–Legendre 2 (symplectic: conserves the quadratic energy).
    let (a, worst, ws) = run(&GaussLegendre2, &sys, &z0, h, steps, e0);
    let b = exact(&GaussLegendre2::STABILITY_P, &GaussLegendre2::STABILITY_Q);
    assert!(
        max_abs_diff(&a, &b) < 1e-8 * max_abs(&b),
        "gauss2: stage solver vs propagator {:e}",
        max_abs_diff(&a, &b)
    );
    assert!(worst < 1e-9, "gauss2: relative energy error {worst:e}");
    let st = ws.stats();
    assert_eq!(
        (st.jacobian_evaluations, st.factorizations),
        (1, 1),
        "{st:?}"
    );
    // Lobatto IIIA, 3 stages (A-stable, not symplectic).
    let (a, _, ws) = run(&LobattoIIIA3, &sys, &z0, h, steps, e0);
    let b = exact(&LobattoIIIA3::STABILITY_P, &LobattoIIIA3::STABILITY_Q);
    assert!(
        max_abs_diff(&a, &b) < 1e-8 * max_abs(&b),
        "lobatto3a-3: stage solver vs propagator {:e}",
        max_abs_diff(&a, &b)
    );
    let st = ws.stats();
    assert_eq!(
        (st.jacobian_evaluations, st.factorizations),
        (1, 1),
        "{st:?}"
    );
}
