//! What a scheme can be applied to. Three traits, from general to special:
//!
//! * [`OdeSystem`]: `z' = f(t, z)`, any first-order system.
//! * [`Hamiltonian`]: `H(q, p)` with both gradients; as an ODE the state is
//!   `z = [q; p]` and `q' = ∂H/∂p`, `p' = −∂H/∂q`.
//! * [`Separable`]: `H = T(p) + V(q)`; the kinetic gradient is `M⁻¹p`, the
//!   force `−∇V`.
//!
//! Every separable system is a Hamiltonian and every Hamiltonian an ODE
//! system (blanket impls), so a Runge–Kutta scheme steps all three, while a
//! drift–kick scheme, a product of the exact flows of two parts, steps only
//! [`Separable`] systems (drifts and kicks) and other
//! [`Split`](crate::Split) systems (every separable system is one): using
//! it on anything else is a compile error.

/// `z' = f(t, z)`.
pub trait OdeSystem {
    /// The length of the state `z`.
    fn dim(&self) -> usize;
    /// `dz = f(t, z)`.
    fn rhs(&self, t: f64, z: &[f64], dz: &mut [f64]);
    /// The Jacobian `∂f/∂z` (row-major, `dim × dim`), if the system has one;
    /// returns `false` when it does not (implicit solvers then use finite
    /// differences).
    fn jacobian(&self, _t: f64, _z: &[f64], _jac: &mut [f64]) -> bool {
        false
    }
}

/// An autonomous Hamiltonian `H(q, p)` with `n` degrees of freedom.
pub trait Hamiltonian {
    /// Degrees of freedom `n`; the state is `z = [q; p]` of length `2n`.
    fn dof(&self) -> usize;
    fn energy(&self, q: &[f64], p: &[f64]) -> f64;
    /// `out = ∂H/∂q`.
    fn grad_q(&self, q: &[f64], p: &[f64], out: &mut [f64]);
    /// `out = ∂H/∂p`.
    fn grad_p(&self, q: &[f64], p: &[f64], out: &mut [f64]);
}

/// A separable Hamiltonian `H = T(p) + V(q)`, typically `T = ½ pᵀM⁻¹p`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` is not a separable Hamiltonian",
    label = "`{Self}` does not implement `Separable`",
    note = "explicit partitioned pairs are symplectic only for separable Hamiltonians, so they step only systems that implement `Separable`; drift–kick sequences and compositions step those and systems that implement `Split` (the exact flows of two parts)"
)]
pub trait Separable {
    /// Degrees of freedom `n`; the state is `z = [q; p]` of length `2n`.
    fn dof(&self) -> usize;
    fn kinetic(&self, p: &[f64]) -> f64;
    fn potential(&self, q: &[f64]) -> f64;
    /// `out = ∂T/∂p` (`M⁻¹p`): the velocity a drift moves `q` with.
    fn velocity(&self, p: &[f64], out: &mut [f64]);
    /// `out = −∂V/∂q`: the force a kick moves `p` with.
    fn force(&self, q: &[f64], out: &mut [f64]);
    /// `out = −∂V/∂q` and the return value `V(q)`, for methods that need
    /// both at every kick (the logarithmic Hamiltonian's force is
    /// `−∇V/(−V)`). Override it where the two share work (Kepler: one
    /// square root for both); it must give the bits of
    /// [`force`](Separable::force) and [`potential`](Separable::potential).
    fn force_and_potential(&self, q: &[f64], out: &mut [f64]) -> f64 {
        self.force(q, out);
        self.potential(q)
    }
}

impl<S: Separable + ?Sized> Hamiltonian for S {
    fn dof(&self) -> usize {
        Separable::dof(self)
    }
    fn energy(&self, q: &[f64], p: &[f64]) -> f64 {
        self.kinetic(p) + self.potential(q)
    }
    fn grad_q(&self, q: &[f64], _p: &[f64], out: &mut [f64]) {
        self.force(q, out);
        for x in out.iter_mut() {
            *x = -*x;
        }
    }
    fn grad_p(&self, _q: &[f64], p: &[f64], out: &mut [f64]) {
        self.velocity(p, out);
    }
}

impl<H: Hamiltonian + ?Sized> OdeSystem for H {
    fn dim(&self) -> usize {
        2 * self.dof()
    }
    fn rhs(&self, _t: f64, z: &[f64], dz: &mut [f64]) {
        let n = self.dof();
        let (q, p) = z.split_at(n);
        let (dq, dp) = dz.split_at_mut(n);
        self.grad_p(q, p, dq);
        self.grad_q(q, p, dp);
        for x in dp.iter_mut() {
            *x = -*x;
        }
    }
}

/// The energy of a state `z = [q; p]`.
pub fn energy<H: Hamiltonian + ?Sized>(sys: &H, z: &[f64]) -> f64 {
    let (q, p) = z.split_at(sys.dof());
    sys.energy(q, p)
}
