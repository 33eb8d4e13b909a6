//! `report.md` of a work–precision sweep, and the Markdown pieces it shares
//! with `--peer-study`: the summary and fastest-first tables, why a method
//! did not reach the target, and our fastest method against the peer.

use std::fmt::Write as _;

use crate::format::{self, MISSING};
use crate::output::{Reach, ladder, not_bracketed, reach, stats};
use crate::rebound::is_rebound;
use crate::row::Row;

/// The method id of the peer.
pub const PEER: &str = "dop853";

fn yes_no(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

/// Where on its sweep a run lies: its step count, or the peer's tolerance.
fn at(r: &Row) -> String {
    if r.tol.is_nan() {
        format!("{} steps", format::count(r.steps as f64))
    } else {
        format!(
            "rtol = atol = {:.0e} ({} steps)",
            r.tol,
            format::count(r.steps as f64)
        )
    }
}

/// Why `method` has no interpolated time to `target`, in words.
pub fn miss_reason(rows: &[Row], method: &str, target: f64) -> String {
    let mine: Vec<&Row> = rows.iter().filter(|r| r.method == method).collect();
    let failed: Vec<&Row> = mine.iter().filter(|r| !r.ok()).copied().collect();
    let runs = ladder(rows, method);
    let Some(cheapest) = runs.first() else {
        return match failed.first() {
            Some(f) if failed.len() == mine.len() => format!(
                "no successful run: all {} failed (first: {})",
                mine.len(),
                f.status
            ),
            _ => "no successful run with a measurable time and error".into(),
        };
    };
    let failures = match failed.first() {
        Some(f) => format!(
            "; {} of {} runs failed (first: {})",
            failed.len(),
            mine.len(),
            f.status
        ),
        None => String::new(),
    };
    if cheapest.error <= target {
        return format!(
            "below the target already at its cheapest run (error {} at {}, {} ms): at most that time{failures}",
            format::err(cheapest.error),
            at(cheapest),
            format::ms(cheapest.time_s)
        );
    }
    let best = runs
        .iter()
        .min_by(|a, b| a.error.total_cmp(&b.error))
        .expect("at least one run");
    format!(
        "smallest error {} at {}{failures}",
        format::err(best.error),
        at(best)
    )
}

/// The method's name in tables: `id`, or `id (interpreted)` when its rows
/// come from a run-time interpreter (a table file).
pub fn method_label(rows: &[Row], method: &str) -> String {
    if rows.iter().any(|r| r.method == method && r.interpreted) {
        format!("{method} (interpreted)")
    } else {
        method.to_string()
    }
}

/// The summary as a Markdown table, one row per method.
pub fn summary_table(rows: &[Row], target: f64) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| method | order | symplectic | ok runs | fitted slope | min error | best energy error | time to {target:.0e} (ms) |"
    );
    let _ = writeln!(s, "|---|---:|---|---:|---:|---:|---:|---:|");
    for st in stats(rows, target) {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {}/{} | {} | {} | {} | {} |",
            method_label(rows, &st.method),
            st.order,
            yes_no(st.symplectic),
            st.ok,
            st.runs,
            format::opt(st.slope, |x| format::fixed(x, 2)),
            format::err(st.min_error),
            format::err(st.best_energy_error),
            format::opt(st.time_to_target, format::ms),
        );
    }
    s
}

/// The bracketed times to `target` as a Markdown table, fastest first.
pub fn time_table(rows: &[Row], target: f64) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| rank | method | symplectic | time (ms) | steps | evaluations |"
    );
    let _ = writeln!(s, "|---:|---|---|---:|---:|---:|");
    let bracketed = reach(rows, target).into_iter().filter(|r| !r.upper_bound);
    for (i, r) in bracketed.enumerate() {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.0} | {:.0} |",
            i + 1,
            method_label(rows, &r.method),
            yes_no(r.symplectic),
            format::ms(r.time_s),
            r.steps,
            r.evals
        );
    }
    s
}

