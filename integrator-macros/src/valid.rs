//! Validation: build the exact table from the entries, then check every
//! claim with `tableau`. Runs completely before expansion; every error is
//! attached to the token it is about and all errors are reported together.

use std::collections::BTreeMap;

use proc_macro2::Span;
use syn::Error;
use tableau::analysis::{self, Analysis};
use tableau::claims::{Claim, parse_claim};
use tableau::expr;
use tableau::{Composition, Number, Prk, Rk, Splitting, Table};

use crate::ast::{Entry, Field, Input, Value};
use crate::errors::Errors;

/// A table whose claims all hold.
pub struct Verified {
    pub table: Table,
    pub analysis: Analysis,
    pub claims: Vec<Claim>,
    pub name: String,
    /// The literature source, for tables read `from` the catalogue.
    pub source: Option<String>,
    /// For a processed method: the corrector `χ` (applied at output, `χ⁻¹`
    /// on entry); `table` is then the kernel.
    pub corrector: Option<Splitting>,
}

const KEYS: &[&str] = &[
    "claims",
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
    "from",
    "file",
    "kernel",
    "corrector_drift",
    "corrector_kick",
    "certificate_unknowns",
    "certificate_radius",
];

pub fn validate(input: &Input) -> Result<Verified, Error> {
    let mut errs = Errors::default();
    let mut fields: BTreeMap<String, &Field> = BTreeMap::new();
    for f in &input.fields {
        let k = f.key.to_string();
        if !KEYS.contains(&k.as_str()) {
            errs.push(
                f.span(),
                format!("unknown field `{k}`; the fields are {}", KEYS.join(", ")),
            );
        } else if fields.insert(k.clone(), f).is_some() {
            errs.push(f.span(), format!("field `{k}` is given twice"));
        }
    }

    // `let` bindings, in order; each may use the ones before it.
    let mut env: BTreeMap<String, Number> = BTreeMap::new();
    for l in &input.lets {
        if let Some(v) = eval(&l.value, &env, &mut errs) {
            env.insert(l.name.to_string(), v);
        }
    }

    let mut claims = Vec::new();
    let mut claim_spans = Vec::new();
    if let Some(f) = fields.get("claims") {
        match &f.value {
            Value::Vector(items, _) => {
                for item in items {
                    match parse_claim(&item.text) {
                        Ok(c) => {
                            claims.push(c);
                            claim_spans.push(item.span());
                        }
                        Err(m) => errs.push(item.span(), m),
                    }
                }
            }
            v => errs.push(
                v.span(),
                "claims are a list: `claims: [symplectic, order = 4]`",
            ),
        }
    }

    let table = build_table(input, &fields, &env, &mut errs);
    let inline_corrector = build_corrector(&fields, &env, &mut errs);
    errs.finish()?;
    let Some((table, name, file_claims, source, file_corrector, file_certificate)) = table else {
        return Err(Error::new(
            input.name.span(),
            "no table: give `a` and `b`, `drift` and `kick`, `compose`, `from` or `file`",
        ));
    };

    // A table read `from` the catalogue or from a `file` brings the claims
    // its file states, unless the invocation states its own.
    if claims.is_empty() && !file_claims.is_empty() {
        let span = fields
            .get("from")
            .or(fields.get("file"))
            .map_or(input.name.span(), |f| f.value.span());
        claim_spans = vec![span; file_claims.len()];
        claims = file_claims;
    }
    let analysis = match Analysis::of(&table) {
        Ok(a) => a,
        Err(e) => {
            let span = field_span(&fields, &e.field).unwrap_or(input.name.span());
            return Err(Error::new(span, e.to_string()));
        }
    };
    // The same budgets as `symlab check` (tableau::budget): a table whose
    // exact stability function is beyond them is refused here, at the table,
    // since its scheme would lack its stability constants. The build never
    // freezes on a table.
    if let Some(why) = &analysis.stability_not_computed {
        return Err(Error::new(
            input.name.span(),
            format!(
                "this table is beyond the budget of exact analysis: its stability function is not computed ({why}); see tableau::budget"
            ),
        ));
    }
    let corrector = inline_corrector.or(file_corrector);
    if let Some(chi) = &corrector {
        let span = fields
            .get("corrector_drift")
            .map_or(input.name.span(), |f| f.span());
        if !matches!(table, Table::Splitting(_) | Table::Composition(_)) {
            return Err(Error::new(
                span,
                "a corrector processes a kernel that is a drift–kick sequence or composition (`drift`/`kick`, `compose` or `kernel: \"ID\"`), not a Runge–Kutta table or pair",
            ));
        }
        if let Err(e) = Table::Splitting(chi.clone()).check_shape() {
            return Err(Error::new(span, format!("the corrector: {}", e.message)));
        }
    }
    let certificate = match certificate_of(input, &fields, &env, &table)? {
        Some(c) => Some(c),
        None => file_certificate,
    };
    let mut errs = Errors::default();
    for (claim, span) in claims.iter().zip(&claim_spans) {
        // A certified order is proven from the certificate's fields, by the
        // Krawczyk test `symlab check` runs (tableau::certificate).
        let certified = match (claim, &certificate) {
            (Claim::CertifiedOrder { p }, Some(spec)) => {
                Some(tableau::certificate::prove(spec, *p).map(|_| ()))
            }
            (Claim::CertifiedNearOrder { orders }, Some(spec)) => {
                Some(tableau::certificate::prove_orders(spec, orders, true).map(|_| ()))
            }
            _ => None,
        };
        if let Some(v) = certified {
            if let Err(e) = v {
                errs.push(*span, e);
            }
            continue;
        }
        // A processed method's order and symmetry claims are about the
        // effective method χ K χ⁻¹, as `symlab check` decides them.
        let processed = corrector.as_ref().and_then(|chi| {
            tableau::near_integrable::check_processed_claim(
                &table,
                &Table::Splitting(chi.clone()),
                claim,
            )
        });
        let verdict = match processed {
            Some(v) => v,
            None => analysis::check_claim(&table, &analysis, claim).map_err(|e| e.to_string()),
        };
        if let Err(e) = verdict {
            errs.push(*span, e);
        }
    }
    errs.finish()?;
    Ok(Verified {
        table,
        analysis,
        claims,
        name,
        source,
        corrector,
    })
}

