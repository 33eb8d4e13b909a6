//! Implicit library schemes on cloth: the model's sparse Jacobian and a
//! runner that steps a scene through the sparse stage solver
//! ([`integrator_core::implicit::step_sparse`]).
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
//! use cloth::{implicit, RunOptions, Scene, Simulation};
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
//! let opts = RunOptions::from_scene(&scene);
//! let run = implicit::run_implicit(&mut sim, "gauss2", &opts, |_frame| Ok(()))?;
//! assert_eq!(run.report.steps, 6);
//! assert_eq!(run.solver.symbolic_factorizations, 1);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::cell::RefCell;
use std::time::Instant;

use integrator_core::implicit::{
    self, ImplicitTable, Settings, SparseJacobian, SparseWorkspace, Stats,
};
use integrator_core::library::*;
use integrator_core::{Info, OdeSystem, Scheme};

use crate::methods::{self, MethodError};
use crate::model::ClothModel;
use crate::sim::{CallbackError, Frame, FrameStats, RunError, RunOptions, RunReport, Simulation};

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

/// The cloth as the stage solver sees it: the state moved by a constant
/// and a uniform drift, `w = z + c + (t − τ)·u`, so that
/// `w' = f̃(t, w) = f(w − c − (t − τ)·u) + u`, with `c` of the size of the
/// positions and momenta the run will see and `u = 10⁻³·c` per second.
///
/// Runge–Kutta methods whose abscissae are the row sums of `A` (every table
/// in [`IMPLICIT`]) commute with such affine changes of variables, so these
/// are the same steps, up to round-off at the scale of `c`. The change is
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
struct Shifted<'m> {
    model: &'m ClothModel,
    /// `c`; the drift is `u = DRIFT·c`.
    offset: Vec<f64>,
    /// `τ`.
    epoch: f64,
    scratch: RefCell<Vec<f64>>,
}

/// The drift per second, relative to the offset: `u = DRIFT·c`. Small,
/// so that the first stage evaluations of a step without history (at `w`,
/// not yet at `w + h·cᵢ·u`) see the cloth barely moved.
const DRIFT: f64 = 1e-3;

/// How often the drift is taken out of the shifted state (s).
const RECENTER: f64 = 10.0;

impl<'m> Shifted<'m> {
    /// Offsets for a run from `z` at time `t`: positions by
    /// `4·(max|q| + size)`, momenta by `4·m·v`, `v = √(2E/M)` the speed of
    /// the whole cloth carrying the run's energy scale
    /// `E = max(|H|, M·|g|·size)` (or the size per second when both vanish).
    fn new(model: &'m ClothModel, z: &[f64], t: f64) -> Self {
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
        Shifted {
            model,
            offset,
            epoch: t,
            scratch: RefCell::new(vec![0.0; 2 * n]),
        }
    }

    /// `w = z + c + (t − τ)·u`.
    fn shift(&self, t: f64, z: &[f64], w: &mut [f64]) {
        let s = t - self.epoch;
        for ((w, z), c) in w.iter_mut().zip(z).zip(&self.offset) {
            *w = z + (c + s * DRIFT * c);
        }
    }

    /// `z = w − c − (t − τ)·u`.
    fn unshift(&self, t: f64, w: &[f64], z: &mut [f64]) {
        let s = t - self.epoch;
        for ((z, w), c) in z.iter_mut().zip(w).zip(&self.offset) {
            *z = w - (c + s * DRIFT * c);
        }
    }

    /// Take the drift out of `w` once it has run for [`RECENTER`].
    fn recenter(&mut self, t: f64, w: &mut [f64]) {
        let s = t - self.epoch;
        if s >= RECENTER {
            for (w, c) in w.iter_mut().zip(&self.offset) {
                *w -= s * DRIFT * c;
            }
            self.epoch = t;
        }
    }
}

