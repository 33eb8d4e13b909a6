//! Designed methods against the library in one sweep: the cost of every
//! method to reach each of a few errors, and for each error whether the
//! best design needs less than the best library method — the verdict of
//! `symlab design … --compare` (its `designs.md`) and of issue 36's check.
//!
//! The cost to an error is [`reach`]'s: interpolated linearly in log–log
//! between the two runs of the sweep that bracket it, as `report.md`'s
//! time-to-error table is (a method whose cheapest run is already below
//! the error has only an upper bound, marked `≤`, and is not ranked).
//!
//! **Evaluations** compare across every row: an interpreted table takes
//! the same steps as generated code. **Wall times** compare only between
//! rows stepped the same way: a design stepped by the run-time interpreter
//! against the library's tables stepped by the same interpreter
//! (`interp:ID`, [`crate::registry::MethodFamily::Interpreted`]), a `wh:`
//! design against the `wh:` methods; the best generated row is named
//! beside, never ranked against an interpreted one.
//!
//! A design is said to need less only beyond a margin ([`EVAL_MARGIN`],
//! [`TIME_MARGIN`]); within it the verdict is "level".
//!
//! ```
//! use compare::versus::{Verdict, versus};
//! use compare::{Family, Row};
//! let row = |method: &str, h: f64, error: f64, evals: u64, time_s: f64, interpreted: bool| Row {
//!     problem: "p".into(), method: method.into(), family: Family::Splitting, order: 4,
//!     symplectic: true, h, tol: f64::NAN, steps: evals, error, energy_error: 0.0, time_s, evals,
//!     newton_iterations: 0, fixed_point_iterations: 0, factorizations: 0,
//!     status: "ok".into(), interpreted,
//! };
//! let rows = vec![
//!     row("lib", 0.1, 1e-5, 100, 1e-3, false),
//!     row("lib", 0.01, 1e-9, 1000, 1e-2, false),
//!     row("interp:lib", 0.1, 1e-5, 100, 2e-3, true),
//!     row("interp:lib", 0.01, 1e-9, 1000, 2e-2, true),
//!     row("mine", 0.2, 1e-5, 50, 1e-3, true),
//!     row("mine", 0.02, 1e-9, 500, 1e-2, true),
//! ];
//! let v = versus(&rows, &["mine".to_string()], &[1e-7]);
//! // Half the evaluations, and half the time of the library stepped alike.
//! let twice = |v: &Verdict| matches!(v, Verdict::DesignLess { ratio } if (ratio - 2.0).abs() < 1e-9);
//! assert!(twice(&v.targets[0].evaluations), "{:?}", v.targets[0].evaluations);
//! assert!(twice(&v.targets[0].time), "{:?}", v.targets[0].time);
//! assert!(v.markdown().contains("interp:lib"));
//! ```

use std::fmt::Write as _;

use crate::Row;
use crate::output::{Reach, reach};

/// Evaluations within this factor are "level": the interpolation between
/// two sweep points is exact only for a pure power law, and a few per cent
/// is what it misses by on the sweeps of the guide (30 points a decade and
/// a half apart).
pub const EVAL_MARGIN: f64 = 1.05;

/// Wall times within this factor are "level": the spread of the median of
/// a few timed runs on a shared two-core machine (the results pages show
/// 0.8–1.3 on unchanged code).
pub const TIME_MARGIN: f64 = 1.10;

/// What one measure says at one error.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// The best design needs `ratio` (> margin) times less than the best
    /// library method compared with it.
    DesignLess { ratio: f64 },
    /// The best library method needs `ratio` (> margin) times less.
    LibraryLess { ratio: f64 },
    /// Within the margin: `ratio` = design / library.
    Level { ratio: f64 },
    /// No design, or no library method compared with it, brackets the
    /// error: `why`.
    Undecided { why: String },
}

