//! A counting wrapper around a system: the same trait(s) as the system it
//! wraps, every evaluation counted in a [`Cell`] (the wrapper lives in one
//! run on one thread).

use std::cell::Cell;
use std::marker::PhantomData;

use integrator_core::{OdeSystem, Separable};

/// Marker: wrap a [`Separable`] system (the default).
pub struct AsSeparable;
/// Marker: wrap a plain [`OdeSystem`] (the linear system).
pub struct AsOde;

/// `P` with its evaluations counted. `Counting<P>` (marker [`AsSeparable`])
/// is [`Separable`] itself: velocity and force calls are counted, and through
/// the core's blanket impls it is a `Hamiltonian` and an `OdeSystem` whose
/// `rhs` is one velocity plus one force call, so every scheme that steps `P`
/// steps the wrapper. `Counting<P, AsOde>` is an [`OdeSystem`] (`rhs` calls
/// counted, the Jacobian passed through) and deliberately nothing more.
///
/// The marker is what lets both impls exist: a single `Counting<P>` with
/// `impl OdeSystem for Counting<LinearHamiltonian>` conflicts with the core's
/// blanket `impl<H: Hamiltonian> OdeSystem for H` (the core could make
/// `LinearHamiltonian` separable), while no `Counting<_, AsOde>` can ever be
/// `Separable`.
pub struct Counting<P, K = AsSeparable> {
    inner: P,
    velocity: Cell<u64>,
    force: Cell<u64>,
    rhs: Cell<u64>,
    kind: PhantomData<K>,
}

/// What a run evaluated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub velocity: u64,
    pub force: u64,
    pub rhs: u64,
}

impl<P, K> Counting<P, K> {
    pub fn new(inner: P) -> Self {
        Counting {
            inner,
            velocity: Cell::new(0),
            force: Cell::new(0),
            rhs: Cell::new(0),
            kind: PhantomData,
        }
    }

    pub fn counts(&self) -> Counts {
        Counts {
            velocity: self.velocity.get(),
            force: self.force.get(),
            rhs: self.rhs.get(),
        }
    }
}

fn bump(c: &Cell<u64>) {
    c.set(c.get() + 1);
}

impl<P: Separable> Separable for Counting<P> {
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
        bump(&self.velocity);
        self.inner.velocity(p, out);
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        bump(&self.force);
        self.inner.force(q, out);
    }
}

impl<P: OdeSystem> OdeSystem for Counting<P, AsOde> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn rhs(&self, t: f64, z: &[f64], dz: &mut [f64]) {
        bump(&self.rhs);
        self.inner.rhs(t, z, dz);
    }
    fn jacobian(&self, t: f64, z: &[f64], jac: &mut [f64]) -> bool {
        self.inner.jacobian(t, z, jac)
    }
}
