//! The paper's figure 5, reproduced: the undamped cloth of its section 5
//! (a horizontal rectangle pinned along one edge, 13.78 g/m², stiffness
//! 50.75) at 60 Hz frames, explicit Euler against symplectic Euler, with
//! Störmer–Verlet, implicit Euler and Gauss–Legendre 2 for contrast, and
//! the midpoint family (`midpoint`, `paper-dirk2`, `paper-dirk4`) solved as
//! energy minimisation (`cloth::step::minimise`) at one step per frame.
//!
//! Two settings of the step:
//!
//! * **one step per 16.7 ms frame**, as the paper states: far beyond the
//!   explicit stability limit `2/ω_max` of this cloth, so every explicit
//!   method, symplectic or not, blows up within a few steps; the implicit
//!   ones are tried too;
//! * **substeps**: the explicit methods at the scene's 256 steps per frame
//!   (`h·ω_max ≈ 1.3`), the implicit ones at [`IMPLICIT_SUBSTEPS`] per frame
//!   for [`IMPLICIT_FRAMES`] frames.
//!
//! Beside them, not in the paper, RATTLE on the same sheet made
//! inextensible at [`INEXTENSIBLE_SUBSTEPS`] steps per frame.
//!
//! Each run stops at the first frame whose relative energy error
//! `|H − H₀|/E_ref` exceeds [`BLOWUP`] or is not finite, or at a failed
//! stage, minimisation or constraint solve, and reports where. A table of `2/ω_max` over grid
//! resolutions of the same cloth shows what the paper's 16.7 ms step can
//! and cannot have meant.
//!
//! The runs are [`cloth::study::figure5`]'s (it returns them as data); this
//! module writes the CSV, the plot, the renderings and the report's section.

use std::fmt::Write as _;
use std::path::Path;

use cloth::render::{Camera, Stage, rasterise};
use cloth::study::energy::relative_errors;
use cloth::study::figure5::{
    BLOWUP, ClothExperiment, ClothRun, IMPLICIT_FRAMES, IMPLICIT_SUBSTEPS, INEXTENSIBLE_SHEAR,
    INEXTENSIBLE_SUBSTEPS, experiment_from,
};
use cloth::{AVERAGE_VECTOR_FIELD, Mechanism, Method, Simulation, Vec3};
use compare::format;
use compare::output::csv_field;
use compare::plot::{self, Plot, Series};

use super::{PaperError, write};

/// The method of a run's id (the plan names library methods only, so
/// `None` does not occur).
fn method_of(id: &str) -> Option<Method> {
    Method::parse(id).ok()
}

/// A run's label in the plots.
fn label(r: &ClothRun) -> String {
    format!("{} ×{}", r.id, r.substeps)
}

/// The file stem of a run's rendering.
fn file_stem(r: &ClothRun) -> String {
    format!("cloth_{}_x{}", r.id, r.substeps)
}

/// The frame interval (s).
fn frame_h(exp: &ClothExperiment) -> f64 {
    1.0 / exp.scene.simulation.frame_rate
}