/// The methods without an interpolated time to `target`, one list item
/// each with the reason.
pub fn misses(rows: &[Row], target: f64) -> String {
    let mut s = String::new();
    for m in not_bracketed(rows, target) {
        let _ = writeln!(s, "- {m}: {}", miss_reason(rows, &m, target));
    }
    s
}

/// Which side is faster at a target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Winner {
    Ours,
    Peer,
    /// The slower side's figure is only an upper bound.
    Undetermined,
    /// Both times interpolated and within [`TIE`] of each other: closer than
    /// the timings can tell apart.
    Tie,
}

/// Times within this factor of each other are a tie.
pub const TIE: f64 = 1.1;

impl Winner {
    pub fn label(self) -> &'static str {
        match self {
            Winner::Ours => "ours",
            Winner::Peer => "dop853",
            Winner::Undetermined => "undetermined",
            Winner::Tie => "tie (within 10 %)",
        }
    }
}

/// Our fastest method against the peer at one target.
#[derive(Clone, Debug)]
pub struct Duel {
    pub target: f64,
    pub ours: Option<Reach>,
    pub peer: Option<Reach>,
    pub winner: Winner,
}

impl Duel {
    /// Peer time over ours (above 1: ours is faster); `None` unless both
    /// are interpolated times.
    pub fn ratio(&self) -> Option<f64> {
        match (&self.ours, &self.peer) {
            (Some(o), Some(p)) if !o.upper_bound && !p.upper_bound => Some(p.time_s / o.time_s),
            _ => None,
        }
    }
}

/// The fastest of our methods and the peer at `target`, or `None` when
/// neither reaches it. A side that does not reach the target loses; when
/// the slower side's time is only an upper bound the winner is
/// undetermined; times within 10 % of each other are a tie.
///
/// Interpreted methods (table files) take no part: their wall times are
/// those of a loop over the table, not of generated code. Nor do REBOUND's
/// (see [`rebound_table`]).
pub fn duel(rows: &[Row], target: f64) -> Option<Duel> {
    let generated: Vec<Row> = rows
        .iter()
        .filter(|r| !r.interpreted && !is_rebound(&r.method))
        .cloned()
        .collect();
    let all = reach(&generated, target);
    let ours = all.iter().find(|r| r.method != PEER).cloned();
    let peer = all.iter().find(|r| r.method == PEER).cloned();
    let winner = match (&ours, &peer) {
        (None, None) => return None,
        (Some(_), None) => Winner::Ours,
        (None, Some(_)) => Winner::Peer,
        (Some(o), Some(p)) => {
            let (slow, ours_faster) = if o.time_s <= p.time_s {
                (p, true)
            } else {
                (o, false)
            };
            if slow.upper_bound {
                Winner::Undetermined
            } else if !o.upper_bound
                && !p.upper_bound
                && slow.time_s <= TIE * o.time_s.min(p.time_s)
            {
                Winner::Tie
            } else if ours_faster {
                Winner::Ours
            } else {
                Winner::Peer
            }
        }
    };
    Some(Duel {
        target,
        ours,
        peer,
        winner,
    })
}

/// `smallest error is 1.7e-11, at rtol = atol = 1e-17 (…)`: the peer's best run.
fn peer_best(rows: &[Row]) -> String {
    ladder(rows, PEER)
        .into_iter()
        .min_by(|a, b| a.error.total_cmp(&b.error))
        .map_or("runs all failed".into(), |r| {
            format!("smallest error is {}, at {}", format::err(r.error), at(r))
        })
}

/// A time cell: `≤ t` for an upper bound, `not reached` for none.
pub fn time_cell(r: Option<&Reach>) -> String {
    match r {
        Some(r) if r.upper_bound => format!("≤ {}", format::ms(r.time_s)),
        Some(r) => format::ms(r.time_s),
        None => "not reached".into(),
    }
}

