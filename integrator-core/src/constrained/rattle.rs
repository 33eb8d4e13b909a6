//! RATTLE in its multiplier form, for large sparse systems: the one
//! constrained Störmer–Verlet step, generic over the system
//! ([`RattleSystem`]: forces, the constraints and the products with their
//! Jacobian `G`) and over the linear algebra ([`ConstraintSolver`]: a
//! factor of `G M⁻¹ Gᵀ`, kept over several steps, and a factor of the true
//! Newton matrix for when the kept one stops contracting). Both are type
//! parameters, so a step is monomorphised: no dynamic call in its loops.
//!
//! With `q̂ = q + h M⁻¹(p + h/2·F(q))` (`F = −∇V`) and multipliers `κ` in
//! the system's own scaling (`κ ∝ h²λ`), one step is
//!
//! ```text
//! q' = q̂ − D(q)κ,  g(q') = 0                 (position solve, for κ; D = M⁻¹Gᵀ scaled)
//! p̃  = p + h/2·F(q) − M D(q)κ / h + h/2·F(q')
//! p' = p̃ − G(q')ᵀμ,  G(q') M⁻¹ p' = 0         (velocity projection, for μ)
//! ```
//!
//! **The position solve** is a simplified Newton iteration
//! `κ ← κ + A⁻¹ g(q'(κ))` with `A = G(q) M⁻¹ G(q)ᵀ` factorised at the end of
//! an earlier step (every [`Settings::refactor_every`] steps, so that most
//! steps factorise nothing), accelerated by Anderson mixing of its last
//! [`Settings::anderson`] corrections; while each residual is at most
//! [`Settings::contraction`] of the one before the factor is kept. When it
//! is not and the factor is older than the step, `A` is factorised afresh
//! at the step's own `q` (which then also serves the next steps); when that
//! does not contract either, the iteration goes on with a factor of the true
//! Jacobian `G(q') M⁻¹ G(q)ᵀ` at the current iterate (which also makes the
//! next step renew the kept factor). It starts from the linear extrapolation of
//! the last two steps' multipliers (an error of `O(h²)`), and stops when the
//! system's residual measure is at its round-off
//! ([`RattleSystem::tolerance`]); the cap [`Settings::max_iterations`] is an
//! error ([`RattleError::NotConverged`]), never a step accepted off the
//! manifold. The run that calls [`Rattle::step`] names the step and time.
//!
//! **The velocity projection** is made every step, or only where a state is
//! handed out ([`Projection::AtLeave`], SHAKE's form of RATTLE): between
//! those the steps carry the unprojected `p̃`. That is the same method: the
//! next step's constraint impulse `G(q')ᵀκ` acts along the same directions
//! `G(q')ᵀ` as the skipped projection's `G(q')ᵀμ`, so its multipliers take
//! the projection's up (`κ` absorbs `μ`) and the positions are those of
//! RATTLE with a projection after every step; the momentum handed out,
//! projected then, is RATTLE's. It halves the solves of a step. The
//! projection solves directly where the factor is of the current `q'`, and
//! otherwise runs conjugate gradients preconditioned with the kept factor,
//! to the round-off of its right-hand side, falling back to a factorisation
//! after [`Settings::max_pcg`] iterations.
//!
//! Only RATTLE (`s = 2`) has this form: its position stage depends on the
//! unknowns through `q'` alone, with the forces and constraint directions
//! taken at the known `q`. The Lobatto IIIA–IIIB pair with `s = 3` has an
//! interior stage whose forces and constraint gradients depend on the
//! unknown positions, so its Newton matrix is not `G M⁻¹ Gᵀ` of a known
//! configuration and no factor can be kept over steps; it is solved by the
//! dense stage Newton of [`ConstrainedPair`](super::ConstrainedPair)
//! (small systems), and this sparse path refuses it by its type (a
//! [`Rattle`] has no stage count).
//!
//! The cloth (`cloth` crate) is this integrator on its warp and weft length
//! constraints, with a sparse Cholesky of `G·Gᵀ` (symbolic analysis once
//! per model) and a sparse LU for the refreshes as its
//! [`ConstraintSolver`].

use std::time::Instant;

use crate::checkpoint::{CheckpointError, Decoder, Encoder};

/// What the multiplier form of RATTLE needs of a constrained system with a
/// diagonal mass matrix `M`: the operators of `G(q)` through a
/// [`Geometry`](Self::Geometry) evaluated once per configuration, in the
/// system's own scaling of the multipliers (the cloth absorbs `M⁻¹ = I/m`
/// and the factor 2 of `∇|d|²` into them). Methods are called in the inner
/// loops; implementations are monomorphised into [`Rattle`].
pub trait RattleSystem {
    /// What of `G(q)` the operators need (the cloth: one edge vector per
    /// constraint), made once and refilled by [`geometry`](Self::geometry).
    type Geometry: Geometry;
    /// `d`, the number of coordinates (the length of `q` and `p`).
    fn coordinates(&self) -> usize;
    /// `m`, the number of constraints (the length of the multipliers).
    fn constraint_count(&self) -> usize;
    /// The diagonal of `M` into `out` (length `d`).
    fn mass(&self, out: &mut [f64]);
    /// The diagonal of `M⁻¹` into `out` (length `d`), as the system rounds
    /// it (the step multiplies by these, not by `1/M`).
    fn inverse_mass(&self, out: &mut [f64]);
    /// The force `−∇V(q)` into `out`.
    fn force(&self, q: &[f64], out: &mut [f64]);
    /// A geometry in its initial state, for [`geometry`](Self::geometry)
    /// to fill.
    fn new_geometry(&self) -> Self::Geometry;
    /// Evaluate the geometry of `G` at `q`.
    fn geometry(&self, q: &[f64], geo: &mut Self::Geometry);
    /// `out = D(q)κ`, the displacement `M⁻¹G(q)ᵀκ` of the multipliers in
    /// the system's scaling (`geo` at `q`).
    fn displace(&self, geo: &Self::Geometry, kappa: &[f64], out: &mut [f64]);
    /// `out = G(q)ᵀμ` in the scaling of [`tangent`](Self::tangent): the
    /// impulse of the velocity projection.
    fn impulse(&self, geo: &Self::Geometry, mu: &[f64], out: &mut [f64]);
    /// `out = G(q) M⁻¹ p` in the system's scaling (the cloth: `G·p`); its
    /// composition with [`impulse`](Self::impulse) is the matrix the
    /// [`ConstraintSolver`] factorises.
    fn tangent(&self, geo: &Self::Geometry, p: &[f64], out: &mut [f64]);
    /// `g(q)` into `out` (`geo` at `q`), returning the residual measure
    /// the position solve stops on: the largest `|g_c|` over its round-off
    /// scale, `q_scale` being `‖q‖∞` of the step.
    fn residuals(&self, q: &[f64], geo: &Self::Geometry, q_scale: f64, out: &mut [f64]) -> f64;
    /// The residual measure at round-off: the position solve stops when
    /// [`residuals`](Self::residuals) is at most this.
    fn tolerance(&self) -> f64;
    /// The round-off of computing [`tangent`](Self::tangent) of `p` at
    /// `geo`: the conjugate gradients of the projection stop below it.
    fn projection_tolerance(&self, geo: &Self::Geometry, p: &[f64]) -> f64;
    /// How close the step came to the stability limit of the waves the
    /// constraint forces carry, from the multipliers of one half-step's
    /// impulse (the cloth: the transverse-wave number `h·ω`, stable below
    /// 2); reported in [`Stats::max_wave_number`]. 0 for a system that has
    /// no such measure.
    fn wave_number(&self, kappa: &[f64]) -> f64 {
        let _ = kappa;
        0.0
    }
}

