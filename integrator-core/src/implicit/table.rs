//! The description of an implicit table that the stage solver works from.

/// How the coefficient matrix is structured; decides how the stage
/// equations are solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Structure {
    /// Lower triangular `A` (and `Â`): the stages are solved one after the
    /// other, each a system of size `d`, with one factorisation of
    /// `I − h·aᵢᵢ·J` per distinct diagonal value (none for a zero diagonal
    /// entry: that stage is explicit).
    Dirk,
    /// Lower triangular with one diagonal value: stage by stage, one
    /// factorisation for all stages. (Solved exactly like [`Dirk`](Self::Dirk);
    /// the solver finds the distinct diagonal values itself.)
    Sdirk,
    /// Fully implicit: the `s` stages are solved together, one system of
    /// size `s·d`.
    Full,
}

/// An implicit Runge–Kutta table, or a partitioned pair, in `f64`:
/// what `butcher!` emits for every implicit table (as a constant) and what
/// [`step`](super::step) solves.
///
/// For a pair, the state is `z = [q; p]`: the first half of the components
/// is advanced with `(a, b)`, the second half with `a_hat = (Â, b̂)`.
/// `c` are the time abscissae of the stages (used for non-autonomous
/// systems and for the extrapolated starting values).
///
/// `structure` is a promise that only makes solving cheaper: the
/// stage-by-stage path is taken only where `A` (and `Â`) really are lower
/// triangular, so a wrong promise costs speed, never correctness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImplicitTable<const S: usize> {
    pub a: [[f64; S]; S],
    pub b: [f64; S],
    pub c: [f64; S],
    pub a_hat: Option<([[f64; S]; S], [f64; S])>,
    pub structure: Structure,
}

impl<const S: usize> ImplicitTable<S> {
    /// A Runge–Kutta table; the structure is read off `a`.
    pub const fn new(a: [[f64; S]; S], b: [f64; S], c: [f64; S]) -> Self {
        let structure = structure_of(&a, None);
        ImplicitTable {
            a,
            b,
            c,
            a_hat: None,
            structure,
        }
    }

    /// A partitioned pair: `(a, b)` for `q`, `(a_hat, b_hat)` for `p`.
    pub const fn partitioned(
        a: [[f64; S]; S],
        b: [f64; S],
        a_hat: [[f64; S]; S],
        b_hat: [f64; S],
        c: [f64; S],
    ) -> Self {
        let structure = structure_of(&a, Some(&a_hat));
        ImplicitTable {
            a,
            b,
            c,
            a_hat: Some((a_hat, b_hat)),
            structure,
        }
    }

    /// The same table with another structure (e.g. [`Structure::Full`] to
    /// solve a DIRK table's stages together, for comparison).
    pub const fn with_structure(mut self, structure: Structure) -> Self {
        self.structure = structure;
        self
    }

    /// `A` (and `Â`) vanish above the diagonal.
    pub const fn is_lower_triangular(&self) -> bool {
        let hat = match &self.a_hat {
            Some((a_hat, _)) => Some(a_hat),
            None => None,
        };
        !matches!(structure_of(&self.a, hat), Structure::Full)
    }
}

/// The structure of `A` (and `Â`): [`Structure::Full`] unless both are lower
/// triangular; [`Structure::Sdirk`] when, moreover, the diagonal pairs
/// `(aᵢᵢ, âᵢᵢ)` are all equal and nonzero; [`Structure::Dirk`] otherwise.
pub const fn structure_of<const S: usize>(
    a: &[[f64; S]; S],
    a_hat: Option<&[[f64; S]; S]>,
) -> Structure {
    let mut single_diagonal = true;
    let mut i = 0;
    while i < S {
        let mut j = i + 1;
        while j < S {
            if a[i][j] != 0.0 {
                return Structure::Full;
            }
            if let Some(ah) = a_hat
                && ah[i][j] != 0.0
            {
                return Structure::Full;
            }
            j += 1;
        }
        if a[i][i] != a[0][0] || a[i][i] == 0.0 {
            single_diagonal = false;
        }
        if let Some(ah) = a_hat
            && (ah[i][i] != ah[0][0] || ah[i][i] == 0.0)
        {
            single_diagonal = false;
        }
        i += 1;
    }
    if single_diagonal && S > 0 {
        Structure::Sdirk
    } else {
        Structure::Dirk
    }
}
