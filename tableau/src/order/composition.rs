//! Word coefficients of a composition of a symmetric second-order method in
//! the free associative algebra on `Y₁, Y₃, Y₅, …` (see
//! [`composition_order`](super::composition_order)).
//!
//! The product `P_j = E(γ₁)⋯E(γ_j)` is built factor by factor,
//! `P_j[w] = P_{j−1}[w] + Σ_{w = u·v, v ≠ ∅} P_{j−1}[u] · γ_j^weight(v) / length(v)!`,
//! and weight by weight: a word's coefficient needs only its prefixes, of
//! lower weight, so the check can stop at the first weight that fails. The
//! coefficients of every prefix are kept for every `j`.
//!
//! Fraction-free: with `Γ_j = D·γ_j` for a common denominator `D`, the
//! coefficient of a word `w` of weight `n` and length `L` is `N[w] / (Dⁿ L!)`
//! with `N` integral, and the recursion becomes
//! `N_j[w] = N_{j−1}[w] + Σ N_{j−1}[u] · Γ_j^weight(v) · C(L, length(v))`.

use std::collections::HashMap;
use std::ops::{ControlFlow, Range};

use num_bigint::BigInt;
use num_rational::BigRational;

use super::scalar::{Monomials, RadicalPoly, Scalar, common_denominator};
use super::{ConditionKind, Conditions, Pending};
use crate::Number;
use crate::table::Composition;

struct Word {
    letters: Vec<u8>,
    /// For each split `w = u·v` with `v` nonempty: the index of `u` (`None`
    /// for the empty word), the weight of `v`, and `C(length(w), length(v))`.
    splits: Vec<(Option<usize>, usize, BigInt)>,
}

struct WordCoefficients<S> {
    /// `powers[j][k] = Γ_j^k` for `k ≤ top`.
    powers: Vec<Vec<S>>,
    /// `Dⁿ` by `n`.
    den_pows: Vec<BigInt>,
    words: Vec<Word>,
    levels: Vec<Range<usize>>,
    index: HashMap<Vec<u8>, usize>,
    /// `history[w][j]`: `N[w]` in `E(γ₁)⋯E(γ_j)`.
    history: Vec<Vec<S>>,
    monomials: Monomials,
}

fn factorial(n: usize) -> BigInt {
    (1..=n).map(BigInt::from).product()
}

fn binomial(n: usize, k: usize) -> BigInt {
    let mut out = BigInt::from(1);
    for i in 0..k {
        out = out * BigInt::from(n - i) / BigInt::from(i + 1);
    }
    out
}

/// The coefficients of a composition, computed up to weight `top`: integers
/// when every `γ` is rational, integer combinations of radicals otherwise.
pub(crate) fn word_coefficients(composition: &Composition, top: usize) -> Box<dyn Conditions> {
    if composition.gamma.iter().all(Number::is_rational) {
        Box::new(WordCoefficients::<BigInt>::new(composition, top))
    } else {
        Box::new(WordCoefficients::<RadicalPoly>::new(composition, top))
    }
}

impl<S: Scalar> WordCoefficients<S> {
    fn new(composition: &Composition, top: usize) -> Self {
        let den = common_denominator(&composition.gamma);
        let powers = composition
            .gamma
            .iter()
            .map(|g| {
                let g = S::from_number(g, &den);
                let mut out = vec![S::one()];
                for k in 1..=top {
                    out.push(out[k - 1].mul(&g));
                }
                out
            })
            .collect();
        let mut den_pows = vec![BigInt::from(1)];
        for n in 1..=top {
            den_pows.push(&den_pows[n - 1] * &den);
        }
        WordCoefficients {
            powers,
            den_pows,
            words: Vec::new(),
            levels: vec![Range::default()],
            index: HashMap::new(),
            history: Vec::new(),
            monomials: Monomials::default(),
        }
    }

