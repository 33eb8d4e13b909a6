//! The stability function `R(z) = 1 + z bᵀ(I − zA)⁻¹𝟙 = P(z)/Q(z)` with
//! `P(z) = det(I − zA + z𝟙bᵀ)` and `Q(z) = det(I − zA)` (Hairer–Wanner II,
//! IV.3), as an exact rational function in lowest terms.
//!
//! Both are characteristic polynomials reversed: `det(I − zM) = Σ cₖ zᵏ`
//! where `det(λI − M) = Σ cₖ λ^(s−k)`, for `M = A` and `M = A − 𝟙bᵀ`. A
//! rational table (the common case) is scaled to integers and its
//! characteristic polynomials are computed modulo primes and recovered by
//! the Chinese remainder theorem from an a-priori bound ([`super::modular`]):
//! no fraction, no gcd in the inner loop, `O(s³)` word operations per prime.
//! An explicit table needs no division at all (`Q = 1`,
//! `P(z) = 1 + Σ bᵀAᵏ⁻¹𝟙 zᵏ`). An implicit table with radicals is reduced to
//! Hessenberg form over the number field. Each path has a budget
//! ([`crate::budget`]); beyond it [`StabilityFunction::of`] says so instead
//! of running without bound, and the other verdicts are still decided.
//!
//! `|R(iy)| = 1` for every
//! real `y` exactly when `P(z)P(−z) = Q(z)Q(−z)` as polynomials (the two
//! sides are polynomials in `y` after `z = iy`, equal on all of ℝ).

use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Zero};

use super::modular;
use crate::budget::{BeyondBudget, RADICAL_STABILITY_WORK, STABILITY_WORK};
use crate::number::{MAX_INVERSE_DEGREE, field_degree};
use crate::{Number, Rk};

/// A polynomial with exact coefficients, constant term first, no trailing
/// zeros (the zero polynomial is empty).
#[derive(Clone, Debug, PartialEq)]
pub struct Poly(pub Vec<Number>);

impl Poly {
    fn trim(mut self) -> Self {
        while self.0.last().is_some_and(Number::is_zero) {
            self.0.pop();
        }
        self
    }

    pub fn degree(&self) -> Option<usize> {
        self.0.len().checked_sub(1)
    }

    fn mul(&self, other: &Poly) -> Poly {
        if self.0.is_empty() || other.0.is_empty() {
            return Poly(Vec::new());
        }
        let mut out = vec![Number::zero(); self.0.len() + other.0.len() - 1];
        for (i, x) in self.0.iter().enumerate() {
            for (j, y) in other.0.iter().enumerate() {
                out[i + j] += &(x * y);
            }
        }
        Poly(out).trim()
    }

    /// `p(−z)`.
    fn reflect(&self) -> Poly {
        Poly(
            self.0
                .iter()
                .enumerate()
                .map(|(k, c)| if k % 2 == 1 { -c } else { c.clone() })
                .collect(),
        )
    }

    fn scale(&self, x: &Number) -> Poly {
        Poly(self.0.iter().map(|c| c * x).collect()).trim()
    }

    /// Quotient and remainder of exact polynomial division.
    fn div_rem(&self, d: &Poly) -> (Poly, Poly) {
        let dd = d.degree().expect("division by the zero polynomial");
        let lead_inv = d.0[dd].recip().expect("leading coefficient is nonzero");
        let mut rem = self.0.clone();
        let mut quot = vec![Number::zero(); self.0.len().saturating_sub(dd).max(1)];
        while rem.len() > dd && !rem.is_empty() {
            let k = rem.len() - 1 - dd;
            let f = &rem[rem.len() - 1] * &lead_inv;
            for (j, dc) in d.0.iter().enumerate() {
                rem[k + j] -= &(&f * dc);
            }
            quot[k] = f;
            rem.pop();
            while rem.last().is_some_and(Number::is_zero) {
                rem.pop();
            }
        }
        (Poly(quot).trim(), Poly(rem).trim())
    }

    fn gcd(a: &Poly, b: &Poly) -> Poly {
        let (mut a, mut b) = (a.clone(), b.clone());
        while !b.0.is_empty() {
            let (_, r) = a.div_rem(&b);
            a = b;
            b = r;
        }
        a
    }

