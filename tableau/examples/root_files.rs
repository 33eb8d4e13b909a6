//! Times the analysis of generated collocation tables written out as
//! `root(...)` table files, with and without `c`:
//! `cargo run --release -p tableau --example root_files [FAMILY S [c|noc]]`.

use std::time::Instant;

use tableau::algebraic::family::{Family, Method};
use tableau::algebraic::file::{Loaded, parse};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let fams: Vec<Family> = match args.first() {
        Some(n) => Family::ALL
            .iter()
            .copied()
            .filter(|f| f.name() == n)
            .collect(),
        None => Family::ALL.to_vec(),
    };
    let stages: Vec<usize> = match args.get(1) {
        Some(s) => vec![s.parse().expect("S")],
        None => (1..=8).collect(),
    };
    let withc: Vec<bool> = match args.get(2).map(String::as_str) {
        Some("c") => vec![true],
        Some("noc") => vec![false],
        _ => vec![true, false],
    };
    for fam in fams {
        for &s in &stages {
            if s < 2 && fam != Family::Gauss && fam != Family::Radau2A {
                continue;
            }
            for &wc in &withc {
                let m = Method::new(fam, s);
                let text = m.to_root_file_with("t", &["symplectic"], None, wc);
                let t0 = Instant::now();
                let r = parse("gen.toml", &text);
                let t1 = t0.elapsed().as_secs_f64();
                match r {
                    Ok(Loaded::Algebraic(f)) => {
                        let an = f.analyse();
                        let t2 = t0.elapsed().as_secs_f64();
                        println!(
                            "{} {s} {} parse {t1:.3}s total {t2:.3}s work {} symplectic {:?} rows {:?} B {:?}",
                            fam.name(),
                            if wc { "c" } else { "noc" },
                            an.work,
                            an.symplectic,
                            an.row_sums_ok,
                            an.b_levels
                        );
                    }
                    Ok(_) => println!("{} {s}: not algebraic", fam.name()),
                    Err(e) => println!("{} {s}: error {e}", fam.name()),
                }
            }
        }
    }
}
