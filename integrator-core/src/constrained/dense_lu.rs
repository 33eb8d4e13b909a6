//! A dense LU factorisation (faer, partial pivoting) in storage made once,
//! for the Newton matrix of the stages and for `G M⁻¹ Gᵀ`.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{Mat, MatMut, Par};

pub(crate) struct DenseLu {
    n: usize,
    lu: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: MemBuffer,
}

impl DenseLu {
    pub fn new(n: usize) -> Self {
        let req = StackReq::any_of(&[
            factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default()),
            solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
        ]);
        DenseLu {
            n,
            lu: Mat::zeros(n, n),
            perm: vec![0; n],
            perm_inv: vec![0; n],
            mem: MemBuffer::new(req),
        }
    }

    /// Set entry `(i, j)` of the matrix to be factorised.
    #[inline]
    pub fn set(&mut self, i: usize, j: usize, x: f64) {
        self.lu[(i, j)] = x;
    }

    pub fn clear(&mut self) {
        self.lu.fill(0.0);
    }

    /// Factorise in place. Returns the index of the first pivot that is
    /// zero, non-finite, or below `rel·max|Aᵢⱼ|` (a matrix singular to
    /// working precision), or `None` when every pivot is sound.
    pub fn factor(&mut self, rel: f64) -> Option<usize> {
        let n = self.n;
        let mut big: f64 = 0.0;
        for j in 0..n {
            for i in 0..n {
                big = big.max(self.lu[(i, j)].abs());
            }
        }
        factor::lu_in_place(
            self.lu.as_mut(),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        );
        (0..n).find(|&k| {
            let u = self.lu[(k, k)];
            !u.is_finite() || u.abs() <= rel * big
        })
    }

    /// Solve in place with the factorisation (after a successful `factor`).
    pub fn solve(&mut self, rhs: &mut [f64]) {
        let n = self.n;
        let perm = PermRef::new_checked(&self.perm, &self.perm_inv, n);
        solve::solve_in_place(
            self.lu.as_ref(),
            self.lu.as_ref(),
            perm,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            Par::Seq,
            MemStack::new(&mut self.mem),
        );
    }
}
