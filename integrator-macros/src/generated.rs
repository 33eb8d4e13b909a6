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
//! small as `f64` allows). Validation and expansion mirror the `Table`
//! path: claims (the invocation's, else the literature's) checked with
//! errors on their tokens, then a scheme stepped by the stage solver.

use proc_macro2::{Span, TokenStream};
use quote::quote;
use syn::Error;
use tableau::algebraic::family::{Family, Generator};
use tableau::algebraic::generated::{Generated, GeneratedTable, literature_claims};
use tableau::claims::parse_claim;

use crate::ast::{Input, Value};
use crate::expand::{rk_consts, stability_tokens};
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
    let mut errs: Option<Error> = None;
    fn push(errs: &mut Option<Error>, span: Span, msg: String) {
        let e = Error::new(span, msg);
        match errs {
            Some(all) => all.combine(e),
            None => *errs = Some(e),
        }
    }
    if !input.lets.is_empty() {
        push(
            &mut errs,
            input.lets[0].name.span(),
            "a generated table takes no `let` bindings".into(),
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
                        Err(m) => push(&mut errs, item.span(), m),
                    }
                }
            }
            ("claims", v) => push(
                &mut errs,
                v.span(),
                "claims are a list: `claims: [symplectic, order = 16]`".into(),
            ),
            (k, _) => push(
                &mut errs,
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
            push(&mut errs, *span, e.to_string());
        }
    }
    match errs {
        Some(e) => Err(e),
        None => Ok(g),
    }
}

/// The scheme type of a generated table: the same items as the `Table`
/// path's (facts, coefficients, stability function, stage-solver step).
pub fn expand(input: &Input, g: &Generated) -> TokenStream {
    let Input {
        attrs, vis, name, ..
    } = input;
    let stages = g.stages;
    let order = g.proven_order();
    let symplectic = g.symplectic;
    let symmetric = g.symmetric;
    let title = &g.name;
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
    let midpoint_weights = if g.generator == Generator::Rk(Family::Gauss, 1) {
        quote!(::core::option::Option::Some(&[1.0]))
    } else {
        quote!(::core::option::Option::None)
    };
    let facts: Vec<String> = g.claims.iter().map(|(c, _)| format!("`{c}`")).collect();
    let summary = format!(
        "*{title}* — generated (`{}`) and verified exactly at compile time: {}; order proof: {}. Source: {}.",
        g.generator.expression(),
        facts.join(", "),
        g.order.text,
        g.source
    );
    quote! {
        #(#attrs)*
        #[doc = ""]
        #[doc = #summary]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        #vis struct #name;

        impl ::integrator_core::Scheme for #name {
            const INFO: ::integrator_core::Info = ::integrator_core::Info {
                name: #title,
                form: #form,
                stages: #stages,
                order: #order,
                symplectic: #symplectic,
                symplectic_separable: #symplectic,
                separable_only: #separable_only,
                symmetric: #symmetric,
                explicit: false,
                class: "implicit",
                evaluations: #evaluations,
                midpoint_weights: #midpoint_weights,
            };
        }

        #step_code

        #[allow(clippy::approx_constant, clippy::excessive_precision)]
        impl #name {
            /// The table's name.
            pub const NAME: &'static str = #title;
            /// `"rk"` or `"prk"`.
            pub const FORM: &'static str = #form;
            /// Stages.
            pub const STAGES: usize = #stages;
            /// The proven order.
            pub const ORDER: usize = #order;
            /// Symplectic, proven exactly.
            pub const SYMPLECTIC: bool = #symplectic;
            /// Symplectic for separable Hamiltonians, proven exactly.
            pub const SYMPLECTIC_SEPARABLE: bool = #symplectic;
            /// Steps separable systems only.
            pub const SEPARABLE_ONLY: bool = #separable_only;
            /// Its own adjoint, proven exactly.
            pub const SYMMETRIC: bool = #symmetric;
            /// Explicit: never, for a collocation-type table.
            pub const EXPLICIT: bool = false;
            /// `"implicit"`.
            pub const CLASS: &'static str = "implicit";
            #coefficients
        }
    }
}
