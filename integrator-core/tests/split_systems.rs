//! Split systems (`Split`): every drift–kick sequence and composition of
//! the library steps a system given by the exact flows of two parts, from
//! this crate (downstream of `integrator-core`, so the coherence of the
//! blanket impl for `Separable` is tested where a user meets it).
//!
//! * A separable system stepped directly and through [`AsSplit`], a
//!   user-written `Split` wrapper whose flows are the drift and the kick
//!   written out here, gives the same bits on every path (slice and fixed,
//!   compensated and plain, with and without first same as last).
//! * On [`RotationSqueeze`], `H = A + B` with `A` a pair of rotations and
//!   `B = ε(q·p)²/2` (a squeeze along `q·p = const`, not of the form
//!   `T(p) + V(q)`), both flows exact: every scheme is symplectic in fact
//!   (the finite-difference test of `symplectic_in_fact.rs`), the symmetric
//!   ones return under `h ↦ −h` (`reversibility.rs`'s test), and the
//!   measured order is the scheme's `ORDER` (`convergence.rs`'s rule).
//! * A flow that fails or leaves a non-finite value stops `integrate` and
//!   `integrate_fixed` with an error naming the part and the step.
//!
//! Measured on `RotationSqueeze` (ε = 3): symplecticity defects at
//! `h = 0.2` of 5e-14…2.2e-13 (tolerance 1e-11, the non-symplectic control
//! map far above it); round trips of the symmetric schemes within 1.0e-15
//! (tolerance 1e-13), of the others no closer than 3.2e-4; slopes within
//! 0.25 of the order for orders ≤ 6, 8.1–8.3 for order 8 and 10.7 for
//! Sofroniou–Spaletta 10.

use integrator_core::fixed::{StepFixed, integrate_fixed, integrate_fixed_with};
use integrator_core::library::*;
use integrator_core::problems::{HenonHeiles, OuterSolarSystem};
use integrator_core::scheme::SplitWorkspace;
use integrator_core::{
    FlowError, Hamiltonian, Info, Part, PartBuffers, Scheme, Separable, SolveError, Split,
    StateSpace, Step, StepError, integrate,
};

use crate::common;
use common::{jacobian, symplecticity_defect};

// ---------------------------------------------------------------------------
// A separable system seen as a user's split system.

/// A separable system behind a `Split` impl of a user's own: the drift
/// `q += h·∇T(p)` and the kick `p += h·F(q)` written out here, with the
/// compensated summation the library's separable step does, and the
/// finiteness check after every flow (the default of `Split`).
struct AsSplit<S>(S);

impl<S: Separable> StateSpace for AsSplit<S> {
    fn state_len(&self) -> usize {
        2 * self.0.dof()
    }
}

/// `d += h·s`, compensated into `e` when asked.
fn add(d: &mut [f64], e: &mut [f64], h: f64, s: &[f64], compensated: bool) {
    for i in 0..d.len() {
        if compensated {
            let inc = e[i] + h * s[i];
            let new = d[i] + inc;
            e[i] = (d[i] - new) + inc;
            d[i] = new;
        } else {
            d[i] += h * s[i];
        }
    }
}

impl<S: Separable> Split for AsSplit<S> {
    fn buffer_len(&self) -> usize {
        self.0.dof()
    }
    fn flow_a(
        &self,
        h: f64,
        z: &mut [f64],
        buf: PartBuffers<'_>,
        reuse: bool,
    ) -> Result<(), FlowError> {
        let n = self.0.dof();
        let (q, p) = z.split_at_mut(n);
        if !reuse {
            self.0.velocity(p, &mut buf.eval[..n]);
        }
        add(q, &mut buf.err[..n], h, &buf.eval[..n], buf.compensated);
        Ok(())
    }
    fn flow_b(
        &self,
        h: f64,
        z: &mut [f64],
        buf: PartBuffers<'_>,
        reuse: bool,
    ) -> Result<(), FlowError> {
        let n = self.0.dof();
        let (q, p) = z.split_at_mut(n);
        if !reuse {
            self.0.force(q, &mut buf.eval[..n]);
        }
        add(p, &mut buf.err[..n], h, &buf.eval[..n], buf.compensated);
        Ok(())
    }
}

