//! Order analysis of known tables, typed in exactly.

use num_bigint::BigInt;
use num_rational::BigRational;
use proptest::prelude::*;
use tableau::Number;
use tableau::order::{
    self, ConditionKind, OrderReport, composition_order, prk_order, prk_order_nystrom,
    prk_order_separable, rk_order, rk_order_nystrom,
};
use tableau::table::{Composition, Prk, Rk, Splitting};
use tableau::trees::{Colouring, Forest};

fn r(n: i64, d: i64) -> Number {
    Number::ratio(n, d).unwrap()
}

fn int(n: i64) -> Number {
    Number::from(n)
}

fn sqrt(n: i64) -> Number {
    Number::from(n).sqrt().unwrap()
}

fn cbrt(n: i64) -> Number {
    Number::from(n).cbrt().unwrap()
}

/// An exact decimal: `"-0.125"` is `-1/8`.
fn dec(s: &str) -> Number {
    let (neg, s) = match s.strip_prefix('-') {
        Some(t) => (true, t),
        None => (false, s),
    };
    let (whole, frac) = s.split_once('.').unwrap_or((s, ""));
    let digits: BigInt = format!("{whole}{frac}").parse().unwrap();
    let den = BigInt::from(10).pow(frac.len() as u32);
    let value = BigRational::new(if neg { -digits } else { digits }, den);
    Number::from_rational(value)
}

fn rk(a: Vec<Vec<Number>>, b: Vec<Number>) -> Rk {
    Rk { a, b, c: None }
}

fn rows(a: &[&[(i64, i64)]]) -> Vec<Vec<Number>> {
    let s = a.len();
    a.iter()
        .map(|row| {
            let mut v: Vec<Number> = row.iter().map(|&(n, d)| r(n, d)).collect();
            v.resize(s, Number::zero());
            v
        })
        .collect()
}

fn ratios(v: &[(i64, i64)]) -> Vec<Number> {
    v.iter().map(|&(n, d)| r(n, d)).collect()
}

/// Order exactly `p` when checked up to `limit > p`.
fn assert_order(report: &OrderReport, p: usize) {
    assert_eq!(report.order, p, "{report}");
    assert!(report.limit > p);
    let f = report
        .first_failure
        .as_ref()
        .expect("a failure above the order");
    assert_eq!(f.order, p + 1);
    assert!(!f.residual.is_zero());
    assert_eq!(f.residual, &f.value - &f.expected);
}

fn euler() -> Rk {
    rk(rows(&[&[]]), ratios(&[(1, 1)]))
}

fn heun() -> Rk {
    rk(rows(&[&[], &[(1, 1)]]), ratios(&[(1, 2), (1, 2)]))
}

fn rk4() -> Rk {
    rk(
        rows(&[&[], &[(1, 2)], &[(0, 1), (1, 2)], &[(0, 1), (0, 1), (1, 1)]]),
        ratios(&[(1, 6), (1, 3), (1, 3), (1, 6)]),
    )
}

fn three_eighths() -> Rk {
    rk(
        rows(&[
            &[],
            &[(1, 3)],
            &[(-1, 3), (1, 1)],
            &[(1, 1), (-1, 1), (1, 1)],
        ]),
        ratios(&[(1, 8), (3, 8), (3, 8), (1, 8)]),
    )
}

fn gauss2() -> Rk {
    let s3 = sqrt(3);
    let q = r(1, 4);
    let d = s3.checked_div(&int(6)).unwrap();
    rk(
        vec![vec![q.clone(), &q - &d], vec![&q + &d, q]],
        ratios(&[(1, 2), (1, 2)]),
    )
}

fn gauss3() -> Rk {
    let s = sqrt(15);
    let f = |n: i64, d: i64, k: i64, e: i64| &r(n, d) + &(&s * &r(k, e));
    rk(
        vec![
            vec![r(5, 36), f(2, 9, -1, 15), f(5, 36, -1, 30)],
            vec![f(5, 36, 1, 24), r(2, 9), f(5, 36, -1, 24)],
            vec![f(5, 36, 1, 30), f(2, 9, 1, 15), r(5, 36)],
        ],
        ratios(&[(5, 18), (4, 9), (5, 18)]),
    )
}