impl OdeSystem for Shifted<'_> {
    fn dim(&self) -> usize {
        self.offset.len()
    }
    fn rhs(&self, t: f64, w: &[f64], dw: &mut [f64]) {
        let mut z = self.scratch.borrow_mut();
        self.unshift(t, w, &mut z);
        self.model.rhs(t, &z, dw);
        for (d, c) in dw.iter_mut().zip(&self.offset) {
            *d += DRIFT * c;
        }
    }
}

impl SparseJacobian for Shifted<'_> {
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        self.model.jacobian_pattern()
    }
    fn jacobian_values(&self, t: f64, w: &[f64], values: &mut [f64]) {
        let mut z = self.scratch.borrow_mut();
        self.unshift(t, w, &mut z);
        // The solver's matrix: compressed springs' transverse terms clamped
        // (the steps are the same; Newton converges where it would not).
        let n = 3 * self.model.free_count();
        let (diag, force) = values.split_at_mut(n);
        diag.fill(self.model.inverse_mass());
        self.model.force_jacobian_values_definite(&z[..n], force);
    }
}

/// The implicit library schemes that step cloth (by catalogue id), through
/// the sparse stage solver. The first three are the ones the command line
/// documents: Gauss–Legendre with 2 stages (order 4, symplectic), the
/// implicit midpoint rule (order 2, symplectic) and implicit Euler (order 1,
/// dissipative).
pub const IMPLICIT: &[&str] = &[
    "gauss2",
    "midpoint",
    "implicit-euler",
    "gauss3",
    "radau2a-3",
    "paper-dirk2",
    "paper-dirk4",
];

/// Whether `id` names an implicit scheme this module steps.
pub fn is_implicit(id: &str) -> bool {
    IMPLICIT.contains(&id)
}

/// Every method name that can step cloth: the explicit ones
/// ([`methods::STEPPABLE`]) and the implicit ones ([`IMPLICIT`]).
pub fn all_methods() -> Vec<&'static str> {
    methods::STEPPABLE.iter().chain(IMPLICIT).copied().collect()
}

