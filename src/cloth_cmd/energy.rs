//! Energy bookkeeping of a cloth run: the reference energy that relative
//! errors are measured against, `energy.csv`, and the energy plot.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use anyhow::{Context, Result, anyhow, bail};
use cloth::{FrameStats, Scene, Simulation};
use plotters::prelude::*;

/// The header of `energy.csv`: the energy split, the relative energy error,
/// then everything `cloth::write_stats_csv` writes.
pub const ENERGY_CSV_HEADER: &str = "frame,step,time,kinetic,potential,total,relative_energy_error,springs,gravity,colliders,momentum_x,momentum_y,momentum_z,max_strain";

/// The strain of the elastic floor of [`reference_energy`]: 0.01 %.
pub const ELASTIC_FLOOR_STRAIN: f64 = 1e-4;

/// The energy that relative energy errors are divided by:
/// `E_ref = max(|H₀|, M·|g|·ℓ, E_ε)`, with `H₀` the initial energy, `M` the
/// mass of the free particles, `ℓ` the larger side of the cloth — the
/// energy of the cloth falling by its own size, which is what a hanging
/// sheet trades between kinetic and potential energy (the paper scene
/// starts at `H₀ = 0`) — and `E_ε = ½·Σ k·L·ε²`, `ε` = 0.01 %
/// ([`ELASTIC_FLOOR_STRAIN`]), the elastic energy of every spring with a
/// free end stretched by 0.01 %. The floor `E_ε` is what keeps a scene
/// with nothing to release (no gravity, starting at rest, `H₀` a round-off
/// 1e-31 J) from dividing round-off by round-off and "blowing up" at step
/// 3; on the shipped scenes it is far below the other two terms (3e-5 J on
/// the paper scene against `M·|g|·ℓ` = 0.13 J, still 2.5e-3 J at 2048 ×
/// 2048), so it changes nothing there.
/// For `symlab paper`, which reads it as a number: 1 J when the scene has
/// no energy scale at all, the value of [`reference_energy_checked`]
/// otherwise.
pub fn reference_energy(scene: &Scene, sim: &Simulation) -> f64 {
    reference_energy_checked(scene, sim).unwrap_or(1.0)
}

/// [`reference_energy`], or an error naming what makes it unusable: zero
/// (nothing in the scene can exchange energy: no gravity, no spring with a
/// free end, nothing stored at the start) or not finite (the scales
/// overflow).
pub fn reference_energy_checked(scene: &Scene, sim: &Simulation) -> Result<f64> {
    let h0 = sim.stats().energy.total().abs();
    let m = sim.model.particle_mass() * sim.model.free_count() as f64;
    // |g| without overflowing the squares (gravity = [0, -1e200, 0]).
    let g = sim.model.gravity().iter().fold(0.0f64, |a, x| a.hypot(*x));
    let size = scene.cloth.width.max(scene.cloth.height) * scene.cloth.prestretch;
    let fall = m * g * size;
    let elastic = sim.model.elastic_energy_scale(ELASTIC_FLOOR_STRAIN);
    let e = h0.max(fall).max(elastic);
    if !e.is_finite() || e.is_nan() {
        let field = if !h0.is_finite() {
            "cloth"
        } else if !fall.is_finite() {
            "gravity"
        } else {
            "material"
        };
        bail!(
            "{field}: the reference energy E_ref = max(|H₀|, M·|g|·ℓ, ½·Σk·L·ε²) = max({h0:e}, {fall:e}, {elastic:e}) J is not finite"
        );
    }
    if e <= 0.0 {
        bail!(
            "gravity: the scene has no energy scale (no gravity, no spring with a free end, no energy at the start): E_ref = 0, so relative energy errors cannot be measured"
        );
    }
    Ok(e)
}

/// `(H − H₀)/E_ref` of each frame.
pub fn relative_errors(frames: &[FrameStats], e_ref: f64) -> Vec<f64> {
    let h0 = frames.first().map_or(0.0, |f| f.energy.total());
    frames
        .iter()
        .map(|f| (f.energy.total() - h0) / e_ref)
        .collect()
}