fn radau_iia3() -> Rk {
    let s = sqrt(6);
    let f = |n: i64, k: i64, d: i64| (&int(n) + &(&s * &int(k))).checked_div(&int(d)).unwrap();
    let last = vec![f(16, -1, 36), f(16, 1, 36), r(1, 9)];
    rk(
        vec![
            vec![f(88, -7, 360), f(296, -169, 1800), f(-2, 3, 225)],
            vec![f(296, 169, 1800), f(88, 7, 360), f(-2, -3, 225)],
            last.clone(),
        ],
        last,
    )
}

/// Dormand–Prince 5(4), the fifth-order weights (FSAL, `b₇ = 0`).
fn dopri5() -> Rk {
    rk(
        rows(&[
            &[],
            &[(1, 5)],
            &[(3, 40), (9, 40)],
            &[(44, 45), (-56, 15), (32, 9)],
            &[(19372, 6561), (-25360, 2187), (64448, 6561), (-212, 729)],
            &[
                (9017, 3168),
                (-355, 33),
                (46732, 5247),
                (49, 176),
                (-5103, 18656),
            ],
            &[
                (35, 384),
                (0, 1),
                (500, 1113),
                (125, 192),
                (-2187, 6784),
                (11, 84),
            ],
        ]),
        ratios(&[
            (35, 384),
            (0, 1),
            (500, 1113),
            (125, 192),
            (-2187, 6784),
            (11, 84),
            (0, 1),
        ]),
    )
}

/// Butcher's explicit 7-stage method of order 6 (Butcher 1964).
fn butcher6() -> Rk {
    rk(
        rows(&[
            &[],
            &[(1, 3)],
            &[(0, 1), (2, 3)],
            &[(1, 12), (1, 3), (-1, 12)],
            &[(-1, 16), (9, 8), (-3, 16), (-3, 8)],
            &[(0, 1), (9, 8), (-3, 8), (-3, 4), (1, 2)],
            &[(9, 44), (-9, 11), (63, 44), (18, 11), (0, 1), (-16, 11)],
        ]),
        ratios(&[
            (11, 120),
            (0, 1),
            (27, 40),
            (27, 40),
            (-4, 15),
            (-4, 15),
            (11, 120),
        ]),
    )
}

/// Solve `M x = y` exactly by Gaussian elimination.
fn solve(mut m: Vec<Vec<Number>>, mut y: Vec<Number>) -> Vec<Number> {
    let n = y.len();
    for col in 0..n {
        let piv = (col..n)
            .find(|&i| !m[i][col].is_zero())
            .expect("nonsingular");
        m.swap(col, piv);
        y.swap(col, piv);
        let inv = m[col][col].recip().unwrap();
        let pivot_row = m[col].clone();
        for i in col + 1..n {
            let f = &m[i][col] * &inv;
            if f.is_zero() {
                continue;
            }
            for (k, p) in pivot_row.iter().enumerate().skip(col) {
                m[i][k] = &m[i][k] - &(&f * p);
            }
            y[i] = &y[i] - &(&f * &y[col]);
        }
    }
    let mut x = vec![Number::zero(); n];
    for i in (0..n).rev() {
        let mut acc = y[i].clone();
        for k in i + 1..n {
            acc = &acc - &(&m[i][k] * &x[k]);
        }
        x[i] = acc.checked_div(&m[i][i]).unwrap();
    }
    x
}

/// The collocation method with nodes `c`: `Σⱼ aᵢⱼ cⱼ^(k−1) = cᵢ^k/k`,
/// `Σⱼ bⱼ cⱼ^(k−1) = 1/k`.
fn collocation(c: &[Number]) -> Rk {
    let s = c.len();
    let vt: Vec<Vec<Number>> = (0..s)
        .map(|k| c.iter().map(|x| x.powi(k as i64).unwrap()).collect())
        .collect();
    let a = c
        .iter()
        .map(|ci| {
            let rhs = (1..=s as i64)
                .map(|k| &ci.powi(k).unwrap() * &r(1, k))
                .collect();
            solve(vt.clone(), rhs)
        })
        .collect();
    let b = solve(vt, (1..=s as i64).map(|k| r(1, k)).collect());
    rk(a, b)
}

