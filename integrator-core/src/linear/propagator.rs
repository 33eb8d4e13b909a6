//! The one-step map of a Runge–Kutta scheme on `z' = Hz + u`.
//!
//! A Runge–Kutta scheme with stability function `R(x) = P(x)/Q(x)` maps
//! `z' = Hz + u` to `z ← Φz + φ` with
//!
//! ```text
//! Φ = Q(hH)⁻¹ P(hH),   φ = h Q(hH)⁻¹ N(hH) u,   N(x) = (P(x) − Q(x))/x.
//! ```
//!
//! (Apply the scheme to the autonomous linear system `w' = Ĥw`,
//! `w = [z; 1]`, `Ĥ = [[H, u], [0, 0]]`: it is `R(hĤ)`, and the top-right
//! block of a polynomial `p(hĤ)` is `((p(hH) − p(0))/hH) hu`.) `N` is an
//! exact polynomial division because `P(0) = Q(0) = 1`.

use faer::linalg::matmul::matmul;
use faer::linalg::solvers::Solve;
use faer::{Accum, ColMut, ColRef, Mat, MatRef, Par};

use super::{LinearError, LinearHamiltonian};
use crate::error::{SolveError, StepError};
use crate::scheme::Step;
use crate::system::OdeSystem;

/// `z ← Φz + φ`: one step of size `h` of a Runge–Kutta scheme on a
/// [`LinearHamiltonian`], formed once (a few dense matrix products and one
/// LU factorisation of `Q(hH)`) and then applied with one dense
/// matrix–vector product per step.
///
/// Build it from the `STABILITY_P`/`STABILITY_Q` constants that `butcher!`
/// emits for every Runge–Kutta table, e.g.
/// `Propagator::new(&sys, h, &GaussLegendre2::STABILITY_P, &GaussLegendre2::STABILITY_Q)`.
#[derive(Clone, Debug)]
pub struct Propagator {
    h: f64,
    phi: Mat<f64>,
    offset: Vec<f64>,
}

/// `Σ c_k X^k` from the powers `X^0 = I, X^1, …` (missing coefficients are 0).
fn combine(powers: &[Mat<f64>], c: &[f64], d: usize) -> Mat<f64> {
    let mut out = Mat::zeros(d, d);
    for (k, &ck) in c.iter().enumerate() {
        if ck == 0.0 {
            continue;
        }
        if k == 0 {
            for i in 0..d {
                out[(i, i)] += ck;
            }
        } else {
            let xk = &powers[k - 1];
            for j in 0..d {
                for i in 0..d {
                    out[(i, j)] += ck * xk[(i, j)];
                }
            }
        }
    }
    out
}

fn check_poly(which: &'static str, c: &[f64]) -> Result<(), LinearError> {
    if c.is_empty() {
        return Err(LinearError::EmptyPolynomial { which });
    }
    if let Some(index) = c.iter().position(|x| !x.is_finite()) {
        return Err(LinearError::NonFiniteCoefficient {
            which,
            index,
            value: c[index],
        });
    }
    if c[0] != 1.0 {
        return Err(LinearError::StabilityConstant { which, value: c[0] });
    }
    Ok(())
}

impl Propagator {
    /// The propagator of the scheme with stability function `R = P/Q`
    /// (coefficients constant term first, `P(0) = Q(0) = 1`) for step size
    /// `h` on `sys`.
    ///
    /// The powers `(hH)^k`, `k ≤ max(deg P, deg Q)`, are formed once and
    /// shared by `P` and `Q` (`deg − 1` dense products: the same count as
    /// one Horner evaluation), `N(hH)·hu` with matrix–vector products, then
    /// `Q(hH)` is factorised once (LU with partial pivoting) and solved for
    /// `[P(hH) | N(hH)hu]` together.
    ///
    /// Refuses a zero or non-finite `h`, empty or non-finite coefficients,
    /// `P(0) ≠ 1` or `Q(0) ≠ 1`, a singular `Q(hH)` (`h` times an eigenvalue
    /// of `H` is a pole of `R`; detected as smallest/largest LU pivot
    /// `≤ 2n·ε`), and a non-finite result.
    pub fn new(sys: &LinearHamiltonian, h: f64, p: &[f64], q: &[f64]) -> Result<Self, LinearError> {
        if h == 0.0 || !h.is_finite() {
            return Err(LinearError::StepSize(h));
        }
        check_poly("P", p)?;
        check_poly("Q", q)?;
        let d = sys.dim();
        let par = faer::get_global_parallelism();
        let x = Mat::from_fn(d, d, |i, j| h * sys.matrix()[(i, j)]);
        let degree = p.len().max(q.len()) - 1;
        // powers[k − 1] = X^k.
        let mut powers: Vec<Mat<f64>> = Vec::with_capacity(degree);
        if degree >= 1 {
            powers.push(x);
        }
        for _ in 1..degree {
            let last = powers.last().expect("at least X^1");
            let mut next = Mat::zeros(d, d);
            matmul(
                next.as_mut(),
                Accum::Replace,
                last.as_ref(),
                powers[0].as_ref(),
                1.0,
                par,
            );
            powers.push(next);
        }
        let pm = combine(&powers, p, d);
        let qm = combine(&powers, q, d);

        // N(X)·hu, N_k = P_{k+1} − Q_{k+1}, k = 0 … degree − 1.
        let hu: Vec<f64> = sys.offset().iter().map(|v| h * v).collect();
        let mut rhs = Mat::zeros(d, d + 1);
        rhs.as_mut()
            .submatrix_mut(0, 0, d, d)
            .copy_from(pm.as_ref());
        let coeff = |c: &[f64], k: usize| c.get(k).copied().unwrap_or(0.0);
        for k in 0..degree {
            let nk = coeff(p, k + 1) - coeff(q, k + 1);
            if nk == 0.0 {
                continue;
            }
            if k == 0 {
                for i in 0..d {
                    rhs[(i, d)] += nk * hu[i];
                }
            } else {
                matmul(
                    rhs.as_mut().col_mut(d).as_mat_mut(),
                    Accum::Add,
                    powers[k - 1].as_ref(),
                    ColRef::from_slice(&hu).as_mat(),
                    nk,
                    par,
                );
            }
        }

        let lu = qm.partial_piv_lu();
        let diag = lu.U().diagonal().column_vector();
        let (mut lo, mut hi) = (f64::INFINITY, 0.0_f64);
        for i in 0..d {
            lo = lo.min(diag[i].abs());
            hi = hi.max(diag[i].abs());
        }
        let ratio = lo / hi;
        if ratio.is_nan() || ratio <= d as f64 * f64::EPSILON {
            return Err(LinearError::SingularDenominator { h, ratio });
        }
        lu.solve_in_place(rhs.as_mut());
        let phi = rhs.as_ref().submatrix(0, 0, d, d).to_owned();
        let offset: Vec<f64> = (0..d).map(|i| rhs[(i, d)]).collect();
        let finite = offset.iter().all(|v| v.is_finite())
            && (0..d).all(|j| (0..d).all(|i| phi[(i, j)].is_finite()));
        if !finite {
            return Err(LinearError::NonFinitePropagator { h });
        }
        Ok(Propagator { h, phi, offset })
    }

