//! The implicit stage solvers on hand-built tables: Newton against fixed
//! point, stage by stage against stacked, dense against sparse,
//! conservation of quadratic invariants by Gauss methods, damping by Radau
//! IIA and implicit Euler, the errors, and no allocation per step.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use integrator_core::implicit::{
    self, ImplicitTable, ImplicitWorkspace, Settings, Solver, SparseJacobian, SparseWorkspace,
    Structure,
};
use integrator_core::{OdeSystem, SolveError};

// ---------------------------------------------------------------------------
// Allocation counting (this thread only).

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

// SAFETY: forwards to the system allocator.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> usize {
    ALLOCATIONS.with(|c| c.get())
}

// ---------------------------------------------------------------------------
// Tables, from their exact entries.

fn gauss1() -> ImplicitTable<1> {
    ImplicitTable::new([[0.5]], [1.0], [0.5])
}

fn gauss2() -> ImplicitTable<2> {
    let r = 3f64.sqrt() / 6.0;
    ImplicitTable::new(
        [[0.25, 0.25 - r], [0.25 + r, 0.25]],
        [0.5, 0.5],
        [0.5 - r, 0.5 + r],
    )
}

fn gauss3() -> ImplicitTable<3> {
    let r = 15f64.sqrt();
    ImplicitTable::new(
        [
            [5.0 / 36.0, 2.0 / 9.0 - r / 15.0, 5.0 / 36.0 - r / 30.0],
            [5.0 / 36.0 + r / 24.0, 2.0 / 9.0, 5.0 / 36.0 - r / 24.0],
            [5.0 / 36.0 + r / 30.0, 2.0 / 9.0 + r / 15.0, 5.0 / 36.0],
        ],
        [5.0 / 18.0, 4.0 / 9.0, 5.0 / 18.0],
        [0.5 - r / 10.0, 0.5, 0.5 + r / 10.0],
    )
}

/// Radau IIA, 2 stages, order 3.
fn radau2() -> ImplicitTable<2> {
    ImplicitTable::new(
        [[5.0 / 12.0, -1.0 / 12.0], [0.75, 0.25]],
        [0.75, 0.25],
        [1.0 / 3.0, 1.0],
    )
}

/// Radau IIA, 3 stages, order 5.
fn radau3() -> ImplicitTable<3> {
    let r = 6f64.sqrt();
    ImplicitTable::new(
        [
            [
                (88.0 - 7.0 * r) / 360.0,
                (296.0 - 169.0 * r) / 1800.0,
                (-2.0 + 3.0 * r) / 225.0,
            ],
            [
                (296.0 + 169.0 * r) / 1800.0,
                (88.0 + 7.0 * r) / 360.0,
                (-2.0 - 3.0 * r) / 225.0,
            ],
            [(16.0 - r) / 36.0, (16.0 + r) / 36.0, 1.0 / 9.0],
        ],
        [(16.0 - r) / 36.0, (16.0 + r) / 36.0, 1.0 / 9.0],
        [(4.0 - r) / 10.0, (4.0 + r) / 10.0, 1.0],
    )
}

fn implicit_euler() -> ImplicitTable<1> {
    ImplicitTable::new([[1.0]], [1.0], [1.0])
}

/// The paper's SDIRK: A = [[1/4, 0], [1/2, 1/4]], b = [1/2, 1/2].
fn sdirk() -> ImplicitTable<2> {
    ImplicitTable::new([[0.25, 0.0], [0.5, 0.25]], [0.5, 0.5], [0.25, 0.75])
}

