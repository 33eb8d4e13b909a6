//! The expression grammar: exact values, identities between radicals,
//! round trips through the canonical text, and errors (never panics) with
//! the right positions.

use num_bigint::BigInt;
use num_rational::BigRational;
use proptest::prelude::*;
use tableau::expr::{
    EvalErrorKind, Expr, ExprKind, ParseError, decimal_text, eval, parse, parse_number,
};
use tableau::{Number, NumberError};

fn num(src: &str) -> Number {
    parse_number(src).unwrap_or_else(|e| panic!("{src}: {e}"))
}

fn no_names(_: &str) -> Option<Number> {
    None
}

// ---------------------------------------------------------------------------
// Values and identities

#[test]
fn identities_from_text() {
    assert!(num("sqrt(8) - 2*sqrt(2)").is_zero());
    assert!(num("sqrt(6) - sqrt(2)*sqrt(3)").is_zero());
    assert!(num("cbrt(16) - 2*cbrt(2)").is_zero());
    assert_eq!(num("1/(1+sqrt(2))"), num("sqrt(2)-1"));
    assert!(num("1/(1+sqrt(2)) - (sqrt(2) - 1)").is_zero());
    assert!(num("cbrt(2)^3 - 2").is_zero());
    assert!(num("sqrt(3)^2 - 3").is_zero());
    assert!(num("(1/4 + sqrt(3)/6) + (1/4 - sqrt(3)/6) - 1/2").is_zero());
    // Forest–Ruth: x (2 − 2^(1/3)) = 1.
    assert!(num("1/(2 - cbrt(2)) * (2 - cbrt(2)) - 1").is_zero());
}

#[test]
fn exact_decimals() {
    assert_eq!(num("0.5"), Number::ratio(1, 2).unwrap());
    assert_eq!(num("1.25e-3"), Number::ratio(1, 800).unwrap());
    let ten24 = num_traits::pow(BigInt::from(10), 24);
    assert_eq!(
        num("1e-24"),
        Number::from_rational(BigRational::new(BigInt::from(1), ten24))
    );
    assert_eq!(num("0.1 + 0.2"), num("0.3"));
}

#[test]
fn precedence_and_associativity() {
    assert_eq!(num("-2^2"), Number::from(-4));
    assert_eq!(num("2^3^2"), Number::from(512));
    assert_eq!(num("2^-2"), Number::ratio(1, 4).unwrap());
    assert_eq!(num("2^(-2)"), Number::ratio(1, 4).unwrap());
    assert_eq!(num("powi(2, -2)"), Number::ratio(1, 4).unwrap());
    assert_eq!(num("8/4/2"), Number::from(1));
    assert_eq!(num("8-4-2"), Number::from(2));
    assert_eq!(num("2 + 3*4^2"), Number::from(50));
}

#[test]
fn names_are_looked_up() {
    let e = parse("x/2 + y_1").unwrap();
    let env = |n: &str| match n {
        "x" => Some(Number::from(1)),
        "y_1" => Some(Number::from(2)),
        _ => None,
    };
    assert_eq!(eval(&e, &env).unwrap(), Number::ratio(5, 2).unwrap());
}

#[test]
fn trees_can_be_built_by_hand() {
    // As the macro does: positions index its own span table.
    let two = || Expr::new(ExprKind::Int(BigInt::from(2)), 0, 0);
    let e = Expr::new(
        ExprKind::Binary {
            op: tableau::expr::BinOp::Div,
            lhs: Box::new(two()),
            rhs: Box::new(Expr::new(
                ExprKind::Call {
                    func: tableau::expr::Func::Sqrt,
                    arg: Box::new(two()),
                },
                1,
                0,
            )),
        },
        2,
        0,
    );
    assert_eq!(eval(&e, &no_names).unwrap(), num("sqrt(2)"));
    assert_eq!(e.to_string(), "2/sqrt(2)");
}

// ---------------------------------------------------------------------------
// Errors with positions

fn parse_err(src: &str) -> ParseError {
    match parse(src) {
        Ok(e) => panic!("{src:?} parsed as {e}"),
        Err(e) => e,
    }
}

#[test]
fn empty_input() {
    for src in ["", " ", "\t\n"] {
        let e = parse_err(src);
        assert_eq!(e.to_string(), "empty expression");
        assert_eq!(e.pos, 0);
    }
}

