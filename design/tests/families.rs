//! Family files: every file in `designs/` reads (a second-corrector family
//! with `design::processed`'s reader), and bad input is an error naming the
//! file and the field.

use design::parse_family;

#[test]
fn every_shipped_family_reads() {
    let dir = crate::common::family_path("");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let text = std::fs::read_to_string(&path).unwrap();
            if design::processed::is_corrector_family(&text) {
                design::processed::load_corrector_family(&path).unwrap();
            } else {
                let f = design::load_family(&path).unwrap();
                design::conditions::system(&f, &path.display().to_string()).unwrap();
            }
            n += 1;
        }
    }
    assert!(n >= 5, "{n} families");
}

fn err(text: &str) -> String {
    parse_family("fam.toml", text).unwrap_err().to_string()
}

const BASE: &str = "name = \"x\"\nform = \"ABA\"\nstages = 5\norder = 4\n";

#[test]
fn errors_name_the_file_and_field() {
    let m = err(&format!("{BASE}stagez = 3\n"));
    assert!(
        m.starts_with("fam.toml: field stagez: unknown field"),
        "{m}"
    );
    let m = err("name = \"x\"\nform = \"ABC\"\nstages = 5\norder = 4\n");
    assert!(m.starts_with("fam.toml: field form: `ABC`"), "{m}");
    let m = err(&format!("{BASE}fixed = {{ b1 = \"sqrt(2)\" }}\n"));
    assert!(
        m.starts_with("fam.toml: field fixed.b1: `sqrt(2)` is irrational"),
        "{m}"
    );
    let m = err(&format!("{BASE}fixed = {{ b9 = \"1/2\" }}\n"));
    assert!(
        m.contains("field fixed.b9: `b9` is not a coefficient")
            && m.contains("a1, a2, a3, b1, b2, b3"),
        "{m}"
    );
    let m = err(&format!("{BASE}fixed = {{ b1 = 0.5 }}\n"));
    assert!(
        m.contains("field fixed.b1: expected a quoted exact value"),
        "{m}"
    );
    let m = err("name = \"x\"\nform = \"ABA\"\nstages = 5\norder = 5\n");
    assert!(m.contains("field order: order 5"), "{m}");
    let m = err("name = \"x\"\nform = \"ABA\"\nstages = 5\n");
    assert!(m.contains("`order` is missing"), "{m}");
    let m = err(&format!("{BASE}equal = [[\"a1\"]]\n"));
    assert!(m.contains("field equal[0]: expected a pair"), "{m}");
    let m = err("name = \"x\"\nform = \"ABA\nstages = 5\n");
    assert!(m.starts_with("fam.toml: not a TOML file"), "{m}");
}

#[test]
fn impossible_families_are_errors() {
    // Three steps cannot reach order 6: more conditions than unknowns.
    let f = parse_family(
        "c.toml",
        "name = \"x\"\nform = \"composition\"\nstages = 3\norder = 6\n",
    )
    .unwrap();
    let m = design::conditions::system(&f, "c.toml")
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("field stages: order 6 imposes 3 conditions"),
        "{m}"
    );
    // Fixed values that break consistency.
    let f = parse_family(
        "c.toml",
        "name = \"x\"\nform = \"composition\"\nstages = 3\norder = 4\nfixed = { g1 = \"1/3\", g2 = \"1/2\" }\n",
    )
    .unwrap();
    let m = design::conditions::system(&f, "c.toml")
        .unwrap_err()
        .to_string();
    assert!(
        m.contains("field fixed: the fixed values make the g coefficients sum to 7/6"),
        "{m}"
    );
}

#[test]
fn rkn_families_are_drift_kick_of_order_at_most_six() {
    let base = "name = \"x\"\nform = \"BAB\"\nstages = 6\nrkn = true\n";
    let f = design::parse_family("f.toml", &format!("{base}order = 4\n")).unwrap();
    assert_eq!(f.error_basis, design::ErrorBasis::Brackets);
    let e = design::parse_family("f.toml", &format!("{base}order = 8\n")).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("rkn"), "{e}");
    // Order 6: the degree-5 conditions are the four coordinates outside the
    // ideal of [B,[B,[B,A]]].
    let f = design::parse_family(
        "f.toml",
        "name = \"x\"\nform = \"BAB\"\nstages = 7\nrkn = true\norder = 6\n",
    )
    .unwrap();
    let s = design::conditions::system(&f, "x").unwrap();
    let words: Vec<&str> = s.conditions.iter().map(|c| c.word.as_str()).collect();
    assert_eq!(
        words,
        ["AAB", "ABB", "P(AAAAB)", "P(AAABB)", "P(AABAB)", "P(ABABB)"]
    );
    assert_eq!(
        s.error_terms.len(),
        10,
        "degree 7: 18 Lyndon words, 8 in the ideal"
    );
    let e = design::parse_family(
        "f.toml",
        &format!("{base}order = 4\nerror_basis = \"words\"\n"),
    )
    .unwrap_err();
    assert_eq!(e.field.as_deref(), Some("error_basis"), "{e}");
    let e = design::parse_family(
        "f.toml",
        "name = \"x\"\nform = \"composition\"\nstages = 5\norder = 4\nrkn = true\n",
    )
    .unwrap_err();
    assert_eq!(e.field.as_deref(), Some("rkn"), "{e}");
    // The Lyndon basis keeps all six degree-5 terms; RKN drops two.
    let mut f = design::Family::new("x", design::Form::Bab, 6, 4);
    f.error_basis = design::ErrorBasis::Brackets;
    assert_eq!(
        design::conditions::system(&f, "x")
            .unwrap()
            .error_terms
            .len(),
        6
    );
    f.rkn = true;
    let s = design::conditions::system(&f, "x").unwrap();
    let words: Vec<&str> = s.error_terms.iter().map(|c| c.word.as_str()).collect();
    assert_eq!(words, ["P(AAAAB)", "P(AAABB)", "P(AABAB)", "P(ABABB)"]);
}

#[test]
fn the_objective_is_read_and_a_wrong_one_named() {
    let f = parse_family("fam.toml", BASE).unwrap();
    assert_eq!(f.objective, design::Objective::EffectiveError);
    let f = parse_family("fam.toml", &format!("{BASE}objective = \"stability\"\n")).unwrap();
    assert_eq!(f.objective, design::Objective::Stability);
    let m = err(&format!("{BASE}objective = \"speed\"\n"));
    assert!(
        m.starts_with("fam.toml: field objective: `speed`")
            && m.contains("\"effective-error\" and \"stability\""),
        "{m}"
    );
}
