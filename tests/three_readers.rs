//! One table, three readers, one verdict: a table written with `root(...)`
//! entries gets the same verdicts from `symlab check FILE`, from
//! `symlab compare --table FILE` and from `butcher!` (compiled in
//! `integrator-core/tests/root_schemes.rs`, refused in
//! `integrator-macros/tests/ui/gauss4_roots_perturbed.rs`).
//!
//! The fixtures are written by `tableau::algebraic::family::Method::to_root_file`
//! from the exact generated tables, and the `butcher!` invocations are
//! rendered from the same files; [`fixtures_are_what_tableau_writes`] checks
//! that the committed files are exactly these (run it with
//! `SYMLAB_BLESS_FIXTURES=1` to rewrite them after a change).

use std::path::{Path, PathBuf};

use serde_json::Value;
use tableau::algebraic::family::{Generator, Method, PairMethod};

use crate::common;
use common::symlab;

/// A table written with `root(...)` entries.
struct Fixture {
    /// `tests/tables/roots/{stem}.toml`.
    stem: &'static str,
    /// The `butcher!` type name.
    scheme: &'static str,
    /// What `tableau::algebraic::family` generates.
    generator: &'static str,
    claims: &'static [&'static str],
    /// `a[i][j] += text`.
    perturb: Option<(usize, usize, &'static str)>,
    /// The verdict on symplecticity.
    symplectic: bool,
    /// Where the `butcher!` invocation is committed: an `include!`d file of
    /// `integrator-core/tests/root_schemes.rs`, or a whole trybuild case.
    macro_file: &'static str,
    /// The refusal every reader gives (the nonzero `Wᵢⱼ`), if refused.
    refusal: Option<&'static str>,
    /// A library scheme with the same exact table, run beside it by
    /// `compare` (its errors must agree: the same steps up to the last bits
    /// of the coefficients).
    peer: Option<&'static str>,
}

const FIXTURES: &[Fixture] = &[
    Fixture {
        stem: "gauss4-roots",
        scheme: "Gauss4Roots",
        generator: "gauss(4)",
        claims: &["symplectic"],
        perturb: None,
        symplectic: true,
        macro_file: "integrator-core/tests/root_tables/gauss4_roots.rs",
        refusal: None,
        peer: Some("gauss4"),
    },
    Fixture {
        stem: "gauss4-roots-perturbed",
        scheme: "AlmostGauss4Roots",
        generator: "gauss(4)",
        claims: &["symplectic"],
        perturb: Some((0, 1, "1/10^40")),
        symplectic: false,
        macro_file: "integrator-macros/tests/ui/gauss4_roots_perturbed.rs",
        refusal: Some("W[0][1] ≠ 0"),
        peer: None,
    },
    Fixture {
        stem: "radau2a5-roots",
        scheme: "Radau5Roots",
        generator: "radau2a(5)",
        claims: &[],
        perturb: None,
        symplectic: false,
        macro_file: "integrator-core/tests/root_tables/radau2a5_roots.rs",
        refusal: None,
        peer: None,
    },
    Fixture {
        stem: "lobatto3a3b4-roots",
        scheme: "Lobatto3a3b4Roots",
        generator: "lobatto3a3b(4)",
        claims: &["symplectic"],
        perturb: None,
        symplectic: true,
        macro_file: "integrator-core/tests/root_tables/lobatto3a3b4_roots.rs",
        refusal: None,
        peer: None,
    },
];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn toml_path(f: &Fixture) -> String {
    format!("tests/tables/roots/{}.toml", f.stem)
}

/// The table file `tableau` writes for a fixture.
fn root_file(f: &Fixture) -> String {
    let name = format!(
        "{} via root(...) nodes{}",
        Generator::parse(f.generator)
            .unwrap()
            .title()
            .replace(" (generated)", ""),
        if f.perturb.is_some() {
            ", a[0][1] + 1/10^40"
        } else {
            ""
        }
    );
    match Generator::parse(f.generator).unwrap() {
        Generator::Rk(family, s) => Method::new(family, s).to_root_file(&name, f.claims, f.perturb),
        Generator::Lobatto3A3B(s) => {
            PairMethod::new(s).to_root_file(&name, f.claims, f.perturb, false)
        }
    }
}