/// The ratio cell of a duel.
pub fn ratio_cell(d: &Duel) -> String {
    format::opt(d.ratio(), format::ratio)
}

/// One sentence per outcome: at which targets ours is faster (and at
/// which the peer does not reach the target at all), at which the peer
/// (and at which none of ours reaches it), with the range of the speed-ups.
/// `rows` are the runs the duels were computed from (for the peer's
/// smallest error).
pub fn verdict(duels: &[Duel], rows: &[Row]) -> String {
    let pick =
        |f: &dyn Fn(&Duel) -> bool| -> Vec<&Duel> { duels.iter().filter(|d| f(d)).collect() };
    let targets = |ds: &[&Duel]| -> String {
        ds.iter()
            .map(|d| format!("{:.0e}", d.target))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let range = |ds: &[&Duel], invert: bool| -> String {
        let r: Vec<f64> = ds
            .iter()
            .filter_map(|d| d.ratio())
            .map(|x| if invert { 1.0 / x } else { x })
            .collect();
        if r.is_empty() {
            return String::new();
        }
        let lo = r.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = r.iter().copied().fold(0.0, f64::max);
        if format::ratio(lo) == format::ratio(hi) {
            format!(", {}× faster", format::ratio(lo))
        } else {
            format!(", {}–{}× faster", format::ratio(lo), format::ratio(hi))
        }
    };
    let say = |ds: Vec<&Duel>, text: &str, invert: Option<bool>| -> String {
        if ds.is_empty() {
            return String::new();
        }
        let r = invert.map_or(String::new(), |inv| range(&ds, inv));
        format!("- {text} {}{r}.\n", targets(&ds))
    };
    let mut s = say(
        pick(&|d| d.winner == Winner::Ours && d.peer.is_some()),
        "Our fastest method beats DOP853 at",
        Some(false),
    );
    let only_ours = pick(&|d| d.winner == Winner::Ours && d.peer.is_none());
    if !only_ours.is_empty() {
        let _ = writeln!(
            s,
            "- Only ours reach {}; DOP853's {}.",
            targets(&only_ours),
            peer_best(rows)
        );
    }
    s += &say(
        pick(&|d| d.winner == Winner::Peer && d.ours.is_some()),
        "DOP853 beats our fastest method at",
        Some(true),
    );
    s += &say(
        pick(&|d| d.winner == Winner::Peer && d.ours.is_none()),
        "Only DOP853 reaches (none of ours does within the sweep):",
        None,
    );
    s += &say(
        pick(&|d| d.winner == Winner::Tie),
        "A tie (times within 10 %, closer than the timings tell apart) at",
        None,
    );
    s += &say(
        pick(&|d| d.winner == Winner::Undetermined),
        "Undetermined (the slower side is below the target already at its cheapest run):",
        None,
    );
    s
}

/// The "Peer" section of `report.md`: our fastest method against DOP853
/// at each decade 1e-2 … 1e-12 that either side reaches; `None` without
/// successful peer runs.
pub fn peer_section(rows: &[Row]) -> Option<String> {
    if !rows.iter().any(|r| r.method == PEER && r.ok()) {
        return None;
    }
    let duels: Vec<Duel> = (2..=12)
        .filter_map(|k| duel(rows, 10f64.powi(-k)))
        .collect();
    let mut s = String::new();
    let _ = writeln!(s, "## Peer: DOP853 against our fastest method\n");
    let _ = writeln!(
        s,
        "For each relative error from 1e-2 to 1e-12 (by decades) that either side reaches within the sweep: \
         the fastest of our methods at that error, DOP853's time (interpolated between its tolerances as ours \
         between step sizes), their ratio (above 1: ours is faster) and the faster side. `≤` marks a time \
         that is only an upper bound (the cheapest run is already below the target). DOP853's time is that of \
         a whole call: building the solver and storing the state at each accepted step (four numbers).\n"
    );
    if duels.is_empty() {
        let _ = writeln!(s, "Neither side reaches 1e-2 within the sweep.");
        return Some(s);
    }
    let _ = writeln!(
        s,
        "| target | fastest of ours | symplectic | ours (ms) | dop853 (ms) | dop853 / ours | faster |"
    );
    let _ = writeln!(s, "|---:|---|---|---:|---:|---:|---|");
    for d in &duels {
        let _ = writeln!(
            s,
            "| {:.0e} | {} | {} | {} | {} | {} | {} |",
            d.target,
            d.ours.as_ref().map_or(MISSING, |o| o.method.as_str()),
            d.ours.as_ref().map_or(MISSING, |o| yes_no(o.symplectic)),
            time_cell(d.ours.as_ref()),
            time_cell(d.peer.as_ref()),
            ratio_cell(d),
            d.winner.label()
        );
    }
    let _ = writeln!(s);
    s.push_str(&verdict(&duels, rows));
    Some(s)
}

/// Our fastest method, REBOUND's fastest without WHFast512, and WHFast512's
/// fastest at `target` (each `None` when it does not reach it). Ours are
/// the generated schemes (not interpreted tables, not DOP853).
pub fn rebound_fastest(rows: &[Row], target: f64) -> (Option<Reach>, Option<Reach>, Option<Reach>) {
    let all = reach(rows, target);
    let interpreted = |m: &str| rows.iter().any(|r| r.method == m && r.interpreted);
    let w512 = |m: &str| m.starts_with("rebound:whfast512");
    let ours = all
        .iter()
        .find(|r| !is_rebound(&r.method) && r.method != PEER && !interpreted(&r.method))
        .cloned();
    let theirs = all
        .iter()
        .find(|r| is_rebound(&r.method) && !w512(&r.method))
        .cloned();
    let avx = all.iter().find(|r| w512(&r.method)).cloned();
    (ours, theirs, avx)
}

/// `ours / theirs` when both times are interpolated (not upper bounds).
fn time_ratio(ours: &Option<Reach>, theirs: &Option<Reach>) -> String {
    match (ours, theirs) {
        (Some(o), Some(t)) if !o.upper_bound && !t.upper_bound => {
            format::ratio(o.time_s / t.time_s)
        }
        _ => MISSING.to_string(),
    }
}

/// Our fastest method against REBOUND's at each decade 1e-2 … 1e-12 that
/// any side reaches: the table, as plain text for the terminal and
/// Markdown for `report.md`. `ours / REBOUND` below 1: ours is faster.
pub fn rebound_table(rows: &[Row], version: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\nREBOUND {version} against our fastest method (time to each relative error, interpolated; ≤: an upper bound):\n"
    );
    let _ = writeln!(
        s,
        "| error | our fastest | ours (ms) | REBOUND's fastest, no AVX-512 | REBOUND (ms) | ours / REBOUND | WHFast512 | WHFast512 (ms) | ours / WHFast512 |"
    );
    let _ = writeln!(s, "|---:|---|---:|---|---:|---:|---|---:|---:|");
    let name = |r: &Option<Reach>| r.as_ref().map_or(MISSING.to_string(), |r| r.method.clone());
    let mut any = false;
    for k in 2..=12 {
        let target = 10f64.powi(-k);
        let (ours, theirs, avx) = rebound_fastest(rows, target);
        if ours.is_none() && theirs.is_none() && avx.is_none() {
            continue;
        }
        any = true;
        let _ = writeln!(
            s,
            "| {target:.0e} | {} | {} | {} | {} | {} | {} | {} | {} |",
            name(&ours),
            time_cell(ours.as_ref()),
            name(&theirs),
            time_cell(theirs.as_ref()),
            time_ratio(&ours, &theirs),
            name(&avx),
            time_cell(avx.as_ref()),
            time_ratio(&ours, &avx),
        );
    }
    if !any {
        let _ = writeln!(s, "No method reaches 1e-2 within the sweep.");
    }
    s
}

