//! The one-screen summary of a finished cloth run: one function
//! per line or group of lines, from what the crate returned.

use std::fmt::Write as _;
use std::path::Path;

use cloth::study::energy::{relative_errors, worst_relative_error};
use cloth::study::growth::Growth;
use cloth::{ClothModel, FrameStats, Method, RunOptions, RunReport, Scene, SolverStats};
use compare::format::{MISSING, fixed, sci};

/// What the summary shows.
pub struct Summary<'a> {
    pub scene: &'a Scene,
    pub model: &'a ClothModel,
    pub method: &'a Method,
    pub report: &'a RunReport,
    pub opts: &'a RunOptions,
    /// Wall-clock time of the whole run, output included (s).
    pub wall: f64,
    pub e_ref: f64,
    pub note: Option<&'a str>,
    pub dir: &'a Path,
    pub objs: usize,
    pub written: &'a [String],
}

impl Summary<'_> {
    pub fn render(&self) -> String {
        let mut s = String::new();
        self.header(&mut s);
        self.method_line(&mut s);
        self.step_line(&mut s);
        self.timing(&mut s);
        self.energy(&mut s);
        self.solver(&mut s);
        self.output(&mut s);
        s
    }

    /// The scene and its grid.
    fn header(&self, s: &mut String) {
        let (scene, model) = (self.scene, self.model);
        let (nx, ny) = model.grid();
        let families: Vec<String> = cloth::Family::ALL
            .iter()
            .zip(model.family_counts())
            .filter(|(_, n)| *n > 0)
            .map(|(f, n)| format!("{} {n}", f.name()))
            .collect();
        let _ = writeln!(
            s,
            "cloth: {}{}",
            scene.name,
            scene
                .description
                .as_ref()
                .map_or(String::new(), |d| format!(" — {d}"))
        );
        let _ = writeln!(
            s,
            "  grid         {nx} × {ny} particles ({} free, {} pinned), {} springs ({}){}",
            model.free_count(),
            model.pinned_count(),
            model.spring_count(),
            families.join(", "),
            if model.is_inextensible() {
                format!(
                    ", {} length constraints (warp and weft, inextensible){}",
                    model.constraint_count(),
                    if model.bending_stiffness() > 0.0 {
                        format!(
                            ", isometric bending B = {} N·m",
                            sci(model.bending_stiffness(), 3)
                        )
                    } else {
                        String::new()
                    }
                )
            } else {
                String::new()
            }
        );
    }

    /// The method with its kind, order, what it conserves and (implicit)
    /// how it is solved: from the method's facts, for every method alike.
    fn method_line(&self, s: &mut String) {
        let _ = writeln!(
            s,
            "  method       {} ({}) — {}",
            self.method.id(),
            self.report.method,
            facts(self.method)
        );
    }

    /// The step size beside the linear stability limit.
    fn step_line(&self, s: &mut String) {
        let r = self.report;
        let stab = self.model.stability();
        // ω_max is 0 when the power iteration finds no positive eigenvalue
        // of M⁻¹K (a cloth deep inside a sphere is unstable tangentially):
        // then there is no linear limit to print.
        let limit = if stab.omega_max > 0.0 && stab.h_max.is_finite() {
            format!(
                "2/ω_max = {} s, h·ω_max = {}{}",
                sci(stab.h_max, 4),
                fixed(r.h * stab.omega_max, 3),
                if stab.converged {
                    String::new()
                } else {
                    format!(
                        " (ω_max a lower bound: {} power iterations, not converged)",
                        stab.iterations
                    )
                }
            )
        } else {
            format!("2/ω_max {MISSING} (the power iteration found no positive eigenvalue of M⁻¹K)")
        };
        match &r.variable {
            None => {
                let _ = writeln!(
                    s,
                    "  step         h = {} s ({} per frame at {} Hz); {limit}",
                    sci(r.h, 4),
                    self.opts.substeps,
                    fixed(self.opts.frame_rate, 4),
                );
            }
            Some(v) => {
                let _ = writeln!(
                    s,
                    "  step         variable, at most h = {} s ({} per frame at {} Hz, the floor); {limit}",
                    sci(r.h, 4),
                    v.floor,
                    fixed(self.opts.frame_rate, 4),
                );
            }
        }
        if let Some(wave) = self.model.tension_wave_step() {
            let _ = writeln!(
                s,
                "               tension waves: ℓ/√(|g|·L) = {} s, h/(ℓ/√(|g|·L)) = {}",
                sci(wave, 4),
                fixed(r.h / wave, 3)
            );
        }
        if let Some(note) = self.note {
            let _ = writeln!(s, "               ({note})");
        }
        if let Some(v) = &r.variable {
            variable_lines(s, v);
        }
    }

    /// Steps, wall time, time per frame and the real-time factor.
    fn timing(&self, s: &mut String) {
        let r = self.report;
        let simulated = self.simulated();
        let _ = writeln!(
            s,
            "  steps        {} over {} frames, {} s simulated",
            r.steps,
            r.frames.len() - 1,
            fixed(simulated, 4)
        );
        let _ = writeln!(
            s,
            "  wall time    {} s ({} s stepping; the rest is statistics and output)",
            fixed(self.wall, 3),
            fixed(r.stepping_seconds, 3)
        );
        if simulated > 0.0 {
            let per_frame = r.stepping_seconds / (simulated * 60.0) * 1e3;
            let _ = writeln!(
                s,
                "  per frame    {} ms of stepping per 60 Hz frame (1/60 s simulated)",
                fixed(per_frame, 3)
            );
            let _ = writeln!(
                s,
                "  real time    {}× (simulated s / stepping s; {}× with output)",
                fixed(simulated / r.stepping_seconds.max(1e-12), 3),
                fixed(simulated / self.wall.max(1e-12), 3)
            );
        }
    }

    fn simulated(&self) -> f64 {
        let r = self.report;
        r.frames.last().map_or(0.0, |f| f.time) - r.frames.first().map_or(0.0, |f| f.time)
    }

    /// The energy error, its growth, and the largest strain.
    fn energy(&self, s: &mut String) {
        let r = self.report;
        let (worst, at) = worst_relative_error(&r.frames, self.e_ref);
        let _ = writeln!(
            s,
            "  energy       max relative error {} (at t = {} s; |H − H₀|/E_ref, E_ref = {} J)",
            sci(worst, 3),
            fixed(at, 3),
            sci(self.e_ref, 4)
        );
        let _ = writeln!(s, "  growth       {}", energy_growth(&r.frames, self.e_ref));
        let (strain, frame) = r.frames.iter().fold((0.0f64, 0usize), |(m, k), f| {
            if f.max_strain > m {
                (f.max_strain, f.frame)
            } else {
                (m, k)
            }
        });
        let _ = writeln!(
            s,
            "  max strain   {} % (frame {frame})",
            fixed(100.0 * strain, 3)
        );
    }

    /// What the solver did, for an implicit run.
    fn solver(&self, s: &mut String) {
        match &self.report.solver {
            SolverStats::Minimise(st, settings) => {
                let _ = writeln!(
                    s,
                    "  solver       {} minimisation, tolerance {:e}: {} iterations per step (at most {} in one solve), {} factorisations per step ({} symbolic, {} of an exact Hessian found indefinite), {} line-search halvings, final residual ≤ {}{}",
                    settings.solver.name(),
                    settings.tolerance,
                    fixed(st.iterations_per_step(), 2),
                    st.max_iterations,
                    fixed(st.factorizations_per_step(), 2),
                    st.symbolic_factorizations,
                    st.indefinite,
                    st.backtracks,
                    sci(st.max_residual, 2),
                    if st.floor_accepts > 0 {
                        format!(
                            "; {} solves stopped at their round-off floor above the tolerance",
                            st.floor_accepts
                        )
                    } else {
                        String::new()
                    }
                );
            }
            SolverStats::Stage(st) => {
                let steps = st.steps.max(1) as f64;
                let _ = writeln!(
                    s,
                    "  newton       {} iterations per step, {} numeric LU ({} symbolic), {} Jacobians, {} failed steps",
                    fixed(st.newton_iterations as f64 / steps, 2),
                    st.factorizations,
                    st.symbolic_factorizations,
                    st.jacobian_evaluations,
                    st.failures
                );
            }
            SolverStats::Constrained(st) => {
                let t = st.seconds;
                let total = (t.forces + t.constraints + t.factorize + t.solve).max(1e-300);
                let pc = |x: f64| fixed(100.0 * x / total, 3);
                let _ = writeln!(
                    s,
                    "  constraints  RATTLE: {} simplified Newton iterations per step (at most {} in one solve), {} Cholesky of G·Gᵀ ({} per step, 1 symbolic), {} LU refreshes of G(q')·G(q)ᵀ, residual ≤ {} (tolerance {} = 32·ε, as max|g|/(L(L + ‖q‖∞)))",
                    fixed(st.iterations_per_step(), 2),
                    st.max_iterations,
                    st.factorizations,
                    fixed(st.factorizations as f64 / st.steps.max(1) as f64, 3),
                    st.lu_factorizations,
                    sci(st.max_residual, 2),
                    sci(cloth::CONSTRAINT_TOLERANCE, 2)
                );
                let _ = writeln!(
                    s,
                    "  tension      largest transverse-wave number h·ω = 4·√(½ΣΛ) {} (RATTLE steps these waves explicitly: stable below 2)",
                    fixed(st.max_wave_number, 3)
                );
                let _ = writeln!(
                    s,
                    "  time split   forces {} %, constraint loops {} %, factorisation {} %, solves {} %",
                    pc(t.forces),
                    pc(t.constraints),
                    pc(t.factorize),
                    pc(t.solve)
                );
            }
            SolverStats::None => {}
        }
    }

    /// Where the files went.
    fn output(&self, s: &mut String) {
        let mut files = self.written.to_vec();
        if self.objs > 0 {
            files.insert(2.min(files.len()), format!("{} OBJ in frames/", self.objs));
        }
        let _ = writeln!(
            s,
            "  output       {}: {}",
            self.dir.display(),
            files.join(", ")
        );
    }
}

