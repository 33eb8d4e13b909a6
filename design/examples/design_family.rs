//! Run one family file through the library and print the report and the
//! search's time: `cargo run --release -p design --example design_family --
//! designs/bab6-order4.toml` (the timing quoted in the guide).

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: design_family FAMILY.toml");
        std::process::exit(2);
    };
    let family = match design::load_family(std::path::Path::new(&path)) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    };
    match design::design(&family, &path, &mut |_| {}) {
        Ok(out) => print!("{}", out.report()),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    }
}