/// One method's cost to one error.
#[derive(Clone, Debug, PartialEq)]
pub struct Cost {
    pub evals: f64,
    /// Milliseconds.
    pub ms: f64,
    /// The cheapest run is already below the error: an upper bound.
    pub upper_bound: bool,
}

/// One method of the sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodCosts {
    pub method: String,
    pub design: bool,
    /// Stepped by the run-time interpreter (its time compares only with
    /// rows stepped alike).
    pub interpreted: bool,
    /// Per target, `None` where the sweep does not reach it.
    pub costs: Vec<Option<Cost>>,
}

/// The verdicts at one error.
#[derive(Clone, Debug, PartialEq)]
pub struct AtTarget {
    pub target: f64,
    /// Best design and best library method by evaluations, and the verdict.
    pub evaluations: Verdict,
    pub eval_pair: Option<(String, String)>,
    /// Best design and best library method stepped the same way, by wall
    /// time, and the verdict.
    pub time: Verdict,
    pub time_pair: Option<(String, String)>,
    /// The fastest generated library row when the designs are interpreted
    /// (named beside, not ranked against them): method and ms.
    pub fastest_generated: Option<(String, f64)>,
}

/// The whole comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Versus {
    pub methods: Vec<MethodCosts>,
    pub targets: Vec<AtTarget>,
}

/// The comparison of the rows `designs` name against every other row of
/// `rows` (one sweep), at each error of `targets`.
pub fn versus(rows: &[Row], designs: &[String], targets: &[f64]) -> Versus {
    let is_design = |m: &str| designs.iter().any(|d| d == m);
    let mut names: Vec<&str> = Vec::new();
    for r in rows {
        if !names.contains(&r.method.as_str()) {
            names.push(&r.method);
        }
    }
    let interpreted = |m: &str| rows.iter().any(|r| r.method == m && r.interpreted);
    let reaches: Vec<Vec<Reach>> = targets.iter().map(|&t| reach(rows, t)).collect();
    let methods: Vec<MethodCosts> = names
        .iter()
        .map(|m| MethodCosts {
            method: m.to_string(),
            design: is_design(m),
            interpreted: interpreted(m),
            costs: reaches
                .iter()
                .map(|rs| {
                    rs.iter().find(|r| r.method == *m).map(|r| Cost {
                        evals: r.evals,
                        ms: r.time_s * 1e3,
                        upper_bound: r.upper_bound,
                    })
                })
                .collect(),
        })
        .collect();
    let targets = targets
        .iter()
        .enumerate()
        .map(|(i, &target)| at_target(&methods, i, target))
        .collect();
    Versus { methods, targets }
}

