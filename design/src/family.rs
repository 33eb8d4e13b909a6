//! A family of methods, declared in a file (TOML) or built in Rust: the form,
//! the number of stages, the classical order to impose, which coefficients
//! are fixed or tied together, and the search's seed, number of starts and
//! time cap.
//!
//! ```toml
//! name = "Yoshida's triple jump"
//! form = "composition"        # "ABA", "BAB" (symmetric drift–kick sequences) or "composition"
//! stages = 3                  # force evaluations (ABA, BAB) or base steps (composition)
//! order = 4                   # the classical order imposed
//! # fixed = { b1 = "-3/73" }  # coefficients given a rational value (tableau's grammar)
//! # equal = [["g1", "g2"]]    # coefficients tied together (Suzuki's g1 = g2)
//! seed = 1                    # the starts are drawn from this seed
//! starts = 200                # the number of starts
//! range = 1.0                 # starts uniform in [-range, range] for every unknown
//! max_seconds = 60            # no start begins after this many seconds
//! ```
//!
//! Every family is symmetric (palindromic), so its coefficients are named
//! by their first half: an ABA sequence with `s` kicks has drifts
//! `a1 a2 … a2 a1` (`s + 1` of them) and kicks `b1 b2 … b2 b1`; a BAB
//! sequence with `s` force evaluations has `s + 1` kicks `b1 … b1` (the last
//! merged with the next step's first) and `s` drifts; a composition of `m`
//! Störmer–Verlet steps has step sizes `g1 g2 … g2 g1`. The middle
//! coefficient of each kind is the one consistency (`Σ = 1`) determines.

use std::fmt;

use num_rational::BigRational;
use toml::Value;

/// The shape of the method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// A symmetric drift–kick sequence starting and ending with a drift.
    Aba,
    /// A symmetric drift–kick sequence starting and ending with a kick.
    Bab,
    /// A symmetric composition of Störmer–Verlet (any symmetric second-order
    /// method): `Φ_{g1 h} ∘ Φ_{g2 h} ∘ …`.
    Composition,
}

impl Form {
    pub fn name(self) -> &'static str {
        match self {
            Form::Aba => "ABA",
            Form::Bab => "BAB",
            Form::Composition => "composition",
        }
    }
}

/// The most stages a family may have: the conditions grow with it, and the
/// literature's families of interest have at most about a dozen.
pub const MAX_STAGES: usize = 16;

/// The highest classical order imposed: the Lie-word algebra is built to one
/// degree beyond it, with polynomial coefficients.
pub const MAX_ORDER: usize = 8;

/// The highest entry of a generalised order: only the Lie terms with few
/// letters `B` reach high degrees, so the product stays small.
pub const MAX_GENERALISED_ORDER: usize = 10;

/// How the objective measures the first error terms not imposed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ErrorBasis {
    /// The coefficients of the Lie element on the Lyndon words (the default).
    #[default]
    Words,
    /// The coordinates of the Lie element in the Lyndon basis: the standard
    /// bracketing of each Lyndon word (`AAB → [A,[A,B]]`, `AABAB →
    /// [[A,[A,B]],[A,B]]`), the basis in which Blanes & Moan (2002) state
    /// their error terms (`error_basis = "brackets"`).
    Brackets,
}

/// What the free coefficients are chosen for, and the designs ranked by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Objective {
    /// The size of the first error terms not imposed (the default,
    /// `objective = "effective-error"`).
    #[default]
    EffectiveError,
    /// The linear stability threshold on the harmonic oscillator
    /// (`objective = "stability"`, [`crate::stability`]): from each
    /// solution of the error search, the free coefficients move to a local
    /// maximum of the threshold on the conditions, and the designs are
    /// ranked by it, largest first.
    Stability,
}

