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
    /// Run the best designs (see --designs) beside library methods on this
    /// built-in problem (kepler, outer-solar, oscillator, …) in one
    /// work–precision sweep, as `symlab compare --table` does, and write its
    /// report (runs.csv, report.md, the plots) into DIR/compare/.
    #[arg(long, value_name = "PROBLEM", value_parser = crate::compare::problem_id)]
    pub compare: Option<compare::builtin::Builtin>,
    /// With --compare: the library methods to run beside the designs
    /// (comma-separated ids of `symlab list`, wh:ID on outer-solar; default:
    /// compare's references for table files on that problem).
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "ID,...",
        requires = "compare"
    )]
    pub methods: Option<Vec<String>>,
    /// With --compare: how many of the best proven designs to run (default 3).
    #[arg(long, value_name = "N", default_value_t = 3, requires = "compare")]
    pub designs: usize,
    /// With --compare: rank the proven designs by their error on the
    /// problem after N equal steps over its end time (the smallest first),
    /// instead of by the family's objective, before choosing --designs of
    /// them: the error measured on a named problem as the objective.
    #[arg(long, value_name = "N", requires = "compare", value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    pub rank_steps: Option<u64>,
    /// With --compare: run the designs on the problem's Wisdom–Holman
    /// split (outer-solar: Kepler drifts, interaction kicks), as the wh:
    /// methods are run (`symlab compare --table wh:FILE`); their times then
    /// compare with the wh: methods'.
    #[arg(long, requires = "compare")]
    pub wisdom_holman: bool,
    /// With --compare: the sweep's settings, as for `symlab compare`.
    #[command(flatten)]
    pub sweep: crate::compare::SweepFlags,
}

pub fn run(args: &DesignArgs) -> Result<ExitCode> {
    if args.compare.is_none()
        && let Some(flag) = args.sweep.request(false).any_given()
    {
        anyhow::bail!("{flag} belongs to --compare PROBLEM (the sweep's settings)");
    }
    let text = design::read_family_text(&args.file)?;
    if design::processed::is_corrector_family(&text) {
        return run_corrector(args);
    }
    let mut family = design::parse_family(&args.file.display().to_string(), &text)?;
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
        let stability = d
            .stability_per_stage(family.stages)
            .map_or(String::new(), |x| format!(", x*/s = {x:.6}"));
        println!(
            "  {}. E_f = {:.6}{stability}, found {} times: {proof}",
            i + 1,
            d.solution.effective_error,
            d.solution.hits
        );
    }
    for p in &written {
        println!("wrote {}", p.display());
    }
    if let Some(problem) = args.compare {
        let mut proven: Vec<PathBuf> = outcome
            .designs
            .iter()
            .filter(|d| d.exact.is_some() || matches!(d.certificate, Some(Ok(_))))
            .filter_map(|d| d.table.as_ref())
            .filter_map(|(name, _)| written.iter().find(|p| p.ends_with(name)).cloned())
            .collect();
        if let Some(steps) = args.rank_steps {
            proven = rank_on_problem(args, problem, proven, steps as usize)?;
        }
        proven.truncate(args.designs);
        compare_designs(args, problem, &proven)?;
    }
    Ok(ExitCode::SUCCESS)
}

/// A second-corrector family (`form = "second-corrector"`,
/// [`design::processed`]): one unknown, solved exactly, no search, so
/// `--seed` and `--starts` do not apply.
fn run_corrector(args: &DesignArgs) -> Result<ExitCode> {
    for (flag, given) in [
        ("--seed", args.seed.is_some()),
        ("--starts", args.starts.is_some()),
    ] {
        if given {
            anyhow::bail!(
                "{flag}: {} is a {} family, solved exactly with no random starts",
                args.file.display(),
                design::processed::FORM
            );
        }
    }
    let family = design::processed::load_corrector_family(&args.file)?;
    let origin = args.file.display().to_string();
    let d = design::processed::design_corrector(&family, &origin)?;
    let written = d
        .write(&args.out)
        .with_context(|| format!("writing into {}", args.out.display()))?;
    println!(
        "{}: a second corrector for {}: c² = {} exactly, c = {} ≈ {}; effective generalised order {} without it, {} with it",
        family.name,
        family.kernel,
        d.c_squared,
        d.c,
        d.c.approx_text(),
        d.orders_before,
        d.orders_after
    );
    for p in &written {
        println!("wrote {}", p.display());
    }
    if let Some(problem) = args.compare {
        let table = written.first().cloned().into_iter().collect::<Vec<_>>();
        compare_designs(args, problem, &table)?;
    }
    Ok(ExitCode::SUCCESS)
}