/// Lobatto IIIA–IIIB, 3 stages: a symplectic pair of order 4.
fn lobatto3ab() -> ImplicitTable<3> {
    ImplicitTable::partitioned(
        [
            [0.0, 0.0, 0.0],
            [5.0 / 24.0, 1.0 / 3.0, -1.0 / 24.0],
            [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
        ],
        [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
        [
            [1.0 / 6.0, -1.0 / 6.0, 0.0],
            [1.0 / 6.0, 1.0 / 3.0, 0.0],
            [1.0 / 6.0, 5.0 / 6.0, 0.0],
        ],
        [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
        [0.0, 0.5, 1.0],
    )
}

// ---------------------------------------------------------------------------
// Systems.

/// `q' = ω·p, p' = −ω·q` for each frequency: `z = [q; p]`. Eigenvalues `±iω`.
struct Oscillators {
    omega: Vec<f64>,
    jacobian: bool,
}

impl Oscillators {
    fn new(omega: &[f64]) -> Self {
        Oscillators {
            omega: omega.to_vec(),
            jacobian: true,
        }
    }
    fn energies(&self, z: &[f64]) -> Vec<f64> {
        let n = self.omega.len();
        (0..n)
            .map(|k| 0.5 * (z[k] * z[k] + z[n + k] * z[n + k]))
            .collect()
    }
}

impl OdeSystem for Oscillators {
    fn dim(&self) -> usize {
        2 * self.omega.len()
    }
    fn rhs(&self, _t: f64, z: &[f64], dz: &mut [f64]) {
        let n = self.omega.len();
        for (k, w) in self.omega.iter().enumerate() {
            dz[k] = w * z[n + k];
            dz[n + k] = -w * z[k];
        }
    }
    fn jacobian(&self, _t: f64, _z: &[f64], jac: &mut [f64]) -> bool {
        if !self.jacobian {
            return false;
        }
        let n = self.omega.len();
        let d = 2 * n;
        jac.fill(0.0);
        for (k, w) in self.omega.iter().enumerate() {
            jac[k * d + n + k] = *w;
            jac[(n + k) * d + k] = -w;
        }
        true
    }
}

impl SparseJacobian for Oscillators {
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        let n = self.omega.len();
        (0..n).flat_map(|k| [(k, n + k), (n + k, k)]).collect()
    }
    fn jacobian_values(&self, _t: f64, _z: &[f64], values: &mut [f64]) {
        for (k, w) in self.omega.iter().enumerate() {
            values[2 * k] = *w;
            values[2 * k + 1] = -w;
        }
    }
}

/// The Kepler problem, `z = [q₁, q₂, p₁, p₂]`, `H = |p|²/2 − 1/|q|`.
struct Kepler {
    jacobian: bool,
}

const KEPLER: Kepler = Kepler { jacobian: true };

fn kepler_start(e: f64) -> [f64; 4] {
    [1.0 - e, 0.0, 0.0, ((1.0 + e) / (1.0 - e)).sqrt()]
}

fn angular_momentum(z: &[f64]) -> f64 {
    z[0] * z[3] - z[1] * z[2]
}

fn kepler_energy(z: &[f64]) -> f64 {
    0.5 * (z[2] * z[2] + z[3] * z[3]) - 1.0 / (z[0] * z[0] + z[1] * z[1]).sqrt()
}

impl OdeSystem for Kepler {
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&self, _t: f64, z: &[f64], dz: &mut [f64]) {
        let r2 = z[0] * z[0] + z[1] * z[1];
        let r3 = r2 * r2.sqrt();
        dz[0] = z[2];
        dz[1] = z[3];
        dz[2] = -z[0] / r3;
        dz[3] = -z[1] / r3;
    }
    fn jacobian(&self, _t: f64, z: &[f64], jac: &mut [f64]) -> bool {
        if !self.jacobian {
            return false;
        }
        let r2 = z[0] * z[0] + z[1] * z[1];
        let r = r2.sqrt();
        let (r3, r5) = (r2 * r, r2 * r2 * r);
        jac.fill(0.0);
        jac[2] = 1.0;
        jac[4 + 3] = 1.0;
        for a in 0..2 {
            for b in 0..2 {
                let delta = if a == b { 1.0 } else { 0.0 };
                jac[(2 + a) * 4 + b] = -delta / r3 + 3.0 * z[a] * z[b] / r5;
            }
        }
        true
    }
}

impl SparseJacobian for Kepler {
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        vec![(0, 2), (1, 3), (2, 0), (2, 1), (3, 0), (3, 1)]
    }
    fn jacobian_values(&self, t: f64, z: &[f64], values: &mut [f64]) {
        let mut jac = [0.0; 16];
        self.jacobian(t, z, &mut jac);
        for (v, (r, c)) in values.iter_mut().zip(self.jacobian_pattern()) {
            *v = jac[r * 4 + c];
        }
    }
}

/// `z' = λ·z` (scalar), to make stage matrices singular on purpose.
struct Linear1(f64);

impl OdeSystem for Linear1 {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, _t: f64, z: &[f64], dz: &mut [f64]) {
        dz[0] = self.0 * z[0];
    }
    fn jacobian(&self, _t: f64, _z: &[f64], jac: &mut [f64]) -> bool {
        jac[0] = self.0;
        true
    }
}

impl SparseJacobian for Linear1 {
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        vec![(0, 0)]
    }
    fn jacobian_values(&self, _t: f64, _z: &[f64], values: &mut [f64]) {
        values[0] = self.0;
    }
}

/// `z' = cos t`: non-autonomous, `z(t) = sin t`.
struct Forced;

impl OdeSystem for Forced {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, t: f64, _z: &[f64], dz: &mut [f64]) {
        dz[0] = t.cos();
    }
    fn jacobian(&self, _t: f64, _z: &[f64], jac: &mut [f64]) -> bool {
        jac[0] = 0.0;
        true
    }
}

fn settings(solver: Solver) -> Settings {
    Settings {
        solver,
        ..Settings::default()
    }
}

