//! Linear Hamiltonian systems `z' = Hz + u`: the model of the paper's
//! eqs. (11)–(12), its exact flow, and the one-step propagator of any
//! Runge–Kutta scheme on it.
//!
//! # The model
//!
//! A gyroscopic linear system `M q̈ + G q̇ + K q = f`, with `M` symmetric
//! positive definite, `K` symmetric and `G` skew (`Gᵀ = −G`), comes from the
//! Lagrangian `L = ½ q̇ᵀMq̇ + ½ q̇ᵀG q − ½ qᵀKq + qᵀf` (Euler–Lagrange:
//! `d/dt(Mq̇ + Gq/2) = Gᵀq̇/2 − Kq + f`, i.e. `Mq̈ + Gq̇ + Kq = f` because
//! `G/2 − Gᵀ/2 = G`). The Legendre transform gives the momentum
//! `p = Mq̇ + Gq/2` and the Hamiltonian
//!
//! ```text
//! E(q, p) = ½ (p − Gq/2)ᵀ M⁻¹ (p − Gq/2) + ½ qᵀKq − qᵀf,
//! ```
//!
//! whose canonical equations `q̇ = ∂E/∂p`, `ṗ = −∂E/∂q` are `z' = Hz + u`
//! with `z = [q; p]`, `u = [0; f]` and
//!
//! ```text
//! H = [[A, D], [B, C]],  A = −M⁻¹G/2,  D = M⁻¹,
//!                        B = G M⁻¹ G/4 − K,  C = −G M⁻¹/2.
//! ```
//!
//! This is exactly the paper's eq. (12): its `B = GM⁻¹G/4 − K` has the
//! right sign (`∂E/∂q = −(G/2)ᵀM⁻¹(p − Gq/2) + Kq − f` and `−(G/2)ᵀ = G/2`
//! for skew `G`, so `−∂E/∂q` contributes `+GM⁻¹Gq/4`; equivalently
//! `B = −GᵀM⁻¹G/4 − K`, which is negative semidefinite minus `K`). The test
//! suite checks numerically that `z' = Hz + u` reproduces the second-order
//! equation.
//!
//! With `J = [[0, I], [−I, 0]]`, `S = −JH = [[−B, −C], [A, D]]` is symmetric
//! (`H` is a Hamiltonian matrix), `H = JS`, and the energy is
//! `E(z) = ½ zᵀSz − zᵀ(Ju)` with `Ju = [f; 0]`: it is conserved by the exact
//! flow for constant `f`, and by every symplectic Runge–Kutta propagator
//! (a quadratic invariant).
//!
//! # Checks and tolerances
//!
//! [`LinearHamiltonian::new`] refuses, with a [`LinearError`] naming the
//! matrix: mismatched sizes, non-finite entries, `M` or `K` not symmetric
//! (`max |a_ij − a_ji| > 1e-10 · max |a_ij|`, [`SYMMETRY_TOL`]), `G` not skew
//! (`max |g_ij + g_ji| > 1e-10 · max |g_ij|`), `M` not positive definite
//! (its Cholesky factorisation meets a non-positive pivot) or singular to
//! working precision (`min L_ii² ≤ n·ε · max L_ii²` for the Cholesky factor
//! `L`), and `JH` not symmetric, checked block by block against the norms
//! of what each block is made of (`‖B − Bᵀ‖_max ≤ 1e-8 (‖K‖_F +
//! ‖G‖_F²‖M⁻¹‖_F/4)`, `‖D − Dᵀ‖_max ≤ 1e-8 ‖M⁻¹‖_F`, `‖A + Cᵀ‖_max ≤
//! 1e-8 ‖G‖_F‖M⁻¹‖_F/2`, [`HAMILTONIAN_TOL`]). After the checks the inputs
//! are replaced by their symmetric (skew) parts and `H` is assembled as `JS`
//! with `S` symmetrised, so `H` is Hamiltonian to the last bit.
//!
//! # Example
//!
//! ```
//! use integrator_core::OdeSystem;
//! use integrator_core::library::GaussLegendre2;
//! use integrator_core::linear::{LinearHamiltonian, Propagator};
//!
//! // Two masses on springs, coupled gyroscopically, with a constant force.
//! let m = [[2.0, 0.0], [0.0, 1.0]];
//! let g = [[0.0, 0.5], [-0.5, 0.0]];
//! let k = [[3.0, -1.0], [-1.0, 2.0]];
//! let f = [0.1, 0.0];
//! let sys = LinearHamiltonian::from_rows(&m, &g, &k, &f)?;
//! assert_eq!(sys.dim(), 4); // z = [q; p]
//!
//! // Gauss–Legendre 2 on z' = Hz + u is z ← Φz + φ: Φ, φ computed once.
//! let h = 0.05;
//! let prop = Propagator::new(&sys, h, &GaussLegendre2::STABILITY_P, &GaussLegendre2::STABILITY_Q)?;
//! let z0 = vec![1.0, 0.0, 0.0, 0.0];
//! let mut z = z0.clone();
//! let mut scratch = prop.workspace();
//! for _ in 0..200 {
//!     prop.step(&mut z, &mut scratch); // one dense matvec
//! }
//!
//! // Order 4 against the exact flow, and the energy conserved to round-off.
//! let exact = sys.exact(&z0, 200.0 * h)?;
//! let err = z.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
//! assert!(err < 1e-5);
//! assert!((sys.energy(&z) - sys.energy(&z0)).abs() < 1e-13);
//! # Ok::<(), integrator_core::linear::LinearError>(())
//! ```

