//! The one emitter of a scheme's items: whichever path verified the table
//! (the `Table` path of [`crate::expand`], a generated table of
//! [`crate::generated`], a table with `root(...)` entries of
//! [`crate::roots`]), it states what was proven as one [`Facts`], and
//! [`emit`] writes the same items from it: the zero-sized type with its
//! doc line, `Scheme::INFO`, the step code, and the constants (facts and
//! coefficients as correctly rounded `f64`).

use proc_macro2::TokenStream;
use quote::quote;
use tableau::Number;
use tableau::rounding::{F64Splitting, F64Table};

use crate::ast::Input;

/// What a path proved about a table, as the scheme states it (`INFO` and
/// the constants of the same names).
pub struct Facts {
    /// The table's name (`NAME`, `INFO.name`).
    pub name: String,
    /// `"rk"`, `"prk"`, `"drift-kick"` or `"composition"`.
    pub form: &'static str,
    pub stages: usize,
    pub order: usize,
    /// What `ORDER` means for this path (how it was proven, what is not
    /// decided).
    pub order_doc: &'static str,
    pub symplectic: bool,
    pub symplectic_separable: bool,
    pub separable_only: bool,
    pub symmetric: bool,
    pub explicit: bool,
    /// `"explicit"`, `"sdirk"`, `"dirk"` or `"implicit"`.
    pub class: &'static str,
    /// Right-hand-side evaluations per step.
    pub evaluations: usize,
    /// `Some(b)` for a composition of implicit midpoint steps, `b` as rounded
    /// for stepping (`Info::midpoint_weights`).
    pub midpoint_weights: Option<Vec<f64>>,
    /// The type's doc line: what was verified, and the source where known.
    pub summary: String,
}

/// The scheme type: `facts` as `INFO` and constants, `coefficients` (the
/// path's coefficient constants) and `step_code` (its `Step` impls).
pub fn emit(
    input: &Input,
    facts: &Facts,
    coefficients: TokenStream,
    step_code: TokenStream,
) -> TokenStream {
    let Input {
        attrs, vis, name, ..
    } = input;
    let Facts {
        name: title,
        form,
        stages,
        order,
        order_doc,
        symplectic,
        symplectic_separable,
        separable_only,
        symmetric,
        explicit,
        class,
        evaluations,
        midpoint_weights,
        summary,
    } = facts;
    let midpoint_weights = match midpoint_weights {
        Some(b) => {
            let b = lit(b);
            quote!(::core::option::Option::Some(&#b))
        }
        None => quote!(::core::option::Option::None),
    };
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

        #step_code

        // The constants are the doubles nearest to exact values; a few
        // (e.g. sqrt(2)/2) coincide with std's constants, which clippy flags.
        #[allow(clippy::approx_constant, clippy::excessive_precision)]
        impl #name {
            /// The table's name.
            pub const NAME: &'static str = #title;
            /// `"rk"`, `"prk"` (a partitioned pair: `a_hat`, `b_hat`),
            /// `"drift-kick"` or `"composition"`.
            pub const FORM: &'static str = #form;
            /// Stages of the (partitioned) Runge–Kutta form.
            pub const STAGES: usize = #stages;
            #[doc = #order_doc]
            pub const ORDER: usize = #order;
            /// Symplectic for every Hamiltonian (W = 0; for a pair, the pair
            /// condition and b = b̂), proven exactly.
            pub const SYMPLECTIC: bool = #symplectic;
            /// Symplectic for separable Hamiltonians (for a pair, the pair
            /// condition), proven exactly.
            pub const SYMPLECTIC_SEPARABLE: bool = #symplectic_separable;
            /// Steps separable systems only (symplectic only for them).
            pub const SEPARABLE_ONLY: bool = #separable_only;
            /// Its own adjoint, proven exactly (`false` where symmetry is not
            /// decided: tables with `root(...)` entries).
            pub const SYMMETRIC: bool = #symmetric;
            /// Explicit (on separable systems for a pair), decided exactly.
            pub const EXPLICIT: bool = #explicit;
            /// `"explicit"`, `"sdirk"`, `"dirk"` or `"implicit"`, decided exactly.
            pub const CLASS: &'static str = #class;
            #coefficients
        }
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

pub fn lit(v: &[f64]) -> TokenStream {
    quote!([#(#v),*])
}

fn lit_mat(a: &[Vec<f64>]) -> TokenStream {
    let rows = a.iter().map(|r| lit(r));
    quote!([#(#rows),*])
}

/// `A`, `B`, `C` (with `suffix`: `A_HAT`, … for a pair's `p` table).
pub fn rk_consts(t: &F64Table, suffix: &str) -> TokenStream {
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

/// `DRIFT` and `KICK`.
pub fn split_consts(s: &F64Splitting) -> TokenStream {
    let (nd, nk) = (s.drift.len(), s.kick.len());
    let (d, k) = (lit(&s.drift), lit(&s.kick));
    quote! {
        /// Drift coefficients (within one ulp, summing to 1.0).
        pub const DRIFT: [f64; #nd] = #d;
        /// Kick coefficients (within one ulp, summing to 1.0).
        pub const KICK: [f64; #nk] = #k;
    }
}

/// `R(z) = P(z)/Q(z)`, coefficients from the constant term up, each the
/// nearest double to the exact coefficient: what the linear model needs to
/// form the one-step propagator `R(hH)`.
pub fn stability_tokens(r: &tableau::analysis::stability::StabilityFunction) -> TokenStream {
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