/// Each test's runs over the drift–kick sequences and compositions of the
/// library (the `splittings` group of its one list, so that a new library
/// table is tested here with no edit).
macro_rules! splitting_runs {
    (
        explicit_rk: [$($e:tt)*], implicit_rk: [$($i:tt)*], explicit_pairs: [$($x:tt)*],
        splittings: [$($id:literal => $ty:ident),*], implicit_pairs: [$($p:tt)*] $(,)?
    ) => {
        fn infos() -> Vec<Info> {
            vec![$(<$ty as Scheme>::INFO),*]
        }
        fn all_same_bits() -> Vec<(Info, bool)> {
            vec![$(same_bits_direct_and_wrapped::<$ty>()),*]
        }
        fn all_defects(sys: &RotationSqueeze) -> Vec<(Info, f64)> {
            vec![$(defect::<$ty>(sys)),*]
        }
        fn all_round_trips(sys: &RotationSqueeze) -> Vec<(Info, f64)> {
            vec![$(round_trip::<$ty>(sys)),*]
        }
        fn all_measures(exact: &[f64]) -> Vec<(Info, f64, usize)> {
            vec![$(measure::<$ty>(exact)),*]
        }
    };
}
integrator_core::for_each_scheme!(splitting_runs);

#[test]
fn the_splittings_group_holds_drift_kick_sequences_and_compositions() {
    let listed = infos();
    assert!(listed.len() > 20, "{} splittings", listed.len());
    assert!(
        listed
            .iter()
            .all(|i| i.form == "drift-kick" || i.form == "composition")
    );
}

fn to_bits(z: &[f64]) -> Vec<u64> {
    z.iter().map(|x| x.to_bits()).collect()
}

/// The final states of every path of the slice and fixed steps.
fn paths<M, S>(m: &M, sys: &S, z0: [f64; 4], h: f64, n: usize) -> Vec<Vec<u64>>
where
    M: Step<S, Workspace = SplitWorkspace> + StepFixed<S, 4>,
    S: StateSpace,
{
    let mut out = Vec::new();
    let mut z = z0;
    integrate(m, sys, &mut z, 0.0, h, n, |_, _, _| {}).unwrap();
    out.push(to_bits(&z));
    for compensated in [true, false] {
        for reuse in [true, false] {
            let mut ws = m.workspace(sys);
            ws.compensated = compensated;
            let mut z = z0;
            for k in 0..n {
                m.step_reusing(sys, k as f64 * h, h, &mut z, &mut ws, reuse && k > 0)
                    .unwrap();
            }
            out.push(to_bits(&z));
        }
    }
    let mut z = z0;
    integrate_fixed(m, sys, &mut z, 0.0, h, n, |_, _, _| {}).unwrap();
    out.push(to_bits(&z));
    let mut z = z0;
    integrate_fixed_with(m, sys, &mut z, 0.0, h, n, false, |_, _, _| {}).unwrap();
    out.push(to_bits(&z));
    out
}

/// Direct and wrapped, on Hénon–Heiles (chaotic start) and the outer solar
/// system (slice path; 30 degrees of freedom).
fn same_bits_direct_and_wrapped<M>() -> (Info, bool)
where
    M: Scheme
        + Step<HenonHeiles, Workspace = SplitWorkspace>
        + StepFixed<HenonHeiles, 4>
        + Step<AsSplit<HenonHeiles>, Workspace = SplitWorkspace>
        + StepFixed<AsSplit<HenonHeiles>, 4>
        + Step<OuterSolarSystem>
        + Step<AsSplit<OuterSolarSystem>>,
{
    let m = M::default();
    let z0 = HenonHeiles::chaotic_start();
    let direct = paths(&m, &HenonHeiles, z0, 0.05, 2000);
    let wrapped = paths(&m, &AsSplit(HenonHeiles), z0, 0.05, 2000);
    // The state moved.
    assert_ne!(direct[0], to_bits(&z0));
    let mut same = direct == wrapped;
    let z0 = OuterSolarSystem.initial_state();
    let (mut a, mut b) = (z0.clone(), z0.clone());
    integrate(&m, &OuterSolarSystem, &mut a, 0.0, 50.0, 400, |_, _, _| {}).unwrap();
    integrate(
        &m,
        &AsSplit(OuterSolarSystem),
        &mut b,
        0.0,
        50.0,
        400,
        |_, _, _| {},
    )
    .unwrap();
    same &= to_bits(&a) == to_bits(&b);
    (M::INFO, same)
}

