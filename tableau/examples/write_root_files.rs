//! Write every generated collocation table with s ≤ 8 (and the Lobatto
//! IIIA–IIIB pair) as a table file with `root(...)` entries, with `c` given
//! and left to the row sums, each also with `a[0][1]` perturbed by 10⁻⁴⁰:
//!
//! ```sh
//! cargo run --release -p tableau --example write_root_files -- DIR
//! ```
//!
//! `scripts/hostile_sweep.py` runs them through `symlab check` and
//! `symlab compare --table` under its time and memory limits.

use tableau::algebraic::family::{Family, Method, PairMethod};

fn main() {
    let Some(dir) = std::env::args().nth(1) else {
        eprintln!("usage: write_root_files DIR");
        std::process::exit(2);
    };
    let dir = std::path::Path::new(&dir);
    if let Err(e) = std::fs::create_dir_all(dir) {
        eprintln!("error: {}: {e}", dir.display());
        std::process::exit(2);
    }
    let claims = ["symplectic"];
    let perturbation = Some((0, 1, "1/10^40"));
    let mut written = 0;
    let mut put = |name: String, text: String| {
        let path = dir.join(name);
        if let Err(e) = std::fs::write(&path, text) {
            eprintln!("error: {}: {e}", path.display());
            std::process::exit(2);
        }
        written += 1;
    };
    for family in Family::ALL {
        // One-stage Radau IA and the Lobatto families need two stages.
        let first = if matches!(family, Family::Gauss | Family::Radau2A) {
            1
        } else {
            2
        };
        for s in first..=8 {
            let m = Method::new(family, s);
            for with_c in [true, false] {
                let c = if with_c { "c" } else { "noc" };
                let name = format!("{}{s}-roots-{c}", family.name());
                put(
                    format!("{name}.toml"),
                    m.to_root_file_with(&name, &claims, None, with_c),
                );
                if s >= 2 {
                    put(
                        format!("{name}-perturbed.toml"),
                        m.to_root_file_with(&name, &claims, perturbation, with_c),
                    );
                }
            }
        }
    }
    for s in 2..=8 {
        let m = PairMethod::new(s);
        for with_c in [true, false] {
            let c = if with_c { "c" } else { "noc" };
            let name = format!("lobatto3a3b{s}-roots-{c}");
            put(
                format!("{name}.toml"),
                m.to_root_file(&name, &claims, None, with_c),
            );
            put(
                format!("{name}-perturbed.toml"),
                m.to_root_file(&name, &claims, perturbation, with_c),
            );
        }
    }
    println!("wrote {written} files into {}", dir.display());
}