/// Lobatto IIIA with 5 stages: nodes `0, 1/2 ∓ √21/14, 1/2, 1`; order 8.
fn lobatto_iiia5() -> Rk {
    let d = sqrt(21).checked_div(&int(14)).unwrap();
    let h = r(1, 2);
    collocation(&[int(0), &h - &d, h.clone(), &h + &d, int(1)])
}

/// The Lobatto IIIA–IIIB pair from IIIA: `âᵢⱼ = bⱼ(1 − aⱼᵢ/bᵢ)`, `b̂ = b`.
fn lobatto_pair(iiia: Rk) -> Prk {
    let s = iiia.b.len();
    let b = &iiia.b;
    let a_hat = (0..s)
        .map(|i| {
            (0..s)
                .map(|j| &b[j] - &(&b[j] * &iiia.a[j][i].checked_div(&b[i]).unwrap()))
                .collect()
        })
        .collect();
    Prk {
        p: Rk {
            a: a_hat,
            b: b.clone(),
            c: None,
        },
        q: iiia,
    }
}

#[test]
fn classical_runge_kutta_orders() {
    assert_order(&rk_order(&euler(), 8, None), 1);
    assert_order(&rk_order(&heun(), 8, None), 2);
    assert_order(&rk_order(&rk4(), 8, None), 4);
    assert_order(&rk_order(&three_eighths(), 8, None), 4);
    assert_order(&rk_order(&dopri5(), 8, None), 5);
    assert_order(&rk_order(&butcher6(), 8, None), 6);
}

#[test]
fn implicit_runge_kutta_orders() {
    let midpoint = rk(rows(&[&[(1, 2)]]), ratios(&[(1, 1)]));
    assert_order(&rk_order(&midpoint, 8, None), 2);
    assert_order(&rk_order(&gauss2(), 8, None), 4);
    assert_order(&rk_order(&gauss3(), 8, None), 6);
    assert_order(&rk_order(&radau_iia3(), 8, None), 5);
    let lobatto_iiia2 = rk(rows(&[&[], &[(1, 2), (1, 2)]]), ratios(&[(1, 2), (1, 2)]));
    assert_order(&rk_order(&lobatto_iiia2, 8, None), 2);
}

#[test]
fn collocation_reproduces_gauss3_and_lobatto5_has_order_8() {
    let d = sqrt(15).checked_div(&int(10)).unwrap();
    let h = r(1, 2);
    let g = collocation(&[&h - &d, h.clone(), &h + &d]);
    assert_eq!(g, gauss3());
    let report = rk_order(&lobatto_iiia5(), 10, None);
    assert_order(&report, 8);
}

#[test]
fn report_at_the_limit() {
    let report = rk_order(&gauss3(), 6, None);
    assert_eq!(report.order, 6);
    assert_eq!(report.limit, 6);
    assert!(report.reached_limit());
    assert!(report.first_failure.is_none());
    // 1 + 1 + 2 + 4 + 9 + 20 trees up to order 6.
    assert_eq!(report.conditions_checked, 37);
    assert_eq!(rk_order(&rk4(), 0, None).order, 0);
}

#[test]
fn perturbed_rk4_fails_at_tau_with_the_perturbation_as_residual() {
    let mut t = rk4();
    t.b[0] = &t.b[0] + &r(1, 1000);
    let report = rk_order(&t, 8, None);
    assert_eq!(report.order, 0);
    let f = report.first_failure.unwrap();
    assert_eq!(f.order, 1);
    assert_eq!(f.kind, ConditionKind::Tree);
    assert_eq!(f.tree, "τ");
    assert_eq!(f.residual, r(1, 1000));
    assert_eq!(f.value, r(1001, 1000));
    assert_eq!(f.expected, int(1));
}

