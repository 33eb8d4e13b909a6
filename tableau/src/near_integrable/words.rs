//! Words in the two letters `A` (the integrable part, a drift) and `B` (the
//! perturbation, a kick), Lyndon words and their standard bracketing.
//!
//! A word is stored as its length and a bit mask (bit `i` set when letter
//! `i`, counted from the left, is `B`); with `A < B` the Lyndon words are the
//! words strictly smaller than each of their proper suffixes. Each Lyndon
//! word `w` has a standard bracketing `P_w` (Lyndon basis of the free Lie
//! algebra), and `P_w = w + (lexicographically larger words)` (Reutenauer,
//! *Free Lie Algebras*, Thm 5.1). So a Lie polynomial is zero exactly when
//! its coefficients on the Lyndon words are zero: the matrix from the Lyndon
//! basis to these coefficients is unitriangular. This is why the verifier
//! tests only Lyndon words, and why each condition can be named by a Lie
//! element, the bracket `P_w` whose leading word is `w`.

/// A word of at most 32 letters (the verifier stops at
/// [`super::MAX_NEAR_DEGREE`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct Word {
    pub len: u8,
    /// Bit `i`: letter `i` is `B`.
    pub bits: u32,
}

impl Word {
    pub const EMPTY: Word = Word { len: 0, bits: 0 };

    pub fn letter(&self, i: usize) -> u8 {
        u8::from(self.bits >> i & 1 == 1)
    }

    pub fn letters(&self) -> Vec<u8> {
        (0..usize::from(self.len)).map(|i| self.letter(i)).collect()
    }

    pub fn from_letters(letters: &[u8]) -> Word {
        let mut bits = 0;
        for (i, &l) in letters.iter().enumerate() {
            if l == 1 {
                bits |= 1 << i;
            }
        }
        Word {
            len: u8::try_from(letters.len()).expect("words stay short"),
            bits,
        }
    }

    /// The number of `B`s.
    pub fn bs(&self) -> usize {
        self.bits.count_ones() as usize
    }

    /// Letters `start..end`.
    pub fn slice(&self, start: usize, end: usize) -> Word {
        let len = end - start;
        let mask = if len == 32 {
            u32::MAX
        } else {
            (1u32 << len) - 1
        };
        Word {
            len: u8::try_from(len).expect("words stay short"),
            bits: (self.bits >> start) & mask,
        }
    }

    /// `self` followed by `other` (at most 32 letters in all).
    pub fn concat(&self, other: &Word) -> Word {
        let len = usize::from(self.len) + usize::from(other.len);
        assert!(len <= 32, "words stay short");
        Word {
            len: u8::try_from(len).expect("words stay short"),
            bits: self.bits | other.bits.checked_shl(u32::from(self.len)).unwrap_or(0),
        }
    }

    /// The word without its last `r` letters.
    pub fn drop_last(&self, r: usize) -> Word {
        self.slice(0, usize::from(self.len) - r)
    }

    /// How many of the last letters equal `letter` (the trailing run).
    pub fn trailing_run(&self, letter: u8) -> usize {
        (0..usize::from(self.len))
            .rev()
            .take_while(|&i| self.letter(i) == letter)
            .count()
    }

    /// `A²B` style, runs written as powers.
    pub fn label(&self) -> String {
        run_label(&self.letters())
    }
}

fn superscript(n: usize) -> String {
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    n.to_string()
        .bytes()
        .map(|b| SUP[usize::from(b - b'0')])
        .collect()
}

fn run_label(letters: &[u8]) -> String {
    let mut out = String::new();
    let mut i = 0;
    while i < letters.len() {
        let run = letters[i..]
            .iter()
            .take_while(|&&x| x == letters[i])
            .count();
        out.push(if letters[i] == 0 { 'A' } else { 'B' });
        if run > 1 {
            out.push_str(&superscript(run));
        }
        i += run;
    }
    out
}

