//! Lists `catalogue/*.toml` for `src/catalogue.rs`, so that a table file
//! dropped into the directory is in the catalogue without a second edit.
//!
//! The generated file holds one `Entry` per file, in id order, each
//! embedding its file with `include_str!` (by absolute path, so the text
//! compiled in is the file on disk). Cargo reruns this script when the
//! directory changes (a file added or removed) and when a listed file
//! changes.

use std::{env, fs, path::Path};

fn main() {
    let manifest = env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let dir = Path::new(&manifest).join("catalogue");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut ids: Vec<String> = fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|f| f.expect("a readable directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| {
            println!("cargo:rerun-if-changed={}", p.display());
            p.file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or_else(|| panic!("{}: the file name is not UTF-8", p.display()))
                .to_string()
        })
        .collect();
    ids.sort();
    let mut out = String::from("&[\n");
    for id in &ids {
        assert!(
            !id.is_empty()
                && id
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'),
            "catalogue/{id}.toml: an id is a short lowercase name (a-z, 0-9, -)"
        );
        let path = dir.join(format!("{id}.toml"));
        out.push_str(&format!(
            "    Entry {{ id: {id:?}, text: include_str!({:?}) }},\n",
            path.display().to_string()
        ));
    }
    out.push(']');
    let dest =
        Path::new(&env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("catalogue_entries.rs");
    fs::write(&dest, out).unwrap_or_else(|e| panic!("cannot write {}: {e}", dest.display()));
}