/// Called with the table (and the facts) of an implicit scheme.
pub trait TableVisitor {
    type Output;
    fn visit<const S: usize>(self, table: &ImplicitTable<S>, info: &'static Info) -> Self::Output;
}

/// Call `visitor` with the table of the implicit library scheme `id` (one
/// of [`IMPLICIT`]).
pub fn with_table<V: TableVisitor>(id: &str, visitor: V) -> Result<V::Output, MethodError> {
    fn go<T: Scheme, V: TableVisitor, const S: usize>(
        table: &ImplicitTable<S>,
        visitor: V,
    ) -> V::Output {
        visitor.visit(table, &T::INFO)
    }
    Ok(match id {
        "gauss2" => go::<GaussLegendre2, V, 2>(&GaussLegendre2::TABLE, visitor),
        "midpoint" => go::<ImplicitMidpoint, V, 1>(&ImplicitMidpoint::TABLE, visitor),
        "implicit-euler" => go::<ImplicitEuler, V, 1>(&ImplicitEuler::TABLE, visitor),
        "gauss3" => go::<GaussLegendre3, V, 3>(&GaussLegendre3::TABLE, visitor),
        "radau2a-3" => go::<RadauIIA3, V, 3>(&RadauIIA3::TABLE, visitor),
        "paper-dirk2" => go::<PaperDirk2, V, 2>(&PaperDirk2::TABLE, visitor),
        "paper-dirk4" => go::<PaperDirk4, V, 3>(&PaperDirk4::TABLE, visitor),
        other => {
            return Err(if integrator_core::library::info(other).is_some() {
                MethodError::NotSteppable(other.to_string())
            } else {
                MethodError::Unknown(other.to_string())
            });
        }
    })
}

/// The facts of an implicit scheme this module steps.
pub fn info(id: &str) -> Option<&'static Info> {
    struct Facts;
    impl TableVisitor for Facts {
        type Output = &'static Info;
        fn visit<const S: usize>(self, _: &ImplicitTable<S>, info: &'static Info) -> &'static Info {
            info
        }
    }
    with_table(id, Facts).ok()
}

/// A finished implicit run: the run's report and what the stage solver did.
#[derive(Clone, Debug, PartialEq)]
pub struct ImplicitRun {
    pub report: RunReport,
    /// Newton iterations, numeric and symbolic factorisations, Jacobian and
    /// right-hand-side evaluations over the run.
    pub solver: Stats,
}

/// Run `opts.frames` frames of `opts.substeps` steps of `table` on the
/// simulation, as [`Simulation::run`] does for explicit schemes: `on_frame`
/// is called with the current frame first and after every frame; a stage
/// solve that fails stops the run with [`RunError::Solve`], a non-finite
/// state with [`RunError::Diverged`], both naming the step, time and
/// method, and the state is left as it was at the end of the last good
/// frame. One [`SparseWorkspace`] serves the whole run, so the symbolic
/// factorisation is computed once.
pub fn run_table<const S: usize, F>(
    sim: &mut Simulation,
    table: &ImplicitTable<S>,
    method: &'static str,
    opts: &RunOptions,
    settings: Settings,
    mut on_frame: F,
) -> Result<ImplicitRun, RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    let h = opts.step_size();
    opts.check()?;
    check_size(&sim.model)?;
    let mut frames = Vec::with_capacity(opts.frames.min(1 << 16) + 1);
    let mut emit = |sim: &Simulation, frames: &mut Vec<FrameStats>| -> Result<(), RunError> {
        let stats = sim.stats();
        frames.push(stats);
        on_frame(&Frame {
            stats,
            model: &sim.model,
            state: &sim.state,
        })
        .map_err(|source| RunError::Callback {
            frame: stats.frame,
            time: stats.time,
            source,
        })
    };
    emit(sim, &mut frames)?;
    let mut shifted = Shifted::new(&sim.model, &sim.state, sim.time);
    let mut w = vec![0.0; sim.state.len()];
    shifted.shift(sim.time, &sim.state, &mut w);
    let mut ws = SparseWorkspace::new(w.len(), S).with_settings(settings);
    let t0 = sim.time;
    let step0 = sim.steps;
    let mut stepping = 0.0;
    for _ in 0..opts.frames {
        let frame_start = sim.steps;
        let clock = Instant::now();
        for _ in 0..opts.substeps {
            let t = t0 + (sim.steps - step0) as f64 * h;
            shifted.recenter(t, &mut w);
            if let Err(source) = implicit::step_sparse(table, &shifted, t, h, &mut w, &mut ws) {
                let step = sim.steps + 1;
                sim.steps = frame_start;
                return Err(RunError::Solve {
                    method,
                    step,
                    time: t,
                    source,
                });
            }
            sim.steps += 1;
            if let Some(index) = w.iter().position(|x| !x.is_finite()) {
                let value = w[index];
                let steps = sim.steps;
                sim.steps = frame_start;
                return Err(RunError::Diverged {
                    method,
                    step: steps,
                    time: t0 + (steps - step0) as f64 * h,
                    frame: sim.frame + 1,
                    index,
                    value,
                    particle: sim.model.particle_of_component(index),
                });
            }
        }
        stepping += clock.elapsed().as_secs_f64();
        sim.frame += 1;
        sim.time = t0 + (sim.steps - step0) as f64 * h;
        shifted.unshift(sim.time, &w, &mut sim.state);
        emit(sim, &mut frames)?;
    }
    Ok(ImplicitRun {
        report: RunReport {
            method,
            h,
            steps: sim.steps - step0,
            frames,
            stepping_seconds: stepping,
        },
        solver: *ws.stats(),
    })
}

