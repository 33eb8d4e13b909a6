//! Generated collocation-type tables: the literature's verdicts, decided
//! exactly; agreement with the hand-written catalogue tables and with the
//! rooted-tree checker where the nodes are radicals; correct rounding against
//! 100-digit values computed independently (mpmath, see
//! `data/gauss8_mpmath.py`); the refusal of a perturbed Gauss-6 table written
//! out entry by entry with `root(...)` nodes.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};
use tableau::Table;
use tableau::algebraic::family::{Family, Generator, Method, PairMethod};
use tableau::algebraic::file::{Loaded, parse};
use tableau::algebraic::generated::{Generated, GeneratedTable};
use tableau::analysis::Analysis;
use tableau::claims::Claim;
use tableau::number::rational_to_f64;
use tableau::rounding::f64_to_rational;

/// Every family, s = 1 (or 2) … 8: the verdicts of Hairer–Wanner II,
/// Table IV.5.13 and Sect. IV.3–5: simplifying assumptions, order,
/// symplecticity (Gauss only), symmetry (Gauss, Lobatto IIIA and IIIB),
/// A-stability for all, L-stability (R(∞) = 0) for Radau IA/IIA and Lobatto
/// IIIC, |R(iy)| = 1 for the symmetric ones.
#[test]
fn literature_verdicts_for_every_family_up_to_8_stages() {
    for fam in Family::ALL {
        let s0 = if matches!(fam, Family::Gauss | Family::Radau2A) {
            1
        } else {
            2
        };
        for s in s0..=8 {
            let m = Method::new(fam, s);
            let v = m.verdicts();
            let what = format!("{fam:?} s = {s}");
            let (c, d) = match fam {
                Family::Gauss => (s, s),
                Family::Radau2A => (s, s - 1),
                Family::Radau1A => (s - 1, s),
                Family::Lobatto3A => (s, s - 2),
                Family::Lobatto3B => (s - 2, s),
                Family::Lobatto3C => (s - 1, s - 1),
            };
            let p = fam.literature_order(s);
            assert_eq!(v.order.b, p, "{what}: B");
            assert_eq!(v.order.c, c, "{what}: C");
            assert_eq!(v.order.d, d, "{what}: D");
            if fam == Family::Lobatto3B && s == 2 {
                // c = (0, 1) is not the row sums (1/2, 1/2): the theorem does
                // not apply.
                assert!(!v.row_sums_ok);
                assert_eq!(v.order.lower, 0);
            } else {
                assert!(v.row_sums_ok, "{what}");
                assert_eq!(v.order.lower, p, "{what}: order lower bound");
                assert_eq!(v.order.upper, Some(p), "{what}: order upper bound");
            }
            assert_eq!(v.symplectic, fam == Family::Gauss, "{what}: symplectic");
            let symmetric = matches!(fam, Family::Gauss | Family::Lobatto3A | Family::Lobatto3B);
            assert_eq!(v.symmetric, symmetric, "{what}: symmetric");
            assert!(v.a_stable, "{what}: A-stable");
            assert_eq!(v.unimodular, symmetric, "{what}: |R(iy)| = 1");
            let l_stable = matches!(fam, Family::Radau1A | Family::Radau2A | Family::Lobatto3C);
            assert_eq!(v.r_infinity.is_zero(), l_stable, "{what}: R(∞)");
        }
    }
}

#[test]
fn lobatto_pair_is_symplectic_and_its_halves_are_not() {
    for s in 2..=8 {
        let pair = PairMethod::new(s);
        let v = pair.verdicts();
        assert!(v.symplectic, "s = {s}");
        assert!(v.symmetric, "s = {s}");
        assert!(!v.q.symplectic && !v.p.symplectic, "s = {s}");
    }
}

/// The pair's order on general partitioned systems, by bicoloured trees,
/// where the nodes are radicals (s ≤ 5): 2s − 2.
#[test]
fn lobatto_pair_order_by_bicoloured_trees() {
    for s in 2..=4 {
        let g = Generated::new(&format!("lobatto3a3b({s})")).unwrap();
        let t = g.tree_order.as_ref().expect("radical nodes");
        assert_eq!(t.order, 2 * s - 2, "s = {s}");
        assert!(
            g.check_claim(&Claim::Order {
                p: 2 * s - 2,
                bound: None
            })
            .is_ok()
        );
        assert!(
            g.check_claim(&Claim::Order {
                p: 2 * s - 1,
                bound: None
            })
            .is_err()
        );
    }
    // s = 6 needs nested radicals: the pair's order is not proven.
    let g = Generated::new("lobatto3a3b6").unwrap();
    assert!(g.tree_order.is_none());
    assert!(g.check_claim(&Claim::Order { p: 10, bound: None }).is_err());
}

