//! The expression grammar of table entries, shared by table files and the
//! `butcher!` macro.
//!
//! ```text
//! expr    := term (('+' | '-') term)*              left-associative
//! term    := unary (('*' | '/') unary)*            left-associative
//! unary   := ('-' | '+') unary | power
//! power   := primary ('^' unary)?                  right-associative, binds tighter than unary minus
//! primary := INTEGER | DECIMAL | NAME | '(' expr ')'
//!          | 'sqrt' '(' expr ')' | 'cbrt' '(' expr ')' | 'powi' '(' expr ',' expr ')'
//! ```
//!
//! `-2^2` is `-(2^2) = -4`, `2^3^2` is `2^(3^2)`, and `2^-1` is `1/2`.
//! An exponent must evaluate to an integer (`x^(1/2)` is an error that says
//! to use `sqrt`). Decimals are exact: `0.1` is `1/10`, `1.25e-3` is `1/800`.
//! Names are identifiers `[A-Za-z_][A-Za-z0-9_]*`; their values come from the
//! caller (the `let` bindings of a table file or of the macro).
//!
//! [`parse`] turns text into an [`Expr`] tree whose nodes carry their byte
//! range in the source; [`eval`] computes its exact value. The macro builds
//! [`Expr`] trees itself (with `pos` an index into its own span table) and
//! calls [`eval`] too, so both give the same value and the same errors.

use std::fmt;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

use crate::budget::MAX_LITERAL_DIGITS;
use crate::{Number, NumberError};

/// The deepest expression tree [`parse`] builds (nesting of parentheses,
/// operators and calls, and the length of a chain such as `1 + 2 + … `).
/// Deeper input is a [`ParseError`], so that no recursion over a parsed tree
/// can exhaust the stack.
pub const MAX_DEPTH: usize = 128;

/// The largest decimal exponent a literal may have (`1e-10000`).
pub const MAX_DECIMAL_EXPONENT: u32 = 10_000;

/// The largest power [`eval`] computes: `|n| ≤ 2^16`, as [`Number::powi`].
pub const MAX_EXPONENT: i64 = 1 << 16;

/// The largest size, in bits of numerators, denominators and radicands, of a
/// product or power [`eval`] computes; beyond it evaluation stops with
/// [`EvalErrorKind::TooLarge`] instead of exhausting memory.
pub const MAX_BITS: u64 = 1 << 22;

/// The most term-by-term products one multiplication in [`eval`] makes
/// (terms of one factor times terms of the other; a power counts its
/// field's degree squared): 2²⁰, e.g. two numbers of 1024 radical terms.
pub const MAX_TERM_PRODUCTS: usize = 1 << 20;

/// The functions of the grammar, for messages.
pub const FUNCTIONS: &str = "sqrt, cbrt, powi";

/// A node of an expression tree: what it is and where it is. `pos` and `len`
/// are a byte range in the parsed text (for a parenthesised subexpression the
/// range includes the parentheses); a tree built elsewhere (the macro) may use
/// them as it likes, e.g. `pos` as an index into a span table.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub pos: usize,
    pub len: usize,
}

/// The kinds of node.
#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    /// An integer literal, `42`.
    Int(BigInt),
    /// A decimal literal with its exact value: `0.5` is `1/2`, `1e-24` is
    /// `1/10^24`.
    Decimal(BigRational),
    /// A name bound by the caller.
    Name(String),
    /// Unary minus.
    Neg(Box<Expr>),
    /// `lhs op rhs`.
    Binary {
        op: BinOp,
        lhs: Box<Expr>,
        rhs: Box<Expr>,
    },
    /// `base^exp` or `powi(base, exp)`; `exp` must evaluate to an integer.
    Pow { base: Box<Expr>, exp: Box<Expr> },
    /// `sqrt(arg)` or `cbrt(arg)`.
    Call { func: Func, arg: Box<Expr> },
}

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
}

/// A function of one argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Func {
    Sqrt,
    Cbrt,
}

impl BinOp {
    pub fn symbol(self) -> char {
        match self {
            BinOp::Add => '+',
            BinOp::Sub => '-',
            BinOp::Mul => '*',
            BinOp::Div => '/',
        }
    }
}

impl Func {
    pub fn name(self) -> &'static str {
        match self {
            Func::Sqrt => "sqrt",
            Func::Cbrt => "cbrt",
        }
    }
}

impl Expr {
    pub fn new(kind: ExprKind, pos: usize, len: usize) -> Self {
        Expr { kind, pos, len }
    }

    /// One past the last byte of the node.
    pub fn end(&self) -> usize {
        self.pos + self.len
    }

    /// The names the expression refers to, each with its node, in source
    /// order (with repetitions).
    pub fn names(&self) -> Vec<&Expr> {
        let mut out = Vec::new();
        let mut stack = vec![self];
        while let Some(e) = stack.pop() {
            match &e.kind {
                ExprKind::Int(_) | ExprKind::Decimal(_) => {}
                ExprKind::Name(_) => out.push(e),
                ExprKind::Neg(x) | ExprKind::Call { arg: x, .. } => stack.push(x),
                ExprKind::Binary { lhs, rhs, .. } => {
                    stack.push(rhs);
                    stack.push(lhs);
                }
                ExprKind::Pow { base, exp } => {
                    stack.push(exp);
                    stack.push(base);
                }
            }
        }
        out
    }
}

// ---------------------------------------------------------------------------
// Errors

/// A syntax error: where (`pos`, a byte offset into the text; every syntax
/// error lies at or before the first non-ASCII character, so it is also the
/// character offset), the offending token (empty at the end of the input) and
/// what was expected.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    pub pos: usize,
    pub token: String,
    pub message: String,
}

const EMPTY: &str = "empty expression";

impl std::error::Error for ParseError {}