/// `--rank-steps N`: the proven designs ordered by their error on the
/// problem after `N` steps ([`compare::versus::errors_after`]), the runs
/// that failed last; the ranking printed.
fn rank_on_problem(
    args: &DesignArgs,
    problem: compare::builtin::Builtin,
    proven: Vec<PathBuf>,
    steps: usize,
) -> Result<Vec<PathBuf>> {
    let tables: Vec<PathBuf> = proven.iter().map(|p| on_split(args, p)).collect();
    let ranked = compare::versus::rank_by_error(problem, args.sweep.t_end, &tables, steps)?;
    println!(
        "ranked by the error on {} after {steps} steps (--rank-steps):",
        problem.name()
    );
    for (i, (k, e)) in ranked.iter().enumerate() {
        let name = proven[*k]
            .file_stem()
            .map(|s| s.to_string_lossy())
            .unwrap_or_default();
        match e {
            Ok(e) => println!("  {}. {name}: {e:.3e}", i + 1),
            Err(why) => println!("  {}. {name}: {why}", i + 1),
        }
    }
    Ok(ranked.into_iter().map(|(k, _)| proven[k].clone()).collect())
}

/// A design's table as the sweep takes it: `wh:PATH` with
/// `--wisdom-holman` (the registry resolves it), else the path.
fn on_split(args: &DesignArgs, p: &std::path::Path) -> PathBuf {
    if args.wisdom_holman {
        PathBuf::from(format!("{}{}", compare::wisdom_holman::PREFIX, p.display()))
    } else {
        p.to_path_buf()
    }
}

/// `--compare PROBLEM`: the proven tables written (exact or certified, the
/// best `--designs` in the order of the objective) beside the library's
/// methods in one sweep of compare's library (the path of `symlab compare
/// --table`), its report written into DIR/compare/.
fn compare_designs(
    args: &DesignArgs,
    problem: compare::builtin::Builtin,
    proven: &[PathBuf],
) -> Result<()> {
    if proven.is_empty() {
        anyhow::bail!(
            "--compare {}: no proven design to run (none exact or certified)",
            problem.name()
        );
    }
    // `wh:PATH`: the table on the problem's Wisdom–Holman split (the
    // registry resolves it, or says the problem has none).
    let tables = proven.iter().map(|p| on_split(args, p)).collect();
    let job = compare::mode::SweepJob {
        problem: compare::mode::SweepProblem::Builtin(problem),
        request: args.sweep.request(false),
        methods: args.methods.clone(),
        tables,
    };
    let sweep = compare::mode::prepare_sweep(job)?;
    println!("{}", sweep.headline());
    let (result, _) = sweep.run(Vec::new(), &mut compare::Quiet)?;
    let dir = args.out.join("compare");
    let files = result
        .write(&dir)
        .with_context(|| format!("writing into {}", dir.display()))?;
    print!("{}", result.summary());
    print!("{}", result.wrote(&files));
    let prefix = if args.wisdom_holman {
        compare::wisdom_holman::PREFIX
    } else {
        ""
    };
    let designs: Vec<String> = proven
        .iter()
        .filter_map(|p| {
            p.file_stem()
                .map(|s| format!("{prefix}{}", s.to_string_lossy()))
        })
        .collect();
    let table =
        compare::versus::versus(&result.rows, &designs, &[1e-6, 1e-8, 1e-10, 1e-12]).markdown();
    let path = dir.join("designs.md");
    std::fs::write(&path, &table).with_context(|| format!("writing {}", path.display()))?;
    print!("{table}");
    println!("wrote {}", path.display());
    Ok(())
}
