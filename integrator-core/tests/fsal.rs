//! First same as last: `integrate` reuses the last force evaluation of a
//! step at the start of the next (drift–kick sequences that start and end
//! with a kick; explicit pairs whose last position stage is `q_{n+1}`, as
//! Störmer–Verlet). The reuse must change the cost and nothing else: the
//! states are bitwise those of plain `step` calls.

use std::cell::Cell;

use integrator_core::library::{ForestRuth, Leapfrog, StormerVerlet, SymplecticEulerA};
use integrator_core::problems::Kepler;
use integrator_core::{Scheme, Separable, Step, integrate};

/// Kepler with a count of force and velocity evaluations.
struct Counting {
    inner: Kepler,
    forces: Cell<usize>,
    velocities: Cell<usize>,
}

impl Separable for Counting {
    fn dof(&self) -> usize {
        self.inner.dof()
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        self.inner.kinetic(p)
    }
    fn potential(&self, q: &[f64]) -> f64 {
        self.inner.potential(q)
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        self.velocities.set(self.velocities.get() + 1);
        self.inner.velocity(p, out)
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        self.forces.set(self.forces.get() + 1);
        self.inner.force(q, out)
    }
}

/// Force plus velocity evaluations and the final state of `n` steps, with
/// `integrate` (reuse) or with plain `step` calls.
fn run<M: Step<Counting> + Scheme>(method: &M, n: usize, reuse: bool) -> (usize, Vec<f64>) {
    let sys = Counting {
        inner: Kepler { e: 0.6 },
        forces: Cell::new(0),
        velocities: Cell::new(0),
    };
    let mut z = sys.inner.initial_state();
    let h = 0.01;
    if reuse {
        integrate(method, &sys, &mut z, 0.0, h, n, |_, _, _| {}).unwrap();
    } else {
        let mut ws = method.workspace(&sys);
        for k in 0..n {
            method.step(&sys, k as f64 * h, h, &mut z, &mut ws).unwrap();
        }
    }
    (sys.forces.get() + sys.velocities.get(), z)
}

#[test]
fn reuse_saves_one_evaluation_per_step_and_changes_no_bit() {
    let n = 1000;
    // (scheme, evaluations per plain step, per step with reuse): a drift
    // costs a velocity, a kick a force; Störmer–Verlet as a pair is
    // kick–drift–kick, leapfrog drift–kick–drift, Forest–Ruth 3 kicks and 4
    // drifts (drift first and last).
    fn check<M: Step<Counting> + Scheme>(m: &M, n: usize, plain: usize, reused: usize) {
        let name = M::INFO.name;
        let (fp, zp) = run(m, n, false);
        let (fr, zr) = run(m, n, true);
        assert_eq!(zp, zr, "{name}: reuse changed the result");
        assert_eq!(fp, plain * n, "{name}: evaluations with plain steps");
        assert_eq!(
            fr,
            reused * n + (plain - reused),
            "{name}: evaluations with reuse"
        );
    }
    check(&Leapfrog, n, 3, 2);
    check(&StormerVerlet, n, 3, 2);
    check(&ForestRuth, n, 7, 6);
    // No first-same-as-last: a kick and a drift per step either way.
    check(&SymplecticEulerA, n, 2, 2);
}