impl fmt::Display for ParseError {
    /// "at column 7, unexpected `)`: expected a number, a name or `(`", with
    /// a 1-based column; an empty input is just "empty expression".
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.message == EMPTY {
            f.write_str(EMPTY)
        } else {
            write!(f, "at column {}, {}", self.pos + 1, self.message)
        }
    }
}

/// An evaluation error and the node it is about.
///
/// Positions: division by zero points at the divisor (for `1/(1-1)` the
/// `(1-1)`); a zero raised to a negative power at the whole power; a bad
/// exponent at the exponent; `sqrt`/`cbrt` of a bad argument at the whole
/// call; an unknown name at the name; a result too large at the operation.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{kind}")]
pub struct EvalError {
    pub pos: usize,
    pub len: usize,
    pub kind: EvalErrorKind,
}

#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum EvalErrorKind {
    /// Exact arithmetic refused: division by zero, square root of a negative
    /// number, a nested radical, a radicand too large to factor.
    #[error("{0}")]
    Number(NumberError),
    #[error("unknown name `{0}`")]
    UnknownName(String),
    /// An exponent whose value (shown) is not an integer.
    #[error(
        "exponent {0} is not an integer (powers are integer powers; use sqrt or cbrt for roots)"
    )]
    NonIntegerExponent(String),
    /// An exponent beyond [`MAX_EXPONENT`], or a power whose result would
    /// exceed [`MAX_BITS`].
    #[error("exponent {0} is too large for exact arithmetic")]
    ExponentTooLarge(String),
    /// A product whose result would exceed [`MAX_BITS`], or that would take
    /// more than [`MAX_TERM_PRODUCTS`] term products.
    #[error(
        "the result is too large for exact arithmetic (more than {MAX_BITS} bits, or more than {MAX_TERM_PRODUCTS} products of radical terms)"
    )]
    TooLarge,
}

impl EvalError {
    fn new(e: &Expr, kind: EvalErrorKind) -> Self {
        EvalError {
            pos: e.pos,
            len: e.len,
            kind,
        }
    }

    /// A message that quotes the source, such as "at column 3, division by
    /// zero: `(1-1)` is zero" or "at column 1, `sqrt(-1)`: square root of a
    /// negative number (-1)". `src` is the text the expression was parsed
    /// from; positions outside it are left out of the message.
    pub fn message(&self, src: &str) -> String {
        let column = src.get(..self.pos).map(|s| s.chars().count() + 1);
        let snippet = src
            .get(self.pos..self.pos + self.len)
            .filter(|s| !s.is_empty());
        let at = match column {
            Some(c) => format!("at column {c}, "),
            None => String::new(),
        };
        match (&self.kind, snippet) {
            (EvalErrorKind::Number(NumberError::DivisionByZero), Some(s)) => {
                format!("{at}division by zero: `{s}` is zero")
            }
            (EvalErrorKind::UnknownName(_), _) | (_, None) => format!("{at}{}", self.kind),
            (kind, Some(s)) => format!("{at}`{s}`: {kind}"),
        }
    }
}

// ---------------------------------------------------------------------------
// Lexer

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Int(BigInt),
    Dec(BigRational),
    Ident(String),
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    LParen,
    RParen,
    Comma,
    End,
}

#[derive(Clone, Debug)]
struct Token {
    tok: Tok,
    pos: usize,
    len: usize,
}

fn perr(pos: usize, token: impl Into<String>, message: impl Into<String>) -> ParseError {
    ParseError {
        pos,
        token: token.into(),
        message: message.into(),
    }
}

/// How to show a character in a message.
fn show_char(c: char) -> String {
    if c.is_control() || c.is_whitespace() {
        format!("{}", c.escape_debug())
    } else {
        c.to_string()
    }
}

fn bad_char(pos: usize, c: char) -> ParseError {
    let shown = show_char(c);
    let code = format!("U+{:04X}", c as u32);
    let message = match c {
        '\u{2212}' | '\u{2013}' | '\u{2014}' => {
            format!("unexpected `{shown}` ({code}): write the ASCII minus `-`")
        }
        '\u{00D7}' | '\u{00B7}' | '\u{2219}' | '\u{22C5}' | '\u{2217}' => {
            format!("unexpected `{shown}` ({code}): write `*` for a product")
        }
        '\u{00F7}' | '\u{2215}' => {
            format!("unexpected `{shown}` ({code}): write `/` for a quotient")
        }
        '\u{221A}' => format!("unexpected `{shown}` ({code}): write `sqrt(...)`"),
        '\u{221B}' => format!("unexpected `{shown}` ({code}): write `cbrt(...)`"),
        '\u{00B2}' | '\u{00B3}' => format!("unexpected `{shown}` ({code}): write `^2` or `^3`"),
        '.' => "unexpected `.`: a decimal needs digits on both sides of the point, as in `0.5`"
            .to_string(),
        _ if !c.is_ascii() => format!(
            "unexpected `{shown}` ({code}): the grammar is ASCII (numbers, names, + - * / ^, parentheses, {FUNCTIONS})"
        ),
        _ => format!(
            "unexpected `{shown}`: not part of the grammar (numbers, names, + - * / ^, parentheses, {FUNCTIONS})"
        ),
    };
    perr(pos, c.to_string(), message)
}

