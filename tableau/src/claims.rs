//! What a table claims about itself: `symplectic`, `symmetric`, `explicit`,
//! `order = 4`, or `order = 8 (residual < 1e-24)` for a table whose order
//! conditions hold only up to a stated residual (coefficients published as
//! decimals), and the same two forms of `order_rkn`, the order on
//! Runge–Kutta–Nyström systems (separable `H = T(p) + V(q)` with `T`
//! quadratic): `order_rkn = 4`, `order_rkn = 4 (residual < 1e-16)`; and the
//! generalised order of a splitting for near-integrable `H = A + εB`
//! ([`crate::near_integrable`]): `order = (8, 6, 4)`, `order = (8, 6, 4)
//! (residual < 1e-30)`.

use std::fmt;
use std::str::FromStr;

use crate::Number;
use crate::budget::MAX_CLAIMED_ORDER;
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
    /// Order `p` on Runge–Kutta–Nyström systems: separable `H = T(p) + V(q)`
    /// with `T = ½pᵀM⁻¹p` quadratic (the Nyström trees, see
    /// [`crate::trees::Colouring::Nystrom`]); `bound` as for [`Claim::Order`].
    OrderRkn {
        p: usize,
        bound: Option<Number>,
    },
    /// Generalised order `(p₁, p₂, …, p_m)` for near-integrable `H = A + εB`
    /// (drifts the flow of `A`, kicks that of `εB`): the error is
    /// `O(ε h^{p₁} + ε² h^{p₂} + … + ε^m h^{p_m})`, `p_m` standing for every
    /// power of `ε` from `m` on (see [`crate::near_integrable`]); `bound` as
    /// for [`Claim::Order`].
    NearOrder {
        orders: Vec<usize>,
        bound: Option<Number>,
    },
    /// `order = p (certified)`: order `p` of an exact method within the
    /// radius of the file's `certificate` around the printed coefficients,
    /// proven by Krawczyk's test ([`crate::certificate`]); never a claim
    /// about the printed decimals themselves.
    CertifiedOrder {
        p: usize,
    },
    /// `order = (p₁, p₂, …) (certified)`: the generalised order of a
    /// drift–kick sequence, certified as [`Claim::CertifiedOrder`] is.
    CertifiedNearOrder {
        orders: Vec<usize>,
    },
}

const SYNTAX: &str = "the claims are symplectic, symmetric, explicit, `order = N`, `order = N (residual < BOUND)`, `order = N (certified)` (with a `certificate`), `order = (P1, P2, …)` (the generalised order for H = A + εB), `order_rkn = N` and `order_rkn = N (residual < BOUND)`";

/// The keywords of the order claims; the longer first, since `order` is a
/// prefix of `order_rkn`.
const ORDER_KEYWORDS: [&str; 2] = ["order_rkn", "order"];

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
    let Some((keyword, rest)) = ORDER_KEYWORDS.iter().find_map(|k| {
        t.strip_prefix(k)
            .filter(|rest| !rest.starts_with(|c: char| c.is_alphanumeric() || c == '_'))
            .map(|rest| (*k, rest))
    }) else {
        return Err(unknown(t));
    };
    if keyword == "order"
        && let Some(tuple) = rest.trim_start().strip_prefix('=').map(str::trim_start)
        && tuple.starts_with('(')
    {
        let close = tuple
            .find(')')
            .ok_or_else(|| format!("`{t}`: expected `order = (P1, P2, …)`, with a closing `)`"))?;
        let mut orders = Vec::new();
        for item in tuple[1..close].split(',') {
            let item = item.trim();
            if item.is_empty() || !item.bytes().all(|b| b.is_ascii_digit()) {
                return Err(format!(
                    "`{t}`: expected whole numbers in `order = (P1, P2, …)`, found `{item}`"
                ));
            }
            orders.push(order_number(t, item)?);
        }
        if strip_certified(&tuple[close + 1..]).is_some_and(|h| h.trim().is_empty()) {
            return Ok(Claim::CertifiedNearOrder { orders });
        }
        // The bound, if any, reads as after a plain order.
        let (_, bound) = parse_order(t, keyword, &format!("= 1 {}", &tuple[close + 1..]))?;
        return Ok(Claim::NearOrder { orders, bound });
    }
    if keyword == "order"
        && let Some(head) = strip_certified(rest)
    {
        let (p, bound) = parse_order(t, keyword, head)?;
        if bound.is_some() {
            return Err(format!(
                "`{t}`: a certified order has no residual bound (the certificate bounds the distance to an exact solution instead)"
            ));
        }
        return Ok(Claim::CertifiedOrder { p });
    }
    let (p, bound) = parse_order(t, keyword, rest)?;
    Ok(if keyword == "order" {
        Claim::Order { p, bound }
    } else {
        Claim::OrderRkn { p, bound }
    })
}

