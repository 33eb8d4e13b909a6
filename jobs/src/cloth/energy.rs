//! The energy plot of a cloth run (the numbers are the cloth crate's:
//! `cloth::study::energy`).

use std::path::Path;

use cloth::FrameStats;
use cloth::study::energy::relative_errors;
use plotters::prelude::*;

use super::request::JobError;

/// Two panels: kinetic, potential and total energy against time, and the
/// relative energy error `|H − H₀|/E_ref` on a log axis. SVG or PNG by the
/// file's extension, 1000 × 800.
pub fn plot(path: &Path, frames: &[FrameStats], e_ref: f64, title: &str) -> Result<(), JobError> {
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
        _ => Err(format!("{}: plots are .svg or .png", path.display())),
    }
    .map_err(|e| {
        JobError::Output(format!(
            "{}: cannot draw the energy plot: {e}",
            path.display()
        ))
    })
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    frames: &[FrameStats],
    e_ref: f64,
    title: &str,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| format!("{e:?}");
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