/// Split `src` into tokens. A lexical error ends the list: the parser reports
/// it when it gets there, so that errors come in source order.
fn lex(src: &str) -> (Vec<Token>, Option<ParseError>) {
    let bytes = src.as_bytes();
    let mut toks = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if b.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let single = match b {
            b'+' => Some(Tok::Plus),
            b'-' => Some(Tok::Minus),
            b'*' if bytes.get(i + 1) == Some(&b'*') => {
                return (
                    toks,
                    Some(perr(i, "**", "unexpected `**`: write `^` for a power")),
                );
            }
            b'*' => Some(Tok::Star),
            b'/' => Some(Tok::Slash),
            b'^' => Some(Tok::Caret),
            b'(' => Some(Tok::LParen),
            b')' => Some(Tok::RParen),
            b',' => Some(Tok::Comma),
            _ => None,
        };
        if let Some(tok) = single {
            toks.push(Token {
                tok,
                pos: i,
                len: 1,
            });
            i += 1;
            continue;
        }
        if b.is_ascii_digit() {
            match lex_number(src, i) {
                Ok((tok, end)) => {
                    toks.push(Token {
                        tok,
                        pos: i,
                        len: end - i,
                    });
                    i = end;
                }
                Err(e) => return (toks, Some(e)),
            }
            continue;
        }
        if b.is_ascii_alphabetic() || b == b'_' {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            toks.push(Token {
                tok: Tok::Ident(src[start..i].to_string()),
                pos: start,
                len: i - start,
            });
            continue;
        }
        // Not ASCII, or ASCII outside the grammar. `i` is on a char boundary:
        // every byte consumed so far was ASCII.
        let c = src[i..].chars().next().unwrap_or('\u{FFFD}');
        return (toks, Some(bad_char(i, c)));
    }
    toks.push(Token {
        tok: Tok::End,
        pos: src.len(),
        len: 0,
    });
    (toks, None)
}

fn digits_end(bytes: &[u8], mut i: usize) -> usize {
    while i < bytes.len() && bytes[i].is_ascii_digit() {
        i += 1;
    }
    i
}

/// A number literal starting at `start` (a digit): `INT`, `INT.FRAC`,
/// optionally followed by `e[+-]EXP`. Returns the token and the end offset.
fn lex_number(src: &str, start: usize) -> Result<(Tok, usize), ParseError> {
    let bytes = src.as_bytes();
    let int_end = digits_end(bytes, start);
    let mut end = int_end;
    let mut frac = "";
    let mut is_decimal = false;
    if bytes.get(end) == Some(&b'.') {
        let frac_end = digits_end(bytes, end + 1);
        if frac_end == end + 1 {
            return Err(perr(
                end,
                ".",
                format!(
                    "unexpected `.` after `{}`: a decimal needs digits after the point, as in `{}.0`",
                    &src[start..end],
                    &src[start..end]
                ),
            ));
        }
        frac = &src[end + 1..frac_end];
        end = frac_end;
        is_decimal = true;
    }
    let mut exp: i64 = 0;
    if matches!(bytes.get(end), Some(b'e' | b'E')) {
        let mut j = end + 1;
        let negative = bytes.get(j) == Some(&b'-');
        if matches!(bytes.get(j), Some(b'+' | b'-')) {
            j += 1;
        }
        let exp_end = digits_end(bytes, j);
        if exp_end == j {
            let lit_end = src[end..]
                .char_indices()
                .find(|&(k, c)| k > 0 && !(c.is_ascii_alphanumeric() || c == '_'))
                .map_or(src.len(), |(k, _)| end + k);
            let lit = &src[start..lit_end];
            return Err(perr(
                start,
                lit,
                format!(
                    "`{lit}` is not a number: an exponent needs digits, as in `1e-3` (for a product with a name, write `*`)"
                ),
            ));
        }
        let digits = src[j..exp_end].trim_start_matches('0');
        let magnitude = if digits.len() > 6 {
            None
        } else {
            digits
                .parse::<u32>()
                .ok()
                .or(Some(0))
                .filter(|&m| m <= MAX_DECIMAL_EXPONENT)
        };
        let Some(magnitude) = magnitude else {
            return Err(perr(
                start,
                &src[start..exp_end],
                format!(
                    "the exponent of `{}` is too large (at most {MAX_DECIMAL_EXPONENT})",
                    &src[start..exp_end]
                ),
            ));
        };
        exp = if negative {
            -(magnitude as i64)
        } else {
            magnitude as i64
        };
        end = exp_end;
        is_decimal = true;
    }
    if let Some(&b) = bytes.get(end)
        && (b.is_ascii_alphanumeric() || b == b'_' || b == b'.')
    {
        let c = b as char;
        let message = if b == b'.' {
            format!("unexpected `.` after the number `{}`", &src[start..end])
        } else {
            format!(
                "unexpected `{c}` right after the number `{}`: write `{}*{c}…` for a product",
                &src[start..end],
                &src[start..end]
            )
        };
        return Err(perr(end, c.to_string(), message));
    }
    let int_text = &src[start..int_end];
    let digits = int_text.len() + frac.len();
    if digits > MAX_LITERAL_DIGITS {
        return Err(perr(
            start,
            format!("{}…", &src[start..start + 20]),
            format!(
                "the number has {digits} digits; a literal may have at most {MAX_LITERAL_DIGITS} (tableau::budget::MAX_LITERAL_DIGITS)"
            ),
        ));
    }
    if !is_decimal {
        let n = int_text.parse::<BigInt>().unwrap_or_default();
        return Ok((Tok::Int(n), end));
    }
    // mantissa = INT FRAC as an integer, value = mantissa · 10^(exp − |FRAC|).
    let mantissa: BigInt = format!("{int_text}{frac}")
        .parse::<BigInt>()
        .unwrap_or_default();
    let shift = exp - frac.len() as i64;
    let ten = BigInt::from(10);
    let value = if shift >= 0 {
        BigRational::from_integer(mantissa * num_traits::pow(ten, shift as usize))
    } else {
        BigRational::new(mantissa, num_traits::pow(ten, (-shift) as usize))
    };
    Ok((Tok::Dec(value), end))
}

// ---------------------------------------------------------------------------
// Parser

