//! `butcher!`: declare a Runge–Kutta table, a partitioned pair, a drift–kick
//! sequence or a composition with exact entries and claims; the claims are
//! verified exactly at compile time by the same `tableau` analysis that
//! `symlab check` runs.
//!
//! Tables with `root(...)` entries in `let` ([`roots`]) are read as the
//! `root(...)` table files of `tableau::algebraic::file`.
//!
//! The macro is split as thiserror and serde_derive are: [`ast`] parses the
//! tokens, [`valid`] builds the exact table and checks every claim (all
//! errors collected in one [`errors::Errors`], each on the token it is
//! about), [`expand`] states what was proven as [`emit::Facts`], and
//! [`emit`] writes the scheme type from them: the one emitter of every path
//! (also [`generated`] tables and [`roots`] tables). On error a stub type is
//! still emitted, so one mistake does not cascade into "cannot find type"
//! errors at every use.

mod ast;
mod emit;
mod errors;
mod expand;
mod generated;
mod roots;
mod step;
mod valid;

use proc_macro::TokenStream;

#[proc_macro]
pub fn butcher(input: TokenStream) -> TokenStream {
    let input = syn::parse_macro_input!(input as ast::Input);
    match generated::validate(&input) {
        Some(Ok(g)) => return generated::expand(&input, &g).into(),
        Some(Err(err)) => return emit::stub(&input, err).into(),
        None => {}
    }
    match roots::validate(&input) {
        Some(Ok(t)) => return roots::expand(&input, &t).into(),
        Some(Err(err)) => return emit::stub(&input, err).into(),
        None => {}
    }
    let tracked = tracked_file(&input);
    let out = match valid::validate(&input) {
        Ok(verified) => expand::expand(&input, &verified),
        Err(err) => emit::stub(&input, err),
    };
    quote::quote!(#out #tracked).into()
}

/// For `file: "PATH"`: the file's bytes included in the emitted code and
/// never used, so that cargo rebuilds the invoking crate when the file
/// changes (a proc macro's own reads are not tracked). Only where the file
/// exists: a missing file is `valid`'s error, on the path's token.
fn tracked_file(input: &ast::Input) -> proc_macro2::TokenStream {
    let Some(ast::Value::Str(path)) = input
        .fields
        .iter()
        .find(|f| f.key == "file")
        .map(|f| &f.value)
    else {
        return proc_macro2::TokenStream::new();
    };
    let full = valid::file_path(&path.value());
    match full.to_str() {
        Some(p) if full.is_file() => quote::quote!(
            const _: &[u8] = include_bytes!(#p);
        ),
        _ => proc_macro2::TokenStream::new(),
    }
}