    /// The step size this propagator was built for.
    pub fn h(&self) -> f64 {
        self.h
    }
    /// The state dimension `2n`.
    pub fn dim(&self) -> usize {
        self.offset.len()
    }
    /// `Φ = R(hH)`.
    pub fn matrix(&self) -> MatRef<'_, f64> {
        self.phi.as_ref()
    }
    /// `φ = h Q(hH)⁻¹ N(hH) u`.
    pub fn offset(&self) -> &[f64] {
        &self.offset
    }
    /// A scratch vector for [`step`](Self::step).
    pub fn workspace(&self) -> Vec<f64> {
        vec![0.0; self.dim()]
    }

    /// `z ← Φz + φ`: one dense matrix–vector product into `scratch`, then
    /// one vector addition. Never allocates.
    ///
    /// # Panics
    /// If `z` or `scratch` does not have length [`dim`](Self::dim).
    #[inline]
    pub fn step(&self, z: &mut [f64], scratch: &mut [f64]) {
        let d = self.dim();
        assert!(
            z.len() == d && scratch.len() == d,
            "propagator of dimension {d} given a state of length {} and scratch of length {}",
            z.len(),
            scratch.len()
        );
        matmul(
            ColMut::from_slice_mut(scratch).as_mat_mut(),
            Accum::Replace,
            self.phi.as_ref(),
            ColRef::from_slice(z).as_mat(),
            1.0,
            Par::Seq,
        );
        for ((zi, si), oi) in z.iter_mut().zip(scratch.iter()).zip(&self.offset) {
            *zi = si + oi;
        }
    }

    /// `Ok` when this propagator steps size `h` (bitwise equal to the `h`
    /// it was built for), the check [`Step::step`] makes.
    pub fn check_step(&self, h: f64) -> Result<(), LinearError> {
        if h.to_bits() == self.h.to_bits() {
            Ok(())
        } else {
            Err(LinearError::StepMismatch {
                built: self.h,
                asked: h,
            })
        }
    }

    /// [`integrate`](crate::integrate) with this propagator's own `h`:
    /// `n` steps from `(t0, z)`, calling `observe(step, t, z)` before the
    /// first step and after every step, stopping at a non-finite state.
    pub fn integrate(
        &self,
        sys: &LinearHamiltonian,
        z: &mut [f64],
        t0: f64,
        n: usize,
        observe: impl FnMut(usize, f64, &[f64]),
    ) -> Result<(), StepError> {
        crate::integrate(self, sys, z, t0, self.h, n, observe)
    }
}

/// A propagator steps the system it was built from, with the `h` it was
/// built for: usable wherever a scheme is, e.g. with
/// [`integrate`](crate::integrate). Another `h` is refused with
/// [`SolveError::StepSizeMismatch`], another size with
/// [`SolveError::DimensionMismatch`]. The propagator does not check that
/// `sys` is the system it was built from (that would cost as much as the
/// step).
impl Step<LinearHamiltonian> for Propagator {
    type Workspace = Vec<f64>;

    fn workspace(&self, sys: &LinearHamiltonian) -> Vec<f64> {
        vec![0.0; sys.dim()]
    }

    fn step(
        &self,
        sys: &LinearHamiltonian,
        _t: f64,
        h: f64,
        z: &mut [f64],
        ws: &mut Vec<f64>,
    ) -> Result<(), SolveError> {
        if h.to_bits() != self.h.to_bits() {
            return Err(SolveError::StepSizeMismatch {
                prepared: self.h,
                asked: h,
            });
        }
        if sys.dim() != self.dim() || z.len() != self.dim() {
            return Err(SolveError::DimensionMismatch {
                prepared: self.dim(),
                got: z.len().max(sys.dim()),
            });
        }
        Propagator::step(self, z, ws);
        Ok(())
    }
}
