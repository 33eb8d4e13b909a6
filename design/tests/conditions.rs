//! The condition polynomials against tableau: they vanish exactly at the
//! published exact methods, and their values at rational points are the
//! Lyndon coefficients tableau's near-integrable verifier computes.

use design::conditions::system;
use design::{Family, Form};
use tableau::{Number, Splitting, Table};

use crate::common::{eval_number, q};

#[test]
fn composition_conditions_vanish_exactly_at_yoshida() {
    let sys = system(&Family::new("y", Form::Composition, 3, 4), "test").unwrap();
    let y = tableau::catalogue::load("yoshida4").unwrap();
    let Table::Composition(c) = &y.table else {
        panic!("yoshida4 is a composition")
    };
    let x = vec![c.gamma[0].clone()];
    for cond in &sys.conditions {
        assert!(eval_number(&cond.poly, &x).is_zero(), "{}", cond.word);
    }
    // The next order's terms do not all vanish, and tableau agrees on 4.
    assert!(
        sys.error_terms
            .iter()
            .any(|e| !eval_number(&e.poly, &x).is_zero())
    );
    assert_eq!(tableau::order::composition_order(c, 8, None).order, 4);
}

#[test]
fn drift_kick_conditions_vanish_exactly_at_forest_ruth() {
    let sys = system(&Family::new("fr", Form::Aba, 3, 4), "test").unwrap();
    assert_eq!(sys.names, ["a1", "b1"]);
    let fr = tableau::catalogue::load("forest-ruth").unwrap();
    let Table::Splitting(s) = &fr.table else {
        panic!("forest-ruth is a drift–kick sequence")
    };
    let x = vec![s.drift[0].clone(), s.kick[0].clone()];
    assert_eq!(sys.conditions.len(), 2);
    for cond in &sys.conditions {
        assert!(eval_number(&cond.poly, &x).is_zero(), "{}", cond.word);
    }
    assert!(
        sys.error_terms
            .iter()
            .any(|e| !eval_number(&e.poly, &x).is_zero())
    );
}

/// `AAB` → `A²B`, tableau's labels.
fn run_label(word: &str) -> String {
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let chars: Vec<char> = word.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < chars.len() {
        let run = chars[i..].iter().take_while(|&&c| c == chars[i]).count();
        out.push(chars[i]);
        if run > 1 {
            out.push(SUP[run]);
        }
        i += run;
    }
    out
}

fn compare_with_near(form: Form, stages: usize, x: Vec<Number>) {
    let sys = system(&Family::new("t", form, stages, 4), "test").unwrap();
    let drift: Vec<Number> = sys.drift.iter().map(|p| eval_number(p, &x)).collect();
    let kick: Vec<Number> = sys.kick.iter().map(|p| eval_number(p, &x)).collect();
    let (drift, kick) = if form == Form::Bab {
        let mut d = vec![Number::zero()];
        d.extend(drift);
        (d, kick)
    } else {
        (drift, kick)
    };
    let table = Table::Splitting(Splitting::new(drift, kick));
    let near = tableau::near_integrable::near_coefficients(&table, &[5, 5, 5, 5]).unwrap();
    let mut compared = 0;
    for cond in sys.conditions.iter().chain(&sys.error_terms) {
        let label = run_label(&cond.word);
        let theirs = near
            .iter()
            .find(|c| c.word == label)
            .unwrap_or_else(|| panic!("tableau has no Lyndon word {label}"));
        assert_eq!(eval_number(&cond.poly, &x), theirs.residual, "{label}");
        compared += 1;
    }
    // Degree 3: AAB, ABB; degree 5: six Lyndon words.
    assert_eq!(compared, 8);
    // And every even-degree coefficient tableau computes is zero (the
    // palindrome), as the system asserts identically.
    assert!(
        near.iter()
            .filter(|c| c.degree % 2 == 0)
            .all(|c| c.value.is_zero())
    );
}

#[test]
fn lyndon_coefficients_are_tableaus_at_rational_points() {
    let n = |a: i64, b: i64| Number::from_rational(q(a, b));
    // ABA, 5 kicks: unknowns a1, a2, b1, b2.
    compare_with_near(Form::Aba, 5, vec![n(1, 7), n(-2, 9), n(3, 11), n(-1, 5)]);
    // BAB, 6 force evaluations: unknowns a1, a2, b1, b2, b3.
    compare_with_near(
        Form::Bab,
        6,
        vec![n(1, 5), n(-1, 7), n(1, 13), n(4, 11), n(-1, 23)],
    );
}

#[test]
fn composition_letters_match_tableaus_word_coefficients() {
    // For the letters Y₃, Y₅ the coefficient in log Φ is the one in Φ.
    let sys = system(&Family::new("c", Form::Composition, 5, 4), "test").unwrap();
    let x = vec![
        Number::from_rational(q(3, 7)),
        Number::from_rational(q(2, 5)),
    ];
    let gamma: Vec<Number> = sys.gamma.iter().map(|p| eval_number(p, &x)).collect();
    let coeffs = tableau::order::composition_coefficients(&tableau::Composition { gamma }, 5);
    for (mine, theirs) in [("Y₃", "Y₃"), ("Y₅", "Y₅")] {
        let c = sys
            .conditions
            .iter()
            .chain(&sys.error_terms)
            .find(|c| c.word == mine)
            .unwrap();
        let t = coeffs.iter().find(|t| t.tree == theirs).unwrap();
        assert_eq!(eval_number(&c.poly, &x), t.residual(), "{mine}");
    }
}
