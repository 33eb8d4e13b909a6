//! The product of exponentials `exp(x₁X₁) ⋯ exp(x_mX_m)` (each `X` the
//! letter `A` or `B`, factors in the order they are applied) in the free
//! associative algebra on `{A, B}`, truncated by (number of `B`s, length),
//! and the coefficients of its logarithm, all in exact [`Number`]s.
//!
//! **Truncation.** A word with `j` letters `B` is kept when its length is at
//! most `D(j)`, for a non-increasing `D` (and `j ≤ J`). The words dropped
//! form a two-sided ideal: if `u` is dropped, `n(u) > D(j(u)) ≥ D(j(u) +
//! j(v)) `, so `uv` and `vu` are dropped too. The quotient is an algebra,
//! so products, `exp` and `log` computed in it are the truncations of the
//! true ones: every coefficient kept is exact. This is why the truncation
//! is non-increasing (degrees asked for that are not are computed in their
//! least non-increasing majorant, see [`super::near_orders`]); it also
//! keeps the work far below the full
//! algebra (`2ⁿ` words of length `n`): only `C(n, j)` words per part.
//!
//! **Coefficients.** `P[w]` (with `h = 1`; a word of length `n` carries
//! `hⁿ`) is built factor by factor: `P_k[w] = Σ_r P_{k−1}[w minus its last r
//! letters] · x_k^r / r!` over the trailing run of the factor's letter. The
//! logarithm's coefficient of `w` is `Σ_k (−1)^{k+1}/k` times the sum over
//! the cuts of `w` into `k` nonempty consecutive pieces of `∏ P[piece]`
//! (`log P = Σ (−1)^{k+1} (P − 1)^k / k`); every piece is a factor of `w`,
//! hence kept by the truncation.

use std::collections::HashMap;

use num_bigint::BigInt;
use num_rational::BigRational;

use super::words::{Word, binomial, words_with};
use crate::Number;

/// The arithmetic of the coefficients: exact [`Number`]s (the radical
/// field, [`Exact`]) or the real algebraic numbers of `root(...)` entries
/// and nested radicals (the `algebraic` module's `near.rs`). `is_zero` is structural (a skip of work, never
/// a verdict): the verdicts are the callers' exact zero tests.
pub(crate) trait Ring {
    type E: Clone;
    fn zero(&self) -> Self::E;
    fn one(&self) -> Self::E;
    fn is_zero(&self, x: &Self::E) -> bool;
    fn add(&self, x: &Self::E, y: &Self::E) -> Self::E;
    fn neg(&self, x: &Self::E) -> Self::E;
    fn mul(&self, x: &Self::E, y: &Self::E) -> Self::E;
    fn scale(&self, x: &Self::E, r: &BigRational) -> Self::E;
}

/// The radical field of [`Number`].
pub(crate) struct Exact;

impl Ring for Exact {
    type E = Number;
    fn zero(&self) -> Number {
        Number::zero()
    }
    fn one(&self) -> Number {
        Number::one()
    }
    fn is_zero(&self, x: &Number) -> bool {
        x.is_zero()
    }
    fn add(&self, x: &Number, y: &Number) -> Number {
        x + y
    }
    fn neg(&self, x: &Number) -> Number {
        -x
    }
    fn mul(&self, x: &Number, y: &Number) -> Number {
        x * y
    }
    fn scale(&self, x: &Number, r: &BigRational) -> Number {
        x.scale(r)
    }
}

/// The truncation: `degrees[j]` is `D(j)` for `j = 0..=J`.
pub(crate) fn word_count(degrees: &[usize]) -> u64 {
    degrees
        .iter()
        .enumerate()
        .map(|(j, &d)| (1..=d).map(|n| binomial(n, j)).sum::<u64>())
        .sum()
}

/// One factor of a product of flows, in the order applied: `exp(x·X)` for a
/// letter `X` (`0` is `A`, `1` is `B`), or a gradient kick
/// `exp(k·B + g·[B,[A,B]])`.
#[derive(Clone, Debug, PartialEq)]
pub enum Factor<T = Number> {
    Letter(u8, T),
    Gradient { kick: T, gradient: T },
}

