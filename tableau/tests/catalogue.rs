//! The built-in catalogue: every file parses, ids are unique and match the
//! files on disk, every table names its source, and every claim verifies.

use std::collections::BTreeSet;
use std::path::Path;

use tableau::Table;
use tableau::analysis::{Analysis, check_claim};
use tableau::catalogue::{self, entries, find};
use tableau::claims::Claim;

#[test]
fn every_entry_parses() {
    let mut failures = Vec::new();
    for e in entries() {
        match catalogue::load(e.id) {
            Ok(t) => assert!(!t.name.trim().is_empty(), "{}: empty name", e.id),
            Err(err) => failures.push(err.to_string()),
        }
    }
    assert!(
        failures.is_empty(),
        "entries that do not parse:\n{}",
        failures.join("\n")
    );
}

#[test]
fn ids_are_unique_and_well_formed() {
    let mut seen = BTreeSet::new();
    for e in entries() {
        assert!(seen.insert(e.id), "duplicate id {}", e.id);
        assert!(
            !e.id.is_empty()
                && e.id
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'),
            "id {:?} is not a short lowercase name",
            e.id
        );
        assert_eq!(find(e.id), Some(e));
    }
}

#[test]
fn the_list_names_exactly_the_files_on_disk() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("catalogue");
    let on_disk: BTreeSet<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|f| f.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    let listed: BTreeSet<String> = entries().iter().map(|e| e.id.to_string()).collect();
    assert_eq!(
        listed, on_disk,
        "tableau/src/catalogue.rs must list every tableau/catalogue/*.toml and nothing else"
    );
    for e in entries() {
        let text = std::fs::read_to_string(dir.join(format!("{}.toml", e.id))).unwrap();
        assert_eq!(
            text, e.text,
            "{}: embedded text differs from the file",
            e.id
        );
    }
}

#[test]
fn every_entry_has_a_source_a_header_and_claims() {
    for e in entries() {
        let t = catalogue::load(e.id).unwrap_or_else(|err| panic!("{err}"));
        let source = t.source.unwrap_or_default();
        assert!(!source.trim().is_empty(), "{}: no literature source", e.id);
        assert!(
            e.text.starts_with('#'),
            "{}: the file should start with a comment describing the method",
            e.id
        );
        assert!(
            t.claims.iter().any(|c| matches!(c, Claim::Order { .. })),
            "{}: no order claim",
            e.id
        );
    }
}

#[test]
fn forms_are_as_documented() {
    let form = |id: &str| match catalogue::load(id).unwrap().table {
        Table::Rk(_) => "rk",
        Table::Prk(_) => "prk",
        Table::Splitting(_) => "drift-kick",
        Table::Composition(_) => "compose",
    };
    assert_eq!(form("gauss2"), "rk");
    assert_eq!(form("lobatto3b-2"), "rk");
    assert_eq!(form("stormer-verlet"), "prk");
    assert_eq!(form("symplectic-euler-a"), "prk");
    assert_eq!(form("leapfrog"), "drift-kick");
    assert_eq!(form("forest-ruth"), "drift-kick");
    assert_eq!(form("yoshida4"), "compose");
    assert_eq!(form("sofroniou-spaletta10"), "compose");
    match catalogue::load("lobatto3b-2").unwrap().table {
        Table::Rk(rk) => assert!(rk.c.is_some(), "Lobatto IIIB s = 2 gives its c"),
        _ => unreachable!(),
    }
}

#[test]
fn unknown_ids_list_close_matches() {
    let err = catalogue::load("gaus2").unwrap_err();
    assert_eq!(err.file, "builtin:gaus2");
    assert!(err.to_string().contains("gauss2"), "{err}");
    let err = catalogue::load("yoshida").unwrap_err();
    assert!(err.to_string().contains("yoshida4"), "{err}");
    assert!(err.to_string().contains("yoshida6"), "{err}");
}

/// The literature's claims, as written in each file, hold under the exact
/// analysis (the same check `symlab check` and `butcher!` run).
#[test]
fn every_claim_verifies() {
    let mut failures = Vec::new();
    for e in entries() {
        let file = catalogue::load(e.id).unwrap_or_else(|err| panic!("{err}"));
        let analysis = match Analysis::of(&file.table) {
            Ok(a) => a,
            Err(err) => {
                failures.push(format!("{}: {err}", e.id));
                continue;
            }
        };
        for claim in &file.claims {
            if let Err(err) = check_claim(&file.table, &analysis, claim) {
                failures.push(format!("{}: claim `{claim}`: {err}", e.id));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "claims that fail:\n{}",
        failures.join("\n")
    );
}
