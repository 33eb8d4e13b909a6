//! Near-integrable (generalised) order claims of drift–kick sequences whose
//! coefficients are real algebraic numbers: the Lie-word algebra of
//! [`crate::near_integrable`] over the ring of this field's numbers.

use crate::budget::BeyondBudget;
use crate::near_integrable::algebra;
use crate::near_integrable::words::{Word, bracket};
use crate::near_integrable::{Factor, claim_degrees, power_label, truncation, tuple_text};

use super::alg::Alg;

/// The real algebraic numbers of a [`Field`](super::alg::Field)
/// as a [`algebra::Ring`]: products within the field's budgets
/// ([`super::alg::Field::try_mul`], charged to its work limit);
/// the first product beyond them is kept, every later product is skipped
/// (zero), and the caller refuses with it.
struct AlgRing<'a> {
    f: &'a super::alg::Field,
    beyond: std::cell::RefCell<Option<BeyondBudget>>,
}

impl algebra::Ring for AlgRing<'_> {
    type E = super::alg::Alg;
    fn zero(&self) -> Self::E {
        Self::E::zero()
    }
    fn one(&self) -> Self::E {
        Self::E::int(1)
    }
    fn is_zero(&self, x: &Self::E) -> bool {
        x.is_zero_poly()
    }
    fn add(&self, x: &Self::E, y: &Self::E) -> Self::E {
        x.add(y)
    }
    fn neg(&self, x: &Self::E) -> Self::E {
        x.neg()
    }
    fn mul(&self, x: &Self::E, y: &Self::E) -> Self::E {
        if self.beyond.borrow().is_some() || x.is_zero_poly() || y.is_zero_poly() {
            return Self::E::zero();
        }
        match self.f.try_mul(x, y) {
            Ok(r) => r,
            Err(e) => {
                *self.beyond.borrow_mut() = Some(e);
                Self::E::zero()
            }
        }
    }
    fn scale(&self, x: &Self::E, r: &num_rational::BigRational) -> Self::E {
        x.scale(r)
    }
}

/// Check a claimed generalised order `(p₁, p₂, …)` (or, with one entry, the
/// classical order on the Lie algebra) of a drift–kick sequence whose
/// coefficients are real algebraic numbers (`root(...)` entries, nested
/// radicals; [`super::alg`]): the same truncated product and
/// Lyndon coefficients as [`check_near_claim`](crate::near_integrable::check_near_claim), every coefficient an
/// [`Alg`](super::alg::Alg) and every condition one exact zero
/// test ([`super::alg::Field::is_zero`]), or, with a rational
/// `bound`, `|residual| < bound` by two exact sign tests. Within
/// [`MAX_NEAR_DEGREE`](crate::near_integrable::MAX_NEAR_DEGREE), [`MAX_NEAR_WORDS`](crate::near_integrable::MAX_NEAR_WORDS), [`MAX_NEAR_WORK`](crate::near_integrable::MAX_NEAR_WORK) and the
/// field's budgets; a condition beyond them refuses the claim as
/// undecided, saying which.
pub fn alg_near_claim(
    f: &super::alg::Field,
    ops: &[Factor<super::alg::Alg>],
    orders: &[usize],
    bound: Option<&num_rational::BigRational>,
) -> Result<(), String> {
    let claimed = tuple_text(orders);
    if orders.is_empty() || orders.contains(&0) {
        return Err(format!(
            "order = {claimed}: a generalised order is a nonempty list of orders of at least 1"
        ));
    }
    let degrees = claim_degrees(orders);
    let (full, lyndon) =
        truncation(ops, &degrees, 1, "").map_err(|e| format!("order = {claimed}: {e}"))?;
    let ring = AlgRing {
        f,
        beyond: std::cell::RefCell::new(None),
    };
    let p = algebra::product_in(&ring, ops, &full);
    let beyond = |ring: &AlgRing<'_>| ring.beyond.borrow().clone();
    if let Some(e) = beyond(&ring) {
        return Err(format!(
            "order = {claimed} cannot be decided: the product of the flows' exponentials: {e}"
        ));
    }
    let a = Word::from_letters(&[0]);
    let words = std::iter::once(a).chain(lyndon.iter().flatten().copied());
    for w in words {
        let value = algebra::log_coefficient_in(&ring, &p, w);
        if let Some(e) = beyond(&ring) {
            return Err(format!(
                "order = {claimed} cannot be decided: the coefficient of {} in log Φ: {e}",
                w.label()
            ));
        }
        let expected = if w.len == 1 { 1 } else { 0 };
        let residual = value.sub(&Alg::int(expected));
        let holds = match bound {
            None => f.is_zero(&residual),
            Some(b) => f
                .sign(&residual.sub(&Alg::rational(b.clone())))
                .and_then(|lo| Ok(lo < 0 && f.sign(&residual.add(&Alg::rational(b.clone())))? > 0)),
        };
        let label = power_label(w.bs(), usize::from(w.len));
        match holds {
            Ok(true) => {}
            Ok(false) => {
                let approx = match f.to_f64(&value) {
                    Ok(v) => format!("≈ {v:e}"),
                    Err(_) => "(value beyond the budget)".into(),
                };
                let within = match bound {
                    Some(b) => format!(" (residual not below {b})"),
                    None => String::new(),
                };
                let part = if w.bs() == 0 {
                    "the drifts are not consistent".to_string()
                } else {
                    format!(
                        "the ε{} part has order {} < {}",
                        power_label(w.bs(), 1)
                            .trim_end_matches('h')
                            .trim_start_matches('ε'),
                        usize::from(w.len) - 1,
                        degrees[w.bs() - 1]
                    )
                };
                return Err(format!(
                    "order = {claimed} claimed, but {part}: the {label} condition fails: the coefficient of {} in log Φ (the leading word of {}) is {approx}, not {expected}{within} (decided exactly on the algebraic coefficients)",
                    w.label(),
                    bracket(&w.letters()),
                ));
            }
            Err(e) => {
                return Err(format!(
                    "order = {claimed} cannot be decided: the {label} condition (the coefficient of {} in log Φ): {e}",
                    w.label()
                ));
            }
        }
    }
    Ok(())
}
