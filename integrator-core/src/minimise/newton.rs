//! Newton's method on an [`Objective`] with the exact Hessian where it is
//! positive definite and the PSD-projected one elsewhere, an
//! Armijo line search on `Φ` that knows `Φ`'s round-off, and a sparse
//! Cholesky factor reused while it still contracts.

use std::time::Instant;

use faer::Par;

use super::llt::{SparseLlt, UpperPattern};
use super::{MinimiseError, NewtonSettings, Objective, Stats};

/// Halvings of the Newton step before the line search gives up.
const MAX_HALVINGS: usize = 60;

/// Armijo's sufficient-decrease constant.
const ARMIJO: f64 = 1e-4;

/// Below this many ulps of `Φ`'s magnitude, Armijo's test is unreliable.
const NOISY: f64 = 4096.0 * f64::EPSILON;

/// A reused factorisation is kept while each iteration shrinks the
/// gradient by at least this factor.
const REUSE_CONTRACTION: f64 = 0.25;

/// Below this many ulps of `Φ`'s magnitude a predicted decrease is round-off.
const ROUNDOFF: f64 = 64.0 * f64::EPSILON;

/// Newton's method for `min Φ(u)` ([`Objective`]) on one Hessian pattern:
/// the symbolic Cholesky analysed once, every buffer allocated here, so that
/// a solve allocates nothing.
pub struct Newton {
    settings: NewtonSettings,
    pattern: UpperPattern,
    llt: SparseLlt,
    /// `∇²U` on the system's pattern.
    hessian: Vec<f64>,
    /// The upper values of `c·M + K⁺` and their factor.
    upper: Vec<f64>,
    factor: Vec<f64>,
    /// The `c` of the factor in `factor`, if any.
    factored: Option<f64>,
    x: Vec<f64>,
    trial_u: Vec<f64>,
    trial_x: Vec<f64>,
    g: Vec<f64>,
    g_trial: Vec<f64>,
    dx: Vec<f64>,
    f: Vec<f64>,
    stats: Stats,
}

impl Newton {
    /// The solver for objectives of dimension `n` whose `U` has its Hessian
    /// on `pattern` (positions `(row, column)`; the full symmetric pattern or
    /// its upper triangle, see [`UpperPattern::new`]).
    ///
    /// # Panics
    /// If a pattern entry lies outside `n × n`.
    pub fn new(
        n: usize,
        pattern: &[(usize, usize)],
        settings: NewtonSettings,
    ) -> Result<Newton, MinimiseError> {
        Newton::with_par(n, pattern, settings, Par::Seq)
    }

    /// [`Newton::new`] with faer's parallelism `par` for the factorisations
    /// and solves.
    pub fn with_par(
        n: usize,
        pattern: &[(usize, usize)],
        settings: NewtonSettings,
        par: Par,
    ) -> Result<Newton, MinimiseError> {
        settings.check().map_err(MinimiseError::Invalid)?;
        let upper_pattern = UpperPattern::new(n, pattern);
        let llt = SparseLlt::new(&upper_pattern, 1, par);
        let stats = Stats {
            symbolic_factorizations: 1,
            ..Stats::default()
        };
        Ok(Newton {
            settings,
            hessian: vec![0.0; pattern.len()],
            upper: vec![0.0; upper_pattern.len()],
            factor: vec![0.0; llt.factor_len()],
            pattern: upper_pattern,
            llt,
            factored: None,
            x: vec![0.0; n],
            trial_u: vec![0.0; n],
            trial_x: vec![0.0; n],
            g: vec![0.0; n],
            g_trial: vec![0.0; n],
            dx: vec![0.0; n],
            f: vec![0.0; n],
            stats,
        })
    }

    pub fn settings(&self) -> &NewtonSettings {
        &self.settings
    }

    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// The counters, for a caller that counts steps or adds its own work.
    pub fn stats_mut(&mut self) -> &mut Stats {
        &mut self.stats
    }

    /// The dimension `n`.
    pub fn dim(&self) -> usize {
        self.x.len()
    }

    /// Forget the kept factorisation (the next solve factorises afresh).
    /// A kept factor is used only with the same `c`, and only while it
    /// contracts, so this changes cost, not results; call it when the
    /// objective changes its kind (e.g. from a midpoint to another step).
    pub fn forget_factor(&mut self) {
        self.factored = None;
    }

    /// The point `x = base + u` of the last solve's result, and the force
    /// `−∇U(x)` there: what the last gradient test evaluated (valid after a
    /// successful [`solve`](Self::solve)).
    pub fn point_and_force(&self) -> (&[f64], &[f64]) {
        (&self.x, &self.f)
    }

