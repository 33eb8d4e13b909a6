//! Table files with algebraic entries, and generated tables in table files.
//!
//! Two additions to the format of [`crate::file`]:
//!
//! ```toml
//! # A generated table (name and claims optional; default claims are the
//! # literature's):
//! generate = "gauss(8)"
//! claims = ["symplectic", "symmetric", "order = 16"]
//! ```
//!
//! ```toml
//! # Entries in real algebraic numbers: `root(POLY, LO, HI)` in `let` is the
//! # one root of POLY (in x, rational coefficients) in (LO, HI].
//! name = "Gauss–Legendre 2 via roots"
//! let = { c0 = "root(x^2 - x + 1/6, 0, 1/2)", c1 = "root(x^2 - x + 1/6, 1/2, 1)" }
//! a = [["1/4", "c0 - 1/4"], ["c1 - 1/4", "1/4"]]
//! b = ["1/2", "1/2"]
//! claims = ["symplectic"]
//! ```
//!
//! Entries of a `root` file are polynomials with rational coefficients in the
//! roots (and in `sqrt`/`cbrt` of rationals, which become roots too);
//! division is allowed by expressions in one root. A pair gives `a_hat`,
//! `b_hat` (and optionally `c_hat`) as well. Zero is decided exactly
//! ([`super::alg`]): the symplecticity verdict names every nonzero `Wᵢⱼ`
//! (for a pair, every nonzero entry of `bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ`, and
//! `b = b̂`). Row sums and `B(k)` (for `b`, and `b̂`) are decided too.
//! Every test is within the budgets of [`crate::budget`]
//! (`MAX_ZERO_TEST_BITS`, `MAX_ZERO_TEST_WORK`, `MAX_ALG_PRODUCT_WORK`,
//! `MAX_ALG_TERMS`, and `MAX_ANALYSIS_WORK` for parsing and analysing a
//! table together); one beyond them is reported as undecided, with the
//! reason in [`AlgAnalysis::refusals`]. Order claims are decided on the
//! trees in the number field ([`super::trees`]). Symmetry and the stability
//! function are not computed for such files. A file without `generate` or `root(`
//! is an ordinary table file.

#![allow(clippy::needless_range_loop)] // index-heavy table code

use std::collections::BTreeMap;
use std::path::Path;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};

use super::alg::{Alg, Field};
use super::family::Generator;
use super::generated::{Generated, literature_claims};
use super::poly::Poly;
use super::root::RealRoot;
use crate::budget::{BeyondBudget, MAX_FILE_BYTES, MAX_ROOT_BITS, MAX_ROOT_DEGREE};
use crate::claims::{Claim, parse_claim};
use crate::expr::{self, BinOp, Expr, ExprKind, Func};
use crate::file::{FileError, TableFile, parse_table_file};

/// What a table file holds.
#[derive(Clone, Debug)]
pub enum Loaded {
    /// An ordinary table file ([`crate::file`]).
    Classic(Box<TableFile>),
    /// `generate = "..."`.
    Generated(Box<Generated>),
    /// Entries with `root(...)`.
    Algebraic(Box<AlgFile>),
}

/// A Runge–Kutta table with real algebraic entries.
#[derive(Clone, Debug)]
pub struct AlgFile {
    pub name: String,
    pub source: Option<String>,
    pub claims: Vec<Claim>,
    pub field: Field,
    pub a: Vec<Vec<Alg>>,
    pub b: Vec<Alg>,
    pub c: Option<Vec<Alg>>,
    /// A partitioned pair: `a_hat`, `b_hat` act on `p` (`a`, `b` on `q`),
    /// `c_hat` optional. `a_hat` and `b_hat` are given together or not at all.
    pub a_hat: Option<Vec<Vec<Alg>>>,
    pub b_hat: Option<Vec<Alg>>,
    pub c_hat: Option<Vec<Alg>>,
    /// A drift–kick sequence (`drift`, `kick`), as written; `a`, `b`,
    /// `a_hat`, `b_hat` then hold its partitioned pair (as
    /// [`crate::Splitting::to_prk`] builds it), which the symplecticity,
    /// row-sum, `B(k)` and tree-order verdicts use, and the generalised
    /// orders are decided on the sequence itself.
    pub sequence: Option<AlgSequence>,
}

/// A drift–kick sequence with real algebraic coefficients: drifts (flows of
/// `A`, or of `T(p)`) and kicks (of `εB`, or `V(q)`), applied `D K D K …`.
#[derive(Clone, Debug)]
pub struct AlgSequence {
    pub drift: Vec<Alg>,
    pub kick: Vec<Alg>,
}

impl AlgSequence {
    /// The flows in the order applied (a structurally zero coefficient is
    /// kept: `exp(0·X)` is the identity).
    pub fn factors(&self) -> Vec<crate::near_integrable::Factor<Alg>> {
        use crate::near_integrable::Factor;
        let mut out = Vec::new();
        for i in 0..self.drift.len().max(self.kick.len()) {
            if let Some(d) = self.drift.get(i) {
                out.push(Factor::Letter(0, d.clone()));
            }
            if let Some(k) = self.kick.get(i) {
                out.push(Factor::Letter(1, k.clone()));
            }
        }
        out
    }

    /// The partitioned pair `(A, b)` on `q`, `(Â, b̂)` on `p`: a leading
    /// zero drift for a kick-first sequence, trailing zero kicks to make the
    /// lengths equal; `aᵢⱼ = dⱼ` for `j ≤ i`, `âᵢⱼ = kⱼ` for `j < i`.
    #[allow(clippy::type_complexity)]
    fn pair(&self) -> (Vec<Vec<Alg>>, Vec<Alg>, Vec<Vec<Alg>>, Vec<Alg>) {
        let mut drift = self.drift.clone();
        let mut kick = self.kick.clone();
        if kick.len() == drift.len() + 1 {
            drift.insert(0, Alg::zero());
        }
        let s = drift.len();
        kick.resize(s, Alg::zero());
        let mut a = vec![vec![Alg::zero(); s]; s];
        let mut a_hat = vec![vec![Alg::zero(); s]; s];
        for i in 0..s {
            for j in 0..s {
                if j <= i {
                    a[i][j] = drift[j].clone();
                }
                if j < i {
                    a_hat[i][j] = kick[j].clone();
                }
            }
        }
        (a, drift, a_hat, kick)
    }
}

