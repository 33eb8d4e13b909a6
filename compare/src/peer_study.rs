//! `symlab compare --peer-study`: our strongest schemes — fixed-step,
//! time-transformed (`logh:ID`) and reversible adaptive (`adaptive:ID`) —
//! against DOP853 on Kepler with e = 0.6 and e = 0.9 over 100 and 1000
//! orbits. The same sweeps as the work–precision comparison
//! ([`sweep::sweep`]), one per eccentricity and run length, with step
//! ranges chosen per length so that the good methods bracket errors around
//! 1e-6 … 1e-12. (For `logh:ID` and `adaptive:ID` a step count `n` sets the
//! first step `T/n`; they take the steps they need, reported in `steps`.)

use std::f64::consts::PI;
use std::fmt::Write as _;

use std::path::Path;

use integrator_core::problems::Kepler;

use crate::builtin;
use crate::error::{CompareError, Result, write};
use crate::format::{self, MISSING};
use crate::method::Method;
use crate::output::{self, Reach, reach};
use crate::report::{self, Duel, PEER, duel, time_cell};
use crate::sweep::SweepObserver;
use crate::sweep::{self, Row};

/// The methods of the study (`--methods` replaces them).
pub const METHODS: &[&str] = &[
    "logh:sofroniou-spaletta10",
    "logh:kahan-li8",
    "logh:mclachlan8",
    "adaptive:sofroniou-spaletta10",
    "adaptive:kahan-li8",
    "sofroniou-spaletta10",
    "kahan-li8",
    "gauss8",
    "dop853",
];
/// The methods of `--quick`.
pub const QUICK_METHODS: &[&str] = &[
    "kahan-li8",
    "logh:kahan-li8",
    "adaptive:kahan-li8",
    "dop853",
];

/// The eccentricities of the study: `kepler` and `kepler-hard`.
pub const ECCENTRICITIES: [f64; 2] = [0.6, 0.9];

/// The relative errors of the verdict (`--target` adds one).
pub const TARGETS: [f64; 3] = [1e-6, 1e-8, 1e-10];

/// One run length: `orbits` orbits of period 2π, fixed-step methods at
/// `points` log-spaced step counts from `min_steps` to `max_steps`.
#[derive(Clone, Copy, Debug)]
pub struct Leg {
    pub orbits: f64,
    pub min_steps: u64,
    pub max_steps: u64,
    pub points: usize,
}

/// From 20 steps per orbit (errors of order one for the eighth-order
/// schemes) up, at most 10⁶ steps per run, about four points per decade.
pub const LEGS: [Leg; 2] = [
    Leg {
        orbits: 100.0,
        min_steps: 2_000,
        max_steps: 1_000_000,
        points: 12,
    },
    Leg {
        orbits: 1000.0,
        min_steps: 20_000,
        max_steps: 1_000_000,
        points: 8,
    },
];
/// The run lengths of `--quick`: 1 and 10 orbits.
pub const QUICK_LEGS: [Leg; 2] = [
    Leg {
        orbits: 1.0,
        min_steps: 20,
        max_steps: 2_000,
        points: 4,
    },
    Leg {
        orbits: 10.0,
        min_steps: 200,
        max_steps: 20_000,
        points: 4,
    },
];

/// The settings of a peer study.
#[derive(Clone, Debug)]
pub struct PeerStudySettings {
    /// The eccentricities (each one a Kepler problem, every leg on each).
    pub eccentricities: Vec<f64>,
    pub legs: Vec<Leg>,
    /// Method ids; `dop853` must be among them.
    pub methods: Vec<String>,
    /// DOP853's `rtol = atol`.
    pub tolerances: Vec<f64>,
    /// Timed runs per point (the median is reported).
    pub repeats: usize,
    /// The relative errors of the verdict, largest first.
    pub targets: Vec<f64>,
    /// The error at which the max energy error of each method is reported.
    pub energy_target: f64,
}

impl PeerStudySettings {
    /// e = 0.6 and 0.9, 100 and 1000 orbits, [`METHODS`], DOP853 at
    /// 1e-4 … 1e-18 (one per decade; over 1000 orbits it reaches 1e-8 only
    /// near 1e-16, its round-off floor near 1e-17), five timed runs per
    /// point (the close calls need it), targets [`TARGETS`].
    pub fn full() -> Self {
        PeerStudySettings {
            eccentricities: ECCENTRICITIES.to_vec(),
            legs: LEGS.to_vec(),
            methods: METHODS.iter().map(|s| s.to_string()).collect(),
            tolerances: sweep::tolerances(sweep::PEER_TOLERANCES),
            repeats: 5,
            targets: TARGETS.to_vec(),
            energy_target: 1e-8,
        }
    }

