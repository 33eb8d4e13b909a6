//! Tests of `compare::rebound::names` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::rebound::*;
use serde_json::json;
#[test]
fn names_settings_and_their_errors() {
    let m = ReboundMethod::parse("rebound:whfast:corrector=11").unwrap();
    assert_eq!(m.integrator, "whfast");
    assert!(m.settings.contains(&("corrector".into(), json!(11))));
    assert!(m.settings.contains(&("safe_mode".into(), json!(0))));
    let m = ReboundMethod::parse("rebound:whfast:kernel=Lazy:safe_mode=1").unwrap();
    assert!(m.settings.contains(&("kernel".into(), json!("LAZY"))));
    assert!(m.settings.contains(&("safe_mode".into(), json!(1))));
    assert!(!m.settings.contains(&("safe_mode".into(), json!(0))));
    let s = ReboundMethod::parse("rebound:saba-10-6-4").unwrap();
    assert_eq!(s.integrator, "saba");
    assert!(s.settings.contains(&("type".into(), json!("10_6_4"))));
    assert_eq!(
        ReboundMethod::parse("rebound:ias15").unwrap().sweep,
        Sweep::Ias15
    );
    let e = ReboundMethod::parse("rebound:whfastt")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("rebound:whfastt") && e.contains("--methods") && e.contains("whckl"),
        "{e}"
    );
    let e = ReboundMethod::parse("rebound:whfast:corrector=4")
        .unwrap_err()
        .to_string();
    assert!(e.contains("corrector") && e.contains("11, 17"), "{e}");
    let e = ReboundMethod::parse("rebound:whfast:order=4")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("unknown setting 'order'") && e.contains("kernel"),
        "{e}"
    );
    let e = ReboundMethod::parse("rebound:ias15:epsilon=1e-9")
        .unwrap_err()
        .to_string();
    assert!(e.contains("takes no settings"), "{e}");
    let e = ReboundMethod::parse("rebound:whfast:corrector")
        .unwrap_err()
        .to_string();
    assert!(e.contains("KEY=VALUE"), "{e}");
}
