//! Rounding verified tables to `f64` (`tableau::rounding`): every emitted
//! entry is within one ulp of its exact value (checked exactly), weights sum
//! to exactly `1.0` left to right, `max |W|` of the emitted coefficients is no
//! larger than that of the plain correct roundings, and symmetric weight
//! vectors stay palindromes. Run with `--nocapture` to see `max |W|` before
//! and after.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::One;
use proptest::prelude::*;
use tableau::analysis::Analysis;
use tableau::analysis::symplectic::{vanishes, w_matrix};
use tableau::catalogue;
use tableau::expr::parse_number;
use tableau::rounding::{
    F64Pair, F64Rounded, F64Table, f64_to_rational, max_abs_w, max_abs_w_pair, nearest_prk,
    nearest_rk, round_composition, round_prk, round_rk, round_splitting, round_table,
    round_weights, sum_left_to_right,
};
use tableau::{Number, Prk, Rk, Table};

// ---------------------------------------------------------------------------
// Exact checks, written independently of the module under test.

fn exact(x: f64) -> Number {
    Number::from_rational(f64_to_rational(x).expect("finite"))
}

fn pow2(e: i64) -> Number {
    let r = if e >= 0 {
        BigRational::from_integer(BigInt::one() << e as usize)
    } else {
        BigRational::new(BigInt::one(), BigInt::one() << (-e) as usize)
    };
    Number::from_rational(r)
}

/// `ulp(x) = 2^max(e − 52, −1074)` for `2^e ≤ |x| < 2^(e+1)`.
fn ulp_of(x: &Number) -> Number {
    let ax = x.abs();
    let approx = x.to_f64().abs();
    assert!(approx.is_finite() && !x.is_zero());
    let mut e = if approx == 0.0 {
        -1075
    } else {
        approx.log2().floor() as i64
    };
    // Correct the estimate exactly.
    while ax < pow2(e) {
        e -= 1;
    }
    while ax >= pow2(e + 1) {
        e += 1;
    }
    pow2((e - 52).max(-1074))
}

/// `|emitted − x| ≤ 1 ulp(x)`, exactly.
fn assert_within_ulp(emitted: f64, x: &Number, what: &str) {
    assert!(emitted.is_finite(), "{what}: {emitted} is not finite");
    if x.is_zero() {
        assert_eq!(emitted, 0.0, "{what}: an exact zero must stay zero");
        return;
    }
    let err = (exact(emitted) - x).abs();
    assert!(
        err <= ulp_of(x),
        "{what}: emitted {emitted:e} is {} ulp from the exact {x}",
        err.to_f64() / ulp_of(x).to_f64()
    );
}

fn assert_vec_within(emitted: &[f64], x: &[Number], what: &str) {
    assert_eq!(emitted.len(), x.len(), "{what}: length");
    for (i, (e, x)) in emitted.iter().zip(x).enumerate() {
        assert_within_ulp(*e, x, &format!("{what}[{i}]"));
    }
}

fn assert_rk_within(emitted: &F64Table, rk: &Rk, what: &str) {
    for (i, (row, exact_row)) in emitted.a.iter().zip(&rk.a).enumerate() {
        assert_vec_within(row, exact_row, &format!("{what}.a[{i}]"));
    }
    assert_vec_within(&emitted.b, &rk.b, &format!("{what}.b"));
    // c is the correct rounding of the exact abscissae, not an f64 row sum.
    let c: Vec<f64> = rk.abscissae().iter().map(Number::to_f64).collect();
    assert_eq!(emitted.c, c, "{what}.c");
}

fn exact_sum(x: &[Number]) -> Number {
    x.iter().fold(Number::zero(), |acc, y| acc + y)
}

/// The weights sum to exactly 1.0 left to right whenever their exact sum is 1.
fn assert_sums_to_one(w: &[f64], x: &[Number], what: &str) {
    if exact_sum(x).is_one() {
        let sum: f64 = w.iter().sum();
        let mut left_to_right = 0.0;
        for v in w {
            left_to_right += v;
        }
        assert_eq!(
            left_to_right, 1.0,
            "{what}: {w:?} sums to {left_to_right:e}"
        );
        assert_eq!(sum, 1.0, "{what}: Iterator::sum");
        assert_eq!(sum_left_to_right(w), 1.0, "{what}: sum_left_to_right");
    }
}

