//! Processed methods stepped (`integrator_core::processed`): the measured
//! error scales with the effective order the verifier proves, `χ` after
//! `χ⁻¹` returns the state to round-off, `χ` is applied to a copy only, and
//! a failing corrector flow is an error naming the part and step.

use integrator_core::library::Leapfrog;
use integrator_core::problems::wisdom_holman::Jacobi;
use integrator_core::processed::{self, Processed};
use integrator_core::scheme::SplitWorkspace;
use integrator_core::sequence::Sequence;
use integrator_core::split::{FlowError, Part, PartBuffers, Split, StateSpace};
use integrator_core::{Step, StepError};

/// `H = (q² + p²)/2 + εq`: the rotation `A` and the constant kick `εB`,
/// both exact. Every Lie bracket with two `B`s is a constant here (`A` is
/// quadratic, `B` linear), whose vector field is zero; so the error of a
/// splitting is its `ε` part alone, `ε h^{p₁}`, and a processed method's
/// measured order is its proven `p₁`, not the `ε²` part's 2.
struct Forced {
    eps: f64,
}

impl StateSpace for Forced {
    fn state_len(&self) -> usize {
        2
    }
}

impl Split for Forced {
    fn flow_a(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        let (s, c) = h.sin_cos();
        let (q, p) = (z[0], z[1]);
        z[0] = c * q + s * p;
        z[1] = c * p - s * q;
        Ok(())
    }
    fn flow_b(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        z[1] -= h * self.eps;
        Ok(())
    }
}

impl Forced {
    /// The exact solution from `(q₀, p₀)` at time `t`: `q + ε` rotates.
    fn exact(&self, z0: [f64; 2], t: f64) -> [f64; 2] {
        let (s, c) = t.sin_cos();
        let (q, p) = (z0[0] + self.eps, z0[1]);
        [c * q + s * p - self.eps, c * p - s * q]
    }
}

fn corrector(id: &str) -> Sequence {
    let file = tableau::catalogue::load(id).unwrap();
    Sequence::from_splitting(file.corrector.as_ref().expect("a processed method"))
}

/// The effective p₁ the verifier proves for `id`.
fn proven_p1(id: &str) -> usize {
    let file = tableau::catalogue::load(id).unwrap();
    let chi = file.corrector_table().unwrap();
    let report =
        tableau::near_integrable::processed_orders(&file.table, &chi, &[12, 3, 3], None).unwrap();
    report.parts[0].order
}

/// The error at `t = 8` of `method` with `n` steps.
fn error<K: Step<Forced>>(method: &Processed<K>, sys: &Forced, n: usize) -> f64 {
    let z0 = [1.0, 0.5];
    let t = 8.0;
    let mut z = z0;
    processed::integrate(method, sys, &mut z, 0.0, t / n as f64, n, |_, _, _| {}).unwrap();
    let e = sys.exact(z0, t);
    ((z[0] - e[0]).powi(2) + (z[1] - e[1]).powi(2)).sqrt()
}

/// The slope of log(error) against log(h), least squares.
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().map(|(h, e)| (h.ln(), e.ln())).unzip();
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// The leapfrog kernel alone has order 2; with the corrector of order 3, 5
/// and 7 the measured order is the proven effective p₁ (4, 6, 8), each
/// fitted over a range of steps where the error is far above round-off and
/// the asymptotic regime holds (a doubling of the number of steps; ranges
/// chosen per order so the smallest error stays above 1e-12).
#[test]
fn measured_order_is_the_proven_effective_order() {
    let sys = Forced { eps: 0.1 };
    let plain = Processed::new(Leapfrog, Sequence::new([]));
    let points: Vec<(f64, f64)> = [32, 64, 128, 256]
        .iter()
        .map(|&n| (8.0 / n as f64, error(&plain, &sys, n)))
        .collect();
    let s = slope(&points);
    assert!((s - 2.0).abs() < 0.1, "leapfrog: slope {s}, {points:?}");
    for (id, steps) in [
        ("leapfrog-c3", [16, 32, 64, 128]),
        ("leapfrog-c5", [8, 16, 32, 64]),
        ("leapfrog-c7", [8, 12, 16, 24]),
    ] {
        let p1 = proven_p1(id);
        let method = Processed::new(Leapfrog, corrector(id));
        let points: Vec<(f64, f64)> = steps
            .iter()
            .map(|&n| (8.0 / n as f64, error(&method, &sys, n)))
            .collect();
        let s = slope(&points);
        println!("{id}: proven p₁ = {p1}, measured slope {s:.3}, {points:?}");
        assert!(
            points.iter().all(|p| p.1 > 1e-12),
            "{id}: above round-off {points:?}"
        );
        assert!(
            (s - p1 as f64).abs() < 0.25,
            "{id}: measured slope {s}, proven p₁ = {p1}; {points:?}"
        );
        // And the corrected method beats the plain kernel by far at the
        // coarsest step.
        let plain_error = error(&plain, &sys, steps[0]);
        assert!(points[0].1 < plain_error / 10.0, "{id}");
    }
}

