//! Table files with `root(...)` entries: every generated collocation
//! table written out with `to_root_file` (with and without `c`) is decided
//! or refused, never decided wrongly; pairs; the inputs that used to
//! overflow the stack or run for minutes; mutations never panic.

use std::time::{Duration, Instant};

use proptest::prelude::*;
use tableau::algebraic::family::{Family, Method, PairMethod};
use tableau::algebraic::file::{AlgFile, Loaded, parse};
use tableau::claims::Claim;

/// A hang detector only (never a performance claim): generous, and more so
/// for unoptimised builds.
fn hang_limit() -> Duration {
    Duration::from_secs(if cfg!(debug_assertions) { 120 } else { 20 })
}

fn alg(text: &str) -> Box<AlgFile> {
    match parse("t.toml", text) {
        Ok(Loaded::Algebraic(f)) => f,
        Ok(other) => panic!("not a root file: {other:?}"),
        Err(e) => panic!("{e}"),
    }
}

/// Checks a generated table written as a root file against the
/// generator's own exact verdicts: nothing decided wrongly.
fn check_family(fam: Family, s: usize, with_c: bool) -> f64 {
    let m = Method::new(fam, s);
    let v = m.verdicts();
    let text = m.to_root_file_with("t", &["symplectic"], None, with_c);
    let t0 = Instant::now();
    let f = alg(&text);
    let an = f.analyse();
    let secs = t0.elapsed().as_secs_f64();
    let tag = format!("{} {s} c={with_c}", fam.name());
    assert!(an.work <= tableau::budget::MAX_ANALYSIS_WORK, "{tag}");
    if std::env::var_os("ROOT_FILES_VERBOSE").is_some() {
        println!("{tag}: work {}, refusals {:?}", an.work, an.refusals);
    }
    if let Some(x) = an.symplectic {
        assert_eq!(x, v.symplectic, "{tag}: symplectic");
    }
    if with_c && let Some(x) = an.row_sums_ok {
        assert_eq!(x, v.row_sums_ok, "{tag}: row sums");
    }
    // B(k) with the nodes as c (given, or the row sums when they agree).
    if with_c || v.row_sums_ok {
        let mb = v.order.b;
        for (i, level) in an.b_levels.iter().enumerate() {
            let k = i + 1;
            match level {
                Some(true) => assert!(
                    k <= mb,
                    "{tag}: B({k}) decided true, generator says B ≤ {mb}"
                ),
                Some(false) => assert_eq!(k, mb + 1, "{tag}: B({k}) decided false"),
                None => {}
            }
        }
    }
    let claim = f.check_claim(&an, &Claim::Symplectic);
    if an.symplectic_separable == Some(true) {
        assert!(claim.is_ok(), "{tag}");
    } else {
        assert!(!claim.unwrap_err().is_empty());
    }
    assert!(t0.elapsed() < hang_limit(), "{tag}");
    secs
}

fn min_stages(f: Family) -> usize {
    match f {
        Family::Gauss | Family::Radau2A => 1,
        _ => 2,
    }
}

#[test]
fn families_up_to_4_stages_decided_or_refused() {
    for fam in Family::ALL {
        for s in min_stages(fam)..=4 {
            for with_c in [true, false] {
                check_family(fam, s, with_c);
                // Small tables are decided outright, nothing refused.
                let text = Method::new(fam, s).to_root_file_with("t", &[], None, with_c);
                let an = alg(&text).analyse();
                assert!(
                    an.refusals.is_empty(),
                    "{} {s}: {:?}",
                    fam.name(),
                    an.refusals
                );
                assert!(an.symplectic.is_some() && an.b_levels.last().is_some_and(|v| v.is_some()));
            }
        }
    }
}