fn assert_palindrome(w: &[f64], what: &str) {
    let rev: Vec<f64> = w.iter().rev().copied().collect();
    assert_eq!(w, rev.as_slice(), "{what} is not a palindrome in f64");
}

fn load(id: &str) -> Table {
    catalogue::load(id).unwrap_or_else(|e| panic!("{e}")).table
}

fn rk_of(id: &str) -> Rk {
    match load(id) {
        Table::Rk(rk) => rk,
        t => panic!("{id} is not an RK table: {t:?}"),
    }
}

fn prk_of(id: &str) -> Prk {
    match load(id) {
        Table::Prk(prk) => prk,
        t => panic!("{id} is not a pair: {t:?}"),
    }
}

/// `max |W|` of the plain correct roundings and of the adjusted table; both
/// printed, and the second must not exceed the first.
fn compare_rk(id: &str, rk: &Rk) -> (f64, f64) {
    let plain = max_abs_w(&nearest_rk(rk));
    let rounded = round_rk(rk, true, true);
    let adjusted = max_abs_w(&rounded);
    println!("{id}: max|W| correctly rounded = {plain:e}, adjusted = {adjusted:e}");
    assert!(adjusted <= plain, "{id}: adjusting made W worse");
    (plain, adjusted)
}

fn compare_prk(id: &str, prk: &Prk) -> (f64, f64) {
    let plain = max_abs_w_pair(&nearest_prk(prk));
    let adjusted = max_abs_w_pair(&round_prk(prk, true, true));
    println!(
        "{id}: max|bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ| correctly rounded = {plain:e}, adjusted = {adjusted:e}"
    );
    assert!(
        adjusted <= plain,
        "{id}: adjusting made the condition worse"
    );
    (plain, adjusted)
}

// ---------------------------------------------------------------------------
// The named tables

fn num(s: &str) -> Number {
    parse_number(s).unwrap_or_else(|e| panic!("{s}: {e}"))
}

#[test]
fn gauss2_typed_in() {
    let rk = Rk {
        a: vec![
            vec![num("1/4"), num("1/4 - sqrt(3)/6")],
            vec![num("1/4 + sqrt(3)/6"), num("1/4")],
        ],
        b: vec![num("1/2"), num("1/2")],
        c: None,
    };
    assert_eq!(rk, rk_of("gauss2"));
    let t = round_rk(&rk, true, true);
    assert_rk_within(&t, &rk, "gauss2");
    assert_sums_to_one(&t.b, &rk.b, "gauss2.b");
    assert_palindrome(&t.b, "gauss2.b");
    compare_rk("gauss2", &rk);
}

#[test]
fn gauss_tables() {
    for id in ["gauss1", "gauss2", "gauss3"] {
        let rk = rk_of(id);
        let t = round_rk(&rk, true, true);
        assert_rk_within(&t, &rk, id);
        assert_sums_to_one(&t.b, &rk.b, &format!("{id}.b"));
        assert_palindrome(&t.b, &format!("{id}.b"));
        let (plain, adjusted) = compare_rk(id, &rk);
        // The diagonal is exactly b/2 where that is exact, and the
        // off-diagonal pairs can be fixed to within rounding of W.
        assert!(adjusted <= plain);
        let s = t.b.len();
        for i in 0..s {
            if rk.a[i][i] == rk.b[i].checked_div(&Number::from(2)).unwrap() {
                assert_eq!(t.a[i][i], t.b[i] / 2.0, "{id}: a[{i}][{i}] = b[{i}]/2");
            }
        }
    }
}

#[test]
fn gauss3_adjusted_is_strictly_better() {
    let (plain, adjusted) = compare_rk("gauss3", &rk_of("gauss3"));
    assert!(adjusted < plain, "gauss3: {adjusted:e} vs {plain:e}");
}