/// The coefficients `P[w]` of every word kept by the truncation `degrees`
/// (see [`word_count`]), the empty word included.
///
/// A letter factor `exp(xX)` updates `P` through the trailing run of `X`
/// (the fast path). A gradient factor `exp(E)`, `E = k·B + g·[B,[A,B]]`
/// with `[B,[A,B]] = 2·BAB − BBA − ABB`, is expanded as the truncated
/// exponential `exp(E)[v]` on every kept word `v` (only words whose
/// letters `B` are all in the image of `E`'s words appear) and multiplied
/// in: `P_new[w] = Σ_{w = uv} P[u]·exp(E)[v]`. Both `B` (degree 1, one `B`)
/// and `[B,[A,B]]` (degree 3, two `B`s) map a kept word to kept or dropped
/// words, and the dropped ones form an ideal, so the truncation is still
/// exact.
pub(crate) fn product_of_exponentials(ops: &[Factor], degrees: &[usize]) -> HashMap<Word, Number> {
    product_in(&Exact, ops, degrees)
}

/// [`product_of_exponentials`] in any [`Ring`].
pub(crate) fn product_in<R: Ring>(
    ring: &R,
    ops: &[Factor<R::E>],
    degrees: &[usize],
) -> HashMap<Word, R::E> {
    let mut words: Vec<Word> = Vec::new();
    for (j, &d) in degrees.iter().enumerate() {
        for n in j.max(1)..=d {
            words.extend(words_with(n, j));
        }
    }
    // Longest first: the update of `w` reads only its (shorter) prefixes,
    // which still hold the previous factor's values.
    words.sort_by_key(|w| std::cmp::Reverse(w.len));
    let top = degrees.iter().copied().max().unwrap_or(0);
    let mut p: HashMap<Word, R::E> = words.iter().map(|w| (*w, ring.zero())).collect();
    p.insert(Word::EMPTY, ring.one());
    for factor in ops {
        let (letter, x) = match factor {
            Factor::Letter(letter, x) => (letter, x),
            Factor::Gradient { kick, gradient } => {
                let e = gradient_exponential(ring, kick, gradient, &words);
                multiply(ring, &mut p, &words, &e);
                continue;
            }
        };
        // x^r / r! for r = 0..=top.
        let mut scaled = vec![ring.one()];
        let mut fact = BigInt::from(1);
        let mut power = ring.one();
        for r in 1..=top {
            power = ring.mul(&power, x);
            fact *= r;
            scaled.push(ring.scale(&power, &BigRational::new(1.into(), fact.clone())));
        }
        for w in &words {
            let run = w.trailing_run(*letter);
            if run == 0 {
                continue;
            }
            let mut add = ring.zero();
            for (r, scale) in scaled.iter().enumerate().take(run + 1).skip(1) {
                let pu = &p[&w.drop_last(r)];
                if !ring.is_zero(pu) {
                    add = ring.add(&add, &ring.mul(pu, scale));
                }
            }
            if !ring.is_zero(&add) {
                let e = p.get_mut(w).expect("every word is kept");
                *e = ring.add(e, &add);
            }
        }
    }
    p
}

