//! Random gyroscopic test problems with a prescribed spread of frequencies.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef};

use super::{LinearError, LinearHamiltonian};

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny seeded generator whose
/// output is fixed by its definition, so a seed names the same problem on
/// every platform and with every version of every crate.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `(0, 1)`.
    fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    /// Standard normal (Box–Muller, one of the pair).
    fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

fn mul(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let mut c = Mat::zeros(a.nrows(), b.ncols());
    matmul(
        c.as_mut(),
        Accum::Replace,
        a,
        b,
        1.0,
        faer::get_global_parallelism(),
    );
    c
}

/// A random orthogonal matrix: `Q` of the QR factorisation of a Gaussian
/// matrix, columns signed so that `diag R > 0` (Haar distributed).
fn orthogonal(n: usize, rng: &mut SplitMix64) -> Mat<f64> {
    let a = Mat::from_fn(n, n, |_, _| rng.normal());
    let qr = a.qr();
    let mut q = qr.compute_Q();
    let r = qr.R();
    for j in 0..n {
        if r[(j, j)] < 0.0 {
            for i in 0..n {
                q[(i, j)] = -q[(i, j)];
            }
        }
    }
    q
}

/// `V diag(d) Vᵀ`, symmetrised.
fn congruence(v: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
    let vd = Mat::from_fn(v.nrows(), v.ncols(), |i, j| v[(i, j)] * d[j]);
    let a = mul(vd.as_ref(), v.transpose());
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

/// A deterministic random gyroscopic system `M q̈ + G q̇ + K q = f` with `n`
/// degrees of freedom whose frequencies spread over the ratio `spread`
/// (e.g. `1e4` for a stiff problem).
///
/// With orthogonal `V`, `U` and a Gaussian skew `R`, all drawn from `seed`:
///
/// * `M = V diag(m) Vᵀ`, masses `m_i = 10^{x_i}`, `x_i` uniform in `[0, 1)`
///   (SPD, condition number below 10);
/// * `K = M^{1/2} U diag(ω²) Uᵀ M^{1/2}` with `ω_i = spread^{i/(n−1)}`, so
///   the undamped frequencies (`K v = ω² M v`) are exactly `1 … spread`,
///   log-spaced (SPD);
/// * `G = M^{1/2} W M^{1/2}`, `W = ½ (R − Rᵀ)/‖R − Rᵀ‖_F` (skew, `‖W‖₂ ≤ ½`);
/// * `f_i` standard normal.
///
/// The gyroscopic system is stable (`K` positive definite), `H` has purely
/// imaginary eigenvalues `±iλ`, and every `λ` solves `λ² ± γλ = ω_R²` with
/// `|γ| ≤ ½` and `ω_R ∈ [1, spread]`, so the frequencies lie in
/// `[0.78, spread + 0.25]`.
///
/// The random numbers come from SplitMix64 built into this module, not from
/// `rand`: the library then needs no random-number dependency, and a seed
/// gives the same problem on every platform and version.
pub fn gyroscopic(n: usize, seed: u64, spread: f64) -> Result<LinearHamiltonian, LinearError> {
    if n == 0 {
        return Err(LinearError::Parameter {
            name: "n",
            value: 0.0,
            reason: "at least one degree of freedom is needed",
        });
    }
    if !(spread.is_finite() && spread >= 1.0) {
        return Err(LinearError::Parameter {
            name: "spread",
            value: spread,
            reason: "the frequency ratio must be finite and at least 1",
        });
    }
    let mut rng = SplitMix64(seed);
    let v = orthogonal(n, &mut rng);
    let u = orthogonal(n, &mut rng);
    let masses: Vec<f64> = (0..n).map(|_| 10f64.powf(rng.uniform())).collect();
    let m = congruence(v.as_ref(), &masses);
    let sqrt_m = congruence(
        v.as_ref(),
        &masses.iter().map(|x| x.sqrt()).collect::<Vec<_>>(),
    );
    let omega2: Vec<f64> = (0..n)
        .map(|i| {
            let e = if n == 1 {
                0.0
            } else {
                i as f64 / (n - 1) as f64
            };
            spread.powf(2.0 * e)
        })
        .collect();
    let inner = congruence(u.as_ref(), &omega2);
    let k = mul(
        mul(sqrt_m.as_ref(), inner.as_ref()).as_ref(),
        sqrt_m.as_ref(),
    );
    let k = Mat::from_fn(n, n, |i, j| 0.5 * (k[(i, j)] + k[(j, i)]));
    let r = Mat::from_fn(n, n, |_, _| rng.normal());
    let skew = Mat::from_fn(n, n, |i, j| r[(i, j)] - r[(j, i)]);
    let norm = skew.norm_l2();
    let w = Mat::from_fn(n, n, |i, j| {
        if norm > 0.0 {
            0.5 * skew[(i, j)] / norm
        } else {
            0.0
        }
    });
    let g = mul(mul(sqrt_m.as_ref(), w.as_ref()).as_ref(), sqrt_m.as_ref());
    let g = Mat::from_fn(n, n, |i, j| 0.5 * (g[(i, j)] - g[(j, i)]));
    let f: Vec<f64> = (0..n).map(|_| rng.normal()).collect();
    LinearHamiltonian::new(m.as_ref(), g.as_ref(), k.as_ref(), &f)
}
