//! The sparse stage solver on cloth: every implicit Runge–Kutta table and
//! implicit pair of the library (and a table of a user's), through
//! [`integrator_core::implicit::step_sparse`] on the model's sparse Jacobian.
//!
//! The state is `z = [q; p]` and `f(z) = [M⁻¹p; F(q)]`, so
//!
//! ```text
//! ∂f/∂z = [[0,      M⁻¹],
//!          [∂F/∂q,  0  ]]
//! ```
//!
//! with `M⁻¹ = I/m` (diagonal) and `∂F/∂q = −∇²V` from
//! [`ClothModel::force_jacobian_pattern`] / [`ClothModel::force_jacobian_values`].
//! The pattern is fixed for the run; the solver's [`SparseWorkspace`] computes
//! the symbolic LU of the Newton matrix `I − h·A⊗J` once per run (one per
//! matrix shape: the stacked `s·d` system of a fully implicit table, or the
//! `d × d` stage matrix of a diagonally implicit one), and a numeric LU
//! only when the Jacobian is refreshed or `h` changes.
//!
//! ```
//! use cloth::{Method, RunSettings, Scene, Simulation, SolverStats};
//!
//! let scene = Scene::from_toml(r#"
//!     gravity = [0.0, -9.81, 0.0]
//!     [cloth]
//!     width = 0.5
//!     height = 0.5
//!     nx = 5
//!     ny = 5
//!     [material]
//!     density = 0.1
//!     stretch = 50.0
//!     [pins]
//!     edges = ["top"]
//!     [simulation]
//!     substeps = 2
//!     frames = 3
//!     method = "leapfrog"
//! "#, "inline.toml")?;
//! let mut sim = Simulation::new(&scene)?;
//! let settings = RunSettings::from_scene(&scene);
//! let run = sim.run(&Method::parse("gauss2")?, &settings, |_frame| Ok(()))?;
//! assert_eq!(run.steps, 6);
//! let SolverStats::Stage(solver) = run.solver else { unreachable!() };
//! assert_eq!(solver.symbolic_factorizations, 1);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::cell::RefCell;

use integrator_core::OdeSystem;
use integrator_core::implicit::{self, ImplicitTable, Settings, SparseJacobian, SparseWorkspace};

use super::{ClothStepper, Refused, SolverStats, StepError};
use crate::model::ClothModel;

impl SparseJacobian for ClothModel {
    /// `(k, n + k)` for the `M⁻¹` block (`n = 3·free`), then the force
    /// Jacobian's pattern shifted down by `n` rows.
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        let n = 3 * self.free_count();
        let force = self.force_jacobian_pattern();
        let mut pattern = Vec::with_capacity(n + force.len());
        pattern.extend((0..n).map(|k| (k, n + k)));
        pattern.extend(force.into_iter().map(|(r, c)| (n + r, c)));
        pattern
    }

    fn jacobian_values(&self, _t: f64, z: &[f64], values: &mut [f64]) {
        let n = 3 * self.free_count();
        let (diag, force) = values.split_at_mut(n);
        diag.fill(self.inverse_mass());
        self.force_jacobian_values(&z[..n], force);
    }
}

/// The state as the stage solver sees it: moved by a constant and a
/// uniform drift, `w = z + c + (t − τ)·u`, so that
/// `w' = f̃(t, w) = f(w − c − (t − τ)·u) + u`, with `c` of the size of the
/// positions and momenta the run will see and `u = 10⁻³·c` per second.
///
/// Runge–Kutta methods whose abscissae are the row sums of `A` commute with
/// such affine changes of variables, so these are the same steps, up to
/// round-off at the scale of `c`; a table whose given `c` differs from its
/// row sums (Lobatto IIIB, and the pairs built on it) commutes with the
/// constant only, and gets no drift. The change is
/// there for the stage solver's convergence test, which measures each
/// correction relative to its own component (`|ΔZₖ|/(|zₖ| + |Zₖ|)` and
/// `|ΔZₖ|/|Zₖ|`, with no absolute floor): a cloth has many components that
/// are zero or nearly so — momenta at rest, a flat sheet's coordinate
/// across its plane, increments that vanish by symmetry — whose corrections
/// are round-off noise of the coupled system, or decay geometrically to
/// zero, and never "converge" relative to themselves. Moved, every
/// component and every increment has the scale of the motion (`c`, `h·u`),
/// and the test asks for corrections at round-off relative to that scale,
/// which is what the energy sees. The drift is taken out again (`τ` reset)
/// every 10 s, so `w` stays within `1.01·c` of `z`.
struct Shift {
    /// `c`; the drift is `u = drift·c`.
    offset: Vec<f64>,
    /// [`DRIFT`], or 0 for a table whose abscissae are not its row sums.
    drift: f64,
    /// `τ`.
    epoch: f64,
    scratch: RefCell<Vec<f64>>,
}

