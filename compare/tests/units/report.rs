//! Tests of `compare::report` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::Family;
use compare::report::*;
use compare::*;

/// A successful run of `method` (the peer at rtol 1e-6) for tests.
pub fn row(method: &str, steps: u64, error: f64, time_s: f64) -> Row {
    Row {
        problem: "p".into(),
        method: method.into(),
        family: Family::Splitting,
        order: 2,
        symplectic: method != PEER,
        h: 1.0 / steps as f64,
        tol: if method == PEER { 1e-6 } else { f64::NAN },
        steps,
        error,
        energy_error: 1e-9,
        time_s,
        evals: steps,
        newton_iterations: 0,
        fixed_point_iterations: 0,
        factorizations: 0,
        status: "ok".into(),
        interpreted: false,
    }
}

#[test]
fn duels_pick_the_faster_side_and_say_why_others_miss() {
    let rows = vec![
        row("a", 100, 1e-4, 1e-3),
        row("a", 1000, 1e-8, 1e-2),
        row(PEER, 50, 1e-3, 1e-4),
        row(PEER, 500, 1e-6, 1e-3),
        row("b", 1000, 1e-3, 1e-3),
        row("b", 1_000_000, 1.8e-3, 1.0),
    ];
    let d = duel(&rows, 1e-5).unwrap();
    assert_eq!(d.winner, Winner::Peer);
    assert_eq!(d.ours.as_ref().unwrap().method, "a");
    let close = vec![row("a", 100, 1e-4, 1.0), row(PEER, 100, 1e-4, 1.05)];
    assert_eq!(duel(&close, 1e-4).unwrap().winner, Winner::Undetermined);
    let close = vec![
        row("a", 10, 1e-2, 0.1),
        row("a", 100, 1e-6, 1.0),
        row(PEER, 10, 1e-2, 0.1),
        row(PEER, 100, 1e-6, 1.05),
    ];
    assert_eq!(duel(&close, 1e-6).unwrap().winner, Winner::Tie);
    let d = duel(&rows, 1e-7).unwrap();
    assert_eq!(d.winner, Winner::Ours);
    assert!(d.peer.is_none());
    assert!(duel(&rows, 1e-9).is_none());
    assert_eq!(
        miss_reason(&rows, "b", 1e-5),
        "smallest error 1.0e-3 at 10³ steps"
    );
    assert!(miss_reason(&rows, PEER, 1e-8).contains("rtol = atol = 1e-6"));
    let report = sweep_report("t", &["x".into()], &rows, 1e-5, "T = 1");
    assert!(report.contains("## Peer: DOP853 against our fastest method"));
    assert!(report.contains("- b: smallest error"));
    assert!(
        report.contains(
            "- Only ours reach 1e-7, 1e-8; DOP853's smallest error is 1.0e-6, at rtol = atol = 1e-6 (500 steps)."
        ),
        "{report}"
    );
}
