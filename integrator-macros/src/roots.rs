//! Entries in real algebraic numbers: `let c0 = root(6*x^2 - 6*x + 1, 0, 1/2);`
//! binds the one root of the polynomial (in `x`, rational coefficients) in
//! `(LO, HI]`, and the entries of `a`, `b` (and `c`) are polynomials in such
//! roots — the `root(...)` table files of `tableau::algebraic::file`.
//!
//! The invocation is rendered to the text of such a table file and read by
//! `tableau::algebraic::file::parse`, so the macro decides exactly what
//! `symlab check` and `symlab compare --table` decide for the same table:
//! symplecticity by exact zero tests of every `Wᵢⱼ` (a false claim names the
//! nonzero entries), `B(k)`, and the order conditions on the trees in the
//! number field (a false claim names the tree); what tableau does not decide
//! for such tables is refused at the claim, saying so. Every
//! error of the file reader names a field (`let.c0`, `a[0][1]`), which is
//! mapped back to the token the user wrote.
//!
//! The coefficients are the correctly rounded doubles of the exact entries
//! and the zero pattern of `A` is decided exactly, both by
//! `tableau::algebraic::rounded::round_root_table` (as for `symlab compare
//! --table`): explicit tables are unrolled, the others step through the
//! core's stage solver.

use std::collections::BTreeMap;
use std::fmt::Write;

use proc_macro2::{Span, TokenStream};
use quote::quote;
use syn::Error;
use tableau::algebraic::file::{AlgAnalysis, AlgFile, Loaded};
use tableau::algebraic::rounded::{RootF64, round_root_table};
use tableau::analysis::Class;
use tableau::claims::{Claim, parse_claim};

use crate::ast::{Entry, Input, Value};
use crate::emit::{Facts, emit, rk_consts};
use crate::errors::Errors;
use crate::step;

/// The fields a table with `root(...)` entries takes (`a_hat`, `b_hat`,
/// `c_hat`: a partitioned pair, `a`, `b` acting on `q`).
const KEYS: &[&str] = &["claims", "a", "b", "c", "a_hat", "b_hat", "c_hat"];

/// A verified table with `root(...)` entries.
pub struct RootTable {
    pub file: AlgFile,
    pub analysis: AlgAnalysis,
    pub claims: Vec<Claim>,
    /// The doubles, the exact zero pattern of `A` and the order its
    /// decided conditions prove (at most 2): `tableau`'s, as `compare
    /// --table` has them.
    pub rounded: RootF64,
}

/// `Some` when a `let` binds a `root(...)`: then the whole invocation is a
/// table with algebraic entries.
pub fn validate(input: &Input) -> Option<Result<RootTable, Error>> {
    if !input.lets.iter().any(|l| is_root(&l.value)) {
        return None;
    }
    Some(check(input))
}

/// `root ( … )` as the whole value: the `(` after `root` closes at the end.
fn is_root(e: &Entry) -> bool {
    let Some(inner) = e.text.strip_prefix("root (") else {
        return false;
    };
    let mut depth = 1i32;
    for (i, ch) in inner.char_indices() {
        match ch {
            '(' => depth += 1,
            ')' => {
                depth -= 1;
                if depth == 0 {
                    return i + 1 == inner.len();
                }
            }
            _ => {}
        }
    }
    false
}

