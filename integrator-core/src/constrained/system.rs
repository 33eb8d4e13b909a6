//! The constrained Hamiltonian system: what a problem provides.

/// A Hamiltonian `H(q, p) = ½ pᵀM⁻¹p + V(q)` with a constant diagonal mass
/// matrix `M`, restricted to the manifold of `m` holonomic constraints
/// `g(q) = 0` (`g: ℝᵈ → ℝᵐ`), with `G(q) = ∂g/∂q` of full rank `m` there.
///
/// The equations of motion are the index-3 differential-algebraic system
///
/// ```text
/// q' = M⁻¹p,   p' = −∇V(q) − G(q)ᵀλ,   0 = g(q),
/// ```
///
/// whose solutions also satisfy the hidden constraint `G(q)M⁻¹p = 0`
/// (the derivative of `g(q(t)) = 0`). The state is `z = [q; p]` in Cartesian
/// coordinates; the multipliers `λ` are not part of it, the stepper solves
/// for them.
///
/// The rows of `G` are dense here: the trait serves small systems (a
/// spherical pendulum, a pendulum chain), where a dense solve of the stage
/// equations is cheapest. A cloth with thousands of edge constraints needs
/// sparse rows and a sparse factorisation, which is the cloth crate's own
/// model.
pub trait Constrained {
    /// `d`, the number of position coordinates.
    fn dof(&self) -> usize;

    /// `m`, the number of constraints (at most `d`).
    fn constraints(&self) -> usize;

    /// The diagonal of `M⁻¹` (`out` has length `d`); every entry must be
    /// positive and finite. A diagonal mass keeps `G M⁻¹ Gᵀ` cheap to form
    /// and covers particle systems, the case the constraint solvers are for.
    fn inverse_mass(&self, out: &mut [f64]);

    /// `V(q)`.
    fn potential(&self, q: &[f64]) -> f64;

    /// `∇V(q)` into `out` (length `d`).
    fn grad_potential(&self, q: &[f64], out: &mut [f64]);

    /// `g(q)` into `out` (length `m`).
    fn constraint(&self, q: &[f64], out: &mut [f64]);

    /// `G(q) = ∂g/∂q` into `out`, row-major `m × d`: row `l` is `∇g_l(q)ᵀ`.
    fn constraint_jacobian(&self, q: &[f64], out: &mut [f64]);

    /// `∇²V(q) + Σₗ λₗ ∇²gₗ(q)` into `out` (row-major `d × d`), returning
    /// `true`; or `false` where the problem does not provide it.
    ///
    /// With it the stage equations are solved by Newton's method proper
    /// (quadratic convergence); without it the `O(h²)` curvature term of the
    /// Newton matrix is left out (a simplified Newton iteration, linear
    /// convergence with rate `O(h²)`). Either way the iteration stops only
    /// at round-off, so the result is the same to round-off. For the s = 2
    /// pair (RATTLE) the term does not occur at all.
    fn curvature(&self, q: &[f64], lambda: &[f64], out: &mut [f64]) -> bool {
        let _ = (q, lambda, out);
        false
    }

    /// A name for constraint `l` in messages (e.g. `link 3 (bob 2 – bob 3)`).
    fn constraint_name(&self, l: usize) -> String {
        format!("constraint {l}")
    }
}

/// `H(q, p) = ½ pᵀM⁻¹p + V(q)` at `z = [q; p]`.
pub fn constrained_energy<S: Constrained + ?Sized>(sys: &S, z: &[f64]) -> f64 {
    let d = sys.dof();
    let mut minv = vec![0.0; d];
    sys.inverse_mass(&mut minv);
    let (q, p) = z.split_at(d);
    let kinetic: f64 = p.iter().zip(&minv).map(|(p, w)| 0.5 * w * p * p).sum();
    kinetic + sys.potential(q)
}

/// The residuals of a state: `|gₗ(q)|` and `|(G M⁻¹ p)ₗ|` for every
/// constraint, each divided by its round-off scale (see [`Residuals`]).
pub fn residuals<S: Constrained + ?Sized>(sys: &S, z: &[f64]) -> Residuals {
    let (d, m) = (sys.dof(), sys.constraints());
    let (q, p) = z.split_at(d);
    let mut g = vec![0.0; m];
    let mut gq = vec![0.0; m * d];
    let mut minv = vec![0.0; d];
    sys.constraint(q, &mut g);
    sys.constraint_jacobian(q, &mut gq);
    sys.inverse_mass(&mut minv);
    let qn = inf_norm(q);
    let v: Vec<f64> = p.iter().zip(&minv).map(|(p, w)| p * w).collect();
    let vn = inf_norm(&v);
    let mut out = Residuals {
        position: Vec::with_capacity(m),
        velocity: Vec::with_capacity(m),
    };
    for l in 0..m {
        let row = &gq[l * d..(l + 1) * d];
        let gn: f64 = row.iter().map(|x| x.abs()).sum();
        let gv: f64 = row.iter().zip(&v).map(|(a, b)| a * b).sum();
        out.position.push(Residual {
            value: g[l],
            scale: gn * qn,
        });
        out.velocity.push(Residual {
            value: gv,
            scale: gn * vn,
        });
    }
    out
}

/// One residual and the scale of its rounding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Residual {
    pub value: f64,
    /// `‖∇gₗ‖₁·‖q‖∞` for `gₗ(q)` (how much `gₗ` moves when every coordinate
    /// moves by its unit in the last place, over `ε`), `‖∇gₗ‖₁·‖M⁻¹p‖∞` for
    /// `(G M⁻¹ p)ₗ`. A residual at round-off is a small multiple of
    /// `ε·scale`.
    pub scale: f64,
}

impl Residual {
    /// `|value| / (ε·scale)`: the residual in units of its round-off (0 where
    /// both vanish, infinite where only the scale does).
    pub fn in_ulps(&self) -> f64 {
        if self.value == 0.0 {
            0.0
        } else {
            self.value.abs() / (f64::EPSILON * self.scale)
        }
    }
}

/// The constraint residuals of a state, per constraint.
#[derive(Clone, Debug, PartialEq)]
pub struct Residuals {
    /// `gₗ(q)`.
    pub position: Vec<Residual>,
    /// `(G(q) M⁻¹ p)ₗ`, the hidden (velocity) constraint.
    pub velocity: Vec<Residual>,
}

impl Residuals {
    /// The largest position residual in units of round-off, and its index.
    pub fn worst_position(&self) -> (usize, f64) {
        worst(&self.position)
    }
    /// The largest velocity residual in units of round-off, and its index.
    pub fn worst_velocity(&self) -> (usize, f64) {
        worst(&self.velocity)
    }
}

fn worst(r: &[Residual]) -> (usize, f64) {
    r.iter()
        .enumerate()
        .map(|(i, r)| (i, r.in_ulps()))
        .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a })
}

pub(crate) fn inf_norm(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |a: f64, b| a.max(b.abs()))
}
