//! The oscillator's plots, the counterparts of the paper's figures 2–4: per
//! step size, `q(t)` and `p(t)` of every method against the exact solution,
//! and `|H − H₀|` against time on a log axis.

use std::path::{Path, PathBuf};

use anyhow::Result;

use compare::paper_oscillator::{ENERGY_CEILING, ENERGY_FLOOR, Experiment, h_name};
use compare::plot::{self, Plot, Series};

/// The file names of the three plots at step size `h`.
pub fn plot_names(h: f64) -> [String; 3] {
    [
        format!("oscillator_h{}_q.svg", h_name(h)),
        format!("oscillator_h{}_p.svg", h_name(h)),
        format!("oscillator_h{}_energy.svg", h_name(h)),
    ]
}

/// Write the three plots of step size `h` into `dir`; returns their paths.
pub fn write_plots(exp: &Experiment, h: f64, dir: &Path) -> Result<Vec<PathBuf>> {
    let runs: Vec<_> = exp.at(h).collect();
    // The longest run carries the exact solution (a run may stop early).
    let Some(first) = runs.iter().max_by_key(|r| r.t.len()) else {
        return Ok(Vec::new());
    };
    let steps = first.steps();
    let [q_name, p_name, e_name] = plot_names(h);
    let mut written = Vec::new();

    for (name, what, exact, num) in [
        (&q_name, "q", &first.q_exact, 0usize),
        (&p_name, "p", &first.p_exact, 1usize),
    ] {
        let mut series = vec![Series {
            name: "analytic".into(),
            points: first.t.iter().copied().zip(exact.iter().copied()).collect(),
            markers: false,
        }];
        for r in &runs {
            let values = if num == 0 { &r.q } else { &r.p };
            series.push(Series {
                name: r.method.label().into(),
                points: r.t.iter().copied().zip(values.iter().copied()).collect(),
                markers: false,
            });
        }
        let title = format!("Oscillator, h = {h}, {steps} steps: {what}(t)");
        let path = dir.join(name);
        plot::lines(
            &path,
            &Plot {
                title: &title,
                x_label: "t",
                y_label: what,
                log_x: false,
                log_y: false,
                series: &series,
            },
        )?;
        written.push(path);
    }

    let series: Vec<Series> = runs
        .iter()
        .map(|r| Series {
            name: r.method.label().into(),
            points: r
                .t
                .iter()
                .zip(&r.energy_error)
                .map(|(&t, &e)| (t, e.abs().clamp(ENERGY_FLOOR, ENERGY_CEILING)))
                .collect(),
            markers: false,
        })
        .collect();
    let clipped = runs.iter().any(|r| {
        r.energy_error
            .iter()
            .any(|e| e.is_nan() || e.abs() > ENERGY_CEILING)
    });
    let title = if clipped {
        format!(
            "Oscillator, h = {h}: |H − H₀| (floored at {ENERGY_FLOOR:e}, clipped at {ENERGY_CEILING:e})"
        )
    } else {
        format!("Oscillator, h = {h}: |H − H₀| (floored at {ENERGY_FLOOR:e})")
    };
    let path = dir.join(&e_name);
    plot::lines(
        &path,
        &Plot {
            title: &title,
            x_label: "t",
            y_label: "|H − H₀|",
            log_x: false,
            log_y: true,
            series: &series,
        },
    )?;
    written.push(path);
    Ok(written)
}
