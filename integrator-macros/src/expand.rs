//! Expansion: a zero-sized scheme type with the verified facts and the
//! coefficients as correctly rounded `f64` constants.
//!
//! Step code (explicit tables unrolled, kick/drift sequences, calls of the
//! stage solver) is emitted against the traits of `integrator-core`; that
//! part lands with the scheme traits.

use proc_macro2::TokenStream;
use quote::quote;
use tableau::analysis::Form;
use tableau::{Number, Rk, Table};

use crate::ast::Input;
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
        Table::Rk(rk) => rk_consts(rk, ""),
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
    quote! {
        #(#attrs)*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        #vis struct #name;

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
