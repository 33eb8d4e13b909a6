//! What the symplecticity tests share: the Jacobian of a one-step map by
//! finite differences, and its symplecticity defect.

/// `Ψ'` as columns: `jac[j][i] = ∂Ψᵢ/∂zⱼ` of the map `step` (in place) at
/// `z`, by central differences with increments `δ, δ/2, δ/4`
/// (`δ = delta·max(1, |zⱼ|)`) and two Richardson rounds, which cancel the
/// `δ²` and `δ⁴` terms.
pub fn jacobian(step: impl Fn(&mut [f64]), z: &[f64], delta: f64) -> Vec<Vec<f64>> {
    let central = |j: usize, d: f64| -> Vec<f64> {
        let (mut zp, mut zm) = (z.to_vec(), z.to_vec());
        zp[j] += d;
        zm[j] -= d;
        step(&mut zp);
        step(&mut zm);
        zp.iter()
            .zip(&zm)
            .map(|(a, b)| (a - b) / (2.0 * d))
            .collect()
    };
    let combine = |fine: &[f64], coarse: &[f64], k: f64| -> Vec<f64> {
        fine.iter()
            .zip(coarse)
            .map(|(f, c)| (k * f - c) / (k - 1.0))
            .collect()
    };
    (0..z.len())
        .map(|j| {
            let d = delta * z[j].abs().max(1.0);
            let (d1, d2, d4) = (central(j, d), central(j, d / 2.0), central(j, d / 4.0));
            let (r1, r2) = (combine(&d2, &d1, 4.0), combine(&d4, &d2, 4.0));
            combine(&r2, &r1, 16.0)
        })
        .collect()
}

/// `max |Ψ'ᵀJΨ' − J| / max(1, ‖Ψ'‖²_F)` with `J = [[0, I], [−I, 0]]`.
pub fn symplecticity_defect(jac: &[Vec<f64>]) -> f64 {
    let n = jac.len() / 2;
    let norm2: f64 = jac.iter().flatten().map(|x| x * x).sum();
    let mut worst: f64 = 0.0;
    for a in 0..2 * n {
        for b in 0..2 * n {
            // (Ψ'ᵀ J Ψ')_ab = Σᵢ (∂qᵢ/∂z_a ∂pᵢ/∂z_b − ∂pᵢ/∂z_a ∂qᵢ/∂z_b).
            let form: f64 = (0..n)
                .map(|i| jac[a][i] * jac[b][n + i] - jac[a][n + i] * jac[b][i])
                .sum();
            let j_ab = if b == a + n {
                1.0
            } else if a == b + n {
                -1.0
            } else {
                0.0
            };
            worst = worst.max((form - j_ab).abs());
        }
    }
    worst / norm2.max(1.0)
}
