//! Verdicts of the analysis on tables typed in as text: symplecticity (and
//! that any single perturbation breaks it, pointing at the right entries of
//! W), symmetry, class, reducibility, the stability function, and claims.

use tableau::analysis::{Analysis, Class, check_claim};
use tableau::claims::parse_claim;
use tableau::file::parse_table_file;
use tableau::{Number, Table};

fn table(text: &str) -> Table {
    parse_table_file("test", text)
        .unwrap_or_else(|e| panic!("{e}"))
        .table
}

fn analyse(text: &str) -> Analysis {
    Analysis::of(&table(text)).unwrap()
}

const GAUSS2: &str = r#"name = "g2"
a = [["1/4", "1/4 - sqrt(3)/6"], ["1/4 + sqrt(3)/6", "1/4"]]
b = ["1/2", "1/2"]"#;

const GAUSS3: &str = r#"name = "g3"
a = [["5/36", "2/9 - sqrt(15)/15", "5/36 - sqrt(15)/30"],
     ["5/36 + sqrt(15)/24", "2/9", "5/36 - sqrt(15)/24"],
     ["5/36 + sqrt(15)/30", "2/9 + sqrt(15)/15", "5/36"]]
b = ["5/18", "4/9", "5/18"]"#;

const VERLET_PAIR: &str = r#"name = "sv"
a = [[0, 0], ["1/2", "1/2"]]
b = ["1/2", "1/2"]
a_hat = [["1/2", 0], ["1/2", 0]]
b_hat = ["1/2", "1/2"]"#;

const LOBATTO3A3B_3: &str = r#"name = "l3ab"
a = [[0, 0, 0], ["5/24", "1/3", "-1/24"], ["1/6", "2/3", "1/6"]]
b = ["1/6", "2/3", "1/6"]
a_hat = [["1/6", "-1/6", 0], ["1/6", "1/3", 0], ["1/6", "5/6", 0]]
b_hat = ["1/6", "2/3", "1/6"]"#;

#[test]
fn gauss_legendre() {
    for (text, order) in [(GAUSS2, 4), (GAUSS3, 6)] {
        let a = analyse(text);
        assert!(a.symplectic && a.symmetric);
        assert_eq!(a.class, Class::Implicit);
        assert_eq!(a.order.as_ref().unwrap().order, order);
        assert_eq!(a.unimodular, Some(true));
    }
    let r = analyse(GAUSS3).stability.unwrap();
    assert_eq!(
        r.to_text(),
        "(1 + z/2 + z^2/10 + z^3/120)/(1 - z/2 + z^2/10 - z^3/120)"
    );
}

/// Perturbing any single entry of a symplectic table by 1/1000 breaks W = 0,
/// and the nonzero entries are exactly the ones the perturbation touches.
#[test]
fn every_single_perturbation_breaks_symplecticity() {
    for text in [GAUSS2, GAUSS3] {
        let Table::Rk(rk) = table(text) else {
            unreachable!()
        };
        let s = rk.stages();
        let d = Number::ratio(1, 1000).unwrap();
        for i in 0..s {
            for j in 0..s {
                let mut p = rk.clone();
                p.a[i][j] = &p.a[i][j] + &d;
                let t = Table::Rk(p);
                let a = Analysis::of(&t).unwrap();
                assert!(!a.symplectic);
                // W[i][j] and W[j][i] change by b_i/1000 (W[i][i] by 2·b_i/1000).
                let mut touched: Vec<(usize, usize)> =
                    a.w_nonzero.iter().map(|e| (e.i, e.j)).collect();
                touched.sort();
                let mut expect = vec![(i, j), (j, i)];
                expect.sort();
                expect.dedup();
                assert_eq!(touched, expect, "a[{i}][{j}] perturbed");
                let k = if i == j { 2 } else { 1 };
                let want = &rk.b[i] * &d * Number::from(k);
                assert!(a.w_nonzero.iter().all(|e| e.value == want));
                let err = check_claim(&t, &a, &parse_claim("symplectic").unwrap())
                    .unwrap_err()
                    .to_string();
                assert!(
                    err.contains(&format!("W[{}][{}]", touched[0].0, touched[0].1)),
                    "{err}"
                );
            }
            let mut p = rk.clone();
            p.b[i] = &p.b[i] + &d;
            let a = Analysis::of(&Table::Rk(p)).unwrap();
            assert!(!a.symplectic, "b[{i}] perturbed");
            assert!(a.w_nonzero.iter().any(|e| e.i == i || e.j == i));
        }
    }
}

