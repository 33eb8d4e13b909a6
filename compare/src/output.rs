//! What a sweep leaves behind: `runs.csv`, the work–precision plots, the
//! printed summary, and the figures derived from the rows (fitted orders,
//! time to reach an error).

use std::fmt::Write as _;
use std::path::Path;

use crate::error::{CompareError, Result, write};
use crate::format;
use crate::plot::{self, Plot, Series};
use crate::problem::Family;
use crate::row::{COLUMNS, Row};

pub use crate::format::csv_field;

/// `runs.csv`: the [`COLUMNS`], and `interpreted` after them when a table
/// file ran (the rows of built-in and generated schemes keep the documented
/// columns exactly).
pub fn write_csv(path: &Path, rows: &[Row]) -> Result<()> {
    write_csv_with(path, rows, &[], |_| vec![])
}

/// The columns of `runs.csv` followed by `extra` columns, whose values for
/// row `i` are `values(i)` (and `interpreted` last when a table file ran).
pub fn write_csv_with(
    path: &Path,
    rows: &[Row],
    extra: &[&str],
    values: impl Fn(usize) -> Vec<String>,
) -> Result<()> {
    let interpreted = rows.iter().any(|r| r.interpreted);
    let mut extra: Vec<&str> = extra.to_vec();
    if interpreted {
        extra.push("interpreted");
    }
    let mut s = COLUMNS.join(",");
    for c in extra {
        s.push(',');
        s.push_str(c);
    }
    s.push('\n');
    for (i, r) in rows.iter().enumerate() {
        s.push_str(&r.csv());
        for v in values(i) {
            s.push(',');
            s.push_str(&csv_field(&v));
        }
        if interpreted {
            s.push(',');
            s.push_str(if r.interpreted { "true" } else { "false" });
        }
        s.push('\n');
    }
    write(path, s)
}

/// The methods of `rows`, in order of first appearance.
pub fn methods(rows: &[Row]) -> Vec<&str> {
    let mut out: Vec<&str> = Vec::new();
    for r in rows {
        if !out.contains(&r.method.as_str()) {
            out.push(&r.method);
        }
    }
    out
}

/// Least-squares slope of `ln y` against `ln x`; `None` for fewer than two
/// points or no spread in `x`.
pub fn loglog_slope(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// The observed order of a fixed-step method: the slope of log error
/// against log h over its successful runs with error between 1e-12 (above
/// round-off) and 1e-1 (asymptotic regime), less the round-off plateau at
/// the small-h end: over long runs round-off accumulates above 1e-12, and
/// the smallest steps no longer lower the error. Points are dropped from
/// the smallest h up while the error falls by less than `h` does to the
/// next larger step (local slope below 1; every method here has order ≥ 1).
pub fn fitted_order(rows: &[Row], method: &str) -> Option<f64> {
    let mut pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| {
            r.method == method && r.ok() && r.tol.is_nan() && r.error > 1e-12 && r.error < 1e-1
        })
        .map(|r| (r.h, r.error))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let local = |a: (f64, f64), b: (f64, f64)| (b.1 / a.1).ln() / (b.0 / a.0).ln();
    // A NaN slope (two runs at the same h) counts as flat.
    let flat = |a, b| {
        let l = local(a, b);
        l.is_nan() || l < 1.0
    };
    while pts.len() > 2 && flat(pts[0], pts[1]) {
        pts.remove(0);
    }
    loglog_slope(&pts)
}

/// How a method reaches a relative error at the end time.
#[derive(Clone, Debug)]
pub struct Reach {
    pub method: String,
    pub symplectic: bool,
    /// Wall time, seconds: interpolated, or (for an upper bound) that of
    /// the cheapest run.
    pub time_s: f64,
    /// Steps and evaluations, interpolated like the time.
    pub steps: f64,
    pub evals: f64,
    /// `max |E − E₀|/|E₀|` of the cheapest run that reaches the target (a
    /// measured run, not interpolated).
    pub energy_error: f64,
    /// The cheapest successful run is already below the target: the figures
    /// are that run's, an upper bound on the time to reach the target.
    pub upper_bound: bool,
}

