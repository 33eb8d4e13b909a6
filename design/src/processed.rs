//! A second corrector for a processed method of the catalogue (a kernel `K`
//! with its corrector `χ₁`, stepped `χ Kⁿ χ⁻¹`): the family
//! `form = "second-corrector"`, `kernel = "ID"` (`designs/whckl-c17-corrector2.toml`).
//!
//! **The form.** `χ₂ = U(½, c) U(−½, c)` with
//! `U(a, c) = D(2a) K(c) D(−2a) K(−c) D(2a) K(−c) D(−2a) K(c)` (drifts `D`,
//! kicks `K`, in units of the step `h`, in the order applied): Wisdom, Holman
//! & Touma's second corrector as REBOUND's WHFast applies it
//! (`corrector2`), its coefficient `c` left unknown. The emitted method
//! applies `χ₁` then `χ₂` at output (and their inverse once on entry), the
//! kernel unchanged, so a step costs what the method's step costs.
//!
//! **The condition.** `χ₂`'s part linear in `ε` vanishes (each kick is undone
//! by its negative between drifts that cancel), so the effective method's
//! `ε` terms are the method's. Its `ε²` part is of degree 4 in `h`, a
//! multiple of `[A,[[A,B],B]]` (the only `ε²` Lie element of degree 4), so
//! it changes the `ε²h⁵` error of the effective method `χ K χ⁻¹` only along
//! `[A,[A,[[A,B],B]]]` (conjugation adds `[log χ₂, hA]`). The `ε²h⁵` terms
//! are two, with Lyndon words `A³B²` and `A²BAB`; the second basis element,
//! `[[A,[A,B]],[A,B]]`, has no `A³B²` coefficient, so the part `χ₂` can
//! remove vanishes exactly when the coefficient of `A³B²` does. That is the
//! condition; the `[[A,[A,B]],[A,B]]` part stays, so the claimed generalised
//! order is the method's and the report states both coefficients, before and
//! after. The coefficient is a polynomial of degree at most 2 in `c` (an `ε²`
//! term carries two kicks): it is found exactly from tableau's exact
//! near-integrable coefficients ([`tableau::near_integrable`]) at
//! `c = 0, 1, −1`, checked at `c = 2`, its linear part checked to be zero,
//! and solved, `c² = −f₀/f₂`; where that is negative, `χ₂` is applied
//! inverted (its sequence reversed and negated), which flips the sign of
//! `f₂`. The answer is exact: `c = √(c²)` in tableau's numbers.

use std::path::{Path, PathBuf};

use tableau::near_integrable::{
    NearCondition, near_coefficients, processed_orders, processed_table,
};
use tableau::{Number, Splitting, Table};

use crate::family::{FamilyError, stem};

/// The `form` of a second-corrector family.
pub const FORM: &str = "second-corrector";

/// The keys of a second-corrector family file.
const KEYS: [&str; 4] = ["name", "source", "form", "kernel"];

/// The `let` binding the emitted table gives `c`.
const BINDING: &str = "c2nd";

/// A second-corrector family, read from a file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CorrectorFamily {
    pub name: String,
    pub source: Option<String>,
    /// The catalogue id of the processed method (a kernel with a corrector).
    pub kernel: String,
}

/// Whether the TOML text declares a second-corrector family
/// (`form = "second-corrector"`); `false` for anything else, unreadable
/// text included (the family parser then says what is wrong).
pub fn is_corrector_family(text: &str) -> bool {
    text.parse::<toml::Table>()
        .ok()
        .and_then(|t| t.get("form").and_then(|v| v.as_str()).map(|f| f == FORM))
        .unwrap_or(false)
}

fn error(file: &str, field: Option<&str>, message: String) -> FamilyError {
    FamilyError {
        file: file.to_string(),
        field: field.map(str::to_string),
        message,
    }
}