/// Read a table file of any kind (at most 1 MiB, UTF-8).
pub fn load(path: &Path) -> Result<Loaded, FileError> {
    let file = path.display().to_string();
    let err = |message: String| FileError {
        file: file.clone(),
        field: None,
        message,
    };
    let meta = std::fs::metadata(path).map_err(|e| err(format!("cannot read the file: {e}")))?;
    // Anything but a regular file within the size limit (a device such as
    // /dev/zero, a directory, a huge file) goes to the ordinary loader,
    // which reads at most one byte past the limit and says what is wrong.
    if !meta.is_file() || meta.len() > MAX_FILE_BYTES {
        // The ordinary loader gives the full message.
        return crate::file::load(path).map(|t| Loaded::Classic(Box::new(t)));
    }
    let Ok(text) = std::fs::read_to_string(path) else {
        return crate::file::load(path).map(|t| Loaded::Classic(Box::new(t)));
    };
    parse(&file, &text)
}

/// Parse a table file of any kind given as text.
pub fn parse(file: &str, text: &str) -> Result<Loaded, FileError> {
    let Ok(doc) = text.parse::<toml::Table>() else {
        return parse_table_file(file, text).map(|t| Loaded::Classic(Box::new(t)));
    };
    let has_root = match doc.get("let") {
        Some(toml::Value::Table(t)) => t.values().any(|v| {
            v.as_str()
                .is_some_and(|s| s.trim_start().starts_with("root("))
        }),
        _ => false,
    };
    if doc.contains_key("generate") {
        return generated_file(file, &doc).map(|g| Loaded::Generated(Box::new(g)));
    }
    if has_root {
        return alg_file(file, &doc).map(|a| Loaded::Algebraic(Box::new(a)));
    }
    match parse_table_file(file, text) {
        // Nested radicals (`sqrt(525 + 70*sqrt(30))`) are beyond the radical
        // field: such a file is read with real algebraic numbers instead.
        Err(e) if e.message.contains("is a nested radical") => match alg_file(file, &doc) {
            Ok(a) => Ok(Loaded::Algebraic(Box::new(a))),
            // The algebraic reader's error names its own field.
            Err(alg) => Err(FileError {
                message: format!(
                    "{} (the file has a nested radical, so it is read with real algebraic numbers)",
                    alg.message
                ),
                ..alg
            }),
        },
        other => other.map(|t| Loaded::Classic(Box::new(t))),
    }
}

fn ferr(file: &str, field: Option<&str>, message: impl Into<String>) -> FileError {
    FileError {
        file: file.to_string(),
        field: field.map(str::to_string),
        message: message.into(),
    }
}

fn claims_of(file: &str, doc: &toml::Table) -> Result<Option<Vec<Claim>>, FileError> {
    let Some(v) = doc.get("claims") else {
        return Ok(None);
    };
    let Some(arr) = v.as_array() else {
        return Err(ferr(file, Some("claims"), "expected an array of strings"));
    };
    let mut out = Vec::new();
    for (i, c) in arr.iter().enumerate() {
        let field = format!("claims[{i}]");
        let s = c
            .as_str()
            .ok_or_else(|| ferr(file, Some(&field), "expected a string"))?;
        out.push(parse_claim(s).map_err(|e| ferr(file, Some(&field), e))?);
    }
    Ok(Some(out))
}

fn string_field(file: &str, doc: &toml::Table, key: &str) -> Result<Option<String>, FileError> {
    match doc.get(key) {
        None => Ok(None),
        Some(toml::Value::String(s)) => Ok(Some(s.clone())),
        Some(_) => Err(ferr(file, Some(key), "expected a string")),
    }
}

fn generated_file(file: &str, doc: &toml::Table) -> Result<Generated, FileError> {
    for key in doc.keys() {
        if !["name", "source", "claims", "generate"].contains(&key.as_str()) {
            return Err(ferr(
                file,
                Some(key),
                format!(
                    "unknown field `{key}` in a generated table (the fields are name, source, claims, generate)"
                ),
            ));
        }
    }
    let text = string_field(file, doc, "generate")?.expect("present");
    let g = Generator::parse(&text).map_err(|e| ferr(file, Some("generate"), e))?;
    let claims = claims_of(file, doc)?.unwrap_or_else(|| literature_claims(g));
    let mut out = Generated::with_claims(g, claims);
    if let Some(name) = string_field(file, doc, "name")? {
        out.name = name;
    }
    Ok(out)
}