/// The successful, timed runs of `method`, cheapest first (by evaluations,
/// then by time).
pub fn ladder<'a>(rows: &'a [Row], method: &str) -> Vec<&'a Row> {
    let mut runs: Vec<&Row> = rows
        .iter()
        .filter(|r| r.method == method && r.ok() && r.time_s > 0.0 && r.error > 0.0)
        .collect();
    runs.sort_by(|a, b| a.evals.cmp(&b.evals).then(a.time_s.total_cmp(&b.time_s)));
    runs
}

/// For each method, how it reaches relative error `target` at the end
/// time: following its runs from the cheapest up, the first run whose error
/// is at most `target` and the one before it bracket the target, and the
/// time (steps, evaluations) is interpolated linearly in log–log between
/// them. A method whose cheapest run is already below the target is
/// included as an [`upper_bound`](Reach::upper_bound); one that never
/// reaches it is left out. Fastest first.
pub fn reach(rows: &[Row], target: f64) -> Vec<Reach> {
    let mut out = Vec::new();
    for m in methods(rows) {
        let runs = ladder(rows, m);
        let Some(i) = runs.iter().position(|r| r.error <= target) else {
            continue;
        };
        let b = runs[i];
        let r = if i == 0 {
            Reach {
                method: m.to_string(),
                symplectic: b.symplectic,
                time_s: b.time_s,
                steps: b.steps as f64,
                evals: b.evals as f64,
                energy_error: b.energy_error,
                upper_bound: true,
            }
        } else {
            let a = runs[i - 1];
            let (la, lb, lt) = (a.error.ln(), b.error.ln(), target.ln());
            let f = if la == lb { 1.0 } else { (la - lt) / (la - lb) };
            let lerp = |x: f64, y: f64| (x.ln() + f * (y.ln() - x.ln())).exp();
            Reach {
                method: m.to_string(),
                symplectic: b.symplectic,
                time_s: lerp(a.time_s, b.time_s),
                steps: lerp(a.steps.max(1) as f64, b.steps.max(1) as f64),
                evals: lerp(a.evals.max(1) as f64, b.evals.max(1) as f64),
                energy_error: b.energy_error,
                upper_bound: false,
            }
        };
        out.push(r);
    }
    out.sort_by(|a, b| a.time_s.total_cmp(&b.time_s));
    out
}

/// For each method, the wall time to reach relative error `target` at the
/// end time, interpolated linearly in log–log between the two runs of the
/// sweep that bracket it (see [`reach`]). Methods whose runs never bracket
/// the target (it is not reached, or already the cheapest run is below it)
/// are left out. Fastest first.
pub fn time_to_error(rows: &[Row], target: f64) -> Vec<(String, f64)> {
    reach(rows, target)
        .into_iter()
        .filter(|r| !r.upper_bound)
        .map(|r| (r.method, r.time_s))
        .collect()
}

/// Methods of `rows` that did not reach `target` within the sweep (or were
/// below it already at the cheapest run), for the note under the table.
pub fn not_bracketed(rows: &[Row], target: f64) -> Vec<String> {
    let reached: Vec<String> = time_to_error(rows, target)
        .into_iter()
        .map(|(m, _)| m)
        .collect();
    methods(rows)
        .into_iter()
        .filter(|m| !reached.iter().any(|r| r == m))
        .map(str::to_string)
        .collect()
}

/// A text file of at most `limit` bytes ([`tableau::file::read_text`]).
pub(crate) use tableau::file::read_text;

