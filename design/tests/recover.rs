//! From random starts, without being given the answer, the designer
//! recovers published methods; their coefficients are compared digit by
//! digit with the literature's (as the catalogue holds them, with its
//! sources), and every emitted table passes `symlab check`'s verifier.

use design::design;
use num_rational::BigRational;
use tableau::{Number, Table};

use crate::common::{self, agreement, claims_hold, load, refused_when_moved};

fn assert_claims_hold(origin: &str, text: &str) {
    for (claim, verdict) in claims_hold(origin, text) {
        assert!(verdict.is_ok(), "{origin}: {claim}: {verdict:?}\n{text}");
    }
}

fn exact_number(text: &str) -> Number {
    tableau::expr::parse_number(text).unwrap()
}

#[test]
fn yoshida_triple_jump_exactly() {
    let family = load("yoshida4.toml");
    let out = design(&family, "designs/yoshida4.toml", &mut |_| {}).unwrap();
    assert_eq!(out.search.solutions.len(), 1, "the cubic has one real root");
    let best = &out.designs[0];
    let exact = best.exact.as_ref().expect("one polynomial in one unknown");
    let radicals = exact
        .radicals
        .as_ref()
        .expect("Cardano's radicands are rational");
    // The catalogue's x = 1/(2 − ∛2), decided equal in tableau's field.
    let y = tableau::catalogue::load("yoshida4").unwrap();
    let Table::Composition(c) = &y.table else {
        panic!()
    };
    assert!(
        (&exact_number(radicals) - &c.gamma[0]).is_zero(),
        "{radicals}"
    );
    assert!(
        exact.root.starts_with("root(x^3 - 2*x^2 + x - 1/6, "),
        "{}",
        exact.root
    );
    let (name, text) = best.table.as_ref().unwrap();
    assert!(text.contains("\"order = 4\""), "an exact claim, no bound");
    assert_claims_hold(name, text);
}

#[test]
fn suzuki_five_stage_exactly() {
    let family = load("suzuki4.toml");
    let out = design(&family, "designs/suzuki4.toml", &mut |_| {}).unwrap();
    let best = &out.designs[0];
    let radicals = best.exact.as_ref().unwrap().radicals.as_ref().unwrap();
    assert!((&exact_number(radicals) - &exact_number("1/(4 - cbrt(4))")).is_zero());
    let (name, text) = best.table.as_ref().unwrap();
    assert_claims_hold(name, text);
}

#[test]
fn mclachlan_sb3a_to_the_published_digits_and_certified() {
    let family = load("mclachlan-sb3a.toml");
    let out = design(&family, "designs/mclachlan-sb3a.toml", &mut |_| {}).unwrap();
    let published = tableau::catalogue::load("mclachlan4").unwrap();
    let Table::Splitting(s) = &published.table else {
        panic!()
    };
    let a1 = s.drift[0].as_rational().unwrap();
    let a2 = s.drift[1].as_rational().unwrap();
    // The solution the paper printed is among those found, and the best by
    // the effective error; it agrees in all 20 printed digits (the printed
    // decimals are within 5e-21 of the exact values).
    let best = &out.designs[0];
    let p = best.polished.as_ref().unwrap();
    assert_eq!(out.system.names, ["a1", "a2"]);
    assert!(agreement(&p.x[0], &a1) >= 20, "a1 {}", p.x[0]);
    assert!(agreement(&p.x[1], &a2) >= 19, "a2 {}", p.x[1]);
    let cert = best.certificate.as_ref().unwrap().as_ref().unwrap();
    assert!(cert.radius <= BigRational::new(1.into(), num_bigint::BigInt::from(10).pow(40)));
    let (name, text) = best.table.as_ref().unwrap();
    assert_claims_hold(name, text);
}