#[test]
fn unbalanced_parentheses() {
    let e = parse_err("(1 + 2");
    assert_eq!((e.pos, e.token.as_str()), (0, "("));
    assert!(
        e.to_string()
            .starts_with("at column 1, unbalanced parentheses")
    );
    let e = parse_err("1 + (2 * (3 - 4)");
    assert_eq!(e.pos, 4);
    let e = parse_err("(1 + 2))");
    assert_eq!((e.pos, e.token.as_str()), (7, ")"));
    assert!(e.message.contains("unbalanced parentheses"));
    let e = parse_err("1/2)");
    assert_eq!(e.pos, 3);
    let e = parse_err("()");
    assert_eq!(
        e.to_string(),
        "at column 2, unexpected `)`: expected a number, a name or `(`"
    );
}

#[test]
fn unexpected_tokens() {
    let e = parse_err("1 + * 2");
    assert_eq!(
        e.to_string(),
        "at column 5, unexpected `*`: expected a number, a name or `(`"
    );
    let e = parse_err("1/4 +");
    assert_eq!(e.pos, 5);
    assert!(e.message.contains("unexpected end of input"));
    let e = parse_err("1/4 sqrt(3)");
    assert_eq!((e.pos, e.token.as_str()), (4, "sqrt"));
    assert!(e.message.contains("expected an operator"));
}

#[test]
fn unknown_function() {
    let e = parse_err("1 + exp(1)");
    assert_eq!((e.pos, e.token.as_str()), (4, "exp"));
    assert_eq!(
        e.to_string(),
        "at column 5, unknown function `exp` (the grammar has sqrt, cbrt, powi)"
    );
}

#[test]
fn non_ascii_junk() {
    let e = parse_err("1/2 + π");
    assert_eq!((e.pos, e.token.as_str()), (6, "π"));
    assert!(e.message.contains("U+03C0"), "{e}");
    let e = parse_err("√2");
    assert_eq!(e.pos, 0);
    assert!(e.message.contains("sqrt"), "{e}");
    let e = parse_err("1\u{a0}+ 1");
    assert_eq!(e.pos, 1);
    let e = parse_err("2×3");
    assert!(e.message.contains("`*`"), "{e}");
}

#[test]
fn non_integer_exponents() {
    let e = parse("2^(1/2)").unwrap();
    let err = eval(&e, &no_names).unwrap_err();
    assert_eq!((err.pos, err.len), (2, 5));
    assert!(matches!(err.kind, EvalErrorKind::NonIntegerExponent(ref v) if v == "1/2"));
    assert!(err.to_string().contains("use sqrt or cbrt"));
    let err = parse_number("x^0.5").unwrap_err();
    assert!(err.contains("unknown name `x`"), "{err}");
    let err = parse_number("3^0.5").unwrap_err();
    assert!(
        err.starts_with("at column 3, `0.5`: exponent 1/2 is not an integer"),
        "{err}"
    );
    let err = parse_number("powi(3, sqrt(2))").unwrap_err();
    assert!(err.contains("exponent sqrt(2) is not an integer"), "{err}");
}

#[test]
fn evaluation_errors_point_at_the_culprit() {
    let e = parse("1/4 + 1/0").unwrap();
    let err = eval(&e, &no_names).unwrap_err();
    assert_eq!(err.kind, EvalErrorKind::Number(NumberError::DivisionByZero));
    assert_eq!((err.pos, err.len), (8, 1));

    let e = parse("1/4 + sqrt(-1)").unwrap();
    let err = eval(&e, &no_names).unwrap_err();
    assert!(matches!(
        err.kind,
        EvalErrorKind::Number(NumberError::NegativeSqrt(_))
    ));
    assert_eq!((err.pos, err.len), (6, 8));

    let e = parse("2*y").unwrap();
    let err = eval(&e, &no_names).unwrap_err();
    assert_eq!(err.kind, EvalErrorKind::UnknownName("y".into()));
    assert_eq!((err.pos, err.len), (2, 1));

    assert_eq!(
        parse_number("1 + 1/(2 - 2)").unwrap_err(),
        "at column 7, division by zero: `(2 - 2)` is zero"
    );
    assert_eq!(
        parse_number("sqrt(-1)").unwrap_err(),
        "at column 1, `sqrt(-1)`: square root of a negative number (-1)"
    );
    assert!(
        parse_number("sqrt(1 + sqrt(2))")
            .unwrap_err()
            .contains("nested radical")
    );
}

// ---------------------------------------------------------------------------
// Properties