/// `n` steps from `t = 0`; panics on a solver error.
fn run<Sys: OdeSystem + ?Sized, const S: usize>(
    table: &ImplicitTable<S>,
    sys: &Sys,
    z: &mut [f64],
    h: f64,
    n: usize,
    ws: &mut ImplicitWorkspace,
    mut observe: impl FnMut(&[f64]),
) {
    for k in 0..n {
        implicit::step(table, sys, k as f64 * h, h, z, ws)
            .unwrap_or_else(|e| panic!("step {k}: {e}"));
        observe(z);
    }
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

// ---------------------------------------------------------------------------
// Tests.

#[test]
fn structure_is_read_off_the_table() {
    assert_eq!(gauss2().structure, Structure::Full);
    assert_eq!(radau3().structure, Structure::Full);
    assert_eq!(sdirk().structure, Structure::Sdirk);
    assert_eq!(implicit_euler().structure, Structure::Sdirk);
    assert_eq!(lobatto3ab().structure, Structure::Full);
    let dirk = ImplicitTable::new([[0.5, 0.0], [0.25, 1.0]], [0.5, 0.5], [0.5, 1.25]);
    assert_eq!(dirk.structure, Structure::Dirk);
    // An explicit stage in front (ESDIRK-like): still stage by stage.
    let esdirk = ImplicitTable::new([[0.0, 0.0], [0.5, 0.5]], [0.5, 0.5], [0.0, 1.0]);
    assert_eq!(esdirk.structure, Structure::Dirk);
}

#[test]
fn newton_and_fixed_point_agree_on_kepler() {
    let h = 0.05;
    fn compare<const S: usize>(table: &ImplicitTable<S>, h: f64, name: &str) {
        let z0 = kepler_start(0.6);
        let mut ws_n = ImplicitWorkspace::new(4, S).with_settings(settings(Solver::Newton));
        let mut ws_f = ImplicitWorkspace::new(4, S).with_settings(settings(Solver::FixedPoint));
        // One step from the same state.
        let (mut zn, mut zf) = (z0, z0);
        implicit::step(table, &KEPLER, 0.0, h, &mut zn, &mut ws_n).unwrap();
        implicit::step(table, &KEPLER, 0.0, h, &mut zf, &mut ws_f).unwrap();
        let one = max_diff(&zn, &zf);
        assert!(
            one <= 4.0 * f64::EPSILON,
            "{name}: one step differs by {one:e}"
        );
        // A whole orbit (≈ 2π/h steps) through perihelion.
        let (mut zn, mut zf) = (z0, z0);
        run(table, &KEPLER, &mut zn, h, 130, &mut ws_n, |_| {});
        run(table, &KEPLER, &mut zf, h, 130, &mut ws_f, |_| {});
        let orbit = max_diff(&zn, &zf);
        assert!(
            orbit <= 1e-12,
            "{name}: after an orbit they differ by {orbit:e}"
        );
        assert!(ws_n.stats().newton_iterations > 0 && ws_n.stats().fixed_point_iterations == 0);
        assert!(ws_f.stats().fixed_point_iterations > 0 && ws_f.stats().newton_iterations == 0);
        assert_eq!(ws_f.stats().factorizations, 0);
    }
    compare(&gauss1(), h, "midpoint");
    compare(&gauss2(), h, "GL2");
    compare(&gauss3(), h, "GL3");
    compare(&radau3(), h, "Radau IIA 3");
    compare(&lobatto3ab(), h, "Lobatto IIIA-IIIB");
}

#[test]
fn stiff_linear_system_needs_newton() {
    let sys = Oscillators::new(&[1.0, 10.0, 100.0, 1e3, 1e4]);
    let z0: Vec<f64> = (0..10).map(|k| 1.0 / (k + 1) as f64).collect();
    let h = 0.1;
    // Fixed point: h·ω·ρ(A) ≈ 300, so it fails, says so, and leaves z alone.
    let mut ws = ImplicitWorkspace::new(10, 2).with_settings(settings(Solver::FixedPoint));
    let mut z = z0.clone();
    let err = implicit::step(&gauss2(), &sys, 0.0, h, &mut z, &mut ws).unwrap_err();
    assert!(
        matches!(
            err,
            SolveError::Diverged { .. } | SolveError::NotConverged { .. }
        ),
        "{err}"
    );
    assert_eq!(z, z0);
    assert_eq!(ws.stats().failures, 1);
    assert_eq!(ws.stats().steps, 0);
    // Newton: succeeds, and the Gauss method keeps every mode's energy.
    let e0 = sys.energies(&z0);
    for solver in [Solver::Newton, Solver::Auto] {
        let mut ws = ImplicitWorkspace::new(10, 2).with_settings(settings(solver));
        let mut z = z0.clone();
        run(&gauss2(), &sys, &mut z, h, 1000, &mut ws, |_| {});
        for (e, e0) in sys.energies(&z).iter().zip(&e0) {
            // The update h·Σ bᵢ·F(Yᵢ) sums terms h·ω times larger than the
            // state, so each step rounds at h·ω·ε = 2e-13 for ω = 10⁴.
            assert!(
                (e - e0).abs() <= 1e-11 * e0,
                "{solver:?}: energy {e} vs {e0}"
            );
        }
        // Linear: one Jacobian and one factorisation for the run.
        assert_eq!(ws.stats().factorizations, 1, "{solver:?}");
        assert_eq!(ws.stats().jacobian_evaluations, 1, "{solver:?}");
        assert_eq!(ws.stats().fixed_point_iterations, 0);
    }
    // Without a Jacobian, Auto tries fixed point, falls back to Newton with
    // finite differences, and stays with Newton.
    let nojac = Oscillators {
        jacobian: false,
        ..Oscillators::new(&sys.omega)
    };
    let mut ws = ImplicitWorkspace::new(10, 2);
    let mut z = z0.clone();
    run(&gauss2(), &nojac, &mut z, h, 100, &mut ws, |_| {});
    let stats = *ws.stats();
    assert!(
        stats.fixed_point_iterations > 0 && stats.fixed_point_iterations <= 50,
        "{stats:?}"
    );
    assert_eq!(stats.steps, 100);
    assert_eq!(stats.failures, 0);
    for (e, e0) in sys.energies(&z).iter().zip(&e0) {
        assert!(
            (e - e0).abs() <= 1e-11 * e0,
            "finite differences: energy {e} vs {e0}"
        );
    }
}

/// ε·√n for n = 10⁴ steps.
const ROUND_OFF: f64 = 100.0 * f64::EPSILON;

#[test]
fn gauss_conserves_quadratic_invariants() {
    let h = 0.05;
    let l0 = angular_momentum(&kepler_start(0.6));
    fn kepler_drift<const S: usize>(
        table: &ImplicitTable<S>,
        solver: Solver,
        h: f64,
    ) -> (f64, f64) {
        let z0 = kepler_start(0.6);
        let l0 = angular_momentum(&z0);
        let h0 = kepler_energy(&z0);
        let mut ws = ImplicitWorkspace::new(4, S).with_settings(settings(solver));
        let mut z = z0;
        let (mut dl, mut dh) = (0.0f64, 0.0f64);
        run(table, &KEPLER, &mut z, h, 10_000, &mut ws, |z| {
            dl = dl.max((angular_momentum(z) - l0).abs());
            dh = dh.max((kepler_energy(z) - h0).abs());
        });
        (dl, dh)
    }
    for solver in [Solver::Newton, Solver::FixedPoint] {
        for (name, (dl, dh)) in [
            ("midpoint", kepler_drift(&gauss1(), solver, h)),
            ("GL2", kepler_drift(&gauss2(), solver, h)),
            ("GL3", kepler_drift(&gauss3(), solver, h)),
            ("Lobatto IIIA-IIIB", kepler_drift(&lobatto3ab(), solver, h)),
        ] {
            // Round-off only: a random walk, ε·√n (a loose tolerance would
            // drift linearly, far beyond this).
            assert!(
                dl <= 2.0 * ROUND_OFF * l0,
                "{name} {solver:?}: angular momentum drifts by {dl:e}"
            );
            // The energy is not quadratic: bounded, not conserved.
            assert!(dh < 0.1, "{name} {solver:?}: energy error {dh:e}");
        }
    }
    // The oscillator's energy, over 10⁴ steps.
    let osc = Oscillators::new(&[1.0]);
    for solver in [Solver::Newton, Solver::FixedPoint] {
        let mut worst = [0.0f64; 3];
        let mut ws1 = ImplicitWorkspace::new(2, 1).with_settings(settings(solver));
        let mut ws2 = ImplicitWorkspace::new(2, 2).with_settings(settings(solver));
        let mut ws3 = ImplicitWorkspace::new(2, 3).with_settings(settings(solver));
        let (mut z1, mut z2, mut z3) = ([1.0, 0.0], [1.0, 0.0], [1.0, 0.0]);
        let e = |z: &[f64]| (0.5 * (z[0] * z[0] + z[1] * z[1]) - 0.5).abs();
        run(&gauss1(), &osc, &mut z1, 0.1, 10_000, &mut ws1, |z| {
            worst[0] = worst[0].max(e(z))
        });
        run(&gauss2(), &osc, &mut z2, 0.1, 10_000, &mut ws2, |z| {
            worst[1] = worst[1].max(e(z))
        });
        run(&gauss3(), &osc, &mut z3, 0.1, 10_000, &mut ws3, |z| {
            worst[2] = worst[2].max(e(z))
        });
        for (s, w) in worst.iter().enumerate() {
            assert!(
                *w <= ROUND_OFF,
                "GL{} {solver:?}: energy drifts by {w:e}",
                s + 1
            );
        }
    }
}

#[test]
fn radau_and_implicit_euler_damp() {
    let osc = Oscillators::new(&[1.0]);
    let energy = |z: &[f64]| 0.5 * (z[0] * z[0] + z[1] * z[1]);
    let decays = |name: &str, energies: &[f64], factor: f64| {
        assert!(
            energies.windows(2).all(|w| w[1] < w[0]),
            "{name}: energy not decreasing"
        );
        let last = *energies.last().unwrap();
        assert!(last < factor * 0.5, "{name}: energy {last} after 10⁴ steps");
    };
    let mut es = Vec::new();
    let mut ws = ImplicitWorkspace::new(2, 1);
    let mut z = [1.0, 0.0];
    run(&implicit_euler(), &osc, &mut z, 0.1, 10_000, &mut ws, |z| {
        es.push(energy(z))
    });
    decays("implicit Euler", &es, 1e-10);
    for (name, table_s) in [("Radau IIA 2", 2), ("Radau IIA 3", 3)] {
        let mut es = Vec::new();
        let mut z = [1.0, 0.0];
        if table_s == 2 {
            let mut ws = ImplicitWorkspace::new(2, 2);
            run(&radau2(), &osc, &mut z, 0.1, 10_000, &mut ws, |z| {
                es.push(energy(z))
            });
            decays(name, &es, 0.999);
        } else {
            let mut ws = ImplicitWorkspace::new(2, 3);
            run(&radau3(), &osc, &mut z, 0.1, 10_000, &mut ws, |z| {
                es.push(energy(z))
            });
            // |R(iy)|² = 1 − O(y⁶) for order 5: slow, but strictly decaying.
            decays(name, &es, 1.0);
        }
    }
    // On the stiff system Radau IIA damps the fast modes to nothing.
    let stiff = Oscillators::new(&[1.0, 1e4]);
    let mut ws = ImplicitWorkspace::new(4, 3);
    let mut z = [1.0, 1.0, 0.0, 0.0];
    run(&radau3(), &stiff, &mut z, 0.1, 100, &mut ws, |_| {});
    let e = stiff.energies(&z);
    assert!(e[1] < 1e-100, "fast mode energy {}", e[1]);
    assert!((e[0] - 0.5).abs() < 1e-6, "slow mode energy {}", e[0]);
}

#[test]
fn dirk_stage_by_stage_equals_stacked() {
    let sd = sdirk();
    let stacked = sd.with_structure(Structure::Full);
    for solver in [Solver::Newton, Solver::FixedPoint] {
        let mut ws_a = ImplicitWorkspace::new(4, 2).with_settings(settings(solver));
        let mut ws_b = ImplicitWorkspace::new(4, 2).with_settings(settings(solver));
        let (mut za, mut zb) = (kepler_start(0.6), kepler_start(0.6));
        for k in 0..200 {
            let t = k as f64 * 0.05;
            implicit::step(&sd, &KEPLER, t, 0.05, &mut za, &mut ws_a).unwrap();
            implicit::step(&stacked, &KEPLER, t, 0.05, &mut zb, &mut ws_b).unwrap();
            if k == 0 {
                let one = max_diff(&za, &zb);
                assert!(
                    one <= 4.0 * f64::EPSILON,
                    "{solver:?}: one step differs by {one:e}"
                );
            }
        }
        let diff = max_diff(&za, &zb);
        assert!(diff <= 1e-12, "{solver:?}: {diff:e} after 200 steps");
    }
    // Stiff, linear: stage by stage factorises one d × d matrix (SDIRK: one
    // diagonal value), the stacked solve one 2d × 2d matrix.
    let sys = Oscillators::new(&[1.0, 1e2, 1e4]);
    let mut ws_a = ImplicitWorkspace::new(6, 2);
    let mut ws_b = ImplicitWorkspace::new(6, 2);
    let z0 = [1.0, 0.5, 0.25, 0.0, 0.1, 0.2];
    let (mut za, mut zb) = (z0, z0);
    run(&sd, &sys, &mut za, 0.1, 100, &mut ws_a, |_| {});
    run(&stacked, &sys, &mut zb, 0.1, 100, &mut ws_b, |_| {});
    let diff = max_diff(&za, &zb);
    // h·ω up to 10³ amplifies round-off differences in the update.
    assert!(diff <= 1e-12, "stiff: {diff:e}");
    assert_eq!(ws_a.stats().factorizations, 1);
    assert_eq!(ws_b.stats().factorizations, 1);
    // Two diagonal values: two factorisations per Jacobian.
    let dirk = ImplicitTable::new([[0.5, 0.0], [-0.5, 2.0]], [-0.5, 1.5], [0.5, 1.5]);
    let mut ws = ImplicitWorkspace::new(6, 2).with_settings(Settings {
        reuse_jacobian: false,
        ..Settings::default()
    });
    let mut z = z0;
    run(&dirk, &sys, &mut z, 0.01, 3, &mut ws, |_| {});
    assert_eq!(
        ws.stats().factorizations,
        6,
        "one per diagonal value and step"
    );
    // A false DIRK claim on a full table is not believed.
    let liar = gauss2().with_structure(Structure::Dirk);
    let (mut za, mut zb) = (kepler_start(0.6), kepler_start(0.6));
    let mut ws_a = ImplicitWorkspace::new(4, 2);
    let mut ws_b = ImplicitWorkspace::new(4, 2);
    run(&liar, &KEPLER, &mut za, 0.05, 10, &mut ws_a, |_| {});
    run(&gauss2(), &KEPLER, &mut zb, 0.05, 10, &mut ws_b, |_| {});
    assert_eq!(za, zb);
}

#[test]
fn errors_leave_the_state_alone() {
    // Implicit Euler on z' = 4z with h = 1/4: 1 − h·λ = 0.
    let sys = Linear1(4.0);
    let mut ws = ImplicitWorkspace::new(1, 1).with_settings(settings(Solver::Newton));
    let mut z = [1.0];
    assert_eq!(
        implicit::step(&implicit_euler(), &sys, 0.0, 0.25, &mut z, &mut ws),
        Err(SolveError::Singular)
    );
    assert_eq!(z, [1.0]);
    // A different h is fine, from the same workspace.
    implicit::step(&implicit_euler(), &sys, 0.0, 0.125, &mut z, &mut ws).unwrap();
    assert_eq!(z, [2.0]);
    // SDIRK stage by stage, 1 − h·λ/4 = 0, and stacked.
    let sys = Linear1(16.0);
    for table in [sdirk(), sdirk().with_structure(Structure::Full)] {
        let mut ws = ImplicitWorkspace::new(1, 2).with_settings(settings(Solver::Newton));
        let mut z = [1.0];
        assert_eq!(
            implicit::step(&table, &sys, 0.0, 0.25, &mut z, &mut ws),
            Err(SolveError::Singular)
        );
        assert_eq!(z, [1.0]);
    }
    // Sparse, too.
    let mut ws = SparseWorkspace::new(1, 1);
    let mut z = [1.0];
    let sys = Linear1(4.0);
    assert_eq!(
        implicit::step_sparse(&implicit_euler(), &sys, 0.0, 0.25, &mut z, &mut ws),
        Err(SolveError::Singular)
    );
    assert_eq!(z, [1.0]);
    // Too few iterations.
    let mut ws = ImplicitWorkspace::new(4, 2).with_settings(Settings {
        solver: Solver::FixedPoint,
        max_iterations: 3,
        ..Settings::default()
    });
    let mut z = kepler_start(0.6);
    match implicit::step(&gauss2(), &KEPLER, 0.0, 0.05, &mut z, &mut ws) {
        Err(SolveError::NotConverged {
            iterations: 3,
            correction,
        }) => assert!(correction > 0.0),
        other => panic!("{other:?}"),
    }
    assert_eq!(z, kepler_start(0.6));
    assert_eq!(ws.stats().failures, 1);
    // Newton without a Jacobian when finite differences are not allowed.
    let mut ws = ImplicitWorkspace::new(4, 2).with_settings(Settings {
        solver: Solver::Newton,
        finite_differences: false,
        ..Settings::default()
    });
    let nojac = Kepler { jacobian: false };
    assert_eq!(
        implicit::step(&gauss2(), &nojac, 0.0, 0.05, &mut z, &mut ws),
        Err(SolveError::NoJacobian)
    );
    assert_eq!(z, kepler_start(0.6));
    // Divergence: fixed point far outside its contraction region.
    let stiff = Oscillators::new(&[1e4]);
    let mut ws = ImplicitWorkspace::new(2, 1).with_settings(settings(Solver::FixedPoint));
    let mut z = [1.0, 0.0];
    let err = implicit::step(&gauss1(), &stiff, 0.0, 0.1, &mut z, &mut ws).unwrap_err();
    assert!(matches!(err, SolveError::Diverged { .. }), "{err}");
    assert_eq!(z, [1.0, 0.0]);
    // A right-hand side that blows up: an error, not a NaN state.
    struct Blowup;
    impl OdeSystem for Blowup {
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&self, _t: f64, z: &[f64], dz: &mut [f64]) {
            dz[0] = if z[0] > 1.5 { f64::NAN } else { 10.0 };
        }
    }
    for solver in [Solver::Newton, Solver::FixedPoint, Solver::Auto] {
        let mut ws = ImplicitWorkspace::new(1, 2).with_settings(settings(solver));
        let mut z = [1.0];
        let err = implicit::step(&gauss2(), &Blowup, 0.0, 0.1, &mut z, &mut ws).unwrap_err();
        assert!(
            matches!(err, SolveError::Diverged { .. }),
            "{solver:?}: {err}"
        );
        assert_eq!(z, [1.0]);
    }
}

