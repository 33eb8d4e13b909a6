//! Real algebraic numbers (`tableau::algebraic`): field axioms under
//! proptest, zero tests that only the point (not the algebra) decides, and
//! identities that floating point or a per-root reduction would get wrong.

use num_bigint::BigInt;
use num_rational::BigRational;
use proptest::prelude::*;
use tableau::algebraic::alg::{Alg, Field};
use tableau::algebraic::file::parse_root;
use tableau::algebraic::poly::Poly;
use tableau::algebraic::root::RealRoot;

fn q(n: i64, d: i64) -> BigRational {
    BigRational::new(BigInt::from(n), BigInt::from(d))
}

/// √2 (var 0), √8 (var 1, = 2√2 but a separate root of x² − 8), the real
/// root of x³ − x − 1 (var 2, the plastic number), and a root of the
/// Gauss-4 node polynomial (var 3, not expressible by real radicals of
/// rationals without nesting).
fn field() -> Field {
    let mut f = Field::default();
    f.push(
        RealRoot::new(&Poly::from_ints(&[-2, 0, 1]), q(1, 1), q(2, 1)).unwrap(),
        "r2",
    );
    f.push(
        RealRoot::new(&Poly::from_ints(&[-8, 0, 1]), q(2, 1), q(3, 1)).unwrap(),
        "r8",
    );
    f.push(
        RealRoot::new(&Poly::from_ints(&[-1, -1, 0, 1]), q(1, 1), q(2, 1)).unwrap(),
        "plastic",
    );
    f.push(
        parse_root("root(70*x^4 - 140*x^3 + 90*x^2 - 20*x + 1, 0, 1/10)").unwrap(),
        "g4",
    );
    f
}

