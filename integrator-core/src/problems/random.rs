//! Seeded random separable problems for property tests.

use crate::system::Separable;

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny, seedable generator, good
/// enough for drawing test coefficients and reproducible from the seed
/// alone.
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`, 53 random bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// `H = T(p) + V(q)` with `n` = 2 or 3 degrees of freedom and random
/// coefficients drawn from a seed:
///
/// * `V(q) = ½ qᵀAq + Σᵢⱼ cᵢⱼ qᵢ² qⱼ + Σᵢ dᵢ qᵢ⁴/4`, `A` symmetric and
///   diagonally dominant (positive definite), `dᵢ > 0` (bounded below);
/// * `T(p) = ½ pᵀWp + α Σᵢ pᵢ⁴/4`, `W` symmetric positive definite (a
///   random inverse mass matrix), `α = 0` unless set with
///   [`with_quartic_kinetic`](RandomSeparable::with_quartic_kinetic).
///
/// With `α ≠ 0` the kinetic energy is not quadratic, which exercises the
/// order conditions that Runge–Kutta–Nyström methods skip.
#[derive(Clone, Debug, PartialEq)]
pub struct RandomSeparable {
    pub n: usize,
    /// `n × n`, row-major.
    pub a: Vec<f64>,
    /// `n × n`, row-major: the coefficient of `qᵢ² qⱼ`.
    pub c: Vec<f64>,
    pub d: Vec<f64>,
    /// `n × n`, row-major.
    pub w: Vec<f64>,
    pub alpha: f64,
}

/// A random symmetric, strictly diagonally dominant matrix with diagonal in
/// `[lo, hi)` and off-diagonal entries in `(−off, off)`, `2·off < lo`.
fn spd(rng: &mut SplitMix64, n: usize, lo: f64, hi: f64, off: f64) -> Vec<f64> {
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        m[i * n + i] = rng.uniform(lo, hi);
        for j in 0..i {
            let x = rng.uniform(-off, off);
            m[i * n + j] = x;
            m[j * n + i] = x;
        }
    }
    m
}

impl RandomSeparable {
    /// The problem for `seed`: 2 or 3 degrees of freedom, quadratic `T`.
    pub fn new(seed: u64) -> Self {
        let mut rng = SplitMix64(seed);
        let n = 2 + (rng.next_u64() % 2) as usize;
        let a = spd(&mut rng, n, 0.5, 2.0, 0.2);
        let c = (0..n * n).map(|_| rng.uniform(-0.3, 0.3)).collect();
        let d = (0..n).map(|_| rng.uniform(0.05, 0.3)).collect();
        let w = spd(&mut rng, n, 0.5, 1.5, 0.2);
        RandomSeparable {
            n,
            a,
            c,
            d,
            w,
            alpha: 0.0,
        }
    }

    /// The same problem with `T(p) = ½ pᵀWp + α Σ pᵢ⁴/4`.
    pub fn with_quartic_kinetic(mut self, alpha: f64) -> Self {
        self.alpha = alpha;
        self
    }

    /// A random state with entries in `(−scale, scale)`, from `seed`.
    pub fn random_state(&self, seed: u64, scale: f64) -> Vec<f64> {
        let mut rng = SplitMix64(seed ^ 0xA5A5_5A5A_DEAD_BEEF);
        (0..2 * self.n)
            .map(|_| rng.uniform(-scale, scale))
            .collect()
    }

    fn quad(m: &[f64], x: &[f64], n: usize) -> f64 {
        let mut s = 0.0;
        for i in 0..n {
            for j in 0..n {
                s += x[i] * m[i * n + j] * x[j];
            }
        }
        0.5 * s
    }
}

impl Separable for RandomSeparable {
    fn dof(&self) -> usize {
        self.n
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        Self::quad(&self.w, p, self.n) + self.alpha * p.iter().map(|x| x.powi(4)).sum::<f64>() / 4.0
    }
    fn potential(&self, q: &[f64]) -> f64 {
        let n = self.n;
        let mut v = Self::quad(&self.a, q, n);
        for i in 0..n {
            for j in 0..n {
                v += self.c[i * n + j] * q[i] * q[i] * q[j];
            }
            v += self.d[i] * q[i].powi(4) / 4.0;
        }
        v
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        let n = self.n;
        for i in 0..n {
            let wp: f64 = (0..n).map(|j| self.w[i * n + j] * p[j]).sum();
            out[i] = wp + self.alpha * p[i].powi(3);
        }
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        let n = self.n;
        for k in 0..n {
            // ∂/∂q_k of Σᵢⱼ cᵢⱼ qᵢ² qⱼ = 2 q_k Σⱼ c_kj qⱼ + Σᵢ cᵢₖ qᵢ².
            let mut g: f64 = (0..n).map(|j| self.a[k * n + j] * q[j]).sum();
            for j in 0..n {
                g += 2.0 * self.c[k * n + j] * q[k] * q[j] + self.c[j * n + k] * q[j] * q[j];
            }
            g += self.d[k] * q[k].powi(3);
            out[k] = -g;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradients_match_finite_differences() {
        for seed in 0..20 {
            let sys = RandomSeparable::new(seed).with_quartic_kinetic(0.5);
            let n = sys.n;
            assert!(n == 2 || n == 3);
            let z = sys.random_state(seed, 0.8);
            let (q, p) = z.split_at(n);
            let (mut f, mut v) = (vec![0.0; n], vec![0.0; n]);
            sys.force(q, &mut f);
            sys.velocity(p, &mut v);
            let d = 1e-6;
            for i in 0..n {
                let (mut qp, mut qm, mut pp, mut pm) =
                    (q.to_vec(), q.to_vec(), p.to_vec(), p.to_vec());
                qp[i] += d;
                qm[i] -= d;
                pp[i] += d;
                pm[i] -= d;
                let dv = (sys.potential(&qp) - sys.potential(&qm)) / (2.0 * d);
                let dt = (sys.kinetic(&pp) - sys.kinetic(&pm)) / (2.0 * d);
                assert!(
                    (dv + f[i]).abs() < 1e-8,
                    "seed {seed}: ∂V/∂q{i} = {dv} but force {}",
                    f[i]
                );
                assert!(
                    (dt - v[i]).abs() < 1e-8,
                    "seed {seed}: ∂T/∂p{i} = {dt} but velocity {}",
                    v[i]
                );
            }
        }
    }

    #[test]
    fn seeds_are_reproducible_and_distinct() {
        assert_eq!(RandomSeparable::new(7), RandomSeparable::new(7));
        assert_ne!(RandomSeparable::new(7), RandomSeparable::new(8));
        let mut rng = SplitMix64(1);
        assert!(
            (0..1000)
                .map(|_| rng.unit())
                .all(|x| (0.0..1.0).contains(&x))
        );
    }
}
