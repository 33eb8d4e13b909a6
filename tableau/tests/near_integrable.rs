//! Generalised orders of near-integrable splittings (H = A + εB), decided
//! exactly: the catalogue's SABAₙ, SBABₙ and ABA/ABAH methods against their
//! published orders, perturbed coefficients, over-claims, other forms and
//! budgets.

use std::path::Path;
use std::time::Instant;

use tableau::analysis::{Analysis, check_claim};
use tableau::claims::Claim;
use tableau::expr::parse_number;
use tableau::file::{TableFile, parse_table_file};
use tableau::near_integrable::{
    Factor, NearError, REPORT_DEGREES, check_near_claim, claim_degrees, near_coefficients,
    near_orders,
};
use tableau::{Number, Table};

/// The published generalised orders: Laskar & Robutel (2001) state
/// `O(τ^{2n}ε + τ²ε²)` for SABAₙ and SBABₙ; Blanes et al. (2013) name their
/// methods by theirs.
const PUBLISHED: [(&str, &[usize]); 14] = [
    ("saba1", &[2, 2]),
    ("saba2", &[4, 2]),
    ("saba3", &[6, 2]),
    ("saba4", &[8, 2]),
    ("sbab1", &[2, 2]),
    ("sbab2", &[4, 2]),
    ("sbab3", &[6, 2]),
    ("sbab4", &[8, 2]),
    ("aba-10-4", &[10, 4]),
    ("aba-8-6-4", &[8, 6, 4]),
    ("aba-10-6-4", &[10, 6, 4]),
    ("abah-8-4-4", &[8, 4, 4]),
    ("abah-8-6-4", &[8, 6, 4]),
    ("abah-10-6-4", &[10, 6, 4]),
];

fn text(id: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("catalogue")
        .join(format!("{id}.toml"));
    std::fs::read_to_string(path).unwrap()
}

fn entry(id: &str) -> TableFile {
    parse_table_file(&format!("{id}.toml"), &text(id)).unwrap_or_else(|e| panic!("{e}"))
}

/// The entry's generalised-order claim: its orders and bound.
fn near_claim(file: &TableFile) -> (Vec<usize>, Option<Number>) {
    file.claims
        .iter()
        .find_map(|c| match c {
            Claim::NearOrder { orders, bound } => Some((orders.clone(), bound.clone())),
            _ => None,
        })
        .expect("a generalised-order claim")
}

/// Every claim of every entry holds, the generalised one is the published
/// order, and the orders decided without a claim (at the report degrees)
/// are exactly the published ones: each part's first failing condition is
/// found, one degree above.
#[test]
fn published_generalised_orders_hold_and_are_exact() {
    for (id, published) in PUBLISHED {
        let file = entry(id);
        let (orders, bound) = near_claim(&file);
        assert_eq!(orders, published, "{id}: the claim is the published order");
        let analysis = Analysis::of(&file.table).unwrap();
        for claim in &file.claims {
            check_claim(&file.table, &analysis, claim)
                .unwrap_or_else(|e| panic!("{id}: `{claim}`: {e}"));
        }
        let start = Instant::now();
        let report = near_orders(&file.table, &REPORT_DEGREES, bound.as_ref()).unwrap();
        let took = start.elapsed();
        // (2, 2) and (8, 4, 4) are printed as (2) and (8, 4): the last entry
        // stands for every higher power of ε.
        let mut expected = published.to_vec();
        while expected.len() > 1 && expected[expected.len() - 1] == expected[expected.len() - 2] {
            expected.pop();
        }
        let found: Vec<usize> = report.generalised().iter().map(|g| g.0).collect();
        assert_eq!(found, expected, "{id}: {}", report.generalised_text());
        assert!(
            report.generalised().iter().all(|g| g.1),
            "{id}: every order exact: {}",
            report.generalised_text()
        );
        println!("{id}: {} in {took:?}", report.generalised_text());
    }
}

/// The bound of each decimal entry is the catalogue's rule: ten times the
/// largest Lyndon coefficient within the claimed degrees, rounded up to a
/// power of ten; and the coefficients really need it (a thousand times
/// tighter, the claim fails).
#[test]
fn decimal_bounds_follow_the_rule() {
    for (id, _) in PUBLISHED {
        let file = entry(id);
        let (orders, bound) = near_claim(&file);
        let Some(bound) = bound else {
            let all = near_coefficients(&file.table, &claim_degrees(&orders)).unwrap();
            assert!(all.iter().all(|c| c.residual.is_zero()), "{id}: exact");
            continue;
        };
        let all = near_coefficients(&file.table, &claim_degrees(&orders)).unwrap();
        let largest = all.iter().map(|c| c.residual.abs()).max().unwrap();
        let ten = &largest * &Number::from(10);
        assert!(ten < bound, "{id}");
        assert!(
            &bound * &Number::ratio(1, 10).unwrap() <= ten,
            "{id}: the bound is the smallest power of ten above ten times {largest}"
        );
        let tight = &bound * &Number::ratio(1, 1000).unwrap();
        assert!(
            check_near_claim(&file.table, &orders, Some(&tight)).is_err(),
            "{id}"
        );
    }
}