/// A random element: a small polynomial in the four roots.
fn element() -> impl Strategy<Value = Alg> {
    prop::collection::vec(
        (-5i64..=5, 1i64..=4, 0u32..3, 0u32..3, 0u32..3, 0u32..2),
        1..5,
    )
    .prop_map(|terms| {
        let mut a = Alg::zero();
        for (n, d, e0, e1, e2, e3) in terms {
            a = a.add(&Alg::monomial(
                q(n, d),
                &[(0, e0), (1, e1), (2, e2), (3, e3)],
            ));
        }
        a
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn ring_axioms(a in element(), b in element(), c in element()) {
        let f = field();
        // Distributivity, commutativity, associativity: exact zeros.
        let lhs = f.mul(&a.add(&b), &c);
        let rhs = f.mul(&a, &c).add(&f.mul(&b, &c));
        prop_assert!(f.is_zero(&lhs.sub(&rhs)).unwrap());
        prop_assert!(f.is_zero(&f.mul(&a, &b).sub(&f.mul(&b, &a))).unwrap());
        let l = f.mul(&f.mul(&a, &b), &c);
        let r = f.mul(&a, &f.mul(&b, &c));
        prop_assert!(f.is_zero(&l.sub(&r)).unwrap());
        // Additive inverse; sign is antisymmetric and zero exactly on equality.
        prop_assert!(f.is_zero(&a.sub(&a)).unwrap());
        let sab = f.sign(&a.sub(&b)).unwrap();
        let sba = f.sign(&b.sub(&a)).unwrap();
        prop_assert_eq!(sab, -sba);
        prop_assert_eq!(sab == 0, f.is_zero(&a.sub(&b)).unwrap());
    }

    /// √8 = 2√2 holds at the point but not in the algebra (the two roots are
    /// independent variables): any polynomial p gives p(√8) − p(2√2) = 0,
    /// decided exactly; adding 10⁻⁴⁰ makes it nonzero, also decided exactly.
    #[test]
    fn zero_only_through_the_point(cs in prop::collection::vec(-9i64..=9, 2..6)) {
        let f = field();
        let r2 = Alg::monomial(q(1, 1), &[(0, 1)]);
        let r8 = Alg::monomial(q(1, 1), &[(1, 1)]);
        let two_r2 = r2.scale(&q(2, 1));
        let mut p8 = Alg::zero();
        let mut p2 = Alg::zero();
        for (k, c) in cs.iter().enumerate() {
            p8 = p8.add(&f.pow(&r8, k as u32).scale(&q(*c, 1)));
            p2 = p2.add(&f.pow(&two_r2, k as u32).scale(&q(*c, 1)));
        }
        let d = f.reduce(&p8.sub(&p2));
        prop_assert!(f.is_zero(&d).unwrap());
        let tiny = BigRational::new(BigInt::from(1), BigInt::from(10).pow(40));
        let e = d.add(&Alg::rational(tiny));
        prop_assert!(!f.is_zero(&e).unwrap());
        prop_assert_eq!(f.sign(&e).unwrap(), 1);
        prop_assert_eq!(f.to_f64(&e).unwrap(), 1e-40);
    }

    /// Division by an expression in one root: a · a⁻¹ = 1.
    #[test]
    fn inverses(cs in prop::collection::vec(-9i64..=9, 1..4)) {
        let mut f = field();
        let x = Alg::monomial(q(1, 1), &[(3, 1)]);
        let mut a = Alg::rational(q(1, 3));
        for (k, c) in cs.iter().enumerate() {
            a = a.add(&f.pow(&x, k as u32 + 1).scale(&q(*c, 1)));
        }
        let inv = f.inverse(&a).unwrap();
        prop_assert!(f.is_zero(&f.mul(&a, &inv).sub(&Alg::int(1))).unwrap());
    }
}

/// The plastic number ρ satisfies ρ³ = ρ + 1; its powers obey the
/// recurrence ρⁿ⁺³ = ρⁿ⁺¹ + ρⁿ; ρ⁴⁰ − (its expansion in 1, ρ, ρ²) = 0 exactly,
/// and ρ is not 1.3247179572447460 (its f64) exactly.
#[test]
fn identities_floating_point_gets_wrong() {
    let f = field();
    let rho = Alg::monomial(q(1, 1), &[(2, 1)]);
    let r40 = f.pow(&rho, 40);
    // ρⁿ = aₙρ² + bₙρ + cₙ with ρ³ = ρ + 1: a' = b, b' = a + c, c' = a.
    let (mut a, mut b, mut c) = (0i64, 1i64, 0i64);
    for _ in 1..40 {
        (a, b, c) = (b, a + c, a);
    }
    let expansion = f
        .pow(&rho, 2)
        .scale(&q(a, 1))
        .add(&rho.scale(&q(b, 1)))
        .add(&Alg::rational(q(c, 1)));
    assert!(f.is_zero(&r40.sub(&expansion)).unwrap());
    let f64_rho = tableau::rounding::f64_to_rational(1.324_717_957_244_746).unwrap();
    let d = rho.sub(&Alg::rational(f64_rho));
    assert!(!f.is_zero(&d).unwrap());
    assert_eq!(f.to_f64(&rho).unwrap(), 1.324_717_957_244_746);
    // √2·√8 = 4 exactly, though neither factor is rational.
    let r2 = Alg::monomial(q(1, 1), &[(0, 1)]);
    let r8 = Alg::monomial(q(1, 1), &[(1, 1)]);
    assert!(f.is_zero(&f.mul(&r2, &r8).sub(&Alg::int(4))).unwrap());
}

/// A conjugate pair: α + β = 0 for the two roots of x² − 2, not as
/// polynomials but at the point.
#[test]
fn conjugates() {
    let p = Poly::from_ints(&[-2, 0, 1]);
    let mut f = Field::default();
    let a = f.push(RealRoot::new(&p, q(1, 1), q(2, 1)).unwrap(), "a");
    let b = f.push(RealRoot::new(&p, q(-2, 1), q(-1, 1)).unwrap(), "b");
    let s = a.add(&b);
    assert!(!s.is_zero_poly());
    assert!(f.is_zero(&s).unwrap());
    assert_eq!(
        f.to_f64(&a.sub(&b)).unwrap(),
        2.0 * std::f64::consts::SQRT_2
    );
}

#[test]
fn root_syntax_errors_name_the_problem() {
    assert!(
        parse_root("root(x^2 - 2, -2, 2)")
            .unwrap_err()
            .contains("2 distinct real roots")
    );
    assert!(
        parse_root("root(x^2 - 2, 2, 1)")
            .unwrap_err()
            .contains("empty")
    );
    assert!(
        parse_root("root(y^2 - 2, 0, 2)")
            .unwrap_err()
            .contains("unknown name `y`")
    );
    assert!(
        parse_root("root(x^2 - 2, 0)")
            .unwrap_err()
            .contains("three arguments")
    );
    assert!(parse_root("root(3, 0, 1)").unwrap_err().contains("degree"));
}

/// A nonzero Wᵢⱼ beyond the largest double is refused as nonzero and named
/// as beyond the range of f64, never printed as "inf".
#[test]
fn a_w_entry_beyond_f64_is_named_as_such() {
    use tableau::algebraic::file::{Loaded, parse};
    use tableau::claims::Claim;
    let text = "name = \"big\"\nlet = { r = \"root(x^2 - 2, 0, 2)\", t = \"10^64\" }\n\
                a = [[\"r*t^6\", \"0\"], [\"0\", \"1/3\"]]\nb = [\"1/2\", \"1/2\"]\n";
    let Ok(Loaded::Algebraic(f)) = parse("big.toml", text) else {
        panic!("a root file")
    };
    let an = f.analyse();
    assert_eq!(an.symplectic, Some(false));
    let message = f.check_claim(&an, &Claim::Symplectic).unwrap_err();
    assert!(
        message.contains("W[0][0] ≠ 0 (> 1.8e308 beyond the range of f64)"),
        "{message}"
    );
    assert!(!message.contains("inf"), "{message}");
}
