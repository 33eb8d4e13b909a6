//! Table files: a Butcher table (or a partitioned pair, a drift–kick
//! sequence, a composition) written in TOML, with exact entries.
//!
//! ```toml
//! name = "Gauss–Legendre, 2 stages"                   # required
//! source = "Butcher 1964"                             # optional: a literature reference
//! claims = ["symplectic", "symmetric", "order = 4"]   # optional, see crate::claims
//! let = { r = "sqrt(3)/6" }                           # optional named values
//! a = [["1/4", "1/4 - r"], ["1/4 + r", "1/4"]]
//! b = ["1/2", "1/2"]
//! # c = [...]                               optional abscissae
//! # a_hat, b_hat (and c_hat)                a partitioned pair: a, b act on q; a_hat, b_hat on p
//! # drift = [...]; kick = [...]             instead of a, b: a drift–kick sequence
//! # kick_gradient = [...]                   optional, beside kick: gradient kicks
//! # compose = [...]                         instead of a, b: a composition of Störmer–Verlet
//! ```
//!
//! **Processed methods.** A drift–kick sequence or composition (the kernel
//! `K`) with a corrector `χ`, stepped as `χ Kⁿ χ⁻¹`: `χ⁻¹` once on entry,
//! `K` every step, `χ` only at output (Wisdom, Holman & Touma 1996;
//! Blanes–Casas processing). The kernel is written inline (`drift`/`kick`
//! or `compose`) or named from the catalogue, and the corrector is a
//! drift–kick sequence, its coefficients typically summing to zero:
//!
//! ```toml
//! kernel = "leapfrog"                  # a catalogue id (or inline drift/kick/compose)
//! corrector_drift = ["a", "-2*a", "a"] # χ, the map applied at output, in the order applied
//! corrector_kick = ["-b", "b"]
//! claims = ["order = (4, 2)"]          # the effective orders, of χ K χ⁻¹
//! ```
//!
//! Every order claim of such a file is about the effective method `χ K χ⁻¹`
//! (see [`crate::near_integrable::check_processed_claim`]).
//!
//! **Gradient kicks.** `kick_gradient = [g₁, g₂, …]` beside `kick` (one
//! entry per kick, `0` for a plain kick) makes kick `i` the exact flow of
//! `kᵢ·h·B + gᵢ·h³·[B,[A,B]]` (see [`crate::Splitting`]): for `T` quadratic,
//! the kick of `kᵢ·V − gᵢ·h²·|∇V|²_{M⁻¹}`. Such a sequence has no
//! partitioned Runge–Kutta form; its claims are decided on the Lie algebra.
//! A corrector's kicks are plain.
//!
//! Entries are strings in the grammar of [`crate::expr`] or TOML integers.
//! TOML floats are refused: a binary float is not the decimal its author
//! wrote. A `let` binding may use other bindings, in any order; a cycle is an
//! error. Every error names the file and, where there is one, the field, as
//! the author wrote it (`a[1][0]`, `b_hat[2]`, `let.x`, with 0-based indices).

use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;

use num_bigint::BigInt;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::budget::{MAX_FILE_BYTES, MAX_LITERAL_DIGITS};
use crate::claims::{Claim, parse_claim};
use crate::expr::{self, EvalErrorKind, Expr, ExprKind};
use crate::{Composition, Number, Prk, Rk, Splitting, Table};

/// A table file, read and checked for shape.
#[derive(Clone, Debug, PartialEq)]
pub struct TableFile {
    pub name: String,
    /// A literature reference, if given.
    pub source: Option<String>,
    /// The claims, in the order written.
    pub claims: Vec<Claim>,
    /// The table; for a processed method, its kernel `K`.
    pub table: Table,
    /// For a processed method: the catalogue id its kernel was read from
    /// (`kernel = "leapfrog"`), `None` for an inline kernel.
    pub kernel: Option<String>,
    /// For a processed method: the corrector `χ` (applied at output; `χ⁻¹`
    /// once on entry), a drift–kick sequence.
    pub corrector: Option<Splitting>,
    /// The `certificate` of a certified order claim (`order = p
    /// (certified)`), read into polynomials ([`crate::certificate`]).
    pub certificate: Option<crate::certificate::CertificateSpec>,
}