#[test]
fn rk4_with_a_wrong_c_fails_on_a_time_tree() {
    let mut t = rk4();
    t.c = Some(vec![int(0), r(1, 2), r(1, 2), r(1, 2)]);
    assert!(order::rk_uses_time_leaves(&t));
    let report = rk_order(&t, 8, None);
    assert!(report.order < 4);
    assert_eq!(report.order, 1);
    let f = report.first_failure.unwrap();
    assert_eq!(f.tree, "[τ_t]");
    assert!(f.tree.contains("τ_t"));
    // Σ bᵢcᵢ = 5/12 instead of 1/2.
    assert_eq!(f.value, r(5, 12));
    assert_eq!(f.residual, r(-1, 12));
    assert!(
        f.to_string().contains("order-2 condition for tree [τ_t]"),
        "{f}"
    );
}

#[test]
fn a_c_equal_to_the_row_sums_adds_no_conditions() {
    let mut t = rk4();
    let plain = rk_order(&t, 8, None);
    t.c = Some(vec![int(0), r(1, 2), r(1, 2), int(1)]);
    assert!(!order::rk_uses_time_leaves(&t));
    assert_eq!(rk_order(&t, 8, None), plain);
    // With time leaves forced, RK4 (c = row sums) satisfies them all too.
    let with_time = order::rk_elementary_weights_with_time(&t, 4);
    assert_eq!(with_time.len(), 1 + 2 + 5 + 13);
    assert!(with_time.iter().all(|c| c.holds(None)));
}

#[test]
fn lobatto_iiib_with_its_own_c() {
    // Lobatto IIIB (s = 2): c = (0, 1) differs from the row sums (1/2, 1/2);
    // the order on non-autonomous problems is still 2.
    let t = Rk {
        a: rows(&[&[(1, 2)], &[(1, 2)]]),
        b: ratios(&[(1, 2), (1, 2)]),
        c: Some(vec![int(0), int(1)]),
    };
    assert!(order::rk_uses_time_leaves(&t));
    assert_order(&rk_order(&t, 6, None), 2);
    // A c that breaks the time conditions only.
    let skewed = Rk {
        c: Some(vec![int(0), r(1, 2)]),
        ..t
    };
    let report = rk_order(&skewed, 6, None);
    assert_order(&report, 1);
    assert_eq!(report.first_failure.unwrap().tree, "[τ_t]");
}

#[test]
fn decimal_weights_need_a_bound() {
    let mut t = rk4();
    t.b = vec![
        dec("0.16666667"),
        dec("0.33333333"),
        dec("0.33333333"),
        dec("0.16666667"),
    ];
    // Σb = 1 and Σbc = 1/2 hold exactly; Σbc² = 0.333333335 does not.
    let exact = rk_order(&t, 8, None);
    assert_eq!(exact.order, 2);
    let f = exact.first_failure.unwrap();
    assert_eq!(f.tree, "[τ²]");
    assert_eq!(f.residual, &dec("0.333333335") - &r(1, 3));
    let loose = rk_order(&t, 8, Some(&dec("0.00000001")));
    assert_eq!(loose.order, 4);
    assert_eq!(loose.first_failure.unwrap().order, 5);
    let tight = rk_order(&t, 8, Some(&dec("0.000000001")));
    assert_eq!(tight.order, 2);
}

#[test]
fn stormer_verlet_pair() {
    let sv = Prk {
        q: rk(rows(&[&[], &[(1, 2), (1, 2)]]), ratios(&[(1, 2), (1, 2)])),
        p: rk(rows(&[&[(1, 2)], &[(1, 2)]]), ratios(&[(1, 2), (1, 2)])),
    };
    assert_order(&prk_order(&sv, 6, None), 2);
    assert_order(&prk_order_separable(&sv, 6, None), 2);
}

#[test]
fn symplectic_euler_pair() {
    let se = Prk {
        q: rk(rows(&[&[]]), ratios(&[(1, 1)])),
        p: rk(rows(&[&[(1, 1)]]), ratios(&[(1, 1)])),
    };
    let general = prk_order(&se, 6, None);
    assert_order(&general, 1);
    assert_eq!(general.first_failure.unwrap().tree, "[τ_q]_q");
    let separable = prk_order_separable(&se, 6, None);
    assert_order(&separable, 1);
    let f = separable.first_failure.unwrap();
    assert_eq!(f.tree, "[τ_p]_q");
    assert_eq!(f.residual, r(1, 2));
}

