//! Processed kernels (`processed = true`): the effective-order conditions,
//! against published kernels of Blanes, Casas & Murua and against the
//! classical conditions; the recovery of a published kernel from random
//! starts; its processor; and the processed table, decided by `symlab
//! check`'s verifier and refused once a coefficient moves.

use design::solve::Compiled;
use num_rational::BigRational;
use tableau::Table;

use crate::common::{agreement, claims_hold, load, refused_when_moved};

fn words(sys: &design::conditions::System) -> Vec<String> {
    sys.conditions.iter().map(|c| c.word.clone()).collect()
}

fn digits_agreeing(a: &BigRational, printed: &str) -> i64 {
    let b = tableau::expr::parse_number(printed)
        .unwrap()
        .as_rational()
        .unwrap();
    agreement(a, &b)
}

/// A processed table's claims hold; the claim `claim` is refused once any
/// of `moved` moves by 1e-30; and, with `kernel_alone`, refused for the
/// kernel without its processor (the lines `corrector_*` and the `let.` of
/// the processor's unknowns, `processor` their first letters, dropped).
fn processed_table_checks(
    name: &str,
    text: &str,
    claim: &str,
    moved: &[&str],
    processor: &[char],
    kernel_alone: bool,
) {
    for (c, verdict) in claims_hold(name, text) {
        assert!(verdict.is_ok(), "{c}: {verdict:?}\n{text}");
    }
    for m in moved {
        refused_when_moved(name, text, m, "1e-30", claim);
    }
    if !kernel_alone {
        return;
    }
    let kernel_only: String = text
        .lines()
        .filter(|l| {
            !l.starts_with("corrector_")
                && !l
                    .strip_prefix("let.")
                    .is_some_and(|r| r.starts_with(processor))
        })
        .collect::<Vec<_>>()
        .join("\n");
    let verdicts = claims_hold(name, &kernel_only);
    let (_, v) = verdicts.iter().find(|(c, _)| c.contains(claim)).unwrap();
    assert!(v.is_err(), "{claim} holds for the kernel alone");
}

/// Effective order 6 of a symmetric composition is Σγ³ = Σγ⁵ = 0: the
/// weight-5 term [Y₁,[Y₁,Y₃]] is the processor's. Classical order 6 also
/// imposes it.
#[test]
fn effective_order_6_is_two_conditions_where_classical_order_6_is_three() {
    let f = load("bcm-processed6-s11.toml");
    let sys = design::conditions::system(&f, "x").unwrap();
    assert_eq!(sys.names, ["g1", "g5"]);
    assert_eq!(words(&sys), ["Y₃", "Y₅"]);
    assert!(!sys.error_terms.is_empty());
    let mut classical = f.clone();
    classical.processed = false;
    classical.processor_stages = 0;
    // Two unknowns cannot meet the three classical conditions.
    let err = design::conditions::system(&classical, "x").unwrap_err();
    assert!(err.message.contains("Y₁Y₁Y₃"), "{err}");
    // The seven-stage family has room for both.
    let mut seven = load("blanes-processed6-s7.toml");
    let eff = design::conditions::system(&seven, "x").unwrap();
    seven.processed = false;
    seven.processor_stages = 0;
    let cl = design::conditions::system(&seven, "x").unwrap();
    assert_eq!(words(&eff), ["Y₃", "Y₅"]);
    assert_eq!(words(&cl), ["Y₃", "Y₁Y₁Y₃", "Y₅"]);
}

/// Classical order implies effective order: Yoshida's seven-stage
/// composition of order 6 meets the effective conditions of its family.
#[test]
fn a_classical_order_6_composition_meets_the_effective_conditions() {
    let f = load("blanes-processed6-s7.toml");
    let sys = design::conditions::system(&f, "x").unwrap();
    let y = tableau::catalogue::load("yoshida6").unwrap();
    let Table::Composition(c) = &y.table else {
        panic!()
    };
    let x: Vec<f64> = c.gamma[..3].iter().map(|g| g.to_f64()).collect();
    let compiled = Compiled::new(&sys);
    assert!(compiled.residual(&x) < 1e-13, "{:e}", compiled.residual(&x));
}