impl TableFile {
    /// The corrector as a table, for a processed method.
    pub fn corrector_table(&self) -> Option<Table> {
        self.corrector.clone().map(Table::Splitting)
    }
}

/// Why a table file was refused: the file (as the caller named it), the
/// field (`a[1][0]`, `let.x`; `None` for the file as a whole) and what is
/// wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileError {
    pub file: String,
    pub field: Option<String>,
    pub message: String,
}

impl fmt::Display for FileError {
    /// `tables/bad.toml: field a[1][0]: at column 3, unexpected …`, or
    /// `tables/bad.toml: …` when no one field is at fault.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.field {
            Some(field) => write!(f, "{}: field {}: {}", self.file, field, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for FileError {}

/// The top-level keys of a table file.
/// The fields that write a table inline (every form's), which a file
/// naming its kernel (`kernel = "ID"`) must not give; the `butcher!` macro
/// checks the same list.
pub const TABLE_FIELDS: [&str; 10] = [
    "a",
    "b",
    "c",
    "a_hat",
    "b_hat",
    "c_hat",
    "drift",
    "kick",
    "kick_gradient",
    "compose",
];

pub const KEYS: [&str; 18] = [
    "name",
    "source",
    "claims",
    "let",
    "a",
    "b",
    "c",
    "a_hat",
    "b_hat",
    "c_hat",
    "drift",
    "kick",
    "kick_gradient",
    "compose",
    "kernel",
    "corrector_drift",
    "corrector_kick",
    "certificate",
];

/// The deepest chain of `let` bindings referring to one another.
const MAX_LET_DEPTH: usize = 64;

/// A text file of at most `limit` bytes, read so that no file makes it
/// allocate more (`/dev/zero` is refused, not read until memory runs out);
/// `what` says what such a file holds, for the message when it is larger.
/// The error is the message without the file's name, for the caller to
/// name it as its messages do. Every front end that reads a user's file
/// reads it through this (table files through [`load`]).
pub fn read_text(path: &Path, limit: u64, what: &str) -> Result<String, String> {
    use std::io::Read;
    let f = std::fs::File::open(path).map_err(|e| format!("cannot read the file: {e}"))?;
    let mut bytes = Vec::new();
    f.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read the file: {e}"))?;
    if bytes.len() as u64 > limit {
        return Err(format!("the file is larger than {limit} bytes; {what}"));
    }
    String::from_utf8(bytes).map_err(|e| {
        format!(
            "not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        )
    })
}

/// Read and check the table file at `path`; messages name the file by
/// `path` as given. At most [`MAX_FILE_BYTES`] (1 MiB) are read: a larger
/// file is refused, and so is one that is not UTF-8 text.
pub fn load(path: &Path) -> Result<TableFile, FileError> {
    use std::io::Read;
    let file = path.display().to_string();
    let err = |message: String| FileError {
        file: file.clone(),
        field: None,
        message,
    };
    let f = std::fs::File::open(path).map_err(|e| err(format!("cannot read the file: {e}")))?;
    // Read at most one byte past the limit: enough to know it is too large,
    // whatever the file is (`/dev/zero` never ends).
    let mut bytes = Vec::new();
    f.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| err(format!("cannot read the file: {e}")))?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(err(format!(
            "the file is larger than {} MiB, the most a table file may be (tableau::budget::MAX_FILE_BYTES); a table file is a few kilobytes",
            MAX_FILE_BYTES >> 20
        )));
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        err(format!(
            "cannot read the file: it is not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        ))
    })?;
    parse_table_file(&file, &text)
}

/// Read and check a table file given as text; `file` is the name that
/// messages show.
pub fn parse_table_file(file: &str, text: &str) -> Result<TableFile, FileError> {
    let cx = Cx {
        file,
        text,
        lets: BTreeMap::new(),
    };
    const EMPTY: &str = "empty file: a table file needs a `name`, and `a` and `b` (or `drift` and `kick`, or `compose`)";
    if text.trim().is_empty() {
        return Err(cx.err(None, EMPTY));
    }
    let doc = DeTable::parse(text).map_err(|e| cx.err(None, e.to_string().trim_end()))?;
    let doc = doc.get_ref();
    if doc.is_empty() {
        return Err(cx.err(None, EMPTY));
    }
    let mut fields: BTreeMap<&str, &Spanned<DeValue<'_>>> = BTreeMap::new();
    for (key, value) in doc.iter() {
        let key: &str = key.get_ref().as_ref();
        if !KEYS.contains(&key) {
            let hint = match suggest(key) {
                Some(k) => format!("did you mean `{k}`? "),
                None => String::new(),
            };
            return Err(cx.err(
                Some(key.to_string()),
                format!(
                    "unknown field `{key}` ({hint}the fields are {})",
                    KEYS.join(", ")
                ),
            ));
        }
        fields.insert(key, value);
    }

    let name = match fields.get("name") {
        None => {
            return Err(cx.err(
                Some("name".into()),
                "missing: every table file needs a `name = \"...\"`",
            ));
        }
        Some(v) => cx.string("name", v)?,
    };
    if name.trim().is_empty() {
        return Err(cx.err(Some("name".into()), "the name is empty"));
    }
    let source = match fields.get("source") {
        None => None,
        Some(v) => Some(cx.string("source", v)?),
    };
    let claims = match fields.get("claims") {
        None => Vec::new(),
        Some(v) => cx.claims(v)?,
    };
    let mut cx = cx;
    if let Some(v) = fields.get("let") {
        cx.lets = cx.lets(v)?;
    }
    let (table, kernel) = match fields.get("kernel") {
        Some(v) => (cx.named_kernel(&fields, v)?, Some(cx.string("kernel", v)?)),
        None => (cx.table(&fields)?, None),
    };
    table
        .check_shape()
        .map_err(|e| cx.err(Some(e.field), e.message))?;
    let corrector = cx.corrector(&fields, &table, kernel.is_some())?;
    let certificate = if fields.contains_key("certificate") {
        if corrector.is_some() || kernel.is_some() {
            return Err(cx.err(
                Some("certificate".into()),
                "a certificate is about an inline drift–kick sequence or composition, not a processed method",
            ));
        }
        let doc: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| cx.err(None, e.to_string().trim_end()))?;
        Some(
            crate::certificate::read_spec(&doc, &cx.lets, &table)
                .map_err(|(field, message)| cx.err(Some(field), message))?,
        )
    } else {
        None
    };
    Ok(TableFile {
        name,
        source,
        claims,
        table,
        kernel,
        corrector,
        certificate,
    })
}

/// A known key close to a mistyped one.
fn suggest(key: &str) -> Option<&'static str> {
    let norm = |s: &str| s.to_ascii_lowercase().replace(['_', '-', ' '], "");
    let k = norm(key);
    KEYS.iter()
        .copied()
        .find(|known| norm(known) == k)
        .or_else(|| {
            KEYS.iter()
                .copied()
                .filter(|known| known.len() > 1)
                .find(|known| edit_distance(&k, known) <= 1)
        })
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// A `let` binding before evaluation: its expression and the text it was
/// parsed from (for messages).
struct Binding {
    expr: Expr,
    text: String,
}

/// The reading context: the file, its text, and the resolved `let` values.
struct Cx<'a> {
    file: &'a str,
    text: &'a str,
    lets: BTreeMap<String, Number>,
}

