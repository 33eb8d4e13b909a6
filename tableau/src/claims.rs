//! What a table claims about itself: `symplectic`, `symmetric`, `explicit`,
//! `order = 4`, or `order = 8 (residual < 1e-24)` for a table whose order
//! conditions hold only up to a stated residual (coefficients published as
//! decimals).

use std::fmt;
use std::str::FromStr;

use crate::Number;
use crate::expr::{decimal_text, parse_number};

/// One claim of a table.
#[derive(Clone, Debug, PartialEq)]
pub enum Claim {
    Symplectic,
    Symmetric,
    Explicit,
    /// Classical order `p`; with a `bound`, every order condition up to `p`
    /// need only hold to within `|residual| < bound`.
    Order {
        p: usize,
        bound: Option<Number>,
    },
}

const SYNTAX: &str = "the claims are symplectic, symmetric, explicit, `order = N` and `order = N (residual < BOUND)`";

/// Parse one claim. Whitespace around the words and symbols is free:
/// `order=4` and `order = 4` are the same claim.
pub fn parse_claim(text: &str) -> Result<Claim, String> {
    let t = text.trim();
    match t {
        "symplectic" => return Ok(Claim::Symplectic),
        "symmetric" => return Ok(Claim::Symmetric),
        "explicit" => return Ok(Claim::Explicit),
        _ => {}
    }
    let Some(rest) = t.strip_prefix("order") else {
        return Err(unknown(t));
    };
    let Some(rest) = rest.trim_start().strip_prefix('=') else {
        if rest.starts_with(|c: char| c.is_alphanumeric() || c == '_') {
            return Err(unknown(t));
        }
        return Err(format!("`{t}`: expected `order = N`, with N the order"));
    };
    let rest = rest.trim_start();
    let digits_end = rest
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(rest.len());
    let (digits, rest) = rest.split_at(digits_end);
    if digits.is_empty() {
        let found = rest.split_whitespace().next().unwrap_or("nothing");
        return Err(format!(
            "`{t}`: expected a whole number after `order =`, found `{found}`"
        ));
    }
    let p: usize = digits
        .parse()
        .map_err(|_| format!("`{t}`: the order {digits} is too large"))?;
    if p == 0 {
        return Err(format!("`{t}`: an order is at least 1"));
    }
    let rest = rest.trim();
    if rest.is_empty() {
        return Ok(Claim::Order { p, bound: None });
    }
    let bound_text = rest
        .strip_prefix('(')
        .and_then(|r| r.strip_suffix(')'))
        .map(str::trim)
        .and_then(|r| r.strip_prefix("residual"))
        .map(str::trim_start)
        .and_then(|r| r.strip_prefix('<'))
        .map(str::trim);
    let Some(bound_text) = bound_text else {
        return Err(format!(
            "`{t}`: after the order, expected `(residual < BOUND)`, found `{rest}`"
        ));
    };
    let bound = parse_number(bound_text)
        .map_err(|e| format!("`{t}`: the residual bound `{bound_text}`: {e}"))?;
    if bound.signum() != std::cmp::Ordering::Greater {
        return Err(format!(
            "`{t}`: the residual bound must be positive, not {bound}"
        ));
    }
    Ok(Claim::Order {
        p,
        bound: Some(bound),
    })
}

fn unknown(t: &str) -> String {
    format!("unknown claim `{t}`: {SYNTAX}")
}

impl FromStr for Claim {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        parse_claim(s)
    }
}

impl fmt::Display for Claim {
    /// The text [`parse_claim`] reads: `symplectic`, `order = 4`,
    /// `order = 8 (residual < 1e-24)`. A bound that is an exact decimal is
    /// written as one; any other bound in the canonical form of [`Number`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Claim::Symplectic => f.write_str("symplectic"),
            Claim::Symmetric => f.write_str("symmetric"),
            Claim::Explicit => f.write_str("explicit"),
            Claim::Order { p, bound: None } => write!(f, "order = {p}"),
            Claim::Order {
                p,
                bound: Some(bound),
            } => {
                let text = bound
                    .as_rational()
                    .and_then(|r| decimal_text(&r))
                    .unwrap_or_else(|| bound.to_string());
                write!(f, "order = {p} (residual < {text})")
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_prints() {
        for text in [
            "symplectic",
            "symmetric",
            "explicit",
            "order = 4",
            "order = 8 (residual < 1e-24)",
            "order = 6 (residual < 2.5e-10)",
            "order = 2 (residual < 0.001)",
            "order = 3 (residual < sqrt(2)/1000)",
        ] {
            let claim = parse_claim(text).unwrap_or_else(|e| panic!("{text}: {e}"));
            let printed = claim.to_string();
            assert_eq!(parse_claim(&printed).unwrap(), claim, "{text}");
            if !text.contains("sqrt") {
                assert_eq!(printed, text);
            }
        }
        assert_eq!(
            parse_claim("  order=4 ").unwrap(),
            Claim::Order { p: 4, bound: None }
        );
        let Claim::Order {
            p: 8,
            bound: Some(b),
        } = parse_claim("order = 8 (residual<1e-24)").unwrap()
        else {
            panic!()
        };
        assert_eq!(b, parse_number("1/1000000000000000000000000").unwrap());
    }

    #[test]
    fn errors() {
        let cases = [
            ("symplectique", "unknown claim"),
            ("", "unknown claim"),
            ("orders = 4", "unknown claim"),
            ("order 4", "expected `order = N`"),
            ("order = four", "found `four`"),
            ("order =", "found `nothing`"),
            ("order = 0", "at least 1"),
            ("order = 99999999999999999999999", "too large"),
            ("order = 4 residual", "expected `(residual < BOUND)`"),
            ("order = 4 (residual < )", "empty expression"),
            ("order = 4 (residual < 1/0)", "division by zero"),
            ("order = 4 (residual < -1)", "positive"),
            ("order = 4 (residual < 0)", "positive"),
            ("order = 4.5", "expected `(residual < BOUND)`"),
        ];
        for (text, phrase) in cases {
            let e = parse_claim(text).unwrap_err();
            assert!(e.contains(phrase), "{text}: {e}");
        }
    }
}