fn alg_file(file: &str, doc: &toml::Table) -> Result<AlgFile, FileError> {
    for key in doc.keys() {
        if ![
            "name", "source", "claims", "let", "a", "b", "c", "a_hat", "b_hat", "c_hat", "drift",
            "kick",
        ]
        .contains(&key.as_str())
        {
            return Err(ferr(
                file,
                Some(key),
                format!(
                    "unknown field `{key}` in a table with root(...) entries (the fields are name, source, claims, let, a, b, c, a_hat, b_hat, c_hat, or drift and kick for a drift–kick sequence)"
                ),
            ));
        }
    }
    let name = string_field(file, doc, "name")?.ok_or_else(|| {
        ferr(
            file,
            Some("name"),
            "missing: every table file needs a `name = \"...\"`",
        )
    })?;
    let source = string_field(file, doc, "source")?;
    let claims = claims_of(file, doc)?.unwrap_or_default();
    let mut cx = AlgCx {
        file,
        // Parsing (roots, products) has the same total budget as analysis.
        field: Field::default().with_work_limit(crate::budget::MAX_ANALYSIS_WORK),
        env: BTreeMap::new(),
    };
    if let Some(toml::Value::Table(lets)) = doc.get("let") {
        // Roots first, then the other bindings in dependency order.
        let mut pending: Vec<(String, String)> = Vec::new();
        for (k, v) in lets {
            let fieldname = format!("let.{k}");
            let text = match v {
                toml::Value::String(s) => s.clone(),
                toml::Value::Integer(n) => n.to_string(),
                _ => {
                    return Err(ferr(
                        file,
                        Some(&fieldname),
                        "expected a string or an integer",
                    ));
                }
            };
            if text.trim_start().starts_with("root(") {
                let r = parse_root(&text).map_err(|e| ferr(file, Some(&fieldname), e))?;
                // Charged as for the widest interval the text allows
                // (Cauchy's bound), since the one given is gone.
                let wide = BigRational::from_integer(1.into());
                cx.field
                    .charge(super::alg::isolation_work(&r.poly, &wide, &wide))
                    .map_err(|e| ferr(file, Some(&fieldname), e.0))?;
                let x = cx.field.push(r, k.clone());
                cx.env.insert(k.clone(), x);
            } else {
                pending.push((k.clone(), text));
            }
        }
        let mut rounds = pending.len() + 1;
        while !pending.is_empty() && rounds > 0 {
            rounds -= 1;
            let mut left = Vec::new();
            for (k, text) in pending {
                let e = expr::parse(&text)
                    .map_err(|e| ferr(file, Some(&format!("let.{k}")), e.to_string()))?;
                let ready = e.names().iter().all(|n| match &n.kind {
                    ExprKind::Name(n) => cx.env.contains_key(n),
                    _ => true,
                });
                if ready {
                    let v = cx.eval(&format!("let.{k}"), &e)?;
                    cx.env.insert(k, v);
                } else {
                    left.push((k, text));
                }
            }
            pending = left;
        }
        if let Some((k, _)) = pending.first() {
            return Err(ferr(
                file,
                Some(&format!("let.{k}")),
                "refers to an unknown name, or the bindings form a cycle",
            ));
        }
    }
    if doc.contains_key("drift") || doc.contains_key("kick") {
        return sequence_file(file, doc, cx, name, source, claims);
    }
    let a = cx.matrix(doc.get("a"), "a")?;
    let b = cx.vector(doc.get("b"), "b")?;
    let c = match doc.get("c") {
        None => None,
        v => Some(cx.vector(v, "c")?),
    };
    let s = b.len();
    if s == 0 {
        return Err(ferr(file, Some("b"), "a table needs at least one stage"));
    }
    if s > crate::budget::MAX_STAGES {
        return Err(ferr(
            file,
            Some("b"),
            format!(
                "{s} stages, beyond the limit of {} (tableau::budget::MAX_STAGES)",
                crate::budget::MAX_STAGES
            ),
        ));
    }
    if a.len() != s || a.iter().any(|r| r.len() != s) || c.as_ref().is_some_and(|c| c.len() != s) {
        return Err(ferr(
            file,
            Some("a"),
            format!("a must be {s}×{s} and c (if given) of length {s}, as b has {s} entries"),
        ));
    }
    let (a_hat, b_hat) = match (doc.get("a_hat"), doc.get("b_hat")) {
        (None, None) => (None, None),
        (Some(_), None) => {
            return Err(ferr(
                file,
                Some("b_hat"),
                "missing: a pair needs both a_hat and b_hat",
            ));
        }
        (None, Some(_)) => {
            return Err(ferr(
                file,
                Some("a_hat"),
                "missing: a pair needs both a_hat and b_hat",
            ));
        }
        (ah, bh) => (Some(cx.matrix(ah, "a_hat")?), Some(cx.vector(bh, "b_hat")?)),
    };
    let c_hat = match doc.get("c_hat") {
        None => None,
        Some(_) if a_hat.is_none() => {
            return Err(ferr(
                file,
                Some("c_hat"),
                "c_hat belongs to a pair: give a_hat and b_hat too",
            ));
        }
        v => Some(cx.vector(v, "c_hat")?),
    };
    if let (Some(ah), Some(bh)) = (&a_hat, &b_hat)
        && (bh.len() != s
            || ah.len() != s
            || ah.iter().any(|r| r.len() != s)
            || c_hat.as_ref().is_some_and(|c| c.len() != s))
    {
        return Err(ferr(
            file,
            Some("a_hat"),
            format!(
                "a_hat must be {s}×{s}, b_hat and c_hat (if given) of length {s}, as b has {s} entries"
            ),
        ));
    }
    Ok(AlgFile {
        name,
        source,
        claims,
        // The field keeps the work spent parsing: parsing and analysis share
        // the budget.
        field: cx.field,
        a,
        b,
        c,
        a_hat,
        b_hat,
        c_hat,
        sequence: None,
    })
}

/// A drift–kick sequence with `root(...)` entries: `drift` and `kick`
/// (and nothing of a Butcher table), stored with its partitioned pair.
fn sequence_file(
    file: &str,
    doc: &toml::Table,
    mut cx: AlgCx<'_>,
    name: String,
    source: Option<String>,
    claims: Vec<Claim>,
) -> Result<AlgFile, FileError> {
    for key in ["a", "b", "c", "a_hat", "b_hat", "c_hat"] {
        if doc.contains_key(key) {
            return Err(ferr(
                file,
                Some(key),
                "a drift–kick sequence (drift, kick) has no Butcher-table fields",
            ));
        }
    }
    let drift = cx.vector(doc.get("drift"), "drift")?;
    let kick = cx.vector(doc.get("kick"), "kick")?;
    let (d, k) = (drift.len(), kick.len());
    if !(d == k || d == k + 1 || (k == d + 1 && d > 0)) || d == 0 {
        return Err(ferr(
            file,
            Some("kick"),
            format!(
                "a drift–kick sequence has as many kicks as drifts or one fewer (or one more, starting with a kick): {d} drifts and {k} kicks"
            ),
        ));
    }
    if d.max(k) > crate::budget::MAX_STAGES {
        return Err(ferr(
            file,
            Some("drift"),
            format!(
                "{} flows, beyond the limit of {} (tableau::budget::MAX_STAGES)",
                d.max(k),
                crate::budget::MAX_STAGES
            ),
        ));
    }
    let sequence = AlgSequence { drift, kick };
    let (a, b, a_hat, b_hat) = sequence.pair();
    Ok(AlgFile {
        name,
        source,
        claims,
        field: cx.field,
        a,
        b,
        c: None,
        a_hat: Some(a_hat),
        b_hat: Some(b_hat),
        c_hat: None,
        sequence: Some(sequence),
    })
}

