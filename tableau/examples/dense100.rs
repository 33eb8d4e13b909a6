//! Times the analysis of a dense 100-stage rational table, aᵢⱼ = 1/(i + j + 2),
//! bⱼ = 1/(j + 2) (0-based i, j):
//! `cargo run --release -p tableau --example dense100`.

use std::time::Instant;

fn main() {
    let s: usize = std::env::args()
        .nth(1)
        .map_or(100, |x| x.parse().expect("stages"));
    let row = |i: usize| {
        let r: Vec<String> = (0..s).map(|j| format!("\"1/{}\"", i + j + 2)).collect();
        format!("[{}]", r.join(", "))
    };
    let a: Vec<String> = (0..s).map(row).collect();
    let b: Vec<String> = (0..s).map(|j| format!("\"1/{}\"", j + 2)).collect();
    let text = format!(
        "name = \"dense {s}\"\na = [{}]\nb = [{}]\n",
        a.join(",\n"),
        b.join(", ")
    );
    let t0 = Instant::now();
    let tf = tableau::file::parse_table_file("dense.toml", &text).expect("parses");
    let t1 = t0.elapsed().as_secs_f64();
    let an = tableau::analysis::Analysis::of(&tf.table).expect("analyses");
    let t2 = t0.elapsed().as_secs_f64();
    println!(
        "{s} stages: parse {t1:.2} s, analysis {:.2} s, total {t2:.2} s (order {:?}, symplectic {})",
        t2 - t1,
        an.order,
        an.symplectic
    );
}
