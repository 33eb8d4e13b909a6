//! Tests of `compare::nbody::hexfloat` (from its `#[cfg(test)]` module: `compare`
//! has no unit-test harness, which would compile the whole crate a second
//! time; see `compare/tests/units/mod.rs`).

use compare::nbody::*;
#[test]
fn hex_matches_python_float_hex() {
    assert_eq!(hex(1.0), "0x1.0000000000000p+0");
    assert_eq!(hex(-0.5), "-0x1.0000000000000p-1");
    assert_eq!(hex(0.0), "0x0.0p+0");
    assert_eq!(hex(-0.0), "-0x0.0p+0");
    assert_eq!(hex(5e-324), "0x0.0000000000001p-1022");
    assert_eq!(hex(0.1), "0x1.999999999999ap-4");
    assert_eq!(hex(f64::MAX), "0x1.fffffffffffffp+1023");
}

#[test]
fn unhex_reads_back_every_kind_of_double() {
    for x in [
        1.0,
        -0.5,
        0.1,
        2.95912208286e-4,
        1.0 / 1.3e8,
        5e-324,
        -2.2250738585072014e-308 / 3.0,
        f64::MAX,
        f64::MIN_POSITIVE,
        f64::INFINITY,
    ] {
        let back = unhex(&hex(x)).unwrap();
        assert_eq!(back.to_bits(), x.to_bits(), "{x}");
    }
    assert_eq!(unhex("-0x0.0p+0").unwrap().to_bits(), (-0.0f64).to_bits());
    assert_eq!(unhex("0x1.8p+1"), Some(3.0));
    assert!(unhex("nan").unwrap().is_nan());
    for bad in [
        "",
        "1.0",
        "0x2.0p+0",
        "0x1.0p",
        "0x1.00000000000000p+0",
        "0x1.0p+1024",
    ] {
        assert_eq!(unhex(bad), None, "{bad}");
    }
}