mod expm;
mod generate;
mod propagator;

pub use expm::expm;
pub use generate::gyroscopic;
pub use propagator::Propagator;

use faer::linalg::matmul::matmul;
use faer::linalg::solvers::Solve;
use faer::{Accum, ColMut, ColRef, Mat, MatRef, Par, Side};

use crate::system::OdeSystem;

/// Relative tolerance of the symmetry checks of `M`, `K` and the skew check
/// of `G`: `max |a_ij ∓ a_ji| ≤ SYMMETRY_TOL · max |a_ij|`.
pub const SYMMETRY_TOL: f64 = 1e-10;

/// Relative tolerance of the check that `JH` is symmetric, block by block
/// against the Frobenius norms of the matrices each block is built from.
pub const HAMILTONIAN_TOL: f64 = 1e-8;

/// Why a linear model or its propagator was refused. Every variant names the
/// input it is about.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LinearError {
    #[error("M is empty (0×0): the system needs at least one degree of freedom")]
    Empty,
    #[error("{matrix} is {rows}×{cols}, but it must be square")]
    NotSquare {
        matrix: &'static str,
        rows: usize,
        cols: usize,
    },
    #[error("{matrix} is {rows}×{cols}, but M is {n}×{n}: {matrix} must be {n}×{n}")]
    ShapeMismatch {
        matrix: &'static str,
        rows: usize,
        cols: usize,
        n: usize,
    },
    #[error("f has length {len}, but M is {n}×{n}: f must have length {n}")]
    ForceLength { len: usize, n: usize },
    #[error(
        "{matrix} has rows of different lengths: row 0 has {expected} entries, row {row} has {len}"
    )]
    Ragged {
        matrix: &'static str,
        row: usize,
        len: usize,
        expected: usize,
    },
    #[error("{matrix}[{i}][{j}] = {value} is not finite")]
    NonFinite {
        matrix: &'static str,
        i: usize,
        j: usize,
        value: f64,
    },
    #[error("f[{i}] = {value} is not finite")]
    NonFiniteForce { i: usize, value: f64 },
    #[error(
        "{matrix} is not symmetric: {matrix}[{i}][{j}] − {matrix}[{j}][{i}] = {diff:e}, above the tolerance {tol:e} (1e-10 · max |{matrix}|)"
    )]
    NotSymmetric {
        matrix: &'static str,
        i: usize,
        j: usize,
        diff: f64,
        tol: f64,
    },
    #[error(
        "G is not skew-symmetric (G + Gᵀ ≠ 0): G[{i}][{j}] + G[{j}][{i}] = {sum:e}, above the tolerance {tol:e} (1e-10 · max |G|)"
    )]
    NotSkew {
        i: usize,
        j: usize,
        sum: f64,
        tol: f64,
    },
    #[error("M is not positive definite: its Cholesky factorisation fails at pivot {pivot}")]
    NotPositiveDefinite { pivot: usize },
    #[error(
        "M is singular to working precision (not positive definite): smallest/largest squared Cholesky pivot = {ratio:e}"
    )]
    SingularMass { ratio: f64 },
    #[error(
        "H is not Hamiltonian: (J·H)[{i}][{j}] − (J·H)[{j}][{i}] = {diff:e}, above the tolerance {tol:e}"
    )]
    NotHamiltonian {
        i: usize,
        j: usize,
        diff: f64,
        tol: f64,
    },
    #[error("step size h = {0} must be finite and nonzero")]
    StepSize(f64),
    #[error("the stability polynomial {which} has no coefficients")]
    EmptyPolynomial { which: &'static str },
    #[error("{which}(0) = {value}, but a stability function R = P/Q has P(0) = Q(0) = 1")]
    StabilityConstant { which: &'static str, value: f64 },
    #[error(
        "the stability polynomial {which} has a non-finite coefficient {which}[{index}] = {value}"
    )]
    NonFiniteCoefficient {
        which: &'static str,
        index: usize,
        value: f64,
    },
    #[error(
        "Q(hH) is singular for h = {h} (smallest/largest LU pivot {ratio:e}): h times an eigenvalue of H is a pole of the stability function"
    )]
    SingularDenominator { h: f64, ratio: f64 },
    #[error("the propagator for h = {h} is not finite: h is too large for this stability function")]
    NonFinitePropagator { h: f64 },
    #[error("the propagator was built for h = {built}, but was asked to step h = {asked}")]
    StepMismatch { built: f64, asked: f64 },
    #[error("state has length {got}, but the system has dimension {expected}")]
    StateLength { expected: usize, got: usize },
    #[error("gyroscopic: {name} = {value}: {reason}")]
    Parameter {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },
}

