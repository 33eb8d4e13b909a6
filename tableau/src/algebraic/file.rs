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
//! division is allowed by expressions in one root. Zero is decided exactly
//! ([`super::alg`]): the symplecticity verdict names every nonzero `Wᵢⱼ`.
//! Conditions that mix many roots (the sums in `B(p)`, `C(q)`, `D(r)`) are
//! decided when within the budget [`super::alg::MAX_ZERO_TEST_BITS`] and
//! reported as undecided otherwise; symmetry and the stability function are
//! not computed for such files. A file without `generate` or `root(` is an
//! ordinary table file.

#![allow(clippy::needless_range_loop)] // index-heavy table code

use std::collections::BTreeMap;
use std::path::Path;

use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};

use super::alg::{Alg, Field};
use super::family::Generator;
use super::generated::{Generated, literature_claims};
use super::poly::Poly;
use super::root::RealRoot;
use crate::budget::MAX_FILE_BYTES;
use crate::claims::{Claim, parse_claim};
use crate::expr::{self, BinOp, Expr, ExprKind, Func};
use crate::file::{FileError, TableFile, parse_table_file};

/// What a table file holds.
#[derive(Debug)]
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
    parse_table_file(file, text).map(|t| Loaded::Classic(Box::new(t)))
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
        if !["name", "source", "claims", "let", "a", "b", "c"].contains(&key.as_str()) {
            return Err(ferr(
                file,
                Some(key),
                format!(
                    "unknown field `{key}` in a table with root(...) entries (the fields are name, source, claims, let, a, b, c)"
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
        field: Field::default(),
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
    let a = cx.matrix(doc.get("a"), "a")?;
    let b = cx.vector(doc.get("b"), "b")?;
    let c = match doc.get("c") {
        None => None,
        v => Some(cx.vector(v, "c")?),
    };
    let s = b.len();
    if a.len() != s || a.iter().any(|r| r.len() != s) || c.as_ref().is_some_and(|c| c.len() != s) {
        return Err(ferr(
            file,
            Some("a"),
            format!("a must be {s}×{s} and c (if given) of length {s}, as b has {s} entries"),
        ));
    }
    Ok(AlgFile {
        name,
        source,
        claims,
        field: cx.field,
        a,
        b,
        c,
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
    if super::poly::qle(&hi, &lo) {
        return Err(format!("the interval ({lo}, {hi}] is empty"));
    }
    RealRoot::new(&p, lo.clone(), hi.clone()).map_err(|n| {
        format!(
            "the polynomial has {n} distinct real roots in ({lo}, {hi}], not exactly one: give an isolating interval"
        )
    })
}

/// A polynomial in `x` with rational coefficients, from an expression.
fn poly_of(e: &Expr) -> Result<Poly, String> {
    Ok(match &e.kind {
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
                    if l.0.len() + r.0.len() > 200 {
                        return Err("degree above 200".into());
                    }
                    l.mul(&r)
                }
                BinOp::Div => match r.degree() {
                    Some(0) => l.scale(&r.coeff(0).recip()),
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
                    .filter(|&k| k <= 200)
                    .ok_or("exponent must be an integer in 0..=200")?,
                _ => return Err("exponent must be an integer".into()),
            };
            b.pow(k)
        }
        ExprKind::Call { .. } => {
            return Err("sqrt/cbrt are not allowed in root(...)'s polynomial".into());
        }
    })
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
                    BinOp::Mul => self.field.mul(&l, &r),
                    BinOp::Div => {
                        let inv = self.field.inverse(&r).map_err(&err)?;
                        self.field.mul(&l, &inv)
                    }
                }
            }
            ExprKind::Pow { base, exp } => {
                let b = self.eval(field, base)?;
                let k = self
                    .eval(field, exp)?
                    .as_rational()
                    .filter(|k| k.is_integer() && super::poly::qle(&k.abs(), &BigRational::from_integer(64.into())))
                    .ok_or_else(|| err("the exponent must be an integer with |k| ≤ 64".into()))?
                    .to_integer()
                    .to_i64()
                    .expect("small");
                let p = self.field.pow(&b, k.unsigned_abs() as u32);
                if k < 0 {
                    self.field.inverse(&p).map_err(&err)?
                } else {
                    p
                }
            }
            ExprKind::Call { func, arg } => {
                let a = self.eval(field, arg)?;
                let r = a.as_rational().ok_or_else(|| {
                    err(format!(
                        "{}(...) of an irrational number: write it as root(...) in `let`",
                        func.name()
                    ))
                })?;
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

/// One `Wᵢⱼ` of a root-entry table.
#[derive(Clone, Debug)]
pub struct WEntryAlg {
    pub i: usize,
    pub j: usize,
    /// `None`: beyond the zero-test budget.
    pub zero: Option<bool>,
    /// The correctly rounded value, for nonzero entries.
    pub value: Option<f64>,
}

/// The verdicts on a root-entry table.
#[derive(Clone, Debug)]
pub struct AlgAnalysis {
    pub stages: usize,
    /// Every `Wᵢⱼ`, `i ≤ j`.
    pub w: Vec<WEntryAlg>,
    /// `Some(true)`: `W = 0`; `Some(false)`: some `Wᵢⱼ ≠ 0`; `None`: some
    /// entries beyond budget and none nonzero.
    pub symplectic: Option<bool>,
    /// Rows whose given `cᵢ` differs from the row sum (`None`: undecided).
    pub row_sums_ok: Option<bool>,
    /// `B(k)` for `k = 1, 2, …`: decided levels until the first failure or
    /// undecided one.
    pub b_levels: Vec<Option<bool>>,
}

impl AlgFile {
    pub fn analyse(&self) -> AlgAnalysis {
        let f = &self.field;
        let s = self.b.len();
        let mut w = Vec::new();
        for i in 0..s {
            for j in i..s {
                let e = f
                    .mul(&self.b[i], &self.a[i][j])
                    .add(&f.mul(&self.b[j], &self.a[j][i]))
                    .sub(&f.mul(&self.b[i], &self.b[j]));
                let zero = f.is_zero(&e).ok();
                let value = (zero == Some(false)).then(|| f.to_f64(&e).ok()).flatten();
                w.push(WEntryAlg { i, j, zero, value });
            }
        }
        let symplectic = if w.iter().any(|e| e.zero == Some(false)) {
            Some(false)
        } else if w.iter().all(|e| e.zero == Some(true)) {
            Some(true)
        } else {
            None
        };
        let row_sums_ok = match &self.c {
            None => Some(true),
            Some(c) => {
                let mut ok = Some(true);
                for i in 0..s {
                    let sum = self.a[i].iter().fold(Alg::zero(), |acc, x| acc.add(x));
                    match f.is_zero(&sum.sub(&c[i])) {
                        Ok(true) => {}
                        Ok(false) => {
                            ok = Some(false);
                            break;
                        }
                        Err(_) => ok = None,
                    }
                }
                ok
            }
        };
        let c: Vec<Alg> = match &self.c {
            Some(c) => c.clone(),
            None => self
                .a
                .iter()
                .map(|r| r.iter().fold(Alg::zero(), |acc, x| acc.add(x)))
                .collect(),
        };
        let mut b_levels = Vec::new();
        for k in 1..=2 * s + 1 {
            let mut sum = Alg::rational(-BigRational::from_integer((k as i64).into()).recip());
            for i in 0..s {
                sum = sum.add(&f.mul(&self.b[i], &f.pow(&c[i], (k - 1) as u32)));
            }
            let v = f.is_zero(&sum).ok();
            b_levels.push(v);
            if v != Some(true) {
                break;
            }
        }
        AlgAnalysis {
            stages: s,
            w,
            symplectic,
            row_sums_ok,
            b_levels,
        }
    }

    /// Check a claim against the analysis; symplecticity is decided
    /// exactly and a refusal names the nonzero `Wᵢⱼ`.
    pub fn check_claim(&self, an: &AlgAnalysis, claim: &Claim) -> Result<(), String> {
        match claim {
            Claim::Symplectic => match an.symplectic {
                Some(true) => Ok(()),
                Some(false) => {
                    let shown: Vec<String> = an
                        .w
                        .iter()
                        .filter(|e| e.zero == Some(false))
                        .take(6)
                        .map(|e| {
                            format!(
                                "W[{}][{}] ≠ 0 (≈ {})",
                                e.i,
                                e.j,
                                e.value.map_or("?".into(), |v| format!("{v:e}"))
                            )
                        })
                        .collect();
                    Err(format!(
                        "not symplectic: {} (W = BA + AᵀB − bbᵀ must vanish; decided exactly on the algebraic entries)",
                        shown.join(", ")
                    ))
                }
                None => Err("symplecticity cannot be decided within the budget of exact zero tests (tableau::algebraic::alg::MAX_ZERO_TEST_BITS)".into()),
            },
            Claim::Order { p, bound: None } => {
                let holds = an.b_levels.iter().take_while(|v| **v == Some(true)).count();
                if holds < *p && an.b_levels.get(holds) == Some(&Some(false)) {
                    {
                        return Err(format!(
                            "order {p} claimed but B({}) fails (Σ bᵢcᵢ^{holds} ≠ 1/{}), so the order is at most {holds}",
                            holds + 1,
                            holds + 1
                        ));
                    }
                }
                Err(format!(
                    "order claims are not decided for tables with root(...) entries (B(k) holds exactly for k ≤ {holds}); use a generator (generate = \"gauss(s)\") for a proven order"
                ))
            }
            other => Err(format!(
                "`{other}` is not decided for tables with root(...) entries"
            )),
        }
    }
}
