//! Table files: good fixtures load to the exact tables, and every bad input
//! is an error that names the field and says what is wrong.

use std::path::{Path, PathBuf};

use tableau::claims::Claim;
use tableau::expr::parse_number;
use tableau::file::{FileError, TableFile, load, parse_table_file};
use tableau::{Number, Table};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("fixtures")
        .join(name)
}

fn load_fixture(name: &str) -> TableFile {
    load(&fixture(name)).unwrap_or_else(|e| panic!("{e}"))
}

fn n(src: &str) -> Number {
    parse_number(src).unwrap()
}

fn ns(srcs: &[&str]) -> Vec<Number> {
    srcs.iter().map(|s| n(s)).collect()
}

fn sum(xs: &[Number]) -> Number {
    xs.iter().fold(Number::zero(), |acc, x| acc + x)
}

/// The error for `text`, which must be refused.
fn refuse(text: &str) -> FileError {
    match parse_table_file("bad.toml", text) {
        Ok(f) => panic!("accepted:\n{text}\nas {f:?}"),
        Err(e) => e,
    }
}

/// Refused, with the error on `field` and `phrase` in the message.
#[track_caller]
fn assert_refused(text: &str, field: Option<&str>, phrase: &str) -> FileError {
    let e = refuse(text);
    assert_eq!(e.field.as_deref(), field, "{e}");
    assert!(e.message.contains(phrase), "expected {phrase:?} in: {e}");
    assert_eq!(e.file, "bad.toml");
    e
}

/// A valid file around one changed line: `name` plus the given body.
fn with_name(body: &str) -> String {
    format!("name = \"test\"\n{body}\n")
}

// ---------------------------------------------------------------------------
// Good files

#[test]
fn gauss_legendre_2() {
    let f = load_fixture("gauss_legendre_2.toml");
    assert_eq!(f.name, "Gauss–Legendre, 2 stages");
    assert!(f.source.as_deref().unwrap().contains("Butcher"));
    assert_eq!(
        f.claims,
        vec![
            Claim::Symplectic,
            Claim::Symmetric,
            Claim::Order { p: 4, bound: None }
        ]
    );
    let Table::Rk(rk) = &f.table else {
        panic!("{:?}", f.table)
    };
    assert_eq!(
        rk.a,
        vec![
            ns(&["1/4", "1/4 - sqrt(3)/6"]),
            ns(&["1/4 + sqrt(3)/6", "1/4"])
        ]
    );
    assert_eq!(rk.b, ns(&["1/2", "1/2"]));
    let c = rk.c.clone().unwrap();
    assert_eq!(c, rk.row_sums());
    assert_eq!(c[0], n("1/2 - sqrt(12)/12"));
}

#[test]
fn lobatto_iiia_iiib_pair() {
    let f = load_fixture("lobatto_iiia_iiib_3.toml");
    let Table::Prk(prk) = &f.table else {
        panic!("{:?}", f.table)
    };
    assert_eq!(prk.q.a[1], ns(&["5/24", "1/3", "-1/24"]));
    assert_eq!(prk.p.a[2], ns(&["1/6", "5/6", "0"]));
    assert_eq!(prk.q.b, prk.p.b);
    assert_eq!(prk.q.c.as_ref().unwrap(), &prk.q.row_sums());
    assert_eq!(prk.p.c.as_ref().unwrap(), &prk.p.row_sums());
    assert_eq!(f.table.stages(), 3);
}

#[test]
fn forest_ruth_with_let() {
    let f = load_fixture("forest_ruth.toml");
    let Table::Splitting(s) = &f.table else {
        panic!("{:?}", f.table)
    };
    let x = n("1/(2 - cbrt(2))");
    assert_eq!(s.kick[0], x);
    assert_eq!(s.drift[0], n("1/(4 - 2*cbrt(2))"));
    assert_eq!(s.drift.len(), 4);
    assert_eq!(s.kick.len(), 3);
    assert_eq!(sum(&s.drift), Number::one());
    assert_eq!(sum(&s.kick), Number::one());
    // x is irrational: 1/(2 - 2^(1/3)) = (4 + 2·2^(1/3) + 2^(2/3))/6.
    assert_eq!(x, n("(4 + 2*cbrt(2) + cbrt(4))/6"));
}