/// Parse a second-corrector family; every error names the file and field.
pub fn parse_corrector_family(file: &str, text: &str) -> Result<CorrectorFamily, FamilyError> {
    let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        error(file, None, format!("not a TOML file: {}", e.message()))
    })?;
    for key in table.keys() {
        if !KEYS.contains(&key.as_str()) {
            return Err(error(
                file,
                Some(key),
                format!(
                    "unknown field for a {FORM} family (it takes {})",
                    KEYS.join(", ")
                ),
            ));
        }
    }
    let string = |key: &str| -> Result<Option<String>, FamilyError> {
        match table.get(key) {
            None => Ok(None),
            Some(toml::Value::String(s)) => Ok(Some(s.clone())),
            Some(other) => Err(error(
                file,
                Some(key),
                format!("expected a string, found {}", other.type_str()),
            )),
        }
    };
    let name =
        string("name")?.ok_or_else(|| error(file, None, "the field `name` is missing".into()))?;
    let kernel = string("kernel")?.ok_or_else(|| {
        error(
            file,
            None,
            "the field `kernel` is missing: the catalogue id of a processed method (a kernel with its corrector, e.g. \"whckl-c17\")".into(),
        )
    })?;
    let loaded =
        tableau::catalogue::load(&kernel).map_err(|e| error(file, Some("kernel"), e.message))?;
    if loaded.corrector.is_none() {
        return Err(error(
            file,
            Some("kernel"),
            format!(
                "'{kernel}' has no corrector; a second corrector is added to a processed method of the catalogue: {}",
                processed_ids().join(", ")
            ),
        ));
    }
    Ok(CorrectorFamily {
        name,
        source: string("source")?,
        kernel,
    })
}

/// The catalogue's processed methods.
fn processed_ids() -> Vec<&'static str> {
    tableau::catalogue::entries()
        .iter()
        .filter(|e| e.load().is_ok_and(|f| f.corrector.is_some()))
        .map(|e| e.id)
        .collect()
}

/// Read a second-corrector family file.
pub fn load_corrector_family(path: &Path) -> Result<CorrectorFamily, FamilyError> {
    let text = crate::family::read_family_text(path)?;
    parse_corrector_family(&path.display().to_string(), &text)
}

/// The designed second corrector.
#[derive(Clone, Debug)]
pub struct CorrectorDesign {
    pub family: CorrectorFamily,
    /// `c²`, exact.
    pub c_squared: Number,
    /// `c = √(c²)`, exact.
    pub c: Number,
    /// How `χ₂` is applied.
    pub orientation: Orientation,
    /// The `ε²h⁵` Lyndon coefficients of the effective method without the
    /// second corrector and with it, exact.
    pub before: Vec<NearCondition>,
    pub after: Vec<NearCondition>,
    /// The effective generalised order without and with it, as tableau
    /// decides them (`(≥18, 4)`: `≥` where the degree examined was reached).
    pub orders_before: String,
    pub orders_after: String,
    /// The emitted table's file name and text.
    pub table: (String, String),
}

/// `χ₂`'s drifts and kicks (signs of `c`) in the order applied: `U(½, c)
/// U(−½, c)`, or its inverse (reversed, negated).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Orientation {
    Forward,
    Inverse,
}

impl Orientation {
    fn drifts(self) -> [i64; 9] {
        match self {
            Orientation::Forward => [1, -1, 1, -1, -1, 1, -1, 1, 0],
            Orientation::Inverse => [0, -1, 1, -1, 1, 1, -1, 1, -1],
        }
    }
    fn kicks(self) -> [i64; 8] {
        match self {
            Orientation::Forward => [1, -1, -1, 1, 1, -1, -1, 1],
            Orientation::Inverse => [-1, 1, 1, -1, -1, 1, 1, -1],
        }
    }
    /// How the report and the table's comment write it.
    pub fn text(self) -> &'static str {
        match self {
            Orientation::Forward => "χ₂ = U(1/2, c) U(−1/2, c)",
            Orientation::Inverse => "χ₂ = (U(1/2, c) U(−1/2, c))⁻¹",
        }
    }
}

/// `χ₁` followed by `χ₂(c)` (`c` in units of `h`).
fn with_second(chi: &Splitting, c: &Number, o: Orientation) -> Splitting {
    let mut drift = chi.drift.clone();
    let last = drift.pop().unwrap_or_else(Number::zero);
    let d = o.drifts();
    drift.push(&last + &Number::from_bigint(d[0].into()));
    for &x in &d[1..] {
        drift.push(Number::from_bigint(x.into()));
    }
    let mut kick = chi.kick.clone();
    for s in o.kicks() {
        kick.push(if s > 0 { c.clone() } else { -c });
    }
    let gradient = if chi.gradient.is_empty() {
        Vec::new()
    } else {
        let mut g = chi.gradient.clone();
        g.extend(std::iter::repeat_n(Number::zero(), 8));
        g
    };
    Splitting {
        drift,
        kick,
        gradient,
    }
}

