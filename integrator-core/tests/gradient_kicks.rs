//! Gradient (modified) kicks, `exp(h·B + γ·[B,[A,B]])` with `γ = g·h³`
//! ([`Split::flow_b_gradient`]): a [`Sequence`] calls them with the right
//! arguments, a system without them refuses, and the kernel they make — the
//! Wisdom–Holman–Touma kernel `D(½) G(1, 1/24) D(½)` of REBOUND's WHCKL and
//! WHCKM, processed by the corrector of order 17 — has the `ε²h⁴` error
//! that the plain leapfrog kernel with the same corrector (`ε²h²`) lacks:
//! measured both on `A = (q² + p²)/2`, `B = q⁴/4` with the exact modified
//! kick, and on the Jacobi split of a Sun with two planets with the lazy
//! implementer's kick of [`Jacobi::interaction_kick_gradient`].

use std::cell::RefCell;

use integrator_core::problems::wisdom_holman::Jacobi;

use crate::quartic;
use integrator_core::processed::{self, Processed};
use integrator_core::scheme::SplitWorkspace;
use integrator_core::sequence::Sequence;
use integrator_core::{FlowError, Part, PartBuffers, SolveError, Split, StateSpace, StepError};
use quartic::Quartic;

/// The corrector of order 17 (Wisdom 2006, as REBOUND's), from the
/// catalogue's WHCKC entry, which shares it.
fn corrector17() -> Sequence {
    let file = tableau::catalogue::load("whckc-c17").unwrap();
    Sequence::from_splitting(file.corrector.as_ref().unwrap())
}

/// `D(½) G(1, g) D(½)`: leapfrog with a gradient kick (`g = 0`: plain).
fn kernel(g: f64) -> Sequence {
    Sequence::with_gradients([(Part::A, 0.5, 0.0), (Part::B, 1.0, g), (Part::A, 0.5, 0.0)])
}

