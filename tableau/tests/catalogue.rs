//! The built-in catalogue: every file parses, ids are unique and match the
//! files on disk, every table names its source, and every claim verifies.

use std::collections::BTreeSet;
use std::path::Path;

use tableau::Table;
use tableau::analysis::{Analysis, check_claim, check_file_claim};
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
        "tableau/build.rs must list every tableau/catalogue/*.toml and nothing else"
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
            if let Err(err) = check_file_claim(&file, &analysis, claim) {
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

/// The claim of `id` as written in its file.
fn claim(id: &str, text: &str) -> Claim {
    let file = catalogue::load(id).unwrap();
    file.claims
        .into_iter()
        .find(|c| c.to_string() == text)
        .unwrap_or_else(|| panic!("{id} does not claim `{text}`"))
}

/// The order on Runge–Kutta–Nyström systems (T quadratic), exactly: the three
/// RKN methods reach their literature orders there (within the bounds their
/// decimals need) and not one more, while on general separable systems they
/// have order 3; the exact tables have the order they have on separable
/// systems.
#[test]
fn orders_on_runge_kutta_nystrom_systems() {
    use tableau::order::{prk_order_nystrom, prk_order_separable};
    let analyse = |id: &str| {
        let file = catalogue::load(id).unwrap();
        let a = Analysis::of(&file.table).unwrap();
        (file.table, a)
    };
    // Exact coefficients: the default analysis decides it.
    for (id, p) in [
        ("leapfrog", 2),
        ("stormer-verlet", 2),
        ("ruth3", 3),
        ("forest-ruth", 4),
        ("yoshida4", 4),
        ("gauss2", 4),
        ("rk4", 4),
    ] {
        let (_, a) = analyse(id);
        assert_eq!(a.order_rkn.order, p, "{id}: {}", a.order_rkn);
        let fail = a.order_rkn.first_failure.as_ref().expect("an exact order");
        assert_eq!(fail.order, p + 1, "{id}");
    }
    let (_, fr) = analyse("forest-ruth");
    assert_eq!(
        fr.order_rkn.first_failure.unwrap().tree,
        "[[τ_q³]_p]_q",
        "the first Nyström tree of order 5"
    );
    // Decimal coefficients: order p within the claimed bound, p + 1 fails by
    // far more than the bound, and the separable order is 3.
    for (id, p, bound, order_bound) in [
        ("mclachlan-atela4", 4, "1e-17", "1e-17"),
        ("mclachlan-atela5", 5, "1e-16", "1e-17"),
        ("calvo-sanz-serna4", 4, "1e-16", "1e-16"),
    ] {
        let (table, a) = analyse(id);
        let c = claim(id, &format!("order_rkn = {p} (residual < {bound})"));
        check_claim(&table, &a, &c).unwrap_or_else(|e| panic!("{id}: {e}"));
        let Claim::OrderRkn {
            bound: Some(eps), ..
        } = c
        else {
            unreachable!()
        };
        let prk = table.to_prk().unwrap();
        let rkn = prk_order_nystrom(&prk, 12, Some(&eps));
        assert_eq!(rkn.order, p, "{id}: {rkn}");
        let miss = rkn.first_failure.unwrap().residual.abs();
        assert!(miss > tableau::expr::parse_number("1e-4").unwrap(), "{id}");
        assert_eq!(prk_order_separable(&prk, 12, Some(&eps)).order, 3, "{id}");
        claim(id, &format!("order = 3 (residual < {order_bound})"));
        let too_many = Claim::OrderRkn {
            p: p + 1,
            bound: Some(eps.clone()),
        };
        let e = check_claim(&table, &a, &too_many).unwrap_err().to_string();
        assert!(
            e.starts_with(&format!(
                "order_rkn {} claimed (on Runge–Kutta–Nyström systems, T quadratic) but the order-{} condition for tree ",
                p + 1,
                p + 1
            )),
            "{id}: {e}"
        );
        // A thousand times below the bound, the rounding of the decimals shows.
        let tight = &eps * &tableau::Number::ratio(1, 1000).unwrap();
        assert!(prk_order_nystrom(&prk, 12, Some(&tight)).order < p, "{id}");
    }
    // With drifts and kicks exchanged, the order is 3 even for T quadratic.
    for id in ["mclachlan-atela4", "calvo-sanz-serna4"] {
        let Table::Splitting(s) = catalogue::load(id).unwrap().table else {
            unreachable!()
        };
        let mut kick = s.kick.clone();
        let mut drift = s.drift.clone();
        if drift.len() == kick.len() {
            assert!(drift[0].is_zero(), "{id}: a leading zero drift");
            drift.remove(0);
        }
        std::mem::swap(&mut kick, &mut drift);
        let swapped = tableau::Splitting::new(drift, kick).to_prk();
        let eps = tableau::expr::parse_number("1e-16").unwrap();
        assert_eq!(prk_order_nystrom(&swapped, 8, Some(&eps)).order, 3, "{id}");
    }
}

/// Every explicit symplectic entry has an RKN order at least its separable
/// order, each within the bound the entry claims for its order; only the
/// RKN methods gain (Blanes–Moan's SRKN₆ᵇ has order 4 on both).
#[test]
fn rkn_order_of_every_explicit_symplectic_entry() {
    use tableau::order::{prk_order_nystrom, prk_order_separable};
    let mut gains = Vec::new();
    for e in entries() {
        let file = catalogue::load(e.id).unwrap();
        // A processed method's order is its effective method's, not its
        // kernel's (tests/near_integrable.rs).
        if file.corrector.is_some() {
            continue;
        }
        let a = Analysis::of(&file.table).unwrap();
        if !(a.symplectic_separable && a.explicit_separable) || file.table.to_prk().is_none() {
            continue;
        }
        let bound = file.claims.iter().find_map(|c| match c {
            Claim::Order { bound, .. } => bound.clone(),
            _ => None,
        });
        let prk = file.table.to_prk().unwrap();
        let rkn = prk_order_nystrom(&prk, 10, bound.as_ref()).order;
        let separable = prk_order_separable(&prk, 10, bound.as_ref()).order;
        assert!(rkn >= separable, "{}: {rkn} < {separable}", e.id);
        assert!(a.order_rkn.order >= a.order_separable.order.min(a.order_rkn.limit));
        if rkn > separable {
            gains.push((e.id, separable, rkn));
        }
    }
    // `entries()` is in id order; the expected list in the order it was
    // first written, sorted the same way here.
    let mut expected = [
        ("mclachlan-atela4", 3, 4),
        ("mclachlan-atela5", 3, 5),
        ("calvo-sanz-serna4", 3, 4),
        ("blanes-moan-srkn11b", 4, 6),
        ("blanes-moan-srkn14a", 4, 6),
    ];
    expected.sort();
    assert_eq!(gains, expected);
}