/// `root(POLY, LO, HI)`.
pub fn parse_root(text: &str) -> Result<RealRoot, String> {
    let t = text.trim();
    let inner = t
        .strip_prefix("root(")
        .and_then(|r| r.strip_suffix(')'))
        .ok_or("expected root(POLY, LO, HI)")?;
    let mut parts = Vec::new();
    let mut depth = 0i32;
    let mut start = 0;
    for (i, ch) in inner.char_indices() {
        match ch {
            '(' => depth += 1,
            ')' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    if parts.len() != 3 {
        return Err(format!(
            "root(...) takes three arguments, POLY, LO and HI, found {}",
            parts.len()
        ));
    }
    let e = expr::parse(parts[0]).map_err(|e| format!("in the polynomial: {e}"))?;
    let p = poly_of(&e)?;
    if p.degree().unwrap_or(0) == 0 {
        return Err("the polynomial must have degree ≥ 1".into());
    }
    let bound = |s: &str, what: &str| -> Result<BigRational, String> {
        let n = expr::parse_number(s).map_err(|e| format!("in {what}: {e}"))?;
        n.as_rational()
            .ok_or_else(|| format!("{what} must be rational, found {n}"))
    };
    let (lo, hi) = (bound(parts[1], "LO")?, bound(parts[2], "HI")?);
    let size = poly_bits(&p) + qbits(&lo) + qbits(&hi);
    if size > MAX_ROOT_BITS {
        return Err(format!(
            "the polynomial and the bounds have {size} bits together, beyond the budget of {MAX_ROOT_BITS} (tableau::budget::MAX_ROOT_BITS)"
        ));
    }
    if super::poly::qle(&hi, &lo) {
        return Err(format!("the interval ({lo}, {hi}] is empty"));
    }
    let work = super::alg::isolation_work(&p, &lo, &hi);
    if work > crate::budget::MAX_ZERO_TEST_WORK {
        return Err(format!(
            "isolating a root of a polynomial of degree {} with coefficients of up to {} bits needs about {work} word products, beyond the budget of {} (tableau::budget::MAX_ZERO_TEST_WORK)",
            p.degree().unwrap_or(0),
            p.0.iter().map(qbits).max().unwrap_or(0),
            crate::budget::MAX_ZERO_TEST_WORK
        ));
    }
    let mut r = RealRoot::new(&p, lo.clone(), hi.clone()).map_err(|n| {
        format!(
            "the polynomial has {n} distinct real roots in ({lo}, {hi}], not exactly one: give an isolating interval"
        )
    })?;
    // Bisect to a narrow interval now, within the work just checked; later
    // refinement takes certified Newton steps.
    let mut narrow = r.clone();
    narrow.refine_to(64);
    if !narrow.is_rational() {
        r = narrow;
    } else if !r.is_rational() {
        // The bisection hit a rational root exactly: keep it a variable
        // (so that it stays in its family of conjugates, see
        // `Field::collapse`), in a small interval around it.
        let v = narrow.lo;
        let mut w = BigRational::new(1.into(), BigInt::from(1u64 << 40));
        for _ in 0..64 {
            if let Ok(c) = RealRoot::new(&p, &v - &w, &v + &w)
                && !c.is_rational()
            {
                r = c;
                break;
            }
            w /= BigRational::from_integer(2.into());
        }
    }
    Ok(r)
}

fn qbits(c: &BigRational) -> u64 {
    c.numer().bits() + c.denom().bits()
}

fn poly_bits(p: &Poly) -> u64 {
    p.0.iter().map(qbits).sum()
}

/// Refuse a polynomial of `root(...)` beyond [`MAX_ROOT_DEGREE`] or
/// [`MAX_ROOT_BITS`] (checked after every operation, so no intermediate
/// grows past them either).
fn check_root_poly(p: Poly) -> Result<Poly, String> {
    if p.degree().unwrap_or(0) > MAX_ROOT_DEGREE {
        return Err(format!(
            "the polynomial has degree above {MAX_ROOT_DEGREE} (tableau::budget::MAX_ROOT_DEGREE)"
        ));
    }
    let b = poly_bits(&p);
    if b > MAX_ROOT_BITS {
        return Err(format!(
            "the polynomial's coefficients have {b} bits together, beyond the budget of {MAX_ROOT_BITS} (tableau::budget::MAX_ROOT_BITS)"
        ));
    }
    Ok(p)
}

/// A polynomial in `x` with rational coefficients, from an expression:
/// degree at most [`MAX_ROOT_DEGREE`] and coefficients of at most
/// [`MAX_ROOT_BITS`] bits together, checked before every product and
/// after every operation. Nesting is bounded by the grammar's depth limit.
fn poly_of(e: &Expr) -> Result<Poly, String> {
    let p = match &e.kind {
        ExprKind::Int(n) => Poly::constant(BigRational::from_integer(n.clone())),
        ExprKind::Decimal(r) => Poly::constant(r.clone()),
        ExprKind::Name(n) if n == "x" => Poly::x(),
        ExprKind::Name(n) => return Err(format!("unknown name `{n}` (the variable is x)")),
        ExprKind::Neg(x) => poly_of(x)?.neg(),
        ExprKind::Binary { op, lhs, rhs } => {
            let (l, r) = (poly_of(lhs)?, poly_of(rhs)?);
            match op {
                BinOp::Add => l.add(&r),
                BinOp::Sub => l.sub(&r),
                BinOp::Mul => {
                    if l.degree().unwrap_or(0) + r.degree().unwrap_or(0) > MAX_ROOT_DEGREE {
                        return Err(format!(
                            "the polynomial has degree above {MAX_ROOT_DEGREE} (tableau::budget::MAX_ROOT_DEGREE)"
                        ));
                    }
                    l.mul(&r)
                }
                BinOp::Div => match r.degree() {
                    Some(0) => l.scale(&r.coeff(0).recip()),
                    None => return Err("division by zero in the polynomial".into()),
                    _ => return Err("division by a non-constant in a polynomial".into()),
                },
            }
        }
        ExprKind::Pow { base, exp } => {
            let b = poly_of(base)?;
            let k = poly_of(exp)?;
            let k = match k.degree() {
                None => 0,
                Some(0) if k.coeff(0).is_integer() => k
                    .coeff(0)
                    .to_integer()
                    .to_usize()
                    .filter(|&k| k <= MAX_ROOT_DEGREE)
                    .ok_or(format!(
                        "the exponent must be an integer in 0..={MAX_ROOT_DEGREE} (tableau::budget::MAX_ROOT_DEGREE)"
                    ))?,
                _ => return Err("exponent must be an integer".into()),
            };
            let deg = b.degree().unwrap_or(0);
            if deg.saturating_mul(k) > MAX_ROOT_DEGREE {
                return Err(format!(
                    "the polynomial has degree {deg}·{k} = {}, above {MAX_ROOT_DEGREE} (tableau::budget::MAX_ROOT_DEGREE)",
                    deg.saturating_mul(k)
                ));
            }
            // Each factor's size is checked, so no power grows unbounded.
            let mut r = Poly::one();
            for _ in 0..k {
                r = check_root_poly(r.mul(&b))?;
            }
            r
        }
        ExprKind::Call { .. } => {
            return Err("sqrt/cbrt are not allowed in root(...)'s polynomial".into());
        }
    };
    check_root_poly(p)
}

struct AlgCx<'a> {
    file: &'a str,
    field: Field,
    env: BTreeMap<String, Alg>,
}

impl AlgCx<'_> {
    fn entry(&mut self, field: &str, v: Option<&toml::Value>) -> Result<Alg, FileError> {
        match v {
            Some(toml::Value::String(s)) => {
                let e = expr::parse(s).map_err(|e| ferr(self.file, Some(field), e.to_string()))?;
                self.eval(field, &e)
            }
            Some(toml::Value::Integer(n)) => Ok(Alg::int(*n)),
            Some(toml::Value::Float(_)) => Err(ferr(
                self.file,
                Some(field),
                "a TOML float is not the decimal its author wrote: quote it, e.g. \"0.1\"",
            )),
            _ => Err(ferr(
                self.file,
                Some(field),
                "expected a string or an integer",
            )),
        }
    }

    fn vector(&mut self, v: Option<&toml::Value>, name: &str) -> Result<Vec<Alg>, FileError> {
        let Some(toml::Value::Array(arr)) = v else {
            return Err(ferr(self.file, Some(name), "missing or not an array"));
        };
        (0..arr.len())
            .map(|i| self.entry(&format!("{name}[{i}]"), arr.get(i)))
            .collect()
    }

    fn matrix(&mut self, v: Option<&toml::Value>, name: &str) -> Result<Vec<Vec<Alg>>, FileError> {
        let Some(toml::Value::Array(rows)) = v else {
            return Err(ferr(
                self.file,
                Some(name),
                "missing or not an array of rows",
            ));
        };
        let mut out = Vec::new();
        for (i, row) in rows.iter().enumerate() {
            let Some(row) = row.as_array() else {
                return Err(ferr(
                    self.file,
                    Some(&format!("{name}[{i}]")),
                    "expected a row (an array)",
                ));
            };
            let mut r = Vec::new();
            for j in 0..row.len() {
                r.push(self.entry(&format!("{name}[{i}][{j}]"), row.get(j))?);
            }
            out.push(r);
        }
        Ok(out)
    }

    fn eval(&mut self, field: &str, e: &Expr) -> Result<Alg, FileError> {
        let err = |m: String| ferr(self.file, Some(field), m);
        Ok(match &e.kind {
            ExprKind::Int(n) => Alg::rational(BigRational::from_integer(n.clone())),
            ExprKind::Decimal(r) => Alg::rational(r.clone()),
            ExprKind::Name(n) => self
                .env
                .get(n)
                .cloned()
                .ok_or_else(|| err(format!("unknown name `{n}`")))?,
            ExprKind::Neg(x) => self.eval(field, x)?.neg(),
            ExprKind::Binary { op, lhs, rhs } => {
                let l = self.eval(field, lhs)?;
                let r = self.eval(field, rhs)?;
                match op {
                    BinOp::Add => l.add(&r),
                    BinOp::Sub => l.sub(&r),
                    BinOp::Mul => self.field.try_mul(&l, &r).map_err(|e| err(e.0))?,
                    BinOp::Div => {
                        let inv = self.field.inverse(&r).map_err(&err)?;
                        self.field.try_mul(&l, &inv).map_err(|e| err(e.0))?
                    }
                }
            }
            ExprKind::Pow { base, exp } => {
                let b = self.eval(field, base)?;
                let k = self
                    .eval(field, exp)?
                    .as_rational()
                    .filter(|k| {
                        k.is_integer()
                            && super::poly::qle(&k.abs(), &BigRational::from_integer(64.into()))
                    })
                    .ok_or_else(|| err("the exponent must be an integer with |k| ≤ 64".into()))?
                    .to_integer()
                    .to_i64()
                    .ok_or_else(|| err("the exponent must be an integer with |k| ≤ 64".into()))?;
                let p = self
                    .field
                    .try_pow(&b, k.unsigned_abs() as u32)
                    .map_err(|e| err(e.0))?;
                if k < 0 {
                    self.field.inverse(&p).map_err(&err)?
                } else {
                    p
                }
            }
            ExprKind::Call { func, arg } => {
                let a = self.eval(field, arg)?;
                let Some(r) = self.field.reduce(&a).as_rational() else {
                    // A nested radical: a new root of the radicand's
                    // characteristic polynomial (Field::nth_root).
                    let n = match func {
                        Func::Sqrt => 2,
                        Func::Cbrt => 3,
                    };
                    let name = format!("{}({arg})", func.name());
                    return self.field.nth_root(&a, n, &name).map_err(err);
                };
                let one = BigRational::from_integer(1.into());
                let big = if super::poly::qlt(&one, &r.abs()) {
                    r.abs() + &one
                } else {
                    &one + &one
                };
                let (poly, lo, name) = match func {
                    Func::Sqrt => {
                        if r.is_negative() {
                            return Err(err(format!("square root of a negative number ({r})")));
                        }
                        if r.is_zero() {
                            return Ok(Alg::zero());
                        }
                        (
                            Poly(vec![-r.clone(), BigRational::zero(), one.clone()]),
                            BigRational::zero(),
                            format!("sqrt({r})"),
                        )
                    }
                    Func::Cbrt => (
                        Poly(vec![
                            -r.clone(),
                            BigRational::zero(),
                            BigRational::zero(),
                            one.clone(),
                        ]),
                        -big.clone(),
                        format!("cbrt({r})"),
                    ),
                };
                let root =
                    RealRoot::new(&poly, lo, big).map_err(|_| err("no unique root".into()))?;
                self.field.push(root, name)
            }
        })
    }
}