/// Least-squares slope of `log e` against `log h`.
fn slope(points: &[(f64, f64)]) -> f64 {
    let k = points.len() as f64;
    let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().map(|(h, e)| (h.ln(), e.ln())).unzip();
    let (mx, my) = (xs.iter().sum::<f64>() / k, ys.iter().sum::<f64>() / k);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Records every flow it is asked for.
#[derive(Default)]
struct Recorder {
    calls: RefCell<Vec<(char, f64, f64)>>,
}

impl StateSpace for Recorder {
    fn state_len(&self) -> usize {
        1
    }
}

impl Split for Recorder {
    fn flow_a(&self, h: f64, _: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        self.calls.borrow_mut().push(('A', h, 0.0));
        Ok(())
    }
    fn flow_b(&self, h: f64, _: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        self.calls.borrow_mut().push(('B', h, 0.0));
        Ok(())
    }
    fn flow_b_gradient(
        &self,
        h: f64,
        gamma: f64,
        _: &mut [f64],
        _: PartBuffers<'_>,
    ) -> Result<(), FlowError> {
        self.calls.borrow_mut().push(('G', h, gamma));
        Ok(())
    }
}

#[test]
fn a_sequence_calls_gradient_kicks_with_gamma_g_h_cubed() {
    let sys = Recorder::default();
    let seq = kernel(1.0 / 24.0);
    let mut z = [0.0];
    let mut ws = SplitWorkspace::new(1);
    seq.apply(&sys, 0.5, &mut z, &mut ws).unwrap();
    let gamma = 0.125 / 24.0;
    assert_eq!(
        *sys.calls.borrow(),
        vec![('A', 0.25, 0.0), ('G', 0.5, gamma), ('A', 0.25, 0.0)]
    );
    // The inverse negates time and weight; merging across steps keeps the
    // gradient kick whole (the drifts at the ends merge).
    assert_eq!(seq.inverse().gradients(), &[0.0, -1.0 / 24.0, 0.0]);
    assert!(seq.merges());
    sys.calls.borrow_mut().clear();
    seq.steps_merged(&sys, 0.5, 2, &mut z, &mut ws).unwrap();
    assert_eq!(
        *sys.calls.borrow(),
        vec![
            ('A', 0.25, 0.0),
            ('G', 0.5, gamma),
            ('A', 0.5, 0.0),
            ('G', 0.5, gamma),
            ('A', 0.25, 0.0)
        ]
    );
    // A gradient kick at the ends does not merge with the next step's.
    let kdk = Sequence::with_gradients([
        (Part::B, 0.5, 0.1),
        (Part::A, 1.0, 0.0),
        (Part::B, 0.5, 0.1),
    ]);
    assert!(!kdk.merges());
}

#[test]
fn a_system_without_gradient_kicks_refuses_them_naming_the_part() {
    /// Only the two flows; the default `flow_b_gradient`.
    struct Plain;
    impl StateSpace for Plain {
        fn state_len(&self) -> usize {
            2
        }
    }
    impl Split for Plain {
        fn flow_a(
            &self,
            _: f64,
            _: &mut [f64],
            _: PartBuffers<'_>,
            _: bool,
        ) -> Result<(), FlowError> {
            Ok(())
        }
        fn flow_b(
            &self,
            _: f64,
            _: &mut [f64],
            _: PartBuffers<'_>,
            _: bool,
        ) -> Result<(), FlowError> {
            Ok(())
        }
    }
    let method = Processed::new(kernel(1.0 / 24.0), Sequence::new([]));
    let mut z = [1.0, 0.0];
    let err = processed::integrate(&method, &Plain, &mut z, 0.0, 0.1, 3, |_, _, _| {}).unwrap_err();
    assert_no_gradient_kick(&err);
}

/// The refusal of a gradient kick by a system that has none: an error of
/// the kick (part B) in the first step.
fn assert_no_gradient_kick(err: &StepError) {
    match err {
        StepError::Solve {
            step: 1,
            source:
                SolveError::Flow {
                    part: Part::B,
                    source,
                },
            ..
        } => assert!(source.to_string().contains("no gradient kick"), "{source}"),
        other => panic!("{other:?}"),
    }
}

/// `χ Kⁿ χ⁻¹` of `kernel` on `sys` from `z0` to `t`, in `n` steps.
fn run<S: Split>(kernel: &Sequence, sys: &S, z0: &[f64], t: f64, n: usize) -> Vec<f64> {
    let method = Processed::new(kernel.clone(), corrector17());
    let mut z = z0.to_vec();
    processed::integrate(&method, sys, &mut z, 0.0, t / n as f64, n, |_, _, _| {}).unwrap();
    z
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// The error of `kernel(g)` with the corrector against `error(kernel, ε, n)`
/// at `n = 50, 100, 200` steps over `t`: its slope in `h` (at `eps[0]`) and
/// `log₂` of its growth from `eps[0]` to `eps[1] = 2·eps[0]`.
fn scaling(
    g: f64,
    t: f64,
    eps: [f64; 2],
    error: impl Fn(&Sequence, f64, usize) -> f64,
) -> (f64, f64) {
    let k = kernel(g);
    let mut points = Vec::new();
    let mut powers = Vec::new();
    for n in [50, 100, 200] {
        let errs = eps.map(|e| error(&k, e, n));
        println!(
            "g = {g:.4}: n = {n}: error {:.3e} (ε = {:e}), {:.3e} (ε = {:e})",
            errs[0], eps[0], errs[1], eps[1]
        );
        points.push((t / n as f64, errs[0]));
        powers.push((errs[1] / errs[0]).log2());
    }
    let s = slope(&points);
    let power = powers.iter().sum::<f64>() / powers.len() as f64;
    println!("g = {g:.4}: slope {s:.2}, ε power {power:.2}");
    (s, power)
}

#[test]
fn the_gradient_kernel_with_the_corrector_has_an_eps2_h4_error() {
    // ε = 0.02 and 0.04, T = 20, h = 0.4 … 0.1: the ε term (order 18 with
    // the corrector) is far below the ε² term. The reference: the gradient
    // kernel at h = 0.0125 (its ε²h⁴ error 4096× below h = 0.1's).
    let z0 = [1.0, 0.5];
    let t = 20.0;
    for (g, p2) in [(1.0 / 24.0, 4.0), (0.0, 2.0)] {
        let (s, power) = scaling(g, t, [0.02, 0.04], |k, eps, n| {
            let sys = Quartic { eps };
            let reference = run(&kernel(1.0 / 24.0), &sys, &z0, t, 1600);
            dist(&run(k, &sys, &z0, t, n), &reference)
        });
        assert!((s - p2).abs() < 0.3, "g = {g}: slope {s:.2}, expected {p2}");
        assert!(
            (power - 2.0).abs() < 0.3,
            "g = {g}: ε power {power:.2}, expected 2"
        );
    }
}

/// A Sun of mass 1 with two planets of masses `eps` and `2·eps` (G = 1) on
/// slightly eccentric, slightly inclined orbits at a = 1 and 1.6: the
/// inertial `[x; p]`.
fn two_planets(eps: f64) -> (Jacobi, Vec<f64>) {
    let m = [1.0, eps, 2.0 * eps];
    let split = Jacobi::new(1.0, &m, None).unwrap();
    let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.02], [0.0, 1.6, -0.01]];
    let v = [[0.0, 0.0, 0.0], [0.0, 1.05, 0.01], [-0.8, 0.0, 0.0]];
    let mut z = vec![0.0; 18];
    for i in 0..3 {
        for k in 0..3 {
            z[3 * i + k] = x[i][k];
            z[9 + 3 * i + k] = m[i] * v[i][k];
        }
    }
    (split, z)
}