/// Every family with s ≤ 8, with and without `c`; prints the time per case
/// (`cargo test -p tableau --release --test integration root_files:: -- --ignored
/// --nocapture`).
#[test]
#[ignore = "about a minute in release; run with --release --ignored"]
fn families_up_to_8_stages_decided_or_refused() {
    for fam in Family::ALL {
        for s in min_stages(fam)..=8 {
            for with_c in [true, false] {
                let t = check_family(fam, s, with_c);
                println!("{} {s} c={with_c}: {t:.3} s", fam.name());
            }
        }
    }
    for s in 2..=8 {
        for with_c in [true, false] {
            let t = check_pair(s, with_c);
            println!("lobatto3a3b {s} c={with_c}: {t:.3} s");
        }
    }
}

fn check_pair(s: usize, with_c: bool) -> f64 {
    let pm = PairMethod::new(s);
    let v = pm.verdicts();
    let text = pm.to_root_file("pair", &["symplectic"], None, with_c);
    let t0 = Instant::now();
    let f = alg(&text);
    let an = f.analyse();
    let secs = t0.elapsed().as_secs_f64();
    assert!(an.pair);
    if let Some(x) = an.symplectic {
        assert_eq!(x, v.symplectic, "pair {s}");
    }
    if let Some(x) = an.symplectic_separable {
        assert!(x, "pair {s}: the IIIA–IIIB conditions hold");
    }
    assert!(t0.elapsed() < hang_limit());
    secs
}

/// The Lobatto IIIA–IIIB pair with 4 stages written with roots is decided
/// symplectic; a_hat[0][1] perturbed by 10⁻³⁰ is refused naming the entry.
#[test]
fn lobatto_pair_with_roots() {
    let pm = PairMethod::new(4);
    let f = alg(&pm.to_root_file("IIIA–IIIB 4", &["symplectic"], None, false));
    let an = f.analyse();
    assert!(an.pair);
    assert_eq!(an.symplectic_separable, Some(true));
    assert_eq!(an.same_weights, Some(true));
    assert_eq!(an.symplectic, Some(true));
    assert!(f.check_claim(&an, &Claim::Symplectic).is_ok());
    assert!(an.b_levels.iter().take(6).all(|v| *v == Some(true)));
    assert!(an.b_hat_levels.iter().take(6).all(|v| *v == Some(true)));

    let bad = alg(&pm.to_root_file("perturbed", &["symplectic"], Some((0, 1, "1/10^30")), false));
    let an = bad.analyse();
    assert_eq!(an.symplectic, Some(false));
    let msg = bad.check_claim(&an, &Claim::Symplectic).unwrap_err();
    assert!(msg.contains("W[0][1] ≠ 0 (≈ "), "{msg}");
    assert!(msg.contains("bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ"), "{msg}");
}

/// A pair file needs both a_hat and b_hat; c_hat needs the pair.
#[test]
fn pair_fields_are_checked() {
    let pm = PairMethod::new(3);
    let text = pm.to_root_file("p", &[], None, true);
    let no_b_hat: String = {
        let start = text.find("\nb_hat = [").unwrap();
        let end = start + text[start + 1..].find("\n]").unwrap() + 3;
        format!("{}{}", &text[..start], &text[end..])
    };
    let e = parse("p.toml", &no_b_hat).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("b_hat"), "{e}");
    let gauss = Method::new(Family::Gauss, 2).to_root_file("g", &[], None);
    let at = gauss.find("\n[let]").unwrap();
    let with_c_hat = format!(
        "{}\nc_hat = [\"1/2\", \"1/2\"]{}",
        &gauss[..at],
        &gauss[at..]
    );
    let e = parse("g.toml", &with_c_hat).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("c_hat"), "{e}");
}