/// Changing one published coefficient in its 10th significant digit (the
/// middle coefficient, a formula, keeps consistency) loses the claim, and the
/// error names the failing condition: its power of ε and h, its Lyndon word,
/// its Lie element and its value.
#[test]
fn a_perturbed_coefficient_loses_the_claim_naming_the_condition() {
    for (id, old, new, phrase) in [
        (
            "aba-8-6-4",
            "0.241153427956640098736487795326289649618",
            "0.241153427856640098736487795326289649618",
            "order = (8, 6, 4) claimed, but the ε part has order 2 < 8: the εh³ condition fails: the coefficient of A²B in log Φ (the leading word of [A,[A,B]]) is",
        ),
        (
            "aba-10-6-4",
            "0.2044461531429987806805077839164344779763",
            "0.2044461531529987806805077839164344779763",
            "order = (10, 6, 4) claimed, but the ε part has order 2 < 10: the εh³ condition fails: the coefficient of A²B in log Φ",
        ),
        (
            "saba4",
            "0.2605776340045981552106403648947824089476",
            "0.2605776340145981552106403648947824089476",
            "order = (8, 2) (residual < 1e-40) claimed, but the ε part has order 2 < 8: the εh³ condition fails: the coefficient of A²B",
        ),
    ] {
        let t = text(id);
        assert!(t.contains(old), "{id}");
        let file = parse_table_file(id, &t.replacen(old, new, 1)).unwrap();
        let (orders, bound) = near_claim(&file);
        let e = check_near_claim(&file.table, &orders, bound.as_ref()).unwrap_err();
        let e = e.replace(" (residual < 1e-40)", "");
        let phrase = phrase.replace(" (residual < 1e-40)", "");
        assert!(e.contains(&phrase), "{id}: {e}");
        assert!(e.contains("≈ "), "{id}: a float approximation: {e}");
    }
    // An exact method: SABA₂ with kicks 1/2 ± 1/1000 (still consistent, no
    // longer symmetric) has order (1, …): [A,B] survives, with coefficient
    // ½ Σ (aᵢbⱼ before − bᵢaⱼ before) = ½ c₂ (k₂ − k₁) = −√3/3000.
    let t = text("saba2").replace(
        "kick = [\"1/2\", \"1/2\"]",
        "kick = [\"1/2 + 1/1000\", \"1/2 - 1/1000\"]",
    );
    let file = parse_table_file("saba2", &t).unwrap();
    let e = check_near_claim(&file.table, &[4, 2], None).unwrap_err();
    assert!(
        e.contains(
            "the ε part has order 1 < 4: the εh² condition fails: the coefficient of AB in log Φ (the leading word of [A,B]) is -sqrt(3)/3000 ≈ -5.774e-4, not 0"
        ),
        "{e}"
    );
}

/// Claiming more than holds fails at the first condition past the truth.
#[test]
fn over_claims_name_the_first_failing_condition() {
    let saba3 = entry("saba3");
    let e = check_near_claim(&saba3.table, &[8, 2], None).unwrap_err();
    assert!(
        e.starts_with(
            "order = (8, 2) claimed, but the ε part has order 6 < 8: the εh⁷ condition fails: the coefficient of A⁶B in log Φ (the leading word of [A,[A,[A,[A,[A,[A,B]]]]]]) is "
        ),
        "{e}"
    );
    let e = check_near_claim(&saba3.table, &[6, 4], None).unwrap_err();
    assert!(
        e.starts_with(
            "order = (6, 4) claimed, but the ε² part has order 2 < 4: the ε²h³ condition fails: the coefficient of AB² in log Φ (the leading word of [[A,B],B]) is "
        ),
        "{e}"
    );
    // Through the claim language and the analysis, as `butcher!` and
    // `symlab check` see it.
    let aba = entry("aba-8-6-4");
    let analysis = Analysis::of(&aba.table).unwrap();
    let claim: Claim = "order = (8, 6, 6) (residual < 1e-38)".parse().unwrap();
    let e = check_claim(&aba.table, &analysis, &claim)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(
            "the ε³ part has order 4 < 6: the ε³h⁵ condition fails: the coefficient of A²B³"
        ),
        "{e}"
    );
    let claim: Claim = "order = (10, 6, 4) (residual < 1e-38)".parse().unwrap();
    let e = check_claim(&aba.table, &analysis, &claim)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("the ε part has order 8 < 10: the εh⁹ condition fails: the coefficient of A⁸B"),
        "{e}"
    );
}

/// The generalised orders agree with the classical order the tree analysis
/// decides, on the exact drift–kick sequences and compositions of the
/// catalogue: the least `p_j` is the order on separable systems.
#[test]
fn the_least_part_is_the_classical_order() {
    for id in [
        "leapfrog",
        "ruth3",
        "forest-ruth",
        "candy-rozmus4",
        "mclachlan-atela2",
        "yoshida4",
        "mclachlan-s5",
        "saba3",
        "sbab4",
    ] {
        let file = entry(id);
        let analysis = Analysis::of(&file.table).unwrap();
        let report = near_orders(&file.table, &REPORT_DEGREES, None).unwrap();
        let least = report.parts.iter().map(|p| p.order).min().unwrap();
        assert_eq!(
            least,
            analysis.order_separable.order,
            "{id}: {}",
            report.generalised_text()
        );
    }
}