/// One `Wᵢⱼ` of a root-entry table (for a pair, one entry of the pair
/// condition `bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ`).
#[derive(Clone, Debug)]
pub struct WEntryAlg {
    pub i: usize,
    pub j: usize,
    /// `None`: beyond the zero-test budget.
    pub zero: Option<bool>,
    /// The correctly rounded value, for nonzero entries (±∞ when the exact
    /// value is beyond the largest double).
    pub value: Option<f64>,
}

impl WEntryAlg {
    /// The value for messages: `≈ 2.5e-3`, `beyond ±1.8e308` where the exact
    /// value overflows a double (an entry with `10^999` in it), `value beyond
    /// the budget` where it could not be rounded.
    pub fn approx(&self) -> String {
        match self.value {
            Some(v) if v.is_infinite() => {
                format!(
                    "{}1.8e308 beyond the range of f64",
                    if v > 0.0 { "> " } else { "< -" }
                )
            }
            Some(v) => format!("≈ {v:e}"),
            None => "value beyond the budget".into(),
        }
    }
}

/// The verdicts on a root-entry table.
#[derive(Clone, Debug)]
pub struct AlgAnalysis {
    pub stages: usize,
    /// Every `Wᵢⱼ`, `i ≤ j` (for a pair: every entry of the pair
    /// condition, all `i, j`).
    pub w: Vec<WEntryAlg>,
    /// `Some(true)`: symplectic for every Hamiltonian (`W = 0`; for a pair,
    /// the pair condition and `b = b̂`); `Some(false)`: not; `None`: some
    /// test beyond budget and none failed.
    pub symplectic: Option<bool>,
    /// Rows whose given `cᵢ` differs from the row sum (`None`: undecided).
    pub row_sums_ok: Option<bool>,
    /// `B(k)` for `k = 1, 2, …`: decided levels until the first failure or
    /// undecided one.
    pub b_levels: Vec<Option<bool>>,
    /// Whether the table is a partitioned pair (`a_hat`, `b_hat` given).
    pub pair: bool,
    /// Symplectic for separable Hamiltonians: the pair condition alone (for
    /// a Runge–Kutta table the same as [`Self::symplectic`]).
    pub symplectic_separable: Option<bool>,
    /// For a pair: `b = b̂` (`None`: undecided or not a pair).
    pub same_weights: Option<bool>,
    /// The first `i` with `bᵢ ≠ b̂ᵢ`, with both values, when `b ≠ b̂`.
    pub weights_differ: Option<(usize, Option<f64>, Option<f64>)>,
    /// For a pair: `c_hat` (or, when absent, nothing to check) against the
    /// row sums of `a_hat`.
    pub row_sums_hat_ok: Option<bool>,
    /// For a pair: `B(k)` for `b_hat` (with `c_hat`, else the row sums of
    /// `a_hat`).
    pub b_hat_levels: Vec<Option<bool>>,
    /// Why each undecided verdict is undecided: the budget, its limit and
    /// its constant's path.
    pub refusals: Vec<String>,
    /// The estimated work of the analysis, in the units of
    /// [`crate::budget::MAX_ANALYSIS_WORK`].
    pub work: u64,
}