/// The published kernels of Blanes, Casas & Murua (2006) and Blanes (2001)
/// meet the designer's effective conditions to their printed digits, the
/// order-8 one included: four conditions (Σγ³, Σγ⁵, Σγ⁷ and a weight-7 term
/// outside the image of ad Y₁), where classical order 8 needs eight. That
/// fourth condition is the elimination's, not a power sum, so this checks
/// the elimination on an independent published result. (The coefficients
/// as printed in S. Blanes, F. Casas & A. Murua, *Splitting methods for
/// differential equations*, arXiv:2401.01722, Table 8.1.)
#[test]
fn published_processed_kernels_meet_the_effective_conditions() {
    let cases: [(&str, Vec<f64>, usize); 3] = [
        (
            "bcm-processed8-s13.toml",
            vec![
                0.585550530805562,
                -0.460090457516872,
                0.172863148729731,
                0.179664539695039,
            ],
            4,
        ),
        (
            "bcm-processed6-s13.toml",
            vec![0.125696288720106, 0.148070660114965, -0.350856370823828],
            2,
        ),
        (
            "blanes-processed6-s7.toml",
            vec![0.513910778424374, 0.364193022833858, -0.867423280969274],
            2,
        ),
    ];
    for (file, x, n) in cases {
        let sys = design::conditions::system(&load(file), "x").unwrap();
        assert_eq!(sys.conditions.len(), n, "{file}");
        let c = Compiled::new(&sys);
        assert!(c.residual(&x) < 1e-15, "{file}: {:e}", c.residual(&x));
        // And they are not of classical order 6 (or 8): processing matters.
        let mut classical = load(file);
        classical.processed = false;
        classical.processor_stages = 0;
        if let Ok(cl) = design::conditions::system(&classical, "x") {
            let cc = Compiled::new(&cl);
            assert!(
                cc.residual(&x) > 1e-10,
                "{file}: classical {:e}",
                cc.residual(&x)
            );
        }
    }
    let sys = design::conditions::system(&load("bcm-processed8-s13.toml"), "x").unwrap();
    assert_eq!(words(&sys), ["Y₃", "Y₅", "Y₁Y₃Y₃", "Y₇"]);
}

/// Blanes, Casas & Murua's eleven-stage kernel of effective order 6 from
/// random starts: the only real solution found, to every printed digit
/// (19 and 18 decimals), certified; its processor found; the processed
/// table's claim `order = 6 (residual < 1e-40)` decided by `symlab
/// check`'s verifier, and refused once the kernel or the processor moves by
/// 1e-30. Prints the report (`-- --nocapture`).
#[test]
fn bcm_eleven_stage_kernel_recovered_with_a_processor_and_checked() {
    let f = load("bcm-processed6-s11.toml");
    let out = design::design(&f, "designs/bcm-processed6-s11.toml", &mut |_| {}).unwrap();
    println!("{}", out.report());
    let best = &out.designs[0];
    let p = best.polished.as_ref().unwrap();
    assert!(digits_agreeing(&p.x[0], "0.1705768865009222157") >= 19);
    assert!(digits_agreeing(&p.x[1], "-0.423366140892658048") >= 18);
    assert!(matches!(best.certificate, Some(Ok(_))));
    let processor = best.processor.as_ref().unwrap().as_ref().unwrap();
    assert_eq!(processor.claims, ["order = 6 (residual < 1e-40)"]);
    let (name, text) = best.table.as_ref().unwrap();
    // Without its processor the kernel is of order 4 only (Σγ³ = 0 is an
    // effective condition too): its order-6 claim is refused.
    processed_table_checks(name, text, "order = 6", &["g1", "z1"], &['z'], true);
}