/// The records of a CSV text as RFC 4180 writes them: fields separated by
/// commas, a field in double quotes may hold commas, doubled quotes and line
/// breaks; CRLF or LF ends a record, empty lines are skipped. Each record
/// with the line it starts on (from 1); an unterminated quote is an error
/// naming that line.
fn csv_records(text: &str) -> std::result::Result<Vec<(usize, Vec<String>)>, String> {
    let mut out = Vec::new();
    let mut fields = vec![String::new()];
    let mut quoted = false;
    let mut line = 1;
    let mut start = 1;
    let mut chars = text.chars().peekable();
    let mut end_record = |fields: &mut Vec<String>, start: usize| {
        let record = std::mem::replace(fields, vec![String::new()]);
        if !(record.len() == 1 && record[0].is_empty()) {
            out.push((start, record));
        }
    };
    while let Some(c) = chars.next() {
        let last = fields.last_mut().expect("at least one field");
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                chars.next();
                last.push('"');
            }
            '"' => quoted = !quoted,
            ',' if !quoted => fields.push(String::new()),
            '\r' if !quoted && chars.peek() == Some(&'\n') => {}
            '\n' if !quoted => {
                end_record(&mut fields, start);
                line += 1;
                start = line;
            }
            c => {
                if c == '\n' {
                    line += 1;
                }
                last.push(c);
            }
        }
    }
    if quoted {
        return Err(format!("line {start}: a quoted field is not closed"));
    }
    end_record(&mut fields, start);
    Ok(out)
}

/// The rows of a `runs.csv` written by `symlab compare` (columns found by
/// name; `interpreted` optional; fields quoted as RFC 4180 says), e.g. to
/// compute [`time_to_error`] again for a report. Read with a size limit of
/// 256 MiB. A row whose numbers cannot have come from a run is refused,
/// naming its line and column: a negative or non-finite `h`, `error`,
/// `energy_error` or `time_s` in a row whose status is `ok` (a failed row
/// has NaN there, as documented), a negative number anywhere, a `tol` that
/// is neither NaN nor positive.
pub fn read_runs(path: &Path) -> Result<Vec<Row>> {
    let err = |why: String| CompareError::Csv {
        path: path.to_path_buf(),
        why,
    };
    let text = read_text(
        path,
        256 << 20,
        "a runs.csv of 10⁶ rows is about 150 MB; at most 256 MiB is read",
    )
    .map_err(err)?;
    let records = csv_records(&text).map_err(err)?;
    let mut records = records.into_iter();
    let (_, header) = records.next().ok_or_else(|| err("empty file".into()))?;
    let col = |name: &str| header.iter().position(|h| h == name);
    let idx: Vec<usize> = COLUMNS
        .iter()
        .map(|c| col(c).ok_or_else(|| err(format!("no column '{c}'"))))
        .collect::<Result<_>>()?;
    let interpreted_col = col("interpreted");
    let mut rows = Vec::new();
    for (line, f) in records {
        let at = |i: usize| -> Result<&str> {
            f.get(idx[i])
                .map(String::as_str)
                .ok_or_else(|| err(format!("line {line} is short: no column '{}'", COLUMNS[i])))
        };
        let num = |i: usize| -> Result<f64> {
            let v = at(i)?;
            let x = v.parse::<f64>().map_err(|_| {
                err(format!(
                    "line {line}: '{v}' is not a number (column {})",
                    COLUMNS[i]
                ))
            })?;
            if x < 0.0 {
                return Err(err(format!(
                    "line {line}: column {} is {v}; it is never negative",
                    COLUMNS[i]
                )));
            }
            Ok(x)
        };
        let int = |i: usize| -> Result<u64> {
            let v = num(i)?;
            if v.is_finite() && v >= 0.0 && v.fract() == 0.0 && v < 2f64.powi(63) {
                Ok(v as u64)
            } else {
                Err(err(format!(
                    "line {line}: '{v}' is not a count (column {})",
                    COLUMNS[i]
                )))
            }
        };
        let method = at(1)?.to_string();
        let family = if method == "dop853" {
            Family::Peer
        } else if crate::rebound::is_rebound(&method) {
            Family::Rebound
        } else {
            match integrator_core::library::info(method.trim_end_matches("-propagator")) {
                Some(i) if !i.explicit || method.ends_with("-propagator") => Family::Implicit,
                Some(i) if i.form == "rk" => Family::ExplicitRk,
                _ => Family::Splitting,
            }
        };
        let row = Row {
            problem: at(0)?.to_string(),
            method,
            family,
            order: int(2)? as usize,
            symplectic: at(3)? == "true",
            h: num(4)?,
            tol: num(5)?,
            steps: int(6)?,
            error: num(7)?,
            energy_error: num(8)?,
            time_s: num(9)?,
            evals: int(10)?,
            newton_iterations: int(11)? as usize,
            fixed_point_iterations: int(12)? as usize,
            factorizations: int(13)? as usize,
            status: at(14)?.to_string(),
            interpreted: interpreted_col
                .and_then(|i| f.get(i))
                .is_some_and(|v| v == "true"),
        };
        if row.tol == 0.0 || row.tol.is_infinite() {
            return Err(err(format!(
                "line {line}: column tol is {}; it is NaN (fixed-step methods) or a finite number > 0",
                row.tol
            )));
        }
        if row.ok() {
            for (name, x) in [
                ("h", row.h),
                ("error", row.error),
                ("energy_error", row.energy_error),
                ("time_s", row.time_s),
            ] {
                let positive = name == "h" || name == "time_s";
                if !x.is_finite() || (positive && x == 0.0) {
                    return Err(err(format!(
                        "line {line}: column {name} is {x} in a row whose status is ok; it must be a finite number {}",
                        if positive { "> 0" } else { ">= 0" }
                    )));
                }
            }
        }
        rows.push(row);
    }
    Ok(rows)
}