/// What the variable step chose and why: the steps per frame (fewest, mean,
/// most, and how many frames took each), the frames integrated again and
/// the steps that cost.
fn variable_lines(s: &mut String, v: &cloth::VariableStats) {
    let (min, mean, max) = v.min_mean_max();
    let _ = writeln!(
        s,
        "  steps/frame  {min} to {max}, mean {} (simulation.step = \"variable\": each frame the fewest steps, at least {}, whose interior h·ω stay ≤ {}, as h·ω ∝ 1/N from the counts tried; largest accepted {}, largest rejected seen {})",
        fixed(mean, 3),
        v.floor,
        fixed(v.target, 3),
        fixed(v.max_accepted, 3),
        fixed(v.max_rejected, 3)
    );
    let shown: Vec<String> = v
        .histogram
        .iter()
        .map(|(n, k)| format!("{n}: {k}"))
        .collect();
    let _ = writeln!(
        s,
        "               frames by steps per frame {{{}}}; {} of {} frames integrated more than once ({} integrations, {} failed solves), {} steps not kept ({} % of the {} kept)",
        shown.join(", "),
        v.redone,
        v.frames,
        v.attempts,
        v.failed,
        v.discarded_steps,
        fixed(
            100.0 * v.discarded_steps as f64 / v.steps().max(1) as f64,
            3
        ),
        v.steps()
    );
}

/// "explicit, order 2, symplectic" or "implicit, order 4, symplectic
/// (sparse stage solver)": a method's kind, order, what it conserves, and
/// for an implicit one how it is solved.
pub fn facts(method: &Method) -> String {
    let how = if method.explicit() {
        String::new()
    } else {
        format!(" ({})", method.mechanism().describe())
    };
    format!(
        "{}, order {}, {}{how}",
        method.kind(),
        method.order(),
        method.conserves().describe()
    )
}

/// The fitted growth of the relative energy error over `frames`.
pub(crate) fn energy_growth(frames: &[FrameStats], e_ref: f64) -> Growth {
    let times: Vec<f64> = frames.iter().map(|f| f.time).collect();
    cloth::study::growth::fit(&times, &relative_errors(frames, e_ref))
}
