//! Numbers as the reports, tables and messages print them — one set of
//! formatters for the whole project, so that a missing value reads the
//! same everywhere and a column of one report looks like the same column of
//! another.
//!
//! Every formatter prints [`MISSING`] for a value that is not there: `None`,
//! or a number that is not finite (a run that stopped before the step a
//! column reads, an error of a diverged run, a ratio over zero). A report
//! never shows `NaN` or `inf` for those: the row's status, or a sentence
//! next to the table, says why the value is missing.
//!
//! Machine-readable files (CSV) do not use these: they write every `f64`
//! with Rust's shortest round-trip form (`NaN` included), so a reader gets
//! back the exact number.
//!
//! ```
//! use compare::format::{self, MISSING};
//!
//! assert_eq!(format::sci(1.8e-3, 1), "1.8e-3");
//! assert_eq!(format::sci(f64::NAN, 2), MISSING);
//! assert_eq!(format::fixed(0.5, 3), "0.500");
//! assert_eq!(format::opt(None, |x| format::fixed(x, 2)), MISSING);
//! assert_eq!(format::ms(0.0123), "12.3");
//! assert_eq!(format::count(1e6), "10⁶");
//! assert_eq!(format::ratio(3.14159), "3.1");
//! assert_eq!(format::times(6.0, 2.0), "×3.000");
//! assert_eq!(format::plain(0.25), "0.25");
//! assert_eq!(format::plain(1e-300), "1e-300");
//! ```

/// The one marker for a value that is missing or not finite. An em dash
/// rather than "n/a": most tables already used it, it does not read as a
/// word, and it keeps a Markdown column narrow.
pub const MISSING: &str = "—";

/// Scientific notation with `digits` digits after the point (`1.8e-3` for
/// 1), or [`MISSING`].
pub fn sci(x: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{x:.digits$e}")
    } else {
        MISSING.into()
    }
}

/// Scientific notation with an explicit sign (`+3.3e-5`, `-6.7e-5`), for
/// errors whose sign matters (a phase that lags or leads), or [`MISSING`].
pub fn signed_sci(x: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{x:+.digits$e}")
    } else {
        MISSING.into()
    }
}

/// Fixed-point notation with `digits` digits after the point, or
/// [`MISSING`].
pub fn fixed(x: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{x:.digits$}")
    } else {
        MISSING.into()
    }
}

/// An optional value through `f` (one of the formatters here), or
/// [`MISSING`] when there is none.
pub fn opt(x: Option<f64>, f: impl FnOnce(f64) -> String) -> String {
    x.map_or_else(|| MISSING.into(), f)
}

/// Seconds as milliseconds with three significant digits (`0.289`, `12.3`,
/// `145`; below a microsecond scientific), or [`MISSING`]. Wall times are
/// medians of a few runs: more digits would be noise.
pub fn ms(seconds: f64) -> String {
    let x = seconds * 1e3;
    if !x.is_finite() {
        MISSING.into()
    } else if x >= 100.0 {
        format!("{x:.0}")
    } else if x >= 10.0 {
        format!("{x:.1}")
    } else if x >= 1.0 {
        format!("{x:.2}")
    } else if x >= 0.1 {
        format!("{x:.3}")
    } else if x >= 0.01 {
        format!("{x:.4}")
    } else if x >= 0.001 {
        format!("{x:.5}")
    } else {
        format!("{x:.2e}")
    }
}

/// An error with two significant digits (`1.8e-3`), or [`MISSING`]: an
/// error is read for its decade, and two digits are what a sweep resolves.
pub fn err(x: f64) -> String {
    sci(x, 1)
}

/// A count: `10⁶` for a power of ten from 100 up (the step counts of long
/// runs), else the integer.
pub fn count(n: f64) -> String {
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    if !n.is_finite() {
        return MISSING.into();
    }
    let k = n.round() as u64;
    let mut p = 100u64;
    let mut e = 2;
    while p < k && p <= u64::MAX / 10 {
        p *= 10;
        e += 1;
    }
    if k == p {
        let digits: String = e
            .to_string()
            .bytes()
            .map(|d| SUP[(d - b'0') as usize])
            .collect();
        format!("10{digits}")
    } else {
        k.to_string()
    }
}

/// A positive ratio (a speed-up) with two significant digits (`31`, `3.1`,
/// `0.31`, `0.031`), or [`MISSING`].
pub fn ratio(x: f64) -> String {
    if !x.is_finite() {
        MISSING.into()
    } else if x >= 10.0 {
        format!("{x:.0}")
    } else if x >= 1.0 {
        format!("{x:.1}")
    } else if x >= 0.1 {
        format!("{x:.2}")
    } else {
        format!("{x:.3}")
    }
}

/// `a/b` as a factor, "×N" (four significant digits between 0.01 and 1000,
/// scientific outside), or [`MISSING`] when `b` is 0 or the quotient is not
/// finite: how much a quantity grows from one setting to the next.
pub fn times(a: f64, b: f64) -> String {
    let r = a / b;
    if b == 0.0 || !r.is_finite() {
        MISSING.into()
    } else if (0.01..1000.0).contains(&r.abs()) {
        format!("×{r:.3}")
    } else {
        format!("×{r:.2e}")
    }
}

/// A number for a message, as the user would have written it: plain where
/// that is short (`0.25`, `1000`), else scientific (`1e-300`); `NaN`, `inf`
/// and `-inf` as Rust writes them, since a message about a bad value must
/// show the value.
pub fn plain(x: f64) -> String {
    if x == 0.0 || (1e-4..1e7).contains(&x.abs()) || !x.is_finite() {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// One CSV field as RFC 4180 writes it: as it is, or — when it holds a
/// comma, a double quote, a CR or an LF — wrapped in double quotes with its
/// quotes doubled. Every CSV file of the workspace writes its text fields
/// through this (names come from user files and may hold anything), and
/// [`read_runs`](crate::output::read_runs) reads them back.
pub fn csv_field(s: &str) -> std::borrow::Cow<'_, str> {
    if s.contains([',', '"', '\r', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\"")).into()
    } else {
        s.into()
    }
}
