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
use tableau::rounding::{F64Rounded, F64Splitting, F64Table, round_table, round_weights};
use tableau::table::Op;
use tableau::{Number, Splitting, Table};

use crate::ast::Input;
use crate::step;
use crate::valid::Verified;

fn lit(v: &[f64]) -> TokenStream {
    quote!([#(#v),*])
}

fn lit_mat(a: &[Vec<f64>]) -> TokenStream {
    let rows = a.iter().map(|r| lit(r));
    quote!([#(#rows),*])
}

pub(crate) fn rk_consts(t: &F64Table, suffix: &str) -> TokenStream {
    let s = t.b.len();
    let a_name = quote::format_ident!("A{}", suffix);
    let b_name = quote::format_ident!("B{}", suffix);
    let c_name = quote::format_ident!("C{}", suffix);
    let (a, b, c) = (lit_mat(&t.a), lit(&t.b), lit(&t.c));
    quote! {
        /// The coefficient matrix: each entry within one ulp of the exact value,
        /// chosen to keep the symplecticity defect as small as rounding allows.
        pub const #a_name: [[f64; #s]; #s] = #a;
        /// The weights, within one ulp of the exact values and summing to 1.0
        /// in floating point (left to right) where that is possible.
        pub const #b_name: [f64; #s] = #b;
        /// The abscissae (the given `c`, else the row sums), correctly rounded.
        pub const #c_name: [f64; #s] = #c;
    }
}

pub fn expand(input: &Input, v: &Verified) -> TokenStream {
    let Input {
        attrs, vis, name, ..
    } = input;
    let a = &v.analysis;
    let stages = a.stages;
    let order = v
        .claims
        .iter()
        .find_map(|c| match c {
            tableau::claims::Claim::Order { p, .. } => Some(*p),
            _ => None,
        })
        .unwrap_or(a.claimed_order_report().order);
    let (symplectic, symplectic_separable, symmetric) =
        (a.symplectic, a.symplectic_separable, a.symmetric);
    let explicit = a.explicit_separable;
    let class = a.class.name();
    let separable_only = a.separable_only();
    let title = &v.name;
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
    };
    let (step_impl, evaluations) = step_code(name, v, &rounded);
    let summary = summary(v);
    let midpoint_weights = midpoint_weights(v, &rounded);
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
                symplectic_separable: #symplectic_separable,
                separable_only: #separable_only,
                symmetric: #symmetric,
                explicit: #explicit,
                class: #class,
                evaluations: #evaluations,
                midpoint_weights: #midpoint_weights,
            };
        }

        #step_impl

        // The constants are the doubles nearest to exact values; a few
        // (e.g. sqrt(2)/2) coincide with std's constants, which clippy flags.
        #[allow(clippy::approx_constant, clippy::excessive_precision)]
        impl #name {
            /// The table's name.
            pub const NAME: &'static str = #title;
            /// `"rk"`, `"prk"`, `"drift-kick"` or `"composition"`.
            pub const FORM: &'static str = #form;
            /// Stages of the (partitioned) Runge–Kutta form.
            pub const STAGES: usize = #stages;
            /// The verified order (the claimed order where one is claimed).
            pub const ORDER: usize = #order;
            /// Symplectic for every Hamiltonian, proven exactly.
            pub const SYMPLECTIC: bool = #symplectic;
            /// Symplectic for separable Hamiltonians, proven exactly.
            pub const SYMPLECTIC_SEPARABLE: bool = #symplectic_separable;
            /// Steps separable systems only (symplectic only for them).
            pub const SEPARABLE_ONLY: bool = #separable_only;
            /// Its own adjoint, proven exactly.
            pub const SYMMETRIC: bool = #symmetric;
            /// Explicit (on separable systems for a pair).
            pub const EXPLICIT: bool = #explicit;
            /// `"explicit"`, `"sdirk"`, `"dirk"` or `"implicit"`.
            pub const CLASS: &'static str = #class;
            #coefficients
        }
    }
}

fn split_consts(s: &F64Splitting) -> TokenStream {
    let (nd, nk) = (s.drift.len(), s.kick.len());
    let (d, k) = (lit(&s.drift), lit(&s.kick));
    quote! {
        /// Drift coefficients (within one ulp, summing to 1.0).
        pub const DRIFT: [f64; #nd] = #d;
        /// Kick coefficients (within one ulp, summing to 1.0).
        pub const KICK: [f64; #nk] = #k;
    }
}

/// On error: the errors, plus the type itself so that uses of it do not add
/// a cascade of unrelated errors.
pub fn stub(input: &Input, err: syn::Error) -> TokenStream {
    let Input {
        attrs, vis, name, ..
    } = input;
    let errors = err.to_compile_error();
    quote! {
        #errors
        #(#attrs)*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        #vis struct #name;
    }
}

/// The `Step` impl for the table's structure, and its evaluations per step.
fn step_code(name: &syn::Ident, v: &Verified, rounded: &F64Rounded) -> (TokenStream, usize) {
    let symmetric = v.analysis.symmetric;
    let drift_kick = |s: &Splitting| {
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
        let ops: Vec<(Op, f64)> = nf
            .iter()
            .map(|(op, _)| {
                let x = match op {
                    Op::Drift => drift.next(),
                    Op::Kick => kick.next(),
                };
                (*op, x.expect("one value per operation"))
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

/// The solver's name for a class of implicit table.
/// `Some(&[b…])` when the exact table is a composition of implicit midpoint
/// steps ([`tableau::midpoint::composition_weights`], exact equality of the
/// entries), with the weights as rounded for stepping; `None` otherwise.
fn midpoint_weights(v: &Verified, rounded: &F64Rounded) -> TokenStream {
    match (&v.table, rounded) {
        (Table::Rk(rk), F64Rounded::Rk(t))
            if tableau::midpoint::composition_weights(rk).is_some() =>
        {
            let b = lit(&t.b);
            quote!(::core::option::Option::Some(&#b))
        }
        _ => quote!(::core::option::Option::None),
    }
}

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

/// The constants of an exact stability function (also for generated tables).
pub(crate) fn stability_tokens(r: &tableau::analysis::stability::StabilityFunction) -> TokenStream {
    let to_f64 = |p: &[Number]| -> Vec<f64> { p.iter().map(Number::to_f64).collect() };
    let (p, q) = (lit(&to_f64(&r.numerator.0)), lit(&to_f64(&r.denominator.0)));
    let (np, nq) = (r.numerator.0.len(), r.denominator.0.len());
    let text = r.to_text();
    quote! {
        /// Numerator `P` of the stability function `R(z) = P(z)/Q(z)`, constant term first.
        pub const STABILITY_P: [f64; #np] = #p;
        /// Denominator `Q` of the stability function, constant term first (`Q(0) = 1`).
        pub const STABILITY_Q: [f64; #nq] = #q;
        /// The stability function, exactly.
        pub const STABILITY: &'static str = #text;
    }
}
