//! End-to-end tests of `symlab check` and `symlab list`: verdicts from table
//! files, the JSON fields of design.md, and clear errors with exit code 2.

use serde_json::Value;

mod common;
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
            "class",
            "kind",
            "name",
            "order",
            "order_limit",
            "order_rkn",
            "order_separable",
            "row_sums_ok",
            "stability_function",
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
    for id in ["rk4", "gauss2", "gauss3", "forest-ruth", "stormer-verlet"] {
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
