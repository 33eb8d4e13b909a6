//! Times parsing and analysing root files given on the command line:
//! `cargo run --release -p tableau --example root_stress -- FILE...`.

use std::time::Instant;

use tableau::algebraic::file::{Loaded, parse};

fn main() {
    for path in std::env::args().skip(1) {
        let text = std::fs::read_to_string(&path).expect("readable");
        let t0 = Instant::now();
        let r = parse(&path, &text);
        let t1 = t0.elapsed().as_secs_f64();
        match r {
            Ok(Loaded::Algebraic(f)) => {
                let an = f.analyse();
                let t2 = t0.elapsed().as_secs_f64();
                println!(
                    "{path}: parse {t1:.2} s, total {t2:.2} s, work {}, W {:?}, B {:?}, refusals {:?}",
                    an.work,
                    an.w.iter().map(|e| e.zero).collect::<Vec<_>>(),
                    an.b_levels,
                    an.refusals
                );
            }
            Ok(_) => println!("{path}: not a root file"),
            Err(e) => println!("{path}: {t1:.2} s error: {e}"),
        }
    }
}
