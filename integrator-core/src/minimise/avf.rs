//! The average vector field (AVF) step on separable systems, solved as one
//! [`Newton`] minimisation per step.
//!
//! For `M q̈ = −∇V(q)` the AVF step (Quispel and McLaren 2008)
//!
//! ```text
//! q₁ = q + h·M⁻¹(p + p₁)/2,   p₁ = p + h·F̄(q, q₁),   F̄(q, q₁) = −∫₀¹ ∇V(q + ξ(q₁ − q)) dξ
//! ```
//!
//! conserves the energy exactly (`V(q₁) − V(q) = −F̄·(q₁ − q)` along the
//! segment, and the kinetic energy changes by `(q₁ − q)·F̄`) and every linear
//! invariant (linear momentum of a translation-invariant `V`). It is not
//! symplectic. Why it is a minimisation, like the midpoint rule: the
//! Jacobian of `F̄` in `q₁`, `−∫₀¹ ξ ∇²V dξ`, is symmetric, so
//! `−F̄ = ∇_{q₁} U` with `U(q₁) = ∫₀¹ (V(q + ξ(q₁ − q)) − V(q))/ξ dξ`, and
//! eliminating `p₁` leaves `M(q₁ − q − hM⁻¹p) = (h²/2)·F̄(q, q₁)`, the
//! stationarity condition of
//!
//! ```text
//! Ψ(u) = ½·(2/h²)·uᵀMu + U(q + hM⁻¹p + u),
//! ```
//!
//! a coercive objective for any `V` bounded below: a solve descends at any
//! step size, where the energy–momentum schemes of the Gonzalez type (not
//! gradients) have only a residual to globalise Newton with.
//!
//! The system supplies `F̄`, `U` and a positive-semidefinite approximation of
//! `∫₀¹ ξ ∇²V dξ` on the pattern of its Hessian ([`AveragedPotential`]); the
//! integrals are its business (closed forms for springs in the cloth crate).

use faer::Par;

use super::midpoint::{MidpointSettings, SparsePotential};
use super::newton::Newton;
use super::update::Update;
use super::{Mass, MinimiseError, Objective, Stats};

/// A [`SparsePotential`] that also gives the segment averages of its force
/// and Hessian: what the AVF step ([`AvfStepper`]) needs.
pub trait AveragedPotential: SparsePotential {
    /// `(U(q₁), |U|ₐ)` with `U(q₁) = ∫₀¹ (V(q + ξ(q₁ − q)) − V(q))/ξ dξ`,
    /// and the sum of the magnitudes of the terms it is summed from (what
    /// its round-off is relative to; the line search judges decreases by
    /// it). Accurate to round-off: the line search compares values of it.
    fn averaged_value(&self, q: &[f64], q1: &[f64]) -> (f64, f64);
    /// `out = F̄(q, q₁) = −∫₀¹ ∇V(q + ξ(q₁ − q)) dξ = −∇U(q₁)`, and the force
    /// scale (as [`SparsePotential::force_and_scale`]). The energy is
    /// conserved to the extent that `V(q₁) − V(q) = −F̄·(q₁ − q)` holds in
    /// floating point; at `q₁ = q` it is the force `F(q)`.
    fn averaged_force(&self, q: &[f64], q1: &[f64], out: &mut [f64]) -> f64;
    /// The values of a positive-semidefinite approximation of
    /// `∇²U(q₁) = ∫₀¹ ξ ∇²V(q + ξ(q₁ − q)) dξ`, in the order of
    /// [`SparsePotential::hessian_pattern`]. Newton needs only a good
    /// positive-definite matrix: the converged step is the same.
    fn averaged_hessian_projected(&self, q: &[f64], q1: &[f64], out: &mut [f64]);
    /// The values of `∫₀¹ ξ ∇²V dξ` unprojected, where the system has them
    /// (returns whether it wrote them): Newton tries them first
    /// ([`Objective::hessian`] says why). Default: none.
    fn averaged_hessian(&self, q: &[f64], q1: &[f64], out: &mut [f64]) -> bool {
        let _ = (q, q1, out);
        false
    }
}

/// The AVF step's objective: `Ψ(u) = ½·c·uᵀMu + U(base + u)`, `c = 2/h²`,
/// `base = q + hM⁻¹p`.
struct AvfObjective<'a, P: ?Sized> {
    sys: &'a P,
    q: &'a [f64],
    base: &'a [f64],
    c: f64,
}

