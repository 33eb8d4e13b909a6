//! Designing splitting and composition methods (issue 36): a family declared
//! in a file ([`family`]), its order conditions as exact polynomials in the
//! free coefficients ([`conditions`]), a seeded multi-start solver in `f64`
//! ([`solve`]), a polish to 50 digits in exact rationals ([`polish`]), an
//! exact value where one polynomial in one unknown remains ([`exact`]) or a
//! Krawczyk certificate in exact rational interval arithmetic otherwise
//! ([`certify`]), and a table file that `symlab check` reads ([`emit`]),
//! whose certificate [`verify`] re-checks from the text alone.
//!
//! ```
//! use design::{Family, Form, design};
//!
//! let mut family = Family::new("Yoshida's triple jump", Form::Composition, 3, 4);
//! family.starts = 20;
//! family.range = 2.0; // the root, 1.35…, is beyond the default [-1, 1]
//! let outcome = design(&family, "(example)", &mut |_| {}).unwrap();
//! let best = &outcome.designs[0];
//! // g1 = 1/(2 − ∛2), recovered in radicals and checked in tableau's field.
//! assert!(best.exact.as_ref().unwrap().radicals.is_some());
//! assert!((best.solution.x[0] - 1.3512071919596578).abs() < 1e-12);
//! ```
//!
//! A processed kernel (`processed = true`; compositions and drift–kick
//! sequences, classical orders) is designed under
//! effective-order conditions ([`effective`]: the processor eliminated
//! weight by weight), and its processor found and written with it as a
//! processed table that tableau decides ([`processor`]).
//!
//! A second family kind, a second corrector for a processed method of the
//! catalogue ([`processed`]), has one unknown and an exact answer, found from
//! tableau's exact near-integrable coefficients.
//!
//! Modules import one way: `poly`, `linalg` ← `family`, `effective` ←
//! `conditions` ← `solve` ← `polish` ← `certify`, `exact` ← `emit` ←
//! `verify`, `processor` ← `pipeline`; `family` ← `processed`.

pub mod certify;
pub mod conditions;
pub mod effective;
pub mod emit;
pub mod exact;
pub mod family;
pub mod linalg;
pub mod pipeline;
pub mod polish;
pub mod poly;
pub mod processed;
pub mod processor;
pub mod solve;
pub mod stability;
pub mod verify;

pub use family::{
    ErrorBasis, Family, FamilyError, Form, Objective, load_family, parse_family, read_family_text,
};
pub use pipeline::{Designed, Outcome, design};

/// The guide's design chapter, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../guide/src/design.md")]
pub struct GuideDesign;
