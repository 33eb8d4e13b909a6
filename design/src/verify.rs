//! Re-checking an emitted table's certificate from its text alone: the
//! coefficients are read with tableau's own file parser, checked to be
//! exactly the family's parametrisation (symmetry, consistency, ties, fixed
//! values) at the unknowns they give, and the Krawczyk test is run again on
//! the box the certificate line states. Any edit to a coefficient (beyond
//! what the radius allows) makes the test fail.

use num_rational::BigRational;
use tableau::{Number, Table};

use crate::certify::{Certificate, Refusal, krawczyk};
use crate::conditions::system;
use crate::emit::CERTIFICATE_KEY;
use crate::family::{Family, Form};

/// Why a table's certificate was not accepted.
#[derive(Debug, thiserror::Error)]
pub enum VerifyError {
    #[error("{0}")]
    File(String),
    #[error("{0}")]
    Shape(String),
    #[error("the certificate is refused: {0}")]
    Refused(#[from] Refusal),
}

fn rational(n: &Number, what: &str) -> Result<BigRational, VerifyError> {
    n.as_rational().ok_or_else(|| {
        VerifyError::Shape(format!(
            "{what} = {n} is irrational; a certificate is about rational coefficients (exact ones are decided by `symlab check`)"
        ))
    })
}

/// Re-check the certificate of an emitted table (`origin` names it in
/// messages) against its family.
pub fn verify_table(family: &Family, origin: &str, text: &str) -> Result<Certificate, VerifyError> {
    let file = tableau::file::parse_table_file(origin, text)
        .map_err(|e| VerifyError::File(e.to_string()))?;
    let sys = system(family, origin).map_err(|e| VerifyError::File(e.to_string()))?;
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix(CERTIFICATE_KEY))
        .ok_or_else(|| VerifyError::Shape(format!("{origin}: no `{CERTIFICATE_KEY}` line")))?;
    let (det_text, radius_text) = line
        .split_once(';')
        .ok_or_else(|| VerifyError::Shape(format!("{origin}: malformed certificate line")))?;
    let det_names: Vec<&str> = det_text
        .trim()
        .strip_prefix("determined =")
        .ok_or_else(|| VerifyError::Shape(format!("{origin}: malformed certificate line")))?
        .split_whitespace()
        .collect();
    let radius: BigRational = radius_text
        .trim()
        .strip_prefix("radius =")
        .and_then(|r| r.trim().parse().ok())
        .ok_or_else(|| VerifyError::Shape(format!("{origin}: malformed radius")))?;
    let determined: Vec<usize> = det_names
        .iter()
        .map(|n| {
            sys.names
                .iter()
                .position(|m| m == n)
                .ok_or_else(|| VerifyError::Shape(format!("{origin}: `{n}` is not an unknown")))
        })
        .collect::<Result<_, _>>()?;
    // The method's coefficients as the file gives them.
    let (given, polys): (Vec<Number>, Vec<&crate::poly::Poly>) = match (&file.table, sys.form) {
        (Table::Composition(c), Form::Composition) => (c.gamma.clone(), sys.gamma.iter().collect()),
        (Table::Splitting(s), Form::Aba) => {
            let mut g = s.drift.clone();
            g.extend(s.kick.iter().cloned());
            (g, sys.drift.iter().chain(&sys.kick).collect())
        }
        (Table::Splitting(s), Form::Bab) => {
            if s.drift.first().is_none_or(|d| !d.is_zero()) {
                return Err(VerifyError::Shape(format!(
                    "{origin}: a BAB table starts with a zero drift"
                )));
            }
            let mut g = s.drift[1..].to_vec();
            g.extend(s.kick.iter().cloned());
            (g, sys.drift.iter().chain(&sys.kick).collect())
        }
        _ => {
            return Err(VerifyError::Shape(format!(
                "{origin}: the table is not a {} method",
                sys.form.name()
            )));
        }
    };
    if given.len() != polys.len() {
        return Err(VerifyError::Shape(format!(
            "{origin}: {} coefficients, the family has {}",
            given.len(),
            polys.len()
        )));
    }
    // Each unknown is read where it first stands alone in the layout; all
    // coefficients must then be the parametrisation exactly.
    let n = sys.unknowns();
    let mut x: Vec<Option<BigRational>> = vec![None; n];
    for (g, p) in given.iter().zip(&polys) {
        let vars = p.variables();
        if vars.len() == 1
            && p.degree() == 1
            && p.as_constant().is_none()
            && p.derivative(vars[0]).as_constant() == Some(num_traits::One::one())
            && p.sub(&crate::poly::Poly::var(n, vars[0])).is_zero()
            && x[vars[0]].is_none()
        {
            x[vars[0]] = Some(rational(g, &sys.names[vars[0]])?);
        }
    }
    let x: Vec<BigRational> = x
        .into_iter()
        .enumerate()
        .map(|(i, v)| {
            v.ok_or_else(|| {
                VerifyError::Shape(format!("{origin}: `{}` is not given alone", sys.names[i]))
            })
        })
        .collect::<Result<_, _>>()?;
    for (k, (g, p)) in given.iter().zip(&polys).enumerate() {
        let expect = p.eval_rational(&x);
        if rational(g, "a coefficient")? != expect {
            return Err(VerifyError::Shape(format!(
                "{origin}: coefficient {k} is {g}, but the family's symmetric, consistent parametrisation gives {expect}"
            )));
        }
    }
    Ok(krawczyk(&sys, &x, &determined, &radius)?)
}