    /// The polynomial in `z` as text in the grammar (`1 + z/2 + z^2/12`).
    pub fn to_text(&self) -> String {
        if self.0.is_empty() {
            return "0".into();
        }
        let mut out = String::new();
        for (k, c) in self.0.iter().enumerate() {
            if c.is_zero() {
                continue;
            }
            let z = match k {
                0 => String::new(),
                1 => "z".into(),
                _ => format!("z^{k}"),
            };
            let neg = c.signum() == std::cmp::Ordering::Less;
            let mag = c.abs();
            let coef = if mag.is_rational() {
                mag.to_string()
            } else {
                format!("({mag})")
            };
            let term = match (k, mag.is_one(), mag.as_rational()) {
                (0, _, _) => coef,
                (_, true, _) => z,
                (_, false, Some(r)) if r.numer() == &1.into() => format!("{z}/{}", r.denom()),
                _ => format!("{coef}*{z}"),
            };
            if out.is_empty() {
                if neg {
                    out.push('-');
                }
            } else {
                out.push_str(if neg { " - " } else { " + " });
            }
            out.push_str(&term);
        }
        out
    }
}

/// `R(z) = P(z)/Q(z)` in lowest terms with `Q(0) = 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityFunction {
    pub numerator: Poly,
    pub denominator: Poly,
}

impl StabilityFunction {
    /// The exact stability function, or why it is beyond the budget (see
    /// [`crate::budget`]): rational tables within
    /// [`STABILITY_WORK`](crate::budget::STABILITY_WORK), explicit tables with
    /// radicals within [`RADICAL_STABILITY_WORK`](crate::budget::RADICAL_STABILITY_WORK),
    /// other tables with radicals also within
    /// [`MAX_INVERSE_DEGREE`](crate::number::MAX_INVERSE_DEGREE).
    pub fn of(rk: &Rk) -> Result<StabilityFunction, BeyondBudget> {
        let entries = rk.a.iter().flatten().chain(&rk.b);
        let rational = entries.clone().all(Number::is_rational);
        if rational {
            return rational_case(rk);
        }
        let s = rk.b.len() as u64;
        let degree = field_degree(entries);
        let explicit = (0..rk.a.len()).all(|i| rk.a[i][i..].iter().all(Number::is_zero));
        // Products of numbers with up to `degree` terms: s³ of them for an
        // explicit table, s⁴ for Berkowitz's algorithm, s³ for the Hessenberg
        // reduction in a quadratic field.
        let d2 = degree.saturating_mul(degree);
        // Berkowitz: s⁴ products whose coefficients grow with s, hence s⁵.
        let work = if explicit || degree <= 2 {
            s.saturating_pow(3).saturating_mul(d2)
        } else {
            s.saturating_pow(5).saturating_mul(d2)
        };
        if work > RADICAL_STABILITY_WORK || (!explicit && degree > MAX_INVERSE_DEGREE) {
            let (what, power) = if explicit || degree <= 2 {
                ("stages³", 3)
            } else {
                ("stages⁵", 5)
            };
            return Err(BeyondBudget(format!(
                "the entries span a field of degree {degree} over Q and the table has {s} stages: {what} × degree² = {s}^{power} × {degree}² is beyond the budget of 2^27 coefficient products (tableau::budget::RADICAL_STABILITY_WORK) for the exact stability function of a table with radicals{}",
                if !explicit && degree > MAX_INVERSE_DEGREE {
                    format!(
                        " (and an implicit table's degree must be at most {MAX_INVERSE_DEGREE})"
                    )
                } else {
                    String::new()
                }
            )));
        }
        if explicit {
            return Ok(explicit_case(rk));
        }
        field_case(rk, degree)
    }

    /// `|R(iy)| = 1` for all real `y`.
    pub fn unimodular_on_imaginary_axis(&self) -> bool {
        // Both sides have degree 2·deg, with nonzero leading coefficients.
        if self.numerator.degree() != self.denominator.degree() {
            return false;
        }
        let all = self.numerator.0.iter().chain(&self.denominator.0);
        if let Some(rats) = all.map(Number::as_rational).collect::<Option<Vec<_>>>() {
            // Rational: compare the products as integer polynomials over a
            // common denominator (no gcd per operation).
            let mut d = BigInt::one();
            for r in &rats {
                if !r.denom().is_one() {
                    d = d.lcm(r.denom());
                }
            }
            let scaled: Vec<BigInt> = rats
                .iter()
                .map(|r| (r * BigRational::from_integer(d.clone())).to_integer())
                .collect();
            let (p, q) = scaled.split_at(self.numerator.0.len());
            let reflect_mul = |v: &[BigInt]| -> Vec<BigInt> {
                let mut out = vec![BigInt::zero(); 2 * v.len() - 1];
                for (i, x) in v.iter().enumerate() {
                    for (j, y) in v.iter().enumerate() {
                        if j % 2 == 1 {
                            out[i + j] -= x * y;
                        } else {
                            out[i + j] += x * y;
                        }
                    }
                }
                out
            };
            return reflect_mul(p) == reflect_mul(q);
        }
        let lhs = self.numerator.mul(&self.numerator.reflect());
        let rhs = self.denominator.mul(&self.denominator.reflect());
        lhs == rhs
    }