/// Inconsistent drifts fail every part at the word A; a table of another
/// form is refused; degrees and budgets are checked before any work.
#[test]
fn refusals_and_consistency() {
    let file = parse_table_file(
        "t",
        "name = \"t\"\ndrift = [\"1/2\", \"1/3\"]\nkick = [\"1\"]\n",
    )
    .unwrap();
    let report = near_orders(&file.table, &[4, 2], None).unwrap();
    for part in &report.parts {
        assert_eq!(part.order, 0);
        let f = part.failure.as_ref().unwrap();
        assert_eq!(f.word, "A");
        assert_eq!(f.value, Number::ratio(5, 6).unwrap());
    }
    let file = parse_table_file(
        "t",
        "name = \"t\"\ndrift = [\"1/2\", \"1/2\"]\nkick = [\"2\"]\n",
    )
    .unwrap();
    let e = check_near_claim(&file.table, &[2, 2], None).unwrap_err();
    assert!(
        e.contains("the ε part has order 0 < 2: the εh condition fails: the coefficient of B in log Φ (the leading word of B) is 2 ≈ 2.000e0, not 1"),
        "{e}"
    );

    let rk4 = tableau::catalogue::load("rk4").unwrap();
    let e = near_orders(&rk4.table, &[4], None).unwrap_err();
    assert!(matches!(e, NearError::Form(_)), "{e}");
    assert!(e.to_string().contains("a Runge–Kutta table"), "{e}");
    let claim: Claim = "order = (4, 2)".parse().unwrap();
    let a = Analysis::of(&rk4.table).unwrap();
    assert!(check_claim(&rk4.table, &a, &claim).is_err());

    let saba2 = entry("saba2");
    for (degrees, phrase) in [
        (vec![30], "at most degree 24"),
        (vec![], "nonempty"),
        (vec![20, 20, 20, 20, 20, 20], "words, more than the 65536"),
    ] {
        let e = near_orders(&saba2.table, &degrees, None).unwrap_err();
        assert!(e.to_string().contains(phrase), "{degrees:?}: {e}");
    }
    // A coefficient in a field of degree 243 (five cube roots): ABA(10,4)
    // at its claimed degrees is refused before the work (it ran 27 s).
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/catalogue/aba-10-4.toml"
    ))
    .unwrap()
    .replace(
        "\"0.04706710064597250612947887637243678556564\"",
        "\"1/(cbrt(2)+cbrt(3)+cbrt(5)+cbrt(7)+cbrt(11))\"",
    );
    let file = tableau::file::parse_table_file("aba-10-4-cbrt.toml", &text).unwrap();
    let started = std::time::Instant::now();
    let e = near_orders(&file.table, &[10, 4], None).unwrap_err();
    assert!(matches!(e, NearError::Budget(_)), "{e}");
    assert!(e.to_string().contains("field of degree 243"), "{e}");
    assert!(started.elapsed() < std::time::Duration::from_secs(2));
    // 5053 words × 17 flows × degree 20 > 2²⁰ products: refused before the work.
    let aba = entry("aba-10-6-4");
    let e = near_orders(&aba.table, &[20, 14, 14, 14], None).unwrap_err();
    assert!(matches!(e, NearError::Budget(_)), "{e}");
    assert!(
        e.to_string()
            .contains("exact products, more than the 1048576"),
        "{e}"
    );
    // (2, 4) is decided, not refused: SABA₂'s ε²h³ term does not vanish.
    let e = check_near_claim(&saba2.table, &[2, 4], None).unwrap_err();
    assert!(
        e.contains("the ε² part has order 2 < 4: the ε²h³ condition fails"),
        "{e}"
    );
    let bound = parse_number("1e-10").unwrap();
    assert!(check_near_claim(&saba2.table, &[4, 2], Some(&bound)).is_ok());
}

/// A composition of Störmer–Verlet is analysed as its drift–kick sequence.
#[test]
fn compositions_are_drift_kick_sequences() {
    let y4 = entry("yoshida4");
    assert!(matches!(y4.table, Table::Composition(_)));
    let report = near_orders(&y4.table, &[6, 6, 6, 6, 6], None).unwrap();
    assert_eq!(report.generalised_text(), "(4)");
}