/// The most free particles an implicit run takes: 2¹⁶ = 65 536 (a 256 ×
/// 256 grid). The Newton matrix of an `s`-stage method is `6·s·free`
/// unknowns square, and its sparse LU fills in far beyond the springs:
/// Gauss–Legendre 2 takes about 3 s per step on 128 × 128 already (README),
/// and the factors of a 2048 × 2048 cloth would not fit in memory. Explicit
/// methods have no such limit beyond [`MAX_PARTICLES`](crate::MAX_PARTICLES).
pub const MAX_FREE_PARTICLES: usize = 1 << 16;

/// Refuse a model too large for the sparse LU ([`MAX_FREE_PARTICLES`]),
/// before anything is built.
pub fn check_size(model: &ClothModel) -> Result<(), RunError> {
    let free = model.free_count();
    if free > MAX_FREE_PARTICLES {
        let (nx, ny) = model.grid();
        return Err(RunError::Options(format!(
            "implicit methods take at most {MAX_FREE_PARTICLES} free particles (e.g. a 256 × 256 grid); this {nx} × {ny} cloth has {free}: use an explicit method or a coarser grid"
        )));
    }
    Ok(())
}

/// [`run_table`] with an implicit library scheme named by its id (one of
/// [`IMPLICIT`]) and the given solver settings.
pub fn run_implicit_with<F>(
    sim: &mut Simulation,
    id: &str,
    opts: &RunOptions,
    settings: Settings,
    on_frame: F,
) -> Result<ImplicitRun, RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    struct Visit<'s, F> {
        sim: &'s mut Simulation,
        opts: &'s RunOptions,
        settings: Settings,
        on_frame: F,
    }
    impl<F: FnMut(&Frame<'_>) -> Result<(), CallbackError>> TableVisitor for Visit<'_, F> {
        type Output = Result<ImplicitRun, RunError>;
        fn visit<const S: usize>(
            self,
            table: &ImplicitTable<S>,
            info: &'static Info,
        ) -> Self::Output {
            run_table(
                self.sim,
                table,
                info.name,
                self.opts,
                self.settings,
                self.on_frame,
            )
        }
    }
    with_table(
        id,
        Visit {
            sim,
            opts,
            settings,
            on_frame,
        },
    )?
}

/// The stage-solver settings for cloth: the defaults (simplified Newton on
/// the sparse Jacobian, iterated to round-off), with the stagnation limit
/// raised from `1e-12` to `1e-9` and up to 100 iterations. The Newton
/// matrix `I − h·A⊗J` of a cloth is ill-conditioned (its condition grows
/// like `(h·ω_max)²`), and the corrections of its stage values stop
/// decreasing at a few `1e-12` of their scale: with the default limit such a
/// step would be reported as diverged. A correction is still only accepted
/// as round-off once it no longer decreases.
pub fn cloth_settings() -> Settings {
    Settings {
        stagnation_limit: 1e-9,
        max_iterations: 100,
        ..Settings::default()
    }
}

/// [`run_implicit_with`] the solver settings for cloth ([`cloth_settings`]).
pub fn run_implicit<F>(
    sim: &mut Simulation,
    id: &str,
    opts: &RunOptions,
    on_frame: F,
) -> Result<ImplicitRun, RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    run_implicit_with(sim, id, opts, cloth_settings(), on_frame)
}

/// Run any method that steps cloth ([`all_methods`]): an explicit one with
/// [`Simulation::run_named`], an implicit one with [`run_implicit`]. The
/// solver statistics are those of an implicit run.
pub fn run_method<F>(
    sim: &mut Simulation,
    id: &str,
    opts: &RunOptions,
    on_frame: F,
) -> Result<(RunReport, Option<Stats>), RunError>
where
    F: FnMut(&Frame<'_>) -> Result<(), CallbackError>,
{
    if is_implicit(id) {
        let run = run_implicit(sim, id, opts, on_frame)?;
        Ok((run.report, Some(run.solver)))
    } else {
        Ok((sim.run_named(id, opts, on_frame)?, None))
    }
}
