//! `report.md`: what the paper claimed, what this run measured, where they
//! differ. Every number is taken from the runs of the experiment and from
//! the [`Findings`] the library derives from them; this module only
//! formats. One file per section, in the report's order.

mod claims;
mod comparison;
mod measured;
mod setup;
mod tables;
mod typos;

use std::fmt::Write as _;

use compare::format::{self, MISSING};
use compare::paper_oscillator::{Experiment, Findings};

pub use tables::{markdown_table, text_table};

/// An error or a size as the report prints it: three significant digits.
fn sci2(x: f64) -> String {
    format::sci(x, 2)
}

fn yes_no(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

/// `format::times` of `f(h₂)/f(h₁)` for consecutive step sizes, as "×N from h = a to h = b".
fn growth_with_h(sorted: &[f64], f: impl Fn(f64) -> f64) -> String {
    let parts: Vec<String> = sorted
        .windows(2)
        .map(|p| {
            format!(
                "{} from h = {} to h = {}",
                format::times(f(p[1]), f(p[0])),
                p[0],
                p[1]
            )
        })
        .collect();
    if parts.is_empty() {
        MISSING.into()
    } else {
        parts.join(", ")
    }
}

/// The whole report. `cloth` is the cloth section (figure 5, without its
/// heading); `files` the names of the files written alongside.
pub fn markdown(exp: &Experiment, cloth: &str, files: &[String]) -> String {
    let f = Findings::of(exp);
    let mut s = String::new();
    let w = &mut s;
    setup::write(w, exp, &f);
    claims::write(w);
    measured::write(w, exp, &f);
    comparison::write(w, exp, &f);
    typos::write(w, exp, &f);
    cloth_section(w, cloth);
    files_section(w, files);
    s
}

/// The cloth comparison of figure 5, as the cloth part wrote it.
fn cloth_section(w: &mut String, cloth: &str) {
    let _ = writeln!(w, "## The cloth comparison (figure 5)\n");
    let _ = writeln!(w, "{}\n", cloth.trim_end());
}

/// The files written alongside the report.
fn files_section(w: &mut String, files: &[String]) {
    let _ = writeln!(w, "## Files\n");
    for name in files {
        let _ = writeln!(w, "- `{name}`");
    }
}