/// Processing: a kernel `K = χ⁻¹ S χ` (as maps, `χ` applied first) built
/// from SABA₃ (`S`, order (6, 2)) and an arbitrary corrector `χ = D(1/5)
/// K(1/7) D(−1/3)` has low orders of its own, and the processed method `χ K
/// χ⁻¹ = S` (`χ⁻¹` applied on entry, `χ` at output) has exactly SABA₃'s:
/// the effective order is decided on the processed sequence. Conjugating
/// the other way round (`χ⁻¹ K χ`) is another method, of low order.
#[test]
fn a_processor_gives_the_effective_order() {
    use tableau::near_integrable::{processed_orders, processed_sequence};
    let kernel = parse_table_file(
        "kernel",
        "name = \"K\"\nlet = { c1 = \"1/2 - sqrt(15)/10\", c2 = \"sqrt(15)/10\" }\n\
         drift = [\"1/5\", \"c1 - 1/3\", \"c2\", \"c2\", \"c1 + 1/3\", \"-1/5\"]\n\
         kick = [\"1/7\", \"5/18\", \"4/9\", \"5/18\", \"-1/7\"]\n",
    )
    .unwrap();
    let chi = parse_table_file(
        "chi",
        "name = \"χ\"\ndrift = [\"1/5\", \"-1/3\"]\nkick = [\"1/7\"]\n",
    )
    .unwrap();
    let degrees = [8, 4, 4];
    let own = near_orders(&kernel.table, &degrees, None).unwrap();
    assert!(own.parts[0].order < 6, "{}", own.generalised_text());
    let effective = processed_orders(&kernel.table, &chi.table, &degrees, None).unwrap();
    let saba3 = near_orders(&entry("saba3").table, &degrees, None).unwrap();
    assert_eq!(effective.generalised_text(), "(6, 2)");
    assert_eq!(effective.parts, saba3.parts);
    // The processed sequence is SABA₃'s, flow for flow.
    let Table::Splitting(s) = &entry("saba3").table else {
        unreachable!()
    };
    let ops: Vec<Factor> = s
        .normal_form()
        .into_iter()
        .map(|(op, x)| Factor::Letter(u8::from(op == tableau::table::Op::Kick), x))
        .collect();
    assert_eq!(processed_sequence(&kernel.table, &chi.table).unwrap(), ops);
    // χ⁻¹ K χ: χ applied on entry instead of at output.
    let chi_inverse = parse_table_file(
        "chi_inverse",
        "name = \"χ⁻¹\"\ndrift = [\"1/3\", \"-1/5\"]\nkick = [\"-1/7\"]\n",
    )
    .unwrap();
    let wrong = processed_orders(&kernel.table, &chi_inverse.table, &degrees, None).unwrap();
    assert!(wrong.parts[0].order < 6, "{}", wrong.generalised_text());
    // A processor of another form is refused.
    let rk4 = tableau::catalogue::load("rk4").unwrap();
    assert!(matches!(
        processed_orders(&kernel.table, &rk4.table, &degrees, None),
        Err(NearError::Form(_))
    ));
}

/// The processed methods of the catalogue: the Wisdom–Holman leapfrog
/// kernel with the correctors of order 3, 5, 7, 11 and 17, and the
/// composition kernel WHCKC with those of order 11 and 17 (Wisdom, Holman &
/// Touma 1996; Wisdom 2006; as REBOUND offers them), with their effective
/// generalised orders.
const PROCESSED: [(&str, &[usize]); 7] = [
    ("leapfrog-c3", &[4, 2]),
    ("leapfrog-c5", &[6, 2]),
    ("leapfrog-c7", &[8, 2]),
    ("leapfrog-c11", &[12, 2]),
    ("leapfrog-c17", &[18, 2]),
    ("whckc-c11", &[12, 4, 3]),
    ("whckc-c17", &[18, 4, 3]),
];

/// A corrector of order `n` removes the kernel's `ε` errors up to `εhⁿ`:
/// the effective `p₁` is `n + 1` exactly (the `εh^{n+2}` condition fails),
/// while the kernel alone has order 2 in every part; the `ε²` part is
/// untouched with the leapfrog kernel (`[[A,B],B]`, coefficient 1/24) and of
/// order 4 with WHCKC. Every claim of each file holds (checked as `symlab
/// check` and `butcher!` check them), and every order is exact: each part's
/// first failing condition is found one degree above.
#[test]
fn correctors_give_their_published_effective_orders() {
    use tableau::analysis::check_file_claim;
    use tableau::near_integrable::processed_orders;
    for (id, published) in PROCESSED {
        let file = entry(id);
        let chi = file.corrector_table().expect("a processed method");
        assert_eq!(near_claim(&file).0, published, "{id}");
        let analysis = Analysis::of(&file.table).unwrap();
        for claim in &file.claims {
            check_file_claim(&file, &analysis, claim)
                .unwrap_or_else(|e| panic!("{id}: `{claim}`: {e}"));
        }
        let degrees: Vec<usize> = [published[0] + 1, 5, 5, 5].to_vec();
        let kernel = near_orders(&file.table, &degrees, None).unwrap();
        assert_eq!(kernel.generalised_text(), "(2)", "{id}: the kernel alone");
        let start = Instant::now();
        let report = processed_orders(&file.table, &chi, &degrees, None).unwrap();
        let found: Vec<usize> = report.generalised().iter().map(|g| g.0).collect();
        assert_eq!(found, published, "{id}: {}", report.generalised_text());
        assert!(report.generalised().iter().all(|g| g.1), "{id}: exact");
        let first = report.parts[0].failure.as_ref().unwrap();
        assert_eq!(first.degree, published[0] + 1, "{id}");
        if id.starts_with("leapfrog") {
            let second = report.parts[1].failure.as_ref().unwrap();
            assert_eq!(
                (second.word.as_str(), second.value.clone()),
                ("AB²", Number::ratio(1, 24).unwrap())
            );
        }
        println!(
            "{id}: effective {} in {:?}",
            report.generalised_text(),
            start.elapsed()
        );
    }
}

