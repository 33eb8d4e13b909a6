//! End-to-end tests of `symlab check` and `symlab list`: verdicts from table
//! files, the JSON fields of design.md, and clear errors with exit code 2.

use serde_json::Value;

use crate::common;
use common::symlab;

fn check_json(args: &[&str]) -> Value {
    let mut all = vec!["check", "--json"];
    all.extend_from_slice(args);
    let (code, out, err) = symlab(&all);
    assert_eq!(code, 0, "stderr: {err}");
    serde_json::from_str(&out).expect("one JSON object")
}

#[test]
fn json_has_exactly_the_documented_fields() {
    let v = check_json(&["tests/tables/gauss2.toml"]);
    let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
    keys.sort();
    assert_eq!(
        keys,
        [
            "claims",
            "class",
            "kind",
            "name",
            "order",
            "order_limit",
            "order_rkn",
            "order_separable",
            "origin",
            "report",
            "row_sums_ok",
            "stability_function",
            "stability_not_computed",
            "stages",
            "symmetric",
            "symplectic",
            "symplectic_separable",
            "w_nonzero"
        ]
    );
}

#[test]
fn gauss_legendre_2() {
    let v = check_json(&["tests/tables/gauss2.toml"]);
    assert_eq!(v["kind"], "rk");
    assert_eq!(v["stages"], 2);
    assert_eq!(v["class"], "implicit");
    assert_eq!(v["symplectic"], true);
    assert_eq!(v["order"], 4);
    assert_eq!(v["order_rkn"], 4);
    assert_eq!(v["symmetric"], true);
    assert_eq!(v["row_sums_ok"], true);
    assert_eq!(
        v["stability_function"],
        "(1 + z/2 + z^2/12)/(1 - z/2 + z^2/12)"
    );
    assert_eq!(v["w_nonzero"], Value::Array(vec![]));
}

