//! Sparse Jacobians (the cloth): `I − h·A⊗J` assembled as a faer
//! `SparseColMat` on a pattern fixed for the run, its symbolic LU computed
//! once per shape, the numeric LU recomputed per new `J` or `h` into storage
//! that is kept.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};

use super::iteration::{Caches, Coefs, Linear, Slot};
use super::settings::{Settings, Stats};
use crate::error::SolveError;
use crate::system::OdeSystem;

/// A system whose Jacobian `∂f/∂z` is sparse, with a sparsity pattern that
/// does not change during a run. Used by [`step_sparse`](super::step_sparse).
pub trait SparseJacobian: OdeSystem {
    /// The positions `(row, column)` of the entries of `∂f/∂z` that may be
    /// nonzero. Asked once per workspace; repeated positions are summed.
    fn jacobian_pattern(&self) -> Vec<(usize, usize)>;
    /// `values[k] = ∂fᵣ/∂z꜀` at `(t, z)` for the `k`-th position `(r, c)` of
    /// the pattern.
    fn jacobian_values(&self, t: f64, z: &[f64], values: &mut [f64]);
}

fn par(settings: &Settings) -> Par {
    if settings.parallel {
        Par::rayon(0)
    } else {
        Par::Seq
    }
}

/// The sparsity structure of `I − h·(C⊗J)` for one coefficient shape, and
/// its symbolic LU.
struct Shape {
    /// The blocks `(i, j)` with a nonzero coefficient.
    blocks: Vec<(usize, usize)>,
    symbolic: SymbolicSparseColMat<usize>,
    /// Where in the values the `e`-th pattern entry of block `b` goes:
    /// `map[b·nnz(J) + e]`.
    map: Vec<usize>,
    /// Where the diagonal entries go.
    diag_map: Vec<usize>,
    lu: SymbolicLu<usize>,
    mem: MemBuffer,
    parallel: bool,
}

impl Shape {
    fn new(
        pattern: &[(usize, usize)],
        d: usize,
        coefs: &Coefs,
        parallel: bool,
    ) -> Result<Self, SolveError> {
        let m = coefs.m;
        let n = m * d;
        let blocks: Vec<(usize, usize)> = (0..m)
            .flat_map(|i| (0..m).map(move |j| (i, j)))
            .filter(|&(i, j)| coefs.q[i * m + j] != 0.0 || coefs.p[i * m + j] != 0.0)
            .collect();
        // (column, row) of every contribution, in assembly order.
        let mut entries: Vec<(usize, usize)> = Vec::with_capacity(blocks.len() * pattern.len() + n);
        for &(i, j) in &blocks {
            entries.extend(pattern.iter().map(|&(r, c)| (j * d + c, i * d + r)));
        }
        entries.extend((0..n).map(|k| (k, k)));
        let mut sorted = entries.clone();
        sorted.sort_unstable();
        sorted.dedup();
        let mut col_ptr = vec![0usize; n + 1];
        for &(c, _) in &sorted {
            col_ptr[c + 1] += 1;
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let row_idx: Vec<usize> = sorted.iter().map(|&(_, r)| r).collect();
        let position = |e: &(usize, usize)| {
            sorted
                .binary_search(e)
                .expect("every entry is in the pattern")
        };
        let nj = blocks.len() * pattern.len();
        let map: Vec<usize> = entries[..nj].iter().map(position).collect();
        let diag_map: Vec<usize> = entries[nj..].iter().map(position).collect();
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let lu = factorize_symbolic_lu(symbolic.as_ref(), Default::default())
            .map_err(|_| SolveError::Singular)?;
        let mem = Self::scratch(&lu, parallel);
        Ok(Shape {
            blocks,
            symbolic,
            map,
            diag_map,
            lu,
            mem,
            parallel,
        })
    }

    fn scratch(lu: &SymbolicLu<usize>, parallel: bool) -> MemBuffer {
        let par = if parallel { Par::rayon(0) } else { Par::Seq };
        MemBuffer::new(StackReq::any_of(&[
            lu.factorize_numeric_lu_scratch::<f64>(par, Default::default()),
            lu.solve_in_place_scratch::<f64>(1, par),
        ]))
    }

    fn nnz(&self) -> usize {
        self.symbolic.row_idx().len()
    }
}

/// One numeric factorisation and what it was made from.
struct SparseLu {
    values: Vec<f64>,
    numeric: NumericLu<usize, f64>,
    valid: bool,
    version: u64,
    h: f64,
    diag: (f64, f64),
}

/// The sparse linear algebra of [`SparseWorkspace`](super::SparseWorkspace).
pub(crate) struct SparseLinear {
    d: usize,
    s: usize,
    pattern: Vec<(usize, usize)>,
    /// Whether `pattern` has been asked for.
    has_pattern: bool,
    /// The Jacobian's values on the pattern.
    jv: Vec<f64>,
    version: u64,
    stamp: u64,
    /// The stage-matrix shape (`m = 1`) and the stacked one (`m = s`).
    shapes: [Option<Shape>; 2],
    /// `s` stage-matrix slots, then the stacked one.
    slots: Vec<Option<SparseLu>>,
}

impl SparseLinear {
    pub fn new(d: usize, s: usize) -> Self {
        SparseLinear {
            d,
            s,
            pattern: Vec::new(),
            has_pattern: false,
            jv: Vec::new(),
            version: 0,
            stamp: 0,
            shapes: [None, None],
            slots: (0..=s).map(|_| None).collect(),
        }
    }