/// The exact `b`s (`r·sqrt(40/7)`) are REBOUND's 50-digit decimals to
/// within 1e-50, compared exactly; and a corrector whose `b` is REBOUND's
/// decimal cut to 16 digits (what a double holds) keeps its `p₁` only up to
/// a residual, so the exact form is what makes the claim exact.
#[test]
fn exact_corrector_coefficients_are_rebounds_decimals() {
    let cases = [
        (
            "leapfrog-c3",
            "b1",
            "-0.024900596027799867499350357910273437184309981229127",
        ),
        (
            "leapfrog-c5",
            "b2",
            "0.041500993379666445832250596517122395307183302048545",
        ),
        (
            "leapfrog-c7",
            "b1",
            "0.0024926811426922105779030593952776964450539008582219",
        ),
        (
            "leapfrog-c11",
            "b5",
            "0.072593394748842738674253180742744961827622366521517",
        ),
        (
            "leapfrog-c17",
            "b1",
            "-0.0000043347415473373580190650223498124944896789841432241",
        ),
        (
            "leapfrog-c17",
            "b8",
            "0.093056103771425958591541059067553547100903397724386",
        ),
    ];
    let tol = parse_number("1e-50").unwrap();
    for (id, name, decimal) in cases {
        let t = text(id);
        let line = t
            .lines()
            .find(|l| l.starts_with(&format!("let.{name} = ")))
            .unwrap_or_else(|| panic!("{id}: let.{name}"));
        let expr = line.split('"').nth(1).unwrap();
        let exact = parse_number(expr).unwrap();
        let diff = (&exact - &parse_number(decimal).unwrap()).abs();
        assert!(diff < tol, "{id} {name}: {exact} vs {decimal}");
    }
    // Cut to 16 digits, leapfrog-c5's b2 breaks the exact (6, 2) claim at εh³.
    let t = text("leapfrog-c5").replace(
        "let.b2 = \"5/288*sqrt(40/7)\"",
        "let.b2 = \"0.04150099337966645\"",
    );
    let file = parse_table_file("cut.toml", &t).unwrap();
    let analysis = Analysis::of(&file.table).unwrap();
    let claim: Claim = "order = (6, 2)".parse().unwrap();
    let e = tableau::analysis::check_file_claim(&file, &analysis, &claim)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("order = (6, 2) claimed, but the ε part has order 2 < 6: the εh³ condition fails: the coefficient of A²B in log Φ (the leading word of [A,[A,B]])"),
        "{e}"
    );
    assert!(
        e.contains("the effective order of the processed method χ K χ⁻¹"),
        "{e}"
    );
}

/// An over-claim of a processed file is an error naming the failing
/// condition of the effective method; `order_rkn` is refused; a kernel
/// named from the catalogue that is not a sequence, a corrector with one
/// list, a corrector beside a Runge–Kutta table and a named kernel beside
/// an inline one are errors naming the field.
#[test]
fn processed_files_refuse_over_claims_and_bad_shapes() {
    use tableau::analysis::check_file_claim;
    let file = entry("leapfrog-c3");
    let analysis = Analysis::of(&file.table).unwrap();
    let over: Claim = "order = (6, 2)".parse().unwrap();
    let e = check_file_claim(&file, &analysis, &over)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("order = (6, 2) claimed, but the ε part has order 4 < 6: the εh⁵ condition fails: the coefficient of A⁴B in log Φ (the leading word of [A,[A,[A,[A,B]]]]) is"),
        "{e}"
    );
    let classical: Claim = "order = 3".parse().unwrap();
    let e = check_file_claim(&file, &analysis, &classical)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("the ε² part has order 2 < 3: the ε²h³ condition fails"),
        "{e}"
    );
    let rkn: Claim = "order_rkn = 2".parse().unwrap();
    assert!(
        check_file_claim(&file, &analysis, &rkn)
            .unwrap_err()
            .to_string()
            .contains("not decided for a processed method")
    );
    let sym: Claim = "symmetric".parse().unwrap();
    assert!(
        check_file_claim(&file, &analysis, &sym)
            .unwrap_err()
            .to_string()
            .contains("not a palindrome")
    );
    let bad = |body: &str| {
        parse_table_file("bad.toml", &format!("name = \"x\"\n{body}"))
            .unwrap_err()
            .to_string()
    };
    let e = bad("kernel = \"rk4\"\ncorrector_drift = [\"1\"]\ncorrector_kick = []\n");
    assert!(
        e.contains("field kernel") && e.contains("not a drift–kick sequence"),
        "{e}"
    );
    let e = bad("kernel = \"leapfrgo\"\ncorrector_drift = [\"1\"]\ncorrector_kick = []\n");
    assert!(e.contains("field kernel") && e.contains("leapfrog"), "{e}");
    let e = bad("kernel = \"leapfrog\"\n");
    assert!(e.contains("needs a corrector"), "{e}");
    let e = bad("drift = [\"1\"]\nkick = []\ncorrector_drift = [\"1\"]\n");
    assert!(e.contains("field corrector_kick: missing"), "{e}");
    let e = bad("a = [[\"0\"]]\nb = [\"1\"]\ncorrector_drift = [\"1\"]\ncorrector_kick = []\n");
    assert!(
        e.contains("field corrector_drift") && e.contains("not a Runge–Kutta table"),
        "{e}"
    );
    let e = bad(
        "kernel = \"leapfrog\"\ndrift = [\"1\"]\nkick = []\ncorrector_drift = [\"1\"]\ncorrector_kick = []\n",
    );
    assert!(
        e.contains("field drift") && e.contains("names the kernel"),
        "{e}"
    );
    let e = bad("kernel = \"leapfrog-c3\"\ncorrector_drift = [\"1\"]\ncorrector_kick = []\n");
    assert!(e.contains("itself a processed method"), "{e}");
    let e = bad(
        "kernel = \"leapfrog\"\ncorrector_drift = [\"1\", \"2\", \"3\"]\ncorrector_kick = [\"1\"]\n",
    );
    assert!(
        e.contains("field corrector_kick") && e.contains("differ by at most one"),
        "{e}"
    );
}