/// The run in Jacobi coordinates, converted in and out.
fn run_jacobi(kernel: &Sequence, split: &Jacobi, z0: &[f64], t: f64, n: usize) -> Vec<f64> {
    let mut w = vec![0.0; z0.len()];
    split.from_inertial_checked(z0, &mut w).unwrap();
    let out = run(kernel, split, &w, t, n);
    let mut z = vec![0.0; z0.len()];
    split.to_inertial(&out, &mut z).unwrap();
    z
}

#[test]
fn the_lazy_modified_kick_gives_the_wisdom_holman_kernel_its_eps2_h4_error() {
    // Planet masses 1e-3 (and 2e-3 for the ε power), T = 12 (about two
    // orbits of the outer planet), h = 0.24 … 0.06. The reference is the
    // gradient kernel at h = 0.0075.
    let t = 12.0;
    for (g, p2) in [(1.0 / 24.0, 4.0), (0.0, 2.0)] {
        let (s, power) = scaling(g, t, [1e-3, 2e-3], |k, eps, n| {
            let (split, z0) = two_planets(eps);
            let reference = run_jacobi(&kernel(1.0 / 24.0), &split, &z0, t, 1600);
            dist(&run_jacobi(k, &split, &z0, t, n), &reference)
        });
        assert!((s - p2).abs() < 0.3, "g = {g}: slope {s:.2}, expected {p2}");
        // No ε term (it is of order 18); the ε³ part is of order 4 as well
        // (proven), so with the gradient the power lies between 2 and 3.
        assert!(
            (1.8..3.2).contains(&power),
            "g = {g}: ε power {power:.2}, expected 2 to 3"
        );
    }
}

#[test]
fn a_lazy_kick_without_kick_time_is_an_error() {
    let (split, z0) = two_planets(1e-3);
    let mut w = vec![0.0; z0.len()];
    split.from_inertial_checked(&z0, &mut w).unwrap();
    let err = split
        .interaction_kick_gradient(0.0, 1e-3, &mut w)
        .unwrap_err();
    assert!(err.to_string().contains("gradient kick"), "{err}");
}

integrator_core::butcher! {
    /// WHCKL's kernel `D(½) G(1, 1/24) D(½)`, declared.
    pub LazyKernel {
        claims: [symplectic, symmetric],
        drift: [1/2, 1/2],
        kick: [1],
        kick_gradient: [1/24],
    }
}

integrator_core::butcher! {
    /// The catalogue's WHCKL kernel with the corrector of order 17, its
    /// effective order (18, 4) proven at compile time.
    pub WhcklC17 {
        from: "whckl-c17",
    }
}

#[test]
fn butcher_steps_gradient_kernels_as_the_sequence_does() {
    // The declared kernel and the catalogue's processed WHCKL against the
    // run-time sequences of the same tables: the same flows with the same
    // coefficients, so the same bits, on the Jacobi split (lazy kick).
    assert_eq!(WhcklC17::EFFECTIVE_ORDER, &[18, 4]);
    let (split, z0) = two_planets(1e-3);
    let mut w0 = vec![0.0; z0.len()];
    split.from_inertial(&z0, &mut w0).unwrap();
    let (n, h) = (40, 0.05);
    let by_sequence = run(&kernel(1.0 / 24.0), &split, &w0, h * n as f64, n);
    let mut declared = w0.clone();
    let method = Processed::new(LazyKernel, corrector17());
    processed::integrate(&method, &split, &mut declared, 0.0, h, n, |_, _, _| {}).unwrap();
    assert_eq!(declared, by_sequence);

    let file = tableau::catalogue::load("whckl-c17").unwrap();
    let whckl = Processed::new(
        match &file.table {
            tableau::Table::Splitting(s) => Sequence::from_splitting(s),
            other => panic!("whckl-c17's kernel is a drift–kick sequence, not {other:?}"),
        },
        Sequence::from_splitting(file.corrector.as_ref().unwrap()),
    );
    let mut a = w0.clone();
    processed::integrate(&whckl, &split, &mut a, 0.0, h, n, |_, _, _| {}).unwrap();
    let mut b = w0.clone();
    processed::integrate(
        &WhcklC17.processed(),
        &split,
        &mut b,
        0.0,
        h,
        n,
        |_, _, _| {},
    )
    .unwrap();
    assert_eq!(a, b);
    // The gradient made a difference: the plain kernel lands elsewhere.
    let plain = run(&kernel(0.0), &split, &w0, h * n as f64, n);
    assert_ne!(plain, by_sequence);
}