/// `file: "PATH"`: a table file (the format of `symlab check`, e.g. a
/// table `symlab design` emitted), read at compile time from `PATH`
/// relative to the invoking crate's `Cargo.toml`, with its claims and its
/// certificate; the invocation gives no entries of its own. The emitted
/// code includes the file's bytes (`lib.rs`), so that cargo rebuilds when
/// the file changes.
fn read_file(f: &Field, fields: &BTreeMap<String, &Field>, errs: &mut Errors) -> Option<Built> {
    let Value::Str(path) = &f.value else {
        errs.push(
            f.value.span(),
            "`file` is a table file's path relative to the crate's Cargo.toml: `file: \"designs/mine.toml\"`",
        );
        return None;
    };
    if let Some(other) = KEYS
        .iter()
        .find(|k| **k != "file" && **k != "claims" && fields.contains_key(**k))
    {
        errs.push(
            fields[*other].span(),
            "a table read from a `file` takes no entries of its own",
        );
        return None;
    }
    let full = file_path(&path.value());
    match tableau::file::load(&full) {
        Ok(tf) => Some((
            tf.table,
            tf.name,
            tf.claims,
            tf.source,
            tf.corrector,
            tf.certificate,
        )),
        Err(e) => {
            errs.push(path.span(), e);
            None
        }
    }
}

/// `path` relative to the invoking crate's directory (`CARGO_MANIFEST_DIR`,
/// which cargo sets for the compiler and so for the macro); as given where
/// it is absolute or the variable is unset.
pub(crate) fn file_path(path: &str) -> std::path::PathBuf {
    match std::env::var_os("CARGO_MANIFEST_DIR") {
        Some(dir) => std::path::Path::new(&dir).join(path),
        None => std::path::PathBuf::from(path),
    }
}

