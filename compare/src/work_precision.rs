//! A work–precision comparison from start to files: the sweep settings,
//! the run ([`work_precision`]), and what it leaves behind (`runs.csv`, the
//! log–log plots, `report.md`, the printed summary).

use std::path::{Path, PathBuf};

use crate::error::{CompareError, Result, write};
use crate::method::Method;
use crate::output;
use crate::problem::{Defaults, Kind, Problem, Setup};
use crate::report;
use crate::sweep::{self, Row};

/// The settings of a work–precision sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSettings {
    /// Smallest and largest step size; `points` log-spaced step sizes
    /// between them, each rounded to a whole number of steps over `T`.
    pub h_min: f64,
    pub h_max: f64,
    pub points: usize,
    /// `rtol = atol` of the adaptive peer, one run each.
    pub tolerances: Vec<f64>,
    /// Timed runs per point after one warm-up; the median is reported.
    pub repeats: usize,
    /// The relative error of the time-to-error table.
    pub target: f64,
}

impl SweepSettings {
    /// The problem's step range (capped at `t_end`), 10 step sizes, DOP853
    /// at 1e-4 … 1e-18 (one per decade), 3 timed runs, target 1e-8.
    pub fn new(defaults: Defaults, t_end: f64) -> Self {
        SweepSettings {
            h_min: defaults.h_min,
            h_max: defaults.h_max.min(t_end),
            points: 10,
            tolerances: sweep::tolerances(sweep::PEER_TOLERANCES),
            repeats: 3,
            target: 1e-8,
        }
    }

    /// Every setting in range for a run to `t_end`: positive finite steps
    /// with `h_min ≤ h_max ≤ t_end`, at most 10⁸ steps per run, 1–200
    /// points, 1–100 repeats, finite positive tolerances and target.
    pub fn validate(&self, t_end: f64) -> Result<()> {
        let positive = |name: &'static str, x: f64| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err(CompareError::setting(
                    name,
                    format!("must be a finite number > 0, got {x}"),
                ))
            }
        };
        positive("t_end", t_end)?;
        positive("h_min", self.h_min)?;
        positive("h_max", self.h_max)?;
        positive("target", self.target)?;
        if self.h_min > self.h_max {
            return Err(CompareError::setting(
                "h_min",
                format!(
                    "h_min ({}) must not exceed h_max ({})",
                    self.h_min, self.h_max
                ),
            ));
        }
        if self.h_max > t_end {
            return Err(CompareError::setting(
                "h_max",
                format!("h_max ({}) exceeds the end time ({t_end})", self.h_max),
            ));
        }
        if t_end / self.h_min > 1e8 {
            return Err(CompareError::setting(
                "h_min",
                format!(
                    "h_min {} over T = {t_end} is {:.1e} steps per run; at most 1e8",
                    self.h_min,
                    t_end / self.h_min
                ),
            ));
        }
        if !(1..=200).contains(&self.points) {
            return Err(CompareError::setting(
                "points",
                format!("between 1 and 200 step sizes, got {}", self.points),
            ));
        }
        if !(1..=100).contains(&self.repeats) {
            return Err(CompareError::setting(
                "repeats",
                format!("between 1 and 100 timed runs, got {}", self.repeats),
            ));
        }
        for &t in &self.tolerances {
            positive("tolerances", t)?;
        }
        Ok(())
    }

    /// The step counts of the sweep over `[0, t_end]`.
    pub fn step_counts(&self, t_end: f64) -> Vec<u64> {
        sweep::step_counts(t_end, self.h_min, self.h_max, self.points)
    }
}

/// The most steps a sweep may take in all (every fixed-step method at every
/// step count, observed, warmed up and timed): 10¹⁰, tens of minutes of
/// explicit steps on the built-in problems in a release build. A sweep
/// beyond it is refused before it starts rather than run for hours; the
/// default sweeps take at most a few times 10⁷.
pub const MAX_SWEEP_STEPS: f64 = 1e10;

/// A finished work–precision sweep.
pub struct WorkPrecision {
    /// The `problem` column and a line for titles.
    pub problem: String,
    pub description: String,
    pub t_end: f64,
    /// `T = 62.8319 (10 orbits)`, or `T = 10.0000`.
    pub run_length: String,
    pub settings: SweepSettings,
    pub steps: Vec<u64>,
    /// Methods by id, in the order run.
    pub methods: Vec<String>,
    /// Whether the problem counts force evaluations (separable) or
    /// right-hand sides.
    pub separable: bool,
    pub rows: Vec<Row>,
    /// The REBOUND release that ran the `rebound:` methods, if any ran.
    pub rebound: Option<String>,
    /// What the sweep left out and why (REBOUND not installed, WHFast512
    /// without AVX-512), with how to fix it; printed with the summary.
    pub notes: Vec<String>,
}