/// Write `cloth_runs.csv`, `cloth_energy.svg` and the renderings; returns
/// the file names written.
fn write_files(exp: &ClothExperiment, dir: &Path) -> Result<Vec<String>, PaperError> {
    let mut files = Vec::new();
    // CSV: one row per run.
    let mut csv = String::from(
        "method,substeps,h,h_omega_max,completed,end_time,max_relative_energy_error,final_relative_energy_error,stepping_seconds,ms_per_frame,newton_per_step,stopped\n",
    );
    for r in &exp.runs {
        let ms = ms_per_frame(r);
        let _ = writeln!(
            csv,
            "{},{},{:e},{:.4},{},{},{:e},{:e},{:e},{:e},{},{}",
            csv_field(r.id),
            r.substeps,
            r.h,
            r.h_omega,
            r.stopped.is_none(),
            r.end_time(),
            r.max_error(exp.e_ref),
            r.final_error(exp.e_ref),
            r.stepping_seconds,
            ms,
            r.newton_per_step
                .map_or("NaN".into(), |n| format!("{n:.2}")),
            csv_field(
                &r.stopped
                    .as_ref()
                    .map(ToString::to_string)
                    .unwrap_or_default()
            )
        );
    }
    write(&dir.join("cloth_runs.csv"), &csv)?;
    files.push("cloth_runs.csv".to_string());

    // The energy plot: |H − H₀|/E_ref against time, log axis.
    let series: Vec<Series> = exp
        .runs
        .iter()
        .map(|r| {
            let rel = relative_errors(&r.frames, exp.e_ref);
            Series {
                name: label(r),
                points: r
                    .frames
                    .iter()
                    .zip(rel)
                    .map(|(f, e)| (f.time, e.abs()))
                    .collect(),
                markers: r.frames.len() < 20,
            }
        })
        .collect();
    let title = format!(
        "Paper cloth ({}×{}, undamped): |H − H₀|/E_ref, E_ref = {:.3e} J",
        exp.scene.cloth.nx, exp.scene.cloth.ny, exp.e_ref
    );
    plot::lines(
        &dir.join("cloth_energy.svg"),
        &Plot {
            title: &title,
            // Log time: the runs at one step per frame end within 0.1 s.
            x_label: "t (s)",
            y_label: "|H − H₀| / E_ref",
            log_x: true,
            log_y: true,
            series: &series,
        },
    )?;
    files.push("cloth_energy.svg".to_string());

    // Renderings of the last good frame of the substepped runs; one camera
    // for the runs that completed, its own for a run that blew up.
    let stage = Stage {
        colliders: exp.scene.colliders.clone(),
        triangles: Simulation::new(&exp.scene)?.model.triangles(),
        nx: exp.scene.cloth.nx,
    };
    let shown: Vec<&ClothRun> = exp.runs.iter().filter(|r| r.substeps > 1).collect();
    let good: Vec<Vec3> = shown
        .iter()
        .filter(|r| r.stopped.is_none())
        .flat_map(|r| r.last_positions.iter().copied())
        .collect();
    let shared = (!good.is_empty()).then(|| Camera::fit(&good, &exp.scene.colliders));
    for r in shown {
        let f = r.frames.last().map_or(0, |f| f.frame);
        let (positions, caption) = match &r.blowing_up {
            Some((step, t, rel, positions)) => (
                positions,
                format!(
                    "paper cloth · {} ×{} · step {step} · t = {t:.4} s · |ΔH|/E_ref = {rel:.2e} (blowing up)",
                    r.id, r.substeps
                ),
            ),
            None => (
                &r.last_positions,
                format!(
                    "paper cloth · {} · {} steps/frame · frame {f} · t = {:.3} s{}",
                    r.id,
                    r.substeps,
                    r.end_time(),
                    if r.stopped.is_some() {
                        " (the last good frame)"
                    } else {
                        ""
                    }
                ),
            ),
        };
        let camera = match (&r.stopped, shared) {
            (None, Some(c)) => c,
            _ => Camera::fit(positions, &exp.scene.colliders),
        };
        let name = format!("{}.png", file_stem(r));
        let picture = rasterise(&stage, &camera, positions);
        let caption = picture.caption(&caption);
        let image = picture.image;
        plot::captioned_png(
            &dir.join(&name),
            (image.width, image.height),
            image.rgb,
            &caption,
        )?;
        files.push(name);
    }
    Ok(files)
}

fn ms_per_frame(r: &ClothRun) -> f64 {
    let frames = r.frames.len().saturating_sub(1);
    if r.stopped.is_none() && frames > 0 {
        1e3 * r.stepping_seconds / frames as f64
    } else {
        f64::NAN
    }
}

/// The report's section (without its heading), one function per part.
fn markdown(exp: &ClothExperiment, files: &[String]) -> String {
    let mut w = String::new();
    claim(&mut w);
    this_run(&mut w, exp, files);
    runs_table(&mut w, exp);
    one_step_explicit(&mut w, exp);
    grid_limits(&mut w, exp);
    minimisation(&mut w, exp);
    implicit_one_step(&mut w, exp);
    substepped(&mut w, exp);
    contrast(&mut w, exp);
    cost(&mut w, exp);
    inextensible(&mut w, exp);
    w
}

/// The report: the paper's claim, in its words.
fn claim(w: &mut String) {
    let _ = writeln!(
        w,
        "**The paper's claim.** On \"a rectangle cloth surface, initially horizontal, attached along one of its \
         edges\", density 13.78 g/m², stiffness 50.75, no damping, with \"constant time-step of 16.7 milliseconds\", \
         explicit Euler's result is \"not satisfactory\" while symplectic Euler \"shows stable and reasonable \
         dynamic behaviors\" (their figure 5, pictures only, no numbers). Implicit methods were omitted as too slow.\n"
    );
}