/// The model seen through a [`Shift`]: what the stage solver steps.
struct Shifted<'a> {
    model: &'a ClothModel,
    shift: &'a Shift,
}

/// The drift per second, relative to the offset: `u = DRIFT·c`. Small,
/// so that the first stage evaluations of a step without history (at `w`,
/// not yet at `w + h·cᵢ·u`) see the cloth barely moved.
const DRIFT: f64 = 1e-3;

/// How often the drift is taken out of the shifted state (s).
const RECENTER: f64 = 10.0;

impl Shift {
    /// Offsets for a run from `z` at time `t`: positions by
    /// `4·(max|q| + size)`, momenta by `4·m·v`, `v = √(2E/M)` the speed of
    /// the whole cloth carrying the run's energy scale
    /// `E = max(|H|, M·|g|·size)` (or the size per second when both vanish).
    fn new(model: &ClothModel, z: &[f64], t: f64, drift: f64) -> Self {
        let n = z.len() / 2;
        let positions = model.positions(&z[..n]);
        let (lo, hi) = positions.iter().fold(
            ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
            |(mut lo, mut hi), x| {
                for a in 0..3 {
                    lo[a] = lo[a].min(x[a]);
                    hi[a] = hi[a].max(x[a]);
                }
                (lo, hi)
            },
        );
        let size = (0..3)
            .map(|a| (hi[a] - lo[a]).powi(2))
            .sum::<f64>()
            .sqrt()
            .max(1e-3);
        let q_max = z[..n].iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let mass = model.particle_mass();
        let total_mass = mass * model.free_count() as f64;
        let energy = model
            .energy(z)
            .total()
            .abs()
            .max(total_mass * model.gravity().norm() * size);
        let speed = if energy > 0.0 {
            (2.0 * energy / total_mass).sqrt()
        } else {
            size
        };
        let p_max = z[n..].iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let (cq, cp) = (4.0 * (q_max + size), 4.0 * (mass * speed).max(p_max));
        let mut offset = vec![cq; 2 * n];
        offset[n..].fill(cp);
        Shift {
            offset,
            drift,
            epoch: t,
            scratch: RefCell::new(vec![0.0; 2 * n]),
        }
    }

    /// `w = z + c + (t − τ)·u`, in place.
    fn shift(&self, t: f64, z: &mut [f64]) {
        let s = t - self.epoch;
        for (z, c) in z.iter_mut().zip(&self.offset) {
            *z += c + s * self.drift * c;
        }
    }

    /// `z = w − c − (t − τ)·u`.
    fn unshift(&self, t: f64, w: &[f64], z: &mut [f64]) {
        let s = t - self.epoch;
        for ((z, w), c) in z.iter_mut().zip(w).zip(&self.offset) {
            *z = w - (c + s * self.drift * c);
        }
    }

    /// Take the drift out of `w` once it has run for [`RECENTER`].
    fn recenter(&mut self, t: f64, w: &mut [f64]) {
        let s = t - self.epoch;
        if s >= RECENTER {
            for (w, c) in w.iter_mut().zip(&self.offset) {
                *w -= s * self.drift * c;
            }
            self.epoch = t;
        }
    }
}

impl OdeSystem for Shifted<'_> {
    fn dim(&self) -> usize {
        self.shift.offset.len()
    }
    fn rhs(&self, t: f64, w: &[f64], dw: &mut [f64]) {
        let mut z = self.shift.scratch.borrow_mut();
        self.shift.unshift(t, w, &mut z);
        self.model.rhs(t, &z, dw);
        for (d, c) in dw.iter_mut().zip(&self.shift.offset) {
            *d += self.shift.drift * c;
        }
    }
}

impl SparseJacobian for Shifted<'_> {
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        self.model.jacobian_pattern()
    }
    fn jacobian_values(&self, t: f64, w: &[f64], values: &mut [f64]) {
        let mut z = self.shift.scratch.borrow_mut();
        self.shift.unshift(t, w, &mut z);
        // The solver's matrix: compressed springs' transverse terms clamped
        // (the steps are the same; Newton converges where it would not).
        let n = 3 * self.model.free_count();
        let (diag, force) = values.split_at_mut(n);
        diag.fill(self.model.inverse_mass());
        self.model.force_jacobian_values_definite(&z[..n], force);
    }
}

/// The stage solver's settings for cloth ([`StageSettings::default`]).
pub type StageSettings = Settings;

