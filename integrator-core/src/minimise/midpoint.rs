//! The implicit midpoint rule and its compositions on separable systems with
//! a sparse Hessian, each midpoint step one [`Newton`] minimisation.

use faer::Par;

use super::newton::Newton;
use super::update::Update;
use super::{Mass, MinimiseError, NewtonSettings, Objective, Stats};
use crate::system::Separable;

/// A separable system `H = ½pᵀM⁻¹p + V(q)` with `M` diagonal that gives,
/// besides [`Separable`]'s potential and force, its mass, the round-off
/// scale of its force and the Hessian of `V` projected onto the
/// positive-semidefinite cone on a fixed sparse pattern: what a midpoint
/// step as minimisation ([`MidpointStepper`]) needs.
pub trait SparsePotential: Separable {
    /// `M` (consistent with [`Separable::velocity`]: `M⁻¹p`).
    fn mass(&self) -> Mass<'_>;
    /// `(V(q), |V|ₐ)`: the potential and the sum of the magnitudes of the
    /// terms it is summed from (what its round-off is relative to). Default:
    /// `(V, |V|)`; override it where `V` is a sum of terms that cancel
    /// (a hanging cloth's gravity against its springs).
    fn potential_and_magnitude(&self, q: &[f64]) -> (f64, f64) {
        let v = self.potential(q);
        (v, v.abs())
    }
    /// `out = F(q) = −∇V(q)` (the bits of [`Separable::force`]), and the
    /// force scale at `q`: the size of the terms whose round-off `F` carries
    /// (for springs the largest tension, and the largest stiffness times
    /// `‖q‖_∞`, since an ulp of position moves a force by the stiffness
    /// times it). Convergence is tested relative to it, so it must not be
    /// the net force alone (near equilibrium that is round-off itself).
    fn force_and_scale(&self, q: &[f64], out: &mut [f64]) -> f64;
    /// The positions `(row, column)` of the entries of `∇²V` that may be
    /// nonzero: the full symmetric pattern or its upper triangle (entries
    /// below the diagonal are ignored); repeated positions are summed. Asked
    /// once per stepper.
    fn hessian_pattern(&self) -> Vec<(usize, usize)>;
    /// The values of `∇²V(q)` projected so that the matrix is positive
    /// semidefinite (e.g. each spring's block onto its PSD part), in the
    /// order of [`hessian_pattern`](Self::hessian_pattern). Newton's method
    /// needs only a positive-definite approximation of the Hessian: the
    /// converged step is the same.
    fn hessian_values_projected(&self, q: &[f64], out: &mut [f64]);
    /// The values of `∇²V(q)` unprojected, where the system has them
    /// (returns whether it wrote them): Newton tries them first
    /// ([`Objective::hessian`] says why). Default: none.
    fn hessian_values(&self, q: &[f64], out: &mut [f64]) -> bool {
        let _ = (q, out);
        false
    }
}

/// The midpoint step's objective: `Φ(u) = ½·c·uᵀMu + V(y + u)`,
/// `c = 4/τ²`.
struct MidpointObjective<'a, P: ?Sized> {
    sys: &'a P,
    y: &'a [f64],
    c: f64,
}

impl<P: SparsePotential + ?Sized> Objective for MidpointObjective<'_, P> {
    fn dim(&self) -> usize {
        self.y.len()
    }
    fn base(&self) -> &[f64] {
        self.y
    }
    fn inertia(&self) -> f64 {
        self.c
    }
    fn mass(&self) -> Mass<'_> {
        self.sys.mass()
    }
    fn value(&self, x: &[f64]) -> (f64, f64) {
        self.sys.potential_and_magnitude(x)
    }
    fn force(&self, x: &[f64], force: &mut [f64]) -> f64 {
        self.sys.force_and_scale(x, force)
    }
    fn hessian_projected(&self, x: &[f64], values: &mut [f64]) {
        self.sys.hessian_values_projected(x, values)
    }
    fn hessian(&self, x: &[f64], values: &mut [f64]) -> bool {
        self.sys.hessian_values(x, values)
    }
}

/// Settings of a [`MidpointStepper`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MidpointSettings {
    /// The Newton solve of each midpoint step.
    pub newton: NewtonSettings,
    /// Add the increments to the state with compensated (Kahan) summation,
    /// the compensation carried from step to step while the state is the
    /// one the last step left (as the stage solver does by default). Default
    /// `true`.
    pub compensated: bool,
}

impl Default for MidpointSettings {
    fn default() -> Self {
        MidpointSettings {
            newton: NewtonSettings::default(),
            compensated: true,
        }
    }
}