/// The report: what this run is: the scene, its scales, the files.
fn this_run(w: &mut String, exp: &ClothExperiment, files: &[String]) {
    let sc = &exp.scene;
    let hf = frame_h(exp);
    let _ = writeln!(
        w,
        "**This run.** `scenes/paper.toml`: {:.0} m × {:.0} m, {}×{} particles pinned along one edge, stretch and shear \
         springs of stiffness 50.75 N per unit strain (the paper does not give the unit; see the scene file), gravity, \
         no damping, {} frames at {} Hz ({:.1} s). At rest ω_max = {:.1} rad/s (power iteration on M⁻¹K), so the \
         explicit stability limit is 2/ω_max = {:.3e} s and one step per frame is h·ω_max = {:.0}. \
         Relative energy errors are |H − H₀|/E_ref with E_ref = {:.3e} J, the energy of the cloth falling by its own \
         size; a run stops once it exceeds {BLOWUP} (blow-up). Files: {}.\n",
        sc.cloth.width,
        sc.cloth.height,
        sc.cloth.nx,
        sc.cloth.ny,
        exp.frames,
        sc.simulation.frame_rate,
        exp.frames as f64 / sc.simulation.frame_rate,
        exp.omega_max,
        exp.h_max,
        hf * exp.omega_max,
        exp.e_ref,
        files
            .iter()
            .map(|f| format!("`{f}`"))
            .collect::<Vec<_>>()
            .join(", ")
    );
}

/// The report: one row per run.
fn runs_table(w: &mut String, exp: &ClothExperiment) {
    let _ = writeln!(
        w,
        "| method | steps per frame | h (s) | h·ω_max | outcome | max \\|H − H₀\\|/E_ref | final (H − H₀)/E_ref | ms stepping per frame | Newton its/step |"
    );
    let _ = writeln!(w, "|---|---:|---:|---:|---|---:|---:|---:|---:|");
    for r in &exp.runs {
        let _ = writeln!(
            w,
            "| {} | {} | {:.3e} | {:.2} | {} | {} | {} | {} | {} |",
            r.name,
            r.substeps,
            r.h,
            r.h_omega,
            r.stopped.as_ref().map_or_else(
                || format!("completed {:.1} s", r.end_time()),
                ToString::to_string
            ),
            format::sci(r.max_error(exp.e_ref), 2),
            format::sci(r.final_error(exp.e_ref), 2),
            format::fixed(ms_per_frame(r), 2),
            format::opt(r.newton_per_step, |n| format::fixed(n, 1)),
        );
    }
    let _ = writeln!(w);
}

/// The report: where this differs from the paper: every explicit method at one step per frame.
fn one_step_explicit(w: &mut String, exp: &ClothExperiment) {
    let hf = frame_h(exp);
    // What the numbers say, from the numbers.
    let one_step_explicit: Vec<&ClothRun> = exp
        .runs
        .iter()
        .filter(|r| r.substeps == 1 && method_of(r.id).is_some_and(|m| m.explicit()))
        .collect();
    let all_blew = one_step_explicit.iter().all(|r| r.stopped.is_some());
    let longest = one_step_explicit
        .iter()
        .map(|r| r.frames.len().saturating_sub(1))
        .max()
        .unwrap_or(0);
    let _ = writeln!(w, "**Where this differs from the paper.**\n");
    if all_blew {
        let _ = writeln!(
            w,
            "- With one step per 16.7 ms frame **every explicit method blows up, symplectic Euler included** (the \
             longest lasted {longest} good step(s)): h·ω_max = {:.0} is far beyond the limit h·ω_max ≤ 2 of symplectic \
             Euler and Störmer–Verlet. Symplecticity bounds the energy error only where the step is stable; it does \
             not extend the stability limit. The paper's figure 5 therefore cannot show one explicit step of 16.7 ms \
             on this cloth.",
            hf * exp.omega_max
        );
    } else {
        let _ = writeln!(
            w,
            "- With one step per 16.7 ms frame, not every explicit method blew up within {} frames (see the table): \
             h·ω_max = {:.0}.",
            exp.frames,
            hf * exp.omega_max
        );
    }
}