/// Drift–kick kernels: effective order 6 of a symmetric ABA sequence is
/// four conditions, the parts of weights 3 and 5 outside the image of
/// ad(A + B) (1 of 2, 3 of 6), where classical order 6 is eight; so five
/// kicks (four unknowns) give a square system, which classical order 6
/// cannot meet.
#[test]
fn effective_order_6_of_a_drift_kick_kernel_is_four_conditions_where_classical_is_eight() {
    let f = load("processed-aba5-order6.toml");
    let sys = design::conditions::system(&f, "x").unwrap();
    assert_eq!(sys.names, ["a1", "a2", "b1", "b2"]);
    assert_eq!(words(&sys), ["ABB", "AABAB", "ABABB", "ABBBB"]);
    let mut classical = f.clone();
    classical.processed = false;
    classical.processor_stages = 0;
    classical.stages = 9;
    let cl = design::conditions::system(&classical, "x").unwrap();
    assert_eq!(cl.conditions.len(), 8);
    let f4 = load("processed-aba3-order4.toml");
    assert_eq!(
        words(&design::conditions::system(&f4, "x").unwrap()),
        ["ABB"]
    );
}

/// Classical order implies effective order, in the letters A and B too:
/// Yoshida's order-6 composition written as a drift–kick sequence (seven
/// kicks) meets the drift–kick effective conditions of order 6, a check of
/// the elimination with ad(A + B) against an independent published
/// method; a point off it does not.
#[test]
fn yoshida6_as_a_drift_kick_sequence_meets_the_effective_conditions() {
    let text = "name = \"x\"\nform = \"ABA\"\nstages = 7\norder = 6\nprocessed = true\nprocessor_stages = 8\n";
    let f = design::parse_family("x.toml", text).unwrap();
    let sys = design::conditions::system(&f, "x").unwrap();
    assert_eq!(sys.conditions.len(), 4);
    let y = tableau::catalogue::load("yoshida6").unwrap();
    let Table::Composition(c) = &y.table else {
        panic!()
    };
    let g: Vec<f64> = c.gamma.iter().map(|g| g.to_f64()).collect();
    let value = |name: &str| -> f64 {
        match name {
            "a1" => g[0] / 2.0,
            "a2" => (g[0] + g[1]) / 2.0,
            "a3" => (g[1] + g[2]) / 2.0,
            "b1" => g[0],
            "b2" => g[1],
            "b3" => g[2],
            other => panic!("unknown {other}"),
        }
    };
    let x: Vec<f64> = sys.names.iter().map(|n| value(n)).collect();
    let compiled = Compiled::new(&sys);
    assert!(compiled.residual(&x) < 1e-13, "{:e}", compiled.residual(&x));
    let mut off = x.clone();
    off[0] += 1e-3;
    assert!(
        compiled.residual(&off) > 1e-6,
        "{:e}",
        compiled.residual(&off)
    );
}

/// A processed drift–kick kernel designed from random starts and proven:
/// three kicks, effective order 4 (one condition, one unknown free), its
/// kernel certified, a drift–kick processor found, and the processed
/// table's `order = 4 (residual < 1e-40)` decided by `symlab check`'s
/// verifier on χ K χ⁻¹; refused once the kernel or the processor moves by
/// 1e-30, and refused for the kernel alone (classical order 2).
#[test]
fn a_processed_drift_kick_kernel_of_effective_order_4_is_designed_and_checked() {
    let f = load("processed-aba3-order4.toml");
    let out = design::design(&f, "designs/processed-aba3-order4.toml", &mut |_| {}).unwrap();
    println!("{}", out.report());
    let best = &out.designs[0];
    assert!(matches!(best.certificate, Some(Ok(_))));
    let processor = best.processor.as_ref().unwrap().as_ref().unwrap();
    assert_eq!(processor.claims, ["order = 4 (residual < 1e-40)"]);
    assert_eq!(processor.system.names, ["u1", "u2", "v1", "v2"]);
    let (name, text) = best.table.as_ref().unwrap();
    assert!(text.contains("\ndrift = [") && text.contains("\ncorrector_kick = ["));
    processed_table_checks(
        name,
        text,
        "order = 4",
        &["a1", "u1", "v2"],
        &['u', 'v'],
        true,
    );
}