/// `χ` after `χ⁻¹` (and `χ⁻¹` after `χ`) returns an outer solar system state
/// in Jacobi coordinates to round-off, for the longest corrector (order 17,
/// 63 flows each way), at the step astronomers use (Jupiter's period / 20,
/// about 200 days): relative difference below 1e-14 (126 exact Kepler flows
/// and kicks, each within a few ulps).
#[test]
fn corrector_round_trips_to_round_off() {
    let split = Jacobi::outer_solar();
    let z0 = integrator_core::problems::OuterSolarSystem.initial_state();
    let mut w0 = vec![0.0; z0.len()];
    split.from_inertial(&z0, &mut w0).unwrap();
    let chi = corrector("leapfrog-c17");
    let inverse = chi.inverse();
    // 16 Z operators of 5 flows; neighbouring drifts merge, and in the
    // middle Z(−a₁, ·) Z(a₁, ·) the drifts cancel and two kicks merge.
    assert_eq!(chi.ops().len(), 63);
    let mut ws = SplitWorkspace::new(split.buffer_len());
    let h = 200.0;
    for (first, second) in [(&chi, &inverse), (&inverse, &chi)] {
        let mut w = w0.clone();
        first.apply(&split, h, &mut w, &mut ws).unwrap();
        let moved = w
            .iter()
            .zip(&w0)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        second.apply(&split, h, &mut w, &mut ws).unwrap();
        let scale = w0.iter().map(|x| x.abs()).fold(0.0, f64::max);
        let back = w
            .iter()
            .zip(&w0)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        println!("moved {moved:e}, back {back:e}, scale {scale:e}");
        assert!(moved > 1e-10 * scale, "χ moves the state: {moved:e}");
        assert!(
            back < 1e-14 * scale,
            "round trip {back:e} (scale {scale:e})"
        );
    }
}

/// The carried state is the kernel's alone: `n` processed steps carry
/// exactly (bit for bit) the state of `n` kernel steps from `χ⁻¹(z₀)`, and
/// each output is `χ` of that state, whatever was observed before.
#[test]
fn the_corrector_is_applied_to_a_copy_only() {
    let sys = Forced { eps: 0.3 };
    let chi = corrector("leapfrog-c5");
    let method = Processed::new(Leapfrog, chi.clone());
    let h = 0.25;
    let z0 = [0.7, -0.2];
    let mut outputs = Vec::new();
    let mut z = z0;
    processed::integrate(&method, &sys, &mut z, 0.0, h, 40, |k, _, out| {
        outputs.push((k, [out[0], out[1]]));
    })
    .unwrap();
    // By hand: χ⁻¹ once, then the kernel, χ on a copy at each output.
    let mut ws = SplitWorkspace::new(2);
    let mut carried = z0;
    chi.inverse().apply(&sys, h, &mut carried, &mut ws).unwrap();
    let mut kernel_ws = Step::<Forced>::workspace(&Leapfrog, &sys);
    for (k, out) in &outputs {
        if *k > 0 {
            Leapfrog
                .step_reusing(&sys, 0.0, h, &mut carried, &mut kernel_ws, *k > 1)
                .unwrap();
        }
        let mut copy = carried;
        let mut fresh = SplitWorkspace::new(2);
        chi.apply(&sys, h, &mut copy, &mut fresh).unwrap();
        assert_eq!(&copy, out, "output {k}");
    }
    assert_eq!(outputs.len(), 41);
    assert_eq!(z, outputs[40].1);
    // The first output is z₀ to round-off (χ after χ⁻¹).
    let first = outputs[0].1;
    assert!((first[0] - z0[0]).abs() < 1e-15 && (first[1] - z0[1]).abs() < 1e-15);
}