/// The report: nor on a coarser grid: 2/ω_max per resolution, and what one explicit step per frame would need.
fn grid_limits(w: &mut String, exp: &ClothExperiment) {
    let sc = &exp.scene;
    let hf = frame_h(exp);
    let coarsest = exp.grids.first();
    let largest = exp.grids.iter().map(|g| g.h_max).fold(0.0f64, f64::max);
    let _ = writeln!(
        w,
        "- Nor on any coarser grid of the same cloth: 2/ω_max at rest for n×n particles pinned along one edge —"
    );
    let _ = writeln!(w);
    let _ = writeln!(
        w,
        "  | n × n | particle mass (kg) | ω_max (rad/s) | 2/ω_max (s) | 16.7 ms / (2/ω_max) |"
    );
    let _ = writeln!(w, "  |---|---:|---:|---:|---:|");
    for g in &exp.grids {
        let _ = writeln!(
            w,
            "  | {}×{} | {:.3e} | {:.1} | {:.3e} | {:.1} |",
            g.n,
            g.n,
            g.particle_mass,
            g.omega_max,
            g.h_max,
            hf / g.h_max
        );
    }
    let _ = writeln!(w);
    let soft = sc.material.stretch.unwrap_or(0.0) * (exp.h_max / hf).powi(2);
    let _ = writeln!(
        w,
        "  The largest limit, {:.2e} s{}, is {} the frame interval. On the 25×25 grid one explicit step per frame \
         would need springs {:.0} times softer (stiffness ≈ {:.1e} instead of 50.75, since h_max ∝ 1/√k), or \
         particles as many times heavier. So the paper's 16.7 ms is the frame interval of a simulation that \
         substeps (as here and as engines such as Bullet do), or its stiffness is in another unit or much \
         smaller than it reads; the paper does not say which.",
        largest,
        coarsest.map_or(String::new(), |g| format!(" (already at {}×{})", g.n, g.n)),
        if largest < hf {
            "shorter than"
        } else {
            "not shorter than"
        },
        50.75 / soft.max(f64::MIN_POSITIVE),
        soft,
    );
}

/// The report: the midpoint family and the AVF as minimisation at one step per frame.
fn minimisation(w: &mut String, exp: &ClothExperiment) {
    let mins: Vec<String> = exp
        .runs
        .iter()
        .filter(|r| {
            r.substeps == 1 && method_of(r.id).is_some_and(|m| m.midpoint_weights().is_some())
        })
        .map(|r| match &r.stopped {
            Some(why) => format!("{} {why}", r.name),
            None => format!(
                "{} ran to the end (max |H − H₀|/E_ref = {})",
                r.name,
                format::sci(r.max_error(exp.e_ref), 2)
            ),
        })
        .collect();
    if !mins.is_empty() {
        let _ = writeln!(
            w,
            "- The midpoint family as energy minimisation (`cloth::step::minimise`: Newton with the exact or PSD-projected Hessian and \
             a line search on the objective, solved to ‖∇Φ‖ ≤ 1e-12 of the force scale) at one step per frame: {}. \
             A robust solve does not make the method stable: the midpoint rule conserves energy only for quadratic \
             potentials, and on these stiff springs at h·ω_max ≈ {:.0} its energy is not bounded (Simo and Tarnow 1992).",
            mins.join("; "),
            frame_h(exp) * exp.omega_max
        );
    }
    if let Some(r) = exp
        .runs
        .iter()
        .find(|r| r.substeps == 1 && r.id == AVERAGE_VECTOR_FIELD)
    {
        let outcome = match &r.stopped {
            Some(why) => why.to_string(),
            None => format!(
                "ran to the end with max |H − H₀|/E_ref = {} (energy-conserving to the solver's tolerance)",
                format::sci(r.max_error(exp.e_ref), 2)
            ),
        };
        let _ = writeln!(
            w,
            "- For comparison, the average vector field discrete gradient (`--method avf`: energy and linear momentum \
             conserved, not symplectic), whose step is also a minimisation (its force is the gradient of a potential \
             averaged over the step) solved with the same Newton machinery, at one step per frame: {outcome}."
        );
    }
}