#[test]
fn extrapolated_starting_values_save_iterations() {
    for solver in [Solver::Newton, Solver::FixedPoint] {
        let iterations = |extrapolate: bool| {
            let mut ws = ImplicitWorkspace::new(4, 3).with_settings(Settings {
                solver,
                extrapolate,
                ..Settings::default()
            });
            let mut z = kepler_start(0.6);
            run(&gauss3(), &KEPLER, &mut z, 0.05, 500, &mut ws, |_| {});
            let s = ws.stats();
            (s.newton_iterations + s.fixed_point_iterations, z)
        };
        let (with, za) = iterations(true);
        let (without, zb) = iterations(false);
        assert!(
            with < without,
            "{solver:?}: {with} iterations extrapolating, {without} from zero"
        );
        assert!(max_diff(&za, &zb) < 1e-11);
    }
    // A change of step size rescales the extrapolation.
    let mut ws = ImplicitWorkspace::new(4, 2);
    let mut fresh = ImplicitWorkspace::new(4, 2);
    let mut z = kepler_start(0.6);
    implicit::step(&gauss2(), &KEPLER, 0.0, 0.05, &mut z, &mut ws).unwrap();
    let mut z2 = z;
    implicit::step(&gauss2(), &KEPLER, 0.05, 0.02, &mut z, &mut ws).unwrap();
    implicit::step(&gauss2(), &KEPLER, 0.05, 0.02, &mut z2, &mut fresh).unwrap();
    assert!(max_diff(&z, &z2) <= 4.0 * f64::EPSILON);
}