/// The geometry of a [`RattleSystem`] as numbers, for a checkpoint: it is
/// of the state the last step ended with, and is saved and restored
/// exactly.
pub trait Geometry {
    fn values(&self) -> &[f64];
    fn values_mut(&mut self) -> &mut [f64];
}

/// One vector of `N` numbers per constraint (the cloth's edge vectors).
/// A dense `G`, row-major.
impl Geometry for Vec<f64> {
    fn values(&self) -> &[f64] {
        self
    }
    fn values_mut(&mut self) -> &mut [f64] {
        self
    }
}

impl<const N: usize> Geometry for Vec<[f64; N]> {
    fn values(&self) -> &[f64] {
        self.as_flattened()
    }
    fn values_mut(&mut self) -> &mut [f64] {
        self.as_flattened_mut()
    }
}

/// The linear algebra of [`Rattle`]: factors of the matrix
/// `A = G(q) M⁻¹ G(q)ᵀ` (in the system's scaling; symmetric positive
/// definite while the constraints are independent) and of the true Newton
/// matrix `J = G(q') M⁻¹ G(q)ᵀ`. A sparse system keeps its symbolic
/// analyses from one factorisation to the next; all storage is made once.
pub trait ConstraintSolver<Sys: RattleSystem> {
    /// Factorise `A` at the configuration of `geo`; `Err` when it is not
    /// (numerically) positive definite.
    fn factorize(&mut self, sys: &Sys, geo: &Sys::Geometry) -> Result<(), Singular>;
    /// `rhs ← A⁻¹ rhs` with the last factor of `A`.
    fn solve(&mut self, rhs: &mut [f64]);
    /// Factorise `J = G(q₁) M⁻¹ G(q)ᵀ` (`geo` at `q`, `geo1` at `q₁`);
    /// `Ok(true)` when its symbolic analysis was made now (counted in
    /// [`Stats::symbolic_lu`]), `Err` when it is singular.
    fn factorize_jacobian(
        &mut self,
        sys: &Sys,
        geo: &Sys::Geometry,
        geo1: &Sys::Geometry,
    ) -> Result<bool, Singular>;
    /// `rhs ← J⁻¹ rhs` with the last factor of `J`.
    fn solve_jacobian(&mut self, rhs: &mut [f64]);
}

/// The kept factor of `A` as numbers, for a checkpoint: the factor is of
/// the configuration of its last renewal, not of the current one, so it is
/// saved rather than recomputed.
pub trait KeptFactor {
    fn factor_values(&self) -> &[f64];
    fn factor_values_mut(&mut self) -> &mut [f64];
}

/// A factorisation met a matrix that is singular (or not positive definite)
/// to working precision.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Singular;

/// The settings of [`Rattle`]'s solves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Simplified Newton iterations of one position solve before the step
    /// fails.
    pub max_iterations: usize,
    /// Leave the kept factor when an iteration shrinks the residual by less
    /// than this factor: for a factor of `A` at the step's own `q` when the
    /// kept one is older than the step, else (or when that one does not
    /// contract either) for the true Jacobian.
    pub contraction: f64,
    /// Anderson acceleration of the simplified Newton iteration with this
    /// many of its last corrections (0: the plain iteration). The
    /// iteration is a fixed-point map `κ ↦ κ + A⁻¹g(q'(κ))` that converges
    /// linearly, held back by a few slow modes where the kept `A` differs
    /// from the true Jacobian; Anderson's mixing (Walker & Ni 2011, "type
    /// II") takes the combination of the last corrections with the least
    /// `ℓ₂` norm, a GMRES-like step on those modes, at a few dot products
    /// per iteration. The solve still stops only when the residual is at
    /// round-off, so the step is the same to round-off. Reset at every
    /// change of matrix and never mixed into the true Jacobian's Newton
    /// steps, which converge quadratically.
    pub anderson: usize,
    /// Factorise `A` afresh every this many steps (1: every step; 0: only
    /// when the conjugate gradients of a projection fail or a position
    /// solve stops contracting), and after every step whose position solve
    /// had to go to the true Jacobian (the configuration turns too fast for
    /// a factor of `A`).
    pub refactor_every: usize,
    /// Conjugate-gradient iterations of one velocity projection before it
    /// falls back to a factorisation.
    pub max_pcg: usize,
    /// When the velocity projection is made.
    pub projection: Projection,
}

/// When [`Rattle`] projects the momentum onto the tangent space.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Projection {
    /// After every step: every state a step leaves is RATTLE's.
    EveryStep,
    /// Only in [`Rattle::leave`], where a state is handed out; the steps in
    /// between carry the unprojected momentum (SHAKE's form, the same
    /// positions and the same momentum where it is handed out: see the
    /// module documentation).
    AtLeave,
}