/// A family to design.
#[derive(Clone, Debug, PartialEq)]
pub struct Family {
    pub name: String,
    pub source: Option<String>,
    pub form: Form,
    pub stages: usize,
    /// The classical order imposed; for a generalised order, its first entry
    /// `p₁` (the order of the `ε` error, which the effective error scales
    /// with).
    pub order: usize,
    /// A generalised (near-integrable) order `(p₁, p₂, …)` for `H = A + εB`
    /// (`order = [4, 2]` in the file; drift–kick forms only): a Lie term with
    /// `j` letters `B` and degree `n` is imposed when `n ≤ p_j` (`p_j` read
    /// as the last entry for larger `j`). Empty for a classical order.
    pub generalised: Vec<usize>,
    /// Coefficients given a value: `(name, value)`.
    pub fixed: Vec<(String, BigRational)>,
    /// Coefficients tied together: the second takes the first's value.
    pub equal: Vec<(String, String)>,
    /// Runge–Kutta–Nyström (`rkn = true`; drift–kick forms): the kinetic
    /// energy (the drift, letter `A`) is quadratic in the momenta, so
    /// `[B,[B,[B,A]]]` vanishes and with it every Lie term in the ideal it
    /// generates. The error terms are the Lyndon-basis coordinates that are
    /// not in that ideal (`error_basis = "brackets"`, dropping the basis
    /// elements with `ABBB = [[[A,B],B],B]` as a sub-bracket; their number is
    /// checked against the ideal's dimension). The conditions up to order 4
    /// are the classical ones (the ideal starts at degree 4, an even degree);
    /// at order 6 the degree-5 conditions are the four coordinates outside
    /// the ideal, and the emitted table claims `order = 4` and
    /// `order_rkn = 6` with residual bounds on its 50 printed digits (the
    /// certificate `symlab check` re-proves is for classical conditions).
    pub rkn: bool,
    /// The basis the objective's error terms are measured in.
    pub error_basis: ErrorBasis,
    /// What the free coefficients are chosen for.
    pub objective: Objective,
    /// A processed kernel (`processed = true`; compositions and drift–kick
    /// forms, classical or, for drift–kick forms, non-increasing generalised
    /// orders, not RKN): the order
    /// imposed is the *effective* order of `χ K χ⁻¹`, for a processor `χ`
    /// the designer then finds ([`crate::effective`]), and the error
    /// measured is the part of the first order not imposed that no
    /// processor removes.
    pub processed: bool,
    /// The processor's stages (`processor_stages`): for a composition
    /// kernel (even) the composition `S(z₁h)⋯S(z_kh) S(−z₁h)⋯S(−z_kh)` of
    /// the same basic method, `k` of them unknown; for a drift–kick kernel
    /// the number `k` of kicks of `D(u₁h)K(v₁h)⋯D(u_kh)K(v_kh)` with
    /// `Σu = Σv = 0`, `2k − 2` unknowns. Only with `processed`.
    pub processor_stages: usize,
    pub seed: u64,
    pub starts: usize,
    pub range: f64,
    pub max_seconds: f64,
}

/// Why a family was refused: the file, the field (`None` for the file as a
/// whole) and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub struct FamilyError {
    pub file: String,
    pub field: Option<String>,
    pub message: String,
}

impl fmt::Display for FamilyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.field {
            Some(field) => write!(f, "{}: field {}: {}", self.file, field, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

const KEYS: [&str; 16] = [
    "name",
    "source",
    "form",
    "stages",
    "order",
    "fixed",
    "equal",
    "seed",
    "starts",
    "range",
    "max_seconds",
    "objective",
    "rkn",
    "error_basis",
    "processed",
    "processor_stages",
];

/// How a coefficient of the method is made of the family's parameters.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Parameter names: `a1, a2, …, b1, …` or `g1, g2, …`.
    pub names: Vec<String>,
    /// For a drift–kick sequence, the parameter index of each drift, in the
    /// order applied; empty for a composition.
    pub drift: Vec<usize>,
    /// The parameter index of each kick.
    pub kick: Vec<usize>,
    /// For a composition, the parameter index of each step size.
    pub gamma: Vec<usize>,
}

/// `min(i, n − 1 − i)`: the palindrome's index into its first half.
fn half(i: usize, n: usize) -> usize {
    i.min(n - 1 - i)
}

impl Family {
    /// `4`, or `(4, 2)` for a generalised order.
    pub fn order_text(&self) -> String {
        if self.generalised.is_empty() {
            self.order.to_string()
        } else {
            let items: Vec<String> = self.generalised.iter().map(usize::to_string).collect();
            format!("({})", items.join(", "))
        }
    }

