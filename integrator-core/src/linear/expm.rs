//! The matrix exponential by scaling and squaring with the degree-13 Padé
//! approximant (Higham, "The scaling and squaring method for the matrix
//! exponential revisited", SIAM J. Matrix Anal. Appl. 26, 2005, Alg. 2.3,
//! degree 13 branch): the reference for the exact flow of `z' = Hz + u`.

use faer::linalg::matmul::matmul;
use faer::linalg::solvers::Solve;
use faer::{Accum, Mat, MatRef};

/// Coefficients `b_0 … b_13` of the [13/13] Padé approximant of `exp`.
const B13: [f64; 14] = [
    64_764_752_532_480_000.0,
    32_382_376_266_240_000.0,
    7_771_770_303_897_600.0,
    1_187_353_796_428_800.0,
    129_060_195_264_000.0,
    10_559_470_521_600.0,
    670_442_572_800.0,
    33_522_128_640.0,
    1_323_241_920.0,
    40_840_800.0,
    960_960.0,
    16_380.0,
    182.0,
    1.0,
];

/// `θ_13`: the largest 1-norm for which the [13/13] Padé approximant has
/// backward error below the unit roundoff.
const THETA13: f64 = 5.371_920_351_148_152;

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

/// `exp(A)` for a square `A`.
///
/// # Panics
/// If `A` is not square.
pub fn expm(a: MatRef<'_, f64>) -> Mat<f64> {
    let n = a.nrows();
    assert_eq!(
        a.ncols(),
        n,
        "expm: the matrix is {}×{}, not square",
        n,
        a.ncols()
    );
    let norm1 = (0..n)
        .map(|j| (0..n).map(|i| a[(i, j)].abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let s = if norm1 > THETA13 {
        (norm1 / THETA13).log2().ceil() as i32
    } else {
        0
    };
    let scale = 0.5_f64.powi(s);
    let a = Mat::from_fn(n, n, |i, j| scale * a[(i, j)]);
    let a2 = mul(a.as_ref(), a.as_ref());
    let a4 = mul(a2.as_ref(), a2.as_ref());
    let a6 = mul(a4.as_ref(), a2.as_ref());
    let b = &B13;
    let id = |i: usize, j: usize| if i == j { 1.0 } else { 0.0 };
    // U = A [A6 (b13 A6 + b11 A4 + b9 A2) + b7 A6 + b5 A4 + b3 A2 + b1 I]
    let inner_u = Mat::from_fn(n, n, |i, j| {
        b[13] * a6[(i, j)] + b[11] * a4[(i, j)] + b[9] * a2[(i, j)]
    });
    let mut tmp = mul(a6.as_ref(), inner_u.as_ref());
    for j in 0..n {
        for i in 0..n {
            tmp[(i, j)] +=
                b[7] * a6[(i, j)] + b[5] * a4[(i, j)] + b[3] * a2[(i, j)] + b[1] * id(i, j);
        }
    }
    let u = mul(a.as_ref(), tmp.as_ref());
    // V = A6 (b12 A6 + b10 A4 + b8 A2) + b6 A6 + b4 A4 + b2 A2 + b0 I
    let inner_v = Mat::from_fn(n, n, |i, j| {
        b[12] * a6[(i, j)] + b[10] * a4[(i, j)] + b[8] * a2[(i, j)]
    });
    let mut v = mul(a6.as_ref(), inner_v.as_ref());
    for j in 0..n {
        for i in 0..n {
            v[(i, j)] +=
                b[6] * a6[(i, j)] + b[4] * a4[(i, j)] + b[2] * a2[(i, j)] + b[0] * id(i, j);
        }
    }
    // R = (V − U)⁻¹ (V + U), then square s times.
    let den = Mat::from_fn(n, n, |i, j| v[(i, j)] - u[(i, j)]);
    let num = Mat::from_fn(n, n, |i, j| v[(i, j)] + u[(i, j)]);
    let mut r = den.partial_piv_lu().solve(num);
    for _ in 0..s {
        r = mul(r.as_ref(), r.as_ref());
    }
    r
}