#[test]
fn lobatto_pair() {
    let id = "lobatto3a3b-3";
    let prk = prk_of(id);
    let t = round_prk(&prk, true, true);
    assert_rk_within(&t.q, &prk.q, &format!("{id}.q"));
    assert_rk_within(&t.p, &prk.p, &format!("{id}.p"));
    assert_sums_to_one(&t.q.b, &prk.q.b, &format!("{id}.b"));
    assert_sums_to_one(&t.p.b, &prk.p.b, &format!("{id}.b_hat"));
    assert_palindrome(&t.q.b, &format!("{id}.b"));
    assert_palindrome(&t.p.b, &format!("{id}.b_hat"));
    assert_eq!(t.q.b, t.p.b, "b = b̂ exactly, so also in f64");
    compare_prk(id, &prk);
    // Structural zeros stay zero (the explicit first row of Lobatto IIIA, the
    // last column of IIIB).
    assert_eq!(t.q.a[0], vec![0.0; 3]);
    for row in &t.p.a {
        assert_eq!(row[2], 0.0);
    }
}

#[test]
fn rk4_weights() {
    let rk = rk_of("rk4");
    let t = round_rk(&rk, false, false);
    assert_rk_within(&t, &rk, "rk4");
    assert_sums_to_one(&t.b, &rk.b, "rk4.b");
    // 1/6 + 1/3 + 1/3 + 1/6 rounds to 1 − 2⁻⁵³; one entry moves.
    let plain = nearest_rk(&rk);
    assert_ne!(sum_left_to_right(&plain.b), 1.0);
    assert_eq!(plain.b.iter().zip(&t.b).filter(|(x, y)| x != y).count(), 1);
    // Not symplectic: A is left as correctly rounded.
    assert_eq!(t.a, nearest_rk(&rk).a);
}

#[test]
fn forest_ruth() {
    let Table::Splitting(s) = load("forest-ruth") else {
        panic!("forest-ruth is a drift–kick sequence")
    };
    let t = round_splitting(&s, true);
    assert_vec_within(&t.drift, &s.drift, "forest-ruth.drift");
    assert_vec_within(&t.kick, &s.kick, "forest-ruth.kick");
    assert_sums_to_one(&t.drift, &s.drift, "forest-ruth.drift");
    assert_sums_to_one(&t.kick, &s.kick, "forest-ruth.kick");
    assert_palindrome(&t.drift, "forest-ruth.drift");
    assert_palindrome(&t.kick, "forest-ruth.kick");
    println!("forest-ruth: drift {:?}, kick {:?}", t.drift, t.kick);
}

#[test]
fn compositions() {
    for id in ["yoshida4", "yoshida6", "kahan-li6", "kahan-li8"] {
        let Table::Composition(c) = load(id) else {
            panic!("{id} is a composition")
        };
        let t = round_composition(&c, true);
        let split = c.to_splitting();
        assert_vec_within(&t.gamma, &c.gamma, &format!("{id}.gamma"));
        assert_vec_within(&t.splitting.drift, &split.drift, &format!("{id}.drift"));
        assert_eq!(t.splitting.kick, t.gamma, "{id}: the kicks are γ");
        assert_sums_to_one(&t.gamma, &c.gamma, &format!("{id}.gamma"));
        assert_sums_to_one(&t.splitting.drift, &split.drift, &format!("{id}.drift"));
        assert_palindrome(&t.gamma, &format!("{id}.gamma"));
        assert_palindrome(&t.splitting.drift, &format!("{id}.drift"));
        let plain: Vec<f64> = c.gamma.iter().map(Number::to_f64).collect();
        let moved = plain.iter().zip(&t.gamma).filter(|(a, b)| a != b).count();
        println!(
            "{id}: γ correctly rounded sums to {:e}; {moved} entries moved",
            sum_left_to_right(&plain)
        );
    }
}

#[test]
fn round_table_follows_the_analysis() {
    let table = load("gauss2");
    let analysis = Analysis::of(&table).unwrap();
    let Table::Rk(rk) = &table else {
        unreachable!()
    };
    assert_eq!(
        round_table(&table, &analysis),
        F64Rounded::Rk(round_rk(rk, true, true))
    );
}