    /// A smoke run: both eccentricities, 1 and 10 orbits, 4 step counts
    /// and tolerances, [`QUICK_METHODS`], one timed run.
    pub fn quick() -> Self {
        PeerStudySettings {
            legs: QUICK_LEGS.to_vec(),
            methods: QUICK_METHODS.iter().map(|s| s.to_string()).collect(),
            tolerances: sweep::tolerances(4),
            repeats: 1,
            ..Self::full()
        }
    }

    /// Add a target (kept sorted, largest first, without duplicates).
    pub fn with_target(mut self, target: f64) -> Self {
        if !self.targets.contains(&target) {
            self.targets.push(target);
        }
        self.targets.sort_by(|a, b| b.total_cmp(a));
        self
    }

    fn validate(&self) -> Result<()> {
        if !(1..=100).contains(&self.repeats) {
            return Err(CompareError::setting(
                "repeats",
                format!("between 1 and 100 timed runs, got {}", self.repeats),
            ));
        }
        if !self.methods.iter().any(|m| m == PEER) {
            return Err(CompareError::setting(
                "methods",
                "--peer-study compares against dop853: keep it in --methods",
            ));
        }
        if let Some(e) = self
            .eccentricities
            .iter()
            .find(|e| !(e.is_finite() && (0.0..1.0).contains(*e)))
        {
            return Err(CompareError::setting(
                "eccentricities",
                format!("a bound Kepler orbit needs 0 ≤ e < 1, got {e}"),
            ));
        }
        if self.eccentricities.is_empty()
            || self.legs.is_empty()
            || self.tolerances.is_empty()
            || self.targets.is_empty()
        {
            return Err(CompareError::setting(
                "legs",
                "a peer study needs at least one run length, tolerance and target",
            ));
        }
        for l in &self.legs {
            if !(l.orbits.is_finite() && l.orbits > 0.0)
                || l.min_steps == 0
                || l.min_steps > l.max_steps
                || l.max_steps > 100_000_000
                || l.points == 0
            {
                return Err(CompareError::setting(
                    "legs",
                    format!(
                        "a run length needs orbits > 0 and 1 ≤ min_steps ≤ max_steps ≤ 10⁸, points ≥ 1; got {l:?}"
                    ),
                ));
            }
        }
        for (name, v) in [("tolerances", &self.tolerances), ("targets", &self.targets)] {
            if let Some(x) = v.iter().find(|x| !(x.is_finite() && **x > 0.0)) {
                return Err(CompareError::setting(
                    name,
                    format!("must be finite numbers > 0, got {x}"),
                ));
            }
        }
        Ok(())
    }
}

/// The results of one eccentricity and run length.
pub struct LegRows {
    pub e: f64,
    pub leg: Leg,
    pub t_end: f64,
    pub rows: Vec<Row>,
}

/// A finished peer study.
pub struct PeerStudy {
    pub settings: PeerStudySettings,
    pub legs: Vec<LegRows>,
    /// What was left out and why (a `rebound:` method whose interpreter or
    /// REBOUND is missing): the front end shows these, and `peer.md` has
    /// them.
    pub notes: Vec<String>,
}