    /// A family with the defaults for the search (seed 1, 200 starts, range
    /// 1, 60 s).
    pub fn new(name: &str, form: Form, stages: usize, order: usize) -> Family {
        Family {
            name: name.to_string(),
            source: None,
            form,
            stages,
            order,
            generalised: Vec::new(),
            fixed: Vec::new(),
            equal: Vec::new(),
            rkn: false,
            error_basis: ErrorBasis::Words,
            objective: Objective::EffectiveError,
            processed: false,
            processor_stages: 0,
            seed: 1,
            starts: 200,
            range: 1.0,
            max_seconds: 60.0,
        }
    }

    /// The parameters and where each coefficient of the method comes from.
    pub fn layout(&self) -> Layout {
        let s = self.stages;
        let (ndrift, nkick, ngamma) = match self.form {
            Form::Aba => (s + 1, s, 0),
            Form::Bab => (s, s + 1, 0),
            Form::Composition => (0, 0, s),
        };
        let na = ndrift.div_ceil(2);
        let nb = nkick.div_ceil(2);
        let ng = ngamma.div_ceil(2);
        let mut names: Vec<String> = (1..=na).map(|i| format!("a{i}")).collect();
        names.extend((1..=nb).map(|i| format!("b{i}")));
        names.extend((1..=ng).map(|i| format!("g{i}")));
        Layout {
            names,
            drift: (0..ndrift).map(|i| half(i, ndrift)).collect(),
            kick: (0..nkick).map(|i| na + half(i, nkick)).collect(),
            gamma: (0..ngamma).map(|i| half(i, ngamma)).collect(),
        }
    }

