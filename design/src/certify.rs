//! The certificate: a Krawczyk test, in exact rational interval arithmetic,
//! that an exact solution of the imposed conditions lies within a radius `r`
//! of the printed coefficients, and a proof that the next order's error
//! terms are bounded away from zero there (so the order is exactly `p`).
//!
//! For the square system `F(x_D; x_free) = 0` in the determined unknowns
//! `x_D` (the free ones fixed at their printed rationals), the box
//! `X = x̃ ± r` and any nonsingular `Y`, the Krawczyk operator
//! `K(X) = x̃ − Y·F(x̃) + (I − Y·J(X))·(X − x̃)` contains every zero of `F`
//! in `X`, and `K(X) ⊂ int X` proves that `X` holds exactly one
//! (Krawczyk 1969; Moore 1977; Rump 1983). Here `x̃` and `r` are rationals,
//! `F(x̃)` is exact, `J(X)` is an enclosure of the Jacobian over `X` from
//! exact rational interval arithmetic on the derivative polynomials (no
//! rounding mode is involved anywhere), and `Y` is any rational matrix (an
//! `f64` inverse of `J(x̃)`, converted exactly): the test is a proof for
//! whatever `Y` is, and a poor `Y` only makes it fail. Componentwise,
//! `K(X) ⊂ int X` reads `|(Y·F(x̃))_i| + r·Σ_j |I − Y·J(X)|_{ij} < r`, with
//! `|·|` the magnitude of an interval, decided exactly.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::One;

use crate::conditions::System;

/// A proof about one printed solution.
#[derive(Clone, Debug)]
pub struct Certificate {
    /// An exact solution lies in the box of this radius (max norm) around
    /// the printed determined unknowns; it is the only one there.
    pub radius: BigRational,
    /// `max_i Σ_j |I − Y·J(X)|_{ij}`: how strongly the Krawczyk map
    /// contracts (must be < 1).
    pub contraction: f64,
    /// `max_i |(Y·F(x̃))_i| / r`.
    pub offset: f64,
    /// An error term of degree `p + 1` whose enclosure over the box excludes
    /// zero, with the enclosure: the order is exactly `p` at every point of
    /// the box.
    pub next_order: Option<(String, f64, f64)>,
}

/// Why a certificate was refused (tableau's, which `symlab check` gives
/// too).
pub use tableau::certificate::Refusal;

/// `10^-k`.
pub fn ten_to_minus(k: u32) -> BigRational {
    BigRational::new(BigInt::one(), BigInt::from(10).pow(k))
}

/// Run the Krawczyk test on the box `x ± radius` in the unknowns
/// `determined` (the others fixed at their values in `x`), and bound the
/// next order's error terms on it: tableau's test
/// ([`tableau::certificate::krawczyk`]), the one `symlab check` runs on the
/// emitted table's certificate.
pub fn krawczyk(
    system: &System,
    x: &[BigRational],
    determined: &[usize],
    radius: &BigRational,
) -> Result<Certificate, Refusal> {
    let conditions: Vec<&crate::poly::Poly> = system.conditions.iter().map(|c| &c.poly).collect();
    let errors: Vec<(&str, &crate::poly::Poly)> = system
        .error_terms
        .iter()
        .map(|e| (e.word.as_str(), &e.poly))
        .collect();
    let (contraction, offset, next_order) =
        tableau::certificate::krawczyk(&conditions, &errors, x, determined, radius)?;
    if next_order.is_none() {
        return Err(Refusal::NextOrder {
            degree: system.order + 1,
            order: system.order,
        });
    }
    Ok(Certificate {
        radius: radius.clone(),
        contraction,
        offset,
        next_order,
    })
}

/// The smallest radius `10^-k` (k from `max_k` down to 10) for which the
/// test succeeds.
pub fn certify(
    system: &System,
    x: &[BigRational],
    determined: &[usize],
    max_k: u32,
) -> Result<Certificate, Refusal> {
    let mut last = Refusal::Singular;
    let mut k = max_k;
    while k >= 10 {
        match krawczyk(system, x, determined, &ten_to_minus(k)) {
            Ok(c) => return Ok(c),
            Err(e @ Refusal::Singular) => return Err(e),
            Err(e) => last = e,
        }
        k -= 2;
    }
    Err(last)
}
