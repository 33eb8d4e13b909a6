//! A chain of point masses joined by massless rods, hanging from a fixed
//! pivot, in the plane or in space: a constrained system with one length
//! constraint per link.

use crate::constrained::Constrained;

/// `n` bobs `x₁ … xₙ ∈ ℝ^dim` (`dim` = 2 or 3), link `l` joining bob `l − 1`
/// (the pivot at the origin for `l = 1`) to bob `l` with
/// `g_l(q) = |x_l − x_{l−1}|² − L_l²`, gravity along the last axis (−y in
/// the plane, −z in space), `V = Σ m_i g x_i[dim − 1]`. The state is
/// `q = [x₁; …; xₙ]`, `p = [m₁ẋ₁; …]`.
///
/// The squared form of the constraint is a polynomial with exact gradient
/// and Hessian. Its gradient vanishes where a link has zero length, so a
/// chain built with `L_l = 0` is accepted here and refused by
/// [`check_start`](crate::constrained::check_start), which names the link.
#[derive(Clone, Debug, PartialEq)]
pub struct PendulumChain {
    dim: usize,
    lengths: Vec<f64>,
    masses: Vec<f64>,
    gravity: f64,
}

/// A chain that cannot be built, naming the field.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("pendulum chain: {field}: {message}")]
pub struct ChainError {
    pub field: String,
    pub message: String,
}

impl PendulumChain {
    /// A chain with these link lengths and bob masses (equally many, at
    /// least one). Lengths must be finite and non-negative, masses positive
    /// and finite, `dim` 2 or 3.
    pub fn new(
        dim: usize,
        lengths: Vec<f64>,
        masses: Vec<f64>,
        gravity: f64,
    ) -> Result<Self, ChainError> {
        let err = |field: String, message: String| Err(ChainError { field, message });
        if dim != 2 && dim != 3 {
            return err("dim".into(), format!("{dim} (must be 2 or 3)"));
        }
        if lengths.is_empty() || lengths.len() != masses.len() {
            return err(
                "lengths".into(),
                format!(
                    "{} links for {} masses (need equally many, at least one)",
                    lengths.len(),
                    masses.len()
                ),
            );
        }
        if let Some(i) = lengths.iter().position(|l| !(l.is_finite() && *l >= 0.0)) {
            return err(
                format!("lengths[{i}]"),
                format!("{} (must be finite and ≥ 0)", lengths[i]),
            );
        }
        if let Some(i) = masses.iter().position(|m| !(m.is_finite() && *m > 0.0)) {
            return err(
                format!("masses[{i}]"),
                format!("{} (must be positive and finite)", masses[i]),
            );
        }
        if !gravity.is_finite() {
            return err("gravity".into(), format!("{gravity} (must be finite)"));
        }
        Ok(PendulumChain {
            dim,
            lengths,
            masses,
            gravity,
        })
    }

    /// `n` equal links of length `length/n` and equal masses `1/n`.
    pub fn uniform(dim: usize, n: usize, length: f64, gravity: f64) -> Result<Self, ChainError> {
        let k = n.max(1) as f64;
        Self::new(dim, vec![length / k; n], vec![1.0 / k; n], gravity)
    }

    pub fn links(&self) -> usize {
        self.lengths.len()
    }

    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The state with link `l` at angle `angles[l]` from the downward
    /// vertical, in the plane of the first and last axes, turning at
    /// `rates[l]`: on the manifold and tangent to it up to rounding.
    pub fn state(&self, angles: &[f64], rates: &[f64]) -> Vec<f64> {
        let (n, dim) = (self.links(), self.dim);
        let mut z = vec![0.0; 2 * n * dim];
        let (mut x, mut y, mut vx, mut vy) = (0.0, 0.0, 0.0, 0.0);
        for l in 0..n {
            let (s, c) = angles[l].sin_cos();
            let len = self.lengths[l];
            x += len * s;
            y -= len * c;
            vx += len * c * rates[l];
            vy += len * s * rates[l];
            z[l * dim] = x;
            z[l * dim + dim - 1] = y;
            z[n * dim + l * dim] = self.masses[l] * vx;
            z[n * dim + l * dim + dim - 1] = self.masses[l] * vy;
        }
        z
    }

    /// `x_l − x_{l−1}` (the pivot for `l = 0`), component `a`.
    #[inline]
    fn link(&self, q: &[f64], l: usize, a: usize) -> f64 {
        let dim = self.dim;
        let prev = if l == 0 { 0.0 } else { q[(l - 1) * dim + a] };
        q[l * dim + a] - prev
    }
}

impl Constrained for PendulumChain {
    fn dof(&self) -> usize {
        self.links() * self.dim
    }
    fn constraints(&self) -> usize {
        self.links()
    }
    fn inverse_mass(&self, out: &mut [f64]) {
        for (i, m) in self.masses.iter().enumerate() {
            out[i * self.dim..(i + 1) * self.dim].fill(1.0 / m);
        }
    }
    fn potential(&self, q: &[f64]) -> f64 {
        let dim = self.dim;
        (0..self.links())
            .map(|i| self.masses[i] * self.gravity * q[i * dim + dim - 1])
            .sum()
    }
    fn grad_potential(&self, _q: &[f64], out: &mut [f64]) {
        let dim = self.dim;
        out.fill(0.0);
        for i in 0..self.links() {
            out[i * dim + dim - 1] = self.masses[i] * self.gravity;
        }
    }
    fn constraint(&self, q: &[f64], out: &mut [f64]) {
        for (l, g) in out.iter_mut().enumerate() {
            let sq: f64 = (0..self.dim).map(|a| self.link(q, l, a).powi(2)).sum();
            *g = sq - self.lengths[l] * self.lengths[l];
        }
    }
    fn constraint_jacobian(&self, q: &[f64], out: &mut [f64]) {
        let (dim, d) = (self.dim, self.dof());
        out.fill(0.0);
        for l in 0..self.links() {
            for a in 0..dim {
                let e = 2.0 * self.link(q, l, a);
                out[l * d + l * dim + a] = e;
                if l > 0 {
                    out[l * d + (l - 1) * dim + a] = -e;
                }
            }
        }
    }
    fn curvature(&self, _q: &[f64], lambda: &[f64], out: &mut [f64]) -> bool {
        // Σ λ_l ∇²g_l: 2λ_l on the blocks (l, l), (l−1, l−1) and −2λ_l on
        // (l, l−1), (l−1, l); V is linear.
        let (dim, d) = (self.dim, self.dof());
        out.fill(0.0);
        for (l, lam) in lambda.iter().enumerate() {
            let w = 2.0 * lam;
            for a in 0..dim {
                let i = l * dim + a;
                out[i * d + i] += w;
                if l > 0 {
                    let j = (l - 1) * dim + a;
                    out[j * d + j] += w;
                    out[i * d + j] -= w;
                    out[j * d + i] -= w;
                }
            }
        }
        true
    }
    fn constraint_name(&self, l: usize) -> String {
        if l == 0 {
            "link 1 (pivot – bob 1)".to_string()
        } else {
            format!("link {} (bob {} – bob {})", l + 1, l, l + 1)
        }
    }
}