#[test]
fn perturbed_entry_points_at_w() {
    let v = check_json(&["tests/tables/gauss2-perturbed.toml"]);
    assert_eq!(v["symplectic"], false);
    // a[0][1] += 1/1000 changes W[0][1] = b₀a₀₁ + b₁a₁₀ − b₀b₁ and W[1][0] by b₀/1000.
    let w: Vec<(u64, u64, String)> = v["w_nonzero"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            (
                e["i"].as_u64().unwrap(),
                e["j"].as_u64().unwrap(),
                e["value"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    assert_eq!(
        w,
        [(0, 1, "1/2000".to_string()), (1, 0, "1/2000".to_string())]
    );
}

#[test]
fn rk4_lobatto3b_verlet_forest_ruth() {
    let v = check_json(&["tests/tables/rk4.toml"]);
    assert_eq!(
        (
            v["symplectic"].as_bool(),
            v["order"].as_u64(),
            v["class"].as_str()
        ),
        (Some(false), Some(4), Some("explicit"))
    );
    assert_eq!(v["stability_function"], "1 + z + z^2/2 + z^3/6 + z^4/24");

    let v = check_json(&["tests/tables/lobatto3b.toml"]);
    assert_eq!(v["row_sums_ok"], false);
    assert_eq!(v["order"], 2);

    let v = check_json(&["tests/tables/verlet-pair.toml"]);
    assert_eq!(v["kind"], "prk");
    assert_eq!(
        (
            v["symplectic"].as_bool(),
            v["symplectic_separable"].as_bool()
        ),
        (Some(true), Some(true))
    );
    assert_eq!(
        (v["order"].as_u64(), v["order_separable"].as_u64()),
        (Some(2), Some(2))
    );
    assert_eq!(v["symmetric"], true);
    assert_eq!(v["stability_function"], Value::Null);

    let v = check_json(&["tests/tables/forest-ruth.toml"]);
    assert_eq!(v["kind"], "prk");
    assert_eq!(v["symplectic_separable"], true);
    assert_eq!(v["order_separable"], 4);
    assert_eq!(v["order_rkn"], 4);
    assert_eq!(v["symmetric"], true);
}

#[test]
fn order_on_runge_kutta_nystrom_systems() {
    // McLachlan–Atela 4: order 3 on separable systems, 4 when T is quadratic,
    // both within the bounds its decimals need.
    let (code, out, err) = symlab(&["check", "--builtin", "mclachlan-atela4"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains(
            "\n  T quadratic  1   (first failing: order-2 condition for tree [τ_p]_q, residual -"
        ),
        "{out}"
    );
    assert!(out.contains("✓ order = 3 (residual < 1e-17)"), "{out}");
    assert!(out.contains("✓ order_rkn = 4 (residual < 1e-17)"), "{out}");
    let v = check_json(&["--builtin", "leapfrog"]);
    assert_eq!(
        (v["order_separable"].as_u64(), v["order_rkn"].as_u64()),
        (Some(2), Some(2))
    );
    let v = check_json(&["--builtin", "mclachlan-atela5"]);
    // Without a bound the decimals fail τ_q = Σb = 1 by 1e-19.
    assert_eq!(v["order_rkn"], 0);
}

#[test]
fn readable_report_and_builtin() {
    let (code, out, err) = symlab(&["check", "--builtin", "gauss2"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("symplectic   yes"), "{out}");
    assert!(out.contains("✓ order = 4"), "{out}");
    let (code, out, _) = symlab(&["list"]);
    assert_eq!(code, 0);
    for id in [
        "rk4",
        "gauss2",
        "gauss3",
        "gauss8",
        "radau2a-5",
        "forest-ruth",
        "stormer-verlet",
    ] {
        assert!(
            out.lines().any(|l| l.starts_with(id)),
            "{id} missing from:\n{out}"
        );
    }
}

#[test]
fn bad_input_is_a_clear_error_with_exit_2() {
    let cases: &[(&str, &[&str])] = &[
        ("empty.toml", &["empty.toml"]),
        ("nonsquare.toml", &["a[1]", "square"]),
        ("short-b.toml", &["b", "1 entries"]),
        ("negative-sqrt.toml", &["a[0][0]", "negative"]),
        ("divide-by-zero.toml", &["a[0][0]", "division by zero"]),
        ("unknown-function.toml", &["a[0][0]", "exp"]),
        ("unbalanced.toml", &["a[0][0]"]),
        ("not-a-number.toml", &["a[0][0]"]),
        ("float.toml", &["a[0][0]", "\"0.5\""]),
        ("does-not-exist.toml", &["does-not-exist.toml"]),
    ];
    for (file, needles) in cases {
        let path = format!("tests/tables/{file}");
        let (code, out, err) = symlab(&["check", &path]);
        assert_eq!(code, 2, "{file}: stdout {out} stderr {err}");
        assert!(!err.contains("panicked"), "{file}: {err}");
        assert!(
            err.contains(file),
            "{file}: message does not name the file: {err}"
        );
        for n in *needles {
            assert!(err.contains(n), "{file}: message lacks {n:?}: {err}");
        }
    }
    let (code, _, err) = symlab(&["check", "--builtin", "no-such-table"]);
    assert_eq!(code, 2);
    assert!(err.contains("no-such-table"), "{err}");
}

// ---------------------------------------------------------------------------
// Hostile, huge and long input (issue 13): budgets instead of hangs.

use std::time::{Duration, Instant};

/// Generous: every case below finishes in well under a second.
const BOUND: Duration = Duration::from_secs(10);

/// `symlab ARGS`, asserting it finished within [`BOUND`].
fn timed(args: &[&str]) -> (i32, String, String) {
    let start = Instant::now();
    let r = symlab(args);
    assert!(
        start.elapsed() < BOUND,
        "{args:?} took {:?}",
        start.elapsed()
    );
    r
}

/// A table file written for one test, in the system's temporary directory.
fn temp_table(name: &str, text: &str) -> String {
    let dir = std::env::temp_dir().join(format!("symlab-check-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

fn rk_text(name: &str, a: &[Vec<String>], b: &[String]) -> String {
    let quote = |v: &[String]| {
        v.iter()
            .map(|x| format!("\"{x}\""))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let rows: Vec<String> = a.iter().map(|r| format!("[{}]", quote(r))).collect();
    format!(
        "name = \"{name}\"\na = [{}]\nb = [{}]\n",
        rows.join(", "),
        quote(b)
    )
}

/// Entries spanning large number fields are decided within the budget: six
/// square roots of primes (degree 64), the inverse of a sum of five cube
/// roots (degree 243), a 60-stage dense rational table.
#[test]
fn large_number_fields_and_many_stages_are_decided_quickly() {
    for file in ["hostile-sqrt-primes.toml", "hostile-cbrt-inverse.toml"] {
        let (code, out, err) = timed(&["check", "--json", &format!("tests/tables/{file}")]);
        assert_eq!(code, 0, "{file}: {err}");
        let v: Value = serde_json::from_str(&out).unwrap();
        assert!(v["stability_function"].is_string(), "{file}: {v}");
        assert!(v["stability_not_computed"].is_null(), "{file}: {v}");
    }
    let s = 60;
    let a: Vec<Vec<String>> = (0..s)
        .map(|i| {
            (0..s)
                .map(|j| format!("{}/{}", (i * 7 + j * 3) % 11, 1 + (i + j) % 9))
                .collect()
        })
        .collect();
    let b: Vec<String> = (0..s).map(|_| format!("1/{s}")).collect();
    let path = temp_table("dense60.toml", &rk_text("Dense, 60 stages", &a, &b));
    let (code, out, err) = timed(&["check", "--json", &path]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["stages"], 60);
    assert!(v["stability_function"].is_string(), "{v}");
}

/// Beyond the budget the stability function is reported as not computed,
/// saying what is too large; the other verdicts are still decided and the
/// exit code is 0.
#[test]
fn stability_beyond_budget_is_reported_not_run() {
    let (code, out, err) = timed(&["check", "tests/tables/hostile-radical-implicit.toml"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("R(z)         not computed: beyond budget ("),
        "{out}"
    );
    assert!(
        out.contains("degree 64") && out.contains("16 stages"),
        "{out}"
    );
    assert!(out.contains("symplectic   no"), "{out}");
    let (_, out, _) = timed(&[
        "check",
        "--json",
        "tests/tables/hostile-radical-implicit.toml",
    ]);
    let v: Value = serde_json::from_str(&out).unwrap();
    assert!(v["stability_function"].is_null());
    assert!(
        v["stability_not_computed"]
            .as_str()
            .is_some_and(|m| m.contains("RADICAL_STABILITY_WORK")),
        "{v}"
    );
}

/// Input beyond a hard limit is refused with exit 2, quickly, naming the
/// file, the field and the limit.
#[test]
fn huge_input_is_refused_naming_the_field_and_the_limit() {
    let sqrts: Vec<String> = [2, 3, 5, 7, 11, 13, 17, 19, 23]
        .iter()
        .map(|p| format!("sqrt({p})"))
        .collect();
    let inverse = format!("1/({})", sqrts.join(" + "));
    let digits = "7".repeat(1_000_000);
    let compose: Vec<String> = (0..10_000).map(|_| "\"1/10000\"".to_string()).collect();
    let cases: Vec<(String, String, &str, &str)> = vec![
        (
            "inverse.toml".into(),
            rk_text("x", &[vec![inverse]], &["1".into()]),
            "field a[0][0]",
            "degree 512",
        ),
        (
            "digits.toml".into(),
            format!("name = \"x\"\na = [[\"{digits}\"]]\nb = [\"1\"]\n"),
            "field a[0][0]",
            "at most 1000",
        ),
        (
            "digits-int.toml".into(),
            format!("name = \"x\"\na = [[{digits}]]\nb = [1]\n"),
            "field a[0][0]",
            "at most 1000",
        ),
        (
            "compose.toml".into(),
            format!("name = \"x\"\ncompose = [{}]\n", compose.join(", ")),
            "field compose",
            "at most 100 stages",
        ),
    ];
    for (name, text, field, limit) in cases {
        let path = temp_table(&name, &text);
        let (code, out, err) = timed(&["check", &path]);
        assert_eq!(code, 2, "{name}: {out}");
        assert!(
            err.contains(&path) && err.contains(field) && err.contains(limit),
            "{name}: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    // A file that never ends is read only up to the limit (Unix has one).
    #[cfg(unix)]
    {
        let (code, _, err) = timed(&["check", "/dev/zero"]);
        assert_eq!(code, 2);
        assert!(
            err.contains("/dev/zero") && err.contains("larger than 1 MiB"),
            "{err}"
        );
    }
}

/// A 3×3 `a_hat` beside a 2×2 `a` is `a_hat`'s fault, not `b_hat`'s.
#[test]
fn mismatched_pair_blames_a_hat() {
    let (code, _, err) = timed(&["check", "tests/tables/ahat-3x3.toml"]);
    assert_eq!(code, 2);
    assert!(err.contains("field a_hat:"), "{err}");
    assert!(!err.contains("b_hat"), "{err}");
}

/// `symlab list` says what each library scheme steps, as the library's own
/// facts say: never "not yet" (every scheme steps), Runge–Kutta tables any
/// ODE (implicit ones through the stage solver), drift–kick sequences and
/// compositions any split system (two parts with exact flows), pairs
/// separable Hamiltonians unless they are implicit pairs symplectic for every
/// Hamiltonian.
#[test]
fn list_agrees_with_the_library_about_what_steps() {
    let (code, out, err) = symlab(&["list", "--json"]);
    assert_eq!(code, 0, "{err}");
    let rows: Vec<Value> = serde_json::from_str(&out).unwrap();
    assert!(!rows.is_empty());
    for row in &rows {
        let id = row["id"].as_str().unwrap();
        let steps = row["steps"].as_str().unwrap();
        if row["processed"] == true {
            // A kernel with a corrector: a catalogue file, stepped χ Kⁿ χ⁻¹
            // by `wh:ID`, not one scheme of the library.
            assert!(integrator_core::library::info(id).is_none(), "{id}");
            let tf = tableau::catalogue::load(id).unwrap();
            assert!(tf.corrector.is_some(), "{id}");
            assert_eq!(steps, "-", "{id}");
            continue;
        }
        assert_eq!(row["processed"], false, "{id}");
        let info = integrator_core::library::info(id)
            .unwrap_or_else(|| panic!("{id} is listed but not in the library"));
        let expected = match (info.form, info.explicit, info.separable_only) {
            ("rk", _, _) => "any ODE",
            ("drift-kick" | "composition", _, _) => "split H",
            (_, true, _) | (_, _, true) => "separable H",
            _ => "any H",
        };
        assert_eq!(steps, expected, "{id}: {info:?}");
        assert_eq!(row["form"], info.form, "{id}");
    }
    let (_, text, _) = symlab(&["list"]);
    assert!(!text.contains("not yet"), "{text}");
}

// ---------------------------------------------------------------------------
// Generated tables and real algebraic entries (issue 15).

#[test]
fn builtin_gauss8_prints_exact_verdicts_and_the_order_proof() {
    let (code, out, err) = timed(&["check", "--builtin", "gauss8"]);
    assert_eq!(code, 0, "{err}");
    for needle in [
        "Gauss–Legendre, 8 stages (generated)",
        "symplectic   yes: W = BA + AᵀB − bbᵀ = 0 exactly",
        "order        16 exactly",
        "B(16), C(8), D(8) hold exactly; Butcher's theorem gives order ≥ min(16, 8+8+1, 2·8+2) = 16",
        "B(17) fails",
        "symmetric    yes",
        "A-stable     yes",
        "✓ symplectic",
        "✓ order = 16",
    ] {
        assert!(out.contains(needle), "missing {needle:?} in:\n{out}");
    }
    let v = check_json(&["--builtin", "gauss8"]);
    assert_eq!(v["order"], 16);
    assert_eq!(v["order_upper"], 16);
    assert_eq!(v["symplectic"], true);
    assert_eq!(v["generator"], "gauss(8)");
    assert!(v["max_w_rounded"].as_f64().unwrap() < 4e-18);
}

#[test]
fn builtin_generated_families_get_the_literature_verdicts() {
    for (id, symplectic, order) in [
        ("radau2a4", false, 7),
        ("radau2a5", false, 9),
        ("gauss(3)", true, 6),
        ("lobatto3a4", false, 6),
        ("lobatto3c5", false, 8),
    ] {
        let v = check_json(&["--builtin", id]);
        assert_eq!(v["symplectic"], symplectic, "{id}");
        assert_eq!(v["order"], order, "{id}");
        assert!(
            v["claims"]
                .as_array()
                .unwrap()
                .iter()
                .all(|c| c["holds"] == true),
            "{id}: {v}"
        );
    }
    let v = check_json(&["--builtin", "lobatto3a3b4"]);
    assert_eq!(v["kind"], "prk");
    assert_eq!(v["symplectic"], true);
    assert_eq!(v["tree_order"], 6);
}

#[test]
fn generate_in_a_table_file_and_bad_generators() {
    let path = temp_table(
        "gen.toml",
        "name = \"my Radau\"\ngenerate = \"radau2a(5)\"\nclaims = [\"symplectic\", \"order = 9\"]\n",
    );
    let (code, out, err) = timed(&["check", &path]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("my Radau"), "{out}");
    assert!(out.contains("✗ symplectic: not symplectic"), "{out}");
    assert!(out.contains("✓ order = 9"), "{out}");
    let bad = temp_table("badgen.toml", "generate = \"gauss(99)\"\n");
    let (code, _, err) = timed(&["check", &bad]);
    assert_eq!(code, 2);
    assert!(
        err.contains("generate") && err.contains("badgen.toml"),
        "{err}"
    );
    let (code, _, err) = timed(&["check", "--builtin", "gauss(0)"]);
    assert_eq!(code, 2);
    assert!(err.contains("gauss"), "{err}");
}

/// Gauss-6 written out entry by entry as polynomials in root(...) nodes, one
/// entry perturbed by 1e-30: the run-time check refuses the symplecticity
/// claim exactly, naming W[0][1]; unperturbed, the claim holds.
#[test]
fn perturbed_gauss6_root_file_is_refused_naming_w01() {
    let (code, out, err) = timed(&[
        "check",
        "tableau/tests/fixtures/gauss6_roots_perturbed.toml",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("symplectic   no"), "{out}");
    assert!(
        out.contains("✗ symplectic: not symplectic: W[0][1] ≠ 0 (≈ 8.566224618958517e-32)"),
        "{out}"
    );
    let (code, out, err) = timed(&["check", "tableau/tests/fixtures/gauss6_roots.toml"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("✓ symplectic"), "{out}");
}

// ---------------------------------------------------------------------------
// The text and JSON of generated pairs and root(...) files say what is true
// and what the README documents.

/// The IIIA–IIIB pair: symplecticity is W = 0 and b = b̂ (not "b = b̂ = 0"),
/// the proof lines are labelled by table, and for s ≥ 6 the pair's own order
/// is not claimed.
#[test]
fn generated_pair_text_says_what_holds() {
    for id in ["lobatto3a3b4", "lobatto3a3b6", "lobatto3a3b8"] {
        let (code, out, err) = symlab(&["check", "--builtin", id]);
        assert_eq!(code, 0, "{id}: {err}");
        assert!(
            out.contains(
                "symplectic   yes: Wᵢⱼ = bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ = 0 for all i, j, and b = b̂, exactly"
            ),
            "{id}:\n{out}"
        );
        assert!(!out.contains("b̂ = 0"), "{id}:\n{out}");
        assert!(
            out.contains("  proof        IIIA table: B("),
            "{id}:\n{out}"
        );
        assert!(
            out.contains("               IIIB table: B("),
            "{id}:\n{out}"
        );
        assert!(!out.contains("proof        :"), "{id}:\n{out}");
    }
    let (_, out, _) = timed(&["check", "--builtin", "lobatto3a3b4"]);
    assert!(
        out.contains("  order        6 exactly (the pair's order"),
        "{out}"
    );
    let (_, out, _) = timed(&["check", "--builtin", "lobatto3a3b6"]);
    assert!(
        out.contains("  order        the pair's order is not proven"),
        "{out}"
    );
    let (_, out, _) = timed(&["check", "--builtin", "gauss4"]);
    assert!(
        out.contains("symplectic   yes: W = BA + AᵀB − bbᵀ = 0 exactly"),
        "{out}"
    );
    assert!(out.contains("  proof        B(8)"), "{out}");
}

/// Every field of a root file's JSON is in the guide's `--json` section
/// (`guide/src/check.md`);
/// W is listed both ways, as for other tables.
#[test]
fn root_file_json_is_documented_and_lists_w_both_ways() {
    // Gauss–Legendre 2 via roots with a[0][1] + 10⁻⁴⁰ (Gauss 4 is in
    // tests/three_readers.rs; its full B(k) analysis is slow in debug builds).
    let path = temp_table(
        "gauss2-roots-perturbed.toml",
        "name = \"Gauss 2 via roots, perturbed\"\n\
         let = { c0 = \"root(6*x^2 - 6*x + 1, 0, 1/2)\", c1 = \"root(6*x^2 - 6*x + 1, 1/2, 1)\" }\n\
         a = [[\"1/4\", \"c0 - 1/4 + 1/10^40\"], [\"c1 - 1/4\", \"1/4\"]]\n\
         b = [\"1/2\", \"1/2\"]\nclaims = [\"symplectic\"]\n",
    );
    let v = check_json(&[&path]);
    let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
    keys.sort();
    assert_eq!(
        keys,
        [
            "b_levels",
            "claims",
            "entries",
            "kind",
            "name",
            "origin",
            "refusals",
            "report",
            "roots",
            "row_sums_ok",
            "stages",
            "symplectic",
            "symplectic_separable",
            "w_nonzero"
        ]
    );
    let guide = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/guide/src/check.md"))
        .unwrap();
    for k in keys.iter().chain(&["zero", "value_f64", "b_hat_levels"]) {
        assert!(
            guide.contains(&format!("`{k}`")),
            "guide/src/check.md does not document `{k}`"
        );
    }
    assert_eq!(v["entries"], "algebraic");
    assert_eq!(v["roots"], serde_json::json!(["c0", "c1"]));
    assert_eq!(v["symplectic"], false);
    let w: Vec<(u64, u64, bool, f64)> = v["w_nonzero"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            (
                e["i"].as_u64().unwrap(),
                e["j"].as_u64().unwrap(),
                e["zero"].as_bool().unwrap(),
                e["value_f64"].as_f64().unwrap(),
            )
        })
        .collect();
    // a[0][1] + 10⁻⁴⁰ moves W[0][1] = W[1][0] by b₀·10⁻⁴⁰, b₀ = 1/2.
    let b0 = 0.5;
    assert_eq!(w.len(), 2, "{w:?}");
    assert_eq!((w[0].0, w[0].1, w[1].0, w[1].1), (0, 1, 1, 0));
    for e in &w {
        assert!(!e.2);
        assert!((e.3 / (b0 * 1e-40) - 1.0).abs() < 1e-12, "{e:?}");
    }
    // The generated table's JSON fields are documented too.
    let g = check_json(&["--builtin", "lobatto3a3b4"]);
    for k in g.as_object().unwrap().keys() {
        assert!(
            guide.contains(&format!("`{k}`")),
            "guide/src/check.md does not document `{k}`"
        );
    }
    let (_, out, _) = timed(&["check", &path]);
    assert!(
        out.contains("symplectic   no: W = BA + AᵀB − bbᵀ (symmetric; entries i ≤ j below)"),
        "{out}"
    );
}

/// A table that claims a generalised order gets its generalised orders,
/// how they were proven and the first failing condition of each part; a
/// table without such a claim keeps its report unless asked.
#[test]
fn near_integrable_orders_are_printed_with_their_proof() {
    let (code, out, err) = symlab(&["check", "tableau/catalogue/saba2.toml"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("  H = A + εB   generalised order (4, 2): error O(εh⁴ + ε²h²), drifts the flow of A, kicks that of εB\n"),
        "{out}"
    );
    assert!(
        out.contains("ε part: order 4; the εh⁵ condition fails: the coefficient of A⁴B in log Φ (the leading word of [A,[A,[A,[A,B]]]]) is -1/4320 ≈ -2.315e-4, not 0"),
        "{out}"
    );
    assert!(
        out.contains("14 Lyndon coefficients tested, each exactly"),
        "{out}"
    );
    assert!(out.contains("    ✓ order = (4, 2)\n"), "{out}");
    // The rows come before the claims.
    assert!(out.find("H = A + εB").unwrap() < out.find("  claims\n").unwrap());

    let v = check_json(&["tableau/catalogue/aba-8-6-4.toml"]);
    let n = &v["near_integrable"];
    assert_eq!(n["orders"], serde_json::json!([8, 6, 4]));
    assert_eq!(n["exact"], serde_json::json!([true, true, true]));
    assert_eq!(n["bound"], "1/100000000000000000000000000000000000000");
    assert_eq!(n["parts"][1]["first_failure"]["word"], "A⁵B²");

    // No claim, no flag: the report of a drift–kick sequence is unchanged.
    let (_, plain, _) = symlab(&["check", "--builtin", "leapfrog"]);
    assert!(!plain.contains("H = A + εB"), "{plain}");
    let v = check_json(&["--builtin", "leapfrog"]);
    assert!(v.get("near_integrable").is_none());
    let (code, asked, err) = symlab(&["check", "--builtin", "leapfrog", "--near-integrable"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        asked.contains("generalised order (2): error O(εh²)"),
        "{asked}"
    );
    assert_eq!(
        asked.replace(
            &asked[asked.find("  H = A + εB").unwrap()..asked.find("  claims\n").unwrap()],
            ""
        ),
        plain
    );
    // A Runge–Kutta table, asked: refused with the reason.
    let (code, rk, _) = symlab(&["check", "--builtin", "rk4", "--near-integrable"]);
    assert_eq!(code, 0);
    assert!(rk.contains("H = A + εB   not decided: a near-integrable (generalised) order is a property of a drift–kick sequence or a composition"), "{rk}");
}

/// A processed method (kernel + corrector): `symlab check` says what it is,
/// prints the effective generalised orders of `χ K χ⁻¹` with their proof
/// and first failing conditions, and checks the claims against the
/// effective method; an over-claim in a user's file is a ✗ naming the
/// condition.
#[test]
fn processed_methods_print_their_effective_orders() {
    let (code, out, err) = symlab(&["check", "--builtin", "leapfrog-c17"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("  processed    kernel K = builtin:leapfrog (the rows above are its own), corrector χ of 33 drifts and 32 kicks (63 flows); stepped as χ Kⁿ χ⁻¹"),
        "{out}"
    );
    assert!(
        out.contains("  H = A + εB   effective generalised order (18, 2): error O(εh¹⁸ + ε²h²)"),
        "{out}"
    );
    assert!(
        out.contains("ε part: order 18; the εh¹⁹ condition fails: the coefficient of A¹⁸B"),
        "{out}"
    );
    assert!(out.contains("ε² part: order 2; the ε²h³ condition fails: the coefficient of AB² in log Φ (the leading word of [[A,B],B]) is 1/24"), "{out}");
    assert!(
        out.contains("proof: log Φ (Φ = χ K χ⁻¹) in the free algebra"),
        "{out}"
    );
    assert!(out.contains("    ✓ order = (18, 2)\n"), "{out}");
    assert!(out.contains("    ✓ order = 2\n"), "{out}");

    let v = check_json(&["--builtin", "whckc-c11"]);
    assert_eq!(
        v["near_integrable"]["orders"],
        serde_json::json!([12, 4, 3])
    );
    assert_eq!(v["processed"]["kernel"], serde_json::Value::Null);
    assert_eq!(
        v["processed"]["corrector_kick"].as_array().unwrap().len(),
        20
    );

    // A user's file: the leapfrog kernel with the order-3 corrector, claiming
    // one order too many.
    let dir = std::env::temp_dir().join(format!("symlab-processed-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string("tableau/catalogue/leapfrog-c3.toml")
        .unwrap()
        .replace("\"order = (4, 2)\"", "\"order = (6, 2)\"");
    let path = dir.join("over.toml");
    std::fs::write(&path, text).unwrap();
    let (code, out, err) = symlab(&["check", path.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("    ✗ order = (6, 2): order = (6, 2) claimed, but the ε part has order 4 < 6: the εh⁵ condition fails: the coefficient of A⁴B in log Φ (the leading word of [A,[A,[A,[A,B]]]]) is"),
        "{out}"
    );
    assert!(out.contains("effective generalised order (4, 2)"), "{out}");
    std::fs::remove_dir_all(&dir).ok();
}