#[test]
fn composition() {
    let f = load_fixture("yoshida_triple_jump.toml");
    let Table::Composition(c) = &f.table else {
        panic!("{:?}", f.table)
    };
    assert_eq!(sum(&c.gamma), Number::one());
    assert!(f.source.is_none());
}

#[test]
fn integers_and_decimals_are_exact() {
    let text = with_name(
        "a = [[0, 0], [\"0.5\", 0]]\nb = [\"0.25\", \"7.5e-1\"]\nc = [0, 0x1]\nclaims = [\"explicit\", \"order = 2 (residual < 1e-24)\"]",
    );
    let f = parse_table_file("t.toml", &text).unwrap();
    let Table::Rk(rk) = &f.table else { panic!() };
    assert_eq!(rk.a[1][0], Number::ratio(1, 2).unwrap());
    assert_eq!(
        rk.b,
        vec![Number::ratio(1, 4).unwrap(), Number::ratio(3, 4).unwrap()]
    );
    assert_eq!(rk.c.as_ref().unwrap()[1], Number::one());
    assert_eq!(f.claims[1].to_string(), "order = 2 (residual < 1e-24)");
}

#[test]
fn big_integers_are_exact() {
    let f = parse_table_file(
        "t.toml",
        &with_name(
            "let = { big = 123456789012345678901234567890 }\na = [[\"big - big\"]]\nb = [1]",
        ),
    )
    .unwrap();
    let Table::Rk(rk) = &f.table else { panic!() };
    assert!(rk.a[0][0].is_zero());
}

// ---------------------------------------------------------------------------
// Bad files

#[test]
fn empty_file() {
    assert_refused("", None, "empty file");
    assert_refused("  \n\n", None, "empty file");
    assert_refused("# only a comment\n", None, "empty file");
}

#[test]
fn missing_name() {
    assert_refused("a = [[0]]\nb = [1]\n", Some("name"), "missing");
    assert_refused(
        "name = 3\na = [[0]]\nb = [1]\n",
        Some("name"),
        "expected a string",
    );
}

#[test]
fn toml_syntax_error() {
    let e = assert_refused(
        "name = \"x\"\na = [[0]\nb = [1]\n",
        None,
        "TOML parse error",
    );
    assert!(e.message.contains("line"), "{e}");
}

#[test]
fn non_square_a() {
    assert_refused(
        &with_name("a = [[\"1/2\", 0], [\"1/2\"]]\nb = [\"1/2\", \"1/2\"]"),
        Some("a[1]"),
        "square",
    );
}

#[test]
fn b_too_short() {
    assert_refused(
        &with_name("a = [[0, 0], [1, 0]]\nb = [1]"),
        Some("b"),
        "b has 1 entries",
    );
}

#[test]
fn hat_shapes() {
    assert_refused(
        &with_name("a = [[0]]\nb = [1]\na_hat = [[0]]\nb_hat = [1, 2]"),
        Some("b_hat"),
        "b has 2 entries",
    );
    assert_refused(
        &with_name("a = [[0]]\nb = [1]\nc = [0, 1]"),
        Some("c"),
        "c has 2 entries",
    );
}

#[test]
fn negative_sqrt() {
    let e = assert_refused(
        &with_name("a = [[\"1 + sqrt(-1)\"]]\nb = [1]"),
        Some("a[0][0]"),
        "square root of a negative number",
    );
    assert!(e.message.contains("at column 5"), "{e}");
    assert!(e.message.contains("`sqrt(-1)`"), "{e}");
}

#[test]
fn division_by_zero() {
    let e = assert_refused(
        &with_name("a = [[0, 0], [1, 0]]\nb = [\"1/2\", \"1/(1 - 1)\"]"),
        Some("b[1]"),
        "division by zero",
    );
    assert!(e.message.contains("at column 3"), "{e}");
    assert_eq!(
        e.to_string(),
        "bad.toml: field b[1]: at column 3, division by zero: `(1 - 1)` is zero"
    );
}

#[test]
fn unknown_function() {
    assert_refused(
        &with_name("a = [[\"exp(1)\"]]\nb = [1]"),
        Some("a[0][0]"),
        "unknown function `exp` (the grammar has sqrt, cbrt, powi)",
    );
}

#[test]
fn unbalanced_parentheses() {
    let e = assert_refused(
        &with_name("a = [[0, 0], [\"(1 + 2\", 0]]\nb = [\"1/2\", \"1/2\"]"),
        Some("a[1][0]"),
        "unbalanced parentheses",
    );
    assert!(e.to_string().contains("a[1][0]: at column 1,"), "{e}");
    assert_refused(
        &with_name("a = [[\"1/2)\"]]\nb = [1]"),
        Some("a[0][0]"),
        "unbalanced parentheses",
    );
}