impl<P: AveragedPotential + ?Sized> Objective for AvfObjective<'_, P> {
    fn dim(&self) -> usize {
        self.base.len()
    }
    fn base(&self) -> &[f64] {
        self.base
    }
    fn inertia(&self) -> f64 {
        self.c
    }
    fn mass(&self) -> Mass<'_> {
        self.sys.mass()
    }
    fn value(&self, x: &[f64]) -> (f64, f64) {
        self.sys.averaged_value(self.q, x)
    }
    fn force(&self, x: &[f64], force: &mut [f64]) -> f64 {
        self.sys.averaged_force(self.q, x, force)
    }
    fn hessian_projected(&self, x: &[f64], values: &mut [f64]) {
        self.sys.averaged_hessian_projected(self.q, x, values)
    }
    fn hessian(&self, x: &[f64], values: &mut [f64]) -> bool {
        self.sys.averaged_hessian(self.q, x, values)
    }
}

/// Steps an [`AveragedPotential`] system with the AVF method, each step one
/// minimisation (the [`minimise` module documentation](super)). Holds the Newton solver (the
/// symbolic Cholesky of the Hessian pattern, analysed once) and every
/// buffer: a step allocates nothing.
pub struct AvfStepper {
    newton: Newton,
    q: Vec<f64>,
    base: Vec<f64>,
    u: Vec<f64>,
    /// The previous step's `u` (about `(h²/2)M⁻¹F`) and its step size: the
    /// next solve starts from it, scaled by `(h/h_prev)²`, when that lowers
    /// `Ψ`.
    last: Vec<f64>,
    last_h: Option<f64>,
    guess: Vec<f64>,
    update: Update,
}

impl AvfStepper {
    /// The stepper for `sys` (its Hessian pattern analysed here). The
    /// settings are the midpoint stepper's: the Newton solve, and whether
    /// increments are added with compensated summation.
    pub fn new<P: AveragedPotential + ?Sized>(
        sys: &P,
        settings: MidpointSettings,
    ) -> Result<AvfStepper, MinimiseError> {
        AvfStepper::with_par(sys, settings, Par::Seq)
    }

    /// [`AvfStepper::new`] with faer's parallelism `par`.
    pub fn with_par<P: AveragedPotential + ?Sized>(
        sys: &P,
        settings: MidpointSettings,
        par: Par,
    ) -> Result<AvfStepper, MinimiseError> {
        let n = sys.dof();
        let newton = Newton::with_par(n, &sys.hessian_pattern(), settings.newton, par)?;
        Ok(AvfStepper {
            newton,
            q: vec![0.0; n],
            base: vec![0.0; n],
            u: vec![0.0; n],
            last: vec![0.0; n],
            last_h: None,
            guess: vec![0.0; n],
            update: Update::new(n, settings.compensated),
        })
    }

    pub fn stats(&self) -> &Stats {
        self.newton.stats()
    }

    pub fn stats_mut(&mut self) -> &mut Stats {
        self.newton.stats_mut()
    }

    /// Forget the previous steps: the starting guess, the compensation and
    /// the kept factorisation.
    pub fn reset(&mut self) {
        self.last_h = None;
        self.update.reset();
        self.newton.forget_factor();
    }

    /// One AVF step of size `h` on `z = [q; p]`. Counts a solve and a step.
    /// On error `z` is unchanged.
    ///
    /// # Panics
    /// If `z` is not of length `2·dof`.
    pub fn step<P: AveragedPotential + ?Sized>(
        &mut self,
        sys: &P,
        h: f64,
        z: &mut [f64],
    ) -> Result<(), MinimiseError> {
        let n = self.q.len();
        assert_eq!(
            z.len(),
            2 * n,
            "AvfStepper: state of length {} expected",
            2 * n
        );
        if !(h.is_finite() && h != 0.0) {
            return Err(MinimiseError::Invalid(format!(
                "step size: h = {h} must be finite and nonzero"
            )));
        }
        self.update.begin(z);
        let mass = sys.mass();
        let (q, p) = z.split_at(n);
        self.q.copy_from_slice(q);
        for (k, b) in self.base.iter_mut().enumerate() {
            *b = q[k] + h * p[k] / mass.get(k);
        }
        self.u.fill(0.0);
        let guess = match self.last_h {
            Some(h_prev) => {
                let r = (h / h_prev) * (h / h_prev);
                for (g, l) in self.guess.iter_mut().zip(&self.last) {
                    *g = r * l;
                }
                Some(self.guess.as_slice())
            }
            None => None,
        };
        let objective = AvfObjective {
            sys,
            q: &self.q,
            base: &self.base,
            c: 2.0 / (h * h),
        };
        self.newton.solve(&objective, &mut self.u, guess)?;
        self.last.copy_from_slice(&self.u);
        self.last_h = Some(h);
        // p₁ = p + h·F̄, q₁ = q + h·M⁻¹(p + (h/2)F̄): the step's equations with
        // F̄ from the last gradient test (q₁ is then base + u to the solve's
        // tolerance).
        let (_, f) = self.newton.point_and_force();
        self.update.apply(z, f, h, mass);
        self.newton.stats_mut().steps += 1;
        Ok(())
    }
}