/// `M q̈ + G q̇ + K q = f` as the linear Hamiltonian system `z' = Hz + u`
/// (paper eqs. (11)–(12); see the [module docs](self) for the derivation
/// and the checks).
///
/// It implements [`OdeSystem`] (`rhs = Hz + u`, `jacobian = H`) and
/// deliberately not [`Hamiltonian`](crate::Hamiltonian): the energy
/// [`energy`](Self::energy) is a method of its own.
#[derive(Clone, Debug)]
pub struct LinearHamiltonian {
    n: usize,
    m: Mat<f64>,
    g: Mat<f64>,
    k: Mat<f64>,
    f: Vec<f64>,
    m_inv: Mat<f64>,
    h: Mat<f64>,
}

/// `(i, j, |a_ij − sign·a_ji|)` of the largest violation over `i < j`
/// (and `i = j` for a skew check), with `sign = 1` for symmetry, `−1` for skew.
fn worst_asymmetry(a: MatRef<'_, f64>, sign: f64) -> (usize, usize, f64) {
    let n = a.nrows();
    let mut worst = (0, 0, 0.0);
    for j in 0..n {
        for i in 0..=j {
            let d = a[(i, j)] - sign * a[(j, i)];
            if d.abs() > worst.2 {
                worst = (i, j, d.abs());
            }
        }
    }
    worst
}

fn check_finite(matrix: &'static str, a: MatRef<'_, f64>) -> Result<(), LinearError> {
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            let value = a[(i, j)];
            if !value.is_finite() {
                return Err(LinearError::NonFinite {
                    matrix,
                    i,
                    j,
                    value,
                });
            }
        }
    }
    Ok(())
}

fn check_symmetric(matrix: &'static str, a: MatRef<'_, f64>) -> Result<(), LinearError> {
    let tol = SYMMETRY_TOL * a.norm_max();
    let (i, j, diff) = worst_asymmetry(a, 1.0);
    if diff > tol {
        return Err(LinearError::NotSymmetric {
            matrix,
            i,
            j,
            diff,
            tol,
        });
    }
    Ok(())
}

/// `(A ± Aᵀ)/2`.
fn sym_part(a: MatRef<'_, f64>, sign: f64) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| {
        0.5 * (a[(i, j)] + sign * a[(j, i)])
    })
}

fn product(a: MatRef<'_, f64>, b: MatRef<'_, f64>, alpha: f64) -> Mat<f64> {
    let mut c = Mat::zeros(a.nrows(), b.ncols());
    matmul(
        c.as_mut(),
        Accum::Replace,
        a,
        b,
        alpha,
        faer::get_global_parallelism(),
    );
    c
}