/// Parse an expression. See the [module docs](self) for the grammar.
pub fn parse(src: &str) -> Result<Expr, ParseError> {
    if src.trim().is_empty() {
        return Err(perr(0, "", EMPTY));
    }
    let (toks, lex_error) = lex(src);
    let mut p = Parser {
        src,
        toks,
        lex_error,
        i: 0,
        depth: 0,
    };
    let (e, _) = p.expr()?;
    let t = p.current()?;
    match t.tok {
        Tok::End => Ok(e),
        Tok::RParen => Err(perr(
            t.pos,
            ")",
            "unbalanced parentheses: this `)` has no matching `(`",
        )),
        _ => Err(p.unexpected(&t, "expected an operator or the end of the expression")),
    }
}

struct Parser<'a> {
    src: &'a str,
    toks: Vec<Token>,
    lex_error: Option<ParseError>,
    i: usize,
    depth: usize,
}

/// A parsed subtree and its depth.
type Parsed = Result<(Expr, usize), ParseError>;

fn boxed(e: Expr) -> Box<Expr> {
    Box::new(e)
}

impl Parser<'_> {
    /// The current token, or the lexical error if the tokens ran out.
    fn current(&self) -> Result<Token, ParseError> {
        if self.i >= self.toks.len() {
            return Err(self
                .lex_error
                .clone()
                .unwrap_or_else(|| perr(self.src.len(), "", "unexpected end of input")));
        }
        Ok(self.toks[self.i].clone())
    }

    fn bump(&mut self) {
        self.i += 1;
    }

    fn text(&self, t: &Token) -> &str {
        self.src.get(t.pos..t.pos + t.len).unwrap_or("")
    }

    fn unexpected(&self, t: &Token, expected: &str) -> ParseError {
        if t.tok == Tok::End {
            perr(t.pos, "", format!("unexpected end of input: {expected}"))
        } else {
            let text = self.text(t).to_string();
            perr(t.pos, &text, format!("unexpected `{text}`: {expected}"))
        }
    }

    fn too_deep(&self, pos: usize) -> ParseError {
        let t = self
            .toks
            .iter()
            .find(|t| t.pos == pos)
            .map(|t| self.text(t).to_string())
            .unwrap_or_default();
        perr(
            pos,
            t,
            format!("expression too deeply nested or too long (more than {MAX_DEPTH} levels)"),
        )
    }

    fn check_depth(&self, depth: usize, pos: usize) -> Result<(), ParseError> {
        if depth > MAX_DEPTH {
            Err(self.too_deep(pos))
        } else {
            Ok(())
        }
    }

    fn binary(op: BinOp, lhs: Expr, rhs: Expr) -> Expr {
        let pos = lhs.pos;
        let len = rhs.end() - pos;
        Expr::new(
            ExprKind::Binary {
                op,
                lhs: boxed(lhs),
                rhs: boxed(rhs),
            },
            pos,
            len,
        )
    }

    fn expr(&mut self) -> Parsed {
        let (mut lhs, mut depth) = self.term()?;
        loop {
            let t = self.current()?;
            let op = match t.tok {
                Tok::Plus => BinOp::Add,
                Tok::Minus => BinOp::Sub,
                _ => return Ok((lhs, depth)),
            };
            self.bump();
            let (rhs, d) = self.term()?;
            depth = depth.max(d) + 1;
            self.check_depth(depth, t.pos)?;
            lhs = Self::binary(op, lhs, rhs);
        }
    }

    fn term(&mut self) -> Parsed {
        let (mut lhs, mut depth) = self.unary()?;
        loop {
            let t = self.current()?;
            let op = match t.tok {
                Tok::Star => BinOp::Mul,
                Tok::Slash => BinOp::Div,
                _ => return Ok((lhs, depth)),
            };
            self.bump();
            let (rhs, d) = self.unary()?;
            depth = depth.max(d) + 1;
            self.check_depth(depth, t.pos)?;
            lhs = Self::binary(op, lhs, rhs);
        }
    }

    /// Every recursion of the parser passes through here, so the nesting
    /// guard lives here.
    fn unary(&mut self) -> Parsed {
        self.depth += 1;
        let result = if self.depth > MAX_DEPTH {
            let pos = self.current().map(|t| t.pos).unwrap_or(self.src.len());
            Err(self.too_deep(pos))
        } else {
            self.unary_inner()
        };
        self.depth -= 1;
        result
    }

    fn unary_inner(&mut self) -> Parsed {
        let t = self.current()?;
        match t.tok {
            Tok::Minus => {
                self.bump();
                let (e, d) = self.unary()?;
                let len = e.end() - t.pos;
                Ok((Expr::new(ExprKind::Neg(boxed(e)), t.pos, len), d + 1))
            }
            Tok::Plus => {
                self.bump();
                let (mut e, d) = self.unary()?;
                e.len = e.end() - t.pos;
                e.pos = t.pos;
                Ok((e, d))
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Parsed {
        let (base, db) = self.primary()?;
        let t = self.current()?;
        if t.tok != Tok::Caret {
            return Ok((base, db));
        }
        self.bump();
        let (exp, de) = self.unary()?;
        let depth = db.max(de) + 1;
        self.check_depth(depth, t.pos)?;
        let pos = base.pos;
        let len = exp.end() - pos;
        Ok((
            Expr::new(
                ExprKind::Pow {
                    base: boxed(base),
                    exp: boxed(exp),
                },
                pos,
                len,
            ),
            depth,
        ))
    }

    const OPERAND: &'static str = "expected a number, a name or `(`";

    fn primary(&mut self) -> Parsed {
        let t = self.current()?;
        match &t.tok {
            Tok::Int(n) => {
                self.bump();
                Ok((Expr::new(ExprKind::Int(n.clone()), t.pos, t.len), 1))
            }
            Tok::Dec(r) => {
                self.bump();
                Ok((Expr::new(ExprKind::Decimal(r.clone()), t.pos, t.len), 1))
            }
            Tok::Ident(name) => {
                self.bump();
                let next = self.current()?;
                if next.tok == Tok::LParen {
                    return self.call(&t, name);
                }
                if matches!(name.as_str(), "sqrt" | "cbrt" | "powi") {
                    let args = if name == "powi" { "x, n" } else { "..." };
                    return Err(perr(
                        t.pos,
                        name.as_str(),
                        format!("`{name}` is a function: write `{name}({args})`"),
                    ));
                }
                Ok((Expr::new(ExprKind::Name(name.clone()), t.pos, t.len), 1))
            }
            Tok::LParen => {
                self.bump();
                let (mut e, d) = self.expr()?;
                let close = self.current()?;
                match close.tok {
                    Tok::RParen => {
                        self.bump();
                        e.pos = t.pos;
                        e.len = close.pos + 1 - t.pos;
                        Ok((e, d))
                    }
                    Tok::End => Err(perr(
                        t.pos,
                        "(",
                        "unbalanced parentheses: this `(` is never closed",
                    )),
                    _ => Err(self.unexpected(&close, "expected an operator or `)`")),
                }
            }
            _ => Err(self.unexpected(&t, Self::OPERAND)),
        }
    }

    /// `name(` has been seen, with `name` the identifier token `t`.
    fn call(&mut self, t: &Token, name: &str) -> Parsed {
        let (func, arity) = match name {
            "sqrt" => (Some(Func::Sqrt), 1),
            "cbrt" => (Some(Func::Cbrt), 1),
            "powi" => (None, 2),
            _ => {
                return Err(perr(
                    t.pos,
                    name,
                    format!("unknown function `{name}` (the grammar has {FUNCTIONS})"),
                ));
            }
        };
        let open = self.current()?;
        self.bump();
        let mut args = Vec::with_capacity(2);
        let mut depth = 0;
        loop {
            let (e, d) = self.expr()?;
            depth = depth.max(d);
            args.push(e);
            let sep = self.current()?;
            match sep.tok {
                Tok::Comma if args.len() < arity => self.bump(),
                Tok::Comma => {
                    return Err(perr(
                        sep.pos,
                        ",",
                        if arity == 1 {
                            format!("unexpected `,`: `{name}` takes one argument")
                        } else {
                            format!("unexpected `,`: `{name}` takes two arguments, `{name}(x, n)`")
                        },
                    ));
                }
                Tok::RParen if args.len() < arity => {
                    return Err(perr(
                        sep.pos,
                        ")",
                        format!(
                            "unexpected `)`: `{name}` takes two arguments, `{name}(x, n)`, with `n` an integer"
                        ),
                    ));
                }
                Tok::RParen => {
                    self.bump();
                    let depth = depth + 1;
                    self.check_depth(depth, t.pos)?;
                    let len = sep.pos + 1 - t.pos;
                    let mut it = args.into_iter();
                    let first = it.next().map(boxed);
                    let second = it.next().map(boxed);
                    let kind = match (func, first, second) {
                        (Some(func), Some(arg), None) => ExprKind::Call { func, arg },
                        (None, Some(base), Some(exp)) => ExprKind::Pow { base, exp },
                        _ => {
                            return Err(perr(t.pos, name, "wrong number of arguments"));
                        }
                    };
                    return Ok((Expr::new(kind, t.pos, len), depth));
                }
                Tok::End => {
                    return Err(perr(
                        open.pos,
                        "(",
                        format!("unbalanced parentheses: the `(` of `{name}(` is never closed"),
                    ));
                }
                _ => {
                    let expected = if args.len() < arity {
                        "expected an operator, `,` or `)`"
                    } else {
                        "expected an operator or `)`"
                    };
                    return Err(self.unexpected(&sep, expected));
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Evaluation

/// The exact value of `expr`, with names looked up in `env`. Errors carry the
/// position of the node they are about (see [`EvalError`]).
///
/// The recursion is as deep as the tree; trees from [`parse`] are at most
/// [`MAX_DEPTH`] deep.
pub fn eval(expr: &Expr, env: &dyn Fn(&str) -> Option<Number>) -> Result<Number, EvalError> {
    let err = |e: &Expr, kind| Err(EvalError::new(e, kind));
    match &expr.kind {
        ExprKind::Int(n) => Ok(Number::from_bigint(n.clone())),
        ExprKind::Decimal(r) => Ok(Number::from_rational(r.clone())),
        ExprKind::Name(name) => match env(name) {
            Some(v) => Ok(v),
            None => err(expr, EvalErrorKind::UnknownName(name.clone())),
        },
        ExprKind::Neg(x) => Ok(-eval(x, env)?),
        ExprKind::Binary { op, lhs, rhs } => {
            let l = eval(lhs, env)?;
            let r = eval(rhs, env)?;
            match op {
                BinOp::Add => Ok(l + r),
                BinOp::Sub => Ok(l - r),
                BinOp::Mul => {
                    if size_bits(&l).saturating_add(size_bits(&r)) > MAX_BITS
                        || l.term_count().saturating_mul(r.term_count()) > MAX_TERM_PRODUCTS
                    {
                        return err(expr, EvalErrorKind::TooLarge);
                    }
                    Ok(l * r)
                }
                BinOp::Div => {
                    if r.is_zero() {
                        return err(rhs, EvalErrorKind::Number(NumberError::DivisionByZero));
                    }
                    if size_bits(&l).saturating_add(size_bits(&r)) > MAX_BITS {
                        return err(expr, EvalErrorKind::TooLarge);
                    }
                    l.checked_div(&r)
                        .or_else(|e| err(expr, EvalErrorKind::Number(e)))
                }
            }
        }
        ExprKind::Pow { base, exp } => {
            let b = eval(base, env)?;
            let e = eval(exp, env)?;
            let n = match e.as_rational() {
                Some(r) if r.is_integer() => r.to_integer(),
                _ => return err(exp, EvalErrorKind::NonIntegerExponent(e.to_string())),
            };
            let too_large = || EvalErrorKind::ExponentTooLarge(n.to_string());
            let Some(k) = n
                .to_i64()
                .filter(|k| k.unsigned_abs() <= MAX_EXPONENT as u64)
            else {
                return err(exp, too_large());
            };
            // Powers of 0 and ±1 stay small; anything else grows linearly in |k|.
            let trivial = b.is_zero() || b.as_rational().is_some_and(|r| r.abs().is_one());
            let degree = crate::number::field_degree([&b]);
            if !trivial
                && k.unsigned_abs() > 1
                && degree.saturating_mul(degree) > MAX_TERM_PRODUCTS as u64
            {
                return err(expr, EvalErrorKind::TooLarge);
            }
            if !trivial && size_bits(&b).saturating_mul(k.unsigned_abs()) > MAX_BITS {
                return err(exp, too_large());
            }
            b.powi(k).or_else(|e| err(expr, EvalErrorKind::Number(e)))
        }
        ExprKind::Call { func, arg } => {
            let a = eval(arg, env)?;
            let r = match func {
                Func::Sqrt => a.sqrt(),
                Func::Cbrt => a.cbrt(),
            };
            r.or_else(|e| err(expr, EvalErrorKind::Number(e)))
        }
    }
}

/// A size measure for the growth guards: the bits of all numerators,
/// denominators and radicands.
fn size_bits(n: &Number) -> u64 {
    n.terms()
        .map(|(m, c)| c.numer().bits() + c.denom().bits() + m.radicand().bits())
        .fold(0u64, u64::saturating_add)
}

/// Parse and evaluate `src` with no names bound, with a readable message on
/// failure (it quotes the offending part of `src` and gives its column).
pub fn parse_number(src: &str) -> Result<Number, String> {
    let e = parse(src).map_err(|e| e.to_string())?;
    eval(&e, &|_| None).map_err(|e| e.message(src))
}

// ---------------------------------------------------------------------------
// Printing

/// The text of a rational as an exact decimal literal of the grammar (`0.5`,
/// `-12.25`, `1e-24`, `2.5e-10`), or `None` when its denominator has a prime
/// factor other than 2 and 5. Small exponents are written out in full,
/// larger ones in scientific notation.
pub fn decimal_text(r: &BigRational) -> Option<String> {
    let mut d = r.denom().clone();
    let (two, five) = (BigInt::from(2), BigInt::from(5));
    let (mut twos, mut fives) = (0usize, 0usize);
    while (&d % &two).is_zero() {
        d /= &two;
        twos += 1;
    }
    while (&d % &five).is_zero() {
        d /= &five;
        fives += 1;
    }
    if !d.is_one() {
        return None;
    }
    // r = m · 10^(-f) with m an integer.
    let mut f = twos.max(fives) as i64;
    let ten = BigInt::from(10);
    let mut m = r.numer() * num_traits::pow(ten.clone(), f as usize) / r.denom();
    if m.is_zero() {
        return Some("0".to_string());
    }
    while (&m % &ten).is_zero() {
        m /= &ten;
        f -= 1;
    }
    let sign = if m.is_negative() { "-" } else { "" };
    let digits = m.abs().to_string();
    let n = digits.len() as i64;
    let e = n - 1 - f; // the decimal exponent of the leading digit
    let body = if (-5..15).contains(&e) {
        if f <= 0 {
            format!("{digits}{}", "0".repeat((-f) as usize))
        } else if f < n {
            let (a, b) = digits.split_at((n - f) as usize);
            format!("{a}.{b}")
        } else {
            format!("0.{}{digits}", "0".repeat((f - n) as usize))
        }
    } else if n == 1 {
        format!("{digits}e{e}")
    } else {
        format!("{}.{}e{e}", &digits[..1], &digits[1..])
    };
    Some(format!("{sign}{body}"))
}

/// Binding strength for printing: higher binds tighter.
fn level(e: &Expr) -> u8 {
    match &e.kind {
        ExprKind::Binary {
            op: BinOp::Add | BinOp::Sub,
            ..
        } => 1,
        ExprKind::Binary { .. } => 2,
        ExprKind::Neg(_) => 3,
        ExprKind::Int(n) if n.is_negative() => 3,
        ExprKind::Decimal(r) if r.is_negative() => 3,
        ExprKind::Pow { .. } => 4,
        _ => 5,
    }
}

struct Child<'a>(&'a Expr, u8);

impl fmt::Display for Child<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if level(self.0) < self.1 {
            write!(f, "({})", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}

impl fmt::Display for Expr {
    /// The expression in the grammar with the fewest parentheses that keep
    /// its tree: parsing the text gives the same tree (up to positions).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.kind {
            ExprKind::Int(n) => write!(f, "{n}"),
            ExprKind::Decimal(r) => match decimal_text(r) {
                Some(t) => f.write_str(&t),
                None => write!(f, "({r})"),
            },
            ExprKind::Name(n) => f.write_str(n),
            ExprKind::Neg(x) => write!(f, "-{}", Child(x, 3)),
            ExprKind::Binary { op, lhs, rhs } => {
                let l = level(self);
                match op {
                    BinOp::Add | BinOp::Sub => {
                        write!(f, "{} {} {}", Child(lhs, l), op.symbol(), Child(rhs, l + 1))
                    }
                    BinOp::Mul | BinOp::Div => {
                        write!(f, "{}{}{}", Child(lhs, l), op.symbol(), Child(rhs, l + 1))
                    }
                }
            }
            ExprKind::Pow { base, exp } => write!(f, "{}^{}", Child(base, 5), Child(exp, 3)),
            ExprKind::Call { func, arg } => write!(f, "{}({arg})", func.name()),
        }
    }
}

// ---------------------------------------------------------------------------

#[cfg(test)]
mod tests {
    use super::*;

    fn num(src: &str) -> Number {
        parse_number(src).unwrap_or_else(|e| panic!("{src}: {e}"))
    }

    fn rat(n: i64, d: i64) -> Number {
        Number::ratio(n, d).unwrap()
    }

    fn perror(src: &str) -> ParseError {
        match parse(src) {
            Ok(e) => panic!("{src} parsed as {e:?}"),
            Err(e) => e,
        }
    }

    fn eerror(src: &str) -> EvalError {
        let e = parse(src).unwrap_or_else(|e| panic!("{src}: {e}"));
        match eval(&e, &|_| None) {
            Ok(v) => panic!("{src} evaluated to {v}"),
            Err(e) => e,
        }
    }

    #[test]
    fn literals() {
        assert_eq!(num("42"), Number::from(42));
        assert_eq!(num("0.5"), rat(1, 2));
        assert_eq!(num("1.25e-3"), rat(1, 800));
        assert_eq!(
            num("1e-24"),
            Number::from_rational(BigRational::new(
                1.into(),
                num_traits::pow(BigInt::from(10), 24)
            ))
        );
        assert_eq!(num("2.5E+2"), Number::from(250));
        assert_eq!(num("1e3"), Number::from(1000));
        assert_eq!(num("007"), Number::from(7));
        assert_eq!(
            num("123456789012345678901234567890"),
            Number::from_bigint("123456789012345678901234567890".parse().unwrap())
        );
    }

    #[test]
    fn precedence() {
        assert_eq!(num("-2^2"), Number::from(-4));
        assert_eq!(num("(-2)^2"), Number::from(4));
        assert_eq!(num("2^3^2"), Number::from(512));
        assert_eq!(num("2^-2"), rat(1, 4));
        assert_eq!(num("2^(-2)"), rat(1, 4));
        assert_eq!(num("powi(2, -2)"), rat(1, 4));
        assert_eq!(num("1 - 2 - 3"), Number::from(-4));
        assert_eq!(num("12 / 2 / 3"), Number::from(2));
        assert_eq!(num("1 + 2*3"), Number::from(7));
        assert_eq!(num("2*-3"), Number::from(-6));
        assert_eq!(num("1 - -1"), Number::from(2));
        assert_eq!(num("+1/2"), rat(1, 2));
        assert_eq!(num("2^-2*3"), rat(3, 4));
        assert_eq!(num("2^(1+1)"), Number::from(4));
        assert_eq!(num("0^0"), Number::from(1));
    }

    #[test]
    fn radicals() {
        assert!(num("sqrt(8) - 2*sqrt(2)").is_zero());
        assert!(num("sqrt(6) - sqrt(2)*sqrt(3)").is_zero());
        assert!(num("cbrt(16) - 2*cbrt(2)").is_zero());
        assert_eq!(num("1/(1+sqrt(2))"), num("sqrt(2)-1"));
        assert_eq!(num("cbrt(-8)"), Number::from(-2));
        assert_eq!(num("sqrt(1/4)"), rat(1, 2));
    }

    #[test]
    fn positions() {
        let e = parse("1 + (2*x)").unwrap();
        assert_eq!((e.pos, e.len), (0, 9));
        let ExprKind::Binary { rhs, .. } = &e.kind else {
            panic!()
        };
        assert_eq!((rhs.pos, rhs.len), (4, 5));
        let names = e.names();
        assert_eq!(names.len(), 1);
        assert_eq!((names[0].pos, names[0].len), (7, 1));
    }

    #[test]
    fn names_from_env() {
        let e = parse("x/2 + y").unwrap();
        let env = |n: &str| match n {
            "x" => Some(Number::from(3)),
            "y" => Some(rat(1, 2)),
            _ => None,
        };
        assert_eq!(eval(&e, &env).unwrap(), Number::from(2));
        let err = eval(&parse("x + z").unwrap(), &env).unwrap_err();
        assert_eq!(err.kind, EvalErrorKind::UnknownName("z".into()));
        assert_eq!((err.pos, err.len), (4, 1));
    }

    #[test]
    fn parse_errors() {
        let e = perror("");
        assert_eq!(e.to_string(), "empty expression");
        assert_eq!(perror("   ").message, "empty expression");

        let e = perror("(1 + 2))");
        assert_eq!((e.pos, e.token.as_str()), (7, ")"));
        assert!(e.message.contains("unbalanced"), "{e}");

        let e = perror("1 + (2 * ");
        assert_eq!(e.pos, 9);
        assert!(e.to_string().contains("unexpected end of input"), "{e}");

        let e = perror("(1 + 2");
        assert_eq!((e.pos, e.token.as_str()), (0, "("));
        assert!(e.message.contains("never closed"), "{e}");

        let e = perror("1 + 2 * )");
        assert_eq!(
            e.to_string(),
            "at column 9, unexpected `)`: expected a number, a name or `(`"
        );

        let e = perror("exp(1)");
        assert_eq!(
            e.to_string(),
            "at column 1, unknown function `exp` (the grammar has sqrt, cbrt, powi)"
        );

        let e = perror("1 2");
        assert_eq!((e.pos, e.token.as_str()), (2, "2"));

        let e = perror("1/2 é");
        assert_eq!((e.pos, e.token.as_str()), (4, "é"));
        assert!(e.message.contains("U+00E9"), "{e}");

        let e = perror("1 − 2");
        assert!(e.message.contains("ASCII minus"), "{e}");

        let e = perror("2**3");
        assert!(e.message.contains("`^`"), "{e}");

        let e = perror("2x");
        assert_eq!((e.pos, e.token.as_str()), (1, "x"));

        let e = perror("1e");
        assert!(e.message.contains("exponent"), "{e}");
        let e = perror("1.");
        assert_eq!(e.pos, 1);
        let e = perror(".5");
        assert_eq!(e.pos, 0);
        let e = perror("1e99999999");
        assert!(e.message.contains("too large"), "{e}");

        let e = perror("sqrt");
        assert!(e.message.contains("is a function"), "{e}");
        let e = perror("sqrt(1, 2)");
        assert_eq!(e.pos, 6);
        let e = perror("powi(2)");
        assert!(e.message.contains("two arguments"), "{e}");
        let e = perror("sqrt(2");
        assert_eq!(e.pos, 4);
        assert!(e.message.contains("never closed"), "{e}");
        let e = perror("1 = 2");
        assert_eq!((e.pos, e.token.as_str()), (2, "="));
    }

    #[test]
    fn depth_limit() {
        let deep = format!("{}1{}", "(".repeat(10_000), ")".repeat(10_000));
        assert!(perror(&deep).message.contains("too deeply"));
        let long = vec!["1"; 10_000].join("+");
        assert!(perror(&long).message.contains("too deeply"));
        let minus = format!("{}1", "-".repeat(10_000));
        assert!(perror(&minus).message.contains("too deeply"));
        let pow = vec!["1"; 10_000].join("^");
        assert!(perror(&pow).message.contains("too deeply"));
        // Within the limit.
        let ok = vec!["1"; 100].join("+");
        assert_eq!(num(&ok), Number::from(100));
    }

    #[test]
    fn eval_errors() {
        let e = eerror("1/0");
        assert_eq!(e.kind, EvalErrorKind::Number(NumberError::DivisionByZero));
        assert_eq!((e.pos, e.len), (2, 1));
        assert_eq!(
            e.message("1/0"),
            "at column 3, division by zero: `0` is zero"
        );

        let e = eerror("2 * 1/(1 - 1)");
        assert_eq!((e.pos, e.len), (6, 7));

        let e = eerror("1 + sqrt(-1)");
        assert!(matches!(
            e.kind,
            EvalErrorKind::Number(NumberError::NegativeSqrt(_))
        ));
        assert_eq!((e.pos, e.len), (4, 8));
        assert!(
            e.message("1 + sqrt(-1)")
                .starts_with("at column 5, `sqrt(-1)`: square root")
        );

        let e = eerror("0^-1");
        assert_eq!(e.kind, EvalErrorKind::Number(NumberError::DivisionByZero));

        let e = eerror("2^(1/2)");
        assert!(matches!(e.kind, EvalErrorKind::NonIntegerExponent(_)));
        assert_eq!((e.pos, e.len), (2, 5));
        let e = eerror("2^0.5");
        assert!(e.to_string().contains("1/2"), "{e}");

        let e = eerror("sqrt(sqrt(2))");
        assert!(matches!(
            e.kind,
            EvalErrorKind::Number(NumberError::NestedRadical { .. })
        ));

        let e = eerror("2^100000");
        assert!(matches!(e.kind, EvalErrorKind::ExponentTooLarge(_)));
        let e = eerror("(10^6000)^6000");
        assert!(matches!(e.kind, EvalErrorKind::ExponentTooLarge(_)));
        let e = eerror("2^100000000000000000000000");
        assert!(matches!(e.kind, EvalErrorKind::ExponentTooLarge(_)));

        let e = eerror("x + 1");
        assert_eq!(e.message("x + 1"), "at column 1, unknown name `x`");
    }

    #[test]
    fn parse_number_messages() {
        assert_eq!(
            parse_number("1/0").unwrap_err(),
            "at column 3, division by zero: `0` is zero"
        );
        assert_eq!(parse_number("").unwrap_err(), "empty expression");
    }

    #[test]
    fn decimal_texts() {
        let d = |s: &str| {
            let n = num(s);
            decimal_text(&n.as_rational().unwrap())
        };
        assert_eq!(d("1/2").as_deref(), Some("0.5"));
        assert_eq!(d("1e-24").as_deref(), Some("1e-24"));
        assert_eq!(d("2.5e-10").as_deref(), Some("2.5e-10"));
        assert_eq!(d("-12.25").as_deref(), Some("-12.25"));
        assert_eq!(d("0.001").as_deref(), Some("0.001"));
        assert_eq!(d("1000").as_deref(), Some("1000"));
        assert_eq!(d("1e20").as_deref(), Some("1e20"));
        assert_eq!(d("0").as_deref(), Some("0"));
        assert_eq!(d("1/3"), None);
    }

    #[test]
    fn display_round_trips() {
        for src in [
            "1 - (2 - 3)",
            "-2^2",
            "(-2)^2",
            "2^3^2",
            "(2^3)^2",
            "2^-2",
            "1/(2*x)",
            "a - -b",
            "--x",
            "sqrt(3)/6 + 1/4",
            "powi(x, 3) * cbrt(2)",
            "0.5 * 1e-24",
            "-(1 + 2)",
        ] {
            let e = parse(src).unwrap();
            let text = e.to_string();
            let again = parse(&text).unwrap_or_else(|err| panic!("{src} → {text}: {err}"));
            let env = |n: &str| match n {
                "x" => Some(Number::from(3)),
                "a" | "b" => Some(Number::from(5)),
                _ => None,
            };
            assert_eq!(eval(&e, &env), eval(&again, &env), "{src} → {text}");
            assert_eq!(text, again.to_string(), "{src}");
        }
        assert_eq!(parse("2^3^2").unwrap().to_string(), "2^3^2");
        assert_eq!(parse("(2^3)^2").unwrap().to_string(), "(2^3)^2");
        assert_eq!(parse("1 - (2 - 3)").unwrap().to_string(), "1 - (2 - 3)");
    }
}