/// A = 0 and b the five Lobatto weights, each in its own root of the node
/// polynomial: this overflowed the stack deciding B(1) (num-rational's
/// comparison recursed once per continued-fraction term).
#[test]
fn lobatto5_weights_in_five_roots() {
    let m = Method::new(Family::Lobatto3A, 5);
    let text = m.to_root_file("w", &["symplectic"], None);
    let start = text.find("a = [").unwrap();
    let end = text.find("\nb = [").unwrap();
    let zeros = vec![format!("[{}]", ["0"; 5].join(", ")); 5].join(", ");
    let text = format!("{}a = [{zeros}]{}", &text[..start], &text[end..]);
    let f = alg(&text);
    let t0 = Instant::now();
    let an = f.analyse();
    // c = the row sums = 0: B(1) holds (the weights sum to 1), B(2) fails.
    assert_eq!(an.b_levels, vec![Some(true), Some(false)]);
    // W = −bbᵀ ≠ 0.
    assert_eq!(an.symplectic, Some(false));
    assert!(t0.elapsed() < hang_limit());
    // With c the nodes: Lobatto quadrature, B(8) holds and B(9) fails.
    let at = text.find("\n[let]").unwrap();
    let with_c = format!(
        "{}\nc = [\"c0\", \"c1\", \"c2\", \"c3\", \"c4\"]{}",
        &text[..at],
        &text[at..]
    );
    let an = alg(&with_c).analyse();
    assert_eq!(&an.b_levels[..8], &[Some(true); 8]);
    assert_eq!(an.b_levels[8], Some(false));
    assert_eq!(an.row_sums_ok, Some(false));
}

/// Gauss–Legendre 4 with `c` left to the row sums (77 s and 600 MB before):
/// decided, B(8) holds and B(9) fails.
#[test]
fn gauss4_roots_without_c() {
    let m = Method::new(Family::Gauss, 4);
    let f = alg(&m.to_root_file("g4", &["symplectic"], None));
    assert!(f.c.is_none());
    let t0 = Instant::now();
    let an = f.analyse();
    assert_eq!(an.symplectic, Some(true));
    assert_eq!(&an.b_levels[..8], &[Some(true); 8]);
    assert_eq!(an.b_levels[8], Some(false));
    assert!(an.refusals.is_empty(), "{:?}", an.refusals);
    assert!(t0.elapsed() < hang_limit());
}

/// A zero test in ten roots: √2·√3·…·√29 (nine square roots of primes,
/// each its own root) equals √(2·3·…·29) (a tenth root), decided exactly;
/// adding 10⁻⁵⁰ makes it nonzero, also decided.
#[test]
fn ten_root_zero_test() {
    let primes = [2u64, 3, 5, 7, 11, 13, 17, 19, 23];
    let prod: u64 = primes.iter().product();
    let mut lets = String::new();
    let mut names = Vec::new();
    for (i, p) in primes.iter().enumerate() {
        lets.push_str(&format!("r{i} = \"root(x^2 - {p}, 0, {p})\"\n"));
        names.push(format!("r{i}"));
    }
    lets.push_str(&format!("big = \"root(x^2 - {prod}, 0, {prod})\"\n"));
    let product = names.join("*");
    for (extra, zero) in [("", true), (" + 1/10^50", false)] {
        let text = format!(
            "name = \"ten\"\na = [[\"{product} - big{extra}\"]]\nb = [\"1\"]\n[let]\n{lets}"
        );
        let f = alg(&text);
        assert_eq!(f.field.roots.len(), 10);
        let e = &f.a[0][0];
        let t0 = Instant::now();
        assert_eq!(f.field.is_zero(e).unwrap(), zero);
        if !zero {
            assert_eq!(f.field.sign(e).unwrap(), 1);
            assert_eq!(f.field.to_f64(e).unwrap(), 1e-50);
        }
        assert!(t0.elapsed() < hang_limit());
    }
}

fn root_file_with(lets: &str, entry: &str) -> String {
    format!("name = \"h\"\na = [[\"{entry}\"]]\nb = [\"1\"]\n[let]\n{lets}\n")
}