/// The certificate of a certified order claim, from the fields
/// `certificate_unknowns: [a1, a2]` and `certificate_radius: "1e-46"`
/// (both or neither), the `let` bindings and the entries as written: the
/// same reading as a table file's `certificate` (tableau::certificate).
fn certificate_of(
    input: &Input,
    fields: &BTreeMap<String, &Field>,
    env: &BTreeMap<String, Number>,
    table: &Table,
) -> Result<Option<tableau::certificate::CertificateSpec>, Error> {
    let (u, r) = match (
        fields.get("certificate_unknowns"),
        fields.get("certificate_radius"),
    ) {
        (None, None) => return Ok(None),
        (Some(u), Some(r)) => (u, r),
        (Some(f), None) | (None, Some(f)) => {
            return Err(Error::new(
                f.span(),
                "a certificate has both `certificate_unknowns: [..]` and `certificate_radius: \"..\"`",
            ));
        }
    };
    let Value::Vector(items, _) = &u.value else {
        return Err(Error::new(
            u.span(),
            "`certificate_unknowns` is a list of names: `[a1, a2]`",
        ));
    };
    let unknowns: Vec<String> = items.iter().map(|e| e.text.trim().to_string()).collect();
    let Value::Str(radius) = &r.value else {
        return Err(Error::new(
            r.span(),
            "`certificate_radius` is a string: `\"1e-46\"`",
        ));
    };
    let radius =
        tableau::certificate::parse_radius(&radius.value()).map_err(|m| Error::new(r.span(), m))?;
    let lets: Vec<(String, String)> = input
        .lets
        .iter()
        .map(|l| (l.name.to_string(), l.value.text.clone()))
        .collect();
    let texts = |key: &str| -> Option<Vec<String>> {
        match &fields.get(key)?.value {
            Value::Vector(items, _) => Some(items.iter().map(|e| e.text.clone()).collect()),
            _ => None,
        }
    };
    tableau::certificate::spec_from_parts(
        &unknowns,
        radius,
        &lets,
        env,
        [texts("drift"), texts("kick"), texts("compose")],
        table,
    )
    .map(Some)
    .map_err(|(field, m)| Error::new(u.span(), format!("{field}: {m}")))
}

/// `corrector_drift` and `corrector_kick`, both or neither.
fn build_corrector(
    fields: &BTreeMap<String, &Field>,
    env: &BTreeMap<String, Number>,
    errs: &mut Errors,
) -> Option<Splitting> {
    let (d, k) = (fields.get("corrector_drift"), fields.get("corrector_kick"));
    match (d, k) {
        (None, None) => None,
        (Some(_), Some(_)) => Some(Splitting::new(vector(d, env, errs)?, vector(k, env, errs)?)),
        (Some(f), None) | (None, Some(f)) => {
            let missing = if d.is_some() {
                "corrector_kick"
            } else {
                "corrector_drift"
            };
            errs.push(
                f.span(),
                format!("missing field `{missing}`: a corrector is a drift–kick sequence (write `{missing}: []` for none)"),
            );
            None
        }
    }
}

/// The span for a shape error's field path such as `a[1]` or `b_hat`.
fn field_span(fields: &BTreeMap<String, &Field>, path: &str) -> Option<Span> {
    let key = path.split('[').next()?;
    let f = fields.get(key)?;
    let row: Option<usize> = path
        .split('[')
        .nth(1)
        .and_then(|r| r.trim_end_matches(']').parse().ok());
    match (&f.value, row) {
        (Value::Matrix(rows, _), Some(r)) => rows.get(r).map(|x| x.1),
        (v, _) => Some(v.span()),
    }
}

fn eval(entry: &Entry, env: &BTreeMap<String, Number>, errs: &mut Errors) -> Option<Number> {
    let parsed = match expr::parse(&entry.text) {
        Ok(p) => p,
        Err(e) => {
            errs.push(entry.span_at(e.pos, e.token.len()), &e.message);
            return None;
        }
    };
    match expr::eval(&parsed, &|name| env.get(name).cloned()) {
        Ok(v) => Some(v),
        Err(e) => {
            errs.push(entry.span_at(e.pos, e.len), e.kind.to_string());
            None
        }
    }
}

fn vector(
    f: Option<&&Field>,
    env: &BTreeMap<String, Number>,
    errs: &mut Errors,
) -> Option<Vec<Number>> {
    let f = f?;
    match &f.value {
        Value::Vector(items, _) => {
            let vals: Vec<Option<Number>> = items.iter().map(|e| eval(e, env, errs)).collect();
            vals.into_iter().collect()
        }
        v => {
            errs.push(
                v.span(),
                format!("`{}` is a list of numbers: `[1/2, 1/2]`", f.key),
            );
            None
        }
    }
}