#[test]
fn separable_systems_step_the_same_bits_directly_and_as_split_systems() {
    let results = all_same_bits();
    let differ: Vec<&str> = results
        .iter()
        .filter(|(_, same)| !same)
        .map(|(i, _)| i.name)
        .collect();
    assert!(differ.is_empty(), "different bits: {differ:?}");
}

// ---------------------------------------------------------------------------
// A split system that is not separable.

/// `H = A + B`, `A = Σ ωᵢ(qᵢ² + pᵢ²)/2` (a rotation in each plane),
/// `B = ε(q·p)²/2`. Under `B`, `s = q·p` is constant, so its flow is
/// `q ← q·e^{εsh}`, `p ← p·e^{−εsh}`: exact, and `B` depends on `q` and
/// `p` together (not of the form `T(p) + V(q)`); `A` and `B` do not commute.
///
/// `ε = 3`, so that `B` is not a small perturbation of `A`: at `ε = 0.3` the
/// leading `h³` error of the three tables of order 3 with RKN order 4 or 5
/// (McLachlan–Atela 4 and 5, Calvo–Sanz-Serna 4) carries `ε³` and their
/// slopes measured 3.9–4.1 over the window (the near-integrable regime),
/// while at `ε = 3` they measure 3.0–3.25.
#[derive(Clone, Copy)]
struct RotationSqueeze {
    omega: [f64; 2],
    eps: f64,
}

const SYS: RotationSqueeze = RotationSqueeze {
    omega: [1.0, std::f64::consts::SQRT_2],
    eps: 3.0,
};
const Z0: [f64; 4] = [0.8, -0.3, 0.4, 0.6];

impl StateSpace for RotationSqueeze {
    fn state_len(&self) -> usize {
        4
    }
}

impl Split for RotationSqueeze {
    fn flow_a(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        for i in 0..2 {
            let (s, c) = (self.omega[i] * h).sin_cos();
            let (q, p) = (z[i], z[2 + i]);
            z[i] = c * q + s * p;
            z[2 + i] = c * p - s * q;
        }
        Ok(())
    }
    fn flow_b(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        let s = z[0] * z[2] + z[1] * z[3];
        let g = (self.eps * s * h).exp();
        for i in 0..2 {
            z[i] *= g;
            z[2 + i] /= g;
        }
        Ok(())
    }
}

/// The same system as a Hamiltonian, for the reference solution (RK4).
struct AsHamiltonian(RotationSqueeze);

impl Hamiltonian for AsHamiltonian {
    fn dof(&self) -> usize {
        2
    }
    fn energy(&self, q: &[f64], p: &[f64]) -> f64 {
        let s = q[0] * p[0] + q[1] * p[1];
        (0..2)
            .map(|i| 0.5 * self.0.omega[i] * (q[i] * q[i] + p[i] * p[i]))
            .sum::<f64>()
            + 0.5 * self.0.eps * s * s
    }
    fn grad_q(&self, q: &[f64], p: &[f64], out: &mut [f64]) {
        let s = q[0] * p[0] + q[1] * p[1];
        for i in 0..2 {
            out[i] = self.0.omega[i] * q[i] + self.0.eps * s * p[i];
        }
    }
    fn grad_p(&self, q: &[f64], p: &[f64], out: &mut [f64]) {
        let s = q[0] * p[0] + q[1] * p[1];
        for i in 0..2 {
            out[i] = self.0.omega[i] * p[i] + self.0.eps * s * q[i];
        }
    }
}

fn one_step<M: Scheme + Step<S>, S: StateSpace>(sys: &S, h: f64, z: &mut [f64]) {
    let m = M::default();
    let mut ws = m.workspace(sys);
    m.step(sys, 0.0, h, z, &mut ws)
        .expect("exact flows do not fail");
}