/// The stage-solver settings for cloth: the defaults (simplified Newton on
/// the sparse Jacobian, iterated to round-off), with the stagnation limit
/// raised from `1e-12` to [`STAGNATION_LIMIT`] and up to
/// [`MAX_ITERATIONS`] iterations. The Newton
/// matrix `I − h·A⊗J` of a cloth is ill-conditioned (its condition grows
/// like `(h·ω_max)²`), and the corrections of its stage values stop
/// decreasing at a few `1e-12` of their scale: with the default limit such a
/// step would be reported as diverged. A correction is still only accepted
/// as round-off once it no longer decreases.
pub fn cloth_settings() -> Settings {
    Settings {
        stagnation_limit: STAGNATION_LIMIT,
        max_iterations: MAX_ITERATIONS,
        ..Settings::default()
    }
}

/// The stage solver's stagnation limit on cloth (see [`cloth_settings`]).
pub const STAGNATION_LIMIT: f64 = 1e-9;

/// The stage solver's iteration cap on cloth (see [`cloth_settings`]).
pub const MAX_ITERATIONS: usize = 100;

/// The most free particles an implicit run takes: 2¹⁶ = 65 536 (a 256 ×
/// 256 grid). The Newton matrix of an `s`-stage method is `6·s·free`
/// unknowns square, and its sparse LU fills in far beyond the springs:
/// Gauss–Legendre 2 takes about 3 s per step on 128 × 128 already (docs/results/cloth-kernels.md),
/// and the factors of a 2048 × 2048 cloth would not fit in memory. Explicit
/// methods have no such limit beyond [`MAX_PARTICLES`](crate::MAX_PARTICLES).
pub const MAX_FREE_PARTICLES: usize = 1 << 16;

/// Refuse a model too large for the sparse LU ([`MAX_FREE_PARTICLES`]),
/// before anything is built.
pub fn check_size(model: &ClothModel) -> Result<(), Refused> {
    let free = model.free_count();
    if free > MAX_FREE_PARTICLES {
        let (nx, ny) = model.grid();
        return Err(Refused(format!(
            "implicit methods take at most {MAX_FREE_PARTICLES} free particles (e.g. a 256 × 256 grid); this {nx} × {ny} cloth has {free}: use an explicit method or a coarser grid"
        )));
    }
    Ok(())
}

/// Whether the abscissae `c` are the row sums of `A` (and of `Â`), to
/// round-off: then the shift may drift.
fn abscissae_are_row_sums<const S: usize>(table: &ImplicitTable<S>) -> bool {
    let rows = |a: &[[f64; S]; S]| {
        a.iter()
            .zip(&table.c)
            .all(|(row, c)| (row.iter().sum::<f64>() - c).abs() <= 1e-14)
    };
    rows(&table.a) && table.a_hat.as_ref().is_none_or(|(a_hat, _)| rows(a_hat))
}

/// The stage solver stepping one implicit table on one model: the shifted
/// state carried from frame to frame, and one [`SparseWorkspace`] for the
/// run, so the symbolic factorisation is computed once.
pub struct StageStepper<const S: usize> {
    table: ImplicitTable<S>,
    shift: Shift,
    workspace: SparseWorkspace,
    /// The shifted state at the end of the last frame (`None` before the
    /// first): carried, not recomputed from `z`, so the frames cost no
    /// round-off.
    carried: Option<Vec<f64>>,
}

impl<const S: usize> StageStepper<S> {
    /// A stepper for `table` on `model` from `z` at time `t`; refuses a
    /// model too large for the sparse LU.
    pub fn new(
        table: &ImplicitTable<S>,
        model: &ClothModel,
        z: &[f64],
        t: f64,
        settings: Settings,
    ) -> Result<Self, Refused> {
        check_size(model)?;
        let drift = if abscissae_are_row_sums(table) {
            DRIFT
        } else {
            0.0
        };
        Ok(StageStepper {
            table: *table,
            shift: Shift::new(model, z, t, drift),
            workspace: SparseWorkspace::new(z.len(), S).with_settings(settings),
            carried: None,
        })
    }
}

impl<const S: usize> ClothStepper for StageStepper<S> {
    fn enter(&mut self, _model: &ClothModel, t: f64, z: &mut [f64]) {
        match &self.carried {
            Some(w) => z.copy_from_slice(w),
            None => self.shift.shift(t, z),
        }
    }

    fn step(&mut self, model: &ClothModel, t: f64, h: f64, w: &mut [f64]) -> Result<(), StepError> {
        self.shift.recenter(t, w);
        let system = Shifted {
            model,
            shift: &self.shift,
        };
        implicit::step_sparse(&self.table, &system, t, h, w, &mut self.workspace)
            .map_err(StepError::Solve)
    }

    fn leave(&mut self, _model: &ClothModel, t: f64, z: &mut [f64]) {
        let carried = self.carried.get_or_insert_with(|| vec![0.0; z.len()]);
        carried.copy_from_slice(z);
        self.shift.unshift(t, carried, z);
    }

    fn stats(&self) -> SolverStats {
        SolverStats::Stage(*self.workspace.stats())
    }
}