/// The report: the implicit methods at one step per frame.
fn implicit_one_step(w: &mut String, exp: &ClothExperiment) {
    let imp1: Vec<&ClothRun> = exp
        .runs
        .iter()
        .filter(|r| {
            r.substeps == 1
                && method_of(r.id).is_some_and(|m| m.mechanism() == Mechanism::StageSolver)
        })
        .collect();
    let imp_failed: Vec<String> = imp1
        .iter()
        .filter(|r| r.stopped.is_some())
        .map(|r| r.name.clone())
        .collect();
    if !imp_failed.is_empty() {
        let _ = writeln!(
            w,
            "- At 16.7 ms the implicit methods are stable in theory (A-stable) but their stage equations are not \
             solved here: {} failed (see the table). Released from rest with no transverse stiffness, the first row \
             of springs becomes stiff within the step (a slack cable pulled taut), and Newton's iteration does not \
             converge (a backtracking line search on the stage residual was tried and did not help). Smaller steps \
             do: see the runs at {IMPLICIT_SUBSTEPS} steps per frame.",
            imp_failed.join(" and ")
        );
    } else {
        let _ = writeln!(
            w,
            "- At 16.7 ms the implicit methods ran to the end (A-stable; the stage equations converged)."
        );
    }
}

/// The report: the paper's qualitative claim, once the step is stable.
fn substepped(w: &mut String, exp: &ClothExperiment) {
    let run = |id: &str, k: usize| exp.runs.iter().find(|r| r.id == id && r.substeps == k);
    let k_exp = exp.scene.simulation.substeps;
    // The substepped comparison: the paper's qualitative claim.
    if let (Some(eu), Some(se)) = (run("euler", k_exp), run("symplectic-euler-a", k_exp)) {
        let eu_text = match &eu.stopped {
            Some(why) => format!("explicit Euler {why}"),
            None => format!(
                "explicit Euler completed with max error {}",
                format::sci(eu.max_error(exp.e_ref), 2)
            ),
        };
        let se_text = match &se.stopped {
            Some(why) => format!("symplectic Euler {why}"),
            None => format!(
                "symplectic Euler's energy error stays bounded: at most {} over {:.1} s, {} at the end",
                format::sci(se.max_error(exp.e_ref), 2),
                se.end_time(),
                format::sci(se.final_error(exp.e_ref), 2)
            ),
        };
        let _ = writeln!(
            w,
            "- **The paper's qualitative claim holds once the step is stable.** At {k_exp} steps per frame \
             (h·ω_max = {:.2}), {eu_text}, while {se_text}. Explicit Euler multiplies the amplitude of every mode \
             by √(1 + h²ω²) per step, so no step size makes it stable on an undamped oscillation.{}",
            se.h_omega,
            eu.blowing_up.as_ref().map_or(String::new(), |(step, _, rel, _)| format!(
                " Its rendering shows the last state whose springs are at most doubled, step {step}: with \
                 |H − H₀|/E_ref = {} the sheet still looks nearly flat, because the unstable modes are the \
                 stiffest, in-plane ones, whose amplitude √(2E/K) stays small even at that energy; a few steps \
                 later the coordinates are astronomical. Explicit Euler's \
                 failure is sudden, not a slow visible drift.",
                format::sci(*rel, 2)
            ))
        );
    }
}

/// The report: Gauss–Legendre 2 and implicit Euler, substepped.
fn contrast(w: &mut String, exp: &ClothExperiment) {
    let hf = frame_h(exp);
    let run = |id: &str, k: usize| exp.runs.iter().find(|r| r.id == id && r.substeps == k);
    if let Some(g) = run("gauss2", IMPLICIT_SUBSTEPS) {
        let ie = run("implicit-euler", IMPLICIT_SUBSTEPS);
        let _ = writeln!(
            w,
            "- For contrast at {IMPLICIT_SUBSTEPS} steps per frame over {:.1} s: Gauss–Legendre 2 (symplectic, implicit) {}{}.",
            exp.frames.min(IMPLICIT_FRAMES) as f64 * hf,
            match &g.stopped {
                Some(why) => why.to_string(),
                None => format!(
                    "keeps the energy error at {} with {} ms of stepping per frame",
                    format::sci(g.max_error(exp.e_ref), 2),
                    format_args!("{:.1}", ms_per_frame(g))
                ),
            },
            ie.map_or(String::new(), |ie| match &ie.stopped {
                Some(why) => format!("; implicit Euler {why}"),
                None => format!(
                    "; implicit Euler, the usual choice of cloth simulators, loses energy to numerical damping: \
                     (H − H₀)/E_ref = {} at the end",
                    format::sci(ie.final_error(exp.e_ref), 2)
                ),
            })
        );
    }
}