/// Symplecticity defect of one step at `h = 0.2`, at three states.
fn defect<M: Scheme + Step<RotationSqueeze>>(sys: &RotationSqueeze) -> (Info, f64) {
    let worst = [Z0, [-0.5, 0.9, 0.7, -0.2], [1.1, 0.2, -0.6, 0.3]]
        .iter()
        .map(|z| symplecticity_defect(&jacobian(|x| one_step::<M, _>(sys, 0.2, x), z, 3e-3)))
        .fold(0.0, f64::max);
    (M::INFO, worst)
}

/// The tolerance of `symplectic_in_fact.rs` (what the finite differences
/// resolve).
const SYMPLECTIC_TOL: f64 = 1e-11;

#[test]
fn splittings_are_symplectic_on_a_non_separable_split_system() {
    let results = all_defects(&SYS);
    let mut report = String::new();
    for (info, d) in &results {
        report += &format!("{:>28} {d:.1e}\n", info.name);
    }
    println!("symplecticity defect on RotationSqueeze, h = 0.2:\n{report}");
    let bad: Vec<_> = results
        .iter()
        .filter(|(_, d)| *d > SYMPLECTIC_TOL)
        .collect();
    assert!(bad.is_empty(), "not symplectic in fact: {report}");
}

/// A map that is not symplectic (the squeeze scales `q` and `p` alike),
/// so that the test above can fail.
struct Stretch(RotationSqueeze);

impl StateSpace for Stretch {
    fn state_len(&self) -> usize {
        4
    }
}

impl Split for Stretch {
    fn flow_a(&self, h: f64, z: &mut [f64], b: PartBuffers<'_>, r: bool) -> Result<(), FlowError> {
        self.0.flow_a(h, z, b, r)
    }
    fn flow_b(&self, h: f64, z: &mut [f64], _: PartBuffers<'_>, _: bool) -> Result<(), FlowError> {
        let s = z[0] * z[2] + z[1] * z[3];
        let g = (self.0.eps * s * h).exp();
        z.iter_mut().for_each(|x| *x *= g);
        Ok(())
    }
}

#[test]
fn the_symplecticity_test_sees_a_map_that_is_not_symplectic() {
    let sys = Stretch(SYS);
    let d = symplecticity_defect(&jacobian(
        |x| one_step::<ForestRuth, _>(&sys, 0.2, x),
        &Z0,
        3e-3,
    ));
    assert!(d > 1e3 * SYMPLECTIC_TOL, "defect {d:e}");
}

/// `|Ψ₋ₕ(Ψₕ(z)) − z|∞ / max(1, |z|∞)` at `h = 0.2`, worst of three states.
fn round_trip<M: Scheme + Step<RotationSqueeze>>(sys: &RotationSqueeze) -> (Info, f64) {
    let worst = [Z0, [-0.5, 0.9, 0.7, -0.2], [1.1, 0.2, -0.6, 0.3]]
        .iter()
        .map(|z0| {
            let mut z = *z0;
            one_step::<M, _>(sys, 0.2, &mut z);
            one_step::<M, _>(sys, -0.2, &mut z);
            let scale = z0.iter().fold(1.0f64, |s, x| s.max(x.abs()));
            z.iter()
                .zip(z0)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
                / scale
        })
        .fold(0.0, f64::max);
    (M::INFO, worst)
}

/// `reversibility.rs`'s tolerance and margin.
const REVERSIBLE_TOL: f64 = 1e-13;