// ---------------------------------------------------------------------------
// Gradient kicks: WHCKL

/// A drift–kick file with gradient kicks.
fn gradient_file(drift: &str, kick: &str, gradient: &str) -> TableFile {
    parse_table_file(
        "gradient.toml",
        &format!("name = \"g\"\ndrift = {drift}\nkick = {kick}\nkick_gradient = {gradient}\n"),
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// WHCKL (`D(1/2) G(1, 1/24) D(1/2)`) with the corrector of order 17 has
/// the effective generalised order (18, 4), exactly: the εh¹⁹ condition
/// fails, and every εʲ part (j ≥ 2) fails at degree 5, the ε² one on
/// `[A,[A,[[A,B],B]]]` with coefficient −11/5760. Its own ε²h³ term, 1/24 on
/// `AB²` (with the plain kick, 1/12), is cancelled by the corrector: with the
/// same corrector the leapfrog kernel has ε order 2. Every claim of the file
/// holds.
#[test]
fn whckl_has_effective_order_18_4() {
    use tableau::analysis::check_file_claim;
    use tableau::near_integrable::processed_orders;
    let file = entry("whckl-c17");
    let analysis = Analysis::of(&file.table).unwrap();
    for claim in &file.claims {
        check_file_claim(&file, &analysis, claim).unwrap_or_else(|e| panic!("`{claim}`: {e}"));
    }
    assert_eq!(near_claim(&file), (vec![18, 4], None));
    let chi = file.corrector_table().unwrap();
    let r = processed_orders(&file.table, &chi, &[19, 5, 5, 5], None).unwrap();
    assert_eq!(r.generalised_text(), "(18, 4)");
    let orders: Vec<(usize, usize)> = r
        .parts
        .iter()
        .map(|p| (p.order, p.failure.as_ref().map_or(0, |f| f.degree)))
        .collect();
    assert_eq!(orders, [(18, 19), (4, 5), (4, 5), (4, 5)]);
    let f = r.parts[1].failure.as_ref().unwrap();
    assert_eq!(
        (f.word.as_str(), f.lie.as_str()),
        ("A³B²", "[A,[A,[[A,B],B]]]")
    );
    assert_eq!(f.value, parse_number("-11/5760").unwrap());
    // The kernel alone: order 2 in ε and ε², the ε²h³ coefficient 1/24.
    let own = near_orders(&file.table, &[3, 3], None).unwrap();
    let f = own.parts[1].failure.as_ref().unwrap();
    assert_eq!((f.degree, f.word.as_str()), (3, "AB²"));
    assert_eq!(f.value, parse_number("1/24").unwrap());
    // The plain leapfrog kernel with the same corrector: ε² order 2.
    let leapfrog = entry("leapfrog-c17");
    assert_eq!(
        leapfrog.corrector, file.corrector,
        "the same corrector, verbatim"
    );
    let plain = processed_orders(&leapfrog.table, &chi, &[19, 5, 5, 5], None).unwrap();
    assert_eq!(plain.generalised_text(), "(18, 2)");
}

/// The gradient moved from 1/24 to 1/25 loses the claim, naming the ε²h³
/// condition (coefficient 1/24 − 1/25 = 1/600 on `AB²`); over-claims name the
/// first condition past the truth.
#[test]
fn whckl_perturbed_gradient_and_over_claims_fail_naming_the_condition() {
    use tableau::analysis::check_file_claim;
    let text = text("whckl-c17");
    assert!(text.contains("kick_gradient = [\"1/24\"]"));
    let perturbed = parse_table_file(
        "perturbed.toml",
        &text.replace("kick_gradient = [\"1/24\"]", "kick_gradient = [\"1/25\"]"),
    )
    .unwrap();
    let analysis = Analysis::of(&perturbed.table).unwrap();
    let claim: Claim = "order = (18, 4)".parse().unwrap();
    let e = check_file_claim(&perturbed, &analysis, &claim)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("order = (18, 4) claimed, but the ε² part has order 2 < 4: the ε²h³ condition fails: the coefficient of AB² in log Φ (the leading word of [[A,B],B]) is 1/600"),
        "{e}"
    );
    let file = entry("whckl-c17");
    let analysis = Analysis::of(&file.table).unwrap();
    for (claim, phrase) in [
        ("order = (19, 4)", "the εh¹⁹ condition fails"),
        (
            "order = (18, 5)",
            "the ε² part has order 4 < 5: the ε²h⁵ condition fails: the coefficient of A³B² in log Φ (the leading word of [A,[A,[[A,B],B]]]) is -11/5760",
        ),
        ("order = 5", "the ε²h⁵ condition fails"),
        ("order_rkn = 4", "not decided for a processed method"),
    ] {
        let c: Claim = claim.parse().unwrap();
        let e = check_file_claim(&file, &analysis, &c)
            .unwrap_err()
            .to_string();
        assert!(e.contains(phrase), "{claim}: {e}");
    }
}

/// A sequence with gradient kicks has no partitioned form: its analysis
/// never uses one. Symplectic and explicit by construction, symmetric when
/// its flows are a palindrome, its order the classical order on the Lie
/// algebra (failures named by Lie term), `order_rkn` refused.
#[test]
fn gradient_sequences_are_analysed_on_the_lie_algebra() {
    use tableau::analysis::Form;
    use tableau::order::ConditionKind;
    // Strang with g = 1/12: the ε²h³ term vanishes; the εh³ one does not.
    let strang = gradient_file("[\"1/2\", \"1/2\"]", "[\"1\"]", "[\"1/12\"]");
    assert!(strang.table.to_prk().is_none());
    let a = Analysis::of(&strang.table).unwrap();
    assert_eq!(a.form, Form::GradientDriftKick);
    assert_eq!(a.kind(), "gradient-drift-kick");
    assert!(a.symplectic_separable && a.explicit_separable && a.symmetric);
    assert!(a.order.is_none(), "no pair, no order on general systems");
    assert_eq!(a.order_separable.order, 2);
    let f = a.order_separable.first_failure.as_ref().unwrap();
    assert_eq!((f.order, f.kind), (3, ConditionKind::LieTerm));
    assert_eq!(f.tree, "[A,[A,B]] (leading word A²B)");
    assert_eq!(f.residual, parse_number("-1/24").unwrap());
    let r = near_orders(&strang.table, &[4, 4, 4], None).unwrap();
    assert_eq!(r.parts[1].order, 4, "the ε²h³ term vanishes with g = 1/12");
    for (claim, ok) in [
        ("symplectic", true),
        ("explicit", true),
        ("symmetric", true),
        ("order = 2", true),
        ("order = (2, 2)", true),
        ("order = 3", false),
        ("order_rkn = 2", false),
    ] {
        let c: Claim = claim.parse().unwrap();
        let verdict = check_claim(&strang.table, &a, &c);
        assert_eq!(verdict.is_ok(), ok, "{claim}: {verdict:?}");
        if let Err(e) = verdict {
            let e = e.to_string();
            let phrase = if claim.starts_with("order_rkn") {
                "kick_gradient"
            } else {
                "the εh³ condition fails: the coefficient of A²B"
            };
            assert!(e.contains(phrase), "{claim}: {e}");
        }
    }
    // Not a palindrome: the gradients differ.
    let lopsided = gradient_file(
        "[\"1/2\", \"0\", \"1/2\"]",
        "[\"1/2\", \"1/2\"]",
        "[\"0\", \"1/24\"]",
    );
    let a = Analysis::of(&lopsided.table).unwrap();
    assert!(!a.symmetric);
    let e = check_claim(&lopsided.table, &a, &Claim::Symmetric).unwrap_err();
    assert!(e.to_string().contains("not a palindrome"), "{e}");
}

/// A gradient kick is never merged with a neighbouring plain kick (`B` and
/// `[B,[A,B]]` do not commute): `K(1/2) G(1/2, g)` is not `G(1, g)`, and
/// differs from it first at ε³h⁴ (`[B,[B,[A,B]]]`, from `[B/2, g·C]`).
/// Processed sequences keep them apart too, and write the zero drift
/// between them.
#[test]
fn gradient_kicks_are_not_merged() {
    use tableau::near_integrable::{processed_orders, processed_sequence, processed_table};
    let split = gradient_file(
        "[\"1/2\", \"0\", \"1/2\"]",
        "[\"1/2\", \"1/2\"]",
        "[\"0\", \"1/24\"]",
    );
    let whole = gradient_file("[\"1/2\", \"1/2\"]", "[\"1\"]", "[\"1/24\"]");
    let degrees = [4, 4, 4];
    let a = near_orders(&split.table, &degrees, None).unwrap();
    let b = near_orders(&whole.table, &degrees, None).unwrap();
    assert_eq!(b.parts[2].order, 4, "{}", b.generalised_text());
    assert_eq!(a.parts[2].order, 3, "{}", a.generalised_text());
    assert_eq!(a.parts[2].failure.as_ref().unwrap().degree, 4);
    let chi = parse_table_file("chi", "name = \"χ\"\ndrift = [\"1/5\"]\nkick = []\n").unwrap();
    let seq = processed_sequence(&split.table, &chi.table).unwrap();
    let gradients = seq
        .iter()
        .filter(|f| matches!(f, Factor::Gradient { .. }))
        .count();
    let kicks = seq
        .iter()
        .filter(|f| matches!(f, Factor::Letter(1, _)))
        .count();
    assert_eq!((gradients, kicks, seq.len()), (1, 1, 4));
    let Table::Splitting(t) = processed_table(&split.table, &chi.table).unwrap() else {
        unreachable!()
    };
    assert_eq!(t.gradient.len(), t.kick.len());
    assert_eq!(t.drift.len(), 3);
    assert!(t.drift[1].is_zero(), "{t:?}");
    assert_eq!(
        near_orders(&Table::Splitting(t), &degrees, None).unwrap(),
        processed_orders(&split.table, &chi.table, &degrees, None).unwrap()
    );
}

/// A Strang splitting whose kick is the gradient kick
/// `exp(h·εB + g·h³·ε²[B,[A,B]])`: `log Φ = h(A + εB) − (h³/24)ε[A,[A,B]] +
/// (g − 1/12)h³ε²[B,[A,B]] + O(h⁵)`. With `g = 1/12` the `ε²h³` term
/// vanishes and the method is `O(εh² + ε²h⁴)`, generalised order `(2, 4)`,
/// the order of Laskar & Robutel's corrected SABAC₁: an increasing claim,
/// decided exactly, not refused.
fn strang_gradient(g: &str) -> TableFile {
    let text = format!(
        "name = \"Strang with a gradient kick\"\ndrift = [\"1/2\", \"1/2\"]\nkick = [\"1\"]\nkick_gradient = [\"{g}\"]\nclaims = [\"order = (2, 4)\"]\n"
    );
    parse_table_file("strang-gradient.toml", &text).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn increasing_generalised_orders_are_decided() {
    let file = strang_gradient("1/12");
    assert_eq!(
        file.claims,
        [Claim::NearOrder {
            orders: vec![2, 4],
            bound: None
        }]
    );
    let analysis = Analysis::of(&file.table).unwrap();
    check_claim(&file.table, &analysis, &file.claims[0]).unwrap();
    let report = check_near_claim(&file.table, &[2, 4], None).unwrap();
    // ε: degree 2; ε², ε³: degree 4 (claim_degrees extends the last entry).
    assert_eq!(claim_degrees(&[2, 4]), [2, 4, 4]);
    let parts: Vec<(usize, usize)> = report.parts.iter().map(|p| (p.order, p.limit)).collect();
    assert_eq!(parts, [(2, 2), (4, 4), (4, 4)]);
    // Examined further, the orders are exactly (2, 4): the εh³ term is
    // −1/24 [A,[A,B]], and the ε²h⁵ terms do not all vanish.
    let full = near_orders(&file.table, &[6, 6, 6, 6, 6], None).unwrap();
    assert_eq!(full.parts[0].order, 2);
    assert_eq!(full.parts[1].order, 4);
    assert_eq!(full.generalised(), [(2, true), (4, true)]);
    assert_eq!(full.generalised_text(), "(2, 4)");
    let f = full.parts[0].failure.as_ref().unwrap();
    assert_eq!((f.bs, f.degree, f.word.as_str()), (1, 3, "A²B"));
    assert_eq!(f.value, Number::ratio(-1, 24).unwrap());

    // Over-claims are refused, naming the failing term.
    let e = check_near_claim(&file.table, &[2, 6], None).unwrap_err();
    assert!(
        e.contains("order = (2, 6) claimed, but the ε² part has order 4 < 6: the ε²h⁵ condition fails: the coefficient of"),
        "{e}"
    );
    let e = check_near_claim(&file.table, &[3, 4], None).unwrap_err();
    assert!(
        e.contains("the ε part has order 2 < 3: the εh³ condition fails: the coefficient of A²B in log Φ (the leading word of [A,[A,B]]) is -1/24"),
        "{e}"
    );
    // The plain modified kick of Wisdom et al. (g = 1/24) halves the ε²h³
    // term but does not remove it: (2, 4) is false, and the word is named.
    let half = strang_gradient("1/24");
    let a = Analysis::of(&half.table).unwrap();
    let e = check_claim(&half.table, &a, &half.claims[0])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("the ε² part has order 2 < 4: the ε²h³ condition fails: the coefficient of AB² in log Φ (the leading word of [[A,B],B]) is 1/24"),
        "{e}"
    );
    // Through the verdict (what `symlab check` prints).
    let v = tableau::verdict::Verdict::of(
        "strang-gradient.toml",
        &tableau::algebraic::file::Loaded::Classic(Box::new(file)),
        &tableau::verdict::Options::default(),
    )
    .unwrap();
    assert!(v.claims[0].verdict.is_ok(), "{:?}", v.claims);
    let text = v.to_string();
    assert!(text.contains("(2, 4)"), "{text}");
}