/// The report: the cost per frame of symplectic Euler against Gauss–Legendre 2.
fn cost(w: &mut String, exp: &ClothExperiment) {
    let run = |id: &str, k: usize| exp.runs.iter().find(|r| r.id == id && r.substeps == k);
    let k_exp = exp.scene.simulation.substeps;
    if let (Some(se), Some(g)) = (
        run("symplectic-euler-a", k_exp),
        run("gauss2", IMPLICIT_SUBSTEPS),
    ) && se.stopped.is_none()
        && g.stopped.is_none()
    {
        let ratio = ms_per_frame(g) / ms_per_frame(se);
        let _ = writeln!(
            w,
            "- Cost, same run, same machine: symplectic Euler with {k_exp} substeps takes {:.2} ms of stepping per \
             60 Hz frame ({}), Gauss–Legendre 2 with {IMPLICIT_SUBSTEPS} takes {:.1} ms ({:.0}× as much). The \
             paper's reason to prefer explicit symplectic schemes — cost per frame — is borne out, but through \
             many cheap substeps, not one large step.",
            ms_per_frame(se),
            if ms_per_frame(se) < 1e3 / 60.0 {
                "faster than real time"
            } else {
                "slower than real time"
            },
            ms_per_frame(g),
            ratio
        );
    }
}

/// The report: RATTLE on the same sheet made inextensible.
fn inextensible(w: &mut String, exp: &ClothExperiment) {
    let Some(r) = exp
        .runs
        .iter()
        .find(|r| r.id == "rattle" && r.substeps == INEXTENSIBLE_SUBSTEPS)
    else {
        return;
    };
    let outcome = match &r.stopped {
        Some(why) => format!(
            "{why} (docs/results/cloth-inextensible.md: released flat, the undamped inextensible sheet cracks like a \
             whip when it swings back through the vertical, and a peak of tension outruns the step)"
        ),
        None => format!(
            "it ran the {:.1} s with max |H − H₀|/E_ref = {} and {} ms of stepping per frame ({} simplified \
             Newton iterations per step)",
            r.end_time(),
            format::sci(r.max_error(exp.e_ref), 2),
            format::fixed(ms_per_frame(r), 2),
            format::opt(r.newton_per_step, |n| format::fixed(n, 1)),
        ),
    };
    let _ = writeln!(
        w,
        "- **Not in the paper: the same sheet inextensible.** Its warp and weft springs made length constraints \
         (`material.stretch = \"inextensible\"`), its shear softened to {INEXTENSIBLE_SHEAR} N (RATTLE steps the \
         shear springs explicitly, and at 50.75 N they would set its step as the stretch springs set the explicit \
         methods'), stepped by RATTLE at {INEXTENSIBLE_SUBSTEPS} steps per frame (h = {:.3e} s, h·ω_max = {:.2} of \
         its soft springs): {outcome}.",
        r.h, r.h_omega
    );
}

/// One line per run, for the terminal.
pub(super) fn terminal(exp: &ClothExperiment) -> String {
    let mut s = String::new();
    for r in &exp.runs {
        let _ = writeln!(
            s,
            "  {:<20} ×{:<4} h·ω_max = {:>7.2}  {}",
            r.id,
            r.substeps,
            r.h_omega,
            match &r.stopped {
                Some(why) => why.to_string(),
                None => format!(
                    "completed, max |H − H₀|/E_ref = {}",
                    format::sci(r.max_error(exp.e_ref), 2)
                ),
            }
        );
    }
    s
}

/// What the cloth part produced.
pub(super) struct Section {
    /// The report's section (without its heading).
    pub markdown: String,
    /// The files written.
    pub files: Vec<String>,
    /// The runs; `None` when the comparison was skipped.
    pub experiment: Option<ClothExperiment>,
}

/// Run, write the files, return the section. `frames = 0` skips the
/// comparison (the section then says so).
/// The cloth section from the runs already `done` (a checkpoint's), asking
/// `go_on` after each new run; `None` when it said no.
pub(super) fn section(
    dir: &Path,
    frames: usize,
    done: Vec<ClothRun>,
    go_on: impl FnMut(&[ClothRun]) -> bool,
) -> Result<Option<Section>, PaperError> {
    if frames == 0 {
        return Ok(Some(Section {
            markdown: "Skipped (`--cloth-frames 0`); run `symlab paper` without it for the figure-5 comparison."
                .to_string(),
            files: Vec::new(),
            experiment: None,
        }));
    }
    let Some(exp) = experiment_from(frames, done, go_on)? else {
        return Ok(None);
    };
    let files = write_files(&exp, dir)?;
    Ok(Some(Section {
        markdown: markdown(&exp, &files),
        files,
        experiment: Some(exp),
    }))
}