/// Steps a [`SparsePotential`] system with the implicit midpoint rule and
/// its compositions, each midpoint step one minimisation ([module
/// documentation](super)). Holds the Newton solver (the symbolic Cholesky,
/// analysed once) and every buffer: a step allocates nothing.
pub struct MidpointStepper {
    newton: Newton,
    y: Vec<f64>,
    u: Vec<f64>,
    /// The previous solve's correction and its `c`: the next solve starts
    /// from it, scaled by `c_prev/c` (the correction is about
    /// `M⁻¹F·τ²/4`), when that lowers `Φ`.
    last: Vec<f64>,
    last_c: Option<f64>,
    guess: Vec<f64>,
    /// The state update and its Kahan compensation.
    update: Update,
}

impl MidpointStepper {
    /// The stepper for `sys` (its Hessian pattern analysed here).
    pub fn new<P: SparsePotential + ?Sized>(
        sys: &P,
        settings: MidpointSettings,
    ) -> Result<MidpointStepper, MinimiseError> {
        MidpointStepper::with_par(sys, settings, Par::Seq)
    }

    /// [`MidpointStepper::new`] with faer's parallelism `par` for the
    /// factorisations and solves.
    pub fn with_par<P: SparsePotential + ?Sized>(
        sys: &P,
        settings: MidpointSettings,
        par: Par,
    ) -> Result<MidpointStepper, MinimiseError> {
        let n = sys.dof();
        let newton = Newton::with_par(n, &sys.hessian_pattern(), settings.newton, par)?;
        Ok(MidpointStepper {
            newton,
            y: vec![0.0; n],
            u: vec![0.0; n],
            last: vec![0.0; n],
            last_c: None,
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

    pub fn newton(&self) -> &Newton {
        &self.newton
    }

    /// Forget the previous steps: the starting guess, the compensation and
    /// the kept factorisation.
    pub fn reset(&mut self) {
        self.last_c = None;
        self.update.reset();
        self.newton.forget_factor();
    }

    /// One implicit midpoint step of size `tau` (negative allowed) on
    /// `z = [q; p]`. Counts a solve, not a step ([`step`](Self::step)
    /// counts steps). On error `z` is unchanged.
    ///
    /// # Panics
    /// If `z` is not of length `2·dof`.
    pub fn midpoint_step<P: SparsePotential + ?Sized>(
        &mut self,
        sys: &P,
        tau: f64,
        z: &mut [f64],
    ) -> Result<(), MinimiseError> {
        let n = self.y.len();
        assert_eq!(
            z.len(),
            2 * n,
            "MidpointStepper: state of length {} expected",
            2 * n
        );
        if !(tau.is_finite() && tau != 0.0) {
            return Err(MinimiseError::Invalid(format!(
                "step size: τ = {tau} must be finite and nonzero"
            )));
        }
        self.update.begin(z);
        let mass = sys.mass();
        let (q, p) = z.split_at(n);
        for (k, y) in self.y.iter_mut().enumerate() {
            *y = q[k] + 0.5 * tau * p[k] / mass.get(k);
        }
        let c = 4.0 / (tau * tau);
        self.u.fill(0.0);
        let guess = match self.last_c {
            Some(c_prev) => {
                let r = c_prev / c;
                for (g, l) in self.guess.iter_mut().zip(&self.last) {
                    *g = r * l;
                }
                Some(self.guess.as_slice())
            }
            None => None,
        };
        let objective = MidpointObjective { sys, y: &self.y, c };
        self.newton.solve(&objective, &mut self.u, guess)?;
        self.last.copy_from_slice(&self.u);
        self.last_c = Some(c);
        // q' = q + τ·M⁻¹(p + (τ/2)F(x̄)), p' = p + τ·F(x̄): the stage
        // solver's update, F(x̄) from the last gradient test.
        let (_, f) = self.newton.point_and_force();
        self.update.apply(z, f, tau, mass);
        Ok(())
    }

    /// A step of size `h` of the composition of midpoint steps of sizes
    /// `weights[i]·h` (the table with `aᵢᵢ = bᵢ/2`, `aᵢⱼ = bⱼ` for `j < i`,
    /// `b = weights`). Counts one step. On error `z` is left after the
    /// midpoint steps that succeeded.
    pub fn step<P: SparsePotential + ?Sized>(
        &mut self,
        sys: &P,
        weights: &[f64],
        h: f64,
        z: &mut [f64],
    ) -> Result<(), MinimiseError> {
        for &b in weights {
            self.midpoint_step(sys, b * h, z)?;
        }
        self.newton.stats_mut().steps += 1;
        Ok(())
    }
}
