//! Double-double arithmetic (about 106 bits) and the two-body flow computed
//! with it: the reference the Kepler drift is measured against. It shares
//! no code with the library's solver: no period reduction, Stumpff's
//! functions by quartering the argument and doubling back
//! (`c₀(4z) = 2c₀² − 1, c₁(4z) = c₀c₁, c₂(4z) = c₁²/2,
//! c₃(4z) = (c₂ + c₀c₃)/4`), the root by bisection then Newton.

#![allow(dead_code)]

use std::ops::{Add, Div, Mul, Neg, Sub};

/// `hi + lo` with `|lo| ≤ ulp(hi)/2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dd {
    pub hi: f64,
    pub lo: f64,
}

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

impl Dd {
    pub const fn new(x: f64) -> Self {
        Dd { hi: x, lo: 0.0 }
    }
    /// π to double-double precision.
    pub const PI: Dd = Dd {
        hi: std::f64::consts::PI,
        lo: 1.2246467991473532e-16,
    };
    pub fn f64(self) -> f64 {
        self.hi + self.lo
    }
    pub fn sqrt(self) -> Dd {
        if self.hi <= 0.0 {
            return Dd::new(0.0);
        }
        let q = self.hi.sqrt();
        let (p, e) = two_prod(q, q);
        let r = (self - Dd { hi: p, lo: e }).hi;
        let (s, t) = fast_two_sum(q, r / (2.0 * q));
        Dd { hi: s, lo: t }
    }
    pub fn abs(self) -> Dd {
        if self.hi < 0.0 { -self } else { self }
    }
    pub fn floor(self) -> Dd {
        let h = self.hi.floor();
        if h == self.hi {
            let (s, t) = fast_two_sum(h, self.lo.floor());
            Dd { hi: s, lo: t }
        } else {
            Dd::new(h)
        }
    }
}

impl From<f64> for Dd {
    fn from(x: f64) -> Self {
        Dd::new(x)
    }
}

impl Add for Dd {
    type Output = Dd;
    fn add(self, b: Dd) -> Dd {
        let (s, e) = two_sum(self.hi, b.hi);
        let (t, f) = two_sum(self.lo, b.lo);
        let (s, e) = fast_two_sum(s, e + t);
        let (s, e) = fast_two_sum(s, e + f);
        Dd { hi: s, lo: e }
    }
}

impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Sub for Dd {
    type Output = Dd;
    fn sub(self, b: Dd) -> Dd {
        self + (-b)
    }
}

impl Mul for Dd {
    type Output = Dd;
    fn mul(self, b: Dd) -> Dd {
        let (p, e) = two_prod(self.hi, b.hi);
        let e = e + (self.hi * b.lo + self.lo * b.hi);
        let (s, t) = fast_two_sum(p, e);
        Dd { hi: s, lo: t }
    }
}

impl Div for Dd {
    type Output = Dd;
    fn div(self, b: Dd) -> Dd {
        let q1 = self.hi / b.hi;
        let r = self - b * Dd::new(q1);
        let q2 = r.hi / b.hi;
        let r = r - b * Dd::new(q2);
        let q3 = r.hi / b.hi;
        let (s, t) = fast_two_sum(q1, q2);
        Dd { hi: s, lo: t } + Dd::new(q3)
    }
}