/// The uncoloured shape of a tree, as a canonical string.
fn shape(f: &Forest, id: usize) -> String {
    let mut kids: Vec<String> = f.tree(id).children.iter().map(|&c| shape(f, c)).collect();
    kids.sort();
    format!("({})", kids.concat())
}

#[test]
fn a_pair_of_equal_tables_is_the_runge_kutta_method() {
    for t in [rk4(), gauss2(), radau_iia3()] {
        let pair = Prk {
            q: t.clone(),
            p: t.clone(),
        };
        assert_eq!(prk_order(&pair, 6, None).order, rk_order(&t, 6, None).order);
        // Every colouring of a tree has the weight of the uncoloured tree.
        let plain = order::rk_elementary_weights(&t, 4);
        let coloured = order::prk_elementary_weights(&pair, 4);
        assert_eq!(coloured.len(), 2 + 4 + 14 + 52);
        // The conditions come in the forests' canonical order.
        let pf = Forest::new(Colouring::Plain, 4);
        let cf = Forest::new(Colouring::Bicoloured, 4);
        let plain_ids: Vec<_> = (1..=4)
            .flat_map(|n| pf.conditions(n).collect::<Vec<_>>())
            .collect();
        let coloured_ids: Vec<_> = (1..=4)
            .flat_map(|n| cf.conditions(n).collect::<Vec<_>>())
            .collect();
        for (c, &id) in coloured.iter().zip(&coloured_ids) {
            assert_eq!(c.tree, cf.bracket(id));
            let k = plain_ids
                .iter()
                .position(|&p| shape(&pf, p) == shape(&cf, id))
                .unwrap();
            assert_eq!(c.value, plain[k].value, "{}", c.tree);
            assert_eq!(c.expected, plain[k].expected);
        }
    }
}

#[test]
fn lobatto_iiia_iiib_pair_with_three_stages() {
    let h = r(1, 2);
    let pair = lobatto_pair(collocation(&[int(0), h, int(1)]));
    let typed_q = rows(&[&[], &[(5, 24), (1, 3), (-1, 24)], &[(1, 6), (2, 3), (1, 6)]]);
    let typed_p = rows(&[&[(1, 6), (-1, 6)], &[(1, 6), (1, 3)], &[(1, 6), (5, 6)]]);
    assert_eq!(pair.q.a, typed_q);
    assert_eq!(pair.p.a, typed_p);
    assert_order(&prk_order(&pair, 8, None), 4);
    assert_order(&prk_order_separable(&pair, 8, None), 4);
    // Lobatto IIIA alone also has order 4.
    assert_order(&rk_order(&pair.q, 8, None), 4);
}

#[test]
fn lobatto_iiia_iiib_pair_has_order_8() {
    let pair = lobatto_pair(lobatto_iiia5());
    let general = prk_order(&pair, 8, None);
    assert_eq!(general.order, 8);
    assert!(general.reached_limit());
    assert_eq!(
        general.conditions_checked,
        2 + 4 + 14 + 52 + 214 + 916 + 4116 + 18996
    );
    let separable = prk_order_separable(&pair, 10, None);
    assert_order(&separable, 8);
}

fn triple_jump() -> Composition {
    let x = (&int(2) - &cbrt(2)).recip().unwrap();
    let mid = &int(1) - &(&int(2) * &x);
    Composition {
        gamma: vec![x.clone(), mid, x],
    }
}

fn forest_ruth() -> Splitting {
    let x = (&int(2) - &cbrt(2)).recip().unwrap();
    let half = r(1, 2);
    let outer = &x * &half;
    let inner = &(&int(1) - &x) * &half;
    Splitting::new(
        vec![outer.clone(), inner.clone(), inner, outer],
        vec![x.clone(), &int(1) - &(&int(2) * &x), x],
    )
}