#[test]
fn syntax_error_in_entry() {
    let e = assert_refused(
        &with_name("a = [[\"1/4 + * 2\"]]\nb = [1]"),
        Some("a[0][0]"),
        "unexpected `*`",
    );
    assert_eq!(
        e.to_string(),
        "bad.toml: field a[0][0]: at column 7, unexpected `*`: expected a number, a name or `(`"
    );
    assert_refused(
        &with_name("a = [[\"\"]]\nb = [1]"),
        Some("a[0][0]"),
        "empty expression",
    );
    assert_refused(
        &with_name("a = [[\"1/2 ≈ 0.5\"]]\nb = [1]"),
        Some("a[0][0]"),
        "unexpected `≈`",
    );
}

#[test]
fn non_numbers_in_a_matrix() {
    assert_refused(
        &with_name("a = [[true]]\nb = [1]"),
        Some("a[0][0]"),
        "found a boolean, `true`",
    );
    assert_refused(
        &with_name("a = [[\"abc\"]]\nb = [1]"),
        Some("a[0][0]"),
        "unknown name `abc`",
    );
    assert_refused(
        &with_name("a = [[0, [1]], [0, 0]]\nb = [1, 0]"),
        Some("a[0][1]"),
        "found an array",
    );
    assert_refused(
        &with_name("a = [\"1/2\"]\nb = [1]"),
        Some("a[0]"),
        "expected a row",
    );
    assert_refused(
        &with_name("a = \"1/2\"\nb = [1]"),
        Some("a"),
        "expected an array of rows",
    );
    assert_refused(
        &with_name("a = [[0]]\nb = [{ x = 1 }]"),
        Some("b[0]"),
        "found a table",
    );
    assert_refused(
        &with_name("a = [[0]]\nb = 1"),
        Some("b"),
        "expected an array of numbers",
    );
    assert_refused(
        &with_name("a = [[0]]\nb = [1979-05-27]"),
        Some("b[0]"),
        "found a date-time",
    );
}

#[test]
fn toml_float() {
    assert_refused(
        &with_name("a = [[0]]\nb = [0.5]"),
        Some("b[0]"),
        "0.5 is a TOML float; write it as a string, \"0.5\", so that it is read exactly",
    );
    let e = load(&fixture("bad_float.toml")).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("b[0]"));
    assert!(e.to_string().ends_with(
        "bad_float.toml: field b[0]: 1.0 is a TOML float; write it as a string, \"1.0\", so that it is read exactly"
    ));
    // The text as written, not as the float prints.
    assert_refused(
        &with_name("a = [[0]]\nb = [1e-24]"),
        Some("b[0]"),
        "\"1e-24\"",
    );
    assert_refused(
        &with_name("let = { x = 0.25 }\na = [[0]]\nb = [1]"),
        Some("let.x"),
        "TOML float",
    );
    assert_refused(&with_name("a = [[0]]\nb = [inf]"), Some("b[0]"), "inf");
}

#[test]
fn unknown_key() {
    assert_refused(
        &with_name("a = [[0]]\nb = [1]\nahat = [[0]]"),
        Some("ahat"),
        "unknown field `ahat` (did you mean `a_hat`?",
    );
    assert_refused(
        &with_name("a = [[0]]\nb = [1]\norder = 1"),
        Some("order"),
        "unknown field `order`",
    );
}

#[test]
fn cyclic_let() {
    let e = load(&fixture("bad_cyclic_let.toml")).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("let.x"), "{e}");
    assert!(
        e.message.contains("cyclic definition: x → y → z → x"),
        "{e}"
    );
    assert_refused(
        &with_name("let = { x = \"x + 1\" }\na = [[\"x\"]]\nb = [1]"),
        Some("let.x"),
        "cyclic definition: x → x",
    );
}