/// `rest` without a trailing `(certified)` (whitespace free inside, as the
/// macro's tokens print it: `( certified )`).
fn strip_certified(rest: &str) -> Option<&str> {
    let r = rest.trim_end().strip_suffix(')')?.trim_end();
    let r = r.strip_suffix("certified")?.trim_end();
    r.strip_suffix('(')
}

/// The rest of an order claim after its keyword: `= N` and an optional
/// `(residual < BOUND)`. `t` is the whole claim, for messages.
fn parse_order(t: &str, keyword: &str, rest: &str) -> Result<(usize, Option<Number>), String> {
    let Some(rest) = rest.trim_start().strip_prefix('=') else {
        return Err(format!("`{t}`: expected `{keyword} = N`, with N the order"));
    };
    let rest = rest.trim_start();
    let digits_end = rest
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(rest.len());
    let (digits, rest) = rest.split_at(digits_end);
    if digits.is_empty() {
        let found = rest.split_whitespace().next().unwrap_or("nothing");
        return Err(format!(
            "`{t}`: expected a whole number after `{keyword} =`, found `{found}`"
        ));
    }
    let p = order_number(t, digits)?;
    let rest = rest.trim();
    if rest.is_empty() {
        return Ok((p, None));
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
    Ok((p, Some(bound)))
}

/// One order of a claim, `digits` being ASCII digits: at least 1 and at
/// most [`MAX_CLAIMED_ORDER`]. The bound is checked here, before any
/// analysis sees the number, because several analyses build a list with an
/// entry per order (`order = (99999999999)` once asked for 8 GB).
fn order_number(t: &str, digits: &str) -> Result<usize, String> {
    let beyond = || {
        format!(
            "`{t}`: the order {digits} is beyond every budget of the verifier: it decides orders up to {MAX_CLAIMED_ORDER} at most (tableau::budget::MAX_CLAIMED_ORDER)"
        )
    };
    let p: usize = digits.parse().map_err(|_| beyond())?;
    if p == 0 {
        return Err(format!("`{t}`: an order is at least 1"));
    }
    if p > MAX_CLAIMED_ORDER {
        return Err(beyond());
    }
    Ok(p)
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
    /// `order = 8 (residual < 1e-24)`, `order_rkn = 4`. A bound that is an
    /// exact decimal is written as one; any other bound in the canonical form
    /// of [`Number`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (keyword, p, bound) = match self {
            Claim::Symplectic => return f.write_str("symplectic"),
            Claim::Symmetric => return f.write_str("symmetric"),
            Claim::Explicit => return f.write_str("explicit"),
            Claim::Order { p, bound } => ("order", p, bound),
            Claim::OrderRkn { p, bound } => ("order_rkn", p, bound),
            Claim::NearOrder { orders, bound } => {
                let items: Vec<String> = orders.iter().map(usize::to_string).collect();
                write!(f, "order = ({})", items.join(", "))?;
                return write_bound(f, bound);
            }
            Claim::CertifiedOrder { p } => return write!(f, "order = {p} (certified)"),
            Claim::CertifiedNearOrder { orders } => {
                let items: Vec<String> = orders.iter().map(usize::to_string).collect();
                return write!(f, "order = ({}) (certified)", items.join(", "));
            }
        };
        write!(f, "{keyword} = {p}")?;
        write_bound(f, bound)
    }
}

