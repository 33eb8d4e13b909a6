//! Generated collocation-type tables: the literature's verdicts, decided
//! exactly, and agreement with the hand-written catalogue tables.

use std::time::Instant;

use tableau::Table;
use tableau::algebraic::family::{Family, Method, PairMethod};
use tableau::analysis::Analysis;

#[test]
fn print_verdicts() {
    for fam in Family::ALL {
        for s in 2..=8 {
            let t = Instant::now();
            let m = Method::new(fam, s);
            let v = m.verdicts();
            println!(
                "{:?} s={s}: sympl={} symm={} order=[{}, {:?}] B{} C{} D{} A-stable={} R(inf)={} uni={} {:?}  {:?}",
                fam, v.symplectic, v.symmetric, v.order.lower, v.order.upper, v.order.b, v.order.c, v.order.d, v.a_stable, v.r_infinity, v.unimodular, v.stability.to_text(), t.elapsed()
            );
        }
    }
}