#[test]
fn reusing_the_jacobian_changes_cost_not_results() {
    let run_with = |reuse: bool| {
        let mut ws = ImplicitWorkspace::new(4, 2).with_settings(Settings {
            solver: Solver::Newton,
            reuse_jacobian: reuse,
            ..Settings::default()
        });
        let mut z = kepler_start(0.6);
        run(&gauss2(), &KEPLER, &mut z, 0.05, 500, &mut ws, |_| {});
        (*ws.stats(), z)
    };
    let (kept, za) = run_with(true);
    let (fresh, zb) = run_with(false);
    assert_eq!(fresh.factorizations, 500);
    assert_eq!(fresh.jacobian_evaluations, 500);
    assert!(
        kept.factorizations < 500 && kept.jacobian_evaluations == kept.factorizations,
        "{kept:?}"
    );
    assert!(max_diff(&za, &zb) < 1e-11);
}

#[test]
fn non_autonomous_abscissae() {
    // z' = cos t: the quadrature of GL2 has order 4.
    let mut ws = ImplicitWorkspace::new(1, 2);
    let mut z = [0.0];
    let h = 0.1;
    run(&gauss2(), &Forced, &mut z, h, 100, &mut ws, |_| {});
    let err = (z[0] - 10f64.sin()).abs();
    assert!(err < 1e-6, "{err:e}");
}