/// ` (residual < BOUND)`, when there is a bound.
fn write_bound(f: &mut fmt::Formatter<'_>, bound: &Option<Number>) -> fmt::Result {
    if let Some(bound) = bound {
        let text = bound
            .as_rational()
            .and_then(|r| decimal_text(&r))
            .unwrap_or_else(|| bound.to_string());
        write!(f, " (residual < {text})")?;
    }
    Ok(())
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
            "order_rkn = 4",
            "order_rkn = 5 (residual < 1e-16)",
            "order_rkn = 4 (residual < sqrt(3)/1000)",
            "order = (8, 6, 4)",
            "order = (2, 2)",
            "order = (2, 4)",
            "order = 4 (certified)",
            "order = (6, 2) (certified)",
            "order = (10, 6, 4) (residual < 1e-30)",
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
        assert_eq!(
            parse_claim("order_rkn=4").unwrap(),
            Claim::OrderRkn { p: 4, bound: None }
        );
        let Claim::OrderRkn {
            p: 5,
            bound: Some(b),
        } = parse_claim(" order_rkn = 5 ( residual < 1e-16 ) ").unwrap()
        else {
            panic!()
        };
        assert_eq!(b, parse_number("1/10000000000000000").unwrap());
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
            ("order = 99999999999999999999999", "beyond every budget"),
            ("order = 18446744073709551615", "beyond every budget"),
            ("order = 65", "up to 64 at most"),
            (
                "order = (99999999999)",
                "the order 99999999999 is beyond every budget",
            ),
            ("order = (65, 4)", "the order 65 is beyond"),
            ("order = (8, 18446744073709551616)", "beyond every budget"),
            ("order = 4 residual", "expected `(residual < BOUND)`"),
            ("order = 4 (residual < )", "empty expression"),
            ("order = 4 (residual < 1/0)", "division by zero"),
            ("order = 4 (residual < -1)", "positive"),
            ("order = 4 (residual < 0)", "positive"),
            ("order = 4.5", "expected `(residual < BOUND)`"),
            ("order_rkns = 4", "unknown claim"),
            ("order_rk = 4", "unknown claim"),
            ("order_rkn 4", "expected `order_rkn = N`"),
            ("order_rkn = five", "after `order_rkn =`, found `five`"),
            ("order_rkn =", "found `nothing`"),
            ("order_rkn = 0", "at least 1"),
            ("order_rkn = 99999999999999999999999", "beyond every budget"),
            (
                "order_rkn = 4 (residual 1e-16)",
                "expected `(residual < BOUND)`",
            ),
            ("order_rkn = 4 (residual < 1e-)", "residual bound `1e-`"),
            ("order_rkn = 4 (residual < 0)", "positive"),
            ("order = (8, 6", "closing `)`"),
            ("order = (8, , 4)", "found ``"),
            ("order = (8, x)", "found `x`"),
            ("order = (8, 0)", "at least 1"),
            ("order = (8, 4) residual", "expected `(residual < BOUND)`"),
            ("order = (8, 4) (residual < -1)", "positive"),
        ];
        for (text, phrase) in cases {
            let e = parse_claim(text).unwrap_err();
            assert!(e.contains(phrase), "{text}: {e}");
        }
        // An unknown claim lists the order_rkn forms among the claims.
        let e = parse_claim("order_rkns = 4").unwrap_err();
        assert!(e.contains("`order_rkn = N (residual < BOUND)`"), "{e}");
    }
}
