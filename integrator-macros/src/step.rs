//! The step code `butcher!` emits, specialised to one table: the
//! coefficients are literals, zero coefficients are skipped, `h·aᵢⱼ` is
//! hoisted out of the loops, every loop runs over slices cut to the system
//! size up front so that bounds checks vanish.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use tableau::table::Op;

/// One stage-vector update `dst[i] = base[i] + Σ (h·cⱼ)·srcⱼ[i]`, written
/// as a loop over slices of length `n`.
fn axpy_loop(
    dst: TokenStream,
    base: Option<TokenStream>,
    terms: &[(f64, TokenStream)],
) -> TokenStream {
    let hoist: Vec<TokenStream> = terms
        .iter()
        .enumerate()
        .map(|(j, (c, _))| {
            let hc = format_ident!("hc{}", j);
            quote!(let #hc: f64 = h * #c;)
        })
        .collect();
    let slices: Vec<TokenStream> = terms
        .iter()
        .enumerate()
        .map(|(j, (_, src))| {
            let s = format_ident!("s{}", j);
            quote!(let #s: &[f64] = &#src[..n];)
        })
        .collect();
    let sum = terms.iter().enumerate().map(|(j, _)| {
        let hc = format_ident!("hc{}", j);
        let s = format_ident!("s{}", j);
        quote!(+ #hc * #s[i])
    });
    let body = match base {
        Some(base) => quote! {
            let base: &[f64] = &#base[..n];
            for i in 0..n { d[i] = base[i] #(#sum)*; }
        },
        None => quote! {
            for i in 0..n { d[i] = d[i] #(#sum)*; }
        },
    };
    quote! {{
        #(#hoist)*
        #(#slices)*
        let d: &mut [f64] = &mut #dst[..n];
        #body
    }}
}

/// The update `dst[i] += Σ (h·cⱼ)·srcⱼ[i]` of the state itself, with
/// compensated (Kahan) summation into the vector `comp` when the workspace's
/// `compensated` flag is set: the increment is added with its rounding error
/// carried to the next update, so round-off in long runs grows like √n
/// (Brouwer's law) instead of n.
fn state_update(dst: TokenStream, comp: TokenStream, terms: &[(f64, TokenStream)]) -> TokenStream {
    let plain = axpy_loop(dst.clone(), None, terms);
    let hoist = terms.iter().enumerate().map(|(j, (c, _))| {
        let hc = format_ident!("hc{}", j);
        quote!(let #hc: f64 = h * #c;)
    });
    let slices = terms.iter().enumerate().map(|(j, (_, src))| {
        let s = format_ident!("s{}", j);
        quote!(let #s: &[f64] = &#src[..n];)
    });
    let sum = terms.iter().enumerate().map(|(j, _)| {
        let hc = format_ident!("hc{}", j);
        let s = format_ident!("s{}", j);
        quote!(+ #hc * #s[i])
    });
    quote! {
        if compensated {
            #(#hoist)*
            #(#slices)*
            let d: &mut [f64] = &mut #dst[..n];
            let e: &mut [f64] = &mut #comp[..n];
            for i in 0..n {
                let inc = e[i] #(#sum)*;
                let new = d[i] + inc;
                e[i] = (d[i] - new) + inc;
                d[i] = new;
            }
        } else #plain
    }
}

/// Nonzero `(coefficient, source)` terms of a row.
fn terms(row: &[f64], src: impl Fn(usize) -> TokenStream) -> Vec<(f64, TokenStream)> {
    row.iter()
        .enumerate()
        .filter(|(_, c)| **c != 0.0)
        .map(|(j, c)| (*c, src(j)))
        .collect()
}

/// An explicit Runge–Kutta step for any `OdeSystem`.
pub fn explicit_rk(name: &syn::Ident, a: &[Vec<f64>], b: &[f64], c: &[f64]) -> TokenStream {
    let s = b.len();
    let ks: Vec<_> = (0..s).map(|j| format_ident!("k{}", j)).collect();
    let mut stages = Vec::new();
    for i in 0..s {
        let ki = &ks[i];
        let t_i = if c[i] == 0.0 {
            quote!(t)
        } else {
            let ci = c[i];
            quote!(t + #ci * h)
        };
        let row = terms(&a[i][..i], |j| {
            let kj = &ks[j];
            quote!(#kj)
        });
        if row.is_empty() {
            stages.push(quote!(sys.rhs(#t_i, &z[..n], &mut #ki[..n]);));
        } else {
            let upd = axpy_loop(quote!(y), Some(quote!(z)), &row);
            stages.push(quote! {
                #upd
                sys.rhs(#t_i, &y[..n], &mut #ki[..n]);
            });
        }
    }
    let out = terms(b, |j| {
        let kj = &ks[j];
        quote!(#kj)
    });
    let update = state_update(quote!(z), quote!(e), &out);
    quote! {
        impl<Sys: ::integrator_core::OdeSystem + ?Sized, const N: usize> ::integrator_core::StepFixed<Sys, N> for #name {
            type Carry = ::integrator_core::fixed::RkCarry<N>;
            fn carry(&self, compensated: bool) -> Self::Carry {
                ::integrator_core::fixed::RkCarry::new(compensated)
            }
            // The same body as `Step::step`, on stack arrays of constant
            // length (see `integrator_core::fixed`).
            #[inline(always)]
            #[allow(unused_variables, unused_mut, clippy::all, clippy::approx_constant, clippy::excessive_precision)]
            fn step_fixed(&self, sys: &Sys, t: f64, h: f64, z: &mut [f64; N], carry: &mut Self::Carry, _reuse: bool) -> ::core::result::Result<(), ::integrator_core::SolveError> {
                debug_assert_eq!(sys.dim(), N, "a fixed-size state must have the system's dimension");
                let n: usize = N;
                let z: &mut [f64] = &mut z[..];
                let ::integrator_core::fixed::RkCarry { e, compensated } = carry;
                let compensated = *compensated;
                let mut k = [[0.0f64; N]; #s];
                let mut y = [0.0f64; N];
                let [#(#ks),*] = &mut k;
                #(#stages)*
                #update
                Ok(())
            }
        }
        impl<Sys: ::integrator_core::OdeSystem + ?Sized> ::integrator_core::Step<Sys> for #name {
            type Workspace = ::integrator_core::scheme::RkWorkspace<#s>;
            fn workspace(&self, sys: &Sys) -> Self::Workspace {
                ::integrator_core::scheme::RkWorkspace::new(sys.dim())
            }
            // Always inlined into the caller's loop: with the compensated
            // branch the body outgrew LLVM's `#[inline]` threshold, and an
            // out-of-line step keeps the state in memory (integrator-core/benches/steps.rs).
            #[inline(always)]
            #[allow(unused_variables, clippy::all, clippy::approx_constant, clippy::excessive_precision)]
            fn step(&self, sys: &Sys, t: f64, h: f64, z: &mut [f64], ws: &mut Self::Workspace) -> ::core::result::Result<(), ::integrator_core::SolveError> {
                let n = sys.dim();
                let z: &mut [f64] = &mut z[..n];
                let ::integrator_core::scheme::RkWorkspace { k, y, e, compensated } = ws;
                let compensated = *compensated;
                let [#(#ks),*] = k;
                #(#stages)*
                #update
                Ok(())
            }
        }
    }
}

/// A drift–kick sequence (normal form) for `Split` systems (every
/// `Separable` one among them): a drift is the flow of part `A`, a kick the
/// flow of part `B`, each for `h` times its coefficient, in the table's
/// order; the flows do the update (for a separable system, with compensated
/// summation, the arithmetic this step always had). When the sequence
/// starts and ends with the same kind of operation, the flow's evaluation
/// of the last one is still valid at the start of the next step and
/// `step_reusing` lets it reuse it (first same as last).
///
/// A kick with a nonzero gradient `g` (the third entry) is a gradient kick,
/// `Split::flow_b_gradient` for `h` times its coefficient with the bracket
/// weight `γ = g·h³`, as `integrator_core::sequence::Sequence` takes it;
/// a system without gradient kicks refuses it at run time, naming the
/// part. Its evaluation is never reused.
pub fn drift_kick(name: &syn::Ident, ops: &[(Op, f64, f64)]) -> TokenStream {
    let fsal = ops.len() > 1
        && ops.first().map(|o| o.0) == ops.last().map(|o| o.0)
        && ops.iter().all(|o| o.2 == 0.0);
    let code = ops.iter().enumerate().map(|(k, (op, c, g))| {
        let (part, eval, err) = match op {
            Op::Drift => (quote!(A), quote!(v), quote!(eq)),
            Op::Kick => (quote!(B), quote!(f), quote!(ep)),
        };
        if *g != 0.0 {
            return quote! {
                ::integrator_core::split::flow_gradient(
                    sys,
                    h * #c,
                    #g * h * h * h,
                    z,
                    ::integrator_core::split::PartBuffers { eval: &mut f[..], err: &mut ep[..], compensated },
                )?;
            };
        }
        let reuse = if k == 0 && fsal {
            quote!(reuse)
        } else {
            quote!(false)
        };
        quote! {
            ::integrator_core::split::flow(
                sys,
                ::integrator_core::split::Part::#part,
                h * #c,
                z,
                ::integrator_core::split::PartBuffers { eval: &mut #eval[..], err: &mut #err[..], compensated },
                #reuse,
            )?;
        }
    });
    let code: Vec<TokenStream> = code.collect();
    let reuse_arg = if fsal { quote!(reuse) } else { quote!(_reuse) };
    quote! {
        impl<Sys: ::integrator_core::split::Split + ?Sized, const N: usize> ::integrator_core::StepFixed<Sys, N> for #name {
            type Carry = ::integrator_core::fixed::SplitCarry<N>;
            fn carry(&self, compensated: bool) -> Self::Carry {
                ::integrator_core::fixed::SplitCarry::new(compensated)
            }
            // The same body as `Step::step_reusing`, on arrays of constant
            // length (see `integrator_core::fixed`).
            #[inline(always)]
            #[allow(unused_variables, clippy::all, clippy::approx_constant, clippy::excessive_precision)]
            fn step_fixed(&self, sys: &Sys, t: f64, h: f64, z: &mut [f64; N], carry: &mut Self::Carry, #reuse_arg: bool) -> ::core::result::Result<(), ::integrator_core::SolveError> {
                debug_assert_eq!(::integrator_core::split::StateSpace::state_len(sys), N, "a fixed-size state must have the system's dimension");
                let z: &mut [f64] = &mut z[..];
                let ::integrator_core::fixed::SplitCarry { v, f, eq, ep, compensated } = carry;
                let compensated = *compensated;
                #(#code)*
                Ok(())
            }
        }
        impl<Sys: ::integrator_core::split::Split + ?Sized> ::integrator_core::Step<Sys> for #name {
            type Workspace = ::integrator_core::scheme::SplitWorkspace;
            fn workspace(&self, sys: &Sys) -> Self::Workspace {
                ::integrator_core::scheme::SplitWorkspace::new(::integrator_core::split::Split::buffer_len(sys))
            }
            // Always inlined, as the Runge–Kutta step: out of line, the plain
            // leapfrog step ran 1.35× slower than the same loop by hand.
            #[inline(always)]
            fn step(&self, sys: &Sys, t: f64, h: f64, z: &mut [f64], ws: &mut Self::Workspace) -> ::core::result::Result<(), ::integrator_core::SolveError> {
                self.step_reusing(sys, t, h, z, ws, false)
            }
            #[inline(always)]
            #[allow(unused_variables, clippy::all, clippy::approx_constant, clippy::excessive_precision)]
            fn step_reusing(&self, sys: &Sys, t: f64, h: f64, z: &mut [f64], ws: &mut Self::Workspace, #reuse_arg: bool) -> ::core::result::Result<(), ::integrator_core::SolveError> {
                let len = ::integrator_core::split::StateSpace::state_len(sys);
                let z: &mut [f64] = &mut z[..len];
                let ::integrator_core::scheme::SplitWorkspace { v, f, eq, ep, compensated } = ws;
                let compensated = *compensated;
                #(#code)*
                Ok(())
            }
        }
    }
}

/// An explicit partitioned pair for `Separable` systems, stage by stage in
/// the order of the dependency graph (`Qᵢ` needs `f(Pⱼ)` where `aᵢⱼ ≠ 0`,
/// `Pᵢ` needs `g(Qⱼ)` where `âᵢⱼ ≠ 0`). Stages with identical rows share one
/// value and one evaluation.
///
/// First same as last: when one position stage is `Q = q` (a zero row) and
/// the last position stage computed is `Q = q_{n+1}` (its row equals `b`,
/// as in Lobatto IIIA–IIIB: Störmer–Verlet), the new `q` is computed in
/// place at that point (with compensated summation) and the force evaluated
/// there, at the very `q` the next step starts from; `step_reusing` then
/// skips the force at `Q = q`, so Störmer–Verlet costs one force per step.
/// (Rows are compared as the correctly rounded coefficients; two distinct
/// exact rows that round to the same doubles would differ below round-off.)
pub fn explicit_prk(
    name: &syn::Ident,
    a: &[Vec<f64>],
    b: &[f64],
    a_hat: &[Vec<f64>],
    b_hat: &[f64],
    order: &[usize],
) -> TokenStream {
    let s = b.len();
    // Canonical stage for identical rows.
    let alias = |m: &[Vec<f64>], i: usize| (0..=i).find(|&k| m[k] == m[i]).unwrap();
    let q_alias: Vec<usize> = (0..s).map(|i| alias(a, i)).collect();
    let p_alias: Vec<usize> = (0..s).map(|i| alias(a_hat, i)).collect();
    // Which evaluations are used: g(Qⱼ) where some âᵢⱼ or b̂ⱼ ≠ 0; f(Pⱼ) where aᵢⱼ or bⱼ ≠ 0.
    let g_needed: Vec<bool> = (0..s)
        .map(|j| {
            (0..s)
                .any(|k| q_alias[k] == j && (b_hat[k] != 0.0 || (0..s).any(|i| a_hat[i][k] != 0.0)))
        })
        .collect();
    let f_needed: Vec<bool> = (0..s)
        .map(|j| (0..s).any(|k| p_alias[k] == j && (b[k] != 0.0 || (0..s).any(|i| a[i][k] != 0.0))))
        .collect();
    // Merge coefficients of aliased stages.
    let merged = |row: &[f64], al: &[usize]| {
        let mut out = vec![0.0; s];
        for (k, c) in row.iter().enumerate() {
            out[al[k]] += c;
        }
        out
    };
    // First same as last (see above).
    let q_nodes: Vec<usize> = order
        .iter()
        .copied()
        .filter(|&i| i < s && q_alias[i] == i && g_needed[i])
        .collect();
    let b_merged = merged(b, &p_alias);
    let first = q_nodes
        .iter()
        .copied()
        .find(|&i| merged(&a[i], &p_alias).iter().all(|c| *c == 0.0));
    let last = q_nodes
        .last()
        .copied()
        .filter(|&i| Some(i) != first && merged(&a[i], &p_alias) == b_merged);
    let fsal = first.zip(last);
    let q_out = state_update(quote!(q), quote!(eq), &terms(&b_merged, |j| quote!(fv[#j])));
    let mut code = Vec::new();
    for &node in order {
        if node < s {
            let i = node;
            if q_alias[i] != i || !g_needed[i] {
                continue;
            }
            let row = terms(&merged(&a[i], &p_alias), |j| quote!(fv[#j]));
            if fsal.is_some_and(|(_, l)| l == i) {
                code.push(quote! { #q_out sys.force(q, &mut gf[#i][..n]); });
            } else if row.is_empty() && fsal.is_some_and(|(f, _)| f == i) {
                code.push(quote!(if !reuse { sys.force(q, &mut gf[#i][..n]); }));
            } else if row.is_empty() {
                code.push(quote!(sys.force(q, &mut gf[#i][..n]);));
            } else {
                let upd = axpy_loop(quote!(qs), Some(quote!(q)), &row);
                code.push(quote! { #upd sys.force(&qs[..n], &mut gf[#i][..n]); });
            }
        } else {
            let i = node - s;
            if p_alias[i] != i || !f_needed[i] {
                continue;
            }
            let row = terms(&merged(&a_hat[i], &q_alias), |j| quote!(gf[#j]));
            if row.is_empty() {
                code.push(quote!(sys.velocity(p, &mut fv[#i][..n]);));
            } else {
                let upd = axpy_loop(quote!(ps), Some(quote!(p)), &row);
                code.push(quote! { #upd sys.velocity(&ps[..n], &mut fv[#i][..n]); });
            }
        }
    }
    let p_out = state_update(
        quote!(p),
        quote!(ep),
        &terms(&merged(b_hat, &q_alias), |j| quote!(gf[#j])),
    );
    // With FSAL, q is already updated, and g(q_{n+1}) moves to the first
    // stage's slot for the next step (a swap of two vectors).
    let (q_out, keep) = match fsal {
        Some((f, l)) => (quote!(), quote!(gf.swap(#f, #l);)),
        None => (q_out, quote!()),
    };
    let reuse_arg = if fsal.is_some() {
        quote!(reuse)
    } else {
        quote!(_reuse)
    };
    quote! {
        impl<Sys: ::integrator_core::Separable + ?Sized, const N: usize> ::integrator_core::StepFixed<Sys, N> for #name {
            type Carry = ::integrator_core::fixed::PrkCarry<N, #s>;
            fn carry(&self, compensated: bool) -> Self::Carry {
                ::integrator_core::fixed::PrkCarry::new(compensated)
            }
            // The same body as `Step::step_reusing`, on arrays of constant
            // length (see `integrator_core::fixed`).
            #[inline(always)]
            #[allow(unused_variables, unused_mut, clippy::all, clippy::approx_constant, clippy::excessive_precision)]
            fn step_fixed(&self, sys: &Sys, t: f64, h: f64, z: &mut [f64; N], carry: &mut Self::Carry, #reuse_arg: bool) -> ::core::result::Result<(), ::integrator_core::SolveError> {
                debug_assert_eq!(2 * sys.dof(), N, "a fixed-size state must have the system's dimension");
                let n: usize = N / 2;
                let (q, p) = z.split_at_mut(n);
                let ::integrator_core::fixed::PrkCarry { fv, gf, q: qs, p: ps, eq, ep, compensated } = carry;
                let compensated = *compensated;
                #(#code)*
                #q_out
                #p_out
                #keep
                Ok(())
            }
        }
        impl<Sys: ::integrator_core::Separable + ?Sized> ::integrator_core::Step<Sys> for #name {
            type Workspace = ::integrator_core::scheme::PrkWorkspace<#s>;
            fn workspace(&self, sys: &Sys) -> Self::Workspace {
                ::integrator_core::scheme::PrkWorkspace::new(sys.dof())
            }
            #[inline]
            fn step(&self, sys: &Sys, t: f64, h: f64, z: &mut [f64], ws: &mut Self::Workspace) -> ::core::result::Result<(), ::integrator_core::SolveError> {
                self.step_reusing(sys, t, h, z, ws, false)
            }
            #[inline]
            #[allow(unused_variables, unused_mut, clippy::all, clippy::approx_constant, clippy::excessive_precision)]
            fn step_reusing(&self, sys: &Sys, t: f64, h: f64, z: &mut [f64], ws: &mut Self::Workspace, #reuse_arg: bool) -> ::core::result::Result<(), ::integrator_core::SolveError> {
                let n = sys.dof();
                let (q, p) = z.split_at_mut(n);
                let ::integrator_core::scheme::PrkWorkspace { fv, gf, q: qs, p: ps, eq, ep, compensated } = ws;
                let compensated = *compensated;
                #(#code)*
                #q_out
                #p_out
                #keep
                Ok(())
            }
        }
    }
}

/// An implicit table: the stage equations are solved by
/// `integrator_core::implicit::step` (simplified Newton with a faer LU, or
/// fixed-point iteration, down to round-off; DIRK tables stage by stage),
/// with the table as a constant. `bound` is the system trait: `OdeSystem`
/// for a Runge–Kutta table, `Hamiltonian` (or `Separable`) for a pair.
pub fn implicit(
    name: &syn::Ident,
    stages: usize,
    structure: &str,
    pair: bool,
    bound: TokenStream,
) -> TokenStream {
    let structure = format_ident!("{}", structure);
    let a_hat = if pair {
        quote!(::core::option::Option::Some((Self::A_HAT, Self::B_HAT)))
    } else {
        quote!(::core::option::Option::None)
    };
    quote! {
        impl #name {
            /// The table handed to the stage solver.
            pub const TABLE: ::integrator_core::implicit::ImplicitTable<#stages> =
                ::integrator_core::implicit::ImplicitTable {
                    a: Self::A,
                    b: Self::B,
                    c: Self::C,
                    a_hat: #a_hat,
                    structure: ::integrator_core::implicit::Structure::#structure,
                };
        }
        impl<Sys: #bound + ?Sized> ::integrator_core::Step<Sys> for #name {
            type Workspace = ::integrator_core::implicit::ImplicitWorkspace;
            fn workspace(&self, sys: &Sys) -> Self::Workspace {
                ::integrator_core::implicit::ImplicitWorkspace::new(::integrator_core::OdeSystem::dim(sys), #stages)
            }
            #[inline]
            fn step(&self, sys: &Sys, t: f64, h: f64, z: &mut [f64], ws: &mut Self::Workspace) -> ::core::result::Result<(), ::integrator_core::SolveError> {
                ::integrator_core::implicit::step(&Self::TABLE, sys, t, h, z, ws)
            }
        }
    }
}