/// The Lie element a second corrector adds to at `ε²h⁵`; its leading word
/// `A³B²` is the condition's.
const REMOVABLE: &str = "[A,[A,[[A,B],B]]]";

/// The `ε²h⁵` Lyndon coefficients of the effective method with `χ₂(c)`.
fn eps2_h5(
    kernel: &Table,
    chi: &Splitting,
    c: &Number,
    o: Orientation,
    origin: &str,
) -> Result<Vec<NearCondition>, FamilyError> {
    let effective = processed_table(kernel, &Table::Splitting(with_second(chi, c, o)))
        .map_err(|e| error(origin, Some("kernel"), e.to_string()))?;
    Ok(near_coefficients(&effective, &[5, 5])
        .map_err(|e| error(origin, Some("kernel"), e.to_string()))?
        .into_iter()
        .filter(|w| w.bs == 2 && w.degree == 5)
        .collect())
}

/// The coefficient of the condition's word among `ws`.
fn removable(ws: &[NearCondition], origin: &str) -> Result<Number, FamilyError> {
    ws.iter()
        .find(|w| w.lie == REMOVABLE)
        .map(|w| w.value.clone())
        .ok_or_else(|| {
            error(
                origin,
                None,
                format!("internal error: no ε²h⁵ term {REMOVABLE}; please report it"),
            )
        })
}

/// `c²` for orientation `o`: the root of the condition's coefficient, a
/// polynomial `f₀ + f₂c²` in `c` (found exactly, checked), or `None` where
/// it is not positive.
fn solve(
    kernel: &Table,
    chi: &Splitting,
    o: Orientation,
    family: &CorrectorFamily,
    origin: &str,
) -> Result<Option<Number>, FamilyError> {
    let n = |k: i64| Number::from_bigint(k.into());
    let at = |c: i64| -> Result<Number, FamilyError> {
        removable(&eps2_h5(kernel, chi, &n(c), o, origin)?, origin)
    };
    let (v0, v1, vm1, v2) = (at(0)?, at(1)?, at(-1)?, at(2)?);
    let half = Number::ratio(1, 2).expect("1/2");
    let f1 = &(&v1 - &vm1) * &half;
    let f2 = &(&(&v1 + &vm1) * &half) - &v0;
    let predicted = &(&v0 + &(&f1 * &n(2))) + &(&f2 * &n(4));
    if predicted != v2 || !f1.is_zero() {
        return Err(error(
            origin,
            Some("kernel"),
            format!(
                "internal error: the ε²h⁵ coefficient of {REMOVABLE} is not even and quadratic in c; please report it"
            ),
        ));
    }
    if f2.is_zero() {
        return Err(error(
            origin,
            Some("kernel"),
            format!(
                "the ε²h⁵ term {REMOVABLE} of '{}' does not depend on c: nothing to design",
                family.kernel
            ),
        ));
    }
    let r = -v0
        .checked_div(&f2)
        .map_err(|e| error(origin, Some("kernel"), e.to_string()))?;
    Ok((r.signum() == std::cmp::Ordering::Greater).then_some(r))
}

/// The degrees the effective orders are decided to: the method's claimed
/// `p₁` (its `ε` terms are untouched), 6 for `ε²` (one degree beyond the
/// terms the condition removes) and 4 for every higher power of `ε` (the
/// method's classical order), within tableau's budget for the method's
/// many flows.
fn degrees(p1: usize) -> Vec<usize> {
    vec![p1, 6, 4]
}

