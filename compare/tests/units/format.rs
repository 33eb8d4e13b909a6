//! Tests of `compare::format` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::format::*;
#[test]
fn counts_and_times() {
    assert_eq!(count(1e6), "10⁶");
    assert_eq!(count(100.0), "10²");
    assert_eq!(count(4642.0), "4642");
    assert_eq!(count(10.0), "10");
    assert_eq!(ms(2.887e-4), "0.289");
    assert_eq!(ms(0.0123), "12.3");
    assert_eq!(ms(1.45e-5), "0.0145");
    assert_eq!(err(1.8e-3), "1.8e-3");
}

#[test]
fn missing_values_share_one_marker() {
    for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(sci(x, 2), MISSING);
        assert_eq!(signed_sci(x, 2), MISSING);
        assert_eq!(fixed(x, 2), MISSING);
        assert_eq!(ms(x), MISSING);
        assert_eq!(err(x), MISSING);
        assert_eq!(count(x), MISSING);
        assert_eq!(ratio(x), MISSING);
    }
    assert_eq!(opt(None, err), MISSING);
    assert_eq!(times(1.0, 0.0), MISSING);
    assert_eq!(times(0.0, 0.0), MISSING);
}

#[test]
fn messages_show_the_value() {
    assert_eq!(plain(f64::NAN), "NaN");
    assert_eq!(plain(-f64::INFINITY), "-inf");
    assert_eq!(plain(5e-324), "5e-324");
    assert_eq!(plain(1e7), "1e7");
    assert_eq!(plain(9999999.0), "9999999");
}
