//! Expansion: a zero-sized scheme type with the verified facts and the
//! coefficients as `f64` constants chosen by [`tableau::rounding`]: each
//! within one ulp of its exact value, weights summing to 1.0 in floating
//! point, and for symplectic tables the symplecticity defect as small as
//! rounding allows.
//!
//! Step code is emitted against the traits of `integrator-core` (see
//! [`crate::step`]): explicit tables unrolled, drift–kick sequences and
//! explicit pairs as kick/drift code for separable systems, implicit tables
//! as calls of the stage solver with the table as a constant.

use proc_macro2::TokenStream;
use quote::quote;
use tableau::analysis::{Class, Form, class::separable_stage_order};
use tableau::rounding::{F64Rounded, round_table, round_weights};
use tableau::table::Op;
use tableau::{Number, Splitting, Table};

use crate::ast::Input;
use crate::emit::{Facts, emit, lit, rk_consts, split_consts, stability_tokens};
use crate::step;
use crate::valid::Verified;

/// The scheme type of a verified table.
pub fn expand(input: &Input, v: &Verified) -> TokenStream {
    let a = &v.analysis;
    // A processed method's order claims are its effective method's; its
    // `Step` is the kernel's, whose own order `ORDER` states.
    let order = v
        .claims
        .iter()
        .find_map(|c| match c {
            // A certified order is the order of the exact method within the
            // certificate's radius of these coefficients.
            tableau::claims::Claim::Order { p, .. }
            | tableau::claims::Claim::CertifiedOrder { p }
                if v.corrector.is_none() =>
            {
                Some(*p)
            }
            _ => None,
        })
        .unwrap_or(a.claimed_order_report().order);
    let rounded = round_table(&v.table, a);
    let coefficients = match &rounded {
        F64Rounded::Rk(t) => {
            let consts = rk_consts(t, "");
            let stab = stability_consts(v);
            quote!(#consts #stab)
        }
        F64Rounded::Prk(pair) => {
            let q = rk_consts(&pair.q, "");
            let p = rk_consts(&pair.p, "_HAT");
            quote!(#q #p)
        }
        F64Rounded::Splitting(s) => split_consts(s),
        F64Rounded::Composition(c) => {
            let g = lit(&c.gamma);
            let m = c.gamma.len();
            let sc = split_consts(&c.splitting);
            quote! {
                /// The composition coefficients γ (within one ulp, summing to 1.0).
                pub const GAMMA: [f64; #m] = #g;
                #sc
            }
        }
    };
    let form = match a.form {
        Form::Rk => "rk",
        Form::Prk => "prk",
        Form::DriftKick => "drift-kick",
        Form::Composition => "composition",
        Form::GradientDriftKick => "gradient-drift-kick",
    };
    let coefficients = match &v.corrector {
        Some(chi) => {
            let extra = corrector_items(v, chi);
            quote!(#coefficients #extra)
        }
        None => coefficients,
    };
    let (step_impl, evaluations) = step_code(&input.name, v, &rounded);
    let facts = Facts {
        name: v.name.clone(),
        form,
        stages: a.stages,
        order,
        order_doc: "The verified order (the claimed order where one is claimed).",
        symplectic: a.symplectic,
        symplectic_separable: a.symplectic_separable,
        separable_only: a.separable_only(),
        symmetric: a.symmetric,
        explicit: a.explicit_separable,
        class: a.class.name(),
        evaluations,
        midpoint_weights: midpoint_weights(v, &rounded),
        summary: summary(v),
    };
    emit(input, &facts, coefficients, step_impl)
}

/// The `Step` impl for the table's structure, and its evaluations per step.
fn step_code(name: &syn::Ident, v: &Verified, rounded: &F64Rounded) -> (TokenStream, usize) {
    let symmetric = v.analysis.symmetric;
    let drift_kick = |s: &Splitting| {
        if s.has_gradient() {
            // The flows as written (zeros dropped, plain neighbours merged
            // exactly, a gradient kick never merged), each coefficient and
            // gradient the nearest double: `Sequence::from_splitting`'s.
            let ops: Vec<(Op, f64, f64)> = s
                .flows()
                .into_iter()
                .map(|(op, x, g)| (op, x.to_f64(), g.to_f64()))
                .collect();
            return (step::drift_kick(name, &ops), ops.len());
        }
        // The normal form (zeros dropped, neighbours merged), its drift and
        // kick values rounded as weight vectors in their own right.
        let nf = s.normal_form();
        let values = |op: Op| -> Vec<Number> {
            nf.iter()
                .filter(|o| o.0 == op)
                .map(|o| o.1.clone())
                .collect()
        };
        let mut drift = round_weights(&values(Op::Drift), symmetric).into_iter();
        let mut kick = round_weights(&values(Op::Kick), symmetric).into_iter();
        let ops: Vec<(Op, f64, f64)> = nf
            .iter()
            .map(|(op, _)| {
                let x = match op {
                    Op::Drift => drift.next(),
                    Op::Kick => kick.next(),
                };
                (*op, x.expect("one value per operation"), 0.0)
            })
            .collect();
        (step::drift_kick(name, &ops), ops.len())
    };
    match (&v.table, rounded) {
        (Table::Rk(_), F64Rounded::Rk(t)) if v.analysis.class == Class::Explicit => {
            (step::explicit_rk(name, &t.a, &t.b, &t.c), t.b.len())
        }
        (Table::Splitting(s), _) => drift_kick(s),
        (Table::Composition(c), _) => drift_kick(&c.to_splitting()),
        (Table::Prk(prk), F64Rounded::Prk(pair)) => match separable_stage_order(&prk.q, &prk.p) {
            Some(order) => {
                let code =
                    step::explicit_prk(name, &pair.q.a, &pair.q.b, &pair.p.a, &pair.p.b, &order);
                (code, 2 * prk.q.stages())
            }
            None => {
                let bound = if v.analysis.separable_only() {
                    quote!(::integrator_core::Separable)
                } else {
                    quote!(::integrator_core::Hamiltonian)
                };
                let s = prk.q.stages();
                (
                    step::implicit(name, s, structure(v.analysis.class), true, bound),
                    2 * s,
                )
            }
        },
        (Table::Rk(rk), _) => {
            let s = rk.stages();
            let bound = quote!(::integrator_core::OdeSystem);
            (
                step::implicit(name, s, structure(v.analysis.class), false, bound),
                s,
            )
        }
        _ => unreachable!("the rounded form matches the table's form"),
    }
}

/// The items of a processed method: the corrector `χ` as the flows in the
/// order applied (each coefficient the double nearest its exact value, the
/// normal form merged exactly first), the claimed effective generalised
/// order, and `processed()`, the scheme with its corrector for
/// `integrator_core::processed`.
fn corrector_items(v: &Verified, chi: &Splitting) -> TokenStream {
    let flows = chi.normal_form().into_iter().map(|(op, x)| {
        let x = x.to_f64();
        match op {
            Op::Drift => quote!((::integrator_core::Part::A, #x)),
            Op::Kick => quote!((::integrator_core::Part::B, #x)),
        }
    });
    let effective: Vec<usize> = v
        .claims
        .iter()
        .find_map(|c| match c {
            tableau::claims::Claim::NearOrder { orders, .. } => Some(orders.clone()),
            _ => None,
        })
        .unwrap_or_default();
    quote! {
        /// The corrector χ, applied at output only (χ⁻¹ once on entry): its
        /// flows in the order applied (`A` a drift, `B` a kick) with their
        /// coefficients, each the double nearest its exact value.
        pub const CORRECTOR: &'static [(::integrator_core::Part, f64)] = &[#(#flows),*];
        /// The effective generalised order `(p₁, p₂, …)` of χ K χ⁻¹ claimed
        /// and proven at compile time (empty when none is claimed); `ORDER`
        /// is the kernel's own.
        pub const EFFECTIVE_ORDER: &'static [usize] = &[#(#effective),*];
        /// This kernel with its corrector, stepped as χ Kⁿ χ⁻¹ by
        /// `integrator_core::processed`.
        pub fn processed(self) -> ::integrator_core::processed::Processed<Self> {
            ::integrator_core::processed::Processed::new(
                self,
                ::integrator_core::sequence::Sequence::new(Self::CORRECTOR.iter().copied()),
            )
        }
    }
}

/// `Some(b)` when the exact table is a composition of implicit midpoint
/// steps ([`tableau::midpoint::composition_weights`], exact equality of the
/// entries), with the weights as rounded for stepping; `None` otherwise.
fn midpoint_weights(v: &Verified, rounded: &F64Rounded) -> Option<Vec<f64>> {
    match (&v.table, rounded) {
        (Table::Rk(rk), F64Rounded::Rk(t))
            if tableau::midpoint::composition_weights(rk).is_some() =>
        {
            Some(t.b.clone())
        }
        _ => None,
    }
}

/// The solver's name for a class of implicit table.
fn structure(class: Class) -> &'static str {
    match class {
        Class::Sdirk => "Sdirk",
        Class::Dirk => "Dirk",
        Class::Explicit | Class::Implicit => "Full",
    }
}

/// A doc line stating what was proven, and the source where known.
fn summary(v: &Verified) -> String {
    let mut facts: Vec<String> = v.claims.iter().map(|c| format!("`{c}`")).collect();
    if facts.is_empty() {
        facts.push("no claims".into());
    }
    let mut s = format!(
        "*{}* — verified exactly at compile time: {}.",
        v.name,
        facts.join(", ")
    );
    if v.corrector.is_some() {
        s.push_str(" A processed method: the kernel steps, the corrector `CORRECTOR` is applied at output only (`processed()`); the order claims are the effective method's.");
    }
    if v.analysis.separable_only() {
        s.push_str(" Steps separable Hamiltonians only.");
    }
    if let Some(src) = &v.source {
        s.push_str(&format!(" Source: {src}."));
    }
    s
}

/// `R(z) = P(z)/Q(z)`, coefficients from the constant term up, each the
/// nearest double to the exact coefficient: what the linear model needs to
/// form the one-step propagator `R(hH)`.
fn stability_consts(v: &Verified) -> TokenStream {
    v.analysis
        .stability
        .as_ref()
        .map(stability_tokens)
        .unwrap_or_default()
}