#[test]
fn pairs() {
    let a = analyse(VERLET_PAIR);
    assert!(a.symplectic && a.symplectic_separable && a.symmetric);
    assert_eq!(a.order.as_ref().unwrap().order, 2);
    assert!(a.explicit_separable);
    let a = analyse(LOBATTO3A3B_3);
    assert!(a.symplectic && a.symmetric);
    assert_eq!(a.order.as_ref().unwrap().order, 4);
    // Lobatto IIIA alone is not symplectic.
    let a = analyse(
        r#"name = "l3a"
a = [[0, 0], ["1/2", "1/2"]]
b = ["1/2", "1/2"]"#,
    );
    assert!(!a.symplectic);
    assert_eq!(a.class, Class::Dirk);
    // Symplectic Euler as a pair with b ≠ b̂ in the drift–kick sense: explicit
    // on separable systems, symplectic there, not for all H.
    let a = analyse(
        r#"name = "se"
drift = [1]
kick = [1]"#,
    );
    assert!(a.symplectic_separable && !a.symmetric);
    assert_eq!(a.order_separable.order, 1);
    assert!(a.separable_only());
}

#[test]
fn splittings_and_compositions() {
    let fr = r#"name = "fr"
let = { x = "1/(2 - cbrt(2))" }
drift = ["x/2", "(1 - x)/2", "(1 - x)/2", "x/2"]
kick = ["x", "1 - 2*x", "x"]"#;
    let a = analyse(fr);
    assert!(a.symplectic_separable && a.symmetric && a.explicit_separable);
    assert_eq!(a.order_separable.order, 4);
    let tj = r#"name = "tj"
let = { x = "1/(2 - cbrt(2))" }
compose = ["x", "1 - 2*x", "x"]"#;
    let a = analyse(tj);
    assert!(a.symplectic_separable && a.symmetric);
    assert_eq!(a.order_separable.order, 4);
    // An asymmetric sequence.
    let a = analyse(
        r#"name = "x"
drift = ["1/3", "2/3"]
kick = [1]"#,
    );
    assert!(!a.symmetric);
}

#[test]
fn classes_and_stability() {
    let a = analyse(
        r#"name = "dirk2"
a = [["1/4", 0], ["1/2", "1/4"]]
b = ["1/2", "1/2"]"#,
    );
    assert_eq!(a.class, Class::Sdirk);
    assert!(a.symplectic && a.symmetric);
    assert_eq!(a.order.as_ref().unwrap().order, 2);
    let a = analyse(
        r#"name = "ie"
a = [[1]]
b = [1]"#,
    );
    assert_eq!(a.stability.as_ref().unwrap().to_text(), "(1)/(1 - z)");
    assert_eq!(a.unimodular, Some(false));
    assert!(!a.symmetric && !a.symplectic);
}

#[test]
fn reducible_tables_are_judged_on_their_irreducible_form() {
    // The implicit midpoint rule written with a duplicated stage: W ≠ 0 as
    // written, but the method is the midpoint rule, which is symplectic.
    let a = analyse(
        r#"name = "dup"
a = [["1/4", "1/4"], ["1/4", "1/4"]]
b = ["1/4", "3/4"]"#,
    );
    assert!(a.reducible);
    assert!(a.symplectic && a.symmetric);
    assert!(!a.w_nonzero.is_empty());
}

#[test]
fn claims_are_checked_with_evidence() {
    let rk4 = r#"name = "rk4"
a = [[0, 0, 0, 0], ["1/2", 0, 0, 0], [0, "1/2", 0, 0], [0, 0, 1, 0]]
b = ["1/6", "1/3", "1/3", "1/6"]"#;
    let t = table(rk4);
    let a = Analysis::of(&t).unwrap();
    let check = |c: &str| check_claim(&t, &a, &parse_claim(c).unwrap()).map_err(|e| e.to_string());
    assert!(check("order = 4").is_ok());
    assert!(check("explicit").is_ok());
    let e = check("symplectic").unwrap_err();
    assert!(e.starts_with("not symplectic: W[0][0] = "), "{e}");
    let e = check("order = 5").unwrap_err();
    assert!(e.contains("order-5 condition"), "{e}");
    let e = check("order = 40").unwrap_err();
    assert!(e.contains("cannot be decided"), "{e}");
    let e = check("symmetric").unwrap_err();
    assert!(e.contains("not symmetric"), "{e}");
    // RK4 with a wrong c: the order conditions use the given c.
    let wrong_c = format!("{rk4}\nc = [0, \"1/2\", \"1/2\", \"1/2\"]");
    let t = table(&wrong_c);
    let a = Analysis::of(&t).unwrap();
    assert_eq!(a.row_sum_mismatch.len(), 1);
    assert!(check_claim(&t, &a, &parse_claim("order = 4").unwrap()).is_err());
}

