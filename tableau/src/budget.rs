//! The budgets of exact analysis: how large an input the verifier takes on.
//!
//! Exact means exact: past a budget the verifier never falls back to
//! floating point. It refuses, saying what is too large and what the limit
//! is. Where a verdict can still be decided without the costly part, it is:
//! a table whose stability function is beyond [`STABILITY_WORK`] or
//! [`RADICAL_STABILITY_WORK`] still gets its symplecticity, order and
//! symmetry, and `symlab check` reports the stability function as "not
//! computed: beyond budget (…)"; `butcher!` refuses such a table with a
//! compile error at the table, since its scheme would lack its stability
//! constants. Every limit is deterministic (a size, never a clock), so the
//! macro and `symlab check` agree on every machine.
//!
//! | budget | limit | applies to |
//! |---|---|---|
//! | [`MAX_FILE_BYTES`] | 1 MiB | a table file ([`crate::file::load`]) |
//! | [`MAX_LITERAL_DIGITS`] | 1000 digits | an integer or decimal literal in an entry |
//! | [`MAX_STAGES`] | 100 stages | the stages of a table, of its equivalent pair (drift–kick sequences, compositions) |
//! | [`MAX_CLAIMED_ORDER`] | order 64 | an order in a claim (`order = N`, each entry of `order = (P1, …)`); each analysis refuses earlier at its own limit |
//! | [`MAX_INVERSE_DEGREE`] | degree 256 | a divisor: the degree over Q of the field its radicals span |
//! | [`crate::expr::MAX_BITS`] | 2²² bits | the size of a product or power in an entry |
//! | [`crate::expr::MAX_TERM_PRODUCTS`] | 2²⁰ | the term products of one multiplication in an entry |
//! | [`crate::expr::MAX_DEPTH`] | 128 levels | the nesting of an entry |
//! | [`STABILITY_WORK`] | 2³⁰ | rational tables: primes × (stages³ + stages² × words of an entry) + primes² × stages |
//! | [`RADICAL_STABILITY_WORK`] | 2²⁷ | tables with radicals: stages⁵ × degree² (stages³ × degree² for explicit tables and quadratic fields) |
//! | [`MAX_ENTRY_BITS`] | 32768 bits | an entry's value: the bits of its numerators, denominators and radicands; and the common denominator of all entries; a coefficient of a real algebraic entry |
//! | [`MAX_ROOT_DEGREE`] | degree 64 | the polynomial of a `root(POLY, LO, HI)`, and every power and product while it is expanded (`(x^200)^200` is refused) |
//! | [`MAX_ROOT_BITS`] | 16384 bits | POLY's coefficients and LO, HI together (the interval is clipped to Cauchy's root bound, so huge bounds cost no bisections) |
//! | [`MAX_ALG_TERMS`] | 16384 terms | a real algebraic entry (a polynomial in the roots), after reduction |
//! | [`MAX_ALG_PRODUCT_WORK`] | 2³² word products | one product or power step in a root-file entry or condition, estimated before it is done: at the limit about 0.75 s, 20 MB (`(√2 + √3 + … + √37)^8`, 2·10⁹ in 0.35 s); `(c0 + … + c7)^64` is refused |
//! | [`MAX_ZERO_TEST_BITS`] | 2¹⁸ bits | the precision `(n − 1)·log₂ M` a zero test in several roots needs (six quintic roots, 218 815 bits: 0.64 s) |
//! | [`MAX_ZERO_TEST_WORK`] | 2³² word products | one zero test, sign, rounding, gcd or root isolation, estimated before it is done: at the limit about 1.6 s (a zero test in six quintic roots, 1.7·10⁹ in 0.64 s; isolating a root of degree 64, 10⁹ in 0.44 s), under 10 MB |
//! | [`crate::near_integrable::MAX_NEAR_DEGREE`] | degree 24 | the power of `h` to which a generalised order (`order = (8, 6, 4)`) is examined |
//! | [`crate::near_integrable::MAX_NEAR_WORDS`] | 2¹⁶ words | the free algebra on {A, B} truncated by (number of B's, degree) for a generalised order |
//! | [`crate::near_integrable::MAX_NEAR_WORK`] | 2²⁰ products | words × flows × degree (a gradient kick counting degree + 4), plus m³/6 per Lyndon word of m letters, times (bits / 320)² for coefficients longer than 640 bits ([`crate::near_integrable::CALIBRATED_BITS`]), estimated before the work: at the limit about 15 s with 40-digit decimals |
//! | [`crate::near_integrable::MAX_NEAR_FIELD_DEGREE`] | 16 | the degree over Q of the field the coefficients of a near-integrable claim span |
//! | [`MAX_ANALYSIS_WORK`] | 2³³ word products | parsing and analysing one root-file table together; the tests past it are reported undecided: at the limit about 3.6 s (36 such zero tests, 6.6·10⁹ in 2.8 s), under 10 MB |
//!
//! Word products are counted with Karatsuba's exponent for long operands
//! ([`crate::algebraic::alg::mul_work`]), calibrated so that one unit is
//! about 0.3–0.45 ns on this project's 2-core machine (release build).
//! Measured there: every collocation table with s ≤ 8 of every family, and
//! the Lobatto IIIA–IIIB pair, written with `root(...)` entries (`c` given
//! or not) is decided, nothing refused, in at most about 2 s and 8 MB
//! (`cargo test -p tableau --release --test integration root_files:: -- --ignored`).