/// Whether `letters` is a Lyndon word: nonempty and strictly smaller than
/// each of its proper suffixes (a proper prefix counts as smaller).
pub(crate) fn is_lyndon(letters: &[u8]) -> bool {
    !letters.is_empty() && (1..letters.len()).all(|i| letters < &letters[i..])
}

/// The standard bracketing of a Lyndon word: `[P_u, P_v]` with `v` the
/// longest proper suffix that is a Lyndon word; a letter is itself.
pub(crate) fn bracket(letters: &[u8]) -> String {
    if letters.len() == 1 {
        return if letters[0] == 0 { "A" } else { "B" }.to_string();
    }
    let split = (1..letters.len())
        .find(|&i| is_lyndon(&letters[i..]))
        .expect("the last letter is a Lyndon suffix");
    format!(
        "[{},{}]",
        bracket(&letters[..split]),
        bracket(&letters[split..])
    )
}

/// Every word with `j` letters `B` and `n` letters in all, in lexicographic
/// order (`A < B`).
pub(crate) fn words_with(n: usize, j: usize) -> Vec<Word> {
    fn go(n: usize, j: usize, prefix: &mut Vec<u8>, out: &mut Vec<Word>) {
        let used: usize = prefix.iter().map(|&x| usize::from(x)).sum();
        if prefix.len() == n {
            if used == j {
                out.push(Word::from_letters(prefix));
            }
            return;
        }
        let left = n - prefix.len();
        for letter in [0u8, 1] {
            let after = used + usize::from(letter);
            if after <= j && after + left > j {
                prefix.push(letter);
                go(n, j, prefix, out);
                prefix.pop();
            }
        }
    }
    let mut out = Vec::new();
    if j <= n {
        go(n, j, &mut Vec::with_capacity(n), &mut out);
    }
    out
}

/// `C(n, k)`, saturating.
pub(crate) fn binomial(n: usize, k: usize) -> u64 {
    if k > n {
        return 0;
    }
    let k = k.min(n - k);
    let mut out: u64 = 1;
    for i in 0..k {
        out = out.saturating_mul((n - i) as u64) / (i as u64 + 1);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lyndon_words_and_brackets() {
        assert!(is_lyndon(&[0, 1]));
        assert!(is_lyndon(&[0, 0, 1]));
        assert!(is_lyndon(&[0, 1, 1]));
        assert!(!is_lyndon(&[1, 0]));
        assert!(!is_lyndon(&[0, 1, 0, 1]));
        assert!(is_lyndon(&[0, 0, 1, 0, 1]));
        assert_eq!(bracket(&[0, 0, 1]), "[A,[A,B]]");
        assert_eq!(bracket(&[0, 1, 1]), "[[A,B],B]");
        assert_eq!(bracket(&[0, 0, 1, 0, 1]), "[[A,[A,B]],[A,B]]");
        // Witt's formula: the Lyndon words with n letters, j of them B.
        for (n, j, count) in [
            (4, 1, 1),
            (4, 2, 1),
            (5, 2, 2),
            (6, 2, 2),
            (6, 3, 3),
            (7, 3, 5),
        ] {
            let lyndon = words_with(n, j)
                .iter()
                .filter(|w| is_lyndon(&w.letters()))
                .count();
            assert_eq!(lyndon, count, "n = {n}, j = {j}");
        }
    }

    #[test]
    fn words_and_labels() {
        assert_eq!(words_with(4, 2).len(), 6);
        assert_eq!(binomial(10, 3), 120);
        let w = Word::from_letters(&[0, 0, 1, 1, 0]);
        assert_eq!(w.label(), "A²B²A");
        assert_eq!(w.bs(), 2);
        assert_eq!(w.trailing_run(0), 1);
        assert_eq!(w.drop_last(1).label(), "A²B²");
        assert_eq!(w.slice(1, 4).label(), "AB²");
    }
}