/// As [`assert_sums_to_one`] for the palindromic weights of a symmetric
/// table, except where no palindromic choice of faithful roundings sums to
/// `1.0` (brute force): there `round_weights` keeps the correct roundings, as
/// documented. In the catalogue that happens once, for the twelve kicks of
/// Blanes–Moan's SRKN₁₁ᵇ, which sum to `1 − 2⁻⁵³`.
fn assert_sums_to_one_palindromic(w: &[f64], x: &[Number], what: &str) {
    if exact_sum(x).is_one() && sum_left_to_right(w) != 1.0 && fewest_moves(x, true).is_none() {
        let plain: Vec<f64> = x.iter().map(Number::to_f64).collect();
        assert_eq!(
            w,
            plain.as_slice(),
            "{what}: the correct roundings are kept"
        );
        println!("{what}: no palindromic faithful rounding sums to 1.0");
        return;
    }
    assert_sums_to_one(w, x, what);
}

/// Every table of the catalogue: entries within one ulp, weights summing to
/// one (for drift–kick sequences and compositions, where a palindromic
/// rounding can), and for tables symplectic as written no worse a W than the
/// plain rounding.
#[test]
fn whole_catalogue() {
    for entry in catalogue::entries() {
        let id = entry.id;
        match load(id) {
            Table::Rk(rk) => {
                let symplectic = vanishes(&w_matrix(&rk, &rk));
                let t = round_rk(&rk, symplectic, true);
                assert_rk_within(&t, &rk, id);
                assert_sums_to_one(&t.b, &rk.b, id);
                if symplectic {
                    compare_rk(id, &rk);
                }
            }
            Table::Prk(prk) => {
                let symplectic = vanishes(&w_matrix(&prk.q, &prk.p));
                let t: F64Pair = round_prk(&prk, symplectic, true);
                assert_rk_within(&t.q, &prk.q, id);
                assert_rk_within(&t.p, &prk.p, id);
                assert_sums_to_one(&t.q.b, &prk.q.b, id);
                assert_sums_to_one(&t.p.b, &prk.p.b, id);
                if symplectic {
                    compare_prk(id, &prk);
                }
            }
            Table::Splitting(s) => {
                let t = round_splitting(&s, true);
                assert_vec_within(&t.drift, &s.drift, id);
                assert_vec_within(&t.kick, &s.kick, id);
                assert_sums_to_one_palindromic(&t.drift, &s.drift, id);
                assert_sums_to_one_palindromic(&t.kick, &s.kick, id);
            }
            Table::Composition(c) => {
                let t = round_composition(&c, true);
                assert_vec_within(&t.gamma, &c.gamma, id);
                assert_sums_to_one_palindromic(&t.gamma, &c.gamma, id);
                let split = c.to_splitting();
                assert_vec_within(&t.splitting.drift, &split.drift, id);
                assert_sums_to_one_palindromic(&t.splitting.drift, &split.drift, id);
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Random weight vectors

fn rational(n: i64, d: i64) -> Number {
    Number::ratio(n, d).unwrap()
}

/// `parts` as rationals and a last entry making the exact sum `total`.
fn completed(parts: &[(i64, i64)], total: Number) -> Vec<Number> {
    let mut w: Vec<Number> = parts.iter().map(|&(n, d)| rational(n, d)).collect();
    let last = total - exact_sum(&w);
    w.push(last);
    w
}

/// The faithful roundings of `x` (the doubles within one ulp), by the test's
/// own `ulp_of`; the correct rounding first.
fn faithful(x: &Number) -> Vec<f64> {
    let r = x.to_f64();
    if x.is_zero() {
        return vec![r];
    }
    let mut out = vec![r];
    for f in [r.next_down(), r.next_up()] {
        if (exact(f) - x).abs() <= ulp_of(x) {
            out.push(f);
        }
    }
    out
}

/// Brute force: the fewest entries that must move to a faithful rounding for
/// the left-to-right sum to be `1.0` (`Some(0)` if none need to), or `None`
/// if no choice works. With `symmetric`, mirror entries with equal exact
/// values take equal doubles.
fn fewest_moves(w: &[Number], symmetric: bool) -> Option<usize> {
    let n = w.len();
    let options: Vec<Vec<f64>> = w.iter().map(faithful).collect();
    let mut best: Option<usize> = None;
    let mut choice = vec![0usize; n];
    loop {
        let tied =
            symmetric && (0..n).any(|i| w[i] == w[n - 1 - i] && choice[i] != choice[n - 1 - i]);
        if !tied {
            let f: Vec<f64> = (0..n).map(|i| options[i][choice[i]]).collect();
            if sum_left_to_right(&f) == 1.0 {
                let moved = choice.iter().filter(|&&k| k > 0).count();
                best = Some(best.map_or(moved, |b| b.min(moved)));
            }
        }
        // Next choice, odometer style.
        let mut i = 0;
        while i < n {
            choice[i] += 1;
            if choice[i] < options[i].len() {
                break;
            }
            choice[i] = 0;
            i += 1;
        }
        if i == n {
            return best;
        }
    }
}

/// (a) every entry within one ulp; (b) the sum is `1.0` exactly when some
/// faithful rounding achieves it, with the fewest moves; (d) palindromes stay
/// palindromes.
fn check_weights(w: &[Number], symmetric: bool) -> Result<(), TestCaseError> {
    let f = round_weights(w, symmetric);
    assert_vec_within(&f, w, "w");
    let plain: Vec<f64> = w.iter().map(Number::to_f64).collect();
    let moved = plain.iter().zip(&f).filter(|(x, y)| x != y).count();
    match fewest_moves(w, symmetric) {
        Some(fewest) => {
            prop_assert_eq!(sum_left_to_right(&f), 1.0, "{:?} from {:?}", f, w);
            prop_assert_eq!(
                moved,
                fewest,
                "{:?} moved {} entries, {} suffice",
                w,
                moved,
                fewest
            );
        }
        None => prop_assert_eq!(&f, &plain, "no faithful rounding of {:?} sums to 1", w),
    }
    if symmetric {
        let mirrored: Vec<f64> = f.iter().rev().copied().collect();
        prop_assert_eq!(f, mirrored);
    }
    Ok(())
}

fn no_persistence(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(no_persistence(512))]

    /// Mixed signs: random rationals and a last entry completing the sum to 1.
    #[test]
    fn random_weights(parts in prop::collection::vec((-60i64..60, 1i64..97), 0..8)) {
        check_weights(&completed(&parts, Number::one()), false)?;
    }

    /// Positive weights `pᵢ / Σp`, the usual case for collocation methods.
    #[test]
    fn random_positive_weights(parts in prop::collection::vec((1i64..200, 1i64..97), 1..9)) {
        let p: Vec<Number> = parts.iter().map(|&(n, d)| rational(n, d)).collect();
        let total = exact_sum(&p);
        let w: Vec<Number> = p.iter().map(|x| x.checked_div(&total).unwrap()).collect();
        check_weights(&w, false)?;
    }

    /// Palindromes: half, [middle], reversed half, with exact sum 1.
    #[test]
    fn random_symmetric_weights(
        parts in prop::collection::vec((-60i64..60, 1i64..97), 1..5),
        middle in any::<bool>(),
    ) {
        let half: Vec<Number> = if middle {
            parts.iter().map(|&(n, d)| rational(n, d)).collect()
        } else {
            completed(&parts[1..], rational(1, 2))
        };
        let mut w = half.clone();
        if middle {
            w.push(Number::one() - exact_sum(&half) - exact_sum(&half));
        }
        w.extend(half.iter().rev().cloned());
        prop_assert!(exact_sum(&w).is_one());
        check_weights(&w, true)?;
    }

    #[test]
    fn weights_not_summing_to_one_are_left_alone(parts in prop::collection::vec((-60i64..60, 1i64..97), 1..12)) {
        let w: Vec<Number> = parts.iter().map(|&(n, d)| rational(n, d)).collect();
        prop_assume!(!exact_sum(&w).is_one());
        let f = round_weights(&w, false);
        let plain: Vec<f64> = w.iter().map(Number::to_f64).collect();
        prop_assert_eq!(f, plain);
    }
}

#[test]
fn exact_conversion_of_doubles() {
    for x in [
        0.0,
        -0.0,
        1.0,
        -0.1,
        1.0 / 3.0,
        f64::MAX,
        f64::MIN_POSITIVE,
        f64::MIN_POSITIVE / 3.0,
        5e-324,
        -1e300,
    ] {
        let r = f64_to_rational(x).unwrap();
        assert_eq!(Some(r.clone()), BigRational::from_float(x), "{x:e}");
        assert_eq!(tableau::number::rational_to_f64(&r), x, "{x:e}");
    }
    assert_eq!(f64_to_rational(f64::INFINITY), None);
    assert_eq!(f64_to_rational(f64::NAN), None);
}