#[test]
fn a_declared_gradient_kernel_on_a_system_without_gradient_kicks_is_an_error_naming_the_part() {
    // A separable Hamiltonian: no mass matrix, so no gradient kick.
    let sys = integrator_core::problems::Oscillator { k: 1.0 };
    let mut z = [1.0, 0.5];
    let err = integrator_core::integrate(&LazyKernel, &sys, &mut z, 0.0, 0.1, 3, |_, _, _| {})
        .unwrap_err();
    assert_no_gradient_kick(&err);
}

#[test]
fn the_exact_modified_kick_adds_the_derivative_of_the_accelerations_along_themselves() {
    // Pᵢ += 2γ·m'ᵢ·DQ̈ᵢ[Q̈] (h = 0, γ = ½) against the central difference of
    // the lazy kick, which takes m'Q̈ at Q ± ε·Q̈ (h = 1, γ = ±ε/2), on the
    // two planets and on the outer solar system (ε a hundredth and a sixth
    // of 1/n², n the inner planet's mean motion, in days for the outer
    // solar system). The quotient's own error
    // (ε⁴ after the extrapolation, and the rounding of Q̈, a difference of
    // the Sun's pull and the Kepler term's, divided by ε) bounds the
    // agreement at 1e-8 to 1e-7; a wrong term would be off at 1e-3 or more.
    let (two, z2) = two_planets(1e-3);
    let outer = Jacobi::outer_solar();
    let zo = integrator_core::problems::OuterSolarSystem.initial_state();
    for (split, z0, eps) in [(&two, &z2, 1e-2), (&outer, &zo, 8e4)] {
        let mut w0 = vec![0.0; z0.len()];
        split.from_inertial_checked(z0, &mut w0).unwrap();
        // Each kick from zero momenta, so that it returns its increment
        // without the rounding of the momenta it is added to.
        let half = z0.len() / 2;
        w0[half..].fill(0.0);
        let kick = |f: &dyn Fn(&mut [f64])| {
            let mut w = w0.clone();
            f(&mut w);
            w.iter().zip(&w0).map(|(a, b)| a - b).collect::<Vec<f64>>()
        };
        let exact = kick(&|w| split.interaction_kick_modified(0.0, 0.5, w).unwrap());
        // The central difference, Richardson-extrapolated (its ε² error
        // removed) from ε and ε/2.
        let central = |eps: f64| -> Vec<f64> {
            let plus = kick(&|w| split.interaction_kick_gradient(1.0, 0.5 * eps, w).unwrap());
            let minus = kick(&|w| split.interaction_kick_gradient(1.0, -0.5 * eps, w).unwrap());
            plus.iter()
                .zip(&minus)
                .map(|(a, b)| (a - b) / (2.0 * eps))
                .collect()
        };
        let (c1, c2) = (central(eps), central(0.5 * eps));
        let fd: Vec<f64> = c1
            .iter()
            .zip(&c2)
            .map(|(a, b)| (4.0 * b - a) / 3.0)
            .collect();
        let scale = exact[half..].iter().fold(0.0f64, |s, x| s.max(x.abs()));
        assert!(scale > 0.0);
        let mut worst = 0.0f64;
        for k in 0..half {
            assert_eq!(exact[k], 0.0, "positions are not kicked");
            let e = (exact[half + k] - fd[half + k]).abs() / scale;
            worst = worst.max(e);
            assert!(
                e < 5e-7,
                "component {k}: {} vs {} ({e:.1e})",
                exact[half + k],
                fd[half + k]
            );
        }
        println!(
            "{} bodies: the exact kick and the difference quotient agree to {worst:.1e}",
            half / 3
        );
    }
}

#[test]
fn the_exact_modified_kick_gives_the_wisdom_holman_kernel_its_eps2_h4_error() {
    // As the lazy kick's test, with WHCKM's exact modified kick: order 4
    // in h.
    let t = 12.0;
    let (s, power) = scaling(1.0 / 24.0, t, [1e-3, 2e-3], |k, eps, n| {
        let (split, z0) = two_planets(eps);
        let split =
            split.with_gradient_kick(integrator_core::problems::wisdom_holman::GradientKick::Exact);
        let reference = run_jacobi(&kernel(1.0 / 24.0), &split, &z0, t, 1600);
        dist(&run_jacobi(k, &split, &z0, t, n), &reference)
    });
    assert!((s - 4.0).abs() < 0.3, "slope {s:.2}, expected 4");
    // As with the lazy kick, the ε³h⁴ part is of the same order in h.
    assert!(
        (1.8..3.2).contains(&power),
        "ε power {power:.2}, expected 2 to 3"
    );
}