/// Run every method over the sweep (see [`sweep::sweep`]: an observed run,
/// then a warm-up and `repeats` timed runs, strictly one at a time). A run
/// that diverges or whose stage solver fails is a row with that status;
/// the result is an error only for settings out of range or an empty list
/// of methods. REBOUND's methods are probed first: where Python, the
/// `rebound` package or AVX-512 (WHFast512) is missing they are left out,
/// and [`WorkPrecision::notes`] says so and how to install REBOUND.
pub fn work_precision<P: Problem>(
    setup: &Setup<P>,
    methods: &[Method<P>],
    settings: &SweepSettings,
) -> Result<WorkPrecision> {
    work_precision_from(setup, methods, settings, Vec::new(), &mut sweep::Quiet).map(|(wp, _)| wp)
}

/// [`work_precision`] continuing from the rows `done` of a sweep that was
/// stopped (they are not run again), telling `observer` the progress and
/// asking it after every row whether to go on
/// ([`sweep::sweep_each_from`]); `true` beside the result when it stopped
/// before the end (its rows are then a prefix).
pub fn work_precision_from<P: Problem>(
    setup: &Setup<P>,
    methods: &[Method<P>],
    settings: &SweepSettings,
    done: Vec<sweep::Row>,
    observer: &mut dyn sweep::SweepObserver,
) -> Result<(WorkPrecision, bool)> {
    settings.validate(setup.t_end)?;
    if methods.is_empty() {
        return Err(CompareError::setting("methods", "no method to compare"));
    }
    if setup.reference.len() != setup.z0.len() {
        return Err(CompareError::problem(
            &setup.name,
            "the setup has no reference end state (made with Setup::energy_only); a sweep measures the error at T",
        ));
    }
    let steps = settings.step_counts(setup.t_end);
    let fixed = methods
        .iter()
        .filter(|m| matches!(m, Method::Fixed(_)))
        .count();
    let per_method: f64 = steps.iter().map(|&n| n as f64).sum();
    // An observed run, a warm-up and the timed runs per step count.
    let runs = (2 + settings.repeats) as f64;
    let total = fixed as f64 * per_method * runs;
    if total > MAX_SWEEP_STEPS {
        return Err(CompareError::setting(
            "h_min",
            format!(
                "the sweep asks for {total:.1e} steps in all ({fixed} fixed-step methods × {per_method:.1e} steps over the step sizes × {runs} runs each: observed, warm-up, timed); at most {MAX_SWEEP_STEPS:.0e} — raise h_min (--h-min), or lower points, repeats or the number of methods"
            ),
        ));
    }
    let rebound = crate::rebound::availability(methods.iter().filter_map(|m| match m {
        Method::Rebound(r) => Some(r),
        _ => None,
    }));
    let run: Vec<&Method<P>> = methods
        .iter()
        .filter(|m| !rebound.left_out.iter().any(|id| id == m.id()))
        .collect();
    let sweep::Swept { rows, stopped } = sweep::sweep_each_from(
        setup,
        run.iter().copied(),
        &steps,
        &settings.tolerances,
        settings.repeats,
        done,
        observer,
    );
    let run_length = match setup.sys.period() {
        Some((period, unit)) => {
            let n = setup.t_end / period;
            format!("T = {:.4} ({n:.4} {unit}s)", setup.t_end)
                .replace(&format!(".0000 {unit}s"), &format!(" {unit}s"))
        }
        None => format!("T = {:.4}", setup.t_end),
    };
    Ok((
        WorkPrecision {
            problem: setup.name.clone(),
            description: setup.description.clone(),
            t_end: setup.t_end,
            run_length,
            settings: settings.clone(),
            steps,
            methods: run.iter().map(|m| m.id().to_string()).collect(),
            separable: <P::Kind as Kind<P>>::SEPARABLE,
            rebound: rebound
                .version
                .filter(|_| rows.iter().any(|r| crate::rebound::is_rebound(&r.method))),
            notes: rebound.notes,
            rows,
        },
        stopped,
    ))
}

