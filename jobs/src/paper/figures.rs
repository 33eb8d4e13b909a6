//! The oscillator's files: the CSV of errors, the CSV of every step, and
//! the plots, the counterparts of the paper's figures 2–4: per step size,
//! `q(t)` and `p(t)` of every method against the exact solution, and
//! `|H − H₀|` against time on a log axis.

use std::path::Path;

use compare::paper_oscillator::{
    Config, ENERGY_CEILING, ENERGY_FLOOR, Experiment, errors_csv, h_name, series_csv,
};
use compare::plot::{self, Plot, Series};

use super::{PaperError, write};

/// The names of every file the oscillator part writes, in the report's order.
pub(super) fn oscillator_files(config: &Config) -> Vec<String> {
    let mut names = vec!["oscillator_errors.csv".to_string()];
    for &h in &config.step_sizes {
        names.push(format!("oscillator_h{}_series.csv", h_name(h)));
        names.extend(plot_names(h));
    }
    names
}

/// Write the oscillator's tables and plots into `dir`.
pub(super) fn write_oscillator(exp: &Experiment, dir: &Path) -> Result<(), PaperError> {
    write(&dir.join("oscillator_errors.csv"), &errors_csv(exp))?;
    for &h in &exp.config.step_sizes {
        write(
            &dir.join(format!("oscillator_h{}_series.csv", h_name(h))),
            &series_csv(exp, h),
        )?;
        write_plots(exp, h, dir)?;
    }
    Ok(())
}

/// The file names of the three plots at step size `h`.
fn plot_names(h: f64) -> [String; 3] {
    [
        format!("oscillator_h{}_q.svg", h_name(h)),
        format!("oscillator_h{}_p.svg", h_name(h)),
        format!("oscillator_h{}_energy.svg", h_name(h)),
    ]
}

/// Write the three plots of step size `h` into `dir` (none where no method
/// ran at `h`).
fn write_plots(exp: &Experiment, h: f64, dir: &Path) -> Result<(), PaperError> {
    let runs: Vec<_> = exp.at(h).collect();
    // The longest run carries the exact solution (a run may stop early).
    let Some(first) = runs.iter().max_by_key(|r| r.t.len()) else {
        return Ok(());
    };
    let steps = first.steps();
    let [q_name, p_name, e_name] = plot_names(h);

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
    Ok(())
}
