//! Processed kernels (`processed = true`): the effective-order conditions
//! and the recovery of published kernels from random starts.

use crate::common::load;

#[test]
fn effective_order_6_of_a_symmetric_composition_is_two_conditions() {
    let f = load("bcm-processed6-s11.toml");
    let sys = design::conditions::system(&f, "x").unwrap();
    for c in &sys.conditions {
        println!(
            "{} (weight {}): {}",
            c.word,
            c.degree,
            c.poly.to_text(&sys.names)
        );
    }
    for c in &sys.error_terms {
        println!(
            "error {} (weight {}): {}",
            c.word,
            c.degree,
            c.poly.to_text(&sys.names)
        );
    }
    assert_eq!(sys.names, ["g1", "g5"]);
    assert_eq!(sys.conditions.len(), 2);
}

#[test]
fn bcm_kernel_6_11_recovered() {
    let f = load("bcm-processed6-s11.toml");
    let out = design::design(&f, "designs/bcm-processed6-s11.toml", &mut |_| {}).unwrap();
    println!("{}", out.report());
    for d in &out.designs {
        println!(
            "{:?}",
            d.processor
                .as_ref()
                .map(|p| p.as_ref().map(|p| p.claims.clone()))
        );
        if let Some((n, t)) = &d.table {
            println!("== {n}\n{t}");
        }
    }
}