/// Design the second corrector of `family` (`origin` names the family file
/// in messages).
pub fn design_corrector(
    family: &CorrectorFamily,
    origin: &str,
) -> Result<CorrectorDesign, FamilyError> {
    let file = tableau::catalogue::load(&family.kernel)
        .map_err(|e| error(origin, Some("kernel"), e.message))?;
    let chi = file.corrector.clone().ok_or_else(|| {
        error(
            origin,
            Some("kernel"),
            format!("'{}' has no corrector", family.kernel),
        )
    })?;
    let (orientation, c_squared) =
        match solve(&file.table, &chi, Orientation::Forward, family, origin)? {
            Some(r) => (Orientation::Forward, r),
            None => match solve(&file.table, &chi, Orientation::Inverse, family, origin)? {
                Some(r) => (Orientation::Inverse, r),
                None => {
                    return Err(error(
                        origin,
                        Some("kernel"),
                        format!(
                            "the ε²h⁵ term {REMOVABLE} of '{}' is already zero: nothing to design",
                            family.kernel
                        ),
                    ));
                }
            },
        };
    let c = c_squared
        .sqrt()
        .map_err(|e| error(origin, Some("kernel"), e.to_string()))?;
    let p1 = file
        .claims
        .iter()
        .find_map(|cl| match cl {
            tableau::claims::Claim::NearOrder { orders, .. } => orders.first().copied(),
            _ => None,
        })
        .unwrap_or(4);
    let orders = |corrector: &Splitting| -> Result<String, FamilyError> {
        processed_orders(
            &file.table,
            &Table::Splitting(corrector.clone()),
            &degrees(p1),
            None,
        )
        .map(|r| r.generalised_text())
        .map_err(|e| error(origin, Some("kernel"), e.to_string()))
    };
    let orders_before = orders(&chi)?;
    let orders_after = orders(&with_second(&chi, &c, orientation))?;
    let table = emitted(family, &c, orientation, &orders_after, origin)?;
    Ok(CorrectorDesign {
        family: family.clone(),
        c_squared,
        orientation,
        before: eps2_h5(&file.table, &chi, &Number::zero(), orientation, origin)?,
        after: eps2_h5(&file.table, &chi, &c, orientation, origin)?,
        orders_before,
        orders_after,
        c,
        table,
    })
}