#[test]
fn forest_ruth_splitting_has_separable_order_4() {
    let report = prk_order_separable(&forest_ruth().to_prk(), 8, None);
    assert_order(&report, 4);
}

#[test]
fn ruth_third_order_splitting() {
    // Ruth (1983): c = (1, −2/3, 2/3) drifts, d = (−1/24, 3/4, 7/24) kicks,
    // applied as D(c₁) K(d₁) D(c₂) K(d₂) D(c₃) K(d₃).
    let ruth = Splitting::new(
        vec![int(1), r(-2, 3), r(2, 3)],
        vec![r(-1, 24), r(3, 4), r(7, 24)],
    );
    assert_order(&prk_order_separable(&ruth.to_prk(), 8, None), 3);
    // Pairing the coefficients the other way round is not a third-order method.
    let swapped = Splitting::new(
        vec![r(-1, 24), r(3, 4), r(7, 24)],
        vec![int(1), r(-2, 3), r(2, 3)],
    );
    assert!(prk_order_separable(&swapped.to_prk(), 8, None).order < 3);
}

#[test]
fn triple_jump_composition_has_order_4_not_5() {
    let report = composition_order(&triple_jump(), 8, None);
    assert_order(&report, 4);
    let f = report.first_failure.unwrap();
    assert_eq!(f.kind, ConditionKind::Word);
    assert_eq!(f.tree, "Y₅");
    // The coefficient of Y₅ is Σγ⁵.
    let sum5 = triple_jump()
        .gamma
        .iter()
        .fold(Number::zero(), |acc, g| &acc + &g.powi(5).unwrap());
    assert_eq!(f.value, sum5);
    assert_eq!(f.residual, sum5);
    // The same verdict from the bicoloured trees of the drift–kick form.
    let prk = triple_jump().to_splitting().to_prk();
    assert_order(&prk_order_separable(&prk, 8, None), 4);
}

#[test]
fn suzuki_fractal_has_order_4() {
    let p = (&int(4) - &cbrt(4)).recip().unwrap();
    let mid = &int(1) - &(&int(4) * &p);
    let suzuki = Composition {
        gamma: vec![p.clone(), p.clone(), mid, p.clone(), p],
    };
    assert_order(&composition_order(&suzuki, 8, None), 4);
    let prk = suzuki.to_splitting().to_prk();
    assert_order(&prk_order_separable(&prk, 7, None), 4);
}

#[test]
fn verlet_alone_and_non_symmetric_compositions() {
    let verlet = Composition {
        gamma: vec![int(1)],
    };
    let report = composition_order(&verlet, 8, None);
    assert_order(&report, 2);
    let f = report.first_failure.unwrap();
    assert_eq!(f.tree, "Y₃");
    assert_eq!(f.residual, int(1));
    let halves = Composition {
        gamma: vec![r(1, 2), r(1, 2)],
    };
    assert_order(&composition_order(&halves, 8, None), 2);
    // Not consistent: Σγ = 2.
    let double = Composition {
        gamma: vec![int(1), int(1)],
    };
    let report = composition_order(&double, 8, None);
    assert_eq!(report.order, 0);
    assert_eq!(report.first_failure.unwrap().tree, "Y₁");
    // A non-palindromic composition of order 2: (1/3, 2/3) has Σγ³ ≠ 0.
    let skew = Composition {
        gamma: vec![r(1, 3), r(2, 3)],
    };
    assert_order(&composition_order(&skew, 8, None), 2);
}

#[test]
fn composition_agrees_with_drift_kick_trees() {
    // Word conditions and separable bicoloured trees give the same order for
    // a few compositions, palindromic or not.
    let cases = [
        vec![r(1, 2), r(1, 2)],
        vec![r(1, 3), r(1, 3), r(1, 3)],
        vec![r(2, 3), r(-1, 3), r(2, 3)],
        vec![r(1, 5), r(3, 5), r(1, 5)],
    ];
    for gamma in cases {
        let c = Composition { gamma };
        let words = composition_order(&c, 6, None);
        let trees = prk_order_separable(&c.to_splitting().to_prk(), 6, None);
        assert_eq!(words.order, trees.order, "{:?}", c.gamma);
    }
}

