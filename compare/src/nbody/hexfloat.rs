//! Doubles as hexadecimal floats, in the form Python's `float.hex` writes
//! and `float.fromhex` reads: the exact way across the pipe to REBOUND.

/// `x` as a hexadecimal float in the form Python's `float.hex` writes
/// (`0x1.8000000000000p+1`, `-0x0.0p+0`, `inf`, `nan`), which
/// `float.fromhex` reads back exactly.
pub fn hex(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    let sign = if x.is_sign_negative() { "-" } else { "" };
    if x.is_infinite() {
        return format!("{sign}inf");
    }
    let bits = x.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i64;
    let mant = bits & ((1u64 << 52) - 1);
    if exp == 0 && mant == 0 {
        return format!("{sign}0x0.0p+0");
    }
    let (lead, e) = if exp == 0 {
        (0, -1022)
    } else {
        (1, exp - 1023)
    };
    let esign = if e < 0 { '-' } else { '+' };
    format!("{sign}0x{lead}.{mant:013x}p{esign}{}", e.abs())
}

/// A hexadecimal float (`[-]0xH.HHHp[+-]E`, as [`hex`] and Python write
/// them, or `inf`/`nan`) read exactly; `None` if it is not one or has more
/// digits than a double holds.
pub fn unhex(s: &str) -> Option<f64> {
    let (neg, body) = match s.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, s.strip_prefix('+').unwrap_or(s)),
    };
    let signed = |x: f64| if neg { -x } else { x };
    match body {
        "inf" => return Some(signed(f64::INFINITY)),
        "nan" => return Some(f64::NAN),
        _ => {}
    }
    let body = body.strip_prefix("0x")?;
    let (digits, exp) = body.split_once('p')?;
    let exp: i64 = exp.parse().ok()?;
    let (int, frac) = digits.split_once('.').unwrap_or((digits, ""));
    if int.len() != 1 || frac.len() > 13 {
        return None;
    }
    let lead = u64::from_str_radix(int, 16).ok()?;
    if lead > 1 {
        return None;
    }
    let frac_bits = if frac.is_empty() {
        0
    } else {
        u64::from_str_radix(frac, 16).ok()? << (4 * (13 - frac.len()))
    };
    if lead == 0 {
        if frac_bits == 0 {
            return Some(signed(0.0));
        }
        // Subnormal: 0.f × 2^-1022 exactly.
        if exp != -1022 {
            return None;
        }
        return Some(signed(f64::from_bits(frac_bits)));
    }
    if !(-1022..=1023).contains(&exp) {
        return None;
    }
    let bits = (((exp + 1023) as u64) << 52) | frac_bits;
    Some(signed(f64::from_bits(bits)))
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