    pub fn to_text(&self) -> String {
        if self.denominator.degree() == Some(0) {
            self.numerator.to_text()
        } else {
            format!(
                "({})/({})",
                self.numerator.to_text(),
                self.denominator.to_text()
            )
        }
    }
}

/// An explicit table: `A` is nilpotent, `Q = 1` and
/// `P(z) = 1 + Σₖ (bᵀAᵏ⁻¹𝟙) zᵏ` — products only, no division.
fn explicit_case(rk: &Rk) -> StabilityFunction {
    let s = rk.b.len();
    let mut v = vec![Number::one(); s];
    let mut coeffs = vec![Number::one()];
    for _ in 0..s {
        let dot =
            rk.b.iter()
                .zip(&v)
                .fold(Number::zero(), |acc, (x, y)| acc + x * y);
        coeffs.push(dot);
        v =
            rk.a.iter()
                .map(|row| {
                    row.iter()
                        .zip(&v)
                        .filter(|(x, y)| !x.is_zero() && !y.is_zero())
                        .fold(Number::zero(), |acc, (x, y)| acc + x * y)
                })
                .collect();
    }
    StabilityFunction {
        numerator: Poly(coeffs).trim(),
        denominator: Poly(vec![Number::one()]),
    }
}

/// `det(I − zM) = Σₖ cₖ zᵏ` where `det(λI − M) = Σₖ cₖ λ^(s−k)`: the
/// characteristic polynomial of `M`, reversed.
fn det_i_minus_z(m: Vec<Vec<Number>>, degree: u64) -> Poly {
    let c = if degree <= 2 {
        charpoly_hessenberg(m)
    } else {
        charpoly_field(m)
    };
    Poly(c).trim()
}

/// An implicit table with radicals: characteristic polynomials over the
/// number field (division-free), lowest terms by Euclid's algorithm over the
/// field.
fn field_case(rk: &Rk, degree: u64) -> Result<StabilityFunction, BeyondBudget> {
    let s = rk.b.len();
    let q = det_i_minus_z(rk.a.clone(), degree);
    let n: Vec<Vec<Number>> = (0..s)
        .map(|i| (0..s).map(|j| &rk.a[i][j] - &rk.b[j]).collect())
        .collect();
    let p = det_i_minus_z(n, degree);
    if q.0.len() <= 1 || field_coprime(&p, &q) {
        return Ok(normalised(p, q));
    }
    let s = s as u64;
    if degree > 2 || s > 20 {
        return Err(BeyondBudget(format!(
            "P and Q are not proven coprime modulo a prime, and their exact gcd over a field of degree {degree} with {s} stages is beyond the budget (Euclid's algorithm over the radicals is run for degree ≤ 2 and at most 20 stages)"
        )));
    }
    Ok(lowest_terms(p, q))
}

/// Whether `P` and `Q` are proven coprime modulo a prime (see
/// [`modular::RadicalHom`]); `false` when three primes do not decide.
fn field_coprime(p: &Poly, q: &Poly) -> bool {
    let mut primes: Vec<u64> =
        p.0.iter()
            .chain(&q.0)
            .flat_map(|x| x.terms().flat_map(|(m, _)| m.factors().iter().map(|f| f.0)))
            .collect();
    primes.sort_unstable();
    primes.dedup();
    (0..3).any(|k| {
        modular::RadicalHom::find(&primes, k).is_some_and(|h| h.proves_coprime(&p.0, &q.0))
    })
}

fn lowest_terms(p: Poly, q: Poly) -> StabilityFunction {
    let g = Poly::gcd(&p, &q);
    let (p, _) = p.div_rem(&g);
    let (q, _) = q.div_rem(&g);
    normalised(p, q)
}

fn normalised(mut p: Poly, mut q: Poly) -> StabilityFunction {
    // Normalise Q(0) = 1 (Q(0) ≠ 0 since Q(0) = det I = 1 before reduction).
    let q0 = q.0[0].recip().expect("Q(0) is nonzero");
    p = p.scale(&q0);
    q = q.scale(&q0);
    StabilityFunction {
        numerator: p,
        denominator: q,
    }
}