/// The REBOUND section of `report.md`; `None` without successful REBOUND
/// runs.
pub fn rebound_section(rows: &[Row], version: &str) -> Option<String> {
    if !rows.iter().any(|r| is_rebound(&r.method) && r.ok()) {
        return None;
    }
    let mut s = String::from("## REBOUND against our fastest method\n\n");
    let _ = writeln!(
        s,
        "REBOUND {version} ran through its Python package (compare/peers/rebound_peer.py), one process per \
         run, from our initial state bit for bit (hexadecimal floats both ways); its final state was measured \
         here against the same reference. Its time is the median of the timed `sim.integrate` calls after a \
         warm-up, measured inside Python: building the simulation is not counted, as building our state is \
         not. WHFast512 (AVX-512) has a column of its own."
    );
    s.push_str(&rebound_table(rows, version));
    Some(s)
}

/// The note on table files stepped by the interpreters, when any ran.
pub fn interpreted_section(rows: &[Row]) -> Option<String> {
    let mut ids: Vec<&str> = Vec::new();
    for r in rows.iter().filter(|r| r.interpreted) {
        if !ids.contains(&r.method.as_str()) {
            ids.push(&r.method);
        }
    }
    if ids.is_empty() {
        return None;
    }
    let mut s = String::from(
        "## Interpreted tables

",
    );
    let _ = writeln!(
        s,
        "{} came from table files, verified exactly and stepped by the run-time interpreters          (`interpreted = true` in runs.csv). Their errors and evaluation counts compare with the          generated schemes; their wall times do not: a loop over a table held in memory is slower          than the step code `butcher!` generates, so they take no part in the comparison with          DOP853. Their times compare with library tables stepped by the same interpreter          (`--methods interp:ID`). For generated-code timings declare the table with `butcher!`          (`butcher! {{ file: \"PATH\" }}` reads a table file) and add it through the library, as          `cargo run --release --example my_scheme` and `--example designed_method` do.",
        ids.iter()
            .map(|i| format!("`{i}`"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    Some(s)
}

/// `report.md` of a work–precision sweep: `title`, the `head` lines (the
/// problem, `T`, the sweep settings), the summary, the fastest-first times
/// to `target`, the methods that do not reach it and why, and (when the
/// peer ran) the peer section. `over` names the run length in the heading
/// (e.g. `T = 62.83`).
pub fn sweep_report(title: &str, head: &[String], rows: &[Row], target: f64, over: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# {title}\n");
    for line in head {
        let _ = writeln!(s, "- {line}");
    }
    let _ = writeln!(s, "\n## Summary\n");
    s.push_str(&summary_table(rows, target));
    let _ = writeln!(
        s,
        "\nFitted slope: least-squares slope of log error against log h over the runs with error in \
         (1e-12, 1e-1) (fixed-step methods). Best energy error: the smallest over the runs of \
         max |E − E₀|/|E₀| along the run.\n"
    );
    let _ = writeln!(
        s,
        "## Wall time to reach relative error {target:.0e} over {over}, fastest first\n"
    );
    let _ = writeln!(
        s,
        "Interpolated in log–log between the two runs of the sweep that bracket the error (steps and \
         evaluations likewise).\n"
    );
    s.push_str(&time_table(rows, target));
    let missing = misses(rows, target);
    let _ = writeln!(s, "\n## Did not reach {target:.0e} within the sweep\n");
    if missing.is_empty() {
        let _ = writeln!(s, "Every method brackets the target.");
    } else {
        s.push_str(&missing);
    }
    if let Some(peer) = peer_section(rows) {
        let _ = writeln!(s);
        s.push_str(&peer);
    }
    if let Some(note) = interpreted_section(rows) {
        let _ = writeln!(s);
        s.push_str(&note);
    }
    s
}