#[test]
fn bab6_order4_beats_blanes_moan_s6_in_its_own_measure() {
    let mut family = load("bab6-order4.toml");
    family.starts = 300;
    let out = design(&family, "designs/bab6-order4.toml", &mut |_| {}).unwrap();
    // Blanes–Moan's S6 (15 printed digits) satisfies the conditions to its
    // digits, and the search's best is at least as good by this objective
    // (the Lyndon coefficients of degree 5; S6 is no minimum of this or of
    // any other measure here: `blanes_moan_s6_is_stationary_for_no_measure_here`).
    let bm = tableau::catalogue::load("blanes-moan-prk6").unwrap();
    let Table::Splitting(s) = &bm.table else {
        panic!()
    };
    let f = |n: &Number| n.to_f64();
    let x = [
        f(&s.drift[1]),
        f(&s.drift[2]),
        f(&s.kick[0]),
        f(&s.kick[1]),
        f(&s.kick[2]),
    ];
    assert_eq!(out.system.names, ["a1", "a2", "b1", "b2", "b3"]);
    let c = design::solve::Compiled::new(&out.system);
    assert!(c.residual(&x) < 1e-14);
    let theirs = c.objective(&x);
    let ours = out.search.solutions[0].objective;
    assert!(ours <= theirs, "ours {ours:e} theirs {theirs:e}");
    for d in out.designs.iter().take(3) {
        let (name, text) = d.table.as_ref().unwrap();
        assert_claims_hold(name, text);
    }
}

#[test]
fn forest_ruth_from_random_starts() {
    let family = design::Family::new("ABA 3", design::Form::Aba, 3, 4);
    let out = design(&family, "(test)", &mut |_| {}).unwrap();
    let fr = tableau::catalogue::load("forest-ruth").unwrap();
    let Table::Splitting(s) = &fr.table else {
        panic!()
    };
    let (a1, b1) = (s.drift[0].to_f64(), s.kick[0].to_f64());
    assert!(
        out.search
            .solutions
            .iter()
            .any(|sol| (sol.x[0] - a1).abs() < 1e-12 && (sol.x[1] - b1).abs() < 1e-12),
        "{:?}",
        out.search.solutions
    );
}

#[test]
fn a_seed_gives_the_same_solutions() {
    let mut family = load("composition5-order4.toml");
    family.starts = 40;
    let mut calls = 0;
    let a = design(&family, "x", &mut |_| calls += 1).unwrap();
    let b = design(&family, "x", &mut |_| {}).unwrap();
    assert_eq!(calls, 40);
    assert_eq!(a.search.solutions, b.search.solutions);
    family.seed = 2;
    let c = design(&family, "x", &mut |_| {}).unwrap();
    // Another seed, other starts: the same minimum, reached from elsewhere.
    assert!((a.search.solutions[0].x[0] - c.search.solutions[0].x[0]).abs() < 1e-6);
}

/// SABA₂ from random starts, generalised order (4, 2): one unknown, one
/// quadratic condition, so the designer finds the Gauss–Legendre node
/// 1/2 − √3/6 exactly (decided equal in tableau's field), and the emitted
/// table's `order = (4, 2)` is proven exactly by `symlab check`.
#[test]
fn saba2_gauss_nodes_exactly() {
    let family = load("saba2.toml");
    assert_eq!(family.generalised, [4, 2]);
    let out = design(&family, "designs/saba2.toml", &mut |_| {}).unwrap();
    assert_eq!(out.system.names, ["a1"]);
    assert_eq!(out.system.conditions.len(), 1);
    assert_eq!(out.system.conditions[0].word, "AAB");
    let node = exact_number("1/2 - sqrt(3)/6");
    let found = out
        .designs
        .iter()
        .find(|d| {
            d.exact
                .as_ref()
                .and_then(|e| e.radicals.as_ref())
                .is_some_and(|r| (&exact_number(r) - &node).is_zero())
        })
        .expect("the Gauss node 1/2 − √3/6 among the exact solutions");
    let (name, text) = found.table.as_ref().unwrap();
    assert!(text.contains("\"order = (4, 2)\""), "{text}");
    assert_claims_hold(name, text);
    // The catalogue's SABA₂ has the same drifts, exactly.
    let saba2 = tableau::catalogue::load("saba2").unwrap();
    let Table::Splitting(s) = &saba2.table else {
        panic!()
    };
    assert!((&s.drift[0] - &node).is_zero());
}

