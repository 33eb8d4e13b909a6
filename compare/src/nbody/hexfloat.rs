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