pub use crate::number::MAX_INVERSE_DEGREE;

/// The largest table file read; a larger file (or `/dev/zero`) is refused
/// after reading this much.
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// The most digits an integer or decimal literal may have (its integer and
/// fractional digits together). Published tables use a few dozen.
pub const MAX_LITERAL_DIGITS: usize = 1000;

/// The most stages a table may have: `a` is at most this many rows, a
/// drift–kick sequence or a composition at most this many stages in its
/// equivalent partitioned pair (a composition of `m` Störmer–Verlet steps has
/// `m + 1`). The order conditions of a 100-stage table are checked in
/// seconds; published methods have at most a few dozen stages.
pub const MAX_STAGES: usize = 100;

/// The largest order a claim may state (`order = N`, `order_rkn = N`, each
/// entry of `order = (P1, P2, …)`). Every analysis has a lower limit of its
/// own ([`crate::trees::MAX_ORDER`], [`crate::near_integrable::MAX_NEAR_DEGREE`],
/// …) and refuses past it with its own message; this bound only keeps a
/// claim such as `order = 18446744073709551615` from reaching code that
/// sizes a list by the order.
pub const MAX_CLAIMED_ORDER: usize = 64;

/// The stability function of a rational table: the number of 61-bit primes
/// its characteristic polynomials need (from Hadamard's bound, so about the
/// stages times the bits of the scaled entries, over 61) times (stages³ +
/// stages² × the 64-bit words of the largest scaled entry), plus primes² ×
/// stages for the Chinese remainder theorem.
pub const STABILITY_WORK: u64 = 1 << 30;

/// The stability function of a table with radicals, counted in coefficient
/// products: each product of two numbers costs up to degree² of them, where
/// the degree is that of the field the entries of `A` and `b` span. An
/// explicit table needs stages³ products; an implicit one stages⁴
/// (Berkowitz's division-free algorithm), or stages³ in a quadratic field
/// (degree 2: Hessenberg reduction). An implicit table's degree must also be
/// at most [`MAX_INVERSE_DEGREE`], and when `P` and `Q` are not proven coprime
/// modulo a prime, their gcd over the field (Euclid's algorithm) is computed
/// only for degree ≤ 2 and at most 20 stages.
pub const RADICAL_STABILITY_WORK: u64 = 1 << 27;

/// The largest entry, in bits of its numerators, denominators and radicands
/// together (about 9800 decimal digits; the inverse of a sum of five cube roots has about 20000). Computed entries can exceed the
/// literal limit (`3^-65536` is written in 8 characters); every order
/// condition multiplies entries, so their size is bounded too.
pub const MAX_ENTRY_BITS: u64 = 32768;

/// A computation refused because its input is beyond a budget: what is too
/// large, and what the limit is.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct BeyondBudget(pub String);

/// The most bits of precision (`(n − 1)·log₂ M`, see
/// [`crate::algebraic::alg`]) a zero test in several roots may need; above
/// it the test is refused rather than run long.
pub const MAX_ZERO_TEST_BITS: u64 = 1 << 18;

/// The work of one zero test, sign or rounding of a real algebraic number,
/// in 64-bit word products (estimated before it is done, with Karatsuba's
/// exponent for long operands: refining the roots to the precision asked
/// for, and the certified enclosure of every term). See
/// [`crate::algebraic::alg::work_of_enclosure`].
pub const MAX_ZERO_TEST_WORK: u64 = 1 << 32;

/// The work of all the zero tests of one table with `root(...)` entries
/// together (symplecticity, row sums, `B(k)`), in the units of
/// [`MAX_ZERO_TEST_WORK`]; the tests past it are reported as undecided.
pub const MAX_ANALYSIS_WORK: u64 = 1 << 33;

/// The most terms (monomials in the roots) of one real algebraic number
/// after reduction; e.g. `(c0 + … + c7)^64` in eight roots of degree 8 has
/// up to 8⁸ ≈ 1.7·10⁷ terms and is refused.
pub const MAX_ALG_TERMS: usize = 1 << 14;

/// The work of one product or power of real algebraic numbers in an
/// entry: term products × the word products of their coefficients
/// (estimated before it is done).
pub const MAX_ALG_PRODUCT_WORK: u64 = 1 << 32;

/// The largest degree of the polynomial of a `root(POLY, LO, HI)` (after
/// expanding it); the node polynomials of generated tables have degree at
/// most 16.
pub const MAX_ROOT_DEGREE: usize = 64;

/// The most bits of a `root(POLY, LO, HI)`: the numerators and denominators
/// of POLY's coefficients and of LO and HI together. Sturm sequences grow
/// like degree² × these bits.
pub const MAX_ROOT_BITS: u64 = 1 << 14;