/// SABA₃, generalised order (6, 2): two unknowns (a1, b1) and two
/// conditions; among the solutions is the 3-point Gauss–Legendre rule
/// (a1 = 1/2 − √15/10, b1 = 5/18), printed to 50 digits and certified:
/// `symlab check` re-proves `order = (6, 2) (certified)`.
#[test]
fn saba3_gauss_nodes_certified() {
    let family = load("saba3.toml");
    let out = design(&family, "designs/saba3.toml", &mut |_| {}).unwrap();
    assert_eq!(out.system.names, ["a1", "b1"]);
    let node = 0.5 - 15f64.sqrt() / 10.0;
    let gauss = out
        .designs
        .iter()
        .find(|d| {
            d.polished.as_ref().is_ok_and(|p| {
                (design::poly::to_f64(&p.x[0]) - node).abs() < 1e-12
                    && (design::poly::to_f64(&p.x[1]) - 5.0 / 18.0).abs() < 1e-12
            })
        })
        .expect("the Gauss–Legendre solution among those found");
    let p = gauss.polished.as_ref().unwrap();
    // 50 printed digits of b1 = 5/18 and a1 = 1/2 − √15/10.
    assert!(agreement(&p.x[1], &common::q(5, 18)) >= 49, "b1 {}", p.x[1]);
    let cert = gauss.certificate.as_ref().unwrap().as_ref().unwrap();
    assert!(cert.radius <= BigRational::new(1.into(), num_bigint::BigInt::from(10).pow(40)));
    let (name, text) = gauss.table.as_ref().unwrap();
    assert!(text.contains("\"order = (6, 2) (certified)\""), "{text}");
    assert_claims_hold(name, text);
}

/// The coefficients of a six-stage BAB table of the catalogue in the
/// family's unknowns `a1, a2, b1, b2, b3` (the catalogue writes a leading
/// zero drift), as the printed decimals.
fn bab6_unknowns(id: &str) -> ([f64; 5], [BigRational; 5]) {
    let t = tableau::catalogue::load(id).unwrap();
    let Table::Splitting(s) = &t.table else {
        panic!()
    };
    let q = [
        s.drift[1].as_rational().unwrap(),
        s.drift[2].as_rational().unwrap(),
        s.kick[0].as_rational().unwrap(),
        s.kick[1].as_rational().unwrap(),
        s.kick[2].as_rational().unwrap(),
    ];
    (q.clone().map(|r| design::poly::to_f64(&r)), q)
}

/// Blanes–Moan's SRKN₆ᵇ from random starts: the RKN family (`rkn = true`:
/// the error measured modulo `[B,[B,[B,A]]] = 0`, in the Lyndon basis) has
/// as its best solution the paper's method, to the paper's optimisation
/// accuracy: their printed point is nearly stationary for this objective
/// (the S6 of the same paper is not, for any of the objectives here: see
/// `blanes_moan_s6_is_stationary_for_no_measure_here`), and the found one is
/// closer to stationary and no worse. Prints the table the guide quotes
/// (`-- --nocapture`).
#[test]
fn blanes_moan_srkn6b_recovered() {
    let family = load("srkn6-order4.toml");
    assert!(family.rkn);
    let out = design(&family, "designs/srkn6-order4.toml", &mut |_| {}).unwrap();
    assert_eq!(out.system.names, ["a1", "a2", "b1", "b2", "b3"]);
    assert_eq!(
        out.system.error_terms.len(),
        4,
        "six degree-5 terms less the ideal's two"
    );
    let c = design::solve::Compiled::new(&out.system);
    let (theirs, theirs_q) = bab6_unknowns("blanes-moan-srkn6b");
    assert!(c.residual(&theirs) < 1e-14);
    let best = &out.designs[0];
    let p = best.polished.as_ref().unwrap();
    let ours: Vec<f64> = p.x.iter().map(design::poly::to_f64).collect();
    let ef = |x: &[f64]| design::solve::effective_error(6, 4, c.objective(x));
    println!("| coefficient | found (seed 1) | Blanes–Moan SRKN6b | digits agreeing |");
    let mut worst = i64::MAX;
    for (i, name) in out.system.names.iter().enumerate() {
        let d = agreement(&p.x[i], &theirs_q[i]);
        worst = worst.min(d);
        println!(
            "| {name} | {} | {} | {d} |",
            design::polish::decimal_text(&p.x[i], 16),
            design::polish::decimal_text(&theirs_q[i], 16)
        );
    }
    let (s_ours, s_theirs) = (c.stationarity(&ours), c.stationarity(&theirs));
    println!(
        "E_f found {:.10} / published {:.10}; stationarity found {s_ours:.1e} / published {s_theirs:.1e}",
        ef(&ours),
        ef(&theirs)
    );
    assert!(
        worst >= 5,
        "every coefficient agrees in at least 5 decimals"
    );
    assert!(ef(&ours) <= ef(&theirs));
    assert!(
        s_theirs < 1e-3,
        "the paper's point is nearly stationary: {s_theirs:e}"
    );
    assert!(s_ours < s_theirs);
    let (name, text) = best.table.as_ref().unwrap();
    assert!(text.contains("\"order = 4 (certified)\""), "{text}");
    assert_claims_hold(name, text);
}