/// Where the stepping time went (s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    /// The forces `−∇V`.
    pub forces: f64,
    /// The geometry, residuals, products with `G` and `Gᵀ`, and the vector
    /// updates.
    pub constraints: f64,
    /// Assembling and factorising `A` and `J`.
    pub factorize: f64,
    /// Solves with the factors (and the projections' conjugate gradients).
    pub solve: f64,
}

/// What the constraint solver did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    pub steps: usize,
    /// Simplified Newton iterations of the position solves, in all.
    pub iterations: usize,
    /// The most iterations one position solve took.
    pub max_iterations: usize,
    /// Factorisations of `A` (one at the start, one every
    /// [`Settings::refactor_every`] steps, one where a position solve
    /// renewed an older factor at the step's `q`, and one where a
    /// projection fell back to it).
    pub factorizations: usize,
    /// Factorisations of the true Jacobian `J` (the position solve's
    /// refreshes), and their symbolic analyses (0 or 1).
    pub lu_factorizations: usize,
    pub symbolic_lu: usize,
    /// Preconditioned conjugate-gradient iterations of the velocity
    /// projections that reused an earlier factor, and the projections that
    /// fell back to a factorisation.
    pub pcg_iterations: usize,
    pub pcg_failures: usize,
    /// The largest residual measure a step ended with (at most
    /// [`RattleSystem::tolerance`]).
    pub max_residual: f64,
    /// The largest [`RattleSystem::wave_number`] a step ended with.
    pub max_wave_number: f64,
    pub seconds: Timing,
}

impl Stats {
    /// Position iterations per step.
    pub fn iterations_per_step(&self) -> f64 {
        self.iterations as f64 / self.steps.max(1) as f64
    }
}

/// Why a step failed (the run adds the step and time).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RattleError {
    #[error(
        "the position solve did not converge in {iterations} iterations: the residual measure is {residual:e}, the tolerance {tolerance:e}"
    )]
    NotConverged {
        iterations: usize,
        residual: f64,
        tolerance: f64,
    },
    /// `A` was not positive definite in the named phase (`"position
    /// solve"` or `"velocity projection"`).
    #[error("G M⁻¹ Gᵀ is not positive definite in the {phase}: the constraints became dependent")]
    NotPositive { phase: &'static str },
    #[error("the position solve's Jacobian G(q') M⁻¹ G(q)ᵀ is singular")]
    Singular,
    #[error("the position solve diverged: the residual measure is {residual:e}")]
    Diverged { residual: f64 },
}

/// Anderson mixing ("type II", Walker & Ni 2011) of a fixed-point
/// iteration `x ↦ x + f(x)` with the last `depth` corrections: with
/// `ΔX`, `ΔF` the differences of the last iterates and corrections,
/// `γ = argmin ‖f − ΔF·γ‖₂` and `x ← x + f − (ΔX + ΔF)·γ`. The history
/// is a ring of `depth` columns made once; its Gram matrix `ΔFᵀΔF` is
/// updated by one column per iteration. Where that matrix is numerically
/// singular (the corrections at round-off, or dependent), the step is the
/// plain one and the history starts again.
struct Anderson {
    depth: usize,
    n: usize,
    dx: Vec<f64>,
    df: Vec<f64>,
    x_prev: Vec<f64>,
    f_prev: Vec<f64>,
    /// `ΔFᵀΔF` (depth × depth, row-major) and the small system's storage
    /// (depth × (depth + 1)).
    gram: Vec<f64>,
    system: Vec<f64>,
    gamma: Vec<f64>,
    /// Whether `x_prev`, `f_prev` hold the last iterate, and the columns
    /// pushed since the last reset.
    primed: bool,
    pushed: usize,
}

impl Anderson {
    fn new(depth: usize, n: usize) -> Anderson {
        let len = if depth > 0 { n } else { 0 };
        Anderson {
            depth,
            n,
            dx: vec![0.0; depth * n],
            df: vec![0.0; depth * n],
            x_prev: vec![0.0; len],
            f_prev: vec![0.0; len],
            gram: vec![0.0; depth * depth],
            system: vec![0.0; depth * (depth + 1)],
            gamma: vec![0.0; depth],
            primed: false,
            pushed: 0,
        }
    }

    /// Forget the history (a new solve, or a new matrix).
    fn reset(&mut self) {
        self.primed = false;
        self.pushed = 0;
    }

    /// `x ← x + f`, mixed with the history.
    fn update(&mut self, x: &mut [f64], f: &[f64]) {
        let (m, n) = (self.depth, self.n);
        if m == 0 {
            for (xi, fi) in x.iter_mut().zip(f) {
                *xi += fi;
            }
            return;
        }
        if self.primed {
            let slot = self.pushed % m;
            let cols = slot * n..(slot + 1) * n;
            for (((dx, df), (xi, fi)), (xp, fp)) in self.dx[cols.clone()]
                .iter_mut()
                .zip(self.df[cols.clone()].iter_mut())
                .zip(x.iter().zip(f))
                .zip(self.x_prev.iter().zip(&self.f_prev))
            {
                *dx = xi - xp;
                *df = fi - fp;
            }
            self.pushed += 1;
            let k = self.pushed.min(m);
            for a in 0..k {
                let v = dot(&self.df[cols.clone()], &self.df[a * n..(a + 1) * n]);
                self.gram[slot * m + a] = v;
                self.gram[a * m + slot] = v;
            }
        }
        self.x_prev.copy_from_slice(x);
        self.f_prev.copy_from_slice(f);
        self.primed = true;
        for (xi, fi) in x.iter_mut().zip(f) {
            *xi += fi;
        }
        let k = self.pushed.min(m);
        if k == 0 {
            return;
        }
        // [ΔFᵀΔF | ΔFᵀf], solved by Gaussian elimination with partial
        // pivoting.
        let w = k + 1;
        let sys = &mut self.system[..k * w];
        for a in 0..k {
            sys[a * w..a * w + k].copy_from_slice(&self.gram[a * m..a * m + k]);
            sys[a * w + k] = dot(&self.df[a * n..(a + 1) * n], f);
        }
        let scale = (0..k).map(|a| sys[a * w + a]).fold(0.0f64, f64::max);
        for c in 0..k {
            let pivot = (c..k)
                .max_by(|&i, &j| sys[i * w + c].abs().total_cmp(&sys[j * w + c].abs()))
                .unwrap_or(c);
            if pivot != c {
                for j in 0..w {
                    sys.swap(c * w + j, pivot * w + j);
                }
            }
            let p = sys[c * w + c];
            // Singular to working precision (or NaN): the plain step.
            if p.abs() <= 1e-13 * scale || !p.is_finite() {
                self.pushed = 0;
                return;
            }
            for r in c + 1..k {
                let factor = sys[r * w + c] / p;
                for j in c..w {
                    sys[r * w + j] -= factor * sys[c * w + j];
                }
            }
        }
        for c in (0..k).rev() {
            let mut v = sys[c * w + k];
            for j in c + 1..k {
                v -= sys[c * w + j] * self.gamma[j];
            }
            self.gamma[c] = v / sys[c * w + c];
        }
        for a in 0..k {
            let g = self.gamma[a];
            let cols = a * n..(a + 1) * n;
            for ((xi, dx), df) in x.iter_mut().zip(&self.dx[cols.clone()]).zip(&self.df[cols]) {
                *xi -= g * (dx + df);
            }
        }
    }
}