/// The shipped effective-order-6 drift–kick family: its best kernel
/// certified, a processor with twelve conditions found, and the processed
/// table's `order = 6` claim decided by the verifier and refused when a
/// coefficient moves.
#[test]
fn a_processed_drift_kick_kernel_of_effective_order_6_is_designed_and_checked() {
    let f = load("processed-aba5-order6.toml");
    let out = design::design(&f, "designs/processed-aba5-order6.toml", &mut |_| {}).unwrap();
    let best = &out.designs[0];
    assert!(matches!(best.certificate, Some(Ok(_))));
    let processor = best.processor.as_ref().unwrap().as_ref().unwrap();
    assert_eq!(processor.system.conditions.len(), 12);
    assert_eq!(processor.claims, ["order = 6 (residual < 1e-40)"]);
    let (name, text) = best.table.as_ref().unwrap();
    processed_table_checks(name, text, "order = 6", &["b2", "u7"], &['u', 'v'], false);
}

/// A processed near-integrable kernel: effective generalised order (8, 4)
/// of a three-kick ABA sequence. Every εhⁿ term is the processor's, so the
/// kernel's one condition is its ε²h³ term (ABB); the processor matches
/// the conjugator on AB, AAB, …, A⁶B and ABB; and the processed table's
/// claim `order = (8, 4) (residual < 1e-40)` is decided by `symlab
/// check`'s verifier on χ K χ⁻¹ (independent code: tableau's
/// near-integrable coefficients of the whole effective sequence), refused
/// once the kernel or the processor moves by 1e-30, and refused for the
/// kernel alone, whose εh³ term is not zero.
#[test]
fn a_processed_near_integrable_kernel_of_effective_order_8_4_is_designed_and_checked() {
    let f = load("processed-near-aba3-8-4.toml");
    let sys = design::conditions::system(&f, "x").unwrap();
    assert_eq!(sys.names, ["a1", "b1"]);
    assert_eq!(words(&sys), ["ABB"]);
    let out = design::design(&f, "designs/processed-near-aba3-8-4.toml", &mut |_| {}).unwrap();
    println!("{}", out.report());
    let best = &out.designs[0];
    assert!(matches!(best.certificate, Some(Ok(_))));
    let processor = best.processor.as_ref().unwrap().as_ref().unwrap();
    let pwords: Vec<String> = processor
        .system
        .conditions
        .iter()
        .map(|c| c.word.clone())
        .collect();
    assert_eq!(
        pwords,
        ["AB", "AAB", "ABB", "AAAB", "AAAAB", "AAAAAB", "AAAAAAB"]
    );
    assert_eq!(processor.claims, ["order = (8, 4) (residual < 1e-40)"]);
    let (name, text) = best.table.as_ref().unwrap();
    processed_table_checks(
        name,
        text,
        "order = (8, 4)",
        &["a1", "u3", "v5"],
        &['u', 'v'],
        true,
    );
}