/// The emitted table: the catalogue file of the method with `χ₂` appended
/// to its corrector (`c` bound in `let`), its name, source and claims
/// replaced (`symplectic`, `explicit`, the effective classical order and
/// the effective generalised order `orders`, which are then checked as
/// `symlab check` checks them).
fn emitted(
    family: &CorrectorFamily,
    c: &Number,
    orientation: Orientation,
    orders: &str,
    origin: &str,
) -> Result<(String, String), FamilyError> {
    let entry = tableau::catalogue::find(&family.kernel).ok_or_else(|| {
        error(
            origin,
            Some("kernel"),
            format!("'{}' is not in the catalogue", family.kernel),
        )
    })?;
    let mut t: toml::Table = entry
        .text
        .parse()
        .map_err(|e: toml::de::Error| error(origin, Some("kernel"), e.message().to_string()))?;
    let lets = t
        .entry("let")
        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
    if let Some(l) = lets.as_table_mut() {
        if l.contains_key(BINDING) {
            return Err(error(
                origin,
                Some("kernel"),
                format!("'{}' binds `let.{BINDING}` already", family.kernel),
            ));
        }
        l.insert(BINDING.into(), toml::Value::String(c.to_string()));
    }
    let strings = |v: Option<&toml::Value>| -> Vec<String> {
        v.and_then(|v| v.as_array())
            .map(|a| {
                a.iter()
                    .map(|x| match x {
                        toml::Value::String(s) => s.clone(),
                        other => other.to_string(),
                    })
                    .collect()
            })
            .unwrap_or_default()
    };
    let mut drift = strings(t.get("corrector_drift"));
    let last = drift.pop().unwrap_or_else(|| "0".into());
    let d = orientation.drifts();
    drift.push(if d[0] == 0 {
        last
    } else {
        format!("{last} + ({})", d[0])
    });
    drift.extend(d[1..].iter().map(i64::to_string));
    let mut kick = strings(t.get("corrector_kick"));
    for s in orientation.kicks() {
        kick.push(if s > 0 {
            BINDING.to_string()
        } else {
            format!("-{BINDING}")
        });
    }
    let array =
        |v: Vec<String>| toml::Value::Array(v.into_iter().map(toml::Value::String).collect());
    t.insert("corrector_drift".into(), array(drift));
    t.insert("corrector_kick".into(), array(kick));
    t.insert("name".into(), toml::Value::String(family.name.clone()));
    let source = match (&family.source, t.get("source").and_then(|s| s.as_str())) {
        (Some(f), Some(k)) => format!("{f}; the method: {k}"),
        (Some(f), None) => f.clone(),
        (None, Some(k)) => k.to_string(),
        (None, None) => String::new(),
    };
    t.insert("source".into(), toml::Value::String(source));
    let classical = orders
        .trim_matches(|ch| ch == '(' || ch == ')')
        .split(", ")
        .filter_map(|p| p.trim_start_matches('≥').parse::<usize>().ok())
        .min()
        .unwrap_or(2);
    let tuple = orders.replace('≥', "");
    t.insert(
        "claims".into(),
        array(vec![
            "symplectic".into(),
            "explicit".into(),
            format!("order = {classical}"),
            format!("order = {tuple}"),
        ]),
    );
    let body = toml::to_string(&t).map_err(|e| error(origin, None, e.to_string()))?;
    let header = format!(
        "# Designed by `symlab design {origin}` (design::processed): the catalogue's `{}` with a\n# second corrector {} applied at output after its corrector,\n# U(a, c) = D(2a) K(c) D(−2a) K(−c) D(2a) K(−c) D(−2a) K(c), c = {} ≈ {} (in units of h):\n# the ε²h⁵ error term {REMOVABLE} of the effective method vanishes exactly; the other,\n# [[A,[A,B]],[A,B]], is not changed by χ₂. Effective generalised order {orders}, as the method's.\n",
        family.kernel,
        orientation.text(),
        c,
        c.approx_text()
    );
    let text = format!("{header}{body}");
    let name = format!("{}.toml", stem(&family.name));
    // The claims hold, decided as `symlab check` decides them.
    let parsed = tableau::file::parse_table_file(&name, &text).map_err(|e| {
        error(
            origin,
            None,
            format!("internal error: the emitted table does not parse: {e}"),
        )
    })?;
    let analysis = tableau::analysis::Analysis::of(&parsed.table)
        .map_err(|e| error(origin, None, format!("internal error: {e}")))?;
    for claim in &parsed.claims {
        tableau::analysis::check_file_claim(&parsed, &analysis, claim).map_err(|e| {
            error(
                origin,
                None,
                format!("internal error: the emitted claim `{claim}` does not hold: {e}"),
            )
        })?;
    }
    Ok((name, text))
}

impl CorrectorDesign {
    /// Write the table and `report.md` into `dir` (created); the paths.
    pub fn write(&self, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let table = dir.join(&self.table.0);
        std::fs::write(&table, &self.table.1)?;
        let report = dir.join("report.md");
        std::fs::write(&report, self.report())?;
        Ok(vec![table, report])
    }

    /// The report: the condition, the answer, the terms and orders before
    /// and after.
    pub fn report(&self) -> String {
        use std::fmt::Write as _;
        let mut out = format!(
            "# {}\n\nA second corrector for `{}` ({FORM}): {}, applied at output after the method's corrector.\n\nThe ε²h⁵ Lyndon coefficients of the effective method χ K χ⁻¹, without χ₂ and with it:\n\n| word | Lie element | without | with |\n|---|---|---|---|\n",
            self.family.name,
            self.family.kernel,
            self.orientation.text()
        );
        for (b, a) in self.before.iter().zip(&self.after) {
            let _ = writeln!(
                out,
                "| {} | {} | {} ≈ {} | {} ≈ {} |",
                b.word,
                b.lie,
                b.value,
                b.value.approx_text(),
                a.value,
                a.value.approx_text()
            );
        }
        let _ = writeln!(
            out,
            "\nThe condition (the coefficient of {REMOVABLE}'s word vanishes) holds for c² = {} exactly: c = {} ≈ {}.\n\nEffective generalised order: {} without χ₂, {} with it (decided exactly by tableau).\n\nWrote `{}`.",
            self.c_squared,
            self.c,
            self.c.approx_text(),
            self.orders_before,
            self.orders_after,
            self.table.0
        );
        out
    }
}