#[test]
fn sparse_equals_dense() {
    let sys = Oscillators::new(&[1.0, 30.0, 1e3, 1e4]);
    let z0 = [1.0, 0.5, 0.25, 0.1, 0.0, 0.2, -0.3, 0.4];
    fn both<Sys: implicit::SparseJacobian, const S: usize>(
        table: &ImplicitTable<S>,
        sys: &Sys,
        z0: &[f64],
        h: f64,
        n: usize,
    ) -> (Vec<f64>, Vec<f64>, implicit::Stats) {
        let d = z0.len();
        let mut dense = ImplicitWorkspace::new(d, S).with_settings(settings(Solver::Newton));
        let mut sparse = SparseWorkspace::new(d, S);
        let (mut za, mut zb) = (z0.to_vec(), z0.to_vec());
        for k in 0..n {
            let t = k as f64 * h;
            implicit::step(table, sys, t, h, &mut za, &mut dense).unwrap();
            implicit::step_sparse(table, sys, t, h, &mut zb, &mut sparse).unwrap();
        }
        (za, zb, *sparse.stats())
    }
    // Stiff (h·ω up to 10³): round-off differences of the two LUs are
    // amplified by h·ω in the update, hence 1e-12 rather than ε.
    let (a, b, stats) = both(&gauss2(), &sys, &z0, 0.1, 100);
    assert!(max_diff(&a, &b) <= 1e-12, "GL2: {:e}", max_diff(&a, &b));
    assert_eq!(stats.symbolic_factorizations, 1);
    assert_eq!(stats.factorizations, 1);
    let (a, b, stats) = both(&sdirk(), &sys, &z0, 0.1, 100);
    assert!(max_diff(&a, &b) <= 1e-12, "SDIRK: {:e}", max_diff(&a, &b));
    assert_eq!(stats.symbolic_factorizations, 1);
    let (a, b, _) = both(&radau3(), &sys, &z0, 0.1, 100);
    assert!(max_diff(&a, &b) <= 1e-12, "Radau: {:e}", max_diff(&a, &b));
    // Nonlinear: the numeric LU is redone when J is, the symbolic one never.
    let z0 = kepler_start(0.6);
    let (a, b, stats) = both(&gauss3(), &KEPLER, &z0, 0.05, 200);
    assert!(max_diff(&a, &b) <= 1e-12, "Kepler: {:e}", max_diff(&a, &b));
    assert_eq!(stats.symbolic_factorizations, 1);
    assert!(stats.factorizations > 1);
}