impl LinearHamiltonian {
    /// The model `M q̈ + G q̇ + K q = f` from dense `n × n` matrices and a
    /// force of length `n`. Refuses bad input with an error that names the
    /// matrix (see the [module docs](self) for every check and tolerance).
    pub fn new(
        m: MatRef<'_, f64>,
        g: MatRef<'_, f64>,
        k: MatRef<'_, f64>,
        f: &[f64],
    ) -> Result<Self, LinearError> {
        let n = m.nrows();
        if m.ncols() != n {
            return Err(LinearError::NotSquare {
                matrix: "M",
                rows: n,
                cols: m.ncols(),
            });
        }
        if n == 0 {
            return Err(LinearError::Empty);
        }
        for (matrix, a) in [("G", g), ("K", k)] {
            if a.nrows() != n || a.ncols() != n {
                return Err(LinearError::ShapeMismatch {
                    matrix,
                    rows: a.nrows(),
                    cols: a.ncols(),
                    n,
                });
            }
        }
        if f.len() != n {
            return Err(LinearError::ForceLength { len: f.len(), n });
        }
        for (matrix, a) in [("M", m), ("G", g), ("K", k)] {
            check_finite(matrix, a)?;
        }
        if let Some(i) = f.iter().position(|x| !x.is_finite()) {
            return Err(LinearError::NonFiniteForce { i, value: f[i] });
        }

        check_symmetric("M", m)?;
        let m = sym_part(m, 1.0);
        let llt = m.llt(Side::Lower).map_err(|e| match e {
            faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => {
                LinearError::NotPositiveDefinite { pivot: index }
            }
        })?;
        let l = llt.L();
        let (mut lo, mut hi) = (f64::INFINITY, 0.0_f64);
        for i in 0..n {
            let d = l[(i, i)] * l[(i, i)];
            lo = lo.min(d);
            hi = hi.max(d);
        }
        let ratio = lo / hi;
        if ratio.is_nan() || ratio <= n as f64 * f64::EPSILON {
            return Err(LinearError::SingularMass { ratio });
        }

        check_symmetric("K", k)?;
        let k = sym_part(k, 1.0);

        let g_tol = SYMMETRY_TOL * g.norm_max();
        let (i, j, sum) = worst_asymmetry(g, -1.0);
        if sum > g_tol {
            return Err(LinearError::NotSkew {
                i,
                j,
                sum,
                tol: g_tol,
            });
        }
        let g = sym_part(g, -1.0);

        let m_inv = llt.solve(Mat::<f64>::identity(n, n));
        let a = product(m_inv.as_ref(), g.as_ref(), -0.5);
        let c = product(g.as_ref(), m_inv.as_ref(), -0.5);
        // (−GM⁻¹/2)·G·(−1/2) = GM⁻¹G/4, then B = GM⁻¹G/4 − K.
        let mut b = product(c.as_ref(), g.as_ref(), -0.5);
        for j in 0..n {
            for i in 0..n {
                b[(i, j)] -= k[(i, j)];
            }
        }
        let d = m_inv;

        // J·H = [[B, C], [−A, −D]] must be symmetric: B, D symmetric and
        // C = −Aᵀ, each against the size of what it is made of.
        let (ng, nk, nd) = (g.norm_l2(), k.norm_l2(), d.norm_l2());
        let tol_b = HAMILTONIAN_TOL * (nk + ng * ng * nd / 4.0);
        let (i, j, diff) = worst_asymmetry(b.as_ref(), 1.0);
        if diff > tol_b {
            return Err(LinearError::NotHamiltonian {
                i,
                j,
                diff,
                tol: tol_b,
            });
        }
        let tol_d = HAMILTONIAN_TOL * nd;
        let (i, j, diff) = worst_asymmetry(d.as_ref(), 1.0);
        if diff > tol_d {
            return Err(LinearError::NotHamiltonian {
                i: n + i,
                j: n + j,
                diff,
                tol: tol_d,
            });
        }
        let tol_ac = HAMILTONIAN_TOL * ng * nd / 2.0;
        let mut worst = (0, 0, 0.0);
        for j in 0..n {
            for i in 0..n {
                let e = (a[(j, i)] + c[(i, j)]).abs();
                if e > worst.2 {
                    worst = (i, j, e);
                }
            }
        }
        if worst.2 > tol_ac {
            // (J·H)[i][n + j] = C[i][j], (J·H)[n + j][i] = −A[j][i].
            return Err(LinearError::NotHamiltonian {
                i: worst.0,
                j: n + worst.1,
                diff: worst.2,
                tol: tol_ac,
            });
        }

        // Assemble H = [[A', D'], [B', −A'ᵀ]] from the symmetrised blocks, so
        // that J·H is symmetric exactly.
        let b = sym_part(b.as_ref(), 1.0);
        let d = sym_part(d.as_ref(), 1.0);
        let a = Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] - c[(j, i)]));
        let h = Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
            (true, true) => a[(i, j)],
            (true, false) => d[(i, j - n)],
            (false, true) => b[(i - n, j)],
            (false, false) => -a[(j - n, i - n)],
        });
        Ok(LinearHamiltonian {
            n,
            m,
            g,
            k,
            f: f.to_vec(),
            m_inv: d,
            h,
        })
    }

    /// [`new`](Self::new) from rows: `Vec<Vec<f64>>`, `[[f64; N]; N]`,
    /// slices of slices. Ragged rows are refused, naming the matrix.
    pub fn from_rows<R: AsRef<[f64]>>(
        m: &[R],
        g: &[R],
        k: &[R],
        f: &[f64],
    ) -> Result<Self, LinearError> {
        fn to_mat<R: AsRef<[f64]>>(
            matrix: &'static str,
            rows: &[R],
        ) -> Result<Mat<f64>, LinearError> {
            let cols = rows.first().map_or(0, |r| r.as_ref().len());
            if let Some((row, r)) = rows
                .iter()
                .enumerate()
                .find(|(_, r)| r.as_ref().len() != cols)
            {
                return Err(LinearError::Ragged {
                    matrix,
                    row,
                    len: r.as_ref().len(),
                    expected: cols,
                });
            }
            Ok(Mat::from_fn(rows.len(), cols, |i, j| rows[i].as_ref()[j]))
        }
        let (m, g, k) = (to_mat("M", m)?, to_mat("G", g)?, to_mat("K", k)?);
        Self::new(m.as_ref(), g.as_ref(), k.as_ref(), f)
    }

    /// The same model with another constant force `f`.
    pub fn with_force(&self, f: &[f64]) -> Result<Self, LinearError> {
        if f.len() != self.n {
            return Err(LinearError::ForceLength {
                len: f.len(),
                n: self.n,
            });
        }
        if let Some(i) = f.iter().position(|x| !x.is_finite()) {
            return Err(LinearError::NonFiniteForce { i, value: f[i] });
        }
        let mut sys = self.clone();
        sys.f = f.to_vec();
        Ok(sys)
    }

    /// Degrees of freedom `n`; the state `z = [q; p]` has length `2n`.
    pub fn dof(&self) -> usize {
        self.n
    }
    /// The mass matrix (its symmetric part).
    pub fn mass(&self) -> MatRef<'_, f64> {
        self.m.as_ref()
    }
    /// `M⁻¹`, symmetric.
    pub fn mass_inverse(&self) -> MatRef<'_, f64> {
        self.m_inv.as_ref()
    }
    /// The gyroscopic matrix (its skew part).
    pub fn gyroscopic(&self) -> MatRef<'_, f64> {
        self.g.as_ref()
    }
    /// The stiffness matrix (its symmetric part).
    pub fn stiffness(&self) -> MatRef<'_, f64> {
        self.k.as_ref()
    }
    /// The constant force `f`.
    pub fn force(&self) -> &[f64] {
        &self.f
    }
    /// The Hamiltonian matrix `H` (`2n × 2n`).
    pub fn matrix(&self) -> MatRef<'_, f64> {
        self.h.as_ref()
    }
    /// `u = [0; f]`.
    pub fn offset(&self) -> Vec<f64> {
        let mut u = vec![0.0; 2 * self.n];
        u[self.n..].copy_from_slice(&self.f);
        u
    }
    /// The symmetric matrix `S = −JH` of the energy `½ zᵀSz − zᵀ(Ju)`.
    pub fn energy_matrix(&self) -> Mat<f64> {
        let n = self.n;
        // −J·H = [[−H_pq, −H_pp], [H_qq, H_qp]] (rows of H: q then p).
        Mat::from_fn(2 * n, 2 * n, |i, j| {
            if i < n {
                -self.h[(i + n, j)]
            } else {
                self.h[(i - n, j)]
            }
        })
    }

    /// The Hamiltonian `E(z) = ½ zᵀSz − zᵀ(Ju)`, with `S = −JH` and
    /// `Ju = [f; 0]`: in the original variables
    /// `½ (p − Gq/2)ᵀM⁻¹(p − Gq/2) + ½ qᵀKq − qᵀf`. Conserved by the exact
    /// flow (and by Gauss–Legendre propagators).
    ///
    /// # Panics
    /// If `z.len() != 2n`.
    pub fn energy(&self, z: &[f64]) -> f64 {
        let n = self.n;
        assert_eq!(
            z.len(),
            2 * n,
            "state has length {}, but the system has dimension {}",
            z.len(),
            2 * n
        );
        let mut w = vec![0.0; 2 * n];
        self.matvec(z, &mut w);
        // zᵀSz = −zᵀJ(Hz) = pᵀ(Hz)_q − qᵀ(Hz)_p.
        let (q, p) = z.split_at(n);
        let quad: f64 = p.iter().zip(&w[..n]).map(|(a, b)| a * b).sum::<f64>()
            - q.iter().zip(&w[n..]).map(|(a, b)| a * b).sum::<f64>();
        let lin: f64 = q.iter().zip(&self.f).map(|(a, b)| a * b).sum();
        0.5 * quad - lin
    }

    /// `out = Hz`.
    fn matvec(&self, z: &[f64], out: &mut [f64]) {
        matmul(
            ColMut::from_slice_mut(out).as_mat_mut(),
            Accum::Replace,
            self.h.as_ref(),
            ColRef::from_slice(z).as_mat(),
            1.0,
            Par::Seq,
        );
    }

    /// The exact flow over time `t`: `(Φ, φ)` with `z(t) = Φ z(0) + φ`,
    /// `Φ = exp(tH)`, `φ = ∫₀ᵗ exp(sH) ds · u`, both read off one matrix
    /// exponential of the augmented matrix `t·[[H, u], [0, 0]]` (scaling and
    /// squaring with the degree-13 Padé approximant, [`expm`]).
    pub fn flow(&self, t: f64) -> (Mat<f64>, Vec<f64>) {
        let d = 2 * self.n;
        let aug = Mat::from_fn(d + 1, d + 1, |i, j| {
            if i == d {
                0.0
            } else if j == d {
                if i >= self.n {
                    t * self.f[i - self.n]
                } else {
                    0.0
                }
            } else {
                t * self.h[(i, j)]
            }
        });
        let e = expm(aug.as_ref());
        let phi = e.as_ref().submatrix(0, 0, d, d).to_owned();
        let offset = (0..d).map(|i| e[(i, d)]).collect();
        (phi, offset)
    }

    /// The exact solution `z(t)` from `z(0) = z0` (see [`flow`](Self::flow)).
    pub fn exact(&self, z0: &[f64], t: f64) -> Result<Vec<f64>, LinearError> {
        let d = 2 * self.n;
        if z0.len() != d {
            return Err(LinearError::StateLength {
                expected: d,
                got: z0.len(),
            });
        }
        let (phi, mut z) = self.flow(t);
        matmul(
            ColMut::from_slice_mut(&mut z).as_mat_mut(),
            Accum::Add,
            phi.as_ref(),
            ColRef::from_slice(z0).as_mat(),
            1.0,
            Par::Seq,
        );
        Ok(z)
    }
}

impl OdeSystem for LinearHamiltonian {
    fn dim(&self) -> usize {
        2 * self.n
    }
    /// `dz = Hz + u`.
    fn rhs(&self, _t: f64, z: &[f64], dz: &mut [f64]) {
        self.matvec(z, dz);
        for (d, f) in dz[self.n..].iter_mut().zip(&self.f) {
            *d += f;
        }
    }
    /// `H`, row-major.
    fn jacobian(&self, _t: f64, _z: &[f64], jac: &mut [f64]) -> bool {
        let d = 2 * self.n;
        for i in 0..d {
            for j in 0..d {
                jac[i * d + j] = self.h[(i, j)];
            }
        }
        true
    }
}