/// The generators reproduce the hand-written catalogue tables exactly
/// (entries as numbers in Q(√d)).
#[test]
fn generated_tables_equal_the_catalogue() {
    let cases: [(&str, Family, usize); 12] = [
        ("midpoint", Family::Gauss, 1),
        ("gauss1", Family::Gauss, 1),
        ("gauss2", Family::Gauss, 2),
        ("gauss3", Family::Gauss, 3),
        ("implicit-euler", Family::Radau2A, 1),
        ("radau2a-2", Family::Radau2A, 2),
        ("radau2a-3", Family::Radau2A, 3),
        ("lobatto3a-2", Family::Lobatto3A, 2),
        ("lobatto3a-3", Family::Lobatto3A, 3),
        ("lobatto3b-3", Family::Lobatto3B, 3),
        ("lobatto3c-2", Family::Lobatto3C, 2),
        ("lobatto3c-3", Family::Lobatto3C, 3),
    ];
    for (id, fam, s) in cases {
        let tf = tableau::catalogue::load(id).unwrap();
        let Table::Rk(rk) = &tf.table else {
            panic!("{id}")
        };
        let gen_table = Method::new(fam, s)
            .radical_table()
            .unwrap_or_else(|| panic!("{id}: no radical form"));
        assert_eq!(rk.a, gen_table.a, "{id}: A");
        assert_eq!(rk.b, gen_table.b, "{id}: b");
        assert_eq!(rk.abscissae(), gen_table.c.clone().unwrap(), "{id}: c");
    }
    // lobatto3b-2 in the catalogue gives c = (0, 1) explicitly.
    let tf = tableau::catalogue::load("lobatto3b-2").unwrap();
    let Table::Rk(rk) = &tf.table else { panic!() };
    let generated = Method::new(Family::Lobatto3B, 2).radical_table().unwrap();
    assert_eq!((&rk.a, &rk.b), (&generated.a, &generated.b));
    let tf = tableau::catalogue::load("lobatto3a3b-3").unwrap();
    let Table::Prk(prk) = &tf.table else { panic!() };
    let pair = PairMethod::new(3);
    assert_eq!(prk.q.a, pair.q.radical_table().unwrap().a);
    assert_eq!(prk.p.a, pair.p.radical_table().unwrap().a);
}

/// Where the nodes are radicals, the tree-based analysis of `crate::analysis`
/// gives the same verdicts as the product-of-fields route.
#[test]
fn tree_analysis_agrees_where_the_nodes_are_radicals() {
    let mut checked = 0;
    for fam in Family::ALL {
        for s in 2..=5 {
            let m = Method::new(fam, s);
            let Some(rk) = m.radical_table() else {
                continue;
            };
            let v = m.verdicts();
            let a = Analysis::of(&Table::Rk(rk)).unwrap();
            let what = format!("{fam:?} s = {s}");
            assert_eq!(a.symplectic, v.symplectic, "{what}");
            assert_eq!(a.symmetric, v.symmetric, "{what}");
            if v.row_sums_ok {
                assert_eq!(
                    a.order.as_ref().unwrap().order,
                    v.order.lower.min(10),
                    "{what}"
                );
            }
            assert_eq!(
                a.stability.as_ref().map(|r| r.to_text()),
                Some(v.stability.to_text()),
                "{what}"
            );
            checked += 1;
        }
    }
    assert!(checked >= 12, "{checked}");
}

fn mpmath_values() -> Vec<(String, Vec<usize>, BigRational)> {
    let text = include_str!("data/gauss8_100digits.txt");
    text.lines()
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            let idx: Vec<usize> = f[1..f.len() - 1]
                .iter()
                .map(|x| x.parse().unwrap())
                .collect();
            let v = tableau::expr::parse_number(f[f.len() - 1])
                .unwrap()
                .as_rational()
                .unwrap();
            (f[0].to_string(), idx, v)
        })
        .collect()
}

/// Correct rounding of every Gauss-8 coefficient, checked against 100-digit
/// values computed independently (mpmath): the certified `f64` equals the
/// `f64` nearest to the 100-digit value (no coefficient is within 10⁻⁹⁰ of a
/// rounding boundary, which the test also checks).
#[test]
fn gauss8_rounds_correctly_against_100_digit_values() {
    let m = Method::new(Family::Gauss, 8);
    let t = m.nearest_f64();
    let vals = mpmath_values();
    assert_eq!(vals.len(), 8 + 8 + 64);
    let tol = BigRational::new(BigInt::one(), BigInt::from(10).pow(90));
    for (kind, idx, v) in vals {
        let ours = match kind.as_str() {
            "c" => t.c[idx[0]],
            "b" => t.b[idx[0]],
            _ => t.a[idx[0]][idx[1]],
        };
        // The value ± 1e-90 rounds the same way: the nearest double is
        // determined by the 100-digit value.
        let lo = rational_to_f64(&(&v - &tol));
        let hi = rational_to_f64(&(&v + &tol));
        assert_eq!(lo, hi, "{kind}{idx:?} too close to a rounding boundary");
        assert_eq!(ours, lo, "{kind}{idx:?}");
    }
}