impl WorkPrecision {
    /// The head of `report.md`: the problem, the run length, the sweep.
    fn report_head(&self) -> Vec<String> {
        let peer = self.methods.iter().any(|m| m == report::PEER);
        let rebound = self
            .methods
            .iter()
            .filter(|m| crate::rebound::is_rebound(m))
            .count();
        let fixed = self.methods.len() - usize::from(peer) - rebound;
        let first = self.steps[0];
        let last = *self.steps.last().expect("at least one step count");
        let mut head = vec![
            format!(
                "Problem: {} (`{}`), {}; relative error ‖z(T) − z_ref(T)‖₂/‖z_ref(T)‖₂ at the end",
                self.description, self.problem, self.run_length
            ),
            format!(
                "Sweep: {fixed} fixed-step method(s) at {} step counts from {first} to {last} \
                 (h = {:.3e} … {:.3e}, log-spaced)",
                self.steps.len(),
                self.t_end / first as f64,
                self.t_end / last as f64
            ),
        ];
        let tols = &self.settings.tolerances;
        if peer && !tols.is_empty() {
            head.push(format!(
                "Peer: dop853 (ode_solvers) at {} tolerances rtol = atol from {:.0e} to {:.0e} (log-spaced)",
                tols.len(),
                tols[0],
                tols.last().expect("not empty")
            ));
        }
        if let Some(version) = &self.rebound {
            head.push(format!(
                "REBOUND {version} (its Python package, through compare/peers/rebound_peer.py): {rebound} \
                 method(s), rows `rebound:…`, from our initial state bit for bit, one process per run, only \
                 `sim.integrate` timed; errors measured here against the same reference"
            ));
        }
        for note in &self.notes {
            head.push(format!("Left out: {note}"));
        }
        head.push(format!(
            "Timing: median of {} timed run(s) after one warm-up, one run at a time; {}",
            self.settings.repeats,
            if cfg!(debug_assertions) {
                "a debug build, so the times are not representative"
            } else {
                "a release build"
            }
        ));
        head.push("Data: runs.csv and the error_vs_*.svg plots in this directory".into());
        head
    }

    /// `report.md` (see [`report::sweep_report`]), with the REBOUND section
    /// when REBOUND ran.
    pub fn report(&self) -> String {
        let mut s = report::sweep_report(
            &format!("Work–precision sweep: {}", self.description),
            &self.report_head(),
            &self.rows,
            self.settings.target,
            &self.run_length,
        );
        if let Some(version) = &self.rebound
            && let Some(section) = report::rebound_section(&self.rows, version)
        {
            s.push('\n');
            s.push_str(&section);
        }
        s
    }

    /// The printed summary and time-to-target table, REBOUND against our
    /// fastest when REBOUND ran, and the notes on what was left out.
    pub fn summary(&self) -> String {
        let what = format!("{}, T = {:.4}", self.description, self.t_end);
        let mut s = output::summary(&self.rows, self.settings.target)
            + &output::time_to_error_table(&self.rows, self.settings.target, &what);
        if let Some(version) = &self.rebound {
            s += &report::rebound_table(&self.rows, version);
        }
        for note in &self.notes {
            s += &format!("note: {note}\n");
        }
        s
    }

    /// What a front end says after [`write`](Self::write) left `files`:
    /// the note on interpreted rows, if any, and a `wrote FILE` line per
    /// file (`runs.csv` with its row count).
    pub fn wrote(&self, files: &[PathBuf]) -> String {
        let mut out = String::new();
        if self.rows.iter().any(|r| r.interpreted) {
            out.push_str(
                "interpreted: rows of table files are stepped by the run-time interpreter; their errors and \
                 evaluations compare with generated code, their times do not (see report.md)\n",
            );
        }
        for f in files {
            if f.ends_with("runs.csv") {
                out.push_str(&format!(
                    "wrote {} ({} rows)\n",
                    f.display(),
                    self.rows.len()
                ));
            } else {
                out.push_str(&format!("wrote {}\n", f.display()));
            }
        }
        out
    }

    /// `runs.csv`, the plots (when some run succeeded) and `report.md` in
    /// `dir` (created if missing); returns the files written.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir).map_err(|source| CompareError::Io {
            path: dir.to_path_buf(),
            source,
        })?;
        let mut files = vec![dir.join("runs.csv")];
        output::write_csv(&files[0], &self.rows)?;
        let evals_label = if self.separable {
            "force evaluations"
        } else {
            "right-hand-side evaluations (propagator: matrix–vector products)"
        };
        if self.rows.iter().any(|r| r.ok()) {
            let title = format!("{}, T = {:.4}", self.description, self.t_end);
            for f in output::plots(dir, &self.rows, &title, evals_label)? {
                files.push(dir.join(f));
            }
        }
        let report = dir.join("report.md");
        write(&report, self.report())?;
        files.push(report);
        Ok(files)
    }
}