#[test]
fn symmetric_splittings_are_reversible_on_a_non_separable_split_system() {
    let results = all_round_trips(&SYS);
    let mut report = String::new();
    let mut failures = Vec::new();
    for (info, miss) in &results {
        report += &format!(
            "{:>28} symmetric {:5} {miss:.1e}\n",
            info.name, info.symmetric
        );
        if info.symmetric && *miss > REVERSIBLE_TOL {
            failures.push(format!(
                "{} is symmetric but returns to {miss:e}",
                info.name
            ));
        }
        if !info.symmetric && *miss <= 100.0 * REVERSIBLE_TOL {
            failures.push(format!(
                "{} is not symmetric but returns to {miss:e}",
                info.name
            ));
        }
    }
    println!("round trip on RotationSqueeze, h = 0.2:\n{report}");
    // Both kinds are present.
    assert!(results.iter().any(|(i, _)| i.symmetric) && results.iter().any(|(i, _)| !i.symmetric));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

// ---------------------------------------------------------------------------
// Order, measured as `convergence.rs` measures it.

const T_END: f64 = 1.3;
const WINDOW: (f64, f64) = (1e-12, 1e-3);
/// Flow evaluations allowed per scheme.
const BUDGET: usize = 2_000_000;

/// RK4 on the Hamiltonian at `2¹⁴` and `2¹⁵` steps, Richardson-extrapolated.
fn reference() -> Vec<f64> {
    let sys = AsHamiltonian(SYS);
    let run = |n: usize| {
        let mut z = Z0.to_vec();
        integrate(&Rk4, &sys, &mut z, 0.0, T_END / n as f64, n, |_, _, _| {}).unwrap();
        z
    };
    let (coarse, fine) = (run(1 << 14), run(1 << 15));
    fine.iter()
        .zip(&coarse)
        .map(|(f, c)| (16.0 * f - c) / 15.0)
        .collect()
}

/// Least-squares slope of `ln y` against `ln x`.
fn loglog_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0.ln()).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1.ln()).sum::<f64>() / n;
    let sxy: f64 = points
        .iter()
        .map(|p| (p.0.ln() - mx) * (p.1.ln() - my))
        .sum();
    let sxx: f64 = points.iter().map(|p| (p.0.ln() - mx).powi(2)).sum();
    sxy / sxx
}

/// `(info, slope, points in the window)` of one scheme.
fn measure<M: Scheme + Step<RotationSqueeze>>(exact: &[f64]) -> (Info, f64, usize) {
    let mut ns: Vec<usize> = (0..20).flat_map(|j| [2usize << j, 3usize << j]).collect();
    ns.sort_unstable();
    let mut points = Vec::new();
    let mut spent = 0;
    for n in ns {
        spent += n * M::INFO.evaluations;
        if spent > BUDGET {
            break;
        }
        let mut z = Z0.to_vec();
        integrate(
            &M::default(),
            &SYS,
            &mut z,
            0.0,
            T_END / n as f64,
            n,
            |_, _, _| {},
        )
        .unwrap();
        let err = z
            .iter()
            .zip(exact)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        if (WINDOW.0..=WINDOW.1).contains(&err) {
            points.push((T_END / n as f64, err));
        }
        if err < WINDOW.0 {
            break;
        }
    }
    let slope = if points.len() >= 2 {
        loglog_slope(&points)
    } else {
        f64::NAN
    };
    (M::INFO, slope, points.len())
}

