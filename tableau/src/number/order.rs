//! Comparisons of rationals whose depth does not depend on the input
//! ([`qcmp`]): the exact algebra's rationals can agree to many thousand
//! bits, where `num-rational`'s own comparisons recurse.

use num_rational::BigRational;

/// The order of two rationals, by one cross multiplication.
///
/// `num-rational`'s `Ord` (and so `<`, `>`, `min`, `max`, and `==` on
/// values with different denominators) compares by continued fractions,
/// recursing once per partial quotient the two numbers share: two rationals
/// agreeing to 100 000 bits overflow the stack. The exact algebra
/// (`algebraic`, `certificate`) compares rationals through this function
/// instead, whose depth does not depend on the input.
pub fn qcmp(a: &BigRational, b: &BigRational) -> std::cmp::Ordering {
    // Ratio keeps its denominator positive and the fraction reduced.
    if a.denom() == b.denom() {
        return a.numer().cmp(b.numer());
    }
    (a.numer() * b.denom()).cmp(&(b.numer() * a.denom()))
}

/// `a == b` for reduced rationals, without [`qcmp`]'s multiplications.
pub fn qeq(a: &BigRational, b: &BigRational) -> bool {
    a.numer() == b.numer() && a.denom() == b.denom()
}

/// `a < b`.
pub fn qlt(a: &BigRational, b: &BigRational) -> bool {
    qcmp(a, b).is_lt()
}

/// `a ≤ b`.
pub fn qle(a: &BigRational, b: &BigRational) -> bool {
    qcmp(a, b).is_le()
}