fn dot(a: &[Dd; 3], b: &[Dd; 3]) -> Dd {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Stumpff's `c₀ … c₃` in double-double.
pub fn stumpff(z: Dd) -> [Dd; 4] {
    let mut n = 0;
    let mut zq = z;
    while zq.hi.abs() > 0.1 {
        zq = zq * Dd::new(0.25);
        n += 1;
    }
    // c₂ = Σ (−z)ᵏ/(2k+2)!, c₃ = Σ (−z)ᵏ/(2k+3)!, 16 terms (|z| ≤ 0.1).
    let m = -zq;
    let terms = 16;
    let mut c2 = Dd::new(0.0);
    let mut c3 = Dd::new(0.0);
    for k in (0..terms).rev() {
        let f2 = fact(2 * k + 2);
        let f3 = fact(2 * k + 3);
        c2 = c2 * m + Dd::new(1.0) / f2;
        c3 = c3 * m + Dd::new(1.0) / f3;
    }
    let one = Dd::new(1.0);
    let mut c0 = one - zq * c2;
    let mut c1 = one - zq * c3;
    for _ in 0..n {
        let (a0, a1, a2, a3) = (c0, c1, c2, c3);
        c0 = Dd::new(2.0) * a0 * a0 - one;
        c1 = a0 * a1;
        c2 = a1 * a1 * Dd::new(0.5);
        c3 = (a2 + a0 * a3) * Dd::new(0.25);
    }
    [c0, c1, c2, c3]
}

fn fact(k: usize) -> Dd {
    (1..=k).fold(Dd::new(1.0), |acc, i| acc * Dd::new(i as f64))
}

/// The exact two-body state at time `h` from `(x, v)`, in double-double,
/// or `None` if the root was not found.
pub fn flow(gm: f64, h: f64, x: [f64; 3], v: [f64; 3]) -> Option<([Dd; 3], [Dd; 3])> {
    flow_dd(gm, Dd::new(h), x, v)
}

/// [`flow`] over a time given in double-double (a long run's `k·h`).
pub fn flow_dd(gm: f64, h: Dd, x: [f64; 3], v: [f64; 3]) -> Option<([Dd; 3], [Dd; 3])> {
    let x0 = x.map(Dd::new);
    let v0 = v.map(Dd::new);
    let gm = Dd::new(gm);
    let r0 = dot(&x0, &x0).sqrt();
    let eta = dot(&x0, &v0);
    let beta = Dd::new(2.0) * gm / r0 - dot(&v0, &v0);
    let zeta = gm - beta * r0;
    let eval = |s: Dd| {
        let c = stumpff(beta * s * s);
        let g1 = s * c[1];
        let g2 = s * s * c[2];
        let g3 = s * s * s * c[3];
        let f = r0 * s + eta * g2 + zeta * g3 - h;
        let r = r0 + eta * g1 + zeta * g2;
        (f, r, g1, g2, g3)
    };
    // Bracket [lo, hi] with F(lo) ≤ 0 ≤ F(hi); F is increasing.
    let sign = if h.hi >= 0.0 { 1.0 } else { -1.0 };
    let mut far = Dd::new(sign * (h.hi.abs() / r0.hi).clamp(1e-300, 1.0));
    let mut grows = 0;
    while eval(far).0.hi * sign < 0.0 {
        far = far * Dd::new(2.0);
        grows += 1;
        if grows > 2000 {
            return None;
        }
    }
    let (mut lo, mut hi) = if sign > 0.0 {
        (Dd::new(0.0), far)
    } else {
        (far, Dd::new(0.0))
    };
    for _ in 0..60 {
        let mid = (lo + hi) * Dd::new(0.5);
        if eval(mid).0.hi < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let mut s = (lo + hi) * Dd::new(0.5);
    let mut done = false;
    for _ in 0..40 {
        let (f, r, ..) = eval(s);
        let ds = f / r;
        s = s - ds;
        if ds.hi.abs() <= 1e-27 * s.hi.abs() || f.hi == 0.0 {
            done = true;
            break;
        }
    }
    if !done {
        eprintln!(
            "reference: Newton stalled at s = {s:?}, F = {:?}",
            eval(s).0
        );
        return None;
    }
    let (_, r, g1, g2, g3) = eval(s);
    let f = Dd::new(1.0) - gm * g2 / r0;
    let g = h - gm * g3;
    let fd = -gm * g1 / (r0 * r);
    let gd = Dd::new(1.0) - gm * g2 / r;
    let xs = [0, 1, 2].map(|k| f * x0[k] + g * v0[k]);
    let vs = [0, 1, 2].map(|k| fd * x0[k] + gd * v0[k]);
    Some((xs, vs))
}

/// `2GM/|x| − |v|²` (positive for a bound orbit) in double-double.
pub fn beta(gm: f64, x: [f64; 3], v: [f64; 3]) -> Dd {
    let x0 = x.map(Dd::new);
    let v0 = v.map(Dd::new);
    Dd::new(2.0 * 1.0) * Dd::new(gm) / dot(&x0, &x0).sqrt() - dot(&v0, &v0)
}