/// A kernel read at run time (`Sequence`) steps as its `butcher!` scheme does:
/// the leapfrog sequence gives Leapfrog's outputs.
#[test]
fn a_run_time_kernel_steps_like_the_compiled_one() {
    let sys = Forced { eps: 0.2 };
    let chi = corrector("leapfrog-c3");
    let compiled = Processed::new(Leapfrog, chi.clone());
    let interpreted = Processed::new(Sequence::from_lists(&[0.5, 0.5], &[1.0]), chi);
    let (mut a, mut b) = ([0.3, 0.9], [0.3, 0.9]);
    processed::integrate(&compiled, &sys, &mut a, 0.0, 0.1, 50, |_, _, _| {}).unwrap();
    processed::integrate(&interpreted, &sys, &mut b, 0.0, 0.1, 50, |_, _, _| {}).unwrap();
    assert!(
        (a[0] - b[0]).abs() < 1e-14 && (a[1] - b[1]).abs() < 1e-14,
        "{a:?} {b:?}"
    );
}

/// Kicks fail once the state's `q` passes `limit`.
struct Fragile {
    limit: f64,
}
impl StateSpace for Fragile {
    fn state_len(&self) -> usize {
        2
    }
}
impl Split for Fragile {
    fn flow_a(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        z[0] += h;
        Ok(())
    }
    fn flow_b(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        if z[0] > self.limit {
            return Err(FlowError::failed(format!("q = {} beyond the limit", z[0])));
        }
        z[1] += h;
        Ok(())
    }
}

/// `steps_merged` is `n` applications of the sequence up to rounding where
/// the last flow of a step and the first of the next are of one part (one
/// flow less per step), the same bits where they are not, and an error names
/// the step of the failing flow.
#[test]
fn merged_steps_are_the_same_map_with_one_flow_less_per_step() {
    /// Counts the flows of each part (a rotation and a constant kick).
    struct Counted {
        inner: Forced,
        a: std::cell::Cell<usize>,
        b: std::cell::Cell<usize>,
    }
    impl StateSpace for Counted {
        fn state_len(&self) -> usize {
            2
        }
    }
    impl Split for Counted {
        fn flow_a(
            &self,
            h: f64,
            z: &mut [f64],
            b: PartBuffers<'_>,
            r: bool,
        ) -> Result<(), FlowError> {
            self.a.set(self.a.get() + 1);
            self.inner.flow_a(h, z, b, r)
        }
        fn flow_b(
            &self,
            h: f64,
            z: &mut [f64],
            b: PartBuffers<'_>,
            r: bool,
        ) -> Result<(), FlowError> {
            self.b.set(self.b.get() + 1);
            if !z[0].is_finite() || z[0] > 1e3 {
                return Err(FlowError::failed("q out of range"));
            }
            self.inner.flow_b(h, z, b, r)
        }
    }
    let sys = Counted {
        inner: Forced { eps: 0.2 },
        a: 0.into(),
        b: 0.into(),
    };
    let n = 1000;
    for id in ["leapfrog", "aba-8-6-4", "kahan-li8"] {
        let seq = Sequence::from_catalogue(id).unwrap();
        assert!(seq.merges(), "{id} starts and ends with a drift");
        let mut ws = SplitWorkspace::new(2);
        let (mut plain, mut merged) = ([0.3, 0.9], [0.3, 0.9]);
        for _ in 0..n {
            seq.apply(&sys, 0.01, &mut plain, &mut ws).unwrap();
        }
        let plain_drifts = sys.a.replace(0);
        seq.steps_merged(&sys, 0.01, n, &mut merged, &mut ws)
            .unwrap();
        assert_eq!(
            sys.a.replace(0),
            plain_drifts - (n - 1),
            "{id}: one drift less per step"
        );
        let diff = (plain[0] - merged[0]).hypot(plain[1] - merged[1]);
        assert!(
            diff < 1e-13,
            "{id}: {plain:?} against {merged:?} ({diff:e})"
        );
    }
    // A sequence that starts with a kick and ends with a drift merges nothing.
    let seq = Sequence::new([(Part::B, 0.5), (Part::A, 1.0)]);
    assert!(!seq.merges());
    let mut ws = SplitWorkspace::new(2);
    let (mut plain, mut merged) = ([0.3, 0.9], [0.3, 0.9]);
    for _ in 0..10 {
        seq.apply(&sys, 0.1, &mut plain, &mut ws).unwrap();
    }
    seq.steps_merged(&sys, 0.1, 10, &mut merged, &mut ws)
        .unwrap();
    assert_eq!(plain, merged);
    // Drifts move q by h; kicks fail beyond q = 2. With D(½) K D(½) and
    // h = 1 the kicks see q = 0.5, 1.5, 2.5: the third step fails.
    let leapfrog = Sequence::from_catalogue("leapfrog").unwrap();
    let mut z = [0.0, 0.0];
    let (step, e) = leapfrog
        .steps_merged(&Fragile { limit: 2.0 }, 1.0, 5, &mut z, &mut ws)
        .unwrap_err();
    assert_eq!(step, 3, "{e}");
    assert!(e.to_string().contains("part B"), "{e}");
}