/// The symplecticity-aware rounding: weights sum to exactly 1.0, every entry
/// is a faithful rounding (within one ulp of the 100-digit value), and the
/// exact `max |Wᵢⱼ|` of the doubles is no larger than that of the plain
/// correct rounding.
#[test]
fn gauss8_symplectic_rounding() {
    let m = Method::new(Family::Gauss, 8);
    let near = m.nearest_f64();
    let r = m.rounded_f64(true);
    assert_eq!(r.b.iter().fold(0.0, |a, &b| a + b), 1.0);
    for (kind, idx, v) in mpmath_values() {
        let x = match kind.as_str() {
            "c" => r.c[idx[0]],
            "b" => r.b[idx[0]],
            _ => r.a[idx[0]][idx[1]],
        };
        let err = (f64_to_rational(x).unwrap() - &v).abs();
        let ulp = f64_to_rational(f64::EPSILON * rational_to_f64(&v).abs()).unwrap();
        assert!(err <= ulp, "{kind}{idx:?}");
    }
    let (wr, wn) = (
        tableau::rounding::max_abs_w(&r),
        tableau::rounding::max_abs_w(&near),
    );
    assert!(wr <= wn, "{wr:e} > {wn:e}");
    assert!(wr < 4e-18, "{wr:e}");
}

/// `symlab check --builtin gauss8` content: the literature's claims hold and
/// the order proof is the simplifying-assumption one.
#[test]
fn gauss8_generated_report() {
    let g = Generated::new("gauss8").unwrap();
    assert_eq!(g.generator, Generator::Rk(Family::Gauss, 8));
    assert!(g.symplectic && g.symmetric && g.row_sums_ok);
    assert_eq!(g.proven_order(), 16);
    assert!(
        g.order.text.contains("B(16), C(8), D(8)"),
        "{}",
        g.order.text
    );
    assert!(g.order.text.contains("B(17) fails"), "{}", g.order.text);
    assert!(g.claims.iter().all(|(_, v)| v.is_ok()));
    assert!(
        g.check_claim(&Claim::Order { p: 17, bound: None })
            .unwrap_err()
            .0
            .contains("at most 16")
    );
    let GeneratedTable::Rk(t) = &g.f64_table else {
        panic!()
    };
    assert_eq!(t.a.len(), 8);
    let radau = Generated::new("radau2a5").unwrap();
    assert!(!radau.symplectic);
    assert!(radau.check_claim(&Claim::Symplectic).is_err());
    assert_eq!(radau.proven_order(), 9);
}

const GAUSS6_ROOTS: &str = include_str!("fixtures/gauss6_roots.toml");
const GAUSS6_ROOTS_PERTURBED: &str = include_str!("fixtures/gauss6_roots_perturbed.toml");

/// The fixtures are what the exporter writes (provenance), entry by entry.
#[test]
fn gauss6_root_fixtures_are_reproducible() {
    let m = Method::new(Family::Gauss, 6);
    assert_eq!(
        m.to_root_file(GAUSS6_NAME, &["symplectic"], None),
        GAUSS6_ROOTS
    );
    assert_eq!(
        m.to_root_file(
            GAUSS6_PERTURBED_NAME,
            &["symplectic"],
            Some((0, 1, "1e-30"))
        ),
        GAUSS6_ROOTS_PERTURBED
    );
}

const GAUSS6_NAME: &str = "Gauss–Legendre 6, entries as polynomials in root(...) nodes";
const GAUSS6_PERTURBED_NAME: &str =
    "Gauss–Legendre 6, entries as polynomials in root(...) nodes, a[0][1] perturbed by 1e-30";

/// Written out entry by entry, Gauss-6 is symplectic exactly: all 21 Wᵢⱼ are
/// zero, each only at the point (not as polynomials in independent roots).
#[test]
fn gauss6_written_out_is_symplectic() {
    let Loaded::Algebraic(f) = parse("gauss6_roots.toml", GAUSS6_ROOTS).unwrap() else {
        panic!()
    };
    let an = f.analyse();
    assert_eq!(an.w.len(), 21);
    assert_eq!(an.symplectic, Some(true));
    assert!(f.check_claim(&an, &Claim::Symplectic).is_ok());
}

/// One entry perturbed by 1e-30: the symplecticity claim is refused, exactly,
/// naming W[0][1] (= b₀·10⁻³⁰ ≈ 8.57e-32) and no other entry.
#[test]
fn gauss6_perturbed_by_1e_30_is_refused_naming_the_w_entry() {
    let Loaded::Algebraic(f) =
        parse("gauss6_roots_perturbed.toml", GAUSS6_ROOTS_PERTURBED).unwrap()
    else {
        panic!()
    };
    let an = f.analyse();
    assert_eq!(an.symplectic, Some(false));
    let nonzero: Vec<_> = an.w.iter().filter(|e| e.zero != Some(true)).collect();
    assert_eq!(nonzero.len(), 1);
    assert_eq!((nonzero[0].i, nonzero[0].j), (0, 1));
    let err = f.check_claim(&an, &Claim::Symplectic).unwrap_err();
    assert!(
        err.contains("W[0][1] ≠ 0 (≈ 8.566224618958517e-32)"),
        "{err}"
    );
}