#[test]
fn bad_let() {
    assert_refused(
        &with_name("let = { x = \"1/0\" }\na = [[0]]\nb = [1]"),
        Some("let.x"),
        "division by zero",
    );
    assert_refused(
        &with_name("let = { x = \"y\" }\na = [[0]]\nb = [1]"),
        Some("let.x"),
        "unknown name `y`",
    );
    assert_refused(
        &with_name("let = { \"1x\" = \"1\" }\na = [[0]]\nb = [1]"),
        Some("let.1x"),
        "not a name",
    );
    assert_refused(
        &with_name("let = { sqrt = \"1\" }\na = [[0]]\nb = [1]"),
        Some("let.sqrt"),
        "function",
    );
    assert_refused(
        &with_name("let = 1\na = [[0]]\nb = [1]"),
        Some("let"),
        "expected a table",
    );
    // An unbound name lists the bound ones.
    assert_refused(
        &with_name("let = { x = \"1\" }\na = [[\"y\"]]\nb = [1]"),
        Some("a[0][0]"),
        "(`let` binds x)",
    );
}

#[test]
fn mixed_forms() {
    let e = assert_refused(
        &with_name("a = [[0]]\nb = [1]\ndrift = [1]\nkick = []"),
        Some("drift"),
        "mixes",
    );
    assert!(e.message.contains("`a`, `b`"), "{e}");
    assert!(e.message.contains("`drift`, `kick`"), "{e}");
    assert_refused(
        &with_name("compose = [1]\nkick = [1]"),
        Some("compose"),
        "mixes",
    );
}

#[test]
fn half_pairs() {
    assert_refused(
        &with_name("a = [[0]]\nb = [1]\na_hat = [[0]]"),
        Some("b_hat"),
        "`a_hat` is given, so `b_hat` is needed too",
    );
    assert_refused(
        &with_name("a = [[0]]\nb = [1]\nb_hat = [1]"),
        Some("a_hat"),
        "`b_hat` is given, so `a_hat` is needed too",
    );
    assert_refused(
        &with_name("a = [[0]]\nb = [1]\nc_hat = [0]"),
        Some("a_hat"),
        "`c_hat` is given",
    );
    assert_refused(&with_name("a = [[0]]"), Some("b"), "`a` is given");
    assert_refused(&with_name("b = [1]"), Some("a"), "`b` is given");
    assert_refused(&with_name("drift = [1]"), Some("kick"), "`drift` is given");
    assert_refused(&with_name("source = \"x\""), None, "no table");
}

#[test]
fn bad_sequences() {
    assert_refused(&with_name("drift = []\nkick = []"), Some("drift"), "empty");
    assert_refused(
        &with_name("drift = [1]\nkick = [1, 2, 3]"),
        Some("kick"),
        "at most one",
    );
    assert_refused(&with_name("compose = []"), Some("compose"), "empty");
    assert_refused(&with_name("a = []\nb = []"), Some("a"), "no stages");
}

#[test]
fn bad_claims() {
    assert_refused(
        &with_name("claims = [\"symplectic\", \"ordre = 4\"]\na = [[0]]\nb = [1]"),
        Some("claims[1]"),
        "unknown claim `ordre = 4`",
    );
    assert_refused(
        &with_name("claims = \"symplectic\"\na = [[0]]\nb = [1]"),
        Some("claims"),
        "expected an array of claims",
    );
    assert_refused(
        &with_name("claims = [4]\na = [[0]]\nb = [1]"),
        Some("claims[0]"),
        "expected a string",
    );
}

#[test]
fn unreadable_file() {
    let path = fixture("no_such_file.toml");
    let e = load(&path).unwrap_err();
    assert_eq!(e.file, path.display().to_string());
    assert_eq!(e.field, None);
    assert!(e.message.contains("cannot read the file"), "{e}");
    // A directory, and a file that is not UTF-8: errors, not panics.
    let e = load(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests")
            .as_path(),
    )
    .unwrap_err();
    assert!(e.message.contains("cannot read"), "{e}");
    let latin1 = std::env::temp_dir().join(format!("tableau-latin1-{}.toml", std::process::id()));
    std::fs::write(&latin1, b"name = \"Gau\xdf\"\na = [[0]]\nb = [1]\n").unwrap();
    let e = load(&latin1).unwrap_err();
    let _ = std::fs::remove_file(&latin1);
    assert!(e.message.contains("UTF-8"), "{e}");
}

#[test]
fn display_without_field() {
    let e = refuse("");
    assert!(e.to_string().starts_with("bad.toml: empty file"), "{e}");
}

// ---------------------------------------------------------------------------
// No panics on damaged files

mod damaged {
    use super::*;
    use proptest::prelude::*;

    const GOOD: &str = include_str!("fixtures/forest_ruth.toml");

