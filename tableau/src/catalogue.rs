//! The built-in catalogue of Butcher tables.
//!
//! Every method is written once, as a table file in `tableau/catalogue/<id>.toml`
//! (format: [`crate::file`]), with its literature source and the literature's
//! claims. The files are embedded here with `include_str!`, so `symlab check
//! --builtin ID` at run time and the `butcher!` macro at compile time read the
//! same text. `tableau/catalogue/README.md` says how the coefficients were
//! cross-checked. The texts and the lookup of ids are [`crate::embedded`]'s;
//! this module parses them.
//!
//! ```
//! let gauss2 = tableau::catalogue::load("gauss2").unwrap();
//! assert_eq!(gauss2.name, "Gauss–Legendre, 2 stages");
//! assert!(tableau::catalogue::load("gaus2").unwrap_err().to_string().contains("gauss2"));
//! ```

use crate::file::{FileError, TableFile, parse_table_file};

pub use crate::embedded::{Entry, close_matches, entries, find};

impl Entry {
    /// Parse this entry's table file; messages name it `builtin:ID`.
    pub fn load(&self) -> Result<TableFile, FileError> {
        parse_table_file(&format!("builtin:{}", self.id), self.text)
    }
}

/// Parse the built-in table `id`. An unknown id is an error that lists the
/// closest ids (or all of them when none is close).
pub fn load(id: &str) -> Result<TableFile, FileError> {
    match find(id) {
        Some(entry) => entry.load(),
        None => Err(FileError {
            file: format!("builtin:{id}"),
            field: None,
            message: crate::embedded::unknown_message(id),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_ids_are_errors_naming_the_builtin() {
        let e = load("rk5").unwrap_err();
        assert_eq!(e.file, "builtin:rk5");
        assert!(e.message.contains("rk4"), "{}", e.message);
        let e = load("no-such-method-at-all").unwrap_err();
        assert!(e.message.contains("the catalogue has"), "{}", e.message);
    }
}