/// Write `energy.csv` (header [`ENERGY_CSV_HEADER`]).
pub fn write_csv(path: &Path, frames: &[FrameStats], e_ref: f64) -> Result<()> {
    let write = || -> std::io::Result<()> {
        let mut out = BufWriter::new(File::create(path)?);
        writeln!(out, "{ENERGY_CSV_HEADER}")?;
        for (f, rel) in frames.iter().zip(relative_errors(frames, e_ref)) {
            let e = &f.energy;
            writeln!(
                out,
                "{},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
                f.frame,
                f.step,
                f.time,
                e.kinetic,
                e.potential(),
                e.total(),
                rel,
                e.springs,
                e.gravity,
                e.colliders,
                f.momentum.x,
                f.momentum.y,
                f.momentum.z,
                f.max_strain
            )?;
        }
        out.flush()
    };
    write().with_context(|| format!("{}: cannot write", path.display()))
}

/// Two panels: kinetic, potential and total energy against time, and the
/// relative energy error `|H − H₀|/E_ref` on a log axis. SVG or PNG by the
/// file's extension, 1000 × 800.
pub fn plot(path: &Path, frames: &[FrameStats], e_ref: f64, title: &str) -> Result<()> {
    compare::plot::register_font();
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    let size = (1000, 800);
    match ext {
        "svg" => draw(
            &SVGBackend::new(path, size).into_drawing_area(),
            frames,
            e_ref,
            title,
        ),
        "png" => draw(
            &BitMapBackend::new(path, size).into_drawing_area(),
            frames,
            e_ref,
            title,
        ),
        _ => Err(anyhow!("{}: plots are .svg or .png", path.display())),
    }
    .with_context(|| format!("{}: cannot draw the energy plot", path.display()))
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    frames: &[FrameStats],
    e_ref: f64,
    title: &str,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("{e:?}");
    root.fill(&WHITE).map_err(err)?;
    let root = root.titled(title, ("sans-serif", 22)).map_err(err)?;
    let (top, bottom) = root.split_vertically(430);
    let t: Vec<f64> = frames.iter().map(|f| f.time).collect();
    let (t0, t1) = (
        t.first().copied().unwrap_or(0.0),
        t.last().copied().unwrap_or(1.0),
    );
    let t1 = if t1 > t0 { t1 } else { t0 + 1.0 };
    let series: [(&str, Vec<f64>, RGBColor); 3] = [
        (
            "kinetic",
            frames.iter().map(|f| f.energy.kinetic).collect(),
            RGBColor(220, 50, 32),
        ),
        (
            "potential",
            frames.iter().map(|f| f.energy.potential()).collect(),
            RGBColor(0, 114, 178),
        ),
        (
            "total",
            frames.iter().map(|f| f.energy.total()).collect(),
            BLACK,
        ),
    ];
    let finite = series
        .iter()
        .flat_map(|s| s.1.iter().copied())
        .filter(|v| v.is_finite());
    let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    let (lo, hi) = if lo.is_finite() && hi > lo {
        let pad = 0.05 * (hi - lo);
        (lo - pad, hi + pad)
    } else {
        (-1.0, 1.0)
    };
    let mut chart = ChartBuilder::on(&top)
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(t0..t1, lo..hi)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc("energy (J)")
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    for (name, values, color) in series {
        let pts: Vec<(f64, f64)> = t
            .iter()
            .copied()
            .zip(values)
            .filter(|p| p.1.is_finite())
            .collect();
        chart
            .draw_series(LineSeries::new(pts, color.stroke_width(2)))
            .map_err(err)?
            .label(name)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(err)?;

    let rel: Vec<(f64, f64)> = t
        .iter()
        .copied()
        .zip(relative_errors(frames, e_ref))
        .map(|(t, e)| (t, e.abs()))
        .filter(|p| p.1 > 0.0 && p.1.is_finite())
        .collect();
    let (lo, hi) = rel
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    let (lo, hi) = if lo.is_finite() {
        (lo / 2.0, (hi * 2.0).max(lo * 10.0))
    } else {
        (1e-16, 1.0)
    };
    let mut chart = ChartBuilder::on(&bottom)
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(t0..t1, (lo..hi).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc(format!("|H − H₀| / {e_ref:.3e} J"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    let color = RGBColor(0, 158, 115);
    chart
        .draw_series(LineSeries::new(rel, color.stroke_width(2)))
        .map_err(err)?
        .label("relative energy error")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .position(SeriesLabelPosition::LowerRight)
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}