/// Run the study: for each run length a sweep (see [`sweep::sweep`]),
/// each announced to `observer` as a stage, its rows reported as they come.
pub fn run(settings: PeerStudySettings, observer: &mut dyn SweepObserver) -> Result<PeerStudy> {
    settings.validate()?;
    let repeats = settings.repeats;
    let mut results = Vec::new();
    let mut notes = Vec::new();
    let mut left_out: Vec<String> = Vec::new();
    for (k, &e) in settings.eccentricities.iter().enumerate() {
        let sys = Kepler { e };
        let mut methods: Vec<Method<Kepler>> = settings
            .methods
            .iter()
            .map(|id| Method::by_id(id, &sys))
            .collect::<Result<_>>()?;
        // REBOUND's methods are probed once, as the sweep does: one whose
        // interpreter or REBOUND is missing is left out with a note rather
        // than run to a column of failures.
        if k == 0 {
            let rebound = crate::rebound::availability(methods.iter().filter_map(|m| match m {
                Method::Rebound(r) => Some(r),
                _ => None,
            }));
            notes = rebound.notes;
            left_out = rebound.left_out;
        }
        methods.retain(|m| !left_out.iter().any(|id| id == m.id()));
        for &leg in &settings.legs {
            let t_end = 2.0 * PI * leg.orbits;
            let setup = if e == 0.6 || e == 0.9 {
                builtin::kepler(e == 0.9, t_end, true)?
            } else {
                crate::problem::Setup::new(sys, t_end)?
            };
            let steps = sweep::step_counts(
                t_end,
                t_end / leg.max_steps as f64,
                t_end / leg.min_steps as f64,
                leg.points,
            );
            observer.stage(&format!(
                "Kepler e = {e}, {} orbits (T = {t_end:.2}): {} methods, {} step counts ({}–{}), dop853 at {} tolerances, {repeats} timed run(s) each",
                leg.orbits,
                methods.len(),
                steps.len(),
                steps[0],
                steps.last().expect("at least one"),
                settings.tolerances.len()
            ));
            let rows = sweep::sweep_each_from(
                &setup,
                methods.iter(),
                &steps,
                &settings.tolerances,
                repeats,
                Vec::new(),
                observer,
            )
            .rows;
            results.push(LegRows {
                e,
                leg,
                t_end,
                rows,
            });
        }
    }
    Ok(PeerStudy {
        settings,
        legs: results,
        notes,
    })
}

impl PeerStudy {
    /// Every row, in the order run, and the end time of each.
    pub fn rows(&self) -> (Vec<Row>, Vec<f64>) {
        let all: Vec<Row> = self.legs.iter().flat_map(|l| l.rows.clone()).collect();
        let t_ends: Vec<f64> = self
            .legs
            .iter()
            .flat_map(|l| std::iter::repeat_n(l.t_end, l.rows.len()))
            .collect();
        (all, t_ends)
    }

    /// `peer.csv` and `peer.md` in `dir`.
    pub fn write(&self, dir: &Path) -> Result<()> {
        let (all, t_ends) = self.rows();
        output::write_csv_with(&dir.join("peer.csv"), &all, &["t_end"], |i| {
            vec![format!("{:e}", t_ends[i])]
        })?;
        write(&dir.join("peer.md"), self.markdown())
    }

    /// `peer.md`.
    pub fn markdown(&self) -> String {
        let s = &self.settings;
        markdown(
            &self.legs,
            &s.methods,
            &self.notes,
            &s.targets,
            s.energy_target,
            &s.tolerances,
            s.repeats,
        )
    }

    /// The verdict: for each run length and target, our fastest method
    /// against DOP853 (Markdown).
    pub fn verdict(&self) -> String {
        verdict_table(&self.legs, &self.settings.targets)
    }
}

fn orbits(leg: &Leg) -> String {
    format!("{}", leg.orbits)
}

/// `e = 0.6, 1 orbit`, `e = 0.9, 10 orbits`.
fn orbits_words(l: &LegRows) -> String {
    if l.leg.orbits == 1.0 {
        format!("e = {}, 1 orbit", l.e)
    } else {
        format!("e = {}, {} orbits", l.e, l.leg.orbits)
    }
}

fn energy_cell(r: Option<&Reach>) -> String {
    format::opt(r.map(|r| r.energy_error), format::err)
}

/// The verdict: for each run length and target, our fastest method against
/// DOP853 with their times and energy errors.
fn verdict_table(results: &[LegRows], targets: &[f64]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| e | orbits | target | fastest of ours | ours (ms) | ours max energy error | dop853 (ms) | dop853 max energy error | dop853 / ours | faster |"
    );
    let _ = writeln!(s, "|---:|---:|---:|---|---:|---:|---:|---:|---:|---|");
    for l in results {
        for &t in targets {
            match duel(&l.rows, t) {
                Some(d) => {
                    let _ = writeln!(
                        s,
                        "| {} | {} | {t:.0e} | {} | {} | {} | {} | {} | {} | {} |",
                        l.e,
                        orbits(&l.leg),
                        d.ours.as_ref().map_or(MISSING, |o| o.method.as_str()),
                        time_cell(d.ours.as_ref()),
                        energy_cell(d.ours.as_ref()),
                        time_cell(d.peer.as_ref()),
                        energy_cell(d.peer.as_ref()),
                        report::ratio_cell(&d),
                        d.winner.label()
                    );
                }
                None => {
                    let _ = writeln!(
                        s,
                        "| {} | {} | {t:.0e} | {MISSING} | not reached | {MISSING} | not reached | {MISSING} | {MISSING} | neither |",
                        l.e,
                        orbits(&l.leg)
                    );
                }
            }
        }
    }
    s
}