    /// `Φ(u)` and the sum of the magnitudes of its terms, with `x = base + u`
    /// formed into `x`.
    fn objective<O: Objective + ?Sized>(obj: &O, u: &[f64], x: &mut [f64]) -> (f64, f64) {
        let c = obj.inertia();
        let mass = obj.mass();
        let mut inertia = 0.0;
        for (k, ((x, b), u)) in x.iter_mut().zip(obj.base()).zip(u).enumerate() {
            *x = b + u;
            inertia += mass.get(k) * u * u;
        }
        let inertia = 0.5 * c * inertia;
        let (value, magnitude) = obj.value(x);
        (inertia + value, inertia + magnitude)
    }

    /// `g = c·M·u − F(x)` into `g` and `F(x)` into `f`; returns `‖g‖_∞/S`,
    /// `S` the larger of the force scale and `c·max|mₖuₖ|` (the size of the
    /// terms of `g`: its round-off).
    fn gradient<O: Objective + ?Sized>(
        obj: &O,
        u: &[f64],
        x: &[f64],
        f: &mut [f64],
        g: &mut [f64],
    ) -> f64 {
        let c = obj.inertia();
        let mass = obj.mass();
        let mut scale = obj.force(x, f);
        let mut gmax: f64 = 0.0;
        for (k, ((g, u), f)) in g.iter_mut().zip(u).zip(f.iter()).enumerate() {
            let inertia = c * mass.get(k) * u;
            scale = scale.max(inertia.abs());
            *g = inertia - f;
            // f64::max ignores NaN: a non-finite entry must not vanish.
            gmax = if g.is_finite() {
                gmax.max(g.abs())
            } else {
                f64::NAN
            };
        }
        if gmax == 0.0 { 0.0 } else { gmax / scale }
    }

    fn refactor<O: Objective + ?Sized>(&mut self, obj: &O) -> Result<(), MinimiseError> {
        let clock = Instant::now();
        let c = obj.inertia();
        let mass = obj.mass();
        self.factored = None;
        // The exact Hessian first, where the objective has it and the matrix
        // is positive definite (quadratic convergence); else the projected.
        if obj.hessian(&self.x, &mut self.hessian) {
            self.pattern
                .assemble(&self.hessian, |k| c * mass.get(k), &mut self.upper);
            self.stats.factorizations += 1;
            match self.llt.factor(&self.upper, &mut self.factor) {
                Ok(()) => {
                    self.factored = Some(c);
                    self.stats.factor_seconds += clock.elapsed().as_secs_f64();
                    return Ok(());
                }
                Err(MinimiseError::NotDefinite { .. }) => self.stats.indefinite += 1,
                Err(e) => return Err(e),
            }
        }
        obj.hessian_projected(&self.x, &mut self.hessian);
        self.pattern
            .assemble(&self.hessian, |k| c * mass.get(k), &mut self.upper);
        self.llt.factor(&self.upper, &mut self.factor)?;
        self.factored = Some(c);
        self.stats.factor_seconds += clock.elapsed().as_secs_f64();
        self.stats.factorizations += 1;
        Ok(())
    }

    /// Minimise `Φ` from `u` (or from `guess` where `Φ(guess) < Φ(u)`,
    /// counted in [`Stats::predicted`]); on success `u` holds the
    /// minimiser and the result is the number of iterations. Counts the
    /// solve and its iterations (when it succeeds), factorisations, halvings
    /// and residual in [`stats`](Self::stats). On error `u` holds the last
    /// iterate.
    ///
    /// # Panics
    /// If `u`, `guess` or the objective are not of dimension `n`.
    pub fn solve<O: Objective + ?Sized>(
        &mut self,
        obj: &O,
        u: &mut [f64],
        guess: Option<&[f64]>,
    ) -> Result<usize, MinimiseError> {
        let n = self.dim();
        assert!(
            u.len() == n && obj.dim() == n && obj.base().len() == n,
            "Newton::solve: dimension {n} expected"
        );
        let tol = self.settings.tolerance;
        let cap = self.settings.max_iterations;
        let c = obj.inertia();
        let mut phi = Self::objective(obj, u, &mut self.x);
        if let Some(guess) = guess {
            assert_eq!(
                guess.len(),
                n,
                "Newton::solve: guess of dimension {n} expected"
            );
            let trial = Self::objective(obj, guess, &mut self.trial_x);
            if trial.0 < phi.0 {
                u.copy_from_slice(guess);
                std::mem::swap(&mut self.x, &mut self.trial_x);
                phi = trial;
                self.stats.predicted += 1;
            }
        }
        let result = self.iterate(obj, u, phi, tol, cap, c);
        if let Ok(it) = result {
            self.stats.solves += 1;
            self.stats.iterations += it;
            self.stats.max_iterations = self.stats.max_iterations.max(it);
        }
        result
    }

