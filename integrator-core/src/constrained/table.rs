//! The Lobatto IIIA–IIIB pair in the form the constrained step needs,
//! read from the tables `tableau` proves.

use crate::library::{LobattoIIIAIIIB3, StormerVerlet};

// The tables' claims are proven exactly at compile time by `butcher!`
// (catalogue files `stormer-verlet` and `lobatto3a3b-3`); these assertions
// tie the constrained step to those verdicts, so a catalogue edit that lost
// them would stop the build here.
const _: () = assert!(StormerVerlet::SYMPLECTIC && StormerVerlet::SYMMETRIC);
const _: () = assert!(StormerVerlet::ORDER == 2 && StormerVerlet::STAGES == 2);
const _: () = assert!(LobattoIIIAIIIB3::SYMPLECTIC && LobattoIIIAIIIB3::SYMMETRIC);
const _: () = assert!(LobattoIIIAIIIB3::ORDER == 4 && LobattoIIIAIIIB3::STAGES == 3);

/// A partitioned pair `(A, b)` for `q`, `(Â, b̂)` for `p` with the structure
/// of the Lobatto IIIA–IIIB family, which is what makes the constrained
/// step well defined:
///
/// - the first row of `A` vanishes, so the first stage is `Q₁ = q₀`, which
///   satisfies `g = 0` already (no equation for it);
/// - the last row of `A` equals `b`, so the last stage is `Q_s = q₁`, and
///   `g(Q_s) = 0` puts the new position on the manifold;
/// - the last column of `Â` vanishes, so the last multiplier `Λ_s` does not
///   enter the stages; it is fixed by the hidden constraint
///   `G(q₁)M⁻¹p₁ = 0` alone (the velocity step);
/// - `b = b̂`.
///
/// With `s` stages there are `s·m` multipliers and `s·m` conditions:
/// `g(Qᵢ) = 0` for `i = 2..s` and the hidden constraint at the end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobattoPair<const S: usize> {
    /// A name for messages.
    pub name: &'static str,
    pub a: [[f64; S]; S],
    pub a_hat: [[f64; S]; S],
    pub b: [f64; S],
    /// The classical order of the pair, as proven by the verifier (also its
    /// order on the constraint manifold, Jay 1996: `2s − 2`).
    pub order: usize,
}

/// A table that lacks the structure above, naming the entry.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("the pair `{name}` cannot step a constrained system: {reason}")]
pub struct PairStructureError {
    pub name: &'static str,
    pub reason: String,
}

impl<const S: usize> LobattoPair<S> {
    /// Check the structure (see the type's documentation).
    pub fn new(
        name: &'static str,
        a: [[f64; S]; S],
        b: [f64; S],
        a_hat: [[f64; S]; S],
        b_hat: [f64; S],
        order: usize,
    ) -> Result<Self, PairStructureError> {
        let fail = |reason: String| Err(PairStructureError { name, reason });
        if S < 2 {
            return fail(format!("it has {S} stage(s); the Lobatto pairs have s ≥ 2"));
        }
        if let Some(j) = (0..S).find(|&j| a[0][j] != 0.0) {
            return fail(format!(
                "A[0][{j}] = {} (the first row of A must vanish)",
                a[0][j]
            ));
        }
        if let Some(j) = (0..S).find(|&j| a[S - 1][j] != b[j]) {
            return fail(format!(
                "A[{}][{j}] = {} ≠ b[{j}] = {} (the last row of A must equal b)",
                S - 1,
                a[S - 1][j],
                b[j]
            ));
        }
        if let Some(i) = (0..S).find(|&i| a_hat[i][S - 1] != 0.0) {
            return fail(format!(
                "Â[{i}][{}] = {} (the last column of Â must vanish)",
                S - 1,
                a_hat[i][S - 1]
            ));
        }
        if let Some(j) = (0..S).find(|&j| b[j] != b_hat[j]) {
            return fail(format!("b[{j}] = {} ≠ b̂[{j}] = {}", b[j], b_hat[j]));
        }
        if b[S - 1] == 0.0 {
            return fail("b[s−1] = 0 (the last multiplier would not enter p₁)".into());
        }
        Ok(LobattoPair {
            name,
            a,
            a_hat,
            b,
            order,
        })
    }

    /// `(AÂ)ᵢₖ = Σⱼ aᵢⱼ âⱼₖ`: how the momentum of stage `k`'s force enters
    /// the position of stage `i` (times `h²`).
    pub(crate) fn a_a_hat(&self) -> [[f64; S]; S] {
        let mut out = [[0.0; S]; S];
        for (i, row) in out.iter_mut().enumerate() {
            for (k, x) in row.iter_mut().enumerate() {
                *x = (0..S).map(|j| self.a[i][j] * self.a_hat[j][k]).sum();
            }
        }
        out
    }

    /// The row sums of `A`, `cᵢ = Σⱼ aᵢⱼ`.
    pub(crate) fn c(&self) -> [f64; S] {
        let mut c = [0.0; S];
        for (i, ci) in c.iter_mut().enumerate() {
            *ci = self.a[i].iter().sum();
        }
        c
    }
}

/// RATTLE: the Lobatto IIIA–IIIB pair with s = 2, read from the catalogue's
/// `stormer-verlet` (which is that pair: `A = [[0, 0], [½, ½]]`,
/// `Â = [[½, 0], [½, 0]]`, `b = b̂ = (½, ½)`; proven symplectic, symmetric,
/// order 2).
pub fn rattle() -> LobattoPair<2> {
    LobattoPair::new(
        "RATTLE (Lobatto IIIA–IIIB, s = 2)",
        StormerVerlet::A,
        StormerVerlet::B,
        StormerVerlet::A_HAT,
        StormerVerlet::B_HAT,
        StormerVerlet::ORDER,
    )
    .expect("the catalogue's s = 2 pair has the Lobatto IIIA–IIIB structure")
}

/// The Lobatto IIIA–IIIB pair with s = 3 (order 4), read from the
/// catalogue's `lobatto3a3b-3` (proven symplectic, symmetric, order 4).
pub fn lobatto3a3b3() -> LobattoPair<3> {
    LobattoPair::new(
        "Lobatto IIIA–IIIB, s = 3",
        LobattoIIIAIIIB3::A,
        LobattoIIIAIIIB3::B,
        LobattoIIIAIIIB3::A_HAT,
        LobattoIIIAIIIB3::B_HAT,
        LobattoIIIAIIIB3::ORDER,
    )
    .expect("the catalogue's s = 3 pair has the Lobatto IIIA–IIIB structure")
}