fn series(rows: &[Row], x: impl Fn(&Row) -> f64, keep: impl Fn(&Row) -> bool) -> Vec<Series> {
    methods(rows)
        .into_iter()
        .filter_map(|m| {
            let mut pts: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.method == m && r.ok() && keep(r))
                .map(|r| (x(r), r.error))
                .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            (!pts.is_empty()).then(|| Series {
                name: m.to_string(),
                points: pts,
                markers: true,
            })
        })
        .collect()
}

/// `error_vs_time.svg` and `error_vs_evals.svg` (all methods), and the same
/// split by family (`…_explicit-rk.svg`, `…_splitting.svg`,
/// `…_implicit.svg`; the peer is drawn in each, REBOUND's integrators —
/// splittings too — in the splitting plots), whose legends stay readable.
/// Returns the files written.
pub fn plots(dir: &Path, rows: &[Row], title: &str, evals_label: &str) -> Result<Vec<String>> {
    let mut written = Vec::new();
    for family in [
        None,
        Some(Family::ExplicitRk),
        Some(Family::Splitting),
        Some(Family::Implicit),
    ] {
        let suffix = family.map_or(String::new(), |f| format!("_{}", f.name()));
        let keep = |r: &Row| {
            family.is_none_or(|f| {
                r.family == f
                    || r.family == Family::Peer
                    || (f == Family::Splitting && r.family == Family::Rebound)
            })
        };
        if family.is_some() && !rows.iter().any(|r| family == Some(r.family)) {
            continue;
        }
        let by_time = series(rows, |r| r.time_s, keep);
        let by_evals = series(rows, |r| r.evals as f64, keep);
        if by_time.is_empty() {
            continue;
        }
        let name_t = format!("error_vs_time{suffix}.svg");
        let name_e = format!("error_vs_evals{suffix}.svg");
        let t_title = format!("{title}: error against wall time");
        let e_title = format!("{title}: error against evaluations");
        plot::lines(
            &dir.join(&name_t),
            &Plot {
                title: &t_title,
                x_label: "wall time (s)",
                y_label: "relative error at t_end",
                log_x: true,
                log_y: true,
                series: &by_time,
            },
        )?;
        plot::lines(
            &dir.join(&name_e),
            &Plot {
                title: &e_title,
                x_label: evals_label,
                y_label: "relative error at t_end",
                log_x: true,
                log_y: true,
                series: &by_evals,
            },
        )?;
        written.push(name_t);
        written.push(name_e);
    }
    Ok(written)
}