/// The row sums of `a`, collapsed to as few roots as the field allows
/// ([`Field::collapse`]), or `c` as given.
fn abscissae(f: &Field, a: &[Vec<Alg>], c: Option<&Vec<Alg>>) -> Vec<Alg> {
    match c {
        Some(c) => c.clone(),
        None => a
            .iter()
            .map(|r| f.collapse(&r.iter().fold(Alg::zero(), |acc, x| acc.add(x))))
            .collect(),
    }
}

/// Whether the given `c` equals the row sums of `a` (`Some(true)` when `c`
/// is absent).
fn row_sums(
    f: &Field,
    a: &[Vec<Alg>],
    c: Option<&Vec<Alg>>,
    refusals: &mut Vec<String>,
    what: &str,
) -> Option<bool> {
    let Some(c) = c else {
        return Some(true);
    };
    let mut ok = Some(true);
    for (i, row) in a.iter().enumerate() {
        let sum = row.iter().fold(Alg::zero(), |acc, x| acc.add(x));
        match f.is_zero(&sum.sub(&c[i])) {
            Ok(true) => {}
            Ok(false) => return Some(false),
            Err(e) => {
                refusals.push(format!("{what}[{i}] against the row sum: {e}"));
                ok = None;
            }
        }
    }
    ok
}

/// `B(k)`, `k = 1 … kmax`, until the first level that fails or is beyond
/// budget: `Σᵢ bᵢ cᵢ^{k−1} = 1/k`.
fn quadrature_levels(
    f: &Field,
    b: &[Alg],
    c: &[Alg],
    kmax: usize,
    refusals: &mut Vec<String>,
    what: &str,
) -> Vec<Option<bool>> {
    let mut out = Vec::new();
    // bᵢ cᵢ^{k−1}, updated by one product per level.
    let mut terms: Vec<Alg> = b.to_vec();
    for k in 1..=kmax {
        if k > 1 {
            let mut next = Vec::with_capacity(terms.len());
            for (t, ci) in terms.iter().zip(c) {
                match f.try_mul(t, ci) {
                    Ok(x) => next.push(x),
                    Err(e) => {
                        refusals.push(format!("B({k}) for {what}: {e}"));
                        out.push(None);
                        return out;
                    }
                }
            }
            terms = next;
        }
        let mut sum = Alg::rational(-BigRational::from_integer((k as i64).into()).recip());
        for t in &terms {
            sum = sum.add(t);
        }
        let v = match f.is_zero(&sum) {
            Ok(v) => Some(v),
            Err(e) => {
                refusals.push(format!("B({k}) for {what}: {e}"));
                None
            }
        };
        out.push(v);
        if v != Some(true) {
            break;
        }
    }
    out
}

/// `x₀y₀ + x₁y₁ − x₂y₂`, each product within the budgets of
/// [`Field::try_mul`].
fn w_entry(f: &Field, x: [&Alg; 3], y: [&Alg; 3]) -> Result<Alg, BeyondBudget> {
    Ok(f.try_mul(x[0], y[0])?
        .add(&f.try_mul(x[1], y[1])?)
        .sub(&f.try_mul(x[2], y[2])?))
}

/// Decide one entry, with its value when nonzero.
fn entry(
    f: &Field,
    e: Result<Alg, BeyondBudget>,
    i: usize,
    j: usize,
    refusals: &mut Vec<String>,
) -> WEntryAlg {
    let zero = match e.as_ref().map_err(Clone::clone).and_then(|e| f.is_zero(e)) {
        Ok(z) => Some(z),
        Err(err) => {
            refusals.push(format!("W[{i}][{j}]: {err}"));
            None
        }
    };
    let value = match (&e, zero) {
        (Ok(e), Some(false)) => f.to_f64(e).ok(),
        _ => None,
    };
    WEntryAlg { i, j, zero, value }
}

fn all_zero(w: &[WEntryAlg]) -> Option<bool> {
    if w.iter().any(|e| e.zero == Some(false)) {
        Some(false)
    } else if w.iter().all(|e| e.zero == Some(true)) {
        Some(true)
    } else {
        None
    }
}