type Value<'v> = Spanned<DeValue<'v>>;

impl Cx<'_> {
    fn err(&self, field: Option<String>, message: impl Into<String>) -> FileError {
        FileError {
            file: self.file.to_string(),
            field,
            message: message.into(),
        }
    }

    fn field_err(&self, field: &str, message: impl Into<String>) -> FileError {
        self.err(Some(field.to_string()), message)
    }

    /// The text of a value as written in the file.
    fn raw(&self, v: &Value<'_>) -> &str {
        self.text.get(v.span()).unwrap_or("").trim()
    }

    /// `a boolean `true``, `a table`, … for messages.
    fn describe(&self, v: &Value<'_>) -> String {
        let kind = match v.get_ref() {
            DeValue::String(_) => "a string",
            DeValue::Integer(_) => "an integer",
            DeValue::Float(_) => "a float",
            DeValue::Boolean(_) => "a boolean",
            DeValue::Datetime(_) => "a date-time",
            DeValue::Array(_) => "an array",
            DeValue::Table(_) => "a table",
        };
        let raw = self.raw(v);
        if !raw.is_empty() && raw.len() <= 40 && !raw.contains('\n') {
            format!("{kind}, `{raw}`")
        } else {
            kind.to_string()
        }
    }

    fn string(&self, field: &str, v: &Value<'_>) -> Result<String, FileError> {
        match v.get_ref() {
            DeValue::String(s) => Ok(s.to_string()),
            _ => Err(self.field_err(
                field,
                format!("expected a string, found {}", self.describe(v)),
            )),
        }
    }

    fn array<'v, 'i>(
        &self,
        field: &str,
        v: &'v Value<'i>,
        what: &str,
    ) -> Result<&'v [Value<'i>], FileError> {
        match v.get_ref() {
            DeValue::Array(items) => Ok(items),
            _ => Err(self.field_err(
                field,
                format!("expected {what}, found {}", self.describe(v)),
            )),
        }
    }

    fn claims(&self, v: &Value<'_>) -> Result<Vec<Claim>, FileError> {
        let items = self.array(
            "claims",
            v,
            "an array of claims, as in [\"symplectic\", \"order = 4\"]",
        )?;
        let mut out = Vec::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            let field = format!("claims[{i}]");
            let text = self.string(&field, item)?;
            out.push(parse_claim(&text).map_err(|e| self.field_err(&field, e))?);
        }
        Ok(out)
    }

    /// Parse the `let` table and evaluate every binding, each after the
    /// bindings it uses.
    fn lets(&self, v: &Value<'_>) -> Result<BTreeMap<String, Number>, FileError> {
        let DeValue::Table(table) = v.get_ref() else {
            return Err(self.field_err(
                "let",
                format!(
                    "expected a table of named values, as in let = {{ x = \"1/(2 - cbrt(2))\" }}, found {}",
                    self.describe(v)
                ),
            ));
        };
        let mut defs = BTreeMap::new();
        for (key, value) in table.iter() {
            let name: &str = key.get_ref().as_ref();
            let field = format!("let.{name}");
            if !is_name(name) {
                return Err(self.field_err(
                    &field,
                    format!(
                        "`{name}` is not a name: a name is letters, digits and `_`, not starting with a digit"
                    ),
                ));
            }
            if matches!(name, "sqrt" | "cbrt" | "powi") {
                return Err(self.field_err(
                    &field,
                    format!("`{name}` is a function of the grammar; choose another name"),
                ));
            }
            let binding = self.binding(&field, value)?;
            defs.insert(name.to_string(), binding);
        }
        let mut done = BTreeMap::new();
        for name in defs.keys() {
            self.resolve(name, &defs, &mut done, &mut Vec::new())?;
        }
        Ok(done)
    }

    fn binding(&self, field: &str, v: &Value<'_>) -> Result<Binding, FileError> {
        match v.get_ref() {
            DeValue::String(s) => {
                let expr = expr::parse(s).map_err(|e| self.field_err(field, e.to_string()))?;
                Ok(Binding {
                    expr,
                    text: s.to_string(),
                })
            }
            DeValue::Integer(_) => {
                let n = self.integer(field, v)?;
                let text = n.to_string();
                let len = text.len();
                Ok(Binding {
                    expr: Expr::new(ExprKind::Int(n), 0, len),
                    text,
                })
            }
            _ => Err(self.not_a_number(field, v)),
        }
    }

    /// Evaluate binding `name` after those it refers to; `stack` holds the
    /// bindings being evaluated, to report a cycle.
    fn resolve(
        &self,
        name: &str,
        defs: &BTreeMap<String, Binding>,
        done: &mut BTreeMap<String, Number>,
        stack: &mut Vec<String>,
    ) -> Result<(), FileError> {
        if done.contains_key(name) {
            return Ok(());
        }
        if let Some(start) = stack.iter().position(|n| n == name) {
            let mut chain: Vec<&str> = stack[start..].iter().map(String::as_str).collect();
            chain.push(name);
            return Err(self.field_err(
                &format!("let.{}", stack[start]),
                format!("cyclic definition: {}", chain.join(" → ")),
            ));
        }
        if stack.len() >= MAX_LET_DEPTH {
            return Err(self.field_err(
                &format!("let.{name}"),
                format!("`let` bindings nested more than {MAX_LET_DEPTH} deep"),
            ));
        }
        let Some(binding) = defs.get(name) else {
            return Ok(());
        };
        stack.push(name.to_string());
        for dep in binding.expr.names() {
            if let ExprKind::Name(dep) = &dep.kind
                && defs.contains_key(dep)
            {
                self.resolve(dep, defs, done, stack)?;
            }
        }
        stack.pop();
        let field = format!("let.{name}");
        let value = self.eval(&field, &binding.expr, &binding.text, done)?;
        done.insert(name.to_string(), value);
        Ok(())
    }

    fn eval(
        &self,
        field: &str,
        e: &Expr,
        text: &str,
        lets: &BTreeMap<String, Number>,
    ) -> Result<Number, FileError> {
        expr::eval(e, &|n| lets.get(n).cloned()).map_err(|err| {
            let mut message = err.message(text);
            if let EvalErrorKind::UnknownName(_) = err.kind {
                if lets.is_empty() {
                    message.push_str(" (bind it under `let`)");
                } else {
                    let names: Vec<&str> = lets.keys().map(String::as_str).collect();
                    message.push_str(&format!(" (`let` binds {})", names.join(", ")));
                }
            }
            self.field_err(field, message)
        })
    }

    fn integer(&self, field: &str, v: &Value<'_>) -> Result<BigInt, FileError> {
        let DeValue::Integer(i) = v.get_ref() else {
            return Err(self.not_a_number(field, v));
        };
        let digits = i.as_str().replace('_', "");
        let count = digits.trim_start_matches(['+', '-']).len();
        if count > MAX_LITERAL_DIGITS {
            return Err(self.field_err(
                field,
                format!(
                    "the integer has {count} digits; a literal may have at most {MAX_LITERAL_DIGITS} (tableau::budget::MAX_LITERAL_DIGITS)"
                ),
            ));
        }
        BigInt::parse_bytes(digits.as_bytes(), i.radix())
            .ok_or_else(|| self.field_err(field, format!("`{}` is not an integer", self.raw(v))))
    }

    fn not_a_number(&self, field: &str, v: &Value<'_>) -> FileError {
        if let DeValue::Float(_) = v.get_ref() {
            let raw = self.raw(v);
            let lower = raw.to_ascii_lowercase();
            if lower.contains("inf") || lower.contains("nan") {
                return self.field_err(field, format!("{raw} is not a number a table can hold"));
            }
            let quoted = raw.replace('_', "");
            return self.field_err(
                field,
                format!(
                    "{raw} is a TOML float; write it as a string, \"{quoted}\", so that it is read exactly"
                ),
            );
        }
        self.field_err(
            field,
            format!(
                "expected a number (a string in the grammar, such as \"1/2\", or an integer), found {}",
                self.describe(v)
            ),
        )
    }

    /// One entry: a string in the grammar or an integer.
    fn number(&self, field: &str, v: &Value<'_>) -> Result<Number, FileError> {
        match v.get_ref() {
            DeValue::String(s) => {
                let e = expr::parse(s).map_err(|e| self.field_err(field, e.to_string()))?;
                self.eval(field, &e, s, &self.lets)
            }
            DeValue::Integer(_) => Ok(Number::from_bigint(self.integer(field, v)?)),
            _ => Err(self.not_a_number(field, v)),
        }
    }

    fn vector(&self, field: &str, v: &Value<'_>) -> Result<Vec<Number>, FileError> {
        let items = self.array(field, v, "an array of numbers")?;
        items
            .iter()
            .enumerate()
            .map(|(i, x)| self.number(&format!("{field}[{i}]"), x))
            .collect()
    }

    fn matrix(&self, field: &str, v: &Value<'_>) -> Result<Vec<Vec<Number>>, FileError> {
        let rows = self.array(
            field,
            v,
            "an array of rows, as in [[\"1/2\", \"0\"], [\"0\", \"1/2\"]]",
        )?;
        rows.iter()
            .enumerate()
            .map(|(i, row)| {
                let f = format!("{field}[{i}]");
                if !matches!(row.get_ref(), DeValue::Array(_)) {
                    return Err(self.field_err(
                        &f,
                        format!(
                            "expected a row (an array of numbers), found {}; `{field}` is an array of rows, as in {field} = [[\"1/2\"]]",
                            self.describe(row)
                        ),
                    ));
                }
                self.vector(&f, row)
            })
            .collect()
    }

    fn table(&self, fields: &BTreeMap<&str, &Value<'_>>) -> Result<Table, FileError> {
        let present = |keys: &[&'static str]| -> Vec<&'static str> {
            keys.iter()
                .copied()
                .filter(|k| fields.contains_key(k))
                .collect()
        };
        let forms = [
            (
                "a Runge–Kutta table",
                present(&["a", "b", "c", "a_hat", "b_hat", "c_hat"]),
            ),
            ("a drift–kick sequence", present(&["drift", "kick"])),
            ("a composition", present(&["compose"])),
        ];
        if fields.contains_key("kick_gradient") && !fields.contains_key("kick") {
            let other = present(&["a", "b", "a_hat", "b_hat", "compose"]);
            let what = match other.first() {
                Some(k) => format!("this file gives `{k}`, not"),
                None => "this file has no".to_string(),
            };
            return Err(self.field_err(
                "kick_gradient",
                format!(
                    "`kick_gradient` gives the gradients of the kicks of a drift–kick sequence (`drift`/`kick`); {what} a `kick`"
                ),
            ));
        }
        let given: Vec<&(&str, Vec<&str>)> =
            forms.iter().filter(|(_, keys)| !keys.is_empty()).collect();
        let quote = |keys: &[&str]| {
            keys.iter()
                .map(|k| format!("`{k}`"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        match given.as_slice() {
            [] => Err(self.err(
                None,
                "no table: give `a` and `b` (a Runge–Kutta table; with `a_hat` and `b_hat`, a partitioned pair), `drift` and `kick` (a drift–kick sequence), or `compose` (a composition of Störmer–Verlet)",
            )),
            [(_, _)] => self.one_form(fields),
            [(first, first_keys), (second, second_keys), ..] => Err(self.field_err(
                second_keys[0],
                format!(
                    "a table file has one form, but this one mixes {first} ({}) with {second} ({}); keep one",
                    quote(first_keys),
                    quote(second_keys)
                ),
            )),
        }
    }

    /// `kernel = "ID"`: the catalogue's drift–kick sequence or composition
    /// `ID`, and no inline table beside it.
    fn named_kernel(
        &self,
        fields: &BTreeMap<&str, &Value<'_>>,
        v: &Value<'_>,
    ) -> Result<Table, FileError> {
        let id = self.string("kernel", v)?;
        let inline: Vec<&str> = TABLE_FIELDS
            .into_iter()
            .filter(|k| fields.contains_key(k))
            .collect();
        if let Some(k) = inline.first() {
            return Err(self.field_err(
                k,
                format!(
                    "`kernel = \"{id}\"` names the kernel, so the file gives no table of its own (`{k}`); write the kernel inline with `drift`/`kick` instead, or drop `{k}`"
                ),
            ));
        }
        if !fields.contains_key("corrector_drift") && !fields.contains_key("corrector_kick") {
            return Err(self.field_err(
                "kernel",
                "`kernel` is the kernel of a processed method and needs a corrector: `corrector_drift` and `corrector_kick`",
            ));
        }
        // The catalogue's text, parsed here (`crate::catalogue` parses with
        // this module; reading its data keeps the two out of a circle).
        let entry = crate::embedded::find(&id)
            .ok_or_else(|| self.field_err("kernel", crate::embedded::unknown_message(&id)))?;
        let tf = parse_table_file(&format!("builtin:{id}"), entry.text)
            .map_err(|e| self.field_err("kernel", e.message))?;
        if tf.corrector.is_some() {
            return Err(self.field_err(
                "kernel",
                format!(
                    "builtin:{id} is itself a processed method; a kernel is a drift–kick sequence or composition"
                ),
            ));
        }
        match tf.table {
            t @ (Table::Splitting(_) | Table::Composition(_)) => Ok(t),
            _ => Err(self.field_err(
                "kernel",
                format!(
                    "builtin:{id} is not a drift–kick sequence or composition; a processed method's kernel is a product of the flows of A and B"
                ),
            )),
        }
    }

    /// `corrector_drift` and `corrector_kick`: the corrector of a processed
    /// method, whose kernel is a drift–kick sequence or composition.
    fn corrector(
        &self,
        fields: &BTreeMap<&str, &Value<'_>>,
        table: &Table,
        named: bool,
    ) -> Result<Option<Splitting>, FileError> {
        let (d, k) = (fields.get("corrector_drift"), fields.get("corrector_kick"));
        let (d, k) = match (d, k) {
            (None, None) => return Ok(None),
            (Some(d), Some(k)) => (d, k),
            (Some(_), None) | (None, Some(_)) => {
                let (given, missing) = if d.is_some() {
                    ("corrector_drift", "corrector_kick")
                } else {
                    ("corrector_kick", "corrector_drift")
                };
                return Err(self.field_err(
                    missing,
                    format!(
                        "missing: `{given}` is given, so `{missing}` is needed too (a corrector is a drift–kick sequence; write `{missing} = []` for none)"
                    ),
                ));
            }
        };
        if !named && !matches!(table, Table::Splitting(_) | Table::Composition(_)) {
            return Err(self.field_err(
                "corrector_drift",
                "a corrector processes a kernel that is a drift–kick sequence or composition (`drift`/`kick`, `compose` or `kernel = \"ID\"`), not a Runge–Kutta table or pair",
            ));
        }
        let s = Splitting::new(
            self.vector("corrector_drift", d)?,
            self.vector("corrector_kick", k)?,
        );
        Table::Splitting(s.clone()).check_shape().map_err(|e| {
            let field = e.field.replacen("drift", "corrector_drift", 1);
            let field = if field == e.field {
                e.field.replacen("kick", "corrector_kick", 1)
            } else {
                field
            };
            self.err(Some(field), e.message)
        })?;
        Ok(Some(s))
    }

    fn one_form(&self, fields: &BTreeMap<&str, &Value<'_>>) -> Result<Table, FileError> {
        let has = |k: &str| fields.contains_key(k);
        let get = |k: &str| {
            fields
                .get(k)
                .copied()
                .ok_or_else(|| self.field_err(k, "missing"))
        };
        let missing = |k: &str, why: String| Err(self.field_err(k, format!("missing: {why}")));
        if has("compose") {
            let gamma = self.vector("compose", get("compose")?)?;
            return Ok(Table::Composition(Composition { gamma }));
        }
        if has("drift") || has("kick") {
            for (k, other) in [("drift", "kick"), ("kick", "drift")] {
                if !has(k) {
                    return missing(
                        k,
                        format!(
                            "`{other}` is given, so `{k}` is needed too (a drift–kick sequence has both; write `{k} = []` for none)"
                        ),
                    );
                }
            }
            let drift = self.vector("drift", get("drift")?)?;
            let kick = self.vector("kick", get("kick")?)?;
            let gradient = match fields.get("kick_gradient") {
                Some(v) => self.vector("kick_gradient", v)?,
                None => Vec::new(),
            };
            // Given, it has one entry per kick (the empty list too: the
            // shape check reads an empty gradient as plain kicks).
            if fields.contains_key("kick_gradient") && gradient.len() != kick.len() {
                return Err(self.field_err(
                    "kick_gradient",
                    format!(
                        "kick_gradient has {} entries, but there are {} kicks: one gradient per kick (0 for a plain kick)",
                        gradient.len(),
                        kick.len()
                    ),
                ));
            }
            return Ok(Table::Splitting(Splitting {
                drift,
                kick,
                gradient,
            }));
        }
        for (k, other) in [("a", "b"), ("b", "a")] {
            if !has(k) {
                let why = if has(other) {
                    format!("`{other}` is given, so `{k}` is needed too")
                } else {
                    "a Runge–Kutta table needs `a` and `b`".to_string()
                };
                return missing(k, why);
            }
        }
        let hat = ["a_hat", "b_hat", "c_hat"];
        let given_hat: Vec<&str> = hat.iter().copied().filter(|k| has(k)).collect();
        if !given_hat.is_empty() {
            for k in ["a_hat", "b_hat"] {
                if !has(k) {
                    let given: Vec<String> = given_hat.iter().map(|g| format!("`{g}`")).collect();
                    return missing(
                        k,
                        format!(
                            "{} {} given, so `{k}` is needed too (a partitioned pair has `a_hat` and `b_hat`)",
                            given.join(" and "),
                            if given.len() == 1 { "is" } else { "are" }
                        ),
                    );
                }
            }
        }
        let rk = |suffix: &str| -> Result<Rk, FileError> {
            let a = self.matrix(&format!("a{suffix}"), get(&format!("a{suffix}"))?)?;
            let b = self.vector(&format!("b{suffix}"), get(&format!("b{suffix}"))?)?;
            let c_key = format!("c{suffix}");
            let c = match fields.get(c_key.as_str()) {
                Some(v) => Some(self.vector(&c_key, v)?),
                None => None,
            };
            Ok(Rk { a, b, c })
        };
        let q = rk("")?;
        if given_hat.is_empty() {
            return Ok(Table::Rk(q));
        }
        let p = rk("_hat")?;
        Ok(Table::Prk(Prk { q, p }))
    }
}

fn is_name(s: &str) -> bool {
    let mut chars = s.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimal_rk() {
        let f = parse_table_file("t.toml", "name = \"Euler\"\na = [[0]]\nb = [1]\n").unwrap();
        assert_eq!(f.name, "Euler");
        assert_eq!(
            f.table,
            Table::Rk(Rk {
                a: vec![vec![Number::from(0)]],
                b: vec![Number::from(1)],
                c: None
            })
        );
    }

    #[test]
    fn suggestions() {
        assert_eq!(suggest("ahat"), Some("a_hat"));
        assert_eq!(suggest("A"), Some("a"));
        assert_eq!(suggest("claim"), Some("claims"));
        assert_eq!(suggest("kicks"), Some("kick"));
        assert_eq!(suggest("zzz"), None);
    }
}