/// A number `Σ (n/d)·sqrt(a)·cbrt(b)` built through the API, and the same sum
/// written as text.
fn radical_sum() -> impl Strategy<Value = (Number, String)> {
    let term = (-60i64..60, 1i64..30, 1i64..40, -40i64..40);
    prop::collection::vec(term, 1..5).prop_map(|terms| {
        let mut value = Number::zero();
        let mut text = Vec::new();
        for (n, d, a, b) in terms {
            let t = Number::ratio(n, d).unwrap()
                * Number::from(a).sqrt().unwrap()
                * Number::from(b).cbrt().unwrap();
            value = value + t;
            text.push(format!("({n})/{d}*sqrt({a})*cbrt({b})"));
        }
        (value, text.join(" + "))
    })
}

/// Random expression text from a small grammar, with a variable `x`.
fn expr_text() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        (0u32..20).prop_map(|n| n.to_string()),
        (0u32..100, 1u32..4).prop_map(|(n, k)| format!("{n}e-{k}")),
        Just("x".to_string()),
        (1u32..30).prop_map(|n| format!("sqrt({n})")),
        (1u32..30).prop_map(|n| format!("cbrt({n})")),
    ];
    leaf.prop_recursive(5, 40, 2, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("{a} + {b}")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("{a} - {b}")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("{a}*{b}")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("{a}/({b})")),
            inner.clone().prop_map(|a| format!("-{a}")),
            inner.clone().prop_map(|a| format!("({a})")),
            (inner.clone(), -3i32..4).prop_map(|(a, k)| format!("({a})^{k}")),
        ]
    })
}

proptest! {
    #[test]
    fn canonical_text_round_trips((value, _) in radical_sum()) {
        let text = value.to_string();
        let back = parse_number(&text).map_err(|e| TestCaseError::fail(format!("{text}: {e}")))?;
        prop_assert_eq!(back, value);
    }

    #[test]
    fn text_and_api_agree((value, text) in radical_sum()) {
        prop_assert_eq!(num(&text), value);
    }

    #[test]
    fn decimal_text_round_trips(n in -1_000_000i64..1_000_000, twos in 0u32..40, fives in 0u32..40) {
        let d = BigInt::from(2).pow(twos) * BigInt::from(5).pow(fives);
        let r = BigRational::new(BigInt::from(n), d);
        let text = decimal_text(&r).unwrap();
        prop_assert_eq!(num(&text), Number::from_rational(r));
    }

    #[test]
    fn display_of_a_tree_parses_to_the_same_value(src in expr_text()) {
        let e = parse(&src).map_err(|e| TestCaseError::fail(format!("{src}: {e}")))?;
        let printed = e.to_string();
        let again = parse(&printed).map_err(|e| TestCaseError::fail(format!("{printed}: {e}")))?;
        prop_assert_eq!(again.to_string(), printed.clone());
        let env = |n: &str| (n == "x").then(|| Number::ratio(3, 7).unwrap());
        // Same value or the same kind of error.
        match (eval(&e, &env), eval(&again, &env)) {
            (Ok(a), Ok(b)) => prop_assert_eq!(a, b),
            (Err(a), Err(b)) => prop_assert_eq!(a.kind, b.kind),
            (a, b) => prop_assert!(false, "{src} → {printed}: {a:?} vs {b:?}"),
        }
    }

    #[test]
    fn arbitrary_strings_never_panic(src in any::<String>()) {
        if let Ok(e) = parse(&src) {
            let _ = eval(&e, &|_| Some(Number::from(2)));
        }
        let _ = parse_number(&src);
    }

    #[test]
    fn grammar_like_strings_never_panic(src in "[0-9a-z_+*/^(),. eE-]{0,40}") {
        match parse(&src) {
            Ok(e) => {
                prop_assert!(e.pos + e.len <= src.len());
                if let Err(err) = eval(&e, &|_| Some(Number::from(3))) {
                    prop_assert!(err.pos + err.len <= src.len());
                    let _ = err.message(&src);
                }
            }
            Err(err) => {
                prop_assert!(err.pos <= src.len());
                prop_assert!(!err.to_string().is_empty());
            }
        }
    }

    #[test]
    fn error_positions_are_in_range(src in "\\PC{0,30}") {
        if let Err(err) = parse(&src) {
            prop_assert!(err.pos <= src.len());
            prop_assert!(src.is_char_boundary(err.pos));
        }
    }
}