/// Blanes–Moan's S6 (15 printed digits) is not a stationary point of any
/// error measure the designer has, so no search for a minimum recovers it:
/// the part of the gradient tangent to the conditions (relative to the
/// whole) is above 0.05, against 5.3·10⁻⁵ at SRKN₆ᵇ's printed digits in its
/// own measure. The measures: the Lyndon-word coefficients and the Lyndon
/// basis, with or without the RKN quotient, and each with the letters'
/// roles exchanged (the same sequence read as an ABA table whose drifts are
/// S6's kicks; the Lyndon basis in the exchanged letters is, up to signs,
/// the classical Hall basis `[A,[A,[A,[A,B]]]]`, `[B,[A,[A,[A,B]]]]`,
/// `[B,[B,[A,[A,B]]]]`, `[B,[B,[B,[A,B]]]]`, `[[A,B],[A,[A,B]]]`,
/// `[[A,B],[B,[A,B]]]` in the original ones). The paper's criterion for S6
/// is not one of these. Prints the figures the guide quotes
/// (`-- --nocapture`).
#[test]
fn blanes_moan_s6_is_stationary_for_no_measure_here() {
    let (s6, _) = bab6_unknowns("blanes-moan-prk6");
    let [a1, a2, b1, b2, b3] = s6;
    for exchanged in [false, true] {
        for (rkn, basis) in [
            (false, design::ErrorBasis::Words),
            (false, design::ErrorBasis::Brackets),
            (true, design::ErrorBasis::Brackets),
        ] {
            let mut f = if exchanged {
                design::Family::new("S6, letters exchanged", design::Form::Aba, 6, 4)
            } else {
                load("bab6-order4.toml")
            };
            f.rkn = rkn;
            f.error_basis = basis;
            let sys = design::conditions::system(&f, "x").unwrap();
            let names: [&str; 5] = if exchanged {
                ["a1", "a2", "a3", "b1", "b2"]
            } else {
                ["a1", "a2", "b1", "b2", "b3"]
            };
            assert_eq!(sys.names, names);
            // The exchanged reading: drifts b1 b2 b3 b4 b3 b2 b1, kicks
            // a1 a2 a3 a3 a2 a1 (a4 and b3 of the ABA family are the middle
            // ones consistency determines).
            let x = if exchanged {
                [b1, b2, b3, a1, a2]
            } else {
                [a1, a2, b1, b2, b3]
            };
            let cs = design::solve::Compiled::new(&sys);
            assert!(cs.residual(&x) < 1e-14, "{:e}", cs.residual(&x));
            let st = cs.stationarity(&x);
            println!(
                "S6 stationarity, letters exchanged {exchanged}, rkn {rkn}, {basis:?}: {st:.3}"
            );
            assert!(st > 5e-2, "{exchanged} {rkn} {basis:?}: {st:e}");
        }
    }
}