/// `x·y` summed in four interleaved partial sums (a plain sum waits on
/// each addition; the order is fixed, so the bits are too).
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let (xc, xr) = x.as_chunks::<4>();
    let (yc, yr) = y.as_chunks::<4>();
    for (a, b) in xc.iter().zip(yc) {
        for k in 0..4 {
            acc[k] += a[k] * b[k];
        }
    }
    let mut tail = 0.0;
    for (a, b) in xr.iter().zip(yr) {
        tail += a * b;
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// `‖x‖∞`.
fn inf_norm(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// The carried data of a [`Rattle`] at one moment ([`Rattle::mark`],
/// [`Rattle::rewind`]): the fields a checkpoint holds
/// ([`Rattle::save`]), less the statistics; a field added there belongs
/// here too (the cloth's `variable_step::a_frame_tried_again_*` test
/// compares the bits of a try made from a mark with a first try).
#[derive(Clone, Debug, Default)]
pub struct Mark {
    lambda: Vec<f64>,
    lambda_prev: Vec<f64>,
    solved: usize,
    lambda_h: f64,
    since_factor: usize,
    stale: bool,
    last_wave_number: f64,
    force: Vec<f64>,
    cached_q: Vec<f64>,
    valid: bool,
    geometry: Vec<f64>,
    factor: Vec<f64>,
    p_carried: Vec<f64>,
    p_out: Vec<f64>,
    resume: bool,
    carried: bool,
    set: bool,
}

/// RATTLE on a [`RattleSystem`] with a [`ConstraintSolver`]: the step's
/// state carried from one step to the next (warm-start multipliers, the
/// kept factor and its age, the force and geometry at the current `q`, the
/// carried momentum) and the statistics.
pub struct Rattle<G, Lin> {
    lin: Lin,
    settings: Settings,
    n: usize,
    mass: Vec<f64>,
    minv: Vec<f64>,
    /// `M/h` for the `h` in `mass_h` (a division per coordinate saved per
    /// step; the same bits as dividing in the loop).
    mass_over_h: Vec<f64>,
    mass_h: f64,
    /// The geometry at the step's start `q`, and at the iterate `q'`.
    d: G,
    d1: G,
    /// Multipliers `κ` (warm start), with the `h` they were made for.
    lambda: Vec<f64>,
    /// The previous step's multipliers, and how many steps in a row were
    /// solved since the last restart (two are needed to extrapolate).
    lambda_prev: Vec<f64>,
    solved: usize,
    lambda_h: f64,
    g: Vec<f64>,
    delta: Vec<f64>,
    /// The velocity projection's right-hand side and the conjugate
    /// gradients' vectors.
    b: Vec<f64>,
    r: Vec<f64>,
    z: Vec<f64>,
    pdir: Vec<f64>,
    ap: Vec<f64>,
    /// The Anderson mixing of the position solve.
    mixing: Anderson,
    /// Steps since the last factorisation of `A`.
    since_factor: usize,
    /// Whether the last position solve refreshed the true Jacobian.
    stale: bool,
    /// The wave number of the last step solved.
    last_wave_number: f64,
    /// The force at `cached_q`; `valid`: `cached_q`, `force`, `d` and the
    /// kept factor belong to the state the last step ended with.
    force: Vec<f64>,
    cached_q: Vec<f64>,
    valid: bool,
    qhat: Vec<f64>,
    q1: Vec<f64>,
    w: Vec<f64>,
    phalf: Vec<f64>,
    /// At a `leave`: the unprojected momentum the steps carry on with, and
    /// the projected one handed out (`resume`: both belong to the state the
    /// last `leave` handed out).
    p_carried: Vec<f64>,
    p_out: Vec<f64>,
    resume: bool,
    /// Whether the step being taken started from an unprojected momentum,
    /// so that its multipliers carry the skipped projection's too.
    carried: bool,
    stats: Stats,
}

impl<G, Lin> Rattle<G, Lin> {
    /// The integrator for `sys` with the linear algebra `lin`, at step `h`
    /// (the scale of the first warm start; any later `h` rescales it).
    pub fn new<Sys: RattleSystem<Geometry = G>>(
        sys: &Sys,
        lin: Lin,
        h: f64,
        settings: Settings,
    ) -> Self
    where
        Lin: ConstraintSolver<Sys>,
    {
        let (n, nc) = (sys.coordinates(), sys.constraint_count());
        let mut mass = vec![0.0; n];
        let mut minv = vec![0.0; n];
        sys.mass(&mut mass);
        sys.inverse_mass(&mut minv);
        Rattle {
            lin,
            settings,
            n,
            mass_over_h: mass.iter().map(|m| m / h).collect(),
            mass_h: h,
            mass,
            minv,
            d: sys.new_geometry(),
            d1: sys.new_geometry(),
            lambda: vec![0.0; nc],
            lambda_prev: vec![0.0; nc],
            solved: 0,
            lambda_h: h,
            g: vec![0.0; nc],
            delta: vec![0.0; nc],
            b: vec![0.0; nc],
            r: vec![0.0; nc],
            z: vec![0.0; nc],
            pdir: vec![0.0; nc],
            ap: vec![0.0; nc],
            mixing: Anderson::new(settings.anderson, nc),
            since_factor: 0,
            stale: false,
            last_wave_number: 0.0,
            force: vec![0.0; n],
            cached_q: vec![0.0; n],
            valid: false,
            qhat: vec![0.0; n],
            q1: vec![0.0; n],
            w: vec![0.0; n],
            phalf: vec![0.0; n],
            p_carried: vec![0.0; n],
            p_out: vec![0.0; n],
            resume: false,
            carried: false,
            stats: Stats::default(),
        }
    }

    /// What the solver did so far.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// The multipliers `κ` of the last position solve (the system's
    /// scaling).
    pub fn multipliers(&self) -> &[f64] {
        &self.lambda
    }

    /// The multipliers `μ` of the last velocity projection (in the scaling
    /// of [`RattleSystem::impulse`]), after a step with
    /// [`Projection::EveryStep`] or a [`leave`](Self::leave) that projected.
    pub fn projection_multipliers(&self) -> &[f64] {
        &self.delta
    }

    /// The wave number of the last step solved (0 before the first): a
    /// failed step reports it, as the state the failure came from.
    pub fn last_wave_number(&self) -> f64 {
        self.last_wave_number
    }

    /// Forget the warm start: the next step starts its position solve from
    /// zero multipliers, and prepares its force, geometry and factor
    /// afresh. For a caller that goes back to an earlier state after a
    /// failed step, whose last iterate (diverged, or stopped at the cap) is
    /// no guess for the next solve and that keeps no [`Mark`] to go back
    /// to (the cloth's variable step with `RattleSettings::rewind` off,
    /// which then integrates the frame again with shorter steps).
    pub fn forget_warm_start(&mut self) {
        self.lambda.fill(0.0);
        self.lambda_prev.fill(0.0);
        self.solved = 0;
        self.valid = false;
    }

    /// The force, geometry and factor at `q` (the start of a run, or after
    /// the caller restored a state).
    fn prepare<Sys: RattleSystem<Geometry = G>>(
        &mut self,
        sys: &Sys,
        q: &[f64],
    ) -> Result<(), RattleError>
    where
        Lin: ConstraintSolver<Sys>,
    {
        let t0 = Instant::now();
        sys.force(q, &mut self.force);
        let t1 = Instant::now();
        sys.geometry(q, &mut self.d);
        let t2 = Instant::now();
        let factored = self.lin.factorize(sys, &self.d);
        let t3 = Instant::now();
        let s = &mut self.stats.seconds;
        s.forces += (t1 - t0).as_secs_f64();
        s.constraints += (t2 - t1).as_secs_f64();
        s.factorize += (t3 - t2).as_secs_f64();
        self.stats.factorizations += 1;
        factored.map_err(|_| RattleError::NotPositive {
            phase: "position solve",
        })?;
        self.cached_q.copy_from_slice(q);
        self.valid = true;
        Ok(())
    }

    /// The position solve: `q1 = q̂ − D(q)κ` with `g(q1) = 0`; leaves
    /// `w = D(q)κ` and the geometry at `q1` in `d1`.
    fn position_solve<Sys: RattleSystem<Geometry = G>>(
        &mut self,
        sys: &Sys,
        q_scale: f64,
    ) -> Result<(), RattleError>
    where
        Lin: ConstraintSolver<Sys>,
    {
        let tolerance = sys.tolerance();
        let mut previous = f64::INFINITY;
        let mut iterations = 0;
        // Whether the iteration runs on the factor of the true Jacobian,
        // and whether it renewed the factor of `A` at this step's `q`.
        let mut exact = false;
        let mut renewed = false;
        self.mixing.reset();
        loop {
            let t0 = Instant::now();
            sys.displace(&self.d, &self.lambda, &mut self.w);
            for ((x, qh), w) in self.q1.iter_mut().zip(&self.qhat).zip(&self.w) {
                *x = qh - w;
            }
            sys.geometry(&self.q1, &mut self.d1);
            let residual = sys.residuals(&self.q1, &self.d1, q_scale, &mut self.g);
            self.stats.seconds.constraints += t0.elapsed().as_secs_f64();
            if residual <= tolerance {
                self.stats.iterations += iterations;
                self.stats.max_iterations = self.stats.max_iterations.max(iterations);
                self.stats.max_residual = self.stats.max_residual.max(residual);
                return Ok(());
            }
            if !residual.is_finite() {
                return Err(RattleError::Diverged { residual });
            }
            if iterations == self.settings.max_iterations {
                return Err(RattleError::NotConverged {
                    iterations,
                    residual,
                    tolerance,
                });
            }
            if residual > self.settings.contraction * previous {
                // Not contracting: the kept factor is of a configuration
                // too far from this step's. Renew it at the step's `q`
                // first (a Cholesky, about a third of an LU here, and it
                // serves the next steps too), and only when that is not
                // enough either (or the factor was already of this `q`)
                // go to the true Jacobian. Measured on the paper's 64²
                // sheet over 600 frames: 769 LU refreshes became 0, with
                // the same steps and energy (docs in the cloth stepper).
                let t = Instant::now();
                if !exact && self.since_factor > 0 && !renewed {
                    let factored = self.lin.factorize(sys, &self.d);
                    self.stats.seconds.factorize += t.elapsed().as_secs_f64();
                    self.stats.factorizations += 1;
                    self.since_factor = 0;
                    renewed = true;
                    factored.map_err(|_| RattleError::NotPositive {
                        phase: "position solve",
                    })?;
                } else {
                    let refreshed = self.lin.factorize_jacobian(sys, &self.d, &self.d1);
                    self.stats.seconds.factorize += t.elapsed().as_secs_f64();
                    self.stats.lu_factorizations += 1;
                    self.stats.symbolic_lu += usize::from(matches!(refreshed, Ok(true)));
                    refreshed.map_err(|_| RattleError::Singular)?;
                    exact = true;
                    self.stale = true;
                }
                self.mixing.reset();
            }
            previous = residual;
            let t = Instant::now();
            self.delta.copy_from_slice(&self.g);
            if exact {
                self.lin.solve_jacobian(&mut self.delta);
            } else {
                self.lin.solve(&mut self.delta);
            }
            let t1 = Instant::now();
            if exact {
                for (l, dl) in self.lambda.iter_mut().zip(&self.delta) {
                    *l += dl;
                }
            } else {
                self.mixing.update(&mut self.lambda, &self.delta);
            }
            let t2 = Instant::now();
            self.stats.seconds.solve += (t1 - t).as_secs_f64();
            self.stats.seconds.constraints += (t2 - t1).as_secs_f64();
            iterations += 1;
        }
    }

    /// The velocity projection's `A(q')·μ = b` (`b` in `self.b`, `μ` left in
    /// `self.delta`) by conjugate gradients preconditioned with the factor
    /// of an earlier configuration, instead of a new factorisation.
    /// Converged when the residual, which is `G(q')M⁻¹p'` itself, is at the
    /// round-off of computing `b` ([`RattleSystem::projection_tolerance`]).
    /// `false` (and nothing kept) when it is not within
    /// [`Settings::max_pcg`] iterations: the caller factorises.
    fn pcg<Sys: RattleSystem<Geometry = G>>(&mut self, sys: &Sys) -> bool
    where
        Lin: ConstraintSolver<Sys>,
    {
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let tol = sys.projection_tolerance(&self.d, &self.phalf);
        if inf_norm(&self.b) <= tol {
            self.delta.fill(0.0);
            return true;
        }
        self.delta.fill(0.0);
        self.r.copy_from_slice(&self.b);
        self.z.copy_from_slice(&self.r);
        self.lin.solve(&mut self.z);
        self.pdir.copy_from_slice(&self.z);
        let mut rz = dot(&self.r, &self.z);
        for it in 1..=self.settings.max_pcg {
            sys.impulse(&self.d, &self.pdir, &mut self.w);
            sys.tangent(&self.d, &self.w, &mut self.ap);
            let alpha = rz / dot(&self.pdir, &self.ap);
            for ((x, r), (pd, ap)) in self
                .delta
                .iter_mut()
                .zip(self.r.iter_mut())
                .zip(self.pdir.iter().zip(&self.ap))
            {
                *x += alpha * pd;
                *r -= alpha * ap;
            }
            if inf_norm(&self.r) <= tol {
                self.stats.pcg_iterations += it;
                return true;
            }
            self.z.copy_from_slice(&self.r);
            self.lin.solve(&mut self.z);
            let rz_new = dot(&self.r, &self.z);
            let beta = rz_new / rz;
            rz = rz_new;
            for (pd, z) in self.pdir.iter_mut().zip(&self.z) {
                *pd = z + beta * *pd;
            }
        }
        self.stats.pcg_failures += 1;
        false
    }

    /// One step of size `h` from `z = [q; p]` in place. With
    /// [`Projection::AtLeave`] the momentum it leaves is the unprojected
    /// `p̃` (see [`leave`](Self::leave)). On error `z` may be anything; the
    /// caller restores a state it kept, and the next step notices the
    /// change of `q` and starts afresh.
    pub fn step<Sys: RattleSystem<Geometry = G>>(
        &mut self,
        sys: &Sys,
        h: f64,
        z: &mut [f64],
    ) -> Result<(), RattleError>
    where
        Lin: ConstraintSolver<Sys>,
    {
        let n = self.n;
        let (q, p) = z.split_at_mut(n);
        if !self.valid || self.cached_q != *q {
            self.solved = 0;
            self.carried = false;
            self.prepare(sys, q)?;
        }
        self.valid = false;
        // Multipliers that also take up the skipped projection's are two
        // half-steps' impulses: the wave number is measured by half of them.
        let impulses: f64 = if self.carried { 2.0 } else { 1.0 };
        // Warm start: κ scales with h².
        if self.lambda_h != h {
            let s = (h / self.lambda_h).powi(2);
            self.lambda.iter_mut().for_each(|l| *l *= s);
            self.lambda_prev.iter_mut().for_each(|l| *l *= s);
            self.lambda_h = h;
            // The extrapolation below assumes the last two multipliers
            // were a step of this size apart: after a change of `h` (a
            // frame of the variable step with another count) it waits for
            // two steps of the new size. Extrapolated across the change,
            // the position solve at the 12² flat sheet's whip converged
            // to another root (an edge turning by 69° in one step where
            // the root found without it turns by 41°, h·ω 2.15 against
            // 0.96; docs/results/cloth-inextensible.md).
            self.solved = 0;
        }
        // The multipliers are smooth in time: start from the linear
        // extrapolation of the last two steps' (the last one's after a
        // restart), an error of O(h²) instead of O(h).
        if self.solved >= 2 {
            for (l, lp) in self.lambda.iter_mut().zip(self.lambda_prev.iter_mut()) {
                let last = *l;
                *l = 2.0 * last - *lp;
                *lp = last;
            }
        } else {
            self.lambda_prev.copy_from_slice(&self.lambda);
        }
        let t0 = Instant::now();
        let half = 0.5 * h;
        for ((((ph, qh), (&pk, &fk)), &qk), &wk) in self
            .phalf
            .iter_mut()
            .zip(self.qhat.iter_mut())
            .zip(p.iter().zip(&self.force))
            .zip(q.iter())
            .zip(&self.minv)
        {
            *ph = pk + half * fk;
            *qh = qk + h * wk * *ph;
        }
        self.stats.seconds.constraints += t0.elapsed().as_secs_f64();
        let q_scale = inf_norm(q).max(inf_norm(&self.qhat));
        self.position_solve(sys, q_scale)?;
        let t_wave = Instant::now();
        self.last_wave_number = sys.wave_number(&self.lambda) / impulses.sqrt();
        self.stats.max_wave_number = self.stats.max_wave_number.max(self.last_wave_number);
        self.stats.seconds.constraints += t_wave.elapsed().as_secs_f64();
        // p½ = p + h/2·F(q) − (M/h)·D(q)κ; then the force at q'.
        let t1 = Instant::now();
        if self.mass_h != h {
            for (s, m) in self.mass_over_h.iter_mut().zip(&self.mass) {
                *s = m / h;
            }
            self.mass_h = h;
        }
        for ((ph, w), s) in self.phalf.iter_mut().zip(&self.w).zip(&self.mass_over_h) {
            *ph -= s * w;
        }
        let t2 = Instant::now();
        sys.force(&self.q1, &mut self.force);
        let t3 = Instant::now();
        for (ph, f) in self.phalf.iter_mut().zip(&self.force) {
            *ph += half * f;
        }
        // No velocity projection here (SHAKE's form of the same steps):
        // p̃ goes on to the next step, whose multipliers take up the
        // projection's. Every `refactor_every` steps the factor of A(q') is
        // renewed for the next position solves.
        std::mem::swap(&mut self.d, &mut self.d1);
        p.copy_from_slice(&self.phalf);
        q.copy_from_slice(&self.q1);
        self.cached_q.copy_from_slice(&self.q1);
        let t4 = Instant::now();
        // Renewed early when this step's solve had to leave the factor for
        // the true Jacobian: the configuration turns too fast for it.
        let due = (self.settings.refactor_every != 0
            && self.since_factor + 1 >= self.settings.refactor_every)
            || std::mem::take(&mut self.stale);
        if due {
            let factored = self.lin.factorize(sys, &self.d);
            self.stats.factorizations += 1;
            self.since_factor = 0;
            factored.map_err(|_| RattleError::NotPositive {
                phase: "position solve",
            })?;
        } else {
            self.since_factor += 1;
        }
        let t5 = Instant::now();
        let s = &mut self.stats.seconds;
        s.constraints += (t2 - t1).as_secs_f64() + (t4 - t3).as_secs_f64();
        s.forces += (t3 - t2).as_secs_f64();
        s.factorize += (t5 - t4).as_secs_f64();
        self.stats.steps += 1;
        self.solved += 1;
        self.carried = true;
        self.valid = true;
        if self.settings.projection == Projection::EveryStep {
            self.project(sys, z)?;
            self.carried = false;
        }
        Ok(())
    }

    /// The velocity projection of the state the steps left in `z`:
    /// `p' = p̃ − G(q')ᵀμ` with `A(q')·μ = G(q')M⁻¹p̃`, directly where the
    /// factor is of this `q'`, else by conjugate gradients preconditioned
    /// with the older factor, falling back to a new factorisation (which
    /// then serves the next position solves too).
    fn project<Sys: RattleSystem<Geometry = G>>(
        &mut self,
        sys: &Sys,
        z: &mut [f64],
    ) -> Result<(), RattleError>
    where
        Lin: ConstraintSolver<Sys>,
    {
        let (_, p) = z.split_at_mut(self.n);
        self.phalf.copy_from_slice(p);
        let t4 = Instant::now();
        sys.tangent(&self.d, &self.phalf, &mut self.b);
        let t5 = Instant::now();
        let mut factorizing = 0.0;
        if self.since_factor == 0 {
            self.delta.copy_from_slice(&self.b);
            self.lin.solve(&mut self.delta);
        } else if !self.pcg(sys) {
            let t6 = Instant::now();
            let factored = self.lin.factorize(sys, &self.d);
            factorizing = t6.elapsed().as_secs_f64();
            self.stats.factorizations += 1;
            self.since_factor = 0;
            factored.map_err(|_| RattleError::NotPositive {
                phase: "velocity projection",
            })?;
            self.delta.copy_from_slice(&self.b);
            self.lin.solve(&mut self.delta);
        }
        let t7 = Instant::now();
        sys.impulse(&self.d, &self.delta, &mut self.w);
        for ((pk, ph), w) in p.iter_mut().zip(&self.phalf).zip(&self.w) {
            *pk = ph - w;
        }
        let t8 = Instant::now();
        let s = &mut self.stats.seconds;
        s.constraints += (t5 - t4).as_secs_f64() + (t8 - t7).as_secs_f64();
        // Conjugate gradients count as solves; a factorisation as
        // factorisation, its solve as a solve.
        s.factorize += factorizing;
        s.solve += (t7 - t5).as_secs_f64() - factorizing;
        Ok(())
    }

    /// Before the steps that follow a [`leave`](Self::leave): carry on from
    /// the unprojected momentum it kept, where `z` is still the state it
    /// handed out (otherwise the steps start from `z` as it is).
    pub fn enter(&mut self, z: &mut [f64]) {
        let (q, p) = z.split_at_mut(self.n);
        if self.resume && self.valid && self.cached_q == *q && self.p_out == *p {
            p.copy_from_slice(&self.p_carried);
        } else {
            self.carried = false;
        }
        self.resume = false;
    }

    /// Hand out `[q; p]` with `p` projected onto the tangent space
    /// (`G(q)·M⁻¹·p = 0`), as RATTLE's own step ends, keeping the carried
    /// momentum for [`enter`](Self::enter). Nothing to do after a projected
    /// step. The positions do not depend on it: the next step's
    /// multipliers would take it up.
    pub fn leave<Sys: RattleSystem<Geometry = G>>(&mut self, sys: &Sys, z: &mut [f64])
    where
        Lin: ConstraintSolver<Sys>,
    {
        if !(self.valid && self.carried) {
            return;
        }
        self.p_carried.copy_from_slice(&z[self.n..]);
        match self.project(sys, z) {
            Ok(()) => {
                self.p_out.copy_from_slice(&z[self.n..]);
                self.resume = true;
            }
            Err(_) => {
                // Not positive definite at the end of a step that solved:
                // leave p̃ as it is; the next step will fail on the same
                // matrix and report it with its step and time.
                z[self.n..].copy_from_slice(&self.p_carried);
                self.valid = false;
            }
        }
    }

    /// Everything the next steps read before writing: the carried p̃ and
    /// the momentum handed out (to recognise the state in `enter`), the
    /// warm-start multipliers and their extrapolation count, the kept
    /// factor (of the configuration of its last renewal, not of the current
    /// one) and the steps since it, the force and geometry at `q`, the
    /// flags, and the statistics; fields named `rattle.*` for the errors of
    /// [`restore`](Self::restore).
    pub fn save(&self, e: &mut Encoder)
    where
        G: Geometry,
        Lin: KeptFactor,
    {
        e.f64s(&self.lambda)
            .f64s(&self.lambda_prev)
            .usize(self.solved)
            .f64(self.lambda_h)
            .usize(self.since_factor)
            .bool(self.stale)
            .f64(self.last_wave_number)
            .f64s(&self.force)
            .f64s(&self.cached_q)
            .bool(self.valid)
            .f64s(self.d.values())
            .f64s(self.lin.factor_values())
            .f64s(&self.p_carried)
            .f64s(&self.p_out)
            .bool(self.resume)
            .bool(self.carried);
        let st = &self.stats;
        e.usize(st.steps)
            .usize(st.iterations)
            .usize(st.max_iterations)
            .usize(st.factorizations)
            .usize(st.lu_factorizations)
            .usize(st.symbolic_lu)
            .usize(st.pcg_iterations)
            .usize(st.pcg_failures)
            .f64(st.max_residual)
            .f64(st.max_wave_number)
            .f64(st.seconds.forces)
            .f64(st.seconds.constraints)
            .f64(st.seconds.factorize)
            .f64(st.seconds.solve);
    }

    /// Keep in `m` what [`save`](Self::save) writes less the statistics:
    /// everything the next steps read before writing. A caller that may
    /// integrate the same stretch again from here (the cloth's variable
    /// step, which tries several counts of steps for one frame) goes back
    /// with [`rewind`](Self::rewind) instead of starting afresh, so that a
    /// further try costs no factorisation and no cold start, and ends on
    /// the bits a first try with the same steps would have. The buffers in
    /// `m` are reused: after the first mark no allocation.
    pub fn mark(&self, m: &mut Mark)
    where
        G: Geometry,
        Lin: KeptFactor,
    {
        fn copy(to: &mut Vec<f64>, from: &[f64]) {
            to.clear();
            to.extend_from_slice(from);
        }
        copy(&mut m.lambda, &self.lambda);
        copy(&mut m.lambda_prev, &self.lambda_prev);
        m.solved = self.solved;
        m.lambda_h = self.lambda_h;
        m.since_factor = self.since_factor;
        m.stale = self.stale;
        m.last_wave_number = self.last_wave_number;
        copy(&mut m.force, &self.force);
        copy(&mut m.cached_q, &self.cached_q);
        m.valid = self.valid;
        copy(&mut m.geometry, self.d.values());
        copy(&mut m.factor, self.lin.factor_values());
        copy(&mut m.p_carried, &self.p_carried);
        copy(&mut m.p_out, &self.p_out);
        m.resume = self.resume;
        m.carried = self.carried;
        m.set = true;
    }

    /// Go back to what [`mark`](Self::mark) kept in `m` (the statistics go
    /// on counting). False, and nothing changed, when `m` holds no mark of
    /// an integrator of this size.
    pub fn rewind(&mut self, m: &Mark) -> bool
    where
        G: Geometry,
        Lin: KeptFactor,
    {
        if !m.set
            || m.lambda.len() != self.lambda.len()
            || m.force.len() != self.force.len()
            || m.geometry.len() != self.d.values().len()
            || m.factor.len() != self.lin.factor_values().len()
        {
            return false;
        }
        self.lambda.copy_from_slice(&m.lambda);
        self.lambda_prev.copy_from_slice(&m.lambda_prev);
        self.solved = m.solved;
        self.lambda_h = m.lambda_h;
        self.since_factor = m.since_factor;
        self.stale = m.stale;
        self.last_wave_number = m.last_wave_number;
        self.force.copy_from_slice(&m.force);
        self.cached_q.copy_from_slice(&m.cached_q);
        self.valid = m.valid;
        self.d.values_mut().copy_from_slice(&m.geometry);
        self.lin.factor_values_mut().copy_from_slice(&m.factor);
        self.p_carried.copy_from_slice(&m.p_carried);
        self.p_out.copy_from_slice(&m.p_out);
        self.resume = m.resume;
        self.carried = m.carried;
        true
    }

    /// Take back what [`save`](Self::save) wrote, on an integrator just
    /// made for the same system and settings, so that the steps go on to
    /// the bits they would have had.
    pub fn restore(&mut self, r: &mut Decoder<'_>) -> Result<(), CheckpointError>
    where
        G: Geometry,
        Lin: KeptFactor,
    {
        r.f64s_into(&mut self.lambda, "rattle.lambda")?;
        r.f64s_into(&mut self.lambda_prev, "rattle.lambda_prev")?;
        self.solved = r.usize("rattle.solved")?;
        self.lambda_h = r.f64("rattle.lambda_h")?;
        self.since_factor = r.usize("rattle.since_factor")?;
        self.stale = r.bool("rattle.stale")?;
        self.last_wave_number = r.f64("rattle.last_wave_number")?;
        r.f64s_into(&mut self.force, "rattle.force")?;
        r.f64s_into(&mut self.cached_q, "rattle.cached_q")?;
        self.valid = r.bool("rattle.valid")?;
        r.f64s_into(self.d.values_mut(), "rattle.edge_vectors")?;
        r.f64s_into(self.lin.factor_values_mut(), "rattle.factor")?;
        r.f64s_into(&mut self.p_carried, "rattle.p_carried")?;
        r.f64s_into(&mut self.p_out, "rattle.p_out")?;
        self.resume = r.bool("rattle.resume")?;
        self.carried = r.bool("rattle.carried")?;
        let st = &mut self.stats;
        st.steps = r.usize("rattle.stats")?;
        st.iterations = r.usize("rattle.stats")?;
        st.max_iterations = r.usize("rattle.stats")?;
        st.factorizations = r.usize("rattle.stats")?;
        st.lu_factorizations = r.usize("rattle.stats")?;
        st.symbolic_lu = r.usize("rattle.stats")?;
        st.pcg_iterations = r.usize("rattle.stats")?;
        st.pcg_failures = r.usize("rattle.stats")?;
        st.max_residual = r.f64("rattle.stats")?;
        st.max_wave_number = r.f64("rattle.stats")?;
        st.seconds.forces = r.f64("rattle.stats")?;
        st.seconds.constraints = r.f64("rattle.stats")?;
        st.seconds.factorize = r.f64("rattle.stats")?;
        st.seconds.solve = r.f64("rattle.stats")?;
        Ok(())
    }
}
