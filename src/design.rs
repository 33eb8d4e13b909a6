//! `symlab design FILE --out DIR`: run a family of methods (designs/*.toml)
//! through the design library and write its tables and report. Thin: the
//! library does the work and reports progress through a callback; this
//! module draws the bar (on a terminal) and prints the summary.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::Args;

#[derive(Args)]
pub struct DesignArgs {
    /// The family file (TOML; see designs/ and the guide's design chapter).
    pub file: PathBuf,
    /// Where to write the tables (*.toml) and report.md (created).
    #[arg(long)]
    pub out: PathBuf,
    /// Override the family's seed.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Override the family's number of starts.
    #[arg(long)]
    pub starts: Option<usize>,
}

pub fn run(args: &DesignArgs) -> Result<ExitCode> {
    let mut family = design::load_family(&args.file)?;
    if let Some(seed) = args.seed {
        family.seed = seed;
    }
    if let Some(starts) = args.starts {
        family.starts = starts;
    }
    let origin = args.file.display().to_string();
    family.validate(&origin)?;
    let bar = if std::io::stderr().is_terminal() {
        let bar = indicatif::ProgressBar::new(family.starts as u64);
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} starts, {msg} [{elapsed}]",
        ) {
            bar.set_style(style);
        }
        bar
    } else {
        indicatif::ProgressBar::hidden()
    };
    let outcome = design::design(&family, &origin, &mut |p| {
        bar.set_position(p.done as u64);
        bar.set_message(format!("{} solutions", p.found));
    })?;
    bar.finish_and_clear();
    let written = outcome
        .write(&args.out)
        .with_context(|| format!("writing into {}", args.out.display()))?;
    let s = &outcome.search;
    println!(
        "{}: {} starts in {:.2} s{}, {} distinct solutions; {} conditions on {} unknowns ({})",
        family.name,
        s.starts_run,
        s.elapsed.as_secs_f64(),
        if s.capped {
            " (stopped by the time cap)"
        } else {
            ""
        },
        s.solutions.len(),
        outcome.system.conditions.len(),
        outcome.system.unknowns(),
        outcome.system.names.join(", ")
    );
    for (i, d) in outcome.designs.iter().enumerate() {
        let proof = match (&d.exact, &d.certificate) {
            (Some(e), _) => format!("exact ({})", e.radicals.as_deref().unwrap_or(&e.root)),
            (_, Some(Ok(c))) => format!("certified, radius {}", c.radius),
            (_, Some(Err(e))) => format!("not certified: {e}"),
            (None, None) => "not polished".to_string(),
        };
        println!(
            "  {}. E_f = {:.6}, found {} times: {proof}",
            i + 1,
            d.solution.effective_error,
            d.solution.hits
        );
    }
    for p in written {
        println!("wrote {}", p.display());
    }
    Ok(ExitCode::SUCCESS)
}
