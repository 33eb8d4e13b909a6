//! The one error collector of the macro: every path (`Table`, `from:` a
//! generated table, `root(...)` entries) pushes each mistake on the token it
//! is about, so that one invocation reports all of its mistakes together.

use proc_macro2::Span;
use syn::Error;

/// The errors found so far, combined into one `syn::Error`.
#[derive(Default)]
pub struct Errors(Option<Error>);

impl Errors {
    pub fn push(&mut self, span: Span, msg: impl std::fmt::Display) {
        let e = Error::new(span, msg);
        match &mut self.0 {
            Some(all) => all.combine(e),
            None => self.0 = Some(e),
        }
    }

    /// The errors so far, leaving none.
    pub fn take(&mut self) -> Option<Error> {
        self.0.take()
    }

    /// `Err` with every error pushed, `Ok` if there was none.
    pub fn finish(self) -> Result<(), Error> {
        self.0.map_or(Ok(()), Err)
    }
}