/// `exp(k·B + g·[B,[A,B]])` on the kept words `words` (the empty word
/// included, as `1`): `Σ_r E^r / r!` with `E`'s words `B` (coefficient
/// `k`), `BAB` (`2g`), `BBA` and `ABB` (`−g`); a power `E^r` is the
/// product of `r` of these, and a word is reached only by concatenations
/// of them, so the sum stops once every word of `E^r` is longer than the
/// longest kept word (`r` is at most that length).
fn gradient_exponential<R: Ring>(
    ring: &R,
    kick: &R::E,
    gradient: &R::E,
    words: &[Word],
) -> HashMap<Word, R::E> {
    let kept: std::collections::HashSet<Word> = words.iter().copied().collect();
    let top = words.iter().map(|w| usize::from(w.len)).max().unwrap_or(0);
    let mut generators: Vec<(Word, R::E)> = Vec::new();
    if !ring.is_zero(kick) {
        generators.push((Word::from_letters(&[1]), kick.clone()));
    }
    if !ring.is_zero(gradient) {
        let two = ring.add(gradient, gradient);
        generators.push((Word::from_letters(&[1, 0, 1]), two));
        generators.push((Word::from_letters(&[1, 1, 0]), ring.neg(gradient)));
        generators.push((Word::from_letters(&[0, 1, 1]), ring.neg(gradient)));
    }
    let mut out: HashMap<Word, R::E> = HashMap::new();
    out.insert(Word::EMPTY, ring.one());
    // power[w]: the coefficient of w in E^r / r!.
    let mut power: HashMap<Word, R::E> = HashMap::from([(Word::EMPTY, ring.one())]);
    for r in 1..=top {
        let mut next: HashMap<Word, R::E> = HashMap::new();
        for (u, x) in &power {
            for (v, y) in &generators {
                if usize::from(u.len) + usize::from(v.len) > top {
                    continue;
                }
                let w = u.concat(v);
                if !kept.contains(&w) {
                    continue;
                }
                let term = ring.mul(x, y);
                let e = next.entry(w).or_insert_with(|| ring.zero());
                *e = ring.add(e, &term);
            }
        }
        let inverse = BigRational::new(1.into(), BigInt::from(r));
        next.retain(|_, x| !ring.is_zero(x));
        for x in next.values_mut() {
            *x = ring.scale(x, &inverse);
        }
        if next.is_empty() {
            break;
        }
        for (w, x) in &next {
            let e = out.entry(*w).or_insert_with(|| ring.zero());
            *e = ring.add(e, x);
        }
        power = next;
    }
    out.retain(|_, x| !ring.is_zero(x));
    out
}

/// `P ← P·E` on the kept words: `P[w] = Σ_{w = uv} P[u]·E[v]`, the words
/// updated longest first so that every prefix `u` still holds its old value.
fn multiply<R: Ring>(
    ring: &R,
    p: &mut HashMap<Word, R::E>,
    words: &[Word],
    e: &HashMap<Word, R::E>,
) {
    for w in words {
        let n = usize::from(w.len);
        let mut add = ring.zero();
        // v = the last r letters of w, r ≥ 1 (r = 0 is P[w]·1).
        for r in 1..=n {
            let Some(ev) = e.get(&w.slice(n - r, n)) else {
                continue;
            };
            let pu = &p[&w.drop_last(r)];
            if !ring.is_zero(pu) {
                add = ring.add(&add, &ring.mul(pu, ev));
            }
        }
        if !ring.is_zero(&add) {
            let x = p.get_mut(w).expect("every word is kept");
            *x = ring.add(x, &add);
        }
    }
}

/// The coefficient of `w` in `log P`, from the coefficients of its factors.
pub(crate) fn log_coefficient(p: &HashMap<Word, Number>, w: Word) -> Number {
    log_coefficient_in(&Exact, p, w)
}

/// [`log_coefficient`] in any [`Ring`].
pub(crate) fn log_coefficient_in<R: Ring>(ring: &R, p: &HashMap<Word, R::E>, w: Word) -> R::E {
    let m = usize::from(w.len);
    // dp[i][k]: the cuts of the first i letters into k nonempty pieces.
    let mut dp = vec![vec![ring.zero(); m + 1]; m + 1];
    dp[0][0] = ring.one();
    for i in 1..=m {
        for l in 0..i {
            let piece = &p[&w.slice(l, i)];
            if ring.is_zero(piece) {
                continue;
            }
            for k in 1..=l + 1 {
                if ring.is_zero(&dp[l][k - 1]) {
                    continue;
                }
                let term = ring.mul(&dp[l][k - 1], piece);
                dp[i][k] = ring.add(&dp[i][k], &term);
            }
        }
    }
    let mut out = ring.zero();
    for (k, v) in dp[m].iter().enumerate().skip(1) {
        if ring.is_zero(v) {
            continue;
        }
        let sign = if k % 2 == 1 { 1 } else { -1 };
        out = ring.add(
            &out,
            &ring.scale(v, &BigRational::new(sign.into(), BigInt::from(k))),
        );
    }
    out
}

