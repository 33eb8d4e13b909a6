//! Time transformations that keep symplecticity: the logarithmic
//! Hamiltonian of Mikkola & Tanikawa (1999) and Preto & Tremaine (1999).
//!
//! For a separable `H = T(p) + V(q)` with `V < 0`, extend phase space by
//! the time `t` (a position) and its conjugate momentum `p₀`, and take
//!
//! ```text
//! Γ(q, t; p, p₀) = ln(T(p) + p₀) − ln(−V(q)).
//! ```
//!
//! Γ is again *separable*: `T̃(p, p₀) = ln(T(p) + p₀)`,
//! `Ṽ(q, t) = −ln(−V(q))`. Its flow in a fictitious time `s` is, on the
//! surface `p₀ = −H(q₀, p₀)` (where `T + p₀ = −V`),
//!
//! ```text
//! q' = ∇T(p)/(T + p₀),   t' = 1/(T + p₀),   p' = −∇V(q)/(−V(q)),   p₀' = 0,
//! ```
//!
//! i.e. the flow of `H` with `dt = ds/(−V)` — Sundman's transformation for
//! gravity, so a fixed step in `s` is a step in `t` that shrinks near a
//! pericentre. Since [`LogHamiltonian`] is itself [`Separable`], every
//! drift–kick sequence and composition of the library steps it unchanged:
//! explicit, symplectic in the extended phase space, time-reversible. For
//! Kepler, leapfrog on Γ follows the exact orbit (only the phase along it
//! is in error).
//!
//! ```
//! use integrator_core::library::Leapfrog;
//! use integrator_core::problems::Kepler;
//! use integrator_core::time_transform::LogHamiltonian;
//! use integrator_core::{Step, energy};
//!
//! let kepler = Kepler { e: 0.9 };
//! let z0 = kepler.initial_state();
//! let logh = LogHamiltonian::new(kepler);
//! let mut w = logh.extend(&z0, 0.0).unwrap();
//! let mut ws = Step::<LogHamiltonian<Kepler>>::workspace(&Leapfrog, &logh);
//! for _ in 0..1000 {
//!     Leapfrog.step(&logh, 0.0, 0.01, &mut w, &mut ws).unwrap();
//! }
//! let (z, t) = logh.restrict(&w);
//! assert!(t > 0.0);
//! assert!((energy(&kepler, &z) - energy(&kepler, &z0)).abs() < 1e-10);
//! ```

use crate::system::Separable;

/// Why a state cannot be put into the extended phase space.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TimeTransformError {
    #[error(
        "the logarithmic Hamiltonian needs V(q) < 0, but V = {potential} at the start \
         (shift the potential by a constant so that it is negative along the motion)"
    )]
    PotentialNotNegative { potential: f64 },
    #[error("the state has {got} components, but the system has {expected} (2·dof)")]
    Dimension { expected: usize, got: usize },
    #[error("the state is not finite: z[{index}] = {value}")]
    NonFinite { index: usize, value: f64 },
}

/// The logarithmic Hamiltonian of a separable system `S`, a separable
/// system of one more degree of freedom: positions `[q, t]`, momenta
/// `[p, p₀]` (see the [module documentation](self)).
#[derive(Clone, Debug)]
pub struct LogHamiltonian<S> {
    pub inner: S,
}

impl<S: Separable> LogHamiltonian<S> {
    pub fn new(inner: S) -> Self {
        LogHamiltonian { inner }
    }

    /// The extended state `[q, t; p, p₀]` of `z = [q; p]` at time `t`, with
    /// `p₀ = −H(q, p)` (the energy surface on which `s`-flow is `t`-flow).
    pub fn extend(&self, z: &[f64], t: f64) -> Result<Vec<f64>, TimeTransformError> {
        let n = self.inner.dof();
        if z.len() != 2 * n {
            return Err(TimeTransformError::Dimension {
                expected: 2 * n,
                got: z.len(),
            });
        }
        if let Some(index) = z.iter().position(|x| !x.is_finite()) {
            return Err(TimeTransformError::NonFinite {
                index,
                value: z[index],
            });
        }
        let (q, p) = z.split_at(n);
        let potential = self.inner.potential(q);
        if potential.is_nan() || potential >= 0.0 {
            return Err(TimeTransformError::PotentialNotNegative { potential });
        }
        let mut w = Vec::with_capacity(2 * n + 2);
        w.extend_from_slice(q);
        w.push(t);
        w.extend_from_slice(p);
        w.push(-(self.inner.kinetic(p) + potential));
        Ok(w)
    }

    /// `(z, t)`: the state `[q; p]` and the time of an extended state.
    pub fn restrict(&self, w: &[f64]) -> (Vec<f64>, f64) {
        let n = self.inner.dof();
        let mut z = Vec::with_capacity(2 * n);
        z.extend_from_slice(&w[..n]);
        z.extend_from_slice(&w[n + 1..2 * n + 1]);
        (z, w[n])
    }

    /// The time `t` of an extended state.
    pub fn time(&self, w: &[f64]) -> f64 {
        w[self.inner.dof()]
    }
}

impl<S: Separable> Separable for LogHamiltonian<S> {
    fn dof(&self) -> usize {
        self.inner.dof() + 1
    }
    /// `ln(T(p) + p₀)`; NaN where `T + p₀ ≤ 0` (off the domain: a step that
    /// lands there has diverged).
    fn kinetic(&self, p: &[f64]) -> f64 {
        let n = self.inner.dof();
        (self.inner.kinetic(&p[..n]) + p[n]).ln()
    }
    /// `−ln(−V(q))`.
    fn potential(&self, q: &[f64]) -> f64 {
        let n = self.inner.dof();
        -(-self.inner.potential(&q[..n])).ln()
    }
    /// `(∇T(p), 1)/(T(p) + p₀)`.
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        let n = self.inner.dof();
        let w = 1.0 / (self.inner.kinetic(&p[..n]) + p[n]);
        self.inner.velocity(&p[..n], &mut out[..n]);
        for v in &mut out[..n] {
            *v *= w;
        }
        out[n] = w;
    }
    /// `(−∇V(q), 0)/(−V(q))`: the system is autonomous, so nothing pushes
    /// `p₀`.
    fn force(&self, q: &[f64], out: &mut [f64]) {
        let n = self.inner.dof();
        let w = 1.0 / (-self.inner.force_and_potential(&q[..n], &mut out[..n]));
        for f in &mut out[..n] {
            *f *= w;
        }
        out[n] = 0.0;
    }
}