/// The best (least) of `pick` over the methods `keep` selects, among the
/// bracketed costs at target `i`.
fn best(
    methods: &[MethodCosts],
    i: usize,
    keep: impl Fn(&MethodCosts) -> bool,
    pick: impl Fn(&Cost) -> f64,
) -> Option<(&str, f64)> {
    methods
        .iter()
        .filter(|m| keep(m))
        .filter_map(|m| match &m.costs[i] {
            Some(c) if !c.upper_bound => Some((m.method.as_str(), pick(c))),
            _ => None,
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

fn verdict(design: f64, library: f64, margin: f64) -> Verdict {
    let ratio = library / design;
    if ratio > margin {
        Verdict::DesignLess { ratio }
    } else if ratio < 1.0 / margin {
        Verdict::LibraryLess {
            ratio: design / library,
        }
    } else {
        Verdict::Level {
            ratio: design / library,
        }
    }
}

fn at_target(methods: &[MethodCosts], i: usize, target: f64) -> AtTarget {
    let undecided = |what: &str| Verdict::Undecided {
        why: format!("{what} brackets {target:.0e} in the sweep"),
    };
    let d = best(methods, i, |m| m.design, |c| c.evals);
    let l = best(methods, i, |m| !m.design, |c| c.evals);
    let (evaluations, eval_pair) = match (d, l) {
        (Some((dm, dv)), Some((lm, lv))) => (
            verdict(dv, lv, EVAL_MARGIN),
            Some((dm.to_string(), lm.to_string())),
        ),
        (None, _) => (undecided("no design"), None),
        (_, None) => (undecided("no library method"), None),
    };
    // Times: the fastest design, against the fastest library row stepped
    // the same way as it.
    let d = best(methods, i, |m| m.design, |c| c.ms);
    let (time, time_pair) = match d {
        None => (undecided("no design"), None),
        Some((dm, dv)) => {
            let kind = methods.iter().any(|m| m.method == dm && m.interpreted);
            match best(methods, i, |m| !m.design && m.interpreted == kind, |c| c.ms) {
                Some((lm, lv)) => (
                    verdict(dv, lv, TIME_MARGIN),
                    Some((dm.to_string(), lm.to_string())),
                ),
                None => (
                    undecided(if kind {
                        "no library method stepped by the interpreter (add interp:ID)"
                    } else {
                        "no generated library method"
                    }),
                    None,
                ),
            }
        }
    };
    let fastest_generated = best(methods, i, |m| !m.design && !m.interpreted, |c| c.ms)
        .filter(|_| methods.iter().any(|m| m.design && m.interpreted))
        .map(|(m, v)| (m.to_string(), v));
    AtTarget {
        target,
        evaluations,
        eval_pair,
        time,
        time_pair,
        fastest_generated,
    }
}

impl Versus {
    /// `designs.md`: the two tables (evaluations, milliseconds) and the
    /// verdict lines.
    pub fn markdown(&self) -> String {
        let mut out = String::from(
            "\nCost to reach each error at the end time, interpolated in log–log between the two runs of the sweep that \
             bracket it (`≤`: the cheapest run is already below it, an upper bound, not ranked; `-`: not reached).\n",
        );
        out.push_str("\nForce evaluations (they compare across every row):\n");
        self.table(&mut out, |c| format!("{:.0}", c.evals));
        out.push_str(
            "\nWall time, ms (the median of the timed runs); it compares only between rows stepped the same way \
             (`interpreter`: the run-time interpreter of table files, `generated`: `butcher!` code):\n",
        );
        self.table(&mut out, |c| format!("{:.4}", c.ms));
        out.push('\n');
        for t in &self.targets {
            let _ = writeln!(out, "{}", t.line());
        }
        let _ = writeln!(
            out,
            "\n(\"level\": within {:.0} % in evaluations, {:.0} % in time.)",
            (EVAL_MARGIN - 1.0) * 100.0,
            (TIME_MARGIN - 1.0) * 100.0
        );
        out
    }

    fn table(&self, out: &mut String, cell: impl Fn(&Cost) -> String) {
        out.push_str("\n| method | design | stepped by |");
        for t in &self.targets {
            let _ = write!(out, " ≤ {:.0e} |", t.target);
        }
        out.push_str("\n|---|---|---|");
        for _ in &self.targets {
            out.push_str("---:|");
        }
        out.push('\n');
        for m in &self.methods {
            let _ = write!(
                out,
                "| {} | {} | {} |",
                m.method,
                if m.design { "yes" } else { "" },
                if m.interpreted {
                    "interpreter"
                } else {
                    "generated"
                }
            );
            for c in &m.costs {
                match c {
                    Some(c) if c.upper_bound => {
                        let _ = write!(out, " ≤ {} |", cell(c));
                    }
                    Some(c) => {
                        let _ = write!(out, " {} |", cell(c));
                    }
                    None => out.push_str(" - |"),
                }
            }
            out.push('\n');
        }
    }
}

impl AtTarget {
    /// The verdict line of this error.
    pub fn line(&self) -> String {
        let say = |v: &Verdict, pair: &Option<(String, String)>, unit: &str| -> String {
            let (d, l) = pair
                .as_ref()
                .map(|(d, l)| (d.as_str(), l.as_str()))
                .unwrap_or(("", ""));
            match v {
                Verdict::DesignLess { ratio } => {
                    format!(
                        "the design {d} needs {ratio:.2}× {} {unit} than the library's best, {l}: the design wins",
                        if unit == "time" { "less" } else { "fewer" }
                    )
                }
                Verdict::LibraryLess { ratio } => {
                    format!(
                        "the library's {l} needs less {unit}; the best design, {d}, {ratio:.2}× as much"
                    )
                }
                Verdict::Level { ratio } => {
                    format!(
                        "level in {unit}: the design {d} needs {ratio:.2}× what the library's {l} does"
                    )
                }
                Verdict::Undecided { why } => format!("{unit}: undecided, {why}"),
            }
        };
        let mut line = format!(
            "error ≤ {:.0e}: {}; {}",
            self.target,
            say(&self.evaluations, &self.eval_pair, "evaluations"),
            say(&self.time, &self.time_pair, "time"),
        );
        if let Some((m, ms)) = &self.fastest_generated {
            let _ = write!(
                line,
                " (stepped alike; the fastest generated library row, {m}, takes {ms:.4} ms)"
            );
        }
        line
    }
}

/// The relative error at the end time of each of `tables` (paths as
/// `symlab compare --table` takes them: `wh:PATH` on the Wisdom–Holman
/// split) after `steps` equal steps on the built-in `problem` over `t_end`
/// (default: the problem's): the designer's "error measured on a named
/// problem", by which `symlab design --rank-steps` ranks the proven designs
/// before choosing the ones it compares. `None` for a table whose run
/// failed (it diverged, or its solver did), with the run's status.
pub fn errors_after(
    problem: crate::builtin::Builtin,
    t_end: Option<f64>,
    tables: &[std::path::PathBuf],
    steps: usize,
) -> crate::Result<Vec<Result<f64, String>>> {
    use crate::mode::{SweepJob, SweepProblem, prepare_sweep};
    let t = t_end.unwrap_or(problem.defaults().t_end);
    let h = t / steps.max(1) as f64;
    let request = crate::sweep_plan::SweepRequest {
        t_end,
        h_min: Some(h),
        h_max: Some(h),
        points: Some(1),
        repeats: Some(1),
        ..Default::default()
    };
    let sweep = prepare_sweep(SweepJob {
        problem: SweepProblem::Builtin(problem),
        request,
        methods: Some(Vec::new()),
        tables: tables.to_vec(),
    })?;
    let (result, _) = sweep.run(Vec::new(), &mut crate::Quiet)?;
    if result.rows.len() != tables.len() {
        return Err(crate::CompareError::Setting {
            name: "--rank-steps",
            why: format!(
                "expected one run per table, got {} for {}",
                result.rows.len(),
                tables.len()
            ),
        });
    }
    Ok(result
        .rows
        .iter()
        .map(|r| {
            if r.ok() {
                Ok(r.error)
            } else {
                Err(r.status.clone())
            }
        })
        .collect())
}

/// `tables` ranked by [`errors_after`] (the smallest error first, the
/// failed runs last, in their given order), each with its error or why its
/// run failed: `symlab design --rank-steps`.
pub fn rank_by_error(
    problem: crate::builtin::Builtin,
    t_end: Option<f64>,
    tables: &[std::path::PathBuf],
    steps: usize,
) -> crate::Result<Vec<(usize, Result<f64, String>)>> {
    if tables.is_empty() {
        return Ok(Vec::new());
    }
    let errors = errors_after(problem, t_end, tables, steps)?;
    let mut ranked: Vec<(usize, Result<f64, String>)> = errors.into_iter().enumerate().collect();
    ranked.sort_by(|a, b| match (&a.1, &b.1) {
        (Ok(x), Ok(y)) => x.total_cmp(y),
        (Ok(_), Err(_)) => std::cmp::Ordering::Less,
        (Err(_), Ok(_)) => std::cmp::Ordering::Greater,
        (Err(_), Err(_)) => a.0.cmp(&b.0),
    });
    Ok(ranked)
}