    fn index(&self, slot: Slot) -> (usize, usize) {
        match slot {
            Slot::Stacked => (self.s, 1),
            Slot::Diag(i) => (i, 0),
        }
    }
}

impl<Sys: SparseJacobian + ?Sized> Linear<Sys> for SparseLinear {
    fn probe(
        &mut self,
        _sys: &Sys,
        _t: f64,
        _z: &[f64],
        _attempt: u64,
        _stats: &mut Stats,
    ) -> bool {
        true
    }

    fn evaluate(
        &mut self,
        sys: &Sys,
        t: f64,
        z: &[f64],
        attempt: u64,
        _settings: &Settings,
        stats: &mut Stats,
    ) -> Result<(), SolveError> {
        if !self.has_pattern {
            let d = self.d;
            self.pattern = sys.jacobian_pattern();
            if let Some(&(r, c)) = self.pattern.iter().find(|&&(r, c)| r >= d || c >= d) {
                panic!(
                    "SparseJacobian::jacobian_pattern: entry ({r}, {c}) is outside the {d} × {d} Jacobian"
                );
            }
            self.jv = vec![0.0; self.pattern.len()];
            self.has_pattern = true;
        }
        sys.jacobian_values(t, z, &mut self.jv);
        self.version += 1;
        self.stamp = attempt;
        stats.jacobian_evaluations += 1;
        Ok(())
    }

    fn version(&self) -> u64 {
        self.version
    }

    fn stamp(&self) -> u64 {
        self.stamp
    }

    fn prepare(
        &mut self,
        _sys: &Sys,
        slot: Slot,
        coefs: &Coefs,
        h: f64,
        settings: &Settings,
        stats: &mut Stats,
    ) -> Result<(), SolveError> {
        let d = self.d;
        let (idx, shape_idx) = self.index(slot);
        let diag = match slot {
            Slot::Diag(_) => (coefs.q[0], coefs.p[0]),
            Slot::Stacked => (0.0, 0.0),
        };
        if let Some(lu) = &self.slots[idx]
            && lu.valid
            && lu.version == self.version
            && lu.h.to_bits() == h.to_bits()
            && lu.diag == diag
        {
            return Ok(());
        }
        if self.shapes[shape_idx].is_none() {
            self.shapes[shape_idx] = Some(Shape::new(&self.pattern, d, coefs, settings.parallel)?);
            stats.symbolic_factorizations += 1;
        }
        let shape = self.shapes[shape_idx].as_mut().expect("made above");
        if shape.parallel != settings.parallel {
            shape.mem = Shape::scratch(&shape.lu, settings.parallel);
            shape.parallel = settings.parallel;
        }
        let nnz = shape.nnz();
        let lu = self.slots[idx].get_or_insert_with(|| SparseLu {
            values: vec![0.0; nnz],
            numeric: NumericLu::new(),
            valid: false,
            version: 0,
            h: f64::NAN,
            diag: (f64::NAN, f64::NAN),
        });
        lu.valid = false;
        let values = &mut lu.values;
        values.fill(0.0);
        let nj = self.pattern.len();
        for (b, &(i, j)) in shape.blocks.iter().enumerate() {
            let map = &shape.map[b * nj..(b + 1) * nj];
            for ((&(r, _), &pos), &jv) in self.pattern.iter().zip(map).zip(&self.jv) {
                values[pos] -= h * coefs.get(i, j, r) * jv;
            }
        }
        for &pos in &shape.diag_map {
            values[pos] += 1.0;
        }
        let matrix = SparseColMatRef::new(shape.symbolic.as_ref(), values);
        let factored = shape
            .lu
            .factorize_numeric_lu(
                &mut lu.numeric,
                matrix,
                par(settings),
                MemStack::new(&mut shape.mem),
                Default::default(),
            )
            .is_ok();
        stats.factorizations += 1;
        if !factored {
            return Err(SolveError::Singular);
        }
        lu.valid = true;
        lu.version = self.version;
        lu.h = h;
        lu.diag = diag;
        Ok(())
    }

    fn solve(
        &mut self,
        slot: Slot,
        rhs: &mut [f64],
        settings: &Settings,
    ) -> Result<(), SolveError> {
        let (idx, shape_idx) = self.index(slot);
        let shape = self.shapes[shape_idx]
            .as_mut()
            .expect("prepared before solving");
        let lu = self.slots[idx].as_ref().expect("prepared before solving");
        let n = rhs.len();
        LuRef::new_unchecked(&shape.lu, &lu.numeric).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            par(settings),
            MemStack::new(&mut shape.mem),
        );
        if rhs.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(SolveError::Singular)
        }
    }
}

impl Caches for SparseLinear {
    fn clear(&mut self) {
        // The stacked shape depends on which coefficients vanish.
        self.shapes[1] = None;
        for lu in self.slots.iter_mut().flatten() {
            lu.valid = false;
        }
        self.slots[self.s] = None;
    }

    fn reset(&mut self) {
        self.clear();
        self.version = 0;
        self.stamp = 0;
    }
}
