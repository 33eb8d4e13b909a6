//! Tests of `compare::peer_study` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::peer_study::*;
use compare::report::PEER;
use compare::*;
use std::f64::consts::PI;
fn row(method: &str, steps: u64, error: f64, time_s: f64, status: &str) -> Row {
    Row {
        status: status.into(),
        ..super::report::row(method, steps, error, time_s)
    }
}

/// A study of two run lengths, with a failed run, a method that never
/// reaches a target and the peer: the report has every section.
fn study() -> PeerStudy {
    let mut settings = PeerStudySettings::quick();
    settings.methods = vec!["kahan-li8".into(), "logh:kahan-li8".into(), PEER.into()];
    let rows = |scale: f64| {
        vec![
            row("kahan-li8", 20, 1e-4 * scale, 1e-4, "ok"),
            row("kahan-li8", 200, 1e-9 * scale, 1e-3, "ok"),
            row("kahan-li8", 2000, 1e-13 * scale, 1e-2, "ok"),
            row("logh:kahan-li8", 20, 1e-3, 2e-4, "ok"),
            row(
                "logh:kahan-li8",
                200,
                f64::NAN,
                f64::NAN,
                "diverged at step 17",
            ),
            row(PEER, 30, 1e-5 * scale, 3e-4, "ok"),
            row(PEER, 300, 1e-7 * scale, 3e-3, "ok"),
        ]
    };
    let legs = QUICK_LEGS
        .iter()
        .zip([1.0, 10.0])
        .map(|(&leg, scale)| LegRows {
            e: 0.6,
            leg,
            t_end: 2.0 * PI * leg.orbits,
            rows: rows(scale),
        })
        .collect();
    PeerStudy {
        settings,
        legs,
        notes: Vec::new(),
    }
}

#[test]
fn the_report_has_every_section() {
    let s = study();
    let md = s.markdown();
    if let Ok(path) = std::env::var("PEER_MD_DUMP") {
        std::fs::write(path, &md).unwrap();
    }
    for section in [
        "# Kepler e = 0.6: our strongest schemes against DOP853 over 1 and 10 orbits",
        "## Verdict",
        "## e = 0.6, 1 orbit (T = 6.28): time to each target",
        "## e = 0.6, 10 orbits (T = 62.83): time to each target",
        "Failed runs:",
        "- logh:kahan-li8 at 200 steps: diverged at step 17",
        "DOP853 at its tightest tolerance (1e-6)",
    ] {
        assert!(md.contains(section), "{section}\n{md}");
    }
}