/// A flow that fails inside `χ⁻¹` on entry is an error at step 0 naming the
/// part; inside `χ` at an output, at that step.
#[test]
fn a_failing_corrector_flow_names_the_part_and_step() {
    // χ = D(1) K(1) D(−1): its kick sees q + h.
    let chi = Sequence::new([(Part::A, 1.0), (Part::B, 1.0), (Part::A, -1.0)]);
    let method = Processed::new(Sequence::new([(Part::A, 1.0)]), chi);
    // χ⁻¹'s kick sees q − h = −1: fine; χ's at output sees q + h = 1 > 0.5.
    let mut z = [0.0, 0.0];
    let e = processed::integrate(
        &method,
        &Fragile { limit: 0.5 },
        &mut z,
        0.0,
        1.0,
        3,
        |_, _, _| {},
    )
    .unwrap_err();
    match &e {
        StepError::Solve { step: 0, .. } => {}
        other => panic!("{other}"),
    }
    assert!(e.to_string().contains("part B"), "{e}");
    // With the limit at 2.5 the outputs at steps 0 and 1 pass (q + h = 1, 2),
    // the one at step 2 (q + h = 3) fails.
    let mut z = [0.0, 0.0];
    let e = processed::integrate(
        &method,
        &Fragile { limit: 2.5 },
        &mut z,
        0.0,
        1.0,
        3,
        |_, _, _| {},
    )
    .unwrap_err();
    assert!(matches!(e, StepError::Solve { step: 2, .. }), "{e}");
}

integrator_core::butcher! {
    /// The catalogue's leapfrog with the corrector of order 5, claims
    /// checked at compile time as the file states them.
    LeapfrogC5 { from: "leapfrog-c5" }
}

integrator_core::butcher! {
    /// The same method written inline: the leapfrog kernel named, the
    /// order-3 corrector's Z operators spelled out.
    LeapfrogC3 {
        let a = sqrt(7/40);
        let b = -1/96*sqrt(40/7);
        claims: [symplectic, order = 2, order = (4, 2)],
        kernel: "leapfrog",
        corrector_drift: [a, -2*a, a - a, 2*a, -a],
        corrector_kick: [-b, b, b, -b],
    }
}

/// A `butcher!` processed scheme carries its corrector (the catalogue's,
/// rounded as `Sequence::from_splitting` rounds it) and its proven effective
/// order; its `Step` is the kernel's (`ORDER` 2), and `processed()` steps
/// as the kernel with the corrector does.
#[test]
fn butcher_declares_processed_schemes() {
    use integrator_core::Scheme;
    assert_eq!(LeapfrogC5::EFFECTIVE_ORDER, &[6, 2]);
    assert_eq!(LeapfrogC3::EFFECTIVE_ORDER, &[4, 2]);
    assert_eq!(LeapfrogC5::ORDER, 2);
    assert_eq!(LeapfrogC5::INFO.order, 2);
    assert_eq!(LeapfrogC5::CORRECTOR, corrector("leapfrog-c5").ops());
    assert_eq!(LeapfrogC3::CORRECTOR, corrector("leapfrog-c3").ops());
    let sys = Forced { eps: 0.2 };
    let (mut a, mut b) = ([0.3, 0.9], [0.3, 0.9]);
    processed::integrate(
        &LeapfrogC5.processed(),
        &sys,
        &mut a,
        0.0,
        0.1,
        50,
        |_, _, _| {},
    )
    .unwrap();
    let by_hand = Processed::new(Leapfrog, corrector("leapfrog-c5"));
    processed::integrate(&by_hand, &sys, &mut b, 0.0, 0.1, 50, |_, _, _| {}).unwrap();
    assert_eq!(a, b);
}
