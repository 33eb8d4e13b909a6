//! A method to its scheme type: generated from the library's scheme list
//! (`integrator_core::for_each_scheme!`), as [`Method::all`] is.
//!
//! Rust has no generic closures, so the dispatch takes a visitor: a value
//! whose `visit` is generic over the scheme type ([`SchemeVisitor`], and
//! [`TableVisitor`] for the stage solver's tables). The step code stays
//! fully monomorphised, specialised to each table.
//!
//! ```
//! use cloth::step::dispatch::{SchemeVisitor, with_explicit_scheme};
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
//! assert_eq!(with_explicit_scheme("forest-ruth", Order).unwrap(), 4);
//! assert!(with_explicit_scheme("gauss2", Order).unwrap_err().to_string().contains("implicit"));
//! ```

use integrator_core::implicit::ImplicitTable;
use integrator_core::library::*;
use integrator_core::{Info, Scheme, Step};

use crate::method::{Method, MethodError};
use crate::model::ClothModel;

/// Called with the scheme type a method stands for.
pub trait SchemeVisitor {
    type Output;
    fn visit<S: Step<ClothModel> + Scheme>(self, scheme: S) -> Self::Output;
}

/// Called with the table (and the facts) of an implicit scheme.
pub trait TableVisitor {
    type Output;
    fn visit<const S: usize>(self, table: &ImplicitTable<S>, info: &'static Info) -> Self::Output;
}

/// Call `visitor` with the method's scheme type (a library scheme; `None`
/// for the energy schemes, which have no table).
pub fn with_scheme<V: SchemeVisitor>(method: &Method, visitor: V) -> Option<V::Output> {
    visit_scheme(method.id(), visitor)
}

/// Call `visitor` with the method's implicit table (`None` for an explicit
/// scheme and the energy schemes).
pub fn with_table<V: TableVisitor>(method: &Method, visitor: V) -> Option<V::Output> {
    if method.explicit() {
        return None;
    }
    visit_table(method.id(), visitor)
}

/// Call `visitor` with the explicit library scheme named `id`; an implicit
/// method is refused ([`MethodError::Implicit`]): it runs through its own
/// solver.
pub fn with_explicit_scheme<V: SchemeVisitor>(
    id: &str,
    visitor: V,
) -> Result<V::Output, MethodError> {
    let method = Method::parse(id)?;
    if !method.explicit() {
        return Err(MethodError::Implicit(method.id().to_string()));
    }
    Ok(with_scheme(&method, visitor).expect("every explicit method is a library scheme"))
}

/// Generates [`visit_scheme`] and [`visit_table`] from the scheme lists.
/// Implicit Runge–Kutta tables are built from the type's `A`, `B`, `C`,
/// which every Runge–Kutta `butcher!` type has, so an explicit table in
/// that list (Lobatto IIIC* with two stages) compiles too; it steps
/// explicitly.
macro_rules! cloth_dispatch {
    (
        explicit_rk: [$($e_id:literal => $e_ty:ident),* $(,)?],
        implicit_rk: [$($i_id:literal => $i_ty:ident),* $(,)?],
        explicit_pairs: [$($x_id:literal => $x_ty:ident),* $(,)?],
        splittings: [$($s_id:literal => $s_ty:ident),* $(,)?],
        implicit_pairs: [$($p_id:literal => $p_ty:ident),* $(,)?] $(,)?
    ) => {
        /// `visitor` with the library scheme type named `id`.
        fn visit_scheme<V: SchemeVisitor>(id: &str, visitor: V) -> Option<V::Output> {
            Some(match id {
                $($x_id => visitor.visit($x_ty),)*
                $($s_id => visitor.visit($s_ty),)*
                $($e_id => visitor.visit($e_ty),)*
                $($i_id => visitor.visit($i_ty),)*
                $($p_id => visitor.visit($p_ty),)*
                _ => return None,
            })
        }

        /// `visitor` with the table of the implicit library scheme `id`.
        fn visit_table<V: TableVisitor>(id: &str, visitor: V) -> Option<V::Output> {
            Some(match id {
                $($i_id => visitor.visit(
                    &ImplicitTable::new(<$i_ty>::A, <$i_ty>::B, <$i_ty>::C),
                    &<$i_ty as Scheme>::INFO,
                ),)*
                $($p_id => visitor.visit(&<$p_ty>::TABLE, &<$p_ty as Scheme>::INFO),)*
                _ => return None,
            })
        }
    };
}

integrator_core::for_each_scheme!(cloth_dispatch);
