//! `from: "gauss8"` (or `"gauss(8)"`, `"radau2a5"`, `"lobatto3a3b4"` …):
//! a collocation-type table that `tableau::algebraic` generates and proves,
//! for any stage count up to its limit. The catalogue's hand-written tables
//! win where an id names both (`gauss3`), so the library's existing schemes
//! keep their constants.
//!
//! The entries of these tables are real algebraic numbers (roots of
//! Legendre-type polynomials), beyond the radicals the `Table` path
//! handles; `tableau` decides their claims exactly in products of number
//! fields and rounds their coefficients with certified refinement (for
//! symplectic tables, the rounding that keeps the symplecticity defect as
//! small as `f64` allows). Validation mirrors the `Table` path: claims (the
//! invocation's, else the literature's) checked with errors on their tokens
//! ([`Errors`]); the scheme, stepped by the stage solver, is written by the
//! same emitter ([`emit`]) from the facts proven here.

use proc_macro2::{Span, TokenStream};
use quote::quote;
use syn::Error;
use tableau::algebraic::family::{Family, Generator};
use tableau::algebraic::generated::{Generated, GeneratedTable, literature_claims};
use tableau::claims::parse_claim;

use crate::ast::{Input, Value};
use crate::emit::{Facts, emit, rk_consts, stability_tokens};
use crate::errors::Errors;
use crate::step;

/// The generated table an invocation names, if it names one: `None` for
/// every invocation the `Table` path handles (entries of its own, or a
/// catalogue id).
pub fn validate(input: &Input) -> Option<Result<Generated, Error>> {
    let from = input.fields.iter().find(|f| f.key == "from")?;
    let Value::Str(id) = &from.value else {
        return None;
    };
    if tableau::catalogue::load(&id.value()).is_ok() {
        return None;
    }
    let generator = Generator::parse(&id.value()).ok()?;
    Some(check(input, generator, id.span()))
}

fn check(input: &Input, generator: Generator, id_span: Span) -> Result<Generated, Error> {
    let mut errs = Errors::default();
    if !input.lets.is_empty() {
        errs.push(
            input.lets[0].name.span(),
            "a generated table takes no `let` bindings",
        );
    }
    let mut claims = Vec::new();
    let mut spans = Vec::new();
    for f in &input.fields {
        match (f.key.to_string().as_str(), &f.value) {
            ("from", _) => {}
            ("claims", Value::Vector(items, _)) => {
                for item in items {
                    match parse_claim(&item.text) {
                        Ok(c) => {
                            claims.push(c);
                            spans.push(item.span());
                        }
                        Err(m) => errs.push(item.span(), m),
                    }
                }
            }
            ("claims", v) => errs.push(
                v.span(),
                "claims are a list: `claims: [symplectic, order = 16]`",
            ),
            (k, _) => errs.push(
                f.span(),
                format!(
                    "a generated table (`from: \"{}\"`) takes no field `{k}`; only `claims`",
                    generator.expression()
                ),
            ),
        }
    }
    if let Some(e) = errs.take() {
        return Err(e);
    }
    if claims.is_empty() {
        claims = literature_claims(generator);
        spans = vec![id_span; claims.len()];
    }
    let g = Generated::with_claims(generator, claims);
    for ((_, verdict), span) in g.claims.iter().zip(&spans) {
        if let Err(e) = verdict {
            errs.push(*span, e.to_string());
        }
    }
    errs.finish()?;
    Ok(g)
}

/// The scheme type of a generated table: the same items as the `Table`
/// path's (facts, coefficients, stability function, stage-solver step).
pub fn expand(input: &Input, g: &Generated) -> TokenStream {
    let name = &input.name;
    let stages = g.stages;
    let (form, coefficients, step_code, evaluations, separable_only) = match &g.f64_table {
        GeneratedTable::Rk(t) => {
            let consts = rk_consts(t, "");
            let stab = g
                .stability
                .as_ref()
                .map(stability_tokens)
                .unwrap_or_default();
            let code = step::implicit(
                name,
                stages,
                "Full",
                false,
                quote!(::integrator_core::OdeSystem),
            );
            ("rk", quote!(#consts #stab), code, stages, false)
        }
        GeneratedTable::Prk(pair) => {
            let q = rk_consts(&pair.q, "");
            let p = rk_consts(&pair.p, "_HAT");
            let code = step::implicit(
                name,
                stages,
                "Full",
                true,
                quote!(::integrator_core::Hamiltonian),
            );
            ("prk", quote!(#q #p), code, 2 * stages, false)
        }
    };
    // Of the generated families only the one-stage Gauss table (A = (1/2),
    // b = (1): the midpoint rule itself) has the shape of a composition of
    // midpoint steps; every other one has a full A (Gauss, Radau, Lobatto
    // IIIC), a zero first row (IIIA) or a zero last column (IIIB). An exact
    // fact of the families, not a floating-point test.
    let midpoint_weights = (g.generator == Generator::Rk(Family::Gauss, 1)).then(|| vec![1.0]);
    let facts: Vec<String> = g.claims.iter().map(|(c, _)| format!("`{c}`")).collect();
    let summary = format!(
        "*{}* — generated (`{}`) and verified exactly at compile time: {}; order proof: {}. Source: {}.",
        g.name,
        g.generator.expression(),
        facts.join(", "),
        g.order.text,
        g.source
    );
    let facts = Facts {
        name: g.name.clone(),
        form,
        stages,
        order: g.proven_order(),
        order_doc: "The order proven exactly (the type's doc names the proof).",
        symplectic: g.symplectic,
        symplectic_separable: g.symplectic,
        separable_only,
        symmetric: g.symmetric,
        // Never, for a collocation-type table.
        explicit: false,
        class: "implicit",
        evaluations,
        midpoint_weights,
        summary,
    };
    emit(input, &facts, coefficients, step_code)
}
