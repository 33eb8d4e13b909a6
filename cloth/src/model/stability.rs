//! The stability estimate of explicit schemes: `ω_max = √λ_max(M⁻¹K)` by
//! matrix-free power iteration, and Gershgorin's upper bound.

use nalgebra::{Matrix3, Vector3};

use super::{ClothModel, spring_block};

/// The stability estimate of explicit schemes at a configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stability {
    /// `√λ_max(M⁻¹K)`, `K = −∂F/∂q`, by power iteration (rad/s); a lower
    /// bound that converges from below.
    pub omega_max: f64,
    /// `2/ω_max`: the stability limit of symplectic Euler and Störmer–Verlet
    /// on the linearised system (s).
    pub h_max: f64,
    /// An upper bound on `ω_max` from Gershgorin's theorem (rad/s):
    /// `2/omega_bound` is a step size that is certainly stable for the
    /// linearisation.
    pub omega_bound: f64,
    /// Power iterations taken.
    pub iterations: usize,
    /// Whether the power iteration converged (to 1e-10 relatively) within
    /// its iterations; if not, `omega_max` is a rougher lower bound.
    pub converged: bool,
}

impl ClothModel {
    /// `y = −(∂F/∂q)·x / m = M⁻¹K·x` without the sparse matrix: spring by
    /// spring, so an explicit run's stability estimate needs no more memory
    /// than the state (see [`jac`](Self::jac) for why that matters).
    fn apply_stiffness(&self, q3: &[[f64; 3]], x: &[f64], y: &mut [f64]) {
        let x3 = &x.as_chunks::<3>().0[..self.free_count()];
        let y3 = &mut y.as_chunks_mut::<3>().0[..self.free_count()];
        y3.fill([0.0; 3]);
        // J·x: a spring's block K adds K(x_b − x_a) to row a and its
        // negative to row b; a pin spring −K·x_a; a collider C·x_a.
        for s in &self.ff {
            let (a, b) = (s.a as usize, s.b as usize);
            let d = Vector3::from(q3[b]) - Vector3::from(q3[a]);
            let k = spring_block(&d, s.kl, s.rest, false);
            let u = k * (Vector3::from(x3[b]) - Vector3::from(x3[a]));
            y3[a] = (Vector3::from(y3[a]) + u).into();
            y3[b] = (Vector3::from(y3[b]) - u).into();
        }
        for s in &self.fp {
            let a = s.a as usize;
            let d = Vector3::from(s.pin) - Vector3::from(q3[a]);
            let k = spring_block(&d, s.kl, s.rest, false);
            y3[a] = (Vector3::from(y3[a]) - k * Vector3::from(x3[a])).into();
        }
        for (k, x) in q3.iter().enumerate() {
            let x = Vector3::from(*x);
            for c in &self.colliders {
                y3[k] = (Vector3::from(y3[k]) + c.force_jacobian(&x) * Vector3::from(x3[k])).into();
            }
        }
        for v in y.iter_mut() {
            *v *= -self.inv_mass;
        }
    }

    /// The largest absolute row sum of `M⁻¹K` (Gershgorin's bound on its
    /// eigenvalues), assembled block by block: diagonal blocks summed over
    /// the springs and colliders of each particle; each off-diagonal block
    /// comes from one spring (two particles of a grid are joined by at most
    /// one spring).
    fn gershgorin_bound(&self, q3: &[[f64; 3]]) -> f64 {
        let n = self.free_count();
        let mut diag = vec![Matrix3::<f64>::zeros(); n];
        let mut row_abs = vec![0.0f64; 3 * n];
        let abs_rows = |m: &Matrix3<f64>, rows: &mut [f64]| {
            for (rr, r) in rows.iter_mut().enumerate() {
                *r += m.row(rr).iter().map(|v| v.abs()).sum::<f64>();
            }
        };
        for s in &self.ff {
            let (a, b) = (s.a as usize, s.b as usize);
            let d = Vector3::from(q3[b]) - Vector3::from(q3[a]);
            let k = spring_block(&d, s.kl, s.rest, false);
            diag[a] -= k;
            diag[b] -= k;
            abs_rows(&k, &mut row_abs[3 * a..3 * a + 3]);
            abs_rows(&k, &mut row_abs[3 * b..3 * b + 3]);
        }
        for s in &self.fp {
            let a = s.a as usize;
            let d = Vector3::from(s.pin) - Vector3::from(q3[a]);
            diag[a] -= spring_block(&d, s.kl, s.rest, false);
        }
        for (k, x) in q3.iter().enumerate() {
            let x = Vector3::from(*x);
            for c in &self.colliders {
                diag[k] += c.force_jacobian(&x);
            }
        }
        for (k, dk) in diag.iter().enumerate() {
            abs_rows(dk, &mut row_abs[3 * k..3 * k + 3]);
        }
        row_abs
            .iter()
            .fold(0.0, |m: f64, v| m.max(v * self.inv_mass))
    }

