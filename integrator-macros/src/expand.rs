//! Expansion: a zero-sized scheme type with the verified facts and the
//! coefficients as correctly rounded `f64` constants.
//!
//! Step code is emitted against the traits of `integrator-core` (see
//! [`crate::step`]): explicit tables unrolled, drift–kick sequences and
//! explicit pairs as kick/drift code for separable systems. Implicit tables
//! are verified and carry their constants, but get no `Step` impl until the
//! stage solver exists; stepping one is a compile error that says so.

use proc_macro2::TokenStream;
use quote::quote;
use tableau::analysis::{Class, Form, class::separable_stage_order};
use tableau::{Number, Rk, Table};

use crate::ast::Input;
use crate::step;
use crate::valid::Verified;

fn f64s(v: &[Number]) -> TokenStream {
    let xs = v.iter().map(|x| {
        let f = x.to_f64();
        quote!(#f)
    });
    quote!([#(#xs),*])
}

fn mat(a: &[Vec<Number>]) -> TokenStream {
    let rows = a.iter().map(|r| f64s(r));
    quote!([#(#rows),*])
}

fn rk_consts(rk: &Rk, suffix: &str) -> TokenStream {
    let s = rk.stages();
    let a_name = quote::format_ident!("A{}", suffix);
    let b_name = quote::format_ident!("B{}", suffix);
    let c_name = quote::format_ident!("C{}", suffix);
    let (a, b, c) = (mat(&rk.a), f64s(&rk.b), f64s(&rk.abscissae()));
    quote! {
        /// The coefficient matrix, each entry the `f64` nearest to the exact value.
        pub const #a_name: [[f64; #s]; #s] = #a;
        /// The weights, correctly rounded.
        pub const #b_name: [f64; #s] = #b;
        /// The abscissae (the given `c`, else the row sums), correctly rounded.
        pub const #c_name: [f64; #s] = #c;
    }
}

pub fn expand(input: &Input, v: &Verified) -> TokenStream {
    let Input { attrs, vis, name, .. } = input;
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
    let (symplectic, symplectic_separable, symmetric) = (a.symplectic, a.symplectic_separable, a.symmetric);
    let explicit = a.explicit_separable;
    let class = a.class.name();
    let separable_only = a.separable_only();
    let title = &v.name;
    let coefficients = match &v.table {
        Table::Rk(rk) => {
            let consts = rk_consts(rk, "");
            let stab = stability_consts(v);
            quote!(#consts #stab)
        }
        Table::Prk(prk) => {
            let q = rk_consts(&prk.q, "");
            let p = rk_consts(&prk.p, "_HAT");
            quote!(#q #p)
        }
        Table::Splitting(s) => split_consts(&s.drift, &s.kick),
        Table::Composition(c) => {
            let s = c.to_splitting();
            let g = f64s(&c.gamma);
            let m = c.gamma.len();
            let sc = split_consts(&s.drift, &s.kick);
            quote! {
                /// The composition coefficients γ, correctly rounded.
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
    let (step_impl, evaluations) = step_code(name, v);
    let summary = summary(v);
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

fn split_consts(drift: &[Number], kick: &[Number]) -> TokenStream {
    let (nd, nk) = (drift.len(), kick.len());
    let (d, k) = (f64s(drift), f64s(kick));
    quote! {
        /// Drift coefficients, correctly rounded.
        pub const DRIFT: [f64; #nd] = #d;
        /// Kick coefficients, correctly rounded.
        pub const KICK: [f64; #nk] = #k;
    }
}

/// On error: the errors, plus the type itself so that uses of it do not add
/// a cascade of unrelated errors.
pub fn stub(input: &Input, err: syn::Error) -> TokenStream {
    let Input { attrs, vis, name, .. } = input;
    let errors = err.to_compile_error();
    quote! {
        #errors
        #(#attrs)*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        #vis struct #name;
    }
}

fn f64_vec(v: &[Number]) -> Vec<f64> {
    v.iter().map(Number::to_f64).collect()
}

fn f64_mat(a: &[Vec<Number>]) -> Vec<Vec<f64>> {
    a.iter().map(|r| f64_vec(r)).collect()
}

/// The `Step` impl for the table's structure, and its evaluations per step.
fn step_code(name: &syn::Ident, v: &Verified) -> (TokenStream, usize) {
    let drift_kick = |s: &tableau::Splitting| {
        let ops: Vec<(tableau::table::Op, f64)> = s.normal_form().into_iter().map(|(op, x)| (op, x.to_f64())).collect();
        (step::drift_kick(name, &ops), ops.len())
    };
    match &v.table {
        Table::Rk(rk) if v.analysis.class == Class::Explicit => {
            let c = f64_vec(&rk.abscissae());
            (step::explicit_rk(name, &f64_mat(&rk.a), &f64_vec(&rk.b), &c), rk.stages())
        }
        Table::Splitting(s) => drift_kick(s),
        Table::Composition(c) => drift_kick(&c.to_splitting()),
        Table::Prk(prk) => match separable_stage_order(&prk.q, &prk.p) {
            Some(order) => {
                let code = step::explicit_prk(
                    name,
                    &f64_mat(&prk.q.a),
                    &f64_vec(&prk.q.b),
                    &f64_mat(&prk.p.a),
                    &f64_vec(&prk.p.b),
                    &order,
                );
                (code, 2 * prk.q.stages())
            }
            None => (TokenStream::new(), 2 * prk.q.stages()),
        },
        Table::Rk(rk) => (TokenStream::new(), rk.stages()),
    }
}

/// A doc line stating what was proven, and the source where known.
fn summary(v: &Verified) -> String {
    let mut facts: Vec<String> = v.claims.iter().map(|c| format!("`{c}`")).collect();
    if facts.is_empty() {
        facts.push("no claims".into());
    }
    let mut s = format!("*{}* — verified exactly at compile time: {}.", v.name, facts.join(", "));
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
    let Some(r) = &v.analysis.stability else {
        return TokenStream::new();
    };
    let (p, q) = (f64s(&r.numerator.0), f64s(&r.denominator.0));
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