    /// Generate the words of the next weight, sorted by length and then
    /// lexicographically, with their splits.
    fn generate_level(&mut self) {
        let n = self.levels.len();
        let mut new: Vec<Vec<u8>> = Vec::new();
        for last in (1..=n).step_by(2) {
            let rest = n - last;
            let letter = u8::try_from(last).expect("weights stay small");
            if rest == 0 {
                new.push(vec![letter]);
            } else {
                for u in self.levels[rest].clone() {
                    let mut w = self.words[u].letters.clone();
                    w.push(letter);
                    new.push(w);
                }
            }
        }
        new.sort_by(|a, b| a.len().cmp(&b.len()).then_with(|| a.cmp(b)));
        let start = self.words.len();
        for letters in new {
            let len = letters.len();
            let mut splits = Vec::with_capacity(len);
            for i in 0..len {
                let u = (i > 0).then(|| self.index[&letters[..i]]);
                let weight: usize = letters[i..].iter().map(|&x| usize::from(x)).sum();
                splits.push((u, weight, binomial(len, len - i)));
            }
            self.index.insert(letters.clone(), self.words.len());
            self.words.push(Word { letters, splits });
        }
        self.levels.push(start..self.words.len());
    }
}

/// A word with runs written as powers: `Y₁²Y₃`.
fn word_label(letters: &[u8]) -> String {
    const SUB: [char; 10] = ['₀', '₁', '₂', '₃', '₄', '₅', '₆', '₇', '₈', '₉'];
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let digits = |n: usize, table: &[char; 10]| -> String {
        n.to_string()
            .bytes()
            .map(|b| table[usize::from(b - b'0')])
            .collect()
    };
    let mut out = String::new();
    let mut i = 0;
    while i < letters.len() {
        let run = letters[i..]
            .iter()
            .take_while(|&&x| x == letters[i])
            .count();
        out.push('Y');
        out.push_str(&digits(usize::from(letters[i]), &SUB));
        if run > 1 {
            out.push_str(&digits(run, &SUP));
        }
        i += run;
    }
    out
}

impl<S: Scalar> Conditions for WordCoefficients<S> {
    fn level(
        &mut self,
        n: usize,
        f: &mut dyn FnMut(Pending<'_>) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        assert!(
            n < self.den_pows.len(),
            "weight {n} beyond the precomputed powers"
        );
        while self.levels.len() <= n {
            self.generate_level();
        }
        let m = self.powers.len();
        let range = self.levels[n].clone();
        self.history.resize(range.end, Vec::new());
        for w in range {
            let word = &self.words[w];
            let mut hist = Vec::with_capacity(m + 1);
            hist.push(S::zero());
            for j in 1..=m {
                let mut acc = hist[j - 1].clone();
                let powers = &self.powers[j - 1];
                for (u, weight, binom) in &word.splits {
                    let g = &powers[*weight];
                    if g.is_zero() {
                        continue;
                    }
                    match u {
                        None => acc.add_assign(&g.scale(binom)),
                        Some(u) => {
                            let pu = &self.history[*u][j - 1];
                            if !pu.is_zero() {
                                acc.add_assign(&pu.mul(g).scale(binom));
                            }
                        }
                    }
                }
                hist.push(acc);
            }
            let value = hist.pop().expect("m + 1 entries");
            hist.push(value.clone());
            self.history[w] = hist;
            let letters = &self.words[w].letters;
            let powers_of_y1 = letters.iter().all(|&x| x == 1);
            // The target 1/n! for Y₁ⁿ is Dⁿ·n!/n! = Dⁿ in the scaled form.
            let den = &self.den_pows[n];
            let exact = if powers_of_y1 {
                value.is_integer(den)
            } else {
                value.is_zero()
            };
            let expected = if powers_of_y1 {
                Number::from_rational(BigRational::new(1.into(), factorial(n)))
            } else {
                Number::zero()
            };
            let full_den = den * factorial(letters.len());
            let monomials = &self.monomials;
            f(Pending {
                order: n,
                kind: ConditionKind::Word,
                label: &|| word_label(letters),
                value: &|| value.to_number(&full_den, monomials),
                expected,
                exact,
            })?;
        }
        ControlFlow::Continue(())
    }
}

#[cfg(test)]
mod tests {
    use super::word_label;

    #[test]
    fn labels() {
        assert_eq!(word_label(&[5]), "Y₅");
        assert_eq!(word_label(&[1, 1, 3]), "Y₁²Y₃");
        assert_eq!(word_label(&[1, 3, 1]), "Y₁Y₃Y₁");
        assert_eq!(word_label(&[11]), "Y₁₁");
        assert_eq!(word_label(&[1; 12]), "Y₁¹²");
    }
}