#[test]
fn order_rkn_claims_are_checked_like_order_claims() {
    // Störmer–Verlet as a drift–kick sequence: order 2 on every system.
    let verlet = table(
        r#"name = "sv"
drift = ["1/2", "1/2"]
kick = [1]"#,
    );
    let a = Analysis::of(&verlet).unwrap();
    assert_eq!(a.order_rkn.order, 2);
    assert_eq!(a.order_rkn.limit, tableau::analysis::RKN_ORDER_LIMIT);
    let check = |t: &Table, a: &Analysis, c: &str| {
        check_claim(t, a, &parse_claim(c).unwrap()).map_err(|e| e.to_string())
    };
    assert!(check(&verlet, &a, "order_rkn = 2").is_ok());
    assert!(check(&verlet, &a, "order_rkn = 2 (residual < 1e-30)").is_ok());
    let e = check(&verlet, &a, "order_rkn = 3").unwrap_err();
    assert_eq!(
        e,
        "order_rkn 3 claimed (on Runge–Kutta–Nyström systems, T quadratic) but the order-3 condition for tree [[τ_q]_p]_q fails: residual 1/12"
    );
    let e = check(&verlet, &a, "order_rkn = 3 (residual < 1/100)").unwrap_err();
    assert!(e.ends_with("residual 1/12 is not below 1/100"), "{e}");
    // Above the default limit the claim is re-checked, up to 14; above, refused.
    let e = check(&verlet, &a, "order_rkn = 14").unwrap_err();
    assert!(e.contains("order-3 condition"), "{e}");
    let e = check(&verlet, &a, "order_rkn = 15").unwrap_err();
    assert_eq!(
        e,
        "order_rkn 15 cannot be decided: the checker verifies order conditions on Runge–Kutta–Nyström systems (T quadratic) up to order 14"
    );
    // The order claim and the order_rkn claim are distinct.
    assert!(check(&verlet, &a, "order = 2").is_ok());

    // A Runge–Kutta table is checked as the pair (A, b), (A, b).
    let rk4 = table(
        r#"name = "rk4"
a = [[0, 0, 0, 0], ["1/2", 0, 0, 0], [0, "1/2", 0, 0], [0, 0, 1, 0]]
b = ["1/6", "1/3", "1/3", "1/6"]"#,
    );
    let a = Analysis::of(&rk4).unwrap();
    assert!(check(&rk4, &a, "order_rkn = 4").is_ok());
    let e = check(&rk4, &a, "order_rkn = 5").unwrap_err();
    assert!(e.contains("order-5 condition for tree [[τ_q³]_p]_q"), "{e}");

    // A composition is checked as its drift–kick sequence: the triple jump.
    let tj = table(
        r#"name = "tj"
let = { x = "1/(2 - cbrt(2))" }
compose = ["x", "1 - 2*x", "x"]"#,
    );
    let a = Analysis::of(&tj).unwrap();
    assert_eq!((a.order_separable.order, a.order_rkn.order), (4, 4));
    assert!(check(&tj, &a, "order_rkn = 4").is_ok());
    assert!(check(&tj, &a, "order_rkn = 6").is_err());

    // Decimal coefficients without a bound: the message says how to claim it.
    let ma4 = tableau::catalogue::load("mclachlan-atela4").unwrap().table;
    let a = Analysis::of(&ma4).unwrap();
    let e = check(&ma4, &a, "order_rkn = 4").unwrap_err();
    assert!(
        e.ends_with(
            "if the coefficients are rounded decimals, claim a bound: `order_rkn = 4 (residual < 1e-14)`"
        ),
        "{e}"
    );
    assert!(check(&ma4, &a, "order_rkn = 4 (residual < 1e-14)").is_ok());
    // On general separable systems it is order 3: the order-4 failure is a
    // tree with a q-vertex of two or more children, which T quadratic removes.
    let e = check(&ma4, &a, "order = 4 (residual < 1e-14)").unwrap_err();
    assert!(e.contains("order-4 condition for tree [τ_p³]_q"), "{e}");
}
