//! The sparse symmetric positive-definite linear algebra of the layer: the
//! upper triangle of a matrix on a fixed pattern, and faer's sparse
//! Cholesky with its symbolic analysis done once.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};

use super::MinimiseError;

/// The upper triangle (row ≤ column) of an `n × n` symmetric matrix whose
/// nonzeros are those of a given pattern plus the whole diagonal, in CSC
/// order, and where each entry of the pattern goes.
#[derive(Clone, Debug)]
pub struct UpperPattern {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// For each entry of the pattern: its position among the upper values,
    /// or `usize::MAX` for an entry below the diagonal (ignored).
    dest: Vec<usize>,
    /// The positions of the diagonal entries among the upper values.
    diag: Vec<usize>,
}

impl UpperPattern {
    /// The upper structure of `pattern` (positions `(row, column)`: the full
    /// symmetric pattern or its upper triangle; entries below the diagonal
    /// are ignored, repeated ones are summed) with the diagonal added.
    ///
    /// # Panics
    /// If an entry lies outside `n × n`.
    pub fn new(n: usize, pattern: &[(usize, usize)]) -> UpperPattern {
        let mut entries: Vec<(usize, usize)> = pattern
            .iter()
            .map(|&(r, c)| {
                assert!(
                    r < n && c < n,
                    "Hessian pattern entry ({r}, {c}) outside {n} × {n}"
                );
                (c, r)
            })
            .filter(|&(c, r)| r <= c)
            .chain((0..n).map(|k| (k, k)))
            .collect();
        entries.sort_unstable();
        entries.dedup();
        let mut col_ptr = vec![0usize; n + 1];
        for &(c, _) in &entries {
            col_ptr[c + 1] += 1;
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let row_idx: Vec<usize> = entries.iter().map(|e| e.1).collect();
        let dest = pattern
            .iter()
            .map(|&(r, c)| {
                if r > c {
                    usize::MAX
                } else {
                    entries
                        .binary_search(&(c, r))
                        .expect("every upper entry is in the structure")
                }
            })
            .collect();
        let diag = (0..n)
            .map(|k| entries.binary_search(&(k, k)).expect("the diagonal"))
            .collect();
        UpperPattern {
            n,
            col_ptr,
            row_idx,
            dest,
            diag,
        }
    }

    /// The order `n`.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The number of upper values.
    pub fn len(&self) -> usize {
        self.row_idx.len()
    }

    /// Whether there are no values (`n = 0`).
    pub fn is_empty(&self) -> bool {
        self.row_idx.is_empty()
    }

    /// `upper = Σ pattern values` (entries below the diagonal skipped) and
    /// `diagonal[k]` added on the diagonal.
    pub fn assemble(
        &self,
        pattern_values: &[f64],
        diagonal: impl Fn(usize) -> f64,
        upper: &mut [f64],
    ) {
        upper.fill(0.0);
        for (&d, &v) in self.dest.iter().zip(pattern_values) {
            if d != usize::MAX {
                upper[d] += v;
            }
        }
        for (k, &d) in self.diag.iter().enumerate() {
            upper[d] += diagonal(k);
        }
    }
}

/// faer's sparse Cholesky `LLᵀ` on an [`UpperPattern`]: the symbolic
/// analysis (AMD ordering) and the scratch of factorisation and solves
/// (up to `columns` right-hand sides) once, at construction.
pub struct SparseLlt {
    symbolic: SymbolicSparseColMat<usize>,
    cholesky: SymbolicCholesky<usize>,
    mem: MemBuffer,
    par: Par,
}

impl SparseLlt {
    /// Analyse `pattern`. `par`: faer's parallelism for the numeric
    /// factorisation and the solves.
    pub fn new(pattern: &UpperPattern, columns: usize, par: Par) -> SparseLlt {
        let n = pattern.n;
        let symbolic = SymbolicSparseColMat::new_checked(
            n,
            n,
            pattern.col_ptr.clone(),
            None,
            pattern.row_idx.clone(),
        );
        let cholesky = factorize_symbolic_cholesky(
            symbolic.as_ref(),
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .expect("the symbolic Cholesky of a valid pattern");
        let mem = MemBuffer::new(StackReq::any_of(&[
            cholesky.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
            cholesky.solve_in_place_scratch::<f64>(columns.max(1), par),
        ]));
        SparseLlt {
            symbolic,
            cholesky,
            mem,
            par,
        }
    }

    /// The length of a factor's values.
    pub fn factor_len(&self) -> usize {
        self.cholesky.len_val()
    }

    /// Factorise the matrix with the upper values `upper` into `factor`
    /// (of [`factor_len`](Self::factor_len)). Allocates nothing.
    pub fn factor(&mut self, upper: &[f64], factor: &mut [f64]) -> Result<(), MinimiseError> {
        let matrix = SparseColMatRef::new(self.symbolic.as_ref(), upper);
        self.cholesky
            .factorize_numeric_llt(
                factor,
                matrix,
                Side::Upper,
                LltRegularization::default(),
                self.par,
                MemStack::new(&mut self.mem),
                Default::default(),
            )
            .map(|_| ())
            .map_err(|e| match e {
                LltError::NonPositivePivot { index } => MinimiseError::NotDefinite { pivot: index },
            })
    }

    /// Solve in place with `factor` for the `columns` column-major
    /// right-hand sides in `rhs` (`n × columns`). Allocates nothing.
    pub fn solve(&mut self, factor: &[f64], rhs: &mut [f64], columns: usize) {
        let n = self.symbolic.nrows();
        LltRef::new(&self.cholesky, factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, columns),
            self.par,
            MemStack::new(&mut self.mem),
        );
    }
}
