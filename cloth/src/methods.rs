//! Method names → library schemes that can step a [`ClothModel`].
//!
//! Rust has no generic closures, so the dispatch takes a visitor: a value
//! whose [`SchemeVisitor::visit`] is generic over the scheme type. The step
//! code stays fully monomorphised, specialised to each table.
//!
//! ```
//! use cloth::methods::{with_scheme, SchemeVisitor};
//! use cloth::ClothModel;
//! use integrator_core::{Scheme, Step};
//!
//! struct Order;
//! impl SchemeVisitor for Order {
//!     type Output = usize;
//!     fn visit<S: Step<ClothModel> + Scheme>(self, _scheme: S) -> usize {
//!         S::INFO.order
//!     }
//! }
//! assert_eq!(with_scheme("forest-ruth", Order).unwrap(), 4);
//! assert!(with_scheme("gauss2", Order).unwrap_err().to_string().contains("implicit"));
//! ```

use integrator_core::library::{self, *};
use integrator_core::{Scheme, Step};

use crate::implicit::{IMPLICIT, is_implicit};
use crate::model::ClothModel;

/// Called with the scheme a name stands for.
pub trait SchemeVisitor {
    type Output;
    fn visit<S: Step<ClothModel> + Scheme>(self, scheme: S) -> Self::Output;
}

/// Why a method name was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MethodError {
    #[error("unknown method \"{0}\"; the methods that step cloth are, explicit: {explicit}; implicit (sparse Newton): {implicit}", explicit = STEPPABLE.join(", "), implicit = IMPLICIT.join(", "))]
    Unknown(String),
    #[error("method \"{0}\" is a library scheme that does not step cloth (it is neither explicit nor one of the implicit schemes wired to the sparse stage solver: {implicit})", implicit = IMPLICIT.join(", "))]
    NotSteppable(String),
    #[error(
        "method \"{0}\" is implicit: it steps cloth through the sparse stage solver (`cloth::implicit::run_method`), not as an explicit scheme"
    )]
    Implicit(String),
}

/// The ids (as in `tableau/catalogue`) of the library schemes that step a
/// cloth model: every explicit one. Symplectic ones first.
pub const STEPPABLE: &[&str] = &[
    "symplectic-euler-a",
    "symplectic-euler-b",
    "stormer-verlet",
    "leapfrog",
    "ruth3",
    "forest-ruth",
    "candy-rozmus4",
    "mclachlan-atela2",
    "mclachlan-atela3",
    "mclachlan-atela4",
    "mclachlan-atela5",
    "calvo-sanz-serna4",
    "mclachlan4",
    "pefrl",
    "mclachlan-s5",
    "blanes-moan-prk6",
    "blanes-moan-prk10",
    "blanes-moan-srkn6b",
    "blanes-moan-srkn11b",
    "blanes-moan-srkn14a",
    "yoshida4",
    "yoshida6",
    "kahan-li6",
    "mclachlan-ss9",
    "kahan-li8",
    "mclachlan8",
    "sofroniou-spaletta10",
    "euler",
    "heun",
    "rk4",
    "rk38",
    "lobatto3cstar-2",
];

/// Whether `id` names a scheme that can step cloth: an explicit one
/// ([`STEPPABLE`]), an implicit one ([`IMPLICIT`]), or one of the two
/// energy-conserving comparison schemes of [`crate::minimise`]
/// (`avf`, `discrete-gradient`).
pub fn check(id: &str) -> Result<(), MethodError> {
    if STEPPABLE.contains(&id)
        || is_implicit(id)
        || id == crate::minimise::AVERAGE_VECTOR_FIELD
        || id == crate::minimise::DISCRETE_GRADIENT
    {
        Ok(())
    } else if library::info(id).is_some() {
        Err(MethodError::NotSteppable(id.to_string()))
    } else {
        Err(MethodError::Unknown(id.to_string()))
    }
}

/// Call `visitor` with the library scheme named `id`.
pub fn with_scheme<V: SchemeVisitor>(id: &str, visitor: V) -> Result<V::Output, MethodError> {
    Ok(match id {
        "symplectic-euler-a" => visitor.visit(SymplecticEulerA),
        "symplectic-euler-b" => visitor.visit(SymplecticEulerB),
        "stormer-verlet" => visitor.visit(StormerVerlet),
        "leapfrog" => visitor.visit(Leapfrog),
        "ruth3" => visitor.visit(Ruth3),
        "forest-ruth" => visitor.visit(ForestRuth),
        "candy-rozmus4" => visitor.visit(CandyRozmus4),
        "mclachlan-atela2" => visitor.visit(McLachlanAtela2),
        "mclachlan-atela3" => visitor.visit(McLachlanAtela3),
        "mclachlan-atela4" => visitor.visit(McLachlanAtela4),
        "mclachlan-atela5" => visitor.visit(McLachlanAtela5),
        "calvo-sanz-serna4" => visitor.visit(CalvoSanzSerna4),
        "mclachlan4" => visitor.visit(McLachlan4),
        "pefrl" => visitor.visit(Pefrl),
        "mclachlan-s5" => visitor.visit(McLachlanS5),
        "blanes-moan-prk6" => visitor.visit(BlanesMoanPrk6),
        "blanes-moan-prk10" => visitor.visit(BlanesMoanPrk10),
        "blanes-moan-srkn6b" => visitor.visit(BlanesMoanSrkn6b),
        "blanes-moan-srkn11b" => visitor.visit(BlanesMoanSrkn11b),
        "blanes-moan-srkn14a" => visitor.visit(BlanesMoanSrkn14a),
        "yoshida4" => visitor.visit(Yoshida4),
        "yoshida6" => visitor.visit(Yoshida6),
        "kahan-li6" => visitor.visit(KahanLi6),
        "mclachlan-ss9" => visitor.visit(McLachlanSS9),
        "kahan-li8" => visitor.visit(KahanLi8),
        "mclachlan8" => visitor.visit(McLachlan8),
        "sofroniou-spaletta10" => visitor.visit(SofroniouSpaletta10),
        "euler" => visitor.visit(ExplicitEuler),
        "heun" => visitor.visit(Heun),
        "rk4" => visitor.visit(Rk4),
        "rk38" => visitor.visit(Rk38),
        "lobatto3cstar-2" => visitor.visit(LobattoIIICStar2),
        other => {
            // `check` refuses every name the match does not cover except the
            // implicit ones (a test keeps `STEPPABLE` and the match in step).
            return Err(check(other)
                .err()
                .unwrap_or_else(|| MethodError::Implicit(other.to_string())));
        }
    })
}
