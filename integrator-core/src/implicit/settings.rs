//! How the stage equations are solved, and what it cost.

/// The iteration for the stage equations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Solver {
    /// Simplified Newton when the system provides a Jacobian
    /// ([`OdeSystem::jacobian`](crate::OdeSystem::jacobian) returns `true`;
    /// always for [`step_sparse`](super::step_sparse)), fixed-point
    /// iteration otherwise. When fixed-point iteration fails on a step
    /// (a stiff problem), the step is retried with simplified Newton on a
    /// finite-difference Jacobian, and that workspace uses Newton from then
    /// on.
    #[default]
    Auto,
    /// Simplified Newton: `(I − h·A⊗J)·ΔZ = −G(Z)` with `J = ∂f/∂z` at the
    /// start of the step (or an earlier one, see
    /// [`Settings::reuse_jacobian`]). Needed for stiff problems. A system
    /// without a Jacobian gets a finite-difference one unless
    /// [`Settings::finite_differences`] is off (then
    /// [`SolveError::NoJacobian`](crate::SolveError::NoJacobian)).
    Newton,
    /// `Z ← h·(A⊗I)·F(z + Z)`: no linear algebra, converges only while
    /// `h·‖A‖·‖J‖ < 1`.
    FixedPoint,
}

/// Settings of the stage solver. The defaults iterate to round-off; they are
/// what the schemes declared with `butcher!` use.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Default [`Solver::Auto`].
    pub solver: Solver,
    /// Iterations per solve (per stage for DIRK tables) before
    /// [`SolveError::NotConverged`](crate::SolveError::NotConverged).
    /// Default 50.
    pub max_iterations: usize,
    /// The iteration has converged when the corrections are at most this
    /// fraction of the increments they correct, component by component
    /// (`maxᵢ|ΔZᵢₖ| ≤ tol·maxᵢ|Zᵢₖ|` for every `k`; for DIRK tables stage by
    /// stage), so that the `F(Yᵢ)` used in the update are those of the
    /// converged stages to round-off; or when the contraction observed
    /// (`θ/(1 − θ)` times the previous correction) shows that the iterate
    /// at which `F` was just evaluated was already that close. Default
    /// `f64::EPSILON`. Where round-off keeps both from being met (a
    /// component whose increments are tiny, or computed with cancellation),
    /// the stagnation test ends the iteration. Stopping earlier (relative
    /// to the state rather than to the increment) leaves a systematic error
    /// of about `h·L·ε` per step that adds up linearly instead of as a
    /// random walk: raise it only knowingly.
    pub tolerance: f64,
    /// The stagnation test of Hairer's GNI codes: when a correction,
    /// measured relative to the stage values (`max |ΔZᵢₖ|/(|zₖ| + |Zᵢₖ|)`),
    /// is no smaller than the previous one and at most this large, the
    /// iteration has reached round-off and stops converged. Above it a
    /// correction that does not decrease is growth
    /// ([`SolveError::Diverged`](crate::SolveError::Diverged)).
    /// Default `1e-12`; raise it for very ill-conditioned stage matrices.
    pub stagnation_limit: f64,
    /// The round-off floor of ill-conditioned stage systems: when the
    /// corrections have fallen by a factor 10⁴ from the largest of the
    /// solve and then stop decreasing (`‖ΔZₖ‖ ≥ ‖ΔZₖ₋₁‖`; noise may rise by
    /// any factor, but stays 10⁴ below the largest correction), at most this
    /// large relative to the stage values, the iteration has reached what
    /// the conditioning of
    /// `I − h·A⊗J` allows and stops converged. A stiff system stepped far
    /// beyond its explicit limit (a cloth at `h·ω_max ≈ 100`: condition
    /// number ~10⁴, and momenta that are small sums of large spring forces)
    /// stalls there at a few `1e-9`, above any fixed
    /// [`stagnation_limit`](Self::stagnation_limit) one would dare to set for
    /// every problem. Default `1e-8`; 0 disables it.
    pub plateau_limit: f64,
    /// Add the increments `h·Σ bᵢ·F(Yᵢ)` to the state with compensated
    /// (Kahan) summation, the compensation carried from step to step, so
    /// that round-off in `z` grows like √n. Default `true`.
    pub compensated: bool,
    /// Keep the Jacobian, and the factorisation while `h` is unchanged,
    /// across steps (for linear systems `J` is constant and the
    /// factorisation is computed once). A kept Jacobian is re-evaluated as
    /// soon as the Newton iteration contracts slower than `refresh_rate`,
    /// fails, or meets a singular matrix, so this changes cost, never the
    /// converged result. Default `true`; `false` evaluates `J` and factorises
    /// at every step.
    pub reuse_jacobian: bool,
    /// Contraction factor `‖ΔZₖ‖/‖ΔZₖ₋₁‖` above which a kept Jacobian is
    /// re-evaluated. Default 0.1.
    pub refresh_rate: f64,
    /// Within one step, how many times the Jacobian may be re-evaluated at
    /// the current iterate (the mean of the stage values `z + Zᵢ`; for
    /// DIRK tables the stage value) and the Newton matrix refactorised,
    /// when the iteration with a Jacobian of this step contracts slower
    /// than [`update_rate`](Self::update_rate) or grows. Simplified Newton
    /// keeps `J` at the start of the step, which fails when the stages move
    /// far along a strongly nonlinear flow within one step (a cloth released
    /// from rest with one step per 60 Hz frame: at rest the springs have no
    /// transverse stiffness, so `J(z)` does not see the forces the stages
    /// meet). Updating turns it into Newton's method proper on such steps;
    /// on ordinary steps the contraction is fast and nothing changes.
    /// Default 8; 0 is classical simplified Newton.
    pub jacobian_updates: usize,
    /// Contraction factor above which a Jacobian evaluated in this step is
    /// re-evaluated at the current iterate (see
    /// [`jacobian_updates`](Self::jacobian_updates)). Default 0.5.
    pub update_rate: f64,
    /// Approximate the Jacobian by forward differences (`d + 1` evaluations
    /// of `f`) when the system has none. Default `true`.
    pub finite_differences: bool,
    /// Start each step from the previous step's collocation polynomial,
    /// extrapolated (tables with distinct `cᵢ`): `Zᵢ⁽⁰⁾ = h·Σⱼ βᵢⱼ·Fⱼ` of the
    /// previous step. Otherwise (and at the first step, or when `z` is not
    /// what the previous step left) from `Z = 0` (stage by stage: from the
    /// explicit part and the previous stage's derivative). Default `true`.
    pub extrapolate: bool,
    /// Tables that are symplectic with distinct nodes (Gauss–Legendre) are
    /// solved by fixed-point iteration in their symplectic form, as IRKGL16
    /// does: coefficients `μᵢⱼ = aᵢⱼ/bⱼ` rounded with `μᵢⱼ + μⱼᵢ = 1`
    /// exactly, iteration until the stage values stop changing, the state
    /// carried in double-double (see
    /// [`collocation`](super::collocation)). Applies wherever fixed-point
    /// iteration is used ([`Solver::FixedPoint`], and [`Solver::Auto`] for
    /// systems without a Jacobian); `false` solves them like other tables.
    /// Default `true`.
    pub symplectic_form: bool,
    /// Let faer use its rayon thread pool in factorisations and solves
    /// (worthwhile only for large systems). Default `false`.
    pub parallel: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            solver: Solver::Auto,
            max_iterations: 50,
            tolerance: f64::EPSILON,
            stagnation_limit: 1e-12,
            plateau_limit: 1e-8,
            compensated: true,
            reuse_jacobian: true,
            refresh_rate: 0.1,
            jacobian_updates: 8,
            update_rate: 0.5,
            finite_differences: true,
            extrapolate: true,
            symplectic_form: true,
            parallel: false,
        }
    }
}

/// What the solver has done since the workspace was made (or
/// [`reset_stats`](super::ImplicitWorkspace::reset_stats)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Steps taken.
    pub steps: usize,
    /// Steps that failed (and left `z` unchanged).
    pub failures: usize,
    /// Newton iterations (each a solve with the factorised matrix; for DIRK
    /// tables counted per stage).
    pub newton_iterations: usize,
    /// Fixed-point iterations (per stage for DIRK tables).
    pub fixed_point_iterations: usize,
    /// Numeric LU factorisations (dense or sparse).
    pub factorizations: usize,
    /// Symbolic sparse LU factorisations (one per run and matrix shape).
    pub symbolic_factorizations: usize,
    /// Jacobian evaluations, analytic or by finite differences.
    pub jacobian_evaluations: usize,
    /// Evaluations of `f`, including those of finite differences.
    pub rhs_evaluations: usize,
}