/// A near-integrable method of generalised order (10, 4), from random
/// starts, certified and re-proven by `symlab check`'s verifier; and the
/// catalogue's ABA(10,4) of Blanes et al. (2013) solves the same conditions
/// (its 40 printed digits) in the family's unknowns. Prints the objective of
/// both (`-- --nocapture`); the guide's figures come from the shipped
/// family's 20000 starts (`symlab design designs/aba-10-4.toml`).
/// Blanes et al.'s ABA(8,6,4), a near-integrable method of generalised
/// order (8, 6, 4) and so of order (8, 4): six conditions on six unknowns,
/// a square system whose solutions are isolated. From 2000 random starts
/// (seed 1, about 2 s in release) the search finds 13, and the best by the
/// objective is the published method, to every one of its printed digits
/// (REBOUND's 40, `tableau/catalogue/aba-8-6-4.toml`).
#[test]
fn blanes_aba_8_6_4_recovered_to_the_printed_digits() {
    let family = load("aba-8-6-4.toml");
    assert_eq!(family.generalised, [8, 6, 4]);
    let out = design(&family, "designs/aba-8-6-4.toml", &mut |_| {}).unwrap();
    assert_eq!(out.system.names, ["a1", "a2", "a3", "b1", "b2", "b3"]);
    assert_eq!(out.system.conditions.len(), 6, "a square system");
    let t = tableau::catalogue::load("aba-8-6-4").unwrap();
    let Table::Splitting(s) = &t.table else {
        panic!()
    };
    let published: Vec<BigRational> = [&s.drift[0], &s.drift[1], &s.drift[2]]
        .into_iter()
        .chain([&s.kick[0], &s.kick[1], &s.kick[2]])
        .map(|n| n.as_rational().unwrap())
        .collect();
    let best = &out.designs[0];
    let p = best.polished.as_ref().unwrap();
    let digits: Vec<i64> =
        p.x.iter()
            .zip(&published)
            .map(|(x, y)| agreement(x, y))
            .collect();
    // The printed values are 40-digit decimals (39 after the leading zero
    // of c1 … d1): each agrees with the found, polished value to within
    // its last printed digit.
    assert!(
        digits.iter().all(|&d| d >= 38),
        "agreement in digits {digits:?}"
    );
    let c = design::solve::Compiled::new(&out.system);
    let theirs: Vec<f64> = published
        .iter()
        .map(|r| Number::from_rational(r.clone()).to_f64())
        .collect();
    assert!(c.residual(&theirs) < 1e-15);
    let (ours, theirs_objective) = (best.solution.objective, c.objective(&theirs));
    println!(
        "ABA(8,6,4): {} distinct solutions; the best agrees with the published in {digits:?} digits; objective Σe² found {ours:e}, published {theirs_objective:e}",
        out.search.solutions.len()
    );
    // The same point: the objectives agree to the f64 evaluation's accuracy
    // (Σe² ≈ 6.3e-8 from terms e ≈ 2.5e-4 of unit slope at points 1e-16
    // apart: about 1e-11 relative; measured 9e-12).
    assert!(((ours - theirs_objective) / ours).abs() < 1e-9);
    // The others are other methods, each worse by the objective.
    assert!(out.designs.len() > 1);
    for d in &out.designs[1..] {
        assert!(d.solution.objective > ours);
    }
    let cert = best.certificate.as_ref().unwrap().as_ref().unwrap();
    assert!(cert.radius <= BigRational::new(1.into(), num_bigint::BigInt::from(10).pow(40)));
    let (name, text) = best.table.as_ref().unwrap();
    assert!(text.contains("\"order = (8, 6, 4) (certified)\""), "{text}");
    assert_claims_hold(name, text);
    // Beyond the radius (1e-46) the claim is refused: b1 moved by 1e-44.
    refused_when_moved(name, text, "b1", "1e-44", "(8, 6, 4) (certified)");
}