#[test]
fn compensated_summation_keeps_round_off_small() {
    // Many small steps: the naive sum of increments drifts; the compensated
    // one stays at the level of a few roundings.
    let osc = Oscillators::new(&[1.0]);
    let drift = |compensated: bool| {
        let mut ws = ImplicitWorkspace::new(2, 1).with_settings(Settings {
            compensated,
            ..Settings::default()
        });
        let mut z = [1.0, 0.0];
        let mut worst = 0.0f64;
        run(&gauss1(), &osc, &mut z, 1e-3, 50_000, &mut ws, |z| {
            worst = worst.max((z[0] * z[0] + z[1] * z[1] - 1.0).abs());
        });
        worst
    };
    let (with, without) = (drift(true), drift(false));
    assert!(with < without, "compensated {with:e}, naive {without:e}");
    assert!(with <= 20.0 * f64::EPSILON, "compensated {with:e}");
}

#[test]
fn steps_do_not_allocate() {
    fn check<F: FnMut(usize)>(name: &str, mut step: F) {
        for k in 0..5 {
            step(k); // first use: factorisation storage, the sparse pattern
        }
        let before = allocations();
        for k in 5..105 {
            step(k);
        }
        let n = allocations() - before;
        assert_eq!(n, 0, "{name}: {n} allocations in 100 steps");
    }
    let h = 0.05;
    for (name, s) in [
        ("Newton, kept J", Settings::default()),
        (
            "Newton, J every step",
            Settings {
                reuse_jacobian: false,
                ..Settings::default()
            },
        ),
        ("fixed point", settings(Solver::FixedPoint)),
    ] {
        let mut ws = ImplicitWorkspace::new(4, 3).with_settings(s);
        let mut z = kepler_start(0.6);
        check(&format!("GL3 {name}"), |k| {
            implicit::step(&gauss3(), &KEPLER, k as f64 * h, h, &mut z, &mut ws).unwrap()
        });
        let mut ws = ImplicitWorkspace::new(4, 2).with_settings(s);
        let mut z = kepler_start(0.6);
        check(&format!("SDIRK {name}"), |k| {
            implicit::step(&sdirk(), &KEPLER, k as f64 * h, h, &mut z, &mut ws).unwrap()
        });
        // faer's sparse numeric LU grows its storage when a new pivot
        // sequence brings more fill than before (amortised, but not zero on
        // a nonlinear problem); on a linear one the fill never changes.
        let sys = Oscillators::new(&[1.0, 2.0]);
        let mut ws = SparseWorkspace::new(4, 2).with_settings(s);
        let mut z = [1.0, 0.5, 0.0, 0.25];
        check(&format!("sparse GL2 {name}"), |k| {
            implicit::step_sparse(&gauss2(), &sys, k as f64 * h, h, &mut z, &mut ws).unwrap()
        });
    }
}