/// Huge bounds, huge coefficients and powers of powers: each refused with
/// a message naming the field and the limit, or decided quickly.
#[test]
fn huge_bounds_and_powers_are_bounded() {
    let digits = "7".repeat(1000);
    let cases: Vec<(String, Option<&str>)> = vec![
        // Two roots in the huge interval: refused; one: fine.
        (
            "c = \"root(x^2 - 2, -10^999, 10^999)\"".into(),
            Some("2 distinct real roots"),
        ),
        ("c = \"root(x^2 - 2, 0, 10^999)\"".into(), None),
        (
            "c = \"root(x^2 - 2, 1, 1 + 1/10^999)\"".into(),
            Some("0 distinct real roots"),
        ),
        (format!("c = \"root(x^2 - {digits}, 0, 10^600)\""), None),
        (
            "c = \"root((x^200)^200 - 2, 0, 2)\"".into(),
            Some("MAX_ROOT_DEGREE"),
        ),
        (
            "c = \"root(((x^2)^100)^100 - 2, 0, 2)\"".into(),
            Some("MAX_ROOT_DEGREE"),
        ),
        (
            "c = \"root(x^40*x^40 - 2, 0, 2)\"".into(),
            Some("MAX_ROOT_DEGREE"),
        ),
        (
            format!("c = \"root((x - {digits})^9, 0, 10^1001)\""),
            Some("MAX_ROOT_BITS"),
        ),
    ];
    for (lets, want) in cases {
        let t0 = Instant::now();
        let r = parse("h.toml", &root_file_with(&lets, "c"));
        match (want, r) {
            (None, Ok(Loaded::Algebraic(f))) => {
                let an = f.analyse();
                assert_eq!(an.b_levels[0], Some(true), "{lets}");
            }
            (Some(w), Err(e)) => {
                assert_eq!(e.field.as_deref(), Some("let.c"), "{lets}: {e}");
                assert!(e.to_string().contains(w), "{lets}: {e}");
            }
            (w, r) => panic!("{lets}: expected {w:?}, got {r:?}"),
        }
        assert!(t0.elapsed() < hang_limit(), "{lets}");
    }
}

