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
//! true ones: every coefficient kept is exact. This is why the claimed
//! orders must be non-increasing; it also keeps the work far below the full
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

/// The truncation: `degrees[j]` is `D(j)` for `j = 0..=J`.
pub(crate) fn word_count(degrees: &[usize]) -> u64 {
    degrees
        .iter()
        .enumerate()
        .map(|(j, &d)| (1..=d).map(|n| binomial(n, j)).sum::<u64>())
        .sum()
}

/// The coefficients `P[w]` of every word kept by the truncation `degrees`
/// (see [`word_count`]), the empty word included.
pub(crate) fn product_of_exponentials(
    ops: &[(u8, Number)],
    degrees: &[usize],
) -> HashMap<Word, Number> {
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
    let mut p: HashMap<Word, Number> = words.iter().map(|w| (*w, Number::zero())).collect();
    p.insert(Word::EMPTY, Number::one());
    for (letter, x) in ops {
        // x^r / r! for r = 0..=top.
        let mut scaled = vec![Number::one()];
        let mut fact = BigInt::from(1);
        let mut power = Number::one();
        for r in 1..=top {
            power = &power * x;
            fact *= r;
            scaled.push(power.scale(&BigRational::new(1.into(), fact.clone())));
        }
        for w in &words {
            let run = w.trailing_run(*letter);
            if run == 0 {
                continue;
            }
            let mut add = Number::zero();
            for (r, scale) in scaled.iter().enumerate().take(run + 1).skip(1) {
                let pu = &p[&w.drop_last(r)];
                if !pu.is_zero() {
                    add += &(pu * scale);
                }
            }
            if !add.is_zero() {
                *p.get_mut(w).expect("every word is kept") += &add;
            }
        }
    }
    p
}

/// The coefficient of `w` in `log P`, from the coefficients of its factors.
pub(crate) fn log_coefficient(p: &HashMap<Word, Number>, w: Word) -> Number {
    let m = usize::from(w.len);
    // dp[i][k]: the cuts of the first i letters into k nonempty pieces.
    let mut dp = vec![vec![Number::zero(); m + 1]; m + 1];
    dp[0][0] = Number::one();
    for i in 1..=m {
        for l in 0..i {
            let piece = &p[&w.slice(l, i)];
            if piece.is_zero() {
                continue;
            }
            for k in 1..=l + 1 {
                if dp[l][k - 1].is_zero() {
                    continue;
                }
                let term = &dp[l][k - 1] * piece;
                dp[i][k] += &term;
            }
        }
    }
    let mut out = Number::zero();
    for (k, v) in dp[m].iter().enumerate().skip(1) {
        if v.is_zero() {
            continue;
        }
        let sign = if k % 2 == 1 { 1 } else { -1 };
        out += &v.scale(&BigRational::new(sign.into(), BigInt::from(k)));
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
        let ops = [(0u8, Number::one()), (1u8, Number::one())];
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
            (0u8, q(1, 3)),
            (1u8, q(1, 2)),
            (0u8, q(1, 3)),
            (1u8, q(1, 2)),
            (0u8, q(1, 3)),
        ];
        let full = product_of_exponentials(&ops, &[6; 7]);
        let cut = product_of_exponentials(&ops, &[6, 6, 4, 3]);
        for (w, v) in &cut {
            assert_eq!(&full[w], v, "{}", w.label());
            assert_eq!(log_coefficient(&full, *w), log_coefficient(&cut, *w));
        }
        assert!(cut.len() < full.len());
    }
}