/// A seven-kick ABA table of the catalogue as the designer's unknowns
/// `a1, a2, a3, b1, b2, b3` (the first three drifts and kicks), in `f64`.
fn aba_unknowns(id: &str) -> [f64; 6] {
    let t = tableau::catalogue::load(id).unwrap();
    let Table::Splitting(s) = &t.table else {
        panic!("{id}: a drift–kick sequence")
    };
    [
        s.drift[0].to_f64(),
        s.drift[1].to_f64(),
        s.drift[2].to_f64(),
        s.kick[0].to_f64(),
        s.kick[1].to_f64(),
        s.kick[2].to_f64(),
    ]
}

#[test]
fn aba_10_4_certified() {
    let mut family = load("aba-10-4.toml");
    assert_eq!(family.generalised, [10, 4]);
    family.starts = 2000;
    let out = design(&family, "designs/aba-10-4.toml", &mut |_| {}).unwrap();
    assert_eq!(out.system.names, ["a1", "a2", "a3", "b1", "b2", "b3"]);
    let words: Vec<&str> = out
        .system
        .conditions
        .iter()
        .map(|c| c.word.as_str())
        .collect();
    assert_eq!(words, ["AAB", "ABB", "AAAAB", "AAAAAAB", "AAAAAAAAB"]);
    let c = design::solve::Compiled::new(&out.system);
    let theirs = aba_unknowns("aba-10-4");
    assert!(c.residual(&theirs) < 1e-15);
    let best = out
        .designs
        .first()
        .expect("a (10, 4) solution from 2000 starts");
    println!(
        "found {:?}: objective {:e}; Blanes et al. ABA(10,4): {:e}",
        best.solution.x,
        best.solution.objective,
        c.objective(&theirs)
    );
    let (name, text) = best.table.as_ref().unwrap();
    assert!(text.contains("\"order = (10, 4) (certified)\""), "{text}");
    assert_claims_hold(name, text);
    // Beyond the radius (1e-46), the claim is refused: a1 moved by 1e-45.
    refused_when_moved(name, text, "a1", "1e-45", "(10, 4) (certified)");
}