/// Each value once, in the order of first appearance.
fn distinct(v: Vec<String>) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for x in v {
        if !out.contains(&x) {
            out.push(x);
        }
    }
    out
}

/// `a, b and c`.
fn and(v: &[String]) -> String {
    match v.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => v.join(""),
    }
}

/// `peer.md`: the set-up, the verdict, then one section per eccentricity
/// and run length.
fn markdown(
    results: &[LegRows],
    ids: &[String],
    notes: &[String],
    targets: &[f64],
    energy_target: f64,
    tols: &[f64],
    repeats: usize,
) -> String {
    let mut s = String::new();
    set_up(&mut s, results, ids, notes, tols, repeats);
    verdict_section(&mut s, results, targets);
    for l in results {
        leg_section(&mut s, l, targets, energy_target);
    }
    s
}

/// The title and the set-up: problem, methods, step counts, tolerances,
/// timing and round-off.
fn set_up(
    s: &mut String,
    results: &[LegRows],
    ids: &[String],
    notes: &[String],
    tols: &[f64],
    repeats: usize,
) {
    let lengths = distinct(results.iter().map(|l| orbits(&l.leg)).collect());
    let es = distinct(results.iter().map(|l| l.e.to_string()).collect());
    let _ = writeln!(
        s,
        "# Kepler e = {}: our strongest schemes against DOP853 over {} orbits\n",
        and(&es),
        and(&lengths)
    );
    let _ = writeln!(
        s,
        "- Problem: Kepler, e = {}, from pericentre, orbit period 2π; error ‖z(T) − z_ref(T)‖₂/‖z_ref(T)‖₂ \
         against the exact flow; energy error max |E − E₀|/|E₀| along the run.",
        and(&es)
    );
    let _ = writeln!(
        s,
        "- logh:ID steps the logarithmic Hamiltonian (a fixed step in a fictitious time), adaptive:ID the \
         symmetric scheme ID under the reversible integrating controller with step density 1/r; both start \
         with a step of T/n for a step count n and take the steps they need (the `steps` column), landing on T."
    );
    // DOP853 and REBOUND's integrators are peers, never "ours".
    let (peers, ours): (Vec<&String>, Vec<&String>) = ids
        .iter()
        .partition(|id| *id == PEER || crate::rebound::is_rebound(id));
    let list = |v: &[&String]| v.iter().map(|x| x.as_str()).collect::<Vec<_>>().join(", ");
    let _ = writeln!(
        s,
        "- Methods: ours {}; peers {}.",
        list(&ours),
        list(&peers)
    );
    for n in notes {
        let _ = writeln!(s, "- Note: {n}");
    }
    for l in results {
        let steps = sweep::step_counts(
            l.t_end,
            l.t_end / l.leg.max_steps as f64,
            l.t_end / l.leg.min_steps as f64,
            l.leg.points,
        );
        let _ = writeln!(
            s,
            "- {} (T = {:.2}): fixed-step methods at {} step counts from {} to {} (log-spaced).",
            orbits_words(l),
            l.t_end,
            steps.len(),
            steps[0],
            steps.last().expect("at least one")
        );
    }
    let _ = writeln!(
        s,
        "- DOP853 (ode_solvers, Hairer's 8(5,3) with its default controller) at rtol = atol = {}.",
        tols.iter()
            .map(|t| format!("{t:.0e}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        s,
        "- Timing: median of {repeats} timed run(s) after one warm-up, one run at a time; times to a target are \
         interpolated in log–log between the two runs that bracket it. DOP853's time is that of a whole call \
         (building the solver, storing the state at each accepted step)."
    );
    let _ = writeln!(
        s,
        "- Round-off: our fixed-step schemes add each step's increment with compensated summation (the \
         library's default); DOP853 does not, so on long runs its error levels off higher."
    );
    let _ = writeln!(
        s,
        "- Data: peer.csv (the columns of runs.csv, then t_end).\n"
    );
}

/// "Verdict": the table of duels, then one paragraph per run length.
fn verdict_section(s: &mut String, results: &[LegRows], targets: &[f64]) {
    let _ = writeln!(s, "## Verdict\n");
    let _ = writeln!(
        s,
        "Our fastest method against DOP853 at each run length and relative error. Max energy error: that of \
         the cheapest run reaching the target (measured, not interpolated). `≤`: an upper bound (the cheapest \
         run is already below the target). Ratio above 1: ours is faster.\n"
    );
    s.push_str(&verdict_table(results, targets));
    let _ = writeln!(s);
    for l in results {
        let duels: Vec<Duel> = targets.iter().filter_map(|&t| duel(&l.rows, t)).collect();
        let _ = writeln!(s, "**{}.**\n", orbits_words(l));
        let v = report::verdict(&duels, &l.rows);
        if v.is_empty() {
            let _ = writeln!(s, "- Neither side reaches any of the targets.");
        } else {
            s.push_str(&v);
        }
        let _ = writeln!(s);
    }
}

/// One eccentricity and run length: the time of every method to each
/// target, DOP853's tightest run, and the runs that failed.
fn leg_section(s: &mut String, l: &LegRows, targets: &[f64], energy_target: f64) {
    let _ = writeln!(
        s,
        "## {} (T = {:.2}): time to each target\n",
        orbits_words(l),
        l.t_end
    );
    time_table(s, l, targets, energy_target);
    let _ = writeln!(s);
    peer_tightest(s, l);
    failed_runs(s, l);
}

/// The smallest error of `method`'s runs, and where on its sweep.
fn smallest_error(rows: &[Row], method: &str) -> String {
    output::ladder(rows, method)
        .into_iter()
        .min_by(|a, b| a.error.total_cmp(&b.error))
        .map_or("no successful run".into(), |r| {
            let at = if r.method == PEER {
                format!("rtol {:.0e}", r.tol)
            } else {
                format!("{} steps", format::count(r.steps as f64))
            };
            format!("{} at {at}", format::err(r.error))
        })
}

/// One row per method: its time to each target, its smallest error and
/// its energy error at the energy target.
fn time_table(s: &mut String, l: &LegRows, targets: &[f64], energy_target: f64) {
    let _ = write!(s, "| method | symplectic |");
    for t in targets {
        let _ = write!(s, " {t:.0e} (ms) |");
    }
    let _ = writeln!(
        s,
        " smallest error | max energy error at {energy_target:.0e} |"
    );
    let _ = write!(s, "|---|---|");
    for _ in targets {
        let _ = write!(s, "---:|");
    }
    let _ = writeln!(s, "---|---:|");
    let reaches: Vec<Vec<Reach>> = targets.iter().map(|&t| reach(&l.rows, t)).collect();
    for st in output::stats(&l.rows, targets[0]) {
        let m = st.method.as_str();
        let _ = write!(s, "| {m} | {} |", if st.symplectic { "yes" } else { "no" });
        for r in &reaches {
            let _ = write!(s, " {} |", time_cell(r.iter().find(|x| x.method == m)));
        }
        let de = reach(&l.rows, energy_target)
            .into_iter()
            .find(|x| x.method == m);
        let _ = writeln!(
            s,
            " {} | {} |",
            smallest_error(&l.rows, m),
            energy_cell(de.as_ref())
        );
    }
}

/// The time of DOP853's run at its tightest tolerance that succeeded.
fn peer_tightest(s: &mut String, l: &LegRows) {
    let timings: Vec<(f64, f64)> = l
        .rows
        .iter()
        .filter(|r| r.method == PEER && r.ok())
        .map(|r| (r.tol, r.time_s))
        .collect();
    if let Some(&(tol, t)) = timings.last() {
        let _ = writeln!(
            s,
            "DOP853 at its tightest tolerance ({tol:.0e}): {} ms.\n",
            format::ms(t)
        );
    }
}

/// The runs that failed, with where and why.
fn failed_runs(s: &mut String, l: &LegRows) {
    let failed: Vec<&Row> = l.rows.iter().filter(|r| !r.ok()).collect();
    if failed.is_empty() {
        return;
    }
    let _ = writeln!(s, "Failed runs:\n");
    for r in failed {
        let _ = writeln!(
            s,
            "- {} at {}: {}",
            r.method,
            if r.method == PEER {
                format!("rtol = atol = {:.0e}", r.tol)
            } else {
                format!("{} steps", r.steps)
            },
            r.status
        );
    }
    let _ = writeln!(s);
}