    /// Gershgorin's upper bound of `ω_max = √λ_max(M⁻¹K)` of the springs
    /// and colliders at the initial positions (rad/s): a rigorous rate
    /// that costs one pass over the springs, for choosing a step
    /// ([`crate::schedule::auto_step`]).
    pub fn spring_rate_bound(&self) -> f64 {
        let z = self.initial_state();
        self.gershgorin_bound(self.chunks(&z[..3 * self.free_count()]))
            .max(0.0)
            .sqrt()
    }

    /// Stability of explicit schemes at `q`: `ω_max = √λ_max(M⁻¹K)` with
    /// `K = −∂F/∂q`, by power iteration with the Rayleigh quotient (at most
    /// `max_iterations`, stopping once it changes by less than 1e-10
    /// relatively), and Gershgorin's upper bound. Matrix-free: memory in
    /// proportion to the state, time to `iterations × springs`.
    pub fn stability_at(&self, q: &[f64], max_iterations: usize) -> Stability {
        let dim = 3 * self.free_count();
        let q3 = self.chunks(q);
        let bound = self.gershgorin_bound(q3);
        // Start from a deterministic pseudo-random vector.
        let mut seed: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut x: Vec<f64> = (0..dim)
            .map(|_| {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect();
        let mut y = vec![0.0; dim];
        let mut lambda: f64 = 0.0;
        let mut iterations = 0;
        let mut converged = false;
        for it in 1..=max_iterations.max(1) {
            iterations = it;
            let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            if norm == 0.0 || !norm.is_finite() {
                converged = norm == 0.0;
                break;
            }
            x.iter_mut().for_each(|v| *v /= norm);
            self.apply_stiffness(q3, &x, &mut y);
            let rq: f64 = x.iter().zip(&y).map(|(a, b)| a * b).sum();
            std::mem::swap(&mut x, &mut y);
            let done = (rq - lambda).abs() <= 1e-10 * rq.abs();
            lambda = rq;
            if done {
                converged = true;
                break;
            }
        }
        let omega_max = lambda.max(0.0).sqrt();
        Stability {
            omega_max,
            h_max: 2.0 / omega_max,
            omega_bound: bound.sqrt(),
            iterations,
            converged,
        }
    }

    /// [`stability_at`](Self::stability_at) the initial positions, with up
    /// to 1000 iterations, and fewer on a large grid: at most
    /// [`STABILITY_WORK`] spring evaluations in all (on the paper's 25 × 25
    /// grid that would be 34 000 iterations, so 1000; on 2048 × 2048 about
    /// 5, and [`Stability::converged`] is then false). The estimate is
    /// printed beside every run, and must not cost more than a second or
    /// two however large the grid.
    pub fn stability(&self) -> Stability {
        let z = self.initial_state();
        let work = (self.active_spring_count() + self.free_count()).max(1);
        let iterations = (STABILITY_WORK / work).clamp(1, 1000);
        self.stability_at(&z[..3 * self.free_count()], iterations)
    }
}

/// The most spring evaluations [`ClothModel::stability`] spends on its
/// power iteration: 10⁸, about a second.
pub const STABILITY_WORK: usize = 100_000_000;
