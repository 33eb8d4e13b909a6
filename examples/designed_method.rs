//! A method `symlab design` found, compiled by `butcher!` from its emitted
//! table file and measured beside the library's best on the pendulum, all
//! of them generated code, in one work–precision sweep:
//!
//! ```sh
//! cargo run --release --example designed_method            # 30 step sizes, 3 timed runs each
//! cargo run --release --example designed_method -- --quick # a smoke run
//! ```
//!
//! The design is solution 3 of `symlab design designs/rkn6-aba8.toml`
//! (seed 1, 2000 starts): a symmetric ABA sequence of 8 force evaluations,
//! Runge–Kutta–Nyström order 6, certified by the Krawczyk test; the file
//! `designs/found/rkn-aba-8-stages-order-6-3.toml` is what the designer
//! wrote (a test checks that it is a certified member of its family). The
//! library's rows are its strongest explicit schemes on this problem
//! (Blanes & Moan's PRK₁₀ and SRKN methods, Kahan–Li 8) and DOP853. The
//! verdict per error is `compare::versus`'s; the whole output goes to
//! `out/designed_method/`. The guide's design chapter shows a run.

use std::path::Path;

use compare::versus::versus;
use compare::{Method, Problem, SweepSettings, work_precision};
use integrator_core::butcher;
use integrator_core::problems::Pendulum;

butcher! {
    /// `symlab design designs/rkn6-aba8.toml`, solution 3 (see above).
    pub Designed {
        file: "designs/found/rkn-aba-8-stages-order-6-3.toml",
    }
}

/// The design's row.
const DESIGN: &str = "rkn-aba-8-stages-order-6-3";

/// The library's rows.
const LIBRARY: [&str; 6] = [
    "blanes-moan-prk10",
    "blanes-moan-srkn14a",
    "blanes-moan-srkn11b",
    "blanes-moan-srkn6b",
    "kahan-li8",
    "dop853",
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let quick = std::env::args().skip(1).any(|a| a == "--quick");
    let defaults = Pendulum.defaults();
    let setup = compare::builtin::pendulum(defaults.t_end, true)?;
    let mut methods = vec![Method::scheme(DESIGN, Designed)];
    for id in LIBRARY {
        methods.push(Method::by_id(id, &setup.sys)?);
    }
    let settings = SweepSettings {
        points: if quick { 6 } else { 30 },
        repeats: if quick { 1 } else { 3 },
        ..SweepSettings::new(defaults, defaults.t_end)
    };
    let result = work_precision(&setup, &methods, &settings)?;
    let dir = Path::new("out").join("designed_method");
    let files = result.write(&dir)?;
    print!("{}", result.summary());
    let table = versus(
        &result.rows,
        &[DESIGN.to_string()],
        &[1e-6, 1e-8, 1e-10, 1e-12],
    )
    .markdown();
    let path = dir.join("designs.md");
    std::fs::write(&path, &table)?;
    print!("{table}");
    for f in files.iter().chain([&path]) {
        println!("wrote {}", f.display());
    }
    Ok(())
}
