//! Exact real algebraic numbers, and the collocation-type tables built from
//! them for any number of stages.
//!
//! Two representations, each for what it does best:
//!
//! * [`pair`]: the **product of fields** of a node polynomial `P`. Every
//!   quantity of a collocation-type table is one element of `Q[x]/(P)` (a
//!   quantity per stage) or of `Q[x, y]/(P(x), (P(x) − P(y))/(x − y))` (a
//!   quantity per ordered pair of distinct stages), so an identity over all
//!   stages (`W = 0`, `B(p)`, `C(q)`, `D(r)`, symmetry) is one exact,
//!   complete zero test on a normal form, with no conjugates to tell apart.
//!   [`family`] builds Gauss, Radau IA/IIA, Lobatto IIIA/IIIB/IIIC and the
//!   IIIA–IIIB pair this way, for any `s` up to
//!   [`family::MAX_GENERATED_STAGES`].
//! * [`alg`]: **general real algebraic numbers**, polynomials in any roots
//!   `root(p, lo, hi)` of rational polynomials picked out by isolating
//!   intervals ([`root`]), with an exact and complete zero test (the
//!   characteristic polynomial of multiplication, plus a certified
//!   enclosure), within a budget on the size of the algebra. Table files
//!   with `root(...)` entries use it ([`file`](mod@file)); [`rounded`] turns such a
//!   table into the correctly rounded doubles and the exact structure that
//!   `butcher!` and `symlab compare --table` step.
//!
//! Signs and correctly rounded `f64` values come from certified refinement
//! (Sturm sequences, exact bisection, rational interval arithmetic), never
//! from floating-point evaluation.

pub mod alg;
pub mod family;
pub mod file;
pub mod generated;
mod near;
pub mod pair;
pub mod poly;
pub mod root;
pub mod rounded;
pub mod trees;