/// Why the search does not return Blanes et al.'s ABA(10,4): its five
/// conditions leave one unknown free, so the published point lies on a
/// curve of solutions, and along that curve (followed here by fixing b3 and
/// solving the conditions for the other five unknowns) every error term of
/// the objective varies by a few per cent only, and in the same direction.
/// The published point is no minimum of the shipped objective there: it
/// decreases towards more negative b3, to a minimum about 0.2 away that is
/// 3 % lower; nor is the εh¹¹ term extremal at it (|εh¹¹| decreases the same
/// way). Its small relative tangential gradient (the guide's 8.1·10⁻⁴) comes
/// from the flatness of the curve, not from a minimum. The coefficients'
/// sizes grow that way (Σ|aᵢ| + Σ|bᵢ|), so the paper's choice may weigh
/// them; its criterion is not known here. Prints the figures the guide
/// quotes (`-- --nocapture`).
#[test]
fn aba_10_4_published_point_is_no_minimum_on_its_curve() {
    let family = load("aba-10-4.toml");
    let sys = design::conditions::system(&family, "designs/aba-10-4.toml").unwrap();
    assert_eq!(sys.names, ["a1", "a2", "a3", "b1", "b2", "b3"]);
    let c = design::solve::Compiled::new(&sys);
    let theirs = aba_unknowns("aba-10-4");
    assert!(c.residual(&theirs) < 1e-15);
    // The point of the curve with the given b3: Newton steps on the
    // conditions in a1, a2, a3, b1, b2 (exact Jacobians), from the
    // published point.
    let on_curve = |b3: f64| -> Vec<f64> {
        let mut x = theirs.to_vec();
        x[5] = b3;
        for _ in 0..40 {
            let f: Vec<f64> = c.f.iter().map(|p| -p.eval(&x)).collect();
            let j: Vec<Vec<f64>> = c
                .condition_jacobian(&x)
                .into_iter()
                .map(|row| row[..5].to_vec())
                .collect();
            let dx = design::linalg::solve_f64(&j, &f).expect("a regular point of the curve");
            for (xk, d) in x.iter_mut().zip(dx) {
                *xk += d;
            }
        }
        assert!(c.residual(&x) < 1e-15, "b3 = {b3}: {:e}", c.residual(&x));
        x
    };
    let e11 = sys
        .error_terms
        .iter()
        .position(|e| e.degree == 11)
        .expect("the εh¹¹ term");
    let eps_h11 = |x: &[f64]| c.e[e11].eval(x);
    let size = |x: &[f64]| -> f64 {
        sys.drift
            .iter()
            .chain(&sys.kick)
            .map(|p| p.compile().eval(x).abs())
            .sum()
    };
    let b3 = theirs[5];
    let at_theirs = on_curve(b3);
    assert!(
        at_theirs
            .iter()
            .zip(&theirs)
            .all(|(p, q)| (p - q).abs() < 1e-14),
        "the curve passes through the published point"
    );
    let theirs_obj = c.objective(&theirs);
    // The objective along the curve, b3 from 0.1 above the published value
    // to 0.5 below, in steps of 0.01.
    let scan: Vec<(f64, f64)> = (-50..=10)
        .map(|k| {
            let b = b3 + f64::from(k) / 100.0;
            (b, c.objective(&on_curve(b)))
        })
        .collect();
    let (b_min, obj_min) = scan
        .iter()
        .copied()
        .min_by(|p, q| p.1.total_cmp(&q.1))
        .unwrap();
    let largest = scan.iter().map(|p| p.1).fold(0.0, f64::max);
    let x_min = on_curve(b_min);
    println!(
        "ABA(10,4) curve: published b3 = {b3:.10}, Σe² = {theirs_obj:.6e}, εh¹¹ = {:.4e}, Σ|coefficients| = {:.6}",
        eps_h11(&theirs),
        size(&theirs)
    );
    println!(
        "  smallest Σe² on b3 ∈ [b3 − 0.5, b3 + 0.1]: {obj_min:.6e} at b3 = {b_min:.4} ({:.1} % lower), εh¹¹ = {:.4e}, Σ|coefficients| = {:.6}; largest {largest:.6e}",
        100.0 * (1.0 - obj_min / theirs_obj),
        eps_h11(&x_min),
        size(&x_min)
    );
    // Flat: within 10 % over the whole stretch.
    assert!(largest < 1.1 * obj_min, "{largest:e} {obj_min:e}");
    // No minimum at the published point: the objective falls towards more
    // negative b3, to a minimum at least 0.1 away and 2 % lower, inside the
    // scanned stretch.
    let below = c.objective(&on_curve(b3 - 0.01));
    let above = c.objective(&on_curve(b3 + 0.01));
    assert!(
        below < theirs_obj && theirs_obj < above,
        "{below:e} {theirs_obj:e} {above:e}"
    );
    assert!(b_min < b3 - 0.1 && b_min > b3 - 0.5, "{b_min}");
    assert!(obj_min < 0.98 * theirs_obj);
    // Nor is the εh¹¹ term extremal there: one sign, |εh¹¹| decreasing the
    // same way.
    let (lo, mid, hi) = (
        eps_h11(&on_curve(b3 - 0.1)),
        eps_h11(&at_theirs),
        eps_h11(&on_curve(b3 + 0.1)),
    );
    println!("  εh¹¹ at b3 − 0.1, b3, b3 + 0.1: {lo:.6e}, {mid:.6e}, {hi:.6e}");
    assert!(lo.signum() == mid.signum() && mid.signum() == hi.signum());
    assert!(lo.abs() < mid.abs() && mid.abs() < hi.abs());
    // The measure that looked like stationarity: the gradient's part
    // tangent to the conditions is small relative to the whole only because
    // the objective hardly changes along the curve.
    let st = c.stationarity(&theirs);
    println!("  tangential part of the gradient at the published point: {st:.1e} of it");
    assert!(st < 1e-2, "{st:e}");
    // The coefficients grow towards the objective's minimum.
    assert!(size(&x_min) > size(&theirs));
}