/// Products that would expand to huge term counts are refused naming the
/// entry and the budget.
#[test]
fn huge_expansions_are_refused() {
    let m = Method::new(Family::Gauss, 8);
    let text = m.to_root_file("g8", &[], None);
    let digits = "7".repeat(1000);
    let big_power = format!("(c0 + {digits})^64");
    for entry in [
        "(c0 + c1 + c2 + c3 + c4 + c5 + c6 + c7)^64",
        "((c0 + c1 + c2 + c3 + c4 + c5 + c6 + c7)^8)^8",
        "(c0 + c1 + c2 + c3 + c4 + c5 + c6 + c7)^6 * (c0 + c1 + c2 + c3 + c4 + c5 + c6 + c7)^6",
        big_power.as_str(),
    ] {
        let start = text.find("a = [").unwrap();
        let end = text.find("\nb = [").unwrap();
        let mut rows = vec![vec!["0".to_string(); 8]; 8];
        rows[2][3] = entry.to_string();
        let a: Vec<String> = rows
            .iter()
            .map(|r| {
                format!(
                    "[{}]",
                    r.iter()
                        .map(|x| format!("\"{x}\""))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })
            .collect();
        let t = format!("{}a = [{}]{}", &text[..start], a.join(", "), &text[end..]);
        let t0 = Instant::now();
        let e = parse("g8.toml", &t).unwrap_err();
        assert_eq!(e.field.as_deref(), Some("a[2][3]"), "{e}");
        assert!(e.to_string().contains("tableau::budget::"), "{e}");
        assert!(t0.elapsed() < hang_limit());
    }
}

fn mutate(text: &str, ops: &[(u8, usize, u32)]) -> String {
    let mut t: Vec<char> = text.chars().collect();
    for &(op, at, x) in ops {
        if t.is_empty() {
            break;
        }
        let i = at % t.len();
        match op % 6 {
            0 => {
                t.remove(i);
            }
            1 => {
                let c = t[i];
                t.insert(i, c);
            }
            2 if t[i].is_ascii_digit() => t[i] = char::from(b'0' + (x % 10) as u8),
            3 => {
                let huge = [
                    "10^999",
                    "99999999999999999999",
                    "^64",
                    "1/10^999",
                    "(x^64)^64",
                    "*c0",
                ][x as usize % 6];
                for (k, ch) in huge.chars().enumerate() {
                    t.insert(i + k, ch);
                }
            }
            4 => {
                let j = (i + x as usize) % t.len();
                t.swap(i, j);
            }
            _ => {
                let s = [
                    "a_hat",
                    "b_hat",
                    "c",
                    "[[\"1\"]]",
                    "root(",
                    ")",
                    ",",
                    "\"",
                    "-",
                    "0",
                ][x as usize % 10];
                for (k, ch) in s.chars().enumerate() {
                    t.insert(i + k, ch);
                }
            }
        }
    }
    t.into_iter().collect()
}

fn run_mutant(text: &str) {
    let t0 = Instant::now();
    match parse("m.toml", text) {
        Ok(Loaded::Algebraic(f)) => {
            let an = f.analyse();
            for c in &f.claims {
                if let Err(e) = f.check_claim(&an, c) {
                    assert!(!e.is_empty());
                }
            }
        }
        Ok(_) => {}
        Err(e) => assert!(!e.message.is_empty()),
    }
    assert!(t0.elapsed() < hang_limit(), "hang on:\n{text}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Mutated root files: Ok or an error with a message; never a panic, a
    /// stack overflow or a hang.
    #[test]
    fn mutated_root_files(ops in prop::collection::vec((0u8..6, 0usize..100_000, 0u32..1000), 1..6)) {
        let base = Method::new(Family::Gauss, 3).to_root_file("g3", &["symplectic", "order = 6"], None);
        run_mutant(&mutate(&base, &ops));
    }

    #[test]
    fn mutated_pair_files(ops in prop::collection::vec((0u8..6, 0usize..100_000, 0u32..1000), 1..4)) {
        let base = PairMethod::new(2).to_root_file("p2", &["symplectic"], None, true);
        run_mutant(&mutate(&base, &ops));
    }

    #[test]
    fn mutated_generated_files(ops in prop::collection::vec((0u8..6, 0usize..100_000, 0u32..1000), 1..4)) {
        let base = "name = \"g\"\ngenerate = \"gauss(4)\"\nclaims = [\"symplectic\", \"order = 8\"]\n";
        let text = mutate(base, &ops);
        let t0 = Instant::now();
        match parse("m.toml", &text) {
            Ok(_) => {}
            Err(e) => prop_assert!(!e.message.is_empty()),
        }
        prop_assert!(t0.elapsed() < hang_limit());
    }
}

/// Repeated squaring through `let` bindings is bounded the same way, and
/// the refusal names the binding.
#[test]
fn repeated_squaring_in_lets_is_refused() {
    let m = Method::new(Family::Gauss, 8);
    let text = m.to_root_file("g8", &[], None);
    let sum = "c0 + c1 + c2 + c3 + c4 + c5 + c6 + c7";
    let lets = format!(
        "x1 = \"({sum})^2\"\nx2 = \"x1*x1\"\nx3 = \"x2*x2\"\nx4 = \"x3*x3\"\nx5 = \"x4*x4\"\n"
    );
    let text = text.replacen("[let]\n", &format!("[let]\n{lets}"), 1);
    let t0 = Instant::now();
    let e = parse("g8.toml", &text).unwrap_err();
    assert!(
        e.field.as_deref().is_some_and(|f| f.starts_with("let.x")),
        "{e}"
    );
    assert!(e.to_string().contains("tableau::budget::"), "{e}");
    assert!(t0.elapsed() < hang_limit());
}

/// Two roots 10⁻³⁰⁰ apart: refining one needs ~1000 bisections before
/// Newton steps take over; the bisections are limited, so the zero test is
/// refused (naming the budget) in seconds instead of running long.
#[test]
fn clustered_roots_are_bounded() {
    let text = "name = \"cl\"\na = [[\"(c*d - d*(1 + 1e-300))/2 + 1/2\"]]\nb = [\"1\"]\n[let]\nc = \"root((x - 1)*(x - 1 - 1e-300)*(x - 3), 1 + 1e-301, 2)\"\nd = \"root(x^2 - 2, 1, 2)\"\n";
    let f = alg(text);
    let t0 = Instant::now();
    let an = f.analyse();
    // The value is zero: never decided otherwise.
    assert_ne!(an.w[0].zero, Some(false));
    if an.w[0].zero.is_none() {
        assert!(
            an.refusals[0].contains("tableau::budget::"),
            "{:?}",
            an.refusals
        );
    }
    assert!(t0.elapsed() < hang_limit());
}

/// The claims of a root file, each with its verdict.
fn claim_verdicts(text: &str) -> Vec<(String, Result<(), String>)> {
    let f = alg(text);
    let an = f.analyse();
    f.claims
        .iter()
        .map(|c| (c.to_string(), f.check_claim(&an, c)))
        .collect()
}

/// Order claims of root files are decided on the trees, in the number field:
/// the collocation tables written out with `root(...)` nodes prove their
/// orders (Gauss s = 1, 2, 3: 2s; Radau IIA s = 2, 3: 2s − 1; Lobatto IIIA
/// s = 3: 4; with and without `c`), and the next order is refused.
#[test]
fn root_tables_prove_their_order_on_the_trees() {
    let t0 = Instant::now();
    for (fam, s, p) in [
        (Family::Gauss, 1, 2),
        (Family::Gauss, 2, 4),
        (Family::Gauss, 3, 6),
        (Family::Radau2A, 2, 3),
        (Family::Radau2A, 3, 5),
        (Family::Lobatto3A, 3, 4),
    ] {
        for with_c in [false, true] {
            let claims = [format!("order = {p}"), format!("order = {}", p + 1)];
            let claims: Vec<&str> = claims.iter().map(String::as_str).collect();
            let text = Method::new(fam, s).to_root_file_with("t", &claims, None, with_c);
            let v = claim_verdicts(&text);
            let tag = format!("{} {s} c={with_c}", fam.name());
            assert!(v[0].1.is_ok(), "{tag}: {:?}", v[0]);
            let e = v[1].1.as_ref().unwrap_err();
            assert!(
                e.contains(&format!("order {} claimed but", p + 1)),
                "{tag}: {e}"
            );
        }
    }
    // A generous hang detector, not a performance claim.
    assert!(t0.elapsed() < hang_limit());
}

/// A table whose quadrature conditions all hold but whose tree conditions do
/// not: Gauss-2 with `a[0][0] + δ` and `a[0][1] − δ` keeps its row sums and
/// `B(1..4)`, and fails the order-3 condition of the tree `[[τ]]`
/// (`Σ bᵢaᵢⱼcⱼ = 1/6` changes by `b₀δ(c₀ − c₁)`); the refusal names it. The
/// same claim on the unperturbed table holds, and `order = 5` is refused by
/// `B(5)`.
#[test]
fn a_tree_condition_that_fails_is_named() {
    let table = |d: &str| {
        format!(
            r#"name = "Gauss–Legendre 2 via roots"
let = {{ c0 = "root(6*x^2 - 6*x + 1, 0, 1/2)", c1 = "root(6*x^2 - 6*x + 1, 1/2, 1)" }}
a = [["1/4 + {d}", "c0 - 1/4 - {d}"], ["c1 - 1/4", "1/4"]]
b = ["1/2", "1/2"]
claims = ["symplectic", "order = 4", "order = 5", "order = 2", "order_rkn = 4", "order = 4 (residual < 1e-3)"]
"#
        )
    };
    let exact = claim_verdicts(&table("0"));
    for (claim, v) in &exact {
        if claim == "order = 5" {
            let e = v.as_ref().unwrap_err();
            assert!(e.contains("B(5) fails"), "{e}");
        } else {
            assert!(v.is_ok(), "{claim}: {v:?}");
        }
    }
    let moved = claim_verdicts(&table("1/1000"));
    let get = |c: &str| moved.iter().find(|(k, _)| k == c).unwrap().1.clone();
    assert!(get("symplectic").is_err());
    let e = get("order = 4").unwrap_err();
    assert!(
        e.contains("order 4 claimed but the order-3 condition for tree [[τ]] fails: Φ(t) − 1/γ(t) ≠ 0 (≈ -2.886751345948"),
        "{e}"
    );
    assert!(e.contains("1/γ(t) = 1/6"), "{e}");
    assert!(get("order = 2").is_ok());
    // |residual| = √3/6000 ≈ 2.9e-4 is below 1e-3 (so the bound claim
    // holds) and not below 1e-4.
    assert!(moved[5].1.is_ok(), "{:?}", moved[5]);
    let tight = table("1/1000").replace("(residual < 1e-3)", "(residual < 1e-4)");
    let v = claim_verdicts(&tight);
    let e = v[5].1.clone().unwrap_err();
    assert!(e.contains("is not below 1/10000"), "{e}");
    let e = get("order_rkn = 4").unwrap_err();
    assert!(e.contains("Runge–Kutta–Nyström"), "{e}");
}

/// The Lobatto IIIA–IIIB pair with 3 stages (b = b̂) proves order 4 on the
/// bicoloured trees; a perturbed `â` loses it, naming a bicoloured tree.
#[test]
fn root_pairs_prove_their_order_on_bicoloured_trees() {
    let pm = PairMethod::new(3);
    let ok = claim_verdicts(&pm.to_root_file("pair", &["order = 4", "order = 5"], None, false));
    assert!(ok[0].1.is_ok(), "{ok:?}");
    assert!(ok[1].1.is_err(), "{ok:?}");
    // â₀₁ + δ changes the row sum ĉ₀: the bushy white tree [τ_p]_p
    // (B(2) for b̂) fails first.
    let bad =
        claim_verdicts(&pm.to_root_file("pair", &["order = 4"], Some((0, 1, "1/1000")), false));
    let e = bad[0].1.as_ref().unwrap_err();
    assert!(e.contains("B(2) fails for b_hat"), "{e}");
    // With ĉ given as the nodes, the row sums differ and the trees decide:
    // a bicoloured tree is named.
    let bad =
        claim_verdicts(&pm.to_root_file("pair", &["order = 4"], Some((0, 1, "1/1000")), true));
    let e = bad[0].1.as_ref().unwrap_err();
    assert!(e.contains("order 4 claimed (on general partitioned systems) but the order-2 condition for tree [τ_p]_q fails"), "{e}");
}

/// SABA₄ (Laskar & Robutel 2001) with its exact coefficients: the drifts
/// are the differences of the 4-point Gauss–Legendre nodes on [0, 1] (the
/// roots of 70x⁴ − 140x³ + 90x² − 20x + 1, i.e. 1/2 ∓ √(525 ± 70√30)/70),
/// the kicks the Gauss weights (18 ∓ √30)/72. Its generalised order (8, 2)
/// is proven exactly in the number field; over-claims are refused naming
/// the Lie word, and so is a table with a weight moved by 10⁻³⁰.
fn saba4(claims: &str, w1: &str) -> String {
    format!(
        r#"name = "SABA4, exact Gauss nodes"
claims = [{claims}]
drift = ["x1", "x2 - x1", "1 - 2*x2", "x2 - x1", "x1"]
kick = ["{w1}", "(18 + sqrt(30))/72", "(18 + sqrt(30))/72", "(18 - sqrt(30))/72"]
[let]
x1 = "root(70*x^4 - 140*x^3 + 90*x^2 - 20*x + 1, 0, 1/5)"
x2 = "root(70*x^4 - 140*x^3 + 90*x^2 - 20*x + 1, 1/5, 1/2)"
"#
    )
}

#[test]
fn saba4_with_exact_nodes_proves_its_generalised_order() {
    let t0 = Instant::now();
    let text = saba4(
        r#""symplectic", "symmetric", "order = (8, 2)", "order = 2", "order = (10, 2)", "order = (8, 4)", "order = 3""#,
        "(18 - sqrt(30))/72",
    );
    let v = claim_verdicts(&text);
    for (claim, verdict) in &v[..4] {
        assert!(verdict.is_ok(), "{claim}: {verdict:?}");
    }
    let e = v[4].1.as_ref().unwrap_err();
    assert!(
        e.contains("order = (10, 2) claimed, but the ε part has order 8 < 10: the εh⁹ condition fails: the coefficient of A⁸B in log Φ"),
        "{e}"
    );
    let e = v[5].1.as_ref().unwrap_err();
    assert!(
        e.contains("the ε² part has order 2 < 4: the ε²h³ condition fails: the coefficient of AB² in log Φ (the leading word of [[A,B],B])"),
        "{e}"
    );
    // Order 3 on separable systems fails on a separable bicoloured tree.
    let e = v[6].1.as_ref().unwrap_err();
    assert!(
        e.contains(
            "order 3 claimed (on separable systems: b ≠ b̂) but the order-3 condition for tree"
        ),
        "{e}"
    );
    // The first weight moved by 1e-30 (and the consistency with it).
    let moved = saba4(
        r#""order = (8, 2)", "symmetric""#,
        "(18 - sqrt(30))/72 + 1e-30",
    );
    let v = claim_verdicts(&moved);
    let e = v[0].1.as_ref().unwrap_err();
    assert!(
        e.contains("the εh condition fails: the coefficient of B in log Φ"),
        "{e}"
    );
    let e = v[1].1.as_ref().unwrap_err();
    assert!(e.contains("not a palindrome"), "{e}");
    assert!(t0.elapsed() < hang_limit());
}

/// SABA₄ written with its nodes as nested radicals,
/// `1/2 ∓ sqrt(525 ± 70*sqrt(30))/70`, with no `root(...)`: the file is
/// beyond the radical field (a nested radical), so it is read with real
/// algebraic numbers (each radical a root of the characteristic polynomial
/// of its radicand), and proves (8, 2) exactly as the `root(...)` form does.
#[test]
fn saba4_with_nested_radicals_is_read_and_proven() {
    let t0 = Instant::now();
    let text = r#"name = "SABA4, nested radicals"
claims = ["symplectic", "symmetric", "order = (8, 2)", "order = (10, 2)"]
let = { x1 = "1/2 - sqrt(525 + 70*sqrt(30))/70", x2 = "1/2 - sqrt(525 - 70*sqrt(30))/70" }
drift = ["x1", "x2 - x1", "1 - 2*x2", "x2 - x1", "x1"]
kick = ["(18 - sqrt(30))/72", "(18 + sqrt(30))/72", "(18 + sqrt(30))/72", "(18 - sqrt(30))/72"]
"#;
    let f = alg(text);
    assert!(
        f.field.names.iter().any(|n| n == "sqrt(525 + 70*sqrt(30))"),
        "{:?}",
        f.field.names
    );
    let v = claim_verdicts(text);
    for (claim, verdict) in &v[..3] {
        assert!(verdict.is_ok(), "{claim}: {verdict:?}");
    }
    let e = v[3].1.as_ref().unwrap_err();
    assert!(e.contains("the εh⁹ condition fails"), "{e}");
    // A nested radical of a negative number, and one in two roots, are
    // refused naming the field.
    let bad = text.replace("sqrt(525 - 70*sqrt(30))", "sqrt(70*sqrt(30) - 525)");
    let e = parse("t.toml", &bad).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("let.x2"), "{e}");
    assert!(
        e.message.contains("square root of a negative number"),
        "{e}"
    );
    let two = text.replace("sqrt(525 - 70*sqrt(30))", "sqrt(sqrt(2) + sqrt(3))");
    let e = parse("t.toml", &two).unwrap_err();
    assert!(e.message.contains("only radicands in one root"), "{e}");
    assert!(t0.elapsed() < hang_limit());
}