#[test]
fn measured_order_on_a_non_separable_split_system_is_the_scheme_order() {
    let exact = reference();
    let results = all_measures(&exact);
    let mut report = String::new();
    let mut failures = Vec::new();
    for (info, slope, pts) in &results {
        report += &format!(
            "{:>28} order {:>2} slope {slope:6.2} ({pts} points)\n",
            info.name, info.order
        );
        // The admissible order nearest to the slope (even for symmetric
        // schemes), as in convergence.rs.
        let inferred = if info.symmetric {
            2 * (slope / 2.0).round() as usize
        } else {
            slope.round() as usize
        };
        if *pts < 3 || inferred != info.order {
            failures.push(format!(
                "{}: order {}, slope {slope:.2} from {pts} points",
                info.name, info.order
            ));
        }
    }
    println!(
        "order on RotationSqueeze, errors in [{:e}, {:e}]:\n{report}",
        WINDOW.0, WINDOW.1
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

// ---------------------------------------------------------------------------
// Flows that fail.

/// `RotationSqueeze` whose flow of `part` fails at its `at`-th call
/// (counted from 1), with `how`.
struct Failing {
    part: Part,
    at: usize,
    how: fn() -> Result<f64, FlowError>,
    calls: std::cell::Cell<usize>,
}

impl Failing {
    fn new(part: Part, at: usize, how: fn() -> Result<f64, FlowError>) -> Self {
        Failing {
            part,
            at,
            how,
            calls: std::cell::Cell::new(0),
        }
    }
    /// `Err` from `how`, or a value written into `z[1]` (a NaN), at the
    /// failing call of the failing part.
    fn maybe_fail(&self, part: Part, z: &mut [f64]) -> Result<(), FlowError> {
        if part != self.part {
            return Ok(());
        }
        self.calls.set(self.calls.get() + 1);
        if self.calls.get() == self.at {
            z[1] = (self.how)()?;
        }
        Ok(())
    }
}

impl StateSpace for Failing {
    fn state_len(&self) -> usize {
        4
    }
}

impl Split for Failing {
    fn flow_a(&self, h: f64, z: &mut [f64], b: PartBuffers<'_>, r: bool) -> Result<(), FlowError> {
        SYS.flow_a(h, z, b, r)?;
        self.maybe_fail(Part::A, z)
    }
    fn flow_b(&self, h: f64, z: &mut [f64], b: PartBuffers<'_>, r: bool) -> Result<(), FlowError> {
        SYS.flow_b(h, z, b, r)?;
        self.maybe_fail(Part::B, z)
    }
}

fn not_converged() -> Result<f64, FlowError> {
    Err(FlowError::NotConverged {
        what: "Kepler's equation",
        iterations: 50,
        correction: 1e-3,
    })
}

fn nan() -> Result<f64, FlowError> {
    Ok(f64::NAN)
}

/// The error of `integrate` and of `integrate_fixed` (which must agree).
fn run_both<M: Step<Failing> + StepFixed<Failing, 4>>(
    m: M,
    make: impl Fn() -> Failing,
) -> StepError {
    let mut z = Z0;
    let slice = integrate(&m, &make(), &mut z, 0.0, 0.1, 100, |_, _, _| {}).unwrap_err();
    let mut z = Z0;
    let fixed = integrate_fixed(&m, &make(), &mut z, 0.0, 0.1, 100, |_, _, _| {}).unwrap_err();
    // (Compared as text: a NaN in the error is not equal to itself.)
    assert_eq!(format!("{slice:?}"), format!("{fixed:?}"));
    slice
}

#[test]
fn a_flow_that_fails_stops_the_run_naming_part_and_step() {
    // Leapfrog (drift, kick, drift; first same as last): part B (the kick)
    // is called once per step, so its 5th call is in step 5.
    let err = run_both(Leapfrog, || Failing::new(Part::B, 5, not_converged));
    match &err {
        StepError::Solve {
            step: 5,
            source:
                SolveError::Flow {
                    part: Part::B,
                    source: FlowError::NotConverged { iterations: 50, .. },
                },
            ..
        } => {}
        other => panic!("{other:?}"),
    }
    let msg = err.to_string();
    assert!(
        msg.contains("step 5") && msg.contains("part B") && msg.contains("Kepler's equation"),
        "{msg}"
    );
    // Part A: two drifts a step, so its 7th call is in step 4.
    let err = run_both(Leapfrog, || Failing::new(Part::A, 7, not_converged));
    assert!(
        matches!(
            err,
            StepError::Solve {
                step: 4,
                source: SolveError::Flow { part: Part::A, .. },
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn a_flow_that_leaves_a_non_finite_value_stops_the_run_naming_part_and_step() {
    // Forest–Ruth: three kicks a step; the 8th is in step 3.
    let err = run_both(ForestRuth, || Failing::new(Part::B, 8, nan));
    match &err {
        StepError::Solve {
            step: 3,
            source:
                SolveError::Flow {
                    part: Part::B,
                    source: FlowError::NonFinite { index: 1, value },
                },
            ..
        } if value.is_nan() => {}
        other => panic!("{other:?}"),
    }
    let msg = err.to_string();
    assert!(
        msg.contains("step 3") && msg.contains("part B") && msg.contains("z[1] = NaN"),
        "{msg}"
    );
    // Part A, at its first call: step 1.
    let err = run_both(Leapfrog, || Failing::new(Part::A, 1, nan));
    assert!(
        matches!(
            err,
            StepError::Solve {
                step: 1,
                source: SolveError::Flow {
                    part: Part::A,
                    source: FlowError::NonFinite { .. }
                },
                ..
            }
        ),
        "{err:?}"
    );
}
