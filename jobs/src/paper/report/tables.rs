//! The table of every run, for the report and for the terminal.

use std::fmt::Write as _;

use compare::paper_oscillator::{Experiment, h_name};

use super::{sci2, yes_no};

/// The measured table, Markdown: one row per (h, method).
pub fn markdown_table(exp: &Experiment) -> String {
    let mut s = String::from(
        "| h | method | order | symplectic | max \\|Δq\\| | max \\|Δp\\| | max \\|ΔH\\|/H₀ | final \\|Δq\\| | final phase error (rad) |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for r in &exp.runs {
        let m = r.summary();
        let info = r.method.info();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:+.2e} |",
            h_name(r.h),
            match &r.failure {
                Some(why) => format!("{} ({why})", r.method.label()),
                None => r.method.label().to_string(),
            },
            info.order,
            yes_no(info.symplectic),
            sci2(m.max_err_q),
            sci2(m.max_err_p),
            sci2(m.max_rel_energy_error),
            sci2(m.final_err_q.abs()),
            m.final_phase_error,
        );
    }
    s
}

/// The same table as plain text for the terminal.
pub fn text_table(exp: &Experiment) -> String {
    let mut s = format!(
        "{:>6}  {:<18} {:>10} {:>10} {:>12} {:>10}\n",
        "h", "method", "max|Δq|", "max|Δp|", "max|ΔH|/H₀", "phase"
    );
    for r in &exp.runs {
        let m = r.summary();
        let _ = writeln!(
            s,
            "{:>6}  {:<18} {:>10} {:>10} {:>12} {:>+10.2e}{}",
            h_name(r.h),
            r.method.label(),
            sci2(m.max_err_q),
            sci2(m.max_err_p),
            sci2(m.max_rel_energy_error),
            m.final_phase_error,
            r.failure
                .as_ref()
                .map_or(String::new(), |why| format!("  stopped: {why}"))
        );
    }
    s
}