/// A TOML basic string.
fn quoted(s: &str) -> String {
    let mut out = String::from("\"");
    for ch in s.chars() {
        match ch {
            '\\' => out.push_str("\\\\"),
            '"' => out.push_str("\\\""),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The text `tableau` reads for a `let` value: `root(…)` without the space
/// the token rendering puts after `root`.
fn let_text(e: &Entry) -> String {
    match e.text.strip_prefix("root (") {
        Some(rest) if is_root(e) => format!("root({rest}"),
        _ => e.text.clone(),
    }
}

fn check(input: &Input) -> Result<RootTable, Error> {
    let mut errs = Errors::default();
    // Where each field of the rendered file came from.
    let mut spans: BTreeMap<String, Span> = BTreeMap::new();
    let mut root_args: BTreeMap<String, Span> = BTreeMap::new();
    let mut claim_items: Vec<&Entry> = Vec::new();
    let mut body = String::new();
    let mut seen = Vec::new();
    for f in &input.fields {
        let k = f.key.to_string();
        if !KEYS.contains(&k.as_str()) {
            errs.push(
                f.span(),
                format!(
                    "a table with root(...) entries takes the fields {}, not `{k}` (roots are read for Runge–Kutta tables and pairs)",
                    KEYS.join(", ")
                ),
            );
            continue;
        }
        if seen.contains(&k) {
            errs.push(f.span(), format!("field `{k}` is given twice"));
            continue;
        }
        seen.push(k.clone());
        spans.insert(k.clone(), f.value.span());
        match (k.as_str(), &f.value) {
            ("claims", Value::Vector(items, _)) => claim_items.extend(items),
            ("claims", v) => errs.push(v.span(), "claims are a list: `claims: [symplectic]`"),
            ("a" | "a_hat", Value::Matrix(rows, _)) => {
                let mut text = format!("{k} = [");
                for (i, (row, row_span)) in rows.iter().enumerate() {
                    spans.insert(format!("{k}[{i}]"), *row_span);
                    let cells: Vec<String> = row
                        .iter()
                        .enumerate()
                        .map(|(j, e)| {
                            spans.insert(format!("{k}[{i}][{j}]"), e.span());
                            quoted(&e.text)
                        })
                        .collect();
                    let _ = write!(text, "[{}], ", cells.join(", "));
                }
                text.push_str("]\n");
                body.push_str(&text);
            }
            ("a" | "a_hat", v) => {
                errs.push(v.span(), format!("`{k}` is a matrix: `{k}: [[…], […]]`"))
            }
            (_, Value::Vector(items, _)) => {
                let cells: Vec<String> = items
                    .iter()
                    .enumerate()
                    .map(|(i, e)| {
                        spans.insert(format!("{k}[{i}]"), e.span());
                        quoted(&e.text)
                    })
                    .collect();
                let _ = writeln!(body, "{k} = [{}]", cells.join(", "));
            }
            (_, v) => errs.push(v.span(), format!("`{k}` is a vector: `{k}: […]`")),
        }
    }
    for key in ["a", "b"] {
        if !seen.iter().any(|k| k == key) {
            errs.push(
                input.name.span(),
                format!("a table with root(...) entries needs `{key}`"),
            );
        }
    }
    let mut lets = String::from("[let]\n");
    for l in &input.lets {
        let name = l.name.to_string();
        if spans
            .insert(format!("let.{name}"), l.value.span())
            .is_some()
        {
            errs.push(l.name.span(), format!("`let {name}` is bound twice"));
        }
        if is_root(&l.value) {
            // The interval: LO and HI, after the first top-level comma.
            let mut depth = 0i32;
            let first_comma = l.value.text.char_indices().find_map(|(i, ch)| match ch {
                '(' => {
                    depth += 1;
                    None
                }
                ')' => {
                    depth -= 1;
                    None
                }
                ',' if depth == 1 => Some(i),
                _ => None,
            });
            if let Some(i) = first_comma {
                let end = l.value.text.len() - 1;
                root_args.insert(
                    format!("let.{name}"),
                    l.value.span_at(i + 1, end.saturating_sub(i + 1)),
                );
            }
        }
        let _ = writeln!(lets, "{} = {}", quoted(&name), quoted(&let_text(&l.value)));
    }
    if let Some(e) = errs.take() {
        return Err(e);
    }
    let text = format!("name = {}\n{body}{lets}", quoted(&input.name.to_string()));
    let label = format!("butcher! {}", input.name);
    let claim_texts: Vec<String> = claim_items.iter().map(|e| e.text.clone()).collect();
    let Some(work) = on_analysis_thread(move || read_and_analyse(&label, &text, &claim_texts))
    else {
        return Err(Error::new(
            input.name.span(),
            "the exact analysis of this root(...) table failed (a panic in tableau): please report it",
        ));
    };
    let file = match work.file {
        Ok(Loaded::Algebraic(f)) => *f,
        Ok(_) => {
            return Err(Error::new(
                input.name.span(),
                "internal: the root(...) table was not read as one",
            ));
        }
        Err(e) => {
            let field = e.field.clone().unwrap_or_default();
            let interval =
                e.message.contains("distinct real roots") || e.message.contains("interval");
            let span = interval
                .then(|| root_args.get(&field))
                .flatten()
                .or_else(|| spans.get(&field))
                .or_else(|| {
                    // `a[1]` for a short row, `a` for a wrong shape.
                    let head = field.split('[').next().unwrap_or("");
                    spans.get(head)
                })
                .copied()
                .unwrap_or_else(|| input.name.span());
            let what = if let Some(name) = field.strip_prefix("let.") {
                format!("`let {name}`")
            } else if field.is_empty() {
                "the table".to_string()
            } else {
                format!("`{field}`")
            };
            return Err(Error::new(span, format!("{what}: {}", e.message)));
        }
    };
    let mut claims = Vec::new();
    for ((item, parsed), verdict) in claim_items.iter().zip(work.claims).zip(work.verdicts) {
        match parsed {
            Ok(c) => {
                if let Err(m) = verdict {
                    errs.push(item.span(), m);
                }
                claims.push(c);
            }
            Err(m) => errs.push(item.span(), m),
        }
    }
    let rounded = match work.coefficients {
        Ok(x) => x,
        Err(m) => {
            errs.push(input.name.span(), m);
            return Err(errs.take().expect("just pushed"));
        }
    };
    errs.finish()?;
    let analysis = work.analysis.expect("analysed when the file was read");
    Ok(RootTable {
        file,
        analysis,
        claims,
        rounded,
    })
}

/// What the reader and the exact analysis decided (no spans: it is computed
/// on another thread).
struct Work {
    file: Result<Loaded, tableau::file::FileError>,
    analysis: Option<AlgAnalysis>,
    /// Each claim as parsed, and its verdict.
    claims: Vec<Result<Claim, String>>,
    verdicts: Vec<Result<(), String>>,
    coefficients: Result<RootF64, String>,
}

/// Read the rendered file, decide what its claims need, check them and
/// round the coefficients.
fn read_and_analyse(label: &str, text: &str, claim_texts: &[String]) -> Work {
    let claims: Vec<Result<Claim, String>> = claim_texts.iter().map(|t| parse_claim(t)).collect();
    let file = tableau::algebraic::file::parse(label, text);
    let Ok(Loaded::Algebraic(f)) = &file else {
        return Work {
            file,
            analysis: None,
            verdicts: vec![Ok(()); claims.len()],
            claims,
            coefficients: Err(String::new()),
        };
    };
    let analysis = f.analyse();
    let verdicts = claims
        .iter()
        .map(|c| match c {
            Ok(c) => f.check_claim(&analysis, c),
            Err(_) => Ok(()),
        })
        .collect();
    let coefficients = round_root_table(f, &analysis);
    Work {
        analysis: Some(analysis),
        claims,
        verdicts,
        coefficients,
        file,
    }
}

/// The stack of the analysis thread. The analysis recurses only as deep as
/// an entry is nested (`tableau::expr::MAX_DEPTH` levels) since `tableau`
/// compares rationals without recursion; the 512 MiB this once was dates
/// from before that, when the unoptimised analysis a proc macro runs
/// overflowed rustc's stack on root tables of a few hundred terms. 16 MiB is
/// what `symlab check` and `compare --table` give the same analysis
/// (`src/check.rs`), where every collocation root file with s ≤ 8 checks on
/// 2 MiB in a debug build: margin for the macro's unoptimised build, and a
/// reservation that a limit on rustc's address space does not refuse.
const ANALYSIS_STACK_BYTES: usize = 16 << 20;

/// Run `f` on a thread of its own, so that a panic of the analysis is a
/// compile error rather than a crash of rustc (`None` if it panicked or the
/// thread could not start), on a stack of [`ANALYSIS_STACK_BYTES`].
fn on_analysis_thread<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> Option<T> {
    std::thread::Builder::new()
        .name("butcher-roots".into())
        .stack_size(ANALYSIS_STACK_BYTES)
        .spawn(f)
        .ok()?
        .join()
        .ok()
}

/// The scheme type: the items of the `Table` path (facts, coefficients,
/// step code), with the verdicts decided for root tables.
pub fn expand(input: &Input, t: &RootTable) -> TokenStream {
    let name = &input.name;
    let stages = t.analysis.stages;
    let symplectic = t.analysis.symplectic == Some(true);
    let symplectic_separable = t.analysis.symplectic_separable == Some(true);
    // A pair symplectic for separable Hamiltonians only (b ≠ b̂) steps only
    // separable systems, as other such pairs do.
    let r = &t.rounded;
    let separable_only = r.hat.is_some() && symplectic_separable && !symplectic;
    let form = if r.hat.is_some() { "prk" } else { "rk" };
    let evaluations = if r.hat.is_some() { 2 * stages } else { stages };
    let explicit = r.class == Class::Explicit;
    let q_consts = rk_consts(&r.table, "");
    let p_consts = r.hat.as_ref().map(|p| rk_consts(p, "_HAT"));
    let coefficients = quote!(#q_consts #p_consts);
    let step_code = match r.class {
        _ if r.hat.is_some() => step::implicit(
            name,
            stages,
            "Full",
            true,
            if separable_only {
                quote!(::integrator_core::Separable)
            } else {
                quote!(::integrator_core::Hamiltonian)
            },
        ),
        Class::Explicit => step::explicit_rk(name, &r.table.a, &r.table.b, &r.table.c),
        class => step::implicit(
            name,
            stages,
            match class {
                Class::Sdirk => "Sdirk",
                Class::Dirk => "Dirk",
                _ => "Full",
            },
            false,
            quote!(::integrator_core::OdeSystem),
        ),
    };
    let mut facts: Vec<String> = t.claims.iter().map(|c| format!("`{c}`")).collect();
    if facts.is_empty() {
        facts.push("no claims".into());
    }
    let summary = format!(
        "*{name}* — entries in {} real algebraic root(s) ({}), verified exactly at compile time: {}. Symplecticity and the order conditions are decided exactly in the number field of the roots.",
        t.file.field.names.len(),
        t.file.field.names.join(", "),
        facts.join(", ")
    );
    let facts = Facts {
        name: name.to_string(),
        form,
        stages,
        // The claimed order where one was proven (on the trees, exactly in
        // the number field), else what the first conditions show.
        order: t
            .claims
            .iter()
            .filter_map(|c| match c {
                Claim::Order { p, .. } => Some(*p),
                _ => None,
            })
            .fold(r.order, usize::max),
        order_doc: "The order proven for a root(...) table: a proven `order = p` claim, \
            else 1 when Σbᵢ = 1 and 2 when also Σbᵢcᵢ = 1/2 with c the row sums \
            (decided exactly; for a pair without a claim at most 1).",
        symplectic,
        symplectic_separable,
        separable_only,
        // Not decided for root(...) tables, so not claimed.
        symmetric: false,
        explicit,
        class: r.class.name(),
        evaluations,
        midpoint_weights: None,
        summary,
    };
    emit(input, &facts, coefficients, step_code)
}