/// Yoshida's sixth-order composition (solution A) as published with decimals;
/// the middle coefficient is truncated, so `Σγ ≠ 1` exactly.
fn yoshida6() -> Composition {
    let w = [
        dec("0.78451361047755726382"),
        dec("0.23557321335935813368"),
        dec("-1.17767998417887100695"),
        dec("1.3151863206839"),
    ];
    Composition {
        gamma: vec![
            w[0].clone(),
            w[1].clone(),
            w[2].clone(),
            w[3].clone(),
            w[2].clone(),
            w[1].clone(),
            w[0].clone(),
        ],
    }
}

#[test]
fn decimal_compositions_with_and_without_a_bound() {
    let y = yoshida6();
    let exact = composition_order(&y, 8, None);
    assert_eq!(exact.order, 0);
    let f = exact.first_failure.unwrap();
    assert_eq!(f.tree, "Y₁");
    assert_eq!(f.residual, dec("-0.0000000000000112189"));
    let bound = dec("0.000000000001");
    let bounded = composition_order(&y, 8, Some(&bound));
    assert_order(&bounded, 6);
    // The drift–kick form (8 stages) on separable systems agrees.
    let prk = y.to_splitting().to_prk();
    assert_eq!(prk.q.b.len(), 8);
    assert_eq!(prk_order_separable(&prk, 8, None).order, 0);
    assert_order(&prk_order_separable(&prk, 8, Some(&bound)), 6);
}

/// Sofroniou–Spaletta (2005): 35 factors, order 10, 32-digit decimals.
fn sofroniou_spaletta10() -> Composition {
    let half = [
        "0.078795722521686419263907679337684",
        "0.31309610341510852776481247192647",
        "0.027918383235078066109520273275299",
        "-0.22959284159390709415121339679655",
        "0.13096206107716486317465685927961",
        "-0.26973340565451071434460973222411",
        "0.074973343155891435666137105641410",
        "0.11199342399981020488957508073640",
        "0.36613344954622675119314812353150",
        "-0.39910563013603589787862981058340",
        "0.10308739852747107731580277001372",
        "0.41143087395589023782070411897608",
        "-0.0048663605831352617621956593099771",
        "-0.39203335370863990644808193642610",
        "0.051942502962449647037182904015976",
        "0.050665090759924496335874344156866",
        "0.049674370639729879054568800279461",
        "0.049317735759594537917680008339338",
    ];
    let mut gamma: Vec<Number> = half.iter().map(|s| dec(s)).collect();
    let mirror: Vec<Number> = gamma[..17].iter().rev().cloned().collect();
    gamma.extend(mirror);
    Composition { gamma }
}

#[test]
fn sofroniou_spaletta_order_10_within_a_bound() {
    let c = sofroniou_spaletta10();
    assert_eq!(c.gamma.len(), 35);
    let report = composition_order(&c, 12, Some(&dec("0.0000000000000000000001")));
    assert_order(&report, 10);
    assert_eq!(composition_order(&c, 12, None).order, 0);
}

#[test]
fn elementary_weights_line_up() {
    let a = order::rk_elementary_weights(&gauss2(), 5);
    assert_eq!(a.len(), 1 + 1 + 2 + 4 + 9);
    assert_eq!(a[3].tree, "[[τ]]");
    assert_eq!(a[3].expected, r(1, 6));
    // GL2 has order 4: the first 8 hold, some order-5 weight does not.
    assert!(a[..8].iter().all(|c| c.holds(None)));
    assert!(a[8..].iter().any(|c| !c.holds(None)));
    let words = order::composition_coefficients(&triple_jump(), 5);
    // Compositions of 1..5 into odd parts: 1 + 1 + 2 + 3 + 5.
    assert_eq!(words.len(), 12);
    assert_eq!(words[0].tree, "Y₁");
    let sep = order::prk_elementary_weights_separable(&forest_ruth().to_prk(), 4);
    assert_eq!(sep.len(), 2 + 2 + 4 + 8);
}