/// The strings of a TOML array written one per line by `to_root_file`.
fn strings_in(line: &str) -> Vec<String> {
    line.split('"')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// The `butcher!` invocation of a root table file (the format
/// `to_root_file` writes: one entry per line).
fn macro_text(toml: &str, scheme: &str) -> String {
    let mut name = String::new();
    let mut claims = Vec::new();
    let mut lets = Vec::new();
    let mut a: Vec<Vec<String>> = Vec::new();
    let mut b = Vec::new();
    let mut a_hat: Vec<Vec<String>> = Vec::new();
    let mut b_hat = Vec::new();
    #[derive(PartialEq)]
    enum Mode {
        Top,
        A,
        B,
        AHat,
        BHat,
        Let,
    }
    let mut mode = Mode::Top;
    for line in toml.lines() {
        let t = line.trim();
        match mode {
            _ if t == "[let]" => mode = Mode::Let,
            Mode::Let => {
                if let Some((k, v)) = t.split_once(" = ") {
                    lets.push((k.to_string(), v.trim_matches('"').to_string()));
                }
            }
            Mode::Top if t.starts_with("name = ") => name = strings_in(t).remove(0),
            Mode::Top if t.starts_with("claims = ") => claims = strings_in(t),
            Mode::Top if t == "a = [" => mode = Mode::A,
            Mode::Top if t == "b = [" => mode = Mode::B,
            Mode::Top if t == "a_hat = [" => mode = Mode::AHat,
            Mode::Top if t == "b_hat = [" => mode = Mode::BHat,
            Mode::Top => {}
            Mode::A if t == "[" => a.push(Vec::new()),
            Mode::A if t == "]" => mode = Mode::Top,
            Mode::A if t.starts_with('"') => a.last_mut().unwrap().extend(strings_in(t)),
            Mode::A => {}
            Mode::B if t == "]" => mode = Mode::Top,
            Mode::B => b.extend(strings_in(t)),
            Mode::AHat if t == "[" => a_hat.push(Vec::new()),
            Mode::AHat if t == "]" => mode = Mode::Top,
            Mode::AHat if t.starts_with('"') => a_hat.last_mut().unwrap().extend(strings_in(t)),
            Mode::AHat => {}
            Mode::BHat if t == "]" => mode = Mode::Top,
            Mode::BHat => b_hat.extend(strings_in(t)),
        }
    }
    let mut out = format!("butcher! {{\n    /// {name}\n    pub {scheme} {{\n");
    for (k, v) in &lets {
        out.push_str(&format!("        let {k} = {v};\n"));
    }
    out.push_str(&format!("        claims: [{}],\n", claims.join(", ")));
    let matrix = |out: &mut String, key: &str, m: &[Vec<String>]| {
        out.push_str(&format!("        {key}: [\n"));
        for row in m {
            out.push_str("            [\n");
            for e in row {
                out.push_str(&format!("                {e},\n"));
            }
            out.push_str("            ],\n");
        }
        out.push_str("        ],\n");
    };
    let vector = |out: &mut String, key: &str, v: &[String]| {
        out.push_str(&format!("        {key}: [\n"));
        for e in v {
            out.push_str(&format!("            {e},\n"));
        }
        out.push_str("        ],\n");
    };
    matrix(&mut out, "a", &a);
    vector(&mut out, "b", &b);
    if !a_hat.is_empty() {
        matrix(&mut out, "a_hat", &a_hat);
        vector(&mut out, "b_hat", &b_hat);
    }
    out.push_str("    }\n}\n");
    out
}

/// The committed `butcher!` file of a fixture: the invocation alone (for
/// `include!`), or a whole compile-fail case.
fn macro_file(f: &Fixture, toml: &str) -> String {
    let head = "// Written by tests/three_readers.rs from the table file of the same name \
                (SYMLAB_BLESS_FIXTURES=1 rewrites it).\n";
    let body = macro_text(toml, f.scheme);
    if f.macro_file.contains("/ui/") {
        // A compile-fail case of integrator-macros' trybuild test: the
        // macro alone, as every case there (`integrator-macros/tests/compile_fail.rs`).
        format!("{head}use integrator_macros::butcher;\n\n{body}\nfn main() {{}}\n")
    } else {
        format!("{head}{body}")
    }
}

#[test]
fn fixtures_are_what_tableau_writes() {
    let bless = std::env::var_os("SYMLAB_BLESS_FIXTURES").is_some();
    for f in FIXTURES {
        let toml = root_file(f);
        for (path, want) in [
            (root().join(toml_path(f)), toml.clone()),
            (root().join(f.macro_file), macro_file(f, &toml)),
        ] {
            if bless {
                std::fs::create_dir_all(path.parent().unwrap()).unwrap();
                std::fs::write(&path, &want).unwrap();
            }
            let have = std::fs::read_to_string(&path).unwrap_or_else(|e| {
                panic!(
                    "{}: {e} (SYMLAB_BLESS_FIXTURES=1 writes it)",
                    path.display()
                )
            });
            assert_eq!(
                have,
                want,
                "{} is not what tableau writes (SYMLAB_BLESS_FIXTURES=1 rewrites it)",
                path.display()
            );
        }
    }
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("symlab-3r-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `symlab check --json FILE`: the symplecticity verdict and the claims.
fn check_verdict(path: &str) -> (bool, Vec<(String, bool, String)>) {
    let (code, out, err) = symlab(&["check", "--json", path]);
    assert_eq!(code, 0, "{path}: {err}");
    let v: Value = serde_json::from_str(&out).expect("one JSON object");
    assert_eq!(v["entries"], "algebraic", "{path}: {v}");
    let claims = v["claims"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            (
                c["claim"].as_str().unwrap().to_string(),
                c["holds"].as_bool().unwrap(),
                c["reason"].as_str().unwrap_or("").to_string(),
            )
        })
        .collect();
    (v["symplectic"].as_bool().expect("decided"), claims)
}

/// `symlab compare --table FILE` on Kepler, two points: the CSV's
/// `symplectic` column and the errors of the table's rows and of the
/// `peer`'s, or the refusal.
#[allow(clippy::type_complexity)]
fn compare_verdict(
    path: &str,
    peer: &str,
    out: &Path,
) -> Result<(bool, Vec<f64>, Vec<f64>), String> {
    let (code, _, err) = symlab(&[
        "compare",
        "--problem",
        "kepler",
        "--methods",
        peer,
        "--table",
        path,
        "--t-end",
        "1",
        "--points",
        "2",
        "--repeats",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!err.contains("panicked"), "{err}");
    if code != 0 {
        assert_eq!(code, 2, "{path}: {err}");
        return Err(err);
    }
    let csv = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let stem = Path::new(path).file_stem().unwrap().to_str().unwrap();
    let rows: Vec<Vec<&str>> = lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|r| r[col("method")] == stem)
        .collect();
    assert_eq!(rows.len(), 2, "{csv}");
    let mut errors = Vec::new();
    for r in &rows {
        assert_eq!(r[col("status")], "ok", "{csv}");
        assert_eq!(r[col("interpreted")], "true", "{csv}");
        errors.push(r[col("error")].parse().unwrap());
    }
    let peer_errors = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|r| r[col("method")] == peer)
        .map(|r| r[col("error")].parse().unwrap())
        .collect();
    Ok((rows[0][col("symplectic")] == "true", errors, peer_errors))
}

/// What `butcher!` decided: the committed invocation compiles (with its
/// verdict asserted in `integrator-core/tests/root_schemes.rs`) or is a
/// compile-fail case whose expected diagnostic names the refusal.
fn macro_verdict(f: &Fixture) -> Result<(), String> {
    let rs = std::fs::read_to_string(root().join(f.macro_file)).unwrap();
    assert!(rs.contains(&format!("pub {} {{", f.scheme)));
    if f.macro_file.contains("/ui/") {
        let stderr = root().join(f.macro_file.replace(".rs", ".stderr"));
        Err(std::fs::read_to_string(&stderr)
            .unwrap_or_else(|e| panic!("{}: {e}", stderr.display())))
    } else {
        let tests =
            std::fs::read_to_string(root().join("integrator-core/tests/root_schemes.rs")).unwrap();
        let file = Path::new(f.macro_file)
            .file_name()
            .unwrap()
            .to_str()
            .unwrap();
        assert!(tests.contains(&format!("include!(\"root_tables/{file}\")")));
        let assertion = format!("({}::SYMPLECTIC, {})", f.scheme, f.symplectic);
        assert!(
            tests.contains(&assertion),
            "root_schemes.rs must assert {assertion}"
        );
        Ok(())
    }
}

#[test]
fn check_compare_and_butcher_agree_on_root_tables() {
    let dir = temp_dir("agree");
    for f in FIXTURES {
        let path = toml_path(f);
        let (symplectic, claims) = check_verdict(&path);
        assert_eq!(symplectic, f.symplectic, "check: {path}");
        let refused_by_check: Vec<&(String, bool, String)> =
            claims.iter().filter(|c| !c.1).collect();
        let compared = compare_verdict(&path, f.peer.unwrap_or("rk4"), &dir.join(f.stem));
        let built = macro_verdict(f);
        match f.refusal {
            None => {
                assert!(refused_by_check.is_empty(), "check: {path}: {claims:?}");
                let (sym, errors, peer_errors) =
                    compared.unwrap_or_else(|e| panic!("compare: {path}: {e}"));
                assert_eq!(sym, f.symplectic, "compare: {path}");
                // High order over t = 1 on Kepler (e = 0.6): small errors at
                // both step sizes, smaller at the smaller one.
                assert!(
                    errors.iter().all(|e| *e < 1e-2) && errors[1] < errors[0],
                    "compare: {path}: errors {errors:?}"
                );
                if f.peer.is_some() {
                    // The same table as the library's: the same steps, up
                    // to the last bits of the coefficients.
                    assert_eq!(peer_errors.len(), 2);
                    for (a, b) in errors.iter().zip(&peer_errors) {
                        assert!(
                            (a - b).abs() <= 1e-6 * b + 1e-13,
                            "compare: {path}: {a:e} vs the library's {b:e}"
                        );
                    }
                }
                built.unwrap();
            }
            Some(needle) => {
                assert!(
                    refused_by_check
                        .iter()
                        .any(|c| c.0 == "symplectic" && c.2.contains(needle)),
                    "check: {path}: {claims:?}"
                );
                let e = compared.expect_err("compare refuses it");
                assert!(
                    e.contains("claim `symplectic` does not hold") && e.contains(needle),
                    "compare: {path}: {e}"
                );
                let e = built.expect_err("butcher! refuses it");
                assert!(
                    e.contains("not symplectic") && e.contains(needle),
                    "butcher!: {e}"
                );
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `generate = …` files enter `symlab compare --table` too: the certified
/// coefficients of `butcher! { from: "gauss4" }` (the library's gauss4), so
/// the same steps and errors; a false claim is refused as `check` refuses it.
#[test]
fn compare_reads_generated_table_files() {
    let dir = temp_dir("generated");
    let good = dir.join("my-gauss4.toml");
    std::fs::write(
        &good,
        "generate = \"gauss(4)\"\nclaims = [\"symplectic\", \"order = 8\"]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let (code, _, err) = symlab(&[
        "compare",
        "--problem",
        "kepler",
        "--methods",
        "gauss4",
        "--table",
        good.to_str().unwrap(),
        "--t-end",
        "1",
        "--points",
        "2",
        "--repeats",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let mine: Vec<&Vec<&str>> = rows
        .iter()
        .filter(|r| r[col("method")] == "my-gauss4")
        .collect();
    let lib: Vec<&Vec<&str>> = rows
        .iter()
        .filter(|r| r[col("method")] == "gauss4")
        .collect();
    assert_eq!((mine.len(), lib.len()), (2, 2), "{csv}");
    for (a, b) in mine.iter().zip(&lib) {
        assert_eq!(a[col("status")], "ok", "{csv}");
        assert_eq!(a[col("order")], "8");
        assert_eq!(a[col("symplectic")], "true");
        assert_eq!(a[col("interpreted")], "true");
        assert_eq!(a[col("steps")], b[col("steps")]);
        let (ea, eb): (f64, f64) = (
            a[col("error")].parse().unwrap(),
            b[col("error")].parse().unwrap(),
        );
        assert!((ea - eb).abs() <= 1e-13 + 1e-6 * eb, "{ea:e} vs {eb:e}");
    }
    let bad = dir.join("radau-claims-symplectic.toml");
    std::fs::write(
        &bad,
        "generate = \"radau2a(4)\"\nclaims = [\"symplectic\"]\n",
    )
    .unwrap();
    let (code, _, err) = symlab(&[
        "compare",
        "--problem",
        "kepler",
        "--table",
        bad.to_str().unwrap(),
        "--t-end",
        "1",
        "--points",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("radau-claims-symplectic.toml")
            && err.contains("claim `symplectic` does not hold: not symplectic"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