/// What the summary says about one method.
pub struct MethodStats {
    pub method: String,
    pub order: usize,
    pub symplectic: bool,
    pub ok: usize,
    pub runs: usize,
    /// [`fitted_order`] (fixed-step methods only).
    pub slope: Option<f64>,
    /// The smallest error and the smallest energy error over the
    /// successful runs (infinite when none succeeded).
    pub min_error: f64,
    pub best_energy_error: f64,
    /// [`time_to_error`] at the summary's target.
    pub time_to_target: Option<f64>,
}

/// One [`MethodStats`] per method, in order of first appearance.
pub fn stats(rows: &[Row], target: f64) -> Vec<MethodStats> {
    let tte = time_to_error(rows, target);
    methods(rows)
        .into_iter()
        .map(|m| {
            let mine: Vec<&Row> = rows.iter().filter(|r| r.method == m).collect();
            let first = mine[0];
            let good = || mine.iter().filter(|r| r.ok());
            MethodStats {
                method: m.to_string(),
                order: first.order,
                symplectic: first.symplectic,
                ok: good().count(),
                runs: mine.len(),
                slope: if first.tol.is_nan() {
                    fitted_order(rows, m)
                } else {
                    None
                },
                min_error: good().map(|r| r.error).fold(f64::INFINITY, f64::min),
                best_energy_error: good().map(|r| r.energy_error).fold(f64::INFINITY, f64::min),
                time_to_target: tte.iter().find(|(n, _)| n == m).map(|(_, t)| *t),
            }
        })
        .collect()
}

/// The printed summary: one line per method.
pub fn summary(rows: &[Row], target: f64) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<22} {:>5} {:>5} {:>6} {:>7} {:>10} {:>10} {:>12}",
        "method",
        "order",
        "sympl",
        "ok",
        "slope",
        "min error",
        "best dE/E",
        format!("t(err={target:.0e})")
    );
    for st in stats(rows, target) {
        let _ = writeln!(
            s,
            "{:<22} {:>5} {:>5} {:>6} {:>7} {:>10} {:>10} {:>12}",
            st.method,
            st.order,
            if st.symplectic { "yes" } else { "no" },
            format!("{}/{}", st.ok, st.runs),
            format::opt(st.slope, |x| format::fixed(x, 2)),
            format::sci(st.min_error, 2),
            format::sci(st.best_energy_error, 2),
            format::opt(st.time_to_target, |t| format!("{} s", format::sci(t, 3))),
        );
    }
    s
}

/// The summary and the time-to-error table of a `runs.csv` read back
/// (what `symlab compare --from` prints); an error when it has no runs.
pub fn summary_of_file(path: &Path, target: f64) -> Result<String> {
    let rows = read_runs(path)?;
    if rows.is_empty() {
        return Err(CompareError::Csv {
            path: path.to_path_buf(),
            why: "no runs".into(),
        });
    }
    Ok(summary(&rows, target) + &time_to_error_table(&rows, target, &path.display().to_string()))
}

/// The time-to-error table, fastest first, as printed.
pub fn time_to_error_table(rows: &[Row], target: f64, what: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Wall time to reach relative error {target:.0e} ({what}), fastest first:"
    );
    let tte = time_to_error(rows, target);
    for (i, (m, t)) in tte.iter().enumerate() {
        let _ = writeln!(s, "{:>3}. {:<22} {:>10.3e} s", i + 1, m, t);
    }
    let missing = not_bracketed(rows, target);
    if !missing.is_empty() {
        let _ = writeln!(s, "not bracketed by the sweep: {}", missing.join(", "));
    }
    s
}