/// The Nyström conditions are the separable conditions of the trees whose
/// q-vertices have at most one child: the same values, in the same order.
#[test]
fn nystrom_weights_are_the_separable_weights_of_the_nystrom_trees() {
    let mut pairs = vec![
        forest_ruth().to_prk(),
        lobatto_pair(collocation(&[int(0), r(1, 2), int(1)])),
    ];
    pairs.push(Prk { q: rk4(), p: rk4() });
    for pair in &pairs {
        let nystrom = order::prk_elementary_weights_nystrom(pair, 7);
        let separable = order::prk_elementary_weights_separable(pair, 7);
        assert_eq!(nystrom.len(), 2 + 2 + 3 + 5 + 9 + 16 + 30);
        let kept: Vec<_> = separable
            .into_iter()
            .filter(|c| nystrom.iter().any(|n| n.tree == c.tree))
            .collect();
        assert_eq!(kept, nystrom);
    }
    // A Runge–Kutta table: the pair with both tables equal to it.
    assert_eq!(
        order::rk_elementary_weights_nystrom(&rk4(), 7),
        order::prk_elementary_weights_nystrom(&pairs[2], 7)
    );
}

#[test]
fn orders_on_runge_kutta_nystrom_systems() {
    let sv = Prk {
        q: rk(rows(&[&[], &[(1, 2), (1, 2)]]), ratios(&[(1, 2), (1, 2)])),
        p: rk(rows(&[&[(1, 2)], &[(1, 2)]]), ratios(&[(1, 2), (1, 2)])),
    };
    assert_order(&prk_order_nystrom(&sv, 8, None), 2);
    let se = Prk {
        q: rk(rows(&[&[]]), ratios(&[(1, 1)])),
        p: rk(rows(&[&[(1, 1)]]), ratios(&[(1, 1)])),
    };
    let f = prk_order_nystrom(&se, 8, None);
    assert_order(&f, 1);
    assert_eq!(f.first_failure.unwrap().tree, "[τ_p]_q");
    let fr = prk_order_nystrom(&forest_ruth().to_prk(), 8, None);
    assert_order(&fr, 4);
    let f = fr.first_failure.unwrap();
    assert_eq!(f.tree, "[[τ_q³]_p]_q");
    // The triple jump as the drift–kick sequence of its Verlet steps.
    let tj = triple_jump().to_splitting().to_prk();
    assert_order(&prk_order_nystrom(&tj, 8, None), 4);
    for (t, p) in [
        (euler(), 1),
        (heun(), 2),
        (rk4(), 4),
        (gauss2(), 4),
        (gauss3(), 6),
    ] {
        assert_order(&rk_order_nystrom(&t, 8, None), p);
    }
    // Lobatto IIIA–IIIB, 5 stages: order 8 everywhere, at the RKN limit too,
    // with every Nyström tree up to 10 checked.
    let pair = lobatto_pair(lobatto_iiia5());
    let rkn = prk_order_nystrom(&pair, 10, None);
    assert_order(&rkn, 8);
    assert_eq!(rkn.conditions_checked, 2 + 2 + 3 + 5 + 9 + 16 + 30 + 56 + 1);
    let at_limit = prk_order_nystrom(&pair, 8, None);
    assert!(at_limit.reached_limit());
    assert_eq!(
        at_limit.conditions_checked,
        2 + 2 + 3 + 5 + 9 + 16 + 30 + 56
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Perturbing any single entry of RK4 (A with c taken as the row sums, or
    /// b) by a nonzero rational lowers its order below 4.
    #[test]
    fn perturbed_rk4_loses_order(i in 0usize..4, j in 0usize..5, num in -50i64..=50, den in 1i64..200) {
        let mut t = rk4();
        let eps = r(num, den);
        if j == 4 {
            t.b[i] = &t.b[i] + &eps;
        } else {
            t.a[i][j] = &t.a[i][j] + &eps;
        }
        let report = rk_order(&t, 6, None);
        if num == 0 {
            prop_assert_eq!(report.order, 4);
        } else {
            prop_assert!(report.order < 4, "{}", report);
        }
    }
}