/// `det(λI − M) = Σₖ cₖ λ^(s−k)` over the number field: `[c₀ = 1, …, c_s]`,
/// by Berkowitz's algorithm, which needs no division (so no inverse, and no
/// growth of coefficients beyond that of the minors themselves): the
/// characteristic polynomial of each leading principal submatrix is the
/// previous one times a Toeplitz matrix built from `a`, `R·C`, `R·S·C`, …
/// (S. J. Berkowitz, Inform. Process. Lett. 18 (1984) 147–150).
fn charpoly_field(m: Vec<Vec<Number>>) -> Vec<Number> {
    let n = m.len();
    // Highest power first.
    let mut vect = vec![Number::one()];
    for r in 0..n {
        // The new row R = m[r][..r], column C = m[..r][r], corner a = m[r][r],
        // and S the leading r×r block.
        let mut q = Vec::with_capacity(r + 2);
        q.push(Number::one());
        q.push(-&m[r][r]);
        let mut v: Vec<Number> = (0..r).map(|i| m[i][r].clone()).collect();
        for k in 0..r {
            // −R·Sᵏ·C
            let dot = (0..r)
                .filter(|&j| !m[r][j].is_zero() && !v[j].is_zero())
                .fold(Number::zero(), |acc, j| acc + &m[r][j] * &v[j]);
            q.push(-dot);
            if k + 1 < r {
                v = (0..r)
                    .map(|i| {
                        (0..r)
                            .filter(|&j| !m[i][j].is_zero() && !v[j].is_zero())
                            .fold(Number::zero(), |acc, j| acc + &m[i][j] * &v[j])
                    })
                    .collect();
            }
        }
        // new[i] = Σ_{j ≤ i} q[i − j] · vect[j], for i in 0..r + 2.
        let new: Vec<Number> = (0..r + 2)
            .map(|i| {
                (0..=i.min(vect.len() - 1))
                    .filter(|&j| !vect[j].is_zero() && !q[i - j].is_zero())
                    .fold(Number::zero(), |acc, j| acc + &q[i - j] * &vect[j])
            })
            .collect();
        vect = new;
    }
    vect
}

/// `det(λI − M) = Σₖ cₖ λ^(s−k)` over the number field: `[c₀ = 1, …, c_s]`
/// by Hessenberg reduction (`s − 2` inverses; cheap in a quadratic field,
/// costly in larger ones, where the inverses' coefficients grow) (Hessenberg reduction, then the recurrence of its leading minors; Cohen,
/// *A Course in Computational Algebraic Number Theory*, 2.2.9).
fn charpoly_hessenberg(mut h: Vec<Vec<Number>>) -> Vec<Number> {
    let n = h.len();
    for col in 0..n.saturating_sub(2) {
        let m1 = col + 1;
        let Some(i) = (m1..n).find(|&i| !h[i][col].is_zero()) else {
            continue;
        };
        if i != m1 {
            h.swap(i, m1);
            for row in h.iter_mut() {
                row.swap(i, m1);
            }
        }
        let t_inv = h[m1][col].recip().expect("the pivot is nonzero");
        for j in m1 + 1..n {
            if h[j][col].is_zero() {
                continue;
            }
            let u = &h[j][col] * &t_inv;
            let (top, bottom) = h.split_at_mut(j);
            for (x, y) in bottom[0].iter_mut().zip(&top[m1]) {
                if !y.is_zero() {
                    *x -= &(&u * y);
                }
            }
            for row in h.iter_mut() {
                if !row[j].is_zero() {
                    let add = &u * &row[j];
                    row[m1] += &add;
                }
            }
        }
    }
    let mut polys: Vec<Vec<Number>> = vec![vec![Number::one()]];
    for k in 1..=n {
        let prev = &polys[k - 1];
        let mut cur = vec![Number::zero(); k + 1];
        for (i, c) in prev.iter().enumerate() {
            cur[i] += c;
            cur[i + 1] -= &(&h[k - 1][k - 1] * c);
        }
        let mut t = Number::one();
        for i in 1..k {
            t = &t * &h[k - i][k - i - 1];
            if t.is_zero() {
                break;
            }
            let f = &t * &h[k - i - 1][k - 1];
            if f.is_zero() {
                continue;
            }
            let q = &polys[k - i - 1];
            let shift = k + 1 - q.len();
            for (j, c) in q.iter().enumerate() {
                cur[shift + j] -= &(&f * c);
            }
        }
        polys.push(cur);
    }
    polys.pop().expect("n + 1 polynomials")
}

