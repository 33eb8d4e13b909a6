//! The springs at equal stretch (`symlab cloth SCENE --equal-stretch`):
//! the spring model and the constrained model of an inextensible scene
//! side by side ([`cloth::study::equal_stretch`] runs them), as a table to
//! print and `equal_stretch.csv`.

use std::fmt::Write as _;
use std::fs;
use std::path::PathBuf;

use cloth::study::equal_stretch::{
    AIM, BRACKET, CLOSE, EqualStretchError, EqualStretchSettings, PEAK_FACTOR, SPRING_METHOD,
    Sampled, check, study,
};
use compare::format;
use compare::output::csv_field;

use super::plan::{output_dir, rename};
use super::request::{Field, InputError, JobError, Request, SceneSource};

/// The study as asked: the scene (at `grid`), the frames (default the
/// scene's), the output folder.
#[derive(Clone, Debug)]
pub struct EqualStretchRequest {
    pub scene: SceneSource,
    pub grid: Option<String>,
    pub frames: Option<usize>,
    pub out: Option<PathBuf>,
}

/// A stretch as a percentage.
fn percent(s: f64) -> String {
    if s.is_finite() {
        format!("{:.3} %", 100.0 * s)
    } else {
        "failed".to_string()
    }
}

/// Run the study, write `equal_stretch.csv`; the table to print.
pub fn run(asked: &EqualStretchRequest) -> Result<String, JobError> {
    let request = Request {
        grid: asked.grid.clone(),
        out: asked.out.clone(),
        ..Request::new(asked.scene.clone())
    };
    let file = asked.scene.file_name();
    let scene = super::plan::load(&request)?.0;
    let frames = asked.frames.unwrap_or(scene.simulation.frames);
    if frames == 0 {
        return Err(InputError::field_value(
            Field::Frames,
            "0",
            "must be at least 1: the study measures a run",
        )
        .into());
    }
    if frames > cloth::MAX_FRAMES {
        return Err(InputError::field_value(
            Field::Frames,
            frames.to_string(),
            format!("more than the limit of {} frames", cloth::MAX_FRAMES),
        )
        .into());
    }
    let settings = EqualStretchSettings::new(frames);
    let refuse = |e: EqualStretchError| -> JobError {
        match e {
            EqualStretchError::NotInextensible | EqualStretchError::NoGravity => {
                InputError::scene(&file, None, e.to_string()).into()
            }
            EqualStretchError::Setting {
                field: "frames",
                message,
            } => InputError::field(Field::Frames, message).into(),
            EqualStretchError::Scene(e) => JobError::Scene(rename(&e, &file)),
            EqualStretchError::Reference(r) => {
                InputError::scene(&file, Some(r.field), r.message).into()
            }
            other => JobError::Run(other.to_string()),
        }
    };
    check(&scene, &settings).map_err(refuse)?;
    let dir = output_dir(&request, &scene)?;
    let found = study(&scene, &settings).map_err(refuse)?;
    let (nx, ny) = found.grid;
    let (dx, dy) = found.rest;
    let bound = found.max_stretch;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "springs against constraints at equal stretch: {} ({file}), {nx} × {ny} particles, {} frames ({:.3} s simulated) at {} Hz",
        scene.name, found.frames, found.duration, scene.simulation.frame_rate
    );
    let _ = writeln!(
        out,
        "the springs: the scene's warp and weft edges as stretch springs (no isometric bending, which a spring scene cannot have), {SPRING_METHOD} at substeps = \"auto\" (0.9 of 2/ω, ω from Gershgorin's bound); stiffness k per unit strain (N), k/Δx = k/{dx:.4e} m and k/Δy = k/{dy:.4e} m as linear springs (N/m)"
    );
    let _ = writeln!(
        out,
        "the rule: the first k whose warp and weft stretch, measured at every step of the whole run, is within [{}, {}]: k₀ = {PEAK_FACTOR}·(ny − 1)·m·|g|/{} (the static tension at the top of a column, {PEAK_FACTOR}×), then k·s/({}), or the geometric mean of the softest k that passed and the stiffest that failed where that is not between them; else, after {} trials or with those two within {} %, the softest that passed",
        percent(CLOSE * bound),
        percent(bound),
        percent(bound),
        percent(AIM * bound),
        settings.max_trials,
        format::fixed(100.0 * (BRACKET - 1.0), 0)
    );
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "{:>5} {:>12} {:>12} {:>8} {:>12} {:>14}",
        "trial", "k (N)", "k/Δx (N/m)", "steps/fr", "max stretch", "max |ΔH|/E_ref"
    );
    for (i, t) in found.trials.iter().enumerate() {
        let _ = writeln!(
            out,
            "{:>5} {:>12.4e} {:>12.4e} {:>8} {:>12} {:>14.3e}{}{}",
            i + 1,
            t.stiffness,
            t.stiffness / dx,
            t.substeps,
            percent(t.max_stretch),
            t.max_energy_error,
            if i == found.taken { "  ← taken" } else { "" },
            t.failed
                .as_ref()
                .map_or(String::new(), |f| format!("  ({f})"))
        );
    }
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "{:<32} {:>11} {:>11} {:>9} {:>3} {:>15} {:>10} {:>14} {:>11}",
        "model",
        "k (N)",
        "k/Δx (N/m)",
        "B (N·m)",
        "thr",
        "steps/frame",
        "ms/frame",
        "max |ΔH|/E_ref",
        "max stretch"
    );
    let mut csv = String::from(
        "model,method,stiffness_n,stiffness_n_per_m,bending_n_m,threads,frames,duration_s,steps,steps_per_frame_min,steps_per_frame_mean,steps_per_frame_max,stepping_seconds,ms_per_frame,e_ref_j,max_relative_energy_error,max_stretch,stretch_sampled,max_stretch_at_frames\n",
    );
    for r in &found.rows {
        let m = &r.run;
        let (lo, mean, hi) = m.steps_per_frame;
        let steps = if lo == hi {
            format!("{lo}")
        } else {
            format!("{lo}–{hi}, mean {mean:.2}")
        };
        let ms = 1e3 * m.seconds_per_frame();
        let stretch = match r.sampled {
            Sampled::EveryStep => percent(r.max_stretch),
            Sampled::EveryFrame => format!("{:.2e}", r.max_stretch),
        };
        let _ = writeln!(
            out,
            "{:<32} {:>11} {:>11} {:>9} {:>3} {:>15} {:>10.3} {:>14.3e} {:>11}",
            r.model,
            r.stiffness.map_or("—".to_string(), |k| format!("{k:.4e}")),
            r.stiffness
                .map_or("—".to_string(), |k| format!("{:.4e}", k / dx)),
            if r.bending > 0.0 {
                format!("{:.1e}", r.bending)
            } else {
                "0".to_string()
            },
            r.threads,
            steps,
            ms,
            m.max_energy_error,
            stretch
        );
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:e},{:e},{},{:e}",
            csv_field(&r.model),
            r.method,
            r.stiffness.map_or(String::new(), |k| format!("{k:e}")),
            r.stiffness
                .map_or(String::new(), |k| format!("{:e}", k / dx)),
            r.bending,
            r.threads,
            m.frames,
            m.duration,
            m.steps,
            lo,
            mean,
            hi,
            m.stepping_seconds,
            ms,
            m.e_ref,
            m.max_energy_error,
            r.max_stretch,
            match r.sampled {
                Sampled::EveryStep => "every step",
                Sampled::EveryFrame => "every frame",
            },
            m.max_stretch,
        );
    }
    let _ = writeln!(out);
    let springs_frames = found
        .rows
        .iter()
        .find(|r| r.sampled == Sampled::EveryStep)
        .map(|r| r.run.max_stretch);
    let _ = writeln!(
        out,
        "max stretch: the largest |ℓ − L|/L of a warp or weft edge; the springs' at every step of the trial taken (their timed run, sampled at the frames: {}), RATTLE's at every frame (its constraint violation; each step solves the constraints to round-off)",
        springs_frames.map_or("—".to_string(), percent)
    );
    let _ = writeln!(
        out,
        "ms/frame: stepping time per {} Hz frame, the energy and stretch measurements excluded; max |ΔH|/E_ref = max over the frames of |H − H₀|/E_ref (E_ref = {:.4e} J)",
        scene.simulation.frame_rate,
        found.rows.first().map_or(f64::NAN, |r| r.run.e_ref)
    );
    let time = |pick: &dyn Fn(&cloth::study::equal_stretch::Row) -> bool| {
        found
            .rows
            .iter()
            .find(|r| pick(r))
            .map(|r| r.run.seconds_per_frame())
    };
    if let (Some(s), Some(c)) = (
        time(&|r| r.stiffness.is_some() && r.threads == 1),
        time(&|r| r.stiffness.is_none() && r.bending == 0.0),
    ) {
        let _ = writeln!(
            out,
            "RATTLE without bending / springs on one thread, time per frame: {:.2}×",
            c / s
        );
    }
    let path = dir.join("equal_stretch.csv");
    fs::write(&path, csv).map_err(|e| JobError::io(&path, "cannot write", e))?;
    let _ = writeln!(out, "table in {}", path.display());
    Ok(out)
}
