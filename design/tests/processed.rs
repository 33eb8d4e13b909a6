//! The second-corrector family (`designs/whckl-c17-corrector2.toml`,
//! `design::processed`): the one unknown solved exactly from tableau's exact
//! near-integrable coefficients, the emitted table's claims decided as
//! `symlab check` decides them, the design read back from the table's text (and a
//! perturbed coefficient seen to leave the term), and bad families refused.

use tableau::Number;

use crate::common::{claims_hold, family_path};

const FILE: &str = "whckl-c17-corrector2.toml";

fn designed() -> design::processed::CorrectorDesign {
    let f = design::processed::load_corrector_family(&family_path(FILE)).unwrap();
    design::processed::design_corrector(&f, FILE).unwrap()
}

/// The ε²h⁵ coefficient of the Lyndon word `A³B²` (the leading word of
/// [A,[A,[[A,B],B]]]) of the effective method of a processed table's text,
/// as tableau computes it from the text alone.
fn removable_term(text: &str) -> Number {
    let file = tableau::file::parse_table_file("t.toml", text).unwrap();
    let chi = file.corrector_table().unwrap();
    let effective = tableau::near_integrable::processed_table(&file.table, &chi).unwrap();
    tableau::near_integrable::near_coefficients(&effective, &[5, 5])
        .unwrap()
        .into_iter()
        .find(|w| w.bs == 2 && w.degree == 5 && w.lie == "[A,[A,[[A,B],B]]]")
        .unwrap()
        .value
}

#[test]
fn whckl_second_corrector_is_exact() {
    let d = designed();
    // WHCKL's corrector leaves −11/5760 on [A,[A,[[A,B],B]]] (the catalogue
    // file states it); χ₂ removes it exactly, with c² = 11/5760 (REBOUND's
    // corrector2 has c² = 7/5760, not this kernel's).
    let word = |ws: &[tableau::near_integrable::NearCondition], w: &str| {
        ws.iter().find(|c| c.word == w).unwrap().value.clone()
    };
    assert_eq!(word(&d.before, "A³B²"), Number::ratio(-11, 5760).unwrap());
    assert_eq!(word(&d.after, "A³B²"), Number::zero());
    assert_eq!(d.c_squared, Number::ratio(11, 5760).unwrap());
    assert_eq!(&d.c * &d.c, d.c_squared);
    assert_eq!(d.orientation, design::processed::Orientation::Inverse);
    // The other term, [[A,[A,B]],[A,B]], is not χ₂'s to change: its
    // coordinate (the A²BAB coefficient plus twice the A³B² one) stays.
    let q = |ws: &[tableau::near_integrable::NearCondition]| {
        &word(ws, "A²BAB") + &(&word(ws, "A³B²") * &Number::ratio(2, 1).unwrap())
    };
    assert_eq!(q(&d.before), q(&d.after));
    assert!(!q(&d.after).is_zero());
    // So the generalised order is the method's, and every claim holds.
    assert_eq!(d.orders_before, "(≥18, 4)");
    assert_eq!(d.orders_after, "(≥18, 4)");
    let (name, text) = &d.table;
    for (claim, verdict) in claims_hold(name, text) {
        assert!(verdict.is_ok(), "{claim}: {verdict:?}");
    }
    assert!(text.contains("\"order = (18, 4)\""), "{text}");
    assert_eq!(removable_term(text), Number::zero());
}

/// The table carries the design: its text, read back by tableau, has the
/// removable ε²h⁵ term zero exactly, and with c moved by one part in a
/// thousand it does not.
#[test]
fn a_perturbed_second_corrector_leaves_the_term() {
    let d = designed();
    let (_, text) = &d.table;
    let line = format!("c2nd = \"{}\"", d.c);
    assert!(text.contains(&line), "{text}");
    let perturbed = text.replace(&line, &format!("c2nd = \"({})*1001/1000\"", d.c));
    // The coefficient is −11/5760 + c² (χ₂ applied inverted adds c²), so
    // c·1.001 leaves c²·(1.001² − 1).
    let t = removable_term(&perturbed);
    let grown =
        &d.c_squared * &(&Number::ratio(1001 * 1001, 1000 * 1000).unwrap() - &Number::one());
    assert_eq!(t, grown, "{t}");
}

#[test]
fn bad_second_corrector_families_name_the_field() {
    let parse = |text: &str| design::processed::parse_corrector_family("f.toml", text).unwrap_err();
    let base = "name = \"x\"\nform = \"second-corrector\"\n";
    let e = parse(&format!("{base}kernel = \"whckl-c71\"\n"));
    assert_eq!(e.field.as_deref(), Some("kernel"), "{e}");
    let e = parse(&format!("{base}kernel = \"leapfrog\"\n"));
    assert_eq!(e.field.as_deref(), Some("kernel"), "{e}");
    assert!(e.message.contains("whckl-c17"), "{e}");
    let e = parse(&format!("{base}kernel = \"whckl-c17\"\nstages = 3\n"));
    assert_eq!(e.field.as_deref(), Some("stages"), "{e}");
    let e = parse(base);
    assert!(e.message.contains("kernel"), "{e}");
    assert!(design::processed::is_corrector_family(base));
    assert!(!design::processed::is_corrector_family("form = \"ABA\"\n"));
}