impl AlgFile {
    /// Decide symplecticity (every `Wᵢⱼ`, or every entry of the pair
    /// condition and `b = b̂`), the row sums and `B(k)`, exactly; each test
    /// within the budgets of [`super::alg`], all of them together within
    /// [`crate::budget::MAX_ANALYSIS_WORK`]. A test beyond a budget is
    /// undecided (`None`), and [`AlgAnalysis::refusals`] says why.
    pub fn analyse(&self) -> AlgAnalysis {
        let f = &self
            .field
            .clone()
            .with_default_work_limit(crate::budget::MAX_ANALYSIS_WORK);
        let s = self.b.len();
        let mut refusals = Vec::new();
        let mut w = Vec::new();
        let pair = match (&self.a_hat, &self.b_hat) {
            (Some(ah), Some(bh)) => Some((ah, bh)),
            _ => None,
        };
        match pair {
            None => {
                for i in 0..s {
                    for j in i..s {
                        let e = w_entry(
                            f,
                            [&self.b[i], &self.b[j], &self.b[i]],
                            [&self.a[i][j], &self.a[j][i], &self.b[j]],
                        );
                        w.push(entry(f, e, i, j, &mut refusals));
                    }
                }
            }
            Some((ah, bh)) => {
                for i in 0..s {
                    for j in 0..s {
                        // bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ
                        let e = w_entry(
                            f,
                            [&self.b[i], &bh[j], &self.b[i]],
                            [&ah[i][j], &self.a[j][i], &bh[j]],
                        );
                        w.push(entry(f, e, i, j, &mut refusals));
                    }
                }
            }
        }
        let conditions = all_zero(&w);
        let (mut same_weights, mut weights_differ) = (None, None);
        if let Some((_, bh)) = pair {
            let mut same = Some(true);
            for i in 0..s {
                let d = self.b[i].sub(&bh[i]);
                match f.is_zero(&d) {
                    Ok(true) => {}
                    Ok(false) => {
                        same = Some(false);
                        weights_differ =
                            Some((i, f.to_f64(&self.b[i]).ok(), f.to_f64(&bh[i]).ok()));
                        break;
                    }
                    Err(e) => {
                        refusals.push(format!("b[{i}] = b_hat[{i}]: {e}"));
                        same = None;
                    }
                }
            }
            same_weights = same;
        }
        let symplectic = match (pair.is_some(), conditions, same_weights) {
            (false, c, _) => c,
            (true, Some(false), _) | (true, _, Some(false)) => Some(false),
            (true, Some(true), Some(true)) => Some(true),
            _ => None,
        };
        let row_sums_ok = row_sums(f, &self.a, self.c.as_ref(), &mut refusals, "c");
        let c = abscissae(f, &self.a, self.c.as_ref());
        let b_levels = quadrature_levels(f, &self.b, &c, 2 * s + 1, &mut refusals, "b");
        let (row_sums_hat_ok, b_hat_levels) = match pair {
            Some((ah, bh)) => {
                let ok = row_sums(f, ah, self.c_hat.as_ref(), &mut refusals, "c_hat");
                let ch = abscissae(f, ah, self.c_hat.as_ref());
                (
                    ok,
                    quadrature_levels(f, bh, &ch, 2 * s + 1, &mut refusals, "b_hat"),
                )
            }
            None => (None, Vec::new()),
        };
        AlgAnalysis {
            stages: s,
            w,
            symplectic,
            row_sums_ok,
            b_levels,
            pair: pair.is_some(),
            symplectic_separable: conditions,
            same_weights,
            weights_differ,
            row_sums_hat_ok,
            b_hat_levels,
            refusals,
            work: f.work_spent(),
        }
    }

    /// Decide an order claim on the trees, in the number field
    /// ([`super::trees`]): a Runge–Kutta table on the rooted trees (with
    /// time leaves when the given `c` differs from the row sums), a pair on
    /// the bicoloured trees (the separable ones when `b ≠ b̂`, where it is
    /// symplectic for separable Hamiltonians only), and `order_rkn` on the
    /// Nyström trees (a Runge–Kutta table as the pair `(A, b), (A, b)`).
    /// The claim holds when every condition up to `p` holds exactly (or
    /// within the rational `bound`); a condition beyond the budgets refuses
    /// the claim as undecided, saying which.
    fn decide_order(
        &self,
        an: &AlgAnalysis,
        p: usize,
        bound: Option<&crate::Number>,
        rkn: bool,
    ) -> Result<(), String> {
        use super::trees::{ColourRule, alg_tree_order};
        use crate::trees::{Colour, Colouring};
        let keyword = if rkn { "order_rkn" } else { "order" };
        if p > crate::trees::MAX_ORDER {
            return Err(format!(
                "{keyword} {p} cannot be decided: the trees are examined up to order {} (tableau::trees::MAX_ORDER)",
                crate::trees::MAX_ORDER
            ));
        }
        let bound = match bound {
            None => None,
            Some(b) => Some(b.as_rational().ok_or_else(|| {
                format!("the residual bound {b} of a table with root(...) entries must be rational")
            })?),
        };
        let f = &self
            .field
            .clone()
            .with_default_work_limit(crate::budget::MAX_ANALYSIS_WORK);
        let s = self.b.len();
        let c = abscissae(f, &self.a, self.c.as_ref());
        let (colouring, rules, scope): (Colouring, Vec<ColourRule<'_>>, &str) = match (
            &self.a_hat,
            &self.b_hat,
        ) {
            (Some(ah), Some(bh)) => {
                let colouring = if rkn {
                    Colouring::Nystrom
                } else {
                    match an.same_weights {
                        Some(true) => Colouring::Bicoloured,
                        Some(false) => Colouring::Separable,
                        None => {
                            return Err(format!(
                                "{keyword} {p} cannot be decided: whether b = b̂ (which trees are the conditions) is beyond the budgets of exact zero tests"
                            ));
                        }
                    }
                };
                let scope = match colouring {
                    Colouring::Nystrom => " (on Runge–Kutta–Nyström systems, T quadratic)",
                    Colouring::Separable => " (on separable systems: b ≠ b̂)",
                    _ => " (on general partitioned systems)",
                };
                (
                    colouring,
                    vec![
                        ColourRule {
                            colour: Colour::Q,
                            a: Some(&self.a),
                            fixed: None,
                            b: Some(&self.b),
                        },
                        ColourRule {
                            colour: Colour::P,
                            a: Some(ah),
                            fixed: None,
                            b: Some(bh),
                        },
                    ],
                    scope,
                )
            }
            _ if rkn => (
                Colouring::Nystrom,
                [Colour::Q, Colour::P]
                    .into_iter()
                    .map(|colour| ColourRule {
                        colour,
                        a: Some(&self.a),
                        fixed: None,
                        b: Some(&self.b),
                    })
                    .collect(),
                " (on Runge–Kutta–Nyström systems, T quadratic)",
            ),
            _ => {
                let time = match an.row_sums_ok {
                    Some(ok) => !ok,
                    None => {
                        return Err(format!(
                            "{keyword} {p} cannot be decided: whether c equals the row sums of A (which trees are the conditions) is beyond the budgets of exact zero tests"
                        ));
                    }
                };
                let mut rules = vec![ColourRule {
                    colour: Colour::Y,
                    a: Some(&self.a),
                    fixed: None,
                    b: Some(&self.b),
                }];
                if time {
                    rules.push(ColourRule {
                        colour: Colour::T,
                        a: None,
                        fixed: Some(&c),
                        b: None,
                    });
                }
                let colouring = if time {
                    Colouring::TimeLeaves
                } else {
                    Colouring::Plain
                };
                let scope = if time {
                    " (on non-autonomous problems: c differs from the row sums)"
                } else {
                    ""
                };
                (colouring, rules, scope)
            }
        };
        let r = alg_tree_order(f, colouring, &rules, s, p, bound.as_ref());
        if r.order >= p {
            return Ok(());
        }
        if let Some(fail) = &r.failure {
            let residual = match fail.residual {
                Some(v) => format!("≈ {v:e}"),
                None => "(value beyond the budget)".into(),
            };
            let how = match &bound {
                Some(b) => format!("Φ(t) − 1/γ(t) {residual} is not below {b} in absolute value"),
                None => format!("Φ(t) − 1/γ(t) ≠ 0 ({residual}), 1/γ(t) = {}", fail.expected),
            };
            return Err(format!(
                "{keyword} {p} claimed{scope} but the order-{} condition for tree {} fails: {how} (decided exactly on the algebraic entries)",
                fail.order, fail.tree
            ));
        }
        Err(format!(
            "{keyword} {p} cannot be decided: every condition up to order {} holds exactly{scope}, but {}",
            r.order,
            r.undecided.as_deref().unwrap_or("(no reason recorded)")
        ))
    }