/// The εh¹¹ term alone as the objective (the shipped family's 20000 starts,
/// seed 1): every start that reaches the conditions ends at a distinct
/// point, and on none of them does the term vanish. Its smallest magnitude
/// there is above the published ABA(10,4)'s −4.01·10⁻¹³, so a search on
/// this term does not return the published point either, and an objective
/// of ~10⁻²⁵ (the square of such a term) is no zero of it.
#[test]
#[ignore = "slow (20000 starts, 20 to 70 s in release): cargo test --release -p design --test integration aba_10_4_eh11 -- --ignored --nocapture"]
fn aba_10_4_eh11_alone_does_not_vanish() {
    let family = load("aba-10-4.toml");
    let mut sys = design::conditions::system(&family, "designs/aba-10-4.toml").unwrap();
    sys.error_terms.retain(|e| e.degree == 11);
    assert_eq!(sys.error_terms.len(), 1, "one Lie term with one letter B");
    let out = design::solve::search(&sys, &family, &mut |_| {});
    assert!(!out.capped, "all 20000 starts ran");
    let c = design::solve::Compiled::new(&sys);
    let theirs = aba_unknowns("aba-10-4");
    let published = c.e[0].eval(&theirs);
    let smallest = out
        .solutions
        .iter()
        .map(|sol| c.e[0].eval(&sol.x).abs())
        .fold(f64::INFINITY, f64::min);
    println!(
        "εh¹¹ alone: {} starts reached the conditions, {} distinct points; smallest |εh¹¹| {smallest:.3e}, published {published:.3e}",
        out.converged,
        out.solutions.len()
    );
    assert!(!out.solutions.is_empty());
    assert!(smallest > published.abs(), "{smallest:e} {published:e}");
}

/// RKN order 6 (`designs/rkn6-aba8.toml`, 8 stages): the emitted tables
/// claim `order = 4` and `order_rkn = 6` with residual bounds on their 50
/// printed digits, which `symlab check`'s verifier decides exactly.
#[test]
fn rkn_order_six_designs_check() {
    let mut family = load("rkn6-aba8.toml");
    family.starts = 300;
    let out = design(&family, "designs/rkn6-aba8.toml", &mut |_| {}).unwrap();
    let best = out
        .designs
        .first()
        .expect("an RKN order-6 solution from 300 starts");
    let (name, text) = best.table.as_ref().unwrap();
    assert!(
        text.contains("\"order_rkn = 6 (residual < 1e-40)\""),
        "{text}"
    );
    assert_claims_hold(name, text);
    println!(
        "best of 300 starts: E_f {:.4}",
        best.solution.effective_error
    );
}

/// Blanes–Moan's SRKN11b and SRKN14a solve the RKN order-6 conditions of
/// their families (to their printed digits); their E_f in this crate's RKN
/// measure, for the guide's comparison with `rkn6-aba8.toml`.
#[test]
#[ignore = "slow (the 14-stage system has 13 unknowns): cargo test --workspace --test integration blanes_moan_rkn6 -- --ignored --nocapture"]
fn blanes_moan_rkn6_effective_errors() {
    for (id, form, stages) in [
        ("blanes-moan-srkn11b", design::Form::Bab, 11),
        ("blanes-moan-srkn14a", design::Form::Aba, 14),
    ] {
        let mut f = design::Family::new(id, form, stages, 6);
        f.rkn = true;
        f.error_basis = design::ErrorBasis::Brackets;
        let sys = design::conditions::system(&f, id).unwrap();
        let t = tableau::catalogue::load(id).unwrap();
        let Table::Splitting(s) = &t.table else {
            panic!()
        };
        // The unknowns a1…, b1… in the catalogue's sequences (a BAB table
        // writes a leading zero drift).
        let skip = usize::from(form == design::Form::Bab);
        let x: Vec<f64> = sys
            .names
            .iter()
            .map(|n| {
                let i: usize = n[1..].parse::<usize>().unwrap() - 1;
                if n.starts_with('a') {
                    s.drift[i + skip].to_f64()
                } else {
                    s.kick[i].to_f64()
                }
            })
            .collect();
        let c = design::solve::Compiled::new(&sys);
        assert!(c.residual(&x) < 1e-13, "{id}: {:e}", c.residual(&x));
        println!(
            "{id}: E_f {:.4}",
            design::solve::effective_error(stages, 6, c.objective(&x))
        );
    }
}