    /// Check the family's numbers and names; `file` names it in messages.
    pub fn validate(&self, file: &str) -> Result<(), FamilyError> {
        let err = |field: &str, message: String| FamilyError {
            file: file.to_string(),
            field: Some(field.to_string()),
            message,
        };
        if self.stages == 0 || self.stages > MAX_STAGES {
            return Err(err(
                "stages",
                format!(
                    "{} stages: a family has 1 to {MAX_STAGES} (design::family::MAX_STAGES)",
                    self.stages
                ),
            ));
        }
        if !self.generalised.is_empty() {
            if self.form == Form::Composition {
                return Err(err(
                    "order",
                    "a generalised order (p1, p2, …) is for drift–kick forms (ABA, BAB), not compositions".into(),
                ));
            }
            if let Some(p) = self
                .generalised
                .iter()
                .find(|&&p| p == 0 || p > MAX_GENERALISED_ORDER || p % 2 == 1)
            {
                return Err(err(
                    "order",
                    format!(
                        "{p} in the generalised order: the families are symmetric, so each entry is even, from 2 to {MAX_GENERALISED_ORDER} (design::family::MAX_GENERALISED_ORDER)"
                    ),
                ));
            }
        }
        if self.generalised.is_empty()
            && (self.order == 0 || self.order > MAX_ORDER || self.order % 2 == 1)
        {
            return Err(err(
                "order",
                format!(
                    "order {}: the families are symmetric, so their order is even, from 2 to {MAX_ORDER} (design::family::MAX_ORDER)",
                    self.order
                ),
            ));
        }
        if self.rkn {
            if self.form == Form::Composition {
                return Err(err(
                    "rkn",
                    "a Runge–Kutta–Nyström family is a drift–kick sequence (ABA or BAB), not a composition".into(),
                ));
            }
            if !self.generalised.is_empty() || self.order > 6 {
                return Err(err(
                    "rkn",
                    format!(
                        "order {}: RKN families impose a classical order up to 6",
                        self.order_text()
                    ),
                ));
            }
            if self.error_basis != ErrorBasis::Brackets {
                return Err(err(
                    "error_basis",
                    "an RKN family measures its error in the Lyndon basis (\"brackets\"), modulo the terms that vanish for quadratic kinetic energy".into(),
                ));
            }
        }
        if self.error_basis == ErrorBasis::Brackets && !self.generalised.is_empty() {
            return Err(err(
                "error_basis",
                "\"brackets\" is for a classical order; a generalised order's error terms are Lyndon-word coefficients".into(),
            ));
        }
        if self.processed {
            if !self.generalised.is_empty()
                && (self.generalised.windows(2).any(|w| w[0] < w[1]) || self.generalised.len() > 16)
            {
                return Err(err(
                    "order",
                    format!(
                        "{}: a processed kernel's effective generalised order is non-increasing (p₁ ≥ p₂ ≥ …), of at most 16 entries",
                        self.order_text()
                    ),
                ));
            }
            if self.rkn {
                return Err(err(
                    "rkn",
                    "a processed kernel's effective-order conditions are those of general separable systems; the RKN quotient is not designed for processing".into(),
                ));
            }
            if self.objective != Objective::EffectiveError {
                return Err(err(
                    "objective",
                    "a processed kernel is chosen for its effective error (\"effective-error\")"
                        .into(),
                ));
            }
            if self.error_basis != ErrorBasis::Words {
                return Err(err(
                    "error_basis",
                    "a processed kernel's error is the part no processor removes, measured on the Lyndon words (\"words\")".into(),
                ));
            }
            if self.form == Form::Composition
                && (self.processor_stages < 2
                    || self.processor_stages % 2 == 1
                    || self.processor_stages > 2 * MAX_STAGES)
            {
                return Err(err(
                    "processor_stages",
                    format!(
                        "{}: the processor S(z₁h)⋯S(z_kh) S(−z₁h)⋯S(−z_kh) has an even number of stages, from 2 to {}",
                        self.processor_stages,
                        2 * MAX_STAGES
                    ),
                ));
            }
            if self.form != Form::Composition
                && (self.processor_stages < 2 || self.processor_stages > MAX_STAGES)
            {
                return Err(err(
                    "processor_stages",
                    format!(
                        "{}: the processor D(u₁h)K(v₁h)⋯D(u_kh)K(v_kh) (Σu = Σv = 0) has from 2 to {MAX_STAGES} stages (kicks)",
                        self.processor_stages,
                    ),
                ));
            }
        } else if self.processor_stages != 0 {
            return Err(err(
                "processor_stages",
                "a processor is designed only for a processed kernel (`processed = true`)".into(),
            ));
        }
        if self.starts == 0 {
            return Err(err("starts", "at least one start is needed".into()));
        }
        if !(self.range.is_finite() && self.range > 0.0) {
            return Err(err(
                "range",
                format!("{}: the starts' range is a positive number", self.range),
            ));
        }
        if !(self.max_seconds.is_finite() && self.max_seconds > 0.0) {
            return Err(err(
                "max_seconds",
                format!(
                    "{}: the time cap is a positive number of seconds",
                    self.max_seconds
                ),
            ));
        }
        let names = self.layout().names;
        let known = |field: &str, n: &str| -> Result<(), FamilyError> {
            if names.iter().any(|m| m == n) {
                Ok(())
            } else {
                Err(err(
                    field,
                    format!(
                        "`{n}` is not a coefficient of this family; its coefficients are {}",
                        names.join(", ")
                    ),
                ))
            }
        };
        for (n, _) in &self.fixed {
            known(&format!("fixed.{n}"), n)?;
        }
        for (i, (x, y)) in self.equal.iter().enumerate() {
            known(&format!("equal[{i}]"), x)?;
            known(&format!("equal[{i}]"), y)?;
            if x == y {
                return Err(err(
                    &format!("equal[{i}]"),
                    format!("`{x}` is tied to itself"),
                ));
            }
        }
        Ok(())
    }
}

/// Read a family file; messages name `file`.
pub fn parse_family(file: &str, text: &str) -> Result<Family, FamilyError> {
    let whole = |message: String| FamilyError {
        file: file.to_string(),
        field: None,
        message,
    };
    let err = |field: &str, message: String| FamilyError {
        file: file.to_string(),
        field: Some(field.to_string()),
        message,
    };
    let table: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| whole(format!("not a TOML file: {}", e.message())))?;
    for key in table.keys() {
        if !KEYS.contains(&key.as_str()) {
            return Err(err(
                key,
                format!("unknown field; the fields are {}", KEYS.join(", ")),
            ));
        }
    }
    let string = |key: &str| -> Result<Option<String>, FamilyError> {
        match table.get(key) {
            None => Ok(None),
            Some(Value::String(s)) => Ok(Some(s.clone())),
            Some(v) => Err(err(key, format!("expected a string, found {v}"))),
        }
    };
    let integer = |key: &str| -> Result<Option<u64>, FamilyError> {
        match table.get(key) {
            None => Ok(None),
            Some(Value::Integer(i)) if *i >= 0 => Ok(Some(*i as u64)),
            Some(v) => Err(err(
                key,
                format!("expected a non-negative integer, found {v}"),
            )),
        }
    };
    let float = |key: &str| -> Result<Option<f64>, FamilyError> {
        match table.get(key) {
            None => Ok(None),
            Some(Value::Integer(i)) => Ok(Some(*i as f64)),
            Some(Value::Float(x)) => Ok(Some(*x)),
            Some(v) => Err(err(key, format!("expected a number, found {v}"))),
        }
    };
    let name = string("name")?.ok_or_else(|| whole("the field `name` is missing".into()))?;
    let form_text = string("form")?.ok_or_else(|| {
        whole("the field `form` is missing (\"ABA\", \"BAB\" or \"composition\")".into())
    })?;
    let form = match form_text.as_str() {
        "ABA" | "aba" => Form::Aba,
        "BAB" | "bab" => Form::Bab,
        "composition" => Form::Composition,
        other => {
            return Err(err(
                "form",
                format!(
                    "`{other}`: the forms are \"ABA\", \"BAB\" and \"composition\" (and \"second-corrector\", a corrector for a processed method, which `symlab design` reads with design::processed)"
                ),
            ));
        }
    };
    let stages = integer("stages")?.ok_or_else(|| whole("the field `stages` is missing".into()))?;
    // `order = 4`, or a generalised order `order = [4, 2]`.
    let (order, generalised) = match table.get("order") {
        Some(Value::Array(items)) => {
            let mut v = Vec::new();
            for (i, item) in items.iter().enumerate() {
                match item {
                    Value::Integer(k) if (1..=64).contains(k) => v.push(*k as usize),
                    other => {
                        return Err(err(
                            &format!("order[{i}]"),
                            format!("expected an order from 1 to 64, found {other}"),
                        ));
                    }
                }
            }
            let first = *v
                .first()
                .ok_or_else(|| err("order", "a generalised order has at least one entry".into()))?;
            (first as u64, v)
        }
        _ => (
            integer("order")?.ok_or_else(|| whole("the field `order` is missing".into()))?,
            Vec::new(),
        ),
    };
    let objective = match string("objective")?.as_deref() {
        None | Some("effective-error") => Objective::EffectiveError,
        Some("stability") => Objective::Stability,
        Some(obj) => {
            return Err(err(
                "objective",
                format!("`{obj}`: the objectives are \"effective-error\" and \"stability\""),
            ));
        }
    };
    let mut family = Family::new(
        &name,
        form,
        usize::try_from(stages).unwrap_or(usize::MAX),
        usize::try_from(order).unwrap_or(usize::MAX),
    );
    family.generalised = generalised;
    family.objective = objective;
    family.source = string("source")?;
    match table.get("rkn") {
        None => {}
        Some(Value::Boolean(b)) => family.rkn = *b,
        Some(v) => return Err(err("rkn", format!("expected true or false, found {v}"))),
    }
    family.error_basis = match string("error_basis")?.as_deref() {
        None if family.rkn => ErrorBasis::Brackets,
        None | Some("words") => ErrorBasis::Words,
        Some("brackets") => ErrorBasis::Brackets,
        Some(other) => {
            return Err(err(
                "error_basis",
                format!(
                    "`{other}`: the bases are \"words\" (Lyndon-word coefficients) and \"brackets\" (the Lyndon basis)"
                ),
            ));
        }
    };
    match table.get("processed") {
        None => {}
        Some(Value::Boolean(b)) => family.processed = *b,
        Some(v) => {
            return Err(err(
                "processed",
                format!("expected true or false, found {v}"),
            ));
        }
    }
    if let Some(k) = integer("processor_stages")? {
        family.processor_stages = usize::try_from(k).unwrap_or(usize::MAX);
    }
    if let Some(seed) = integer("seed")? {
        family.seed = seed;
    }
    if let Some(starts) = integer("starts")? {
        family.starts = usize::try_from(starts).unwrap_or(usize::MAX);
    }
    if let Some(range) = float("range")? {
        family.range = range;
    }
    if let Some(cap) = float("max_seconds")? {
        family.max_seconds = cap;
    }
    match table.get("fixed") {
        None => {}
        Some(Value::Table(t)) => {
            for (k, v) in t {
                let field = format!("fixed.{k}");
                let Value::String(s) = v else {
                    return Err(err(
                        &field,
                        format!("expected a quoted exact value such as \"-3/73\", found {v}"),
                    ));
                };
                let number = tableau::expr::parse_number(s)
                    .map_err(|e| err(&field, format!("`{s}`: {e}")))?;
                let r = number.as_rational().ok_or_else(|| {
                    err(
                        &field,
                        format!("`{s}` is irrational; a fixed coefficient is rational"),
                    )
                })?;
                family.fixed.push((k.clone(), r));
            }
        }
        Some(v) => {
            return Err(err(
                "fixed",
                format!("expected a table such as {{ b1 = \"-3/73\" }}, found {v}"),
            ));
        }
    }
    match table.get("equal") {
        None => {}
        Some(Value::Array(items)) => {
            for (i, item) in items.iter().enumerate() {
                let pair = match item {
                    Value::Array(p) if p.len() == 2 => match (&p[0], &p[1]) {
                        (Value::String(x), Value::String(y)) => Some((x.clone(), y.clone())),
                        _ => None,
                    },
                    _ => None,
                };
                let pair = pair.ok_or_else(|| {
                    err(
                        &format!("equal[{i}]"),
                        format!("expected a pair of names such as [\"g1\", \"g2\"], found {item}"),
                    )
                })?;
                family.equal.push(pair);
            }
        }
        Some(v) => {
            return Err(err(
                "equal",
                format!("expected a list of pairs such as [[\"g1\", \"g2\"]], found {v}"),
            ));
        }
    }
    family.validate(file)?;
    Ok(family)
}