    /// Whether the drift–kick sequence is a palindrome, decided exactly: the
    /// flows with a zero coefficient dropped and neighbours of one kind
    /// merged (the normal form in which two sequences are the same map for
    /// every separable `H` exactly when they are equal), then
    /// `xᵢ = x_{n−1−i}` by exact zero tests.
    fn sequence_symmetric(&self) -> Result<(), String> {
        use crate::near_integrable::Factor;
        let seq = self.sequence.as_ref().expect("a sequence");
        let f = self
            .field
            .clone()
            .with_default_work_limit(crate::budget::MAX_ANALYSIS_WORK);
        let undecided = |e: BeyondBudget| {
            format!("symmetry cannot be decided within the budgets of exact zero tests: {e}")
        };
        let mut flows: Vec<(u8, Alg)> = Vec::new();
        for factor in seq.factors() {
            let Factor::Letter(l, x) = factor else {
                unreachable!("root sequences have plain kicks")
            };
            if f.is_zero(&x).map_err(undecided)? {
                continue;
            }
            match flows.last_mut() {
                Some((m, y)) if *m == l => {
                    *y = y.add(&x);
                    if f.is_zero(y).map_err(undecided)? {
                        flows.pop();
                    }
                }
                _ => flows.push((l, x)),
            }
        }
        let n = flows.len();
        for i in 0..n / 2 {
            let (l, x) = &flows[i];
            let (m, y) = &flows[n - 1 - i];
            if l != m || !f.is_zero(&x.sub(y)).map_err(undecided)? {
                return Err(format!(
                    "not symmetric: the drift–kick sequence (zeros dropped, neighbours merged; {n} flows) is not a palindrome: flow {i} differs from flow {} (decided exactly on the algebraic entries)",
                    n - 1 - i
                ));
            }
        }
        Ok(())
    }

    /// Check a claim against the analysis; symplecticity is decided
    /// exactly and a refusal names the nonzero `Wᵢⱼ`. As for ordinary
    /// table files, `symplectic` on a pair means the pair condition
    /// (symplectic for separable Hamiltonians; for every Hamiltonian when
    /// also `b = b̂`).
    pub fn check_claim(&self, an: &AlgAnalysis, claim: &Claim) -> Result<(), String> {
        let rule = if an.pair {
            "Wᵢⱼ = bᵢâᵢⱼ + b̂ⱼaⱼᵢ − bᵢb̂ⱼ must vanish"
        } else {
            "W = BA + AᵀB − bbᵀ must vanish"
        };
        match claim {
            Claim::Symplectic => match an.symplectic_separable {
                Some(true) => Ok(()),
                Some(false) => {
                    let bad: Vec<&WEntryAlg> =
                        an.w.iter().filter(|e| e.zero == Some(false)).collect();
                    let shown: Vec<String> = bad
                        .iter()
                        .take(6)
                        .map(|e| format!("W[{}][{}] ≠ 0 ({})", e.i, e.j, e.approx()))
                        .collect();
                    let more = if bad.len() > 6 {
                        format!(" and {} more", bad.len() - 6)
                    } else {
                        String::new()
                    };
                    Err(format!(
                        "not symplectic: {}{more} ({rule}; decided exactly on the algebraic entries)",
                        shown.join(", ")
                    ))
                }
                None => Err(format!(
                    "symplecticity cannot be decided within the budgets of exact zero tests: {}",
                    an.refusals
                        .iter()
                        .find(|r| r.starts_with("W["))
                        .map_or("(no reason recorded)", String::as_str)
                )),
            },
            Claim::Order { p, bound: None } => {
                // A failing B(k) is the failing condition of a bushy tree,
                // a quick refusal, where that tree is a condition: for a
                // Runge–Kutta table always (with time leaves when c is not
                // the row sums), for a pair when b = b̂ (all bicoloured
                // trees) and the abscissae are A's (Â's) row sums.
                let same = an.same_weights == Some(true);
                let b_tree = !an.pair || (same && an.row_sums_ok == Some(true));
                let b_hat_tree = an.pair && same && an.row_sums_hat_ok == Some(true);
                let holds = an.b_levels.iter().take_while(|v| **v == Some(true)).count();
                if b_tree && holds < *p && an.b_levels.get(holds) == Some(&Some(false)) {
                    return Err(format!(
                        "order {p} claimed but B({}) fails (Σ bᵢcᵢ^{holds} ≠ 1/{}), so the order is at most {holds}",
                        holds + 1,
                        holds + 1
                    ));
                }
                let hh = an
                    .b_hat_levels
                    .iter()
                    .take_while(|v| **v == Some(true))
                    .count();
                if b_hat_tree && hh < *p && an.b_hat_levels.get(hh) == Some(&Some(false)) {
                    return Err(format!(
                        "order {p} claimed but B({}) fails for b_hat (Σ b̂ᵢĉᵢ^{hh} ≠ 1/{}), so the order is at most {hh}",
                        hh + 1,
                        hh + 1
                    ));
                }
                self.decide_order(an, *p, None, false)
            }
            Claim::Order { p, bound: Some(b) } => self.decide_order(an, *p, Some(b), false),
            Claim::OrderRkn { p, bound } => self.decide_order(an, *p, bound.as_ref(), true),
            Claim::NearOrder { orders, bound } => match &self.sequence {
                Some(seq) => {
                    let bound = match bound {
                        None => None,
                        Some(b) => Some(b.as_rational().ok_or_else(|| {
                            format!("the residual bound {b} of a table with root(...) entries must be rational")
                        })?),
                    };
                    let f = self
                        .field
                        .clone()
                        .with_default_work_limit(crate::budget::MAX_ANALYSIS_WORK);
                    super::near::alg_near_claim(
                        &f,
                        &seq.factors(),
                        orders,
                        bound.as_ref(),
                    )
                }
                None => Err(
                    "a generalised order (p1, p2, …) is a property of a drift–kick sequence (drift, kick); this table is a Butcher table".into(),
                ),
            },
            Claim::Symmetric if self.sequence.is_some() => self.sequence_symmetric(),
            other => Err(format!(
                "`{other}` is not decided for tables with root(...) entries"
            )),
        }
    }
}