    proptest! {
        #[test]
        fn arbitrary_text_never_panics(text in "\\PC{0,200}") {
            let _ = parse_table_file("fuzz.toml", &text);
        }

        #[test]
        fn damaged_fixture_never_panics(
            at in 0usize..GOOD.len(),
            cut in 0usize..8,
            insert in "[\\[\\]{}\"'=,.0-9a-z_ \n#()*/+-]{0,4}",
        ) {
            let mut text: String = GOOD.to_string();
            let start = (0..=at).rev().find(|&i| text.is_char_boundary(i)).unwrap_or(0);
            let end = (start + cut..=text.len()).find(|&i| text.is_char_boundary(i)).unwrap_or(text.len());
            text.replace_range(start..end, &insert);
            match parse_table_file("fuzz.toml", &text) {
                Ok(_) => {}
                Err(e) => prop_assert!(!e.message.is_empty()),
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Gradient kicks

/// `kick_gradient` beside `kick`: exact entries (names from `let`), one per
/// kick; the table keeps them.
#[test]
fn kick_gradient_is_read_exactly() {
    let f = parse_table_file(
        "g.toml",
        &with_name(
            "let.g = \"1/24\"\ndrift = [\"1/2\", \"1/2\"]\nkick = [\"1\"]\nkick_gradient = [\"g\"]",
        ),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let Table::Splitting(s) = &f.table else {
        panic!("a drift–kick sequence")
    };
    assert_eq!(s.gradient, ns(&["1/24"]));
    assert!(s.has_gradient());
    // Plain files have none.
    let Table::Splitting(p) = load_fixture("forest_ruth.toml").table else {
        panic!("a drift–kick sequence")
    };
    assert!(p.gradient.is_empty() && !p.has_gradient());
    // An all-zero list is plain kicks.
    let f = parse_table_file(
        "g.toml",
        &with_name("drift = [\"1/2\", \"1/2\"]\nkick = [\"1\"]\nkick_gradient = [0]"),
    )
    .unwrap();
    let Table::Splitting(s) = &f.table else {
        panic!("a drift–kick sequence")
    };
    assert!(!s.has_gradient());
}

/// Every misuse of `kick_gradient` is an error naming it.
#[test]
fn kick_gradient_errors_name_the_field() {
    let dk = "drift = [\"1/2\", \"1/2\"]\nkick = [\"1\"]\n";
    for (body, field, phrase) in [
        (
            format!("{dk}kick_gradient = [\"1/24\", \"0\"]"),
            "kick_gradient",
            "kick_gradient has 2 entries, but there are 1 kicks",
        ),
        (
            format!("{dk}kick_gradient = []"),
            "kick_gradient",
            "kick_gradient has 0 entries",
        ),
        (
            "compose = [\"1\"]\nkick_gradient = [\"1/24\"]".to_string(),
            "kick_gradient",
            "this file gives `compose`, not a `kick`",
        ),
        (
            "a = [[\"0\"]]\nb = [\"1\"]\nkick_gradient = [\"1/24\"]".to_string(),
            "kick_gradient",
            "this file gives `a`, not a `kick`",
        ),
        (
            "a = [[\"0\"]]\nb = [\"1\"]\na_hat = [[\"0\"]]\nb_hat = [\"1\"]\nkick_gradient = [\"1/24\"]"
                .to_string(),
            "kick_gradient",
            "gradients of the kicks of a drift–kick sequence",
        ),
        (
            "kernel = \"leapfrog\"\nkick_gradient = [\"1/24\"]\ncorrector_drift = [\"1\", \"-1\"]\ncorrector_kick = [\"0\"]"
                .to_string(),
            "kick_gradient",
            "names the kernel",
        ),
        (
            format!("{dk}kick_gradient = [0.5]"),
            "kick_gradient[0]",
            "TOML float",
        ),
        (
            format!("{dk}kick_gradient = [\"g\"]"),
            "kick_gradient[0]",
            "unknown name",
        ),
    ] {
        assert_refused(&with_name(&body), Some(field), phrase);
    }
    // A corrector has plain kicks: there is no corrector_gradient.
    let e = refuse(&with_name(&format!(
        "{dk}corrector_drift = [\"1\", \"-1\"]\ncorrector_kick = [\"0\"]\ncorrector_gradient = [\"1\"]"
    )));
    assert_eq!(e.field.as_deref(), Some("corrector_gradient"), "{e}");
}