/// Read a family file from disk; messages name the path.
pub fn load_family(path: &std::path::Path) -> Result<Family, FamilyError> {
    let text = read_family_text(path)?;
    parse_family(&path.display().to_string(), &text)
}

/// A family file's text, of at most [`tableau::budget::MAX_FILE_BYTES`]
/// (a table file's limit: `/dev/zero` is refused, not read until memory
/// runs out); every front end reads family files through this.
pub fn read_family_text(path: &std::path::Path) -> Result<String, FamilyError> {
    tableau::file::read_text(
        path,
        tableau::budget::MAX_FILE_BYTES,
        "a family file is a few lines of TOML",
    )
    .map_err(|message| FamilyError {
        file: path.display().to_string(),
        field: None,
        message,
    })
}

/// A file-name stem from a family's name, for the tables a run writes:
/// `yoshida-triple-jump` (one place, for every form's writer).
pub(crate) fn stem(name: &str) -> String {
    let mut s = String::new();
    for ch in name.chars() {
        if ch.is_ascii_alphanumeric() {
            s.push(ch.to_ascii_lowercase());
        } else if !s.ends_with('-') && !s.is_empty() {
            s.push('-');
        }
    }
    let s = s.trim_end_matches('-').to_string();
    if s.is_empty() { "design".into() } else { s }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_are_palindromes() {
        let f = Family::new("x", Form::Aba, 5, 4);
        let l = f.layout();
        assert_eq!(l.names, ["a1", "a2", "a3", "b1", "b2", "b3"]);
        assert_eq!(l.drift, [0, 1, 2, 2, 1, 0]);
        assert_eq!(l.kick, [3, 4, 5, 4, 3]);
        let f = Family::new("x", Form::Bab, 6, 4);
        let l = f.layout();
        assert_eq!(l.names, ["a1", "a2", "a3", "b1", "b2", "b3", "b4"]);
        assert_eq!(l.kick, [3, 4, 5, 6, 5, 4, 3]);
        let l = Family::new("x", Form::Composition, 5, 4).layout();
        assert_eq!(l.gamma, [0, 1, 2, 1, 0]);
    }
}