fn matrix(
    f: Option<&&Field>,
    env: &BTreeMap<String, Number>,
    errs: &mut Errors,
) -> Option<Vec<Vec<Number>>> {
    let f = f?;
    match &f.value {
        Value::Matrix(rows, _) => {
            let mut out = Vec::new();
            let mut ok = true;
            for (row, _) in rows {
                let vals: Option<Vec<Number>> = row
                    .iter()
                    .map(|e| eval(e, env, errs))
                    .collect::<Vec<_>>()
                    .into_iter()
                    .collect();
                match vals {
                    Some(v) => out.push(v),
                    None => ok = false,
                }
            }
            ok.then_some(out)
        }
        v => {
            errs.push(
                v.span(),
                format!("`{}` is a matrix: `[[1/4, 0], [1/2, 1/4]]`", f.key),
            );
            None
        }
    }
}

/// A table as built: the table (a processed method's kernel), its name, the
/// claims and source of a catalogue file it was read `from`, and the
/// corrector of such a file.
type Built = (
    Table,
    String,
    Vec<Claim>,
    Option<String>,
    Option<Splitting>,
    Option<tableau::certificate::CertificateSpec>,
);

fn build_table(
    input: &Input,
    fields: &BTreeMap<String, &Field>,
    env: &BTreeMap<String, Number>,
    errs: &mut Errors,
) -> Option<Built> {
    let has = |k: &str| fields.contains_key(k);
    let name = input.name.to_string();
    if let Some(f) = fields.get("from") {
        let Value::Str(id) = &f.value else {
            errs.push(
                f.value.span(),
                "`from` names a catalogue table: `from: \"rk4\"`",
            );
            return None;
        };
        if let Some(other) = KEYS
            .iter()
            .find(|k| **k != "from" && **k != "claims" && has(k))
        {
            errs.push(
                fields[*other].span(),
                "a table read `from` the catalogue takes no entries of its own",
            );
            return None;
        }
        return match tableau::catalogue::load(&id.value()) {
            Ok(tf) => Some((tf.table, tf.name, tf.claims, tf.source, tf.corrector, None)),
            Err(e) => {
                errs.push(id.span(), e);
                None
            }
        };
    }
    if let Some(f) = fields.get("file") {
        return read_file(f, fields, errs);
    }
    if let Some(f) = fields.get("kernel") {
        let Value::Str(id) = &f.value else {
            errs.push(
                f.value.span(),
                "`kernel` names a catalogue drift–kick sequence or composition: `kernel: \"leapfrog\"`",
            );
            return None;
        };
        if let Some(other) = tableau::file::TABLE_FIELDS.iter().find(|k| has(k)) {
            errs.push(
                fields[*other].span(),
                "`kernel` names the kernel, so the table gives none inline",
            );
            return None;
        }
        if !has("corrector_drift") && !has("corrector_kick") {
            errs.push(
                f.span(),
                "`kernel` is the kernel of a processed method and needs `corrector_drift` and `corrector_kick`",
            );
            return None;
        }
        return match tableau::catalogue::load(&id.value()) {
            Ok(tf) if tf.corrector.is_some() => {
                errs.push(id.span(), format!("builtin:{} is itself a processed method; a kernel is a drift–kick sequence or composition", id.value()));
                None
            }
            Ok(tf) => Some((tf.table, name, Vec::new(), None, None, None)),
            Err(e) => {
                errs.push(id.span(), e);
                None
            }
        };
    }
    let rk_like = has("a") || has("b") || has("c");
    let pair = has("a_hat") || has("b_hat") || has("c_hat");
    let split = has("drift") || has("kick");
    let comp = has("compose");
    if has("kick_gradient") && !has("kick") {
        errs.push(
            fields["kick_gradient"].span(),
            "`kick_gradient` gives the gradients of the kicks of a drift–kick sequence (`drift`/`kick`)",
        );
        return None;
    }
    let forms = [rk_like, split, comp].iter().filter(|x| **x).count();
    if forms > 1 || (pair && !rk_like) {
        let span = input.fields.first().map_or(input.name.span(), |f| f.span());
        errs.push(span, "give exactly one form: `a`/`b` (with `a_hat`/`b_hat` for a pair), `drift`/`kick`, or `compose`");
        return None;
    }
    let require = |k: &str, errs: &mut Errors| {
        if !has(k) {
            errs.push(input.name.span(), format!("missing field `{k}`"));
        }
    };
    if rk_like {
        require("a", errs);
        require("b", errs);
        if pair {
            require("a_hat", errs);
            require("b_hat", errs);
        }
        let q = Rk {
            a: matrix(fields.get("a"), env, errs)?,
            b: vector(fields.get("b"), env, errs)?,
            c: if has("c") {
                Some(vector(fields.get("c"), env, errs)?)
            } else {
                None
            },
        };
        if !pair {
            return Some((Table::Rk(q), name, Vec::new(), None, None, None));
        }
        let p = Rk {
            a: matrix(fields.get("a_hat"), env, errs)?,
            b: vector(fields.get("b_hat"), env, errs)?,
            c: if has("c_hat") {
                Some(vector(fields.get("c_hat"), env, errs)?)
            } else {
                None
            },
        };
        return Some((Table::Prk(Prk { q, p }), name, Vec::new(), None, None, None));
    }
    if split {
        require("drift", errs);
        require("kick", errs);
        let gradient = if has("kick_gradient") {
            vector(fields.get("kick_gradient"), env, errs)?
        } else {
            Vec::new()
        };
        let s = Splitting {
            drift: vector(fields.get("drift"), env, errs)?,
            kick: vector(fields.get("kick"), env, errs)?,
            gradient,
        };
        return Some((Table::Splitting(s), name, Vec::new(), None, None, None));
    }
    if comp {
        let gamma = vector(fields.get("compose"), env, errs)?;
        return Some((
            Table::Composition(Composition { gamma }),
            name,
            Vec::new(),
            None,
            None,
            None,
        ));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn validate_text(text: &str) -> Result<Verified, Error> {
        let input: Input = syn::parse_str(text).expect("the invocation parses");
        validate(&input)
    }

    /// A table whose stability function is beyond the budget is a compile
    /// error at the table, quickly, never a frozen build.
    #[test]
    fn beyond_budget_is_an_error_at_the_table() {
        // 12 implicit stages over Q(sqrt(2), sqrt(3), sqrt(5), sqrt(7), sqrt(11), sqrt(13)):
        // 12⁴ × 64² > 2²⁶.
        let primes = [2, 3, 5, 7, 11, 13];
        let s = 12;
        let rows: Vec<String> = (0..s)
            .map(|i| {
                let row: Vec<String> = (0..s)
                    .map(|j| format!("1/{} + sqrt({})", i + j + 2, primes[(i + j) % 6]))
                    .collect();
                format!("[{}]", row.join(", "))
            })
            .collect();
        let b: Vec<String> = (0..s).map(|_| format!("1/{s}")).collect();
        let text = format!(
            "pub Huge {{ a: [{}], b: [{}], }}",
            rows.join(", "),
            b.join(", ")
        );
        let start = std::time::Instant::now();
        let err = validate_text(&text).err().expect("refused");
        assert!(start.elapsed().as_secs() < 10, "{:?}", start.elapsed());
        let msg = err.to_string();
        assert!(msg.contains("beyond the budget"), "{msg}");
        assert!(msg.contains("degree 64"), "{msg}");
    }

    /// `file:` reads a table file relative to the crate (the workspace's
    /// designed table, from integrator-macros), brings its claims and
    /// proves them; a missing file, a file with entries beside it, and a
    /// false claim over the file's table are errors naming what is wrong.
    #[test]
    fn file_tables_are_read_and_their_claims_proven() {
        let found = "../designs/found/rkn-aba-8-stages-order-6-3.toml";
        let v = validate_text(&format!("pub Designed {{ file: \"{found}\", }}"))
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(matches!(v.table, Table::Splitting(_)));
        let err = validate_text("pub Missing { file: \"no/such/table.toml\", }")
            .err()
            .expect("refused");
        assert!(
            err.to_string().contains("no/such/table.toml")
                && err.to_string().contains("cannot read"),
            "{err}"
        );
        let err = validate_text(&format!(
            "pub Both {{ file: \"{found}\", drift: [1/2, 1/2], kick: [1], }}"
        ))
        .err()
        .expect("refused");
        assert!(err.to_string().contains("no entries of its own"), "{err}");
        let err = validate_text(&format!(
            "pub Wrong {{ file: \"{found}\", claims: [order_rkn = 8], }}"
        ))
        .err()
        .expect("refused");
        assert!(err.to_string().contains("order"), "{err}");
        let err = validate_text("pub NotText { file: [a], }")
            .err()
            .expect("refused");
        assert!(
            err.to_string().contains("`file` is a table file's path"),
            "{err}"
        );
    }

    #[test]
    fn too_many_stages_and_long_literals_are_errors() {
        let gamma: Vec<String> = (0..150).map(|_| "1/150".to_string()).collect();
        let err = validate_text(&format!("pub Long {{ compose: [{}], }}", gamma.join(", ")))
            .err()
            .expect("refused");
        assert!(err.to_string().contains("at most 100 stages"), "{err}");
        let digits = "7".repeat(2000);
        let err = validate_text(&format!("pub Big {{ a: [[{digits}]], b: [1], }}"))
            .err()
            .expect("refused");
        assert!(err.to_string().contains("2000 digits"), "{err}");
    }

    /// A table with gradient kicks is verified like any other (its order
    /// on the Lie algebra), inline or read from the catalogue (whckl-c17),
    /// and a false claim is refused; an all-zero gradient list is plain
    /// kicks.
    #[test]
    fn gradient_kicks_are_verified_and_false_claims_refused() {
        use tableau::analysis::Form;
        for text in [
            "pub Lazy { claims: [symplectic, order = 2], drift: [1/2, 1/2], kick: [1], kick_gradient: [1/24], }",
            "pub Whckl { from: \"whckl-c17\", }",
        ] {
            let v = validate_text(text).unwrap_or_else(|e| panic!("{text}: {e}"));
            assert_eq!(v.analysis.form, Form::GradientDriftKick, "{text}");
        }
        let err = validate_text(
            "pub Lazy { claims: [order = 3], drift: [1/2, 1/2], kick: [1], kick_gradient: [1/24], }",
        )
        .err()
        .expect("a false claim is refused");
        assert!(err.to_string().contains("order"), "{err}");
        let err = validate_text("pub Odd { a: [[0]], b: [1], kick_gradient: [1], }")
            .err()
            .expect("refused");
        assert!(err.to_string().contains("`kick_gradient`"), "{err}");
        // The same sequence with plain kicks is accepted.
        for text in [
            "pub Leap { claims: [order = 2], drift: [1/2, 1/2], kick: [1], }",
            "pub Leap { claims: [order = 2], drift: [1/2, 1/2], kick: [1], kick_gradient: [0], }",
        ] {
            let v = validate_text(text).unwrap_or_else(|e| panic!("{text}: {e}"));
            assert_eq!(v.analysis.form, Form::DriftKick, "{text}");
        }
    }

    /// `butcher!` takes a certified order with its certificate's two fields
    /// and re-proves it (tableau's Krawczyk test); moved beyond the radius,
    /// the claim is a compile error saying so.
    #[test]
    fn a_certified_order_is_proven_from_its_certificate() {
        let text = |g1: &str| {
            format!(
                "pub Y {{ let g1 = {g1}; claims: [symmetric, order = 4 (certified)], certificate_unknowns: [g1], certificate_radius: \"1e-45\", compose: [g1, 1 - 2*g1, g1], }}"
            )
        };
        let g1 = "1.35120719195965763404768780897146082692199937621714";
        let v = validate_text(&text(g1)).unwrap_or_else(|e| panic!("{e}"));
        assert!(matches!(v.claims[1], Claim::CertifiedOrder { p: 4 }));
        let Err(err) = validate_text(&text("1.351207191959657634047687808971460826921999")) else {
            panic!("a moved coefficient is refused")
        };
        assert!(
            err.to_string()
                .contains("is not proven: Krawczyk's test fails"),
            "{err}"
        );
        // Without the certificate the claim is refused, saying why.
        let bare = "pub Y { let g1 = 1.35; claims: [order = 4 (certified)], compose: [g1, 1 - 2*g1, g1], }";
        let Err(err) = validate_text(bare) else {
            panic!("a claim without its certificate is refused")
        };
        assert!(err.to_string().contains("`certificate`"), "{err}");
    }
}