    fn iterate<O: Objective + ?Sized>(
        &mut self,
        obj: &O,
        u: &mut [f64],
        mut phi: (f64, f64),
        tol: f64,
        cap: usize,
        c: f64,
    ) -> Result<usize, MinimiseError> {
        let mut residual = Self::gradient(obj, u, &self.x, &mut self.f, &mut self.g);
        let mut it = 0;
        let mut stalled = 0;
        // Keep the last factor (of this c) while it contracts the gradient
        // by REUSE_CONTRACTION per iteration; refactorise otherwise.
        let mut refactor = self.factored != Some(c);
        loop {
            if !phi.0.is_finite() {
                return Err(MinimiseError::NonFinite {
                    solver: "newton",
                    iteration: it,
                });
            }
            if super::converged("newton", it, residual, tol, cap)? {
                self.stats.max_residual = self.stats.max_residual.max(residual);
                return Ok(it);
            }
            it += 1;
            let fresh = refactor || self.factored != Some(c);
            if fresh {
                self.refactor(obj)?;
            }
            for (d, g) in self.dx.iter_mut().zip(&self.g) {
                *d = -g;
            }
            self.llt.solve(&self.factor, &mut self.dx, 1);
            let slope: f64 = self.dx.iter().zip(&self.g).map(|(d, g)| d * g).sum();
            if !slope.is_finite() {
                return Err(MinimiseError::NonFinite {
                    solver: "newton",
                    iteration: it,
                });
            }
            let mut alpha = 1.0;
            let mut halvings = 0;
            let new_phi = loop {
                for ((t, u), d) in self.trial_u.iter_mut().zip(u.iter()).zip(&self.dx) {
                    *t = u + alpha * d;
                }
                let trial = Self::objective(obj, &self.trial_u, &mut self.trial_x);
                // A decrease predicted below the round-off of Φ cannot be
                // tested on Φ: take the full Newton step (the gradient test
                // decides convergence, the cap stops a run that would not).
                if halvings == 0 && -slope <= ROUNDOFF * phi.1 {
                    self.stats.roundoff_steps += 1;
                    break trial;
                }
                if trial.0 <= phi.0 + ARMIJO * alpha * slope {
                    break trial;
                }
                // Where the decrease Armijo asks for is within a few
                // thousand ulps of Φ, Φ's own round-off decides the test:
                // there the full step is judged by the gradient instead
                // (taken when it shrinks ‖∇Φ‖).
                if halvings == 0 && -slope <= NOISY * phi.1 {
                    let r = Self::gradient(
                        obj,
                        &self.trial_u,
                        &self.trial_x,
                        &mut self.f,
                        &mut self.g_trial,
                    );
                    if r < residual {
                        self.stats.roundoff_steps += 1;
                        break trial;
                    }
                }
                halvings += 1;
                self.stats.backtracks += 1;
                if halvings > MAX_HALVINGS || slope >= 0.0 {
                    return Err(MinimiseError::LineSearch {
                        iteration: it,
                        halvings,
                        residual,
                    });
                }
                alpha *= 0.5;
            };
            u.copy_from_slice(&self.trial_u);
            std::mem::swap(&mut self.x, &mut self.trial_x);
            phi = new_phi;
            let before = residual;
            residual = Self::gradient(obj, u, &self.x, &mut self.f, &mut self.g);
            refactor = !fresh && (halvings > 0 || residual > REUSE_CONTRACTION * before);
            // At round-off: a predicted decrease below the round-off of Φ,
            // or a step that moved no coordinate by more than a few ulps of
            // the largest. Counted only for steps with a fresh factor.
            let moved = self.dx.iter().fold(0.0f64, |m, d| m.max((alpha * d).abs()));
            let x_max = self.x.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let at_roundoff = -slope <= ROUNDOFF * phi.1 || moved <= 4.0 * f64::EPSILON * x_max;
            if at_roundoff && !fresh && residual > 0.5 * before {
                refactor = true;
            } else if at_roundoff && residual > 0.5 * before {
                stalled += 1;
                if stalled >= 3 && residual > tol {
                    self.stats.floor_accepts += 1;
                    self.stats.max_residual = self.stats.max_residual.max(residual);
                    return Ok(it);
                }
            } else {
                stalled = 0;
            }
        }
    }
}