/// A rational table: scaled to integers by the common denominator `D` of
/// `A` and `b`, the characteristic polynomials of `DA` and `D(A − 𝟙bᵀ)` are
/// computed modulo primes and recovered exactly (see [`super::modular`]);
/// `Q(z) = Σ cₖ(DA) (z/D)ᵏ`, likewise `P`. Lowest terms: a gcd of degree 0
/// modulo a prime proves the two coprime; otherwise the gcd over Z by the
/// primitive remainder sequence.
fn rational_case(rk: &Rk) -> Result<StabilityFunction, BeyondBudget> {
    let s = rk.b.len();
    let rat = |x: &Number| x.as_rational().expect("a rational table");
    let mut d = BigInt::one();
    for x in rk.a.iter().flatten().chain(&rk.b) {
        let r = rat(x);
        if !r.denom().is_one() {
            d = d.lcm(r.denom());
        }
    }
    let scaled = |x: &BigRational| (x * BigRational::from_integer(d.clone())).to_integer();
    let ma: Vec<Vec<BigInt>> =
        rk.a.iter()
            .map(|row| row.iter().map(|x| scaled(&rat(x))).collect())
            .collect();
    let db: Vec<BigInt> = rk.b.iter().map(|x| scaled(&rat(x))).collect();
    let mn: Vec<Vec<BigInt>> = ma
        .iter()
        .map(|row| row.iter().zip(&db).map(|(x, y)| x - y).collect())
        .collect();
    let primes = modular::primes_needed(&modular::charpoly_bound(&ma))
        .max(modular::primes_needed(&modular::charpoly_bound(&mn)));
    // Per prime: the Hessenberg reduction (s³) and the residues of the s²
    // entries (their 64-bit words); the Chinese remainder theorem: primes²
    // per coefficient.
    let s64 = s as u64;
    let words = ma
        .iter()
        .chain(&mn)
        .flatten()
        .map(|x| x.bits() / 64 + 1)
        .max()
        .unwrap_or(1);
    let work = primes
        .saturating_mul(
            s64.saturating_pow(3)
                .saturating_add(s64.saturating_pow(2).saturating_mul(words)),
        )
        .saturating_add(primes.saturating_mul(primes).saturating_mul(s64 + 1));
    if work > STABILITY_WORK {
        return Err(BeyondBudget(format!(
            "the exact characteristic polynomials of this {s}-stage table need {primes} primes of 61 bits (entries over a common denominator of {} bits), about {work} operations (primes × (stages³ + stages² × words) + primes² × stages); the budget is 2^30 (tableau::budget::STABILITY_WORK)",
            d.bits()
        )));
    }
    let trim = |mut v: Vec<BigInt>| {
        while v.last().is_some_and(Zero::is_zero) {
            v.pop();
        }
        v
    };
    let q = trim(modular::charpoly(&ma));
    let p = trim(modular::charpoly(&mn));
    let coprime = q.len() == 1 || modular::coprime_mod(&p, &q, 8) == Some(true);
    let to_rat = |v: &[BigInt]| -> Vec<BigRational> {
        v.iter().cloned().map(BigRational::from_integer).collect()
    };
    let (p, q) = if coprime {
        (to_rat(&p), to_rat(&q))
    } else {
        let g = modular::gcd_z(&p, &q);
        if g.len() <= 1 {
            (to_rat(&p), to_rat(&q))
        } else {
            (modular::div_exact(&p, &g), modular::div_exact(&q, &g))
        }
    };
    // Back from w = z/D to z, and Q(0) = 1.
    let q0 = q[0].clone();
    let d = BigRational::from_integer(d);
    let unscale = |v: Vec<BigRational>| -> Poly {
        let mut dk = BigRational::one();
        let mut out = Vec::with_capacity(v.len());
        for c in v {
            out.push(Number::from_rational(&c / (&q0 * &dk)));
            dk *= &d;
        }
        Poly(out).trim()
    };
    Ok(StabilityFunction {
        numerator: unscale(p),
        denominator: unscale(q),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn implicit_midpoint_is_the_11_pade() {
        let rk = Rk {
            a: vec![vec![Number::ratio(1, 2).unwrap()]],
            b: vec![Number::one()],
            c: None,
        };
        let r = StabilityFunction::of(&rk).unwrap();
        assert_eq!(r.to_text(), "(1 + z/2)/(1 - z/2)");
        assert!(r.unimodular_on_imaginary_axis());
    }

    #[test]
    fn explicit_euler() {
        let rk = Rk {
            a: vec![vec![Number::zero()]],
            b: vec![Number::one()],
            c: None,
        };
        let r = StabilityFunction::of(&rk).unwrap();
        assert_eq!(r.to_text(), "1 + z");
        assert!(!r.unimodular_on_imaginary_axis());
    }
}