#[test]
fn workspace_reports_and_resets() {
    let mut ws = ImplicitWorkspace::new(4, 2);
    assert_eq!((ws.dim(), ws.stages()), (4, 2));
    assert_eq!(ws.settings(), &Settings::default());
    let mut z = kepler_start(0.6);
    run(&gauss2(), &KEPLER, &mut z, 0.05, 10, &mut ws, |_| {});
    let s = *ws.stats();
    assert_eq!(s.steps, 10);
    assert!(s.rhs_evaluations >= 2 * s.newton_iterations);
    assert!(format!("{ws:?}").contains("steps: 10"));
    ws.reset();
    ws.reset_stats();
    assert_eq!(ws.stats().steps, 0);
    run(&gauss2(), &KEPLER, &mut z, 0.05, 1, &mut ws, |_| {});
    assert_eq!(ws.stats().jacobian_evaluations, 1);
    // The same workspace with another table of the same size.
    run(&radau2(), &KEPLER, &mut z, 0.05, 3, &mut ws, |_| {});
    assert!(z.iter().all(|x| x.is_finite()));
}

#[test]
fn workspaces_can_move_between_threads() {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<ImplicitWorkspace>();
    send_sync::<SparseWorkspace>();
    send_sync::<ImplicitTable<3>>();
}
