//! Line plots (SVG or PNG by the file's extension) with plotters, and the
//! font they need: DejaVu Sans, committed under `assets/fonts` (permissive
//! licence alongside), registered once, so no system library is needed.

use std::path::Path;
use std::sync::Once;

use crate::error::{CompareError, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

static FONT: Once = Once::new();

/// Register the committed font as `sans-serif` (idempotent).
pub fn register_font() {
    FONT.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
        // The font is committed and known to parse; failure would be a build defect.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

/// One line of a plot.
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    /// Draw markers at the points as well as the line.
    pub markers: bool,
}

/// What a plot shows.
pub struct Plot<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub log_x: bool,
    pub log_y: bool,
    pub series: &'a [Series],
}

/// Write the plot to `path` (`.svg` or `.png`, 1000×700). Points that a log
/// axis cannot show (≤ 0, non-finite) are dropped; a plot with no drawable
/// point is an error.
pub fn lines(path: &Path, plot: &Plot) -> Result<()> {
    register_font();
    let err = |why: String| CompareError::Plot {
        path: path.to_path_buf(),
        why,
    };
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    match ext {
        "svg" => {
            let root = SVGBackend::new(path, (1000, 700)).into_drawing_area();
            draw(&root, plot).map_err(err)?;
            root.present()
                .map_err(|e| err(format!("writing the file: {e}")))?;
        }
        "png" => {
            let root = BitMapBackend::new(path, (1000, 700)).into_drawing_area();
            draw(&root, plot).map_err(err)?;
            root.present()
                .map_err(|e| err(format!("writing the file: {e}")))?;
        }
        _ => return Err(err("plots are .svg or .png".into())),
    }
    Ok(())
}

/// Values beyond this magnitude are not drawn: widening an axis near
/// f64::MAX overflows to ∞, and plotters' tick search never ends there.
const MAX_ABS: f64 = 1e150;

fn drawable(plot: &Plot, x: f64, y: f64) -> bool {
    x.is_finite()
        && y.is_finite()
        && x.abs() < MAX_ABS
        && y.abs() < MAX_ABS
        && (!plot.log_x || x > 0.0)
        && (!plot.log_y || y > 0.0)
}

/// Tick labels: short scientific notation on log axes (`1e-11`, not
/// `1.0000000000000001e-11`), plotters' default otherwise.
fn tick(v: &f64, log: bool) -> String {
    if log {
        format!("{v:.0e}")
    } else {
        let a = v.abs();
        if a != 0.0 && !(1e-3..1e5).contains(&a) {
            format!("{v:.1e}")
        } else {
            format!("{v:.3}")
                .trim_end_matches('0')
                .trim_end_matches('.')
                .to_string()
        }
    }
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: &Plot,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| format!("{e:?}"))?;
    let pts: Vec<(f64, f64)> = plot
        .series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .filter(|&(x, y)| drawable(plot, x, y))
        .collect();
    if pts.is_empty() {
        return Err(format!("plot '{}' has no point to draw", plot.title));
    }
    let (mut x0, mut x1) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (mut y0, mut y1) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let widen = |lo: &mut f64, hi: &mut f64, log: bool| {
        if log {
            if *hi <= *lo {
                *hi = *lo * 10.0;
            }
            *lo /= 1.5;
            *hi *= 1.5;
        } else {
            let pad = if *hi > *lo {
                0.05 * (*hi - *lo)
            } else {
                1.0f64.max(lo.abs() * 0.1)
            };
            *lo -= pad;
            *hi += pad;
        }
    };
    widen(&mut x0, &mut x1, plot.log_x);
    widen(&mut y0, &mut y1, plot.log_y);
    let mut chart = ChartBuilder::on(root);
    chart
        .caption(plot.title, ("sans-serif", 24))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80);
    macro_rules! finish {
        ($c:expr) => {{
            let mut c = $c;
            let (lx, ly) = (plot.log_x, plot.log_y);
            let fx = move |v: &f64| tick(v, lx);
            let fy = move |v: &f64| tick(v, ly);
            c.configure_mesh()
                .x_label_formatter(&fx)
                .y_label_formatter(&fy)
                .x_desc(plot.x_label)
                .y_desc(plot.y_label)
                .label_style(("sans-serif", 14))
                .draw()
                .map_err(|e| format!("{e:?}"))?;
            for (k, s) in plot.series.iter().enumerate() {
                let color = Palette99::pick(k).to_rgba();
                let data: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .copied()
                    .filter(|&(x, y)| drawable(plot, x, y))
                    .collect();
                c.draw_series(LineSeries::new(data.clone(), color.stroke_width(2)))
                    .map_err(|e| format!("{e:?}"))?
                    .label(s.name.clone())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                if s.markers {
                    c.draw_series(data.iter().map(|&p| Circle::new(p, 3, color.filled())))
                        .map_err(|e| format!("{e:?}"))?;
                }
            }
            c.configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 14))
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(|e| format!("{e:?}"))?;
        }};
    }
    match (plot.log_x, plot.log_y) {
        (true, true) => finish!(
            chart
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(|e| format!("{e:?}"))?
        ),
        (true, false) => finish!(
            chart
                .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
                .map_err(|e| format!("{e:?}"))?
        ),
        (false, true) => finish!(
            chart
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .map_err(|e| format!("{e:?}"))?
        ),
        (false, false) => finish!(
            chart
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| format!("{e:?}"))?
        ),
    }
    Ok(())
}

/// An RGB bitmap (`width × height`, rows top to bottom, three bytes a
/// pixel) written as a PNG file with `caption` in its top-left corner: how
/// `symlab cloth` and `symlab paper` write the pictures that
/// `cloth::render` draws (the cloth crate has no image library).
pub fn captioned_png(
    path: &Path,
    (width, height): (u32, u32),
    rgb: Vec<u8>,
    caption: &str,
) -> Result<()> {
    register_font();
    let err = |why: String| CompareError::Plot {
        path: path.to_path_buf(),
        why,
    };
    let root = BitMapBackend::new(path, (width, height)).into_drawing_area();
    let bitmap = BitMapElement::with_owned_buffer((0, 0), (width, height), rgb)
        .ok_or_else(|| err("image buffer of the wrong size".into()))?;
    root.draw(&bitmap).map_err(|e| err(format!("{e:?}")))?;
    root.draw(&Text::new(
        caption.to_string(),
        (10, 10),
        ("sans-serif", 16).into_font().color(&BLACK),
    ))
    .map_err(|e| err(format!("{e:?}")))?;
    root.present()
        .map_err(|e| err(format!("cannot write the PNG: {e:?}")))
}