/// The ε² conditions of a processed near-integrable kernel: with every
/// odd-weight coordinate its own unknown, effective order (6, 6) imposes
/// nothing on the terms with one B (the processor's), one ε²h³ (ABB) and
/// one ε²h⁵ term (of AAABB, AABAB, the processor taking one), one ε³h⁵
/// (of AABBB, ABABB, taking one) and ε⁴h⁵ (ABBBB, nothing to take it from:
/// BBBB is no Lyndon word); effective (6, 2)
/// imposes nothing at all (the processed leapfrog of Wisdom, Holman &
/// Touma).
#[test]
fn near_integrable_effective_conditions_start_at_eps_squared() {
    use design::effective::Reach;
    let (six6, six2) = (Reach::new(&[6, 6]), Reach::new(&[6, 2]));
    for (reach, want) in [(six6, vec![(3, "ABB")]), (six2, vec![])] {
        let sys_text = format!(
            "name = \"x\"\nform = \"ABA\"\nstages = 6\norder = {}\nprocessed = true\nprocessor_stages = 8\n",
            reach.text().replace('(', "[").replace(')', "]")
        );
        let f = design::parse_family("x.toml", &sys_text).unwrap();
        let sys = design::conditions::system(&f, "x").unwrap();
        let w3: Vec<(usize, String)> = sys
            .conditions
            .iter()
            .filter(|c| c.degree == 3)
            .map(|c| (c.degree, c.word.clone()))
            .collect();
        let want: Vec<(usize, String)> = want.iter().map(|(d, w)| (*d, w.to_string())).collect();
        assert_eq!(w3, want, "{}", reach.text());
        assert!(
            sys.conditions
                .iter()
                .all(|c| c.word.matches('B').count() >= 2)
        );
    }
    let f = design::parse_family(
        "x.toml",
        "name = \"x\"\nform = \"ABA\"\nstages = 6\norder = [6, 6]\nprocessed = true\nprocessor_stages = 8\n",
    )
    .unwrap();
    let sys = design::conditions::system(&f, "x").unwrap();
    let at = |d: usize, b: usize| {
        sys.conditions
            .iter()
            .filter(|c| c.degree == d && c.word.matches('B').count() == b)
            .count()
    };
    assert_eq!((at(3, 2), at(5, 2), at(5, 3), at(5, 4)), (1, 1, 1, 1));
}

/// Hostile family files: each error names the field.
#[test]
fn processed_family_errors_name_the_field() {
    let base = "name = \"x\"\nform = \"composition\"\nstages = 7\norder = 6\n";
    let cases = [
        (
            "processed = true\nprocessor_stages = 10\nform2 = 1\n",
            "form2",
        ),
        ("processed = true\n", "processor_stages"),
        (
            "processed = true\nprocessor_stages = 9\n",
            "processor_stages",
        ),
        ("processor_stages = 10\n", "processor_stages"),
        ("processed = \"yes\"\n", "processed"),
        (
            "processed = true\nprocessor_stages = 10\nobjective = \"stability\"\n",
            "objective",
        ),
    ];
    for (extra, field) in cases {
        let text = format!("{base}{extra}");
        let err = design::parse_family("f.toml", &text)
            .and_then(|f| f.validate("f.toml").map(|_| f))
            .unwrap_err();
        assert_eq!(err.field.as_deref(), Some(field), "{text}: {err}");
    }
    // Drift–kick kernels: classical effective orders only, not RKN, and a
    // processor of at least two kicks.
    let aba = "name = \"x\"\nform = \"ABA\"\nstages = 4\nprocessed = true\n";
    for (extra, field) in [
        (
            "order = 4\nprocessor_stages = 4\nrkn = true\nerror_basis = \"brackets\"\n",
            "rkn",
        ),
        ("order = [4, 6]\nprocessor_stages = 4\n", "order"),
        ("order = 4\nprocessor_stages = 1\n", "processor_stages"),
        ("order = 4\nprocessor_stages = 99\n", "processor_stages"),
    ] {
        let text = format!("{aba}{extra}");
        let err = design::parse_family("f.toml", &text)
            .and_then(|f| f.validate("f.toml").map(|_| f))
            .unwrap_err();
        assert_eq!(err.field.as_deref(), Some(field), "{text}: {err}");
    }
    // Too small a processor is refused with the conditions it must meet.
    let mut f = load("bcm-processed6-s11.toml");
    f.processor_stages = 2;
    let out = design::design(&f, "x", &mut |_| {}).unwrap();
    let why = out.designs[0]
        .processor
        .as_ref()
        .unwrap()
        .as_ref()
        .unwrap_err();
    assert!(
        why.contains("processor_stages") || why.contains("conditions"),
        "{why}"
    );
}