/// The products [`log_coefficient`] needs for a word of `m` letters, at most.
pub(crate) fn log_work(m: usize) -> u64 {
    let m = m as u64;
    m * (m + 1) * (m + 2) / 6
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64, d: i64) -> Number {
        Number::ratio(n, d).unwrap()
    }

    /// exp(A) exp(B): log = A + B + ½[A,B] + (1/12)([A,[A,B]] + [B,[B,A]]) + …
    /// (Baker–Campbell–Hausdorff), checked word by word.
    #[test]
    fn baker_campbell_hausdorff() {
        let ops = [
            Factor::Letter(0, Number::one()),
            Factor::Letter(1, Number::one()),
        ];
        let degrees = [3, 3, 3];
        let p = product_of_exponentials(&ops, &degrees);
        let w = |l: &[u8]| Word::from_letters(l);
        assert_eq!(p[&w(&[0, 1])], q(1, 1));
        assert_eq!(p[&w(&[1, 0])], q(0, 1));
        assert_eq!(p[&w(&[0, 0, 1])], q(1, 2));
        assert_eq!(log_coefficient(&p, w(&[0])), q(1, 1));
        assert_eq!(log_coefficient(&p, w(&[0, 1])), q(1, 2));
        assert_eq!(log_coefficient(&p, w(&[1, 0])), q(-1, 2));
        // (1/12)[A,[A,B]] = (1/12)(AAB − 2ABA + BAA); (1/12)[B,[B,A]] =
        // (1/12)(BBA − 2BAB + ABB).
        assert_eq!(log_coefficient(&p, w(&[0, 0, 1])), q(1, 12));
        assert_eq!(log_coefficient(&p, w(&[0, 1, 0])), q(-1, 6));
        assert_eq!(log_coefficient(&p, w(&[0, 1, 1])), q(1, 12));
        assert_eq!(log_coefficient(&p, w(&[1, 0, 1])), q(-1, 6));
        // A, A², A³; B and the 2 + 3 words with one B; B², AB², BAB, B²A.
        assert_eq!(word_count(&degrees), 3 + 6 + 4);
    }

    /// A truncated product agrees with the full one on the words it keeps.
    #[test]
    fn truncation_is_exact_on_kept_words() {
        let ops = [
            Factor::Letter(0, q(1, 3)),
            Factor::Letter(1, q(1, 2)),
            Factor::Letter(0, q(1, 3)),
            Factor::Letter(1, q(1, 2)),
            Factor::Letter(0, q(1, 3)),
        ];
        let full = product_of_exponentials(&ops, &[6; 7]);
        let cut = product_of_exponentials(&ops, &[6, 6, 4, 3]);
        for (w, v) in &cut {
            assert_eq!(&full[w], v, "{}", w.label());
            assert_eq!(log_coefficient(&full, *w), log_coefficient(&cut, *w));
        }
        assert!(cut.len() < full.len());
    }

    fn w(l: &[u8]) -> Word {
        Word::from_letters(l)
    }

    /// A gradient kick with gradient 0 is the plain kick: the general
    /// product (exponential of `E`, then `P·exp(E)`) agrees with the fast
    /// path of the letter on every kept word, to degree 8.
    #[test]
    fn a_zero_gradient_is_the_plain_kick() {
        let degrees = [8, 8, 6, 5, 4];
        let plain = [
            Factor::Letter(0, q(1, 3)),
            Factor::Letter(1, q(3, 4)),
            Factor::Letter(0, q(2, 3)),
            Factor::Letter(1, q(1, 4)),
        ];
        let gradient = [
            Factor::Letter(0, q(1, 3)),
            Factor::Gradient {
                kick: q(3, 4),
                gradient: Number::zero(),
            },
            Factor::Letter(0, q(2, 3)),
            Factor::Gradient {
                kick: q(1, 4),
                gradient: Number::zero(),
            },
        ];
        let a = product_of_exponentials(&plain, &degrees);
        let b = product_of_exponentials(&gradient, &degrees);
        assert_eq!(a.len(), b.len());
        for (word, x) in &a {
            assert_eq!(&b[word], x, "{}", word.label());
        }
    }

    /// `exp(g·[B,[A,B]])` alone: its logarithm is `g·(2·BAB − BBA − ABB)`,
    /// nothing else up to degree 7 (the exponential's square `g²·C²/2` of
    /// degree 6 cancels in the logarithm).
    #[test]
    fn a_pure_gradient_factor_is_the_double_bracket() {
        let g = q(2, 7);
        let ops = [Factor::Gradient {
            kick: Number::zero(),
            gradient: g.clone(),
        }];
        let degrees = [7, 7, 7, 7, 7];
        let p = product_of_exponentials(&ops, &degrees);
        // exp(E)[w] directly: E²/2 has (BAB)(BAB) with coefficient (2g)²/2.
        assert_eq!(p[&w(&[1, 0, 1, 1, 0, 1])], &(&g * &g) * &q(2, 1));
        assert_eq!(p[&w(&[0, 1, 1, 0, 1, 1])], &(&g * &g) * &q(1, 2));
        assert_eq!(p[&w(&[1])], Number::zero());
        for n in 1..=7 {
            for j in 0..=4 {
                for word in words_with(n, j) {
                    let expected = match word.letters().as_slice() {
                        [1, 0, 1] => &g + &g,
                        [1, 1, 0] | [0, 1, 1] => -&g,
                        _ => Number::zero(),
                    };
                    assert_eq!(log_coefficient(&p, word), expected, "{}", word.label());
                }
            }
        }
    }

    /// Strang with a gradient kick, `exp(A/2) exp(B + g·[B,[A,B]]) exp(A/2)`:
    /// `log = A + B − (1/24)[A,[A,B]] + (g − 1/12)[B,[A,B]] + O(h⁵)` (the
    /// symmetric Baker–Campbell–Hausdorff formula: the plain Strang splitting
    /// has `−(1/12)[B,[A,B]] = (1/12)[B,[B,A]]`, the sign of the test above).
    /// With `[B,[A,B]] = 2·BAB − BBA − ABB`, the Lyndon coefficient of `AB²`
    /// is `1/12 − g`: `1/12`, `1/24`, `0` for `g = 0, 1/24, 1/12`; the `εh³`
    /// term `AAB` stays `−1/24`, and the degree-4 terms vanish (symmetric).
    #[test]
    fn strang_with_a_gradient_kick() {
        for (g, abb) in [
            (q(0, 1), q(1, 12)),
            (q(1, 24), q(1, 24)),
            (q(1, 12), q(0, 1)),
        ] {
            let ops = [
                Factor::Letter(0, q(1, 2)),
                Factor::Gradient {
                    kick: Number::one(),
                    gradient: g.clone(),
                },
                Factor::Letter(0, q(1, 2)),
            ];
            let p = product_of_exponentials(&ops, &[4, 4, 4, 4]);
            assert_eq!(log_coefficient(&p, w(&[0])), q(1, 1));
            assert_eq!(log_coefficient(&p, w(&[1])), q(1, 1));
            assert_eq!(log_coefficient(&p, w(&[0, 1])), q(0, 1));
            assert_eq!(log_coefficient(&p, w(&[0, 0, 1])), q(-1, 24), "g = {g}");
            assert_eq!(log_coefficient(&p, w(&[0, 1, 1])), abb, "g = {g}");
            // The other words of the same Lie element: BAB = 2(g − 1/12),
            // BBA = 1/12 − g.
            let two = q(2, 1);
            assert_eq!(
                log_coefficient(&p, w(&[1, 0, 1])),
                &two * &(&g - &q(1, 12)),
                "g = {g}"
            );
            assert_eq!(log_coefficient(&p, w(&[1, 1, 0])), abb, "g = {g}");
            for word in [&[0, 0, 0, 1][..], &[0, 0, 1, 1], &[0, 1, 1, 1]] {
                assert_eq!(log_coefficient(&p, w(word)), q(0, 1), "g = {g}");
            }
        }
    }
}
