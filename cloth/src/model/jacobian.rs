//! The sparse force Jacobian `∂F/∂q`: its layout (pattern and where each
//! spring's blocks go), built on first use, and its values.

use nalgebra::{Matrix3, Vector3};

use super::{ClothModel, PinSpring, Spring};

/// Where the Jacobian blocks of each term go in the value array: a block
/// `(r, c)` is stored column by column, entry `(rr, cc)` at
/// `base + cc·stride + rr`.
#[derive(Clone, Debug, Default)]
pub(super) struct JacobianLayout {
    pub(super) pattern: Vec<(usize, usize)>,
    /// Blocks `aa, ab, ba, bb` as `(base, stride)` pairs.
    pub(super) ff: Vec<[u32; 8]>,
    pub(super) fp: Vec<[u32; 2]>,
    /// Diagonal blocks of all free particles (only with colliders).
    pub(super) diag: Vec<[u32; 2]>,
}

impl JacobianLayout {
    pub(super) fn new(
        n_free: usize,
        ff: &[Spring],
        fp: &[PinSpring],
        with_diag: bool,
    ) -> JacobianLayout {
        // Block coordinates as (column, row).
        let mut blocks: Vec<(u32, u32)> = Vec::with_capacity(4 * ff.len() + fp.len() + n_free);
        for s in ff {
            blocks.extend([(s.a, s.a), (s.b, s.a), (s.a, s.b), (s.b, s.b)]);
        }
        blocks.extend(fp.iter().map(|s| (s.a, s.a)));
        if with_diag {
            blocks.extend((0..n_free as u32).map(|a| (a, a)));
        }
        blocks.sort_unstable();
        blocks.dedup();
        // Rows of each block column, and the scalar offset where it starts.
        let mut col_ptr = vec![0usize; n_free + 1];
        for &(c, _) in &blocks {
            col_ptr[c as usize + 1] += 1;
        }
        for c in 0..n_free {
            col_ptr[c + 1] += col_ptr[c];
        }
        let rows: Vec<u32> = blocks.iter().map(|&(_, r)| r).collect();
        let mut pattern = Vec::with_capacity(9 * blocks.len());
        for c in 0..n_free {
            let col_rows = &rows[col_ptr[c]..col_ptr[c + 1]];
            for cc in 0..3 {
                for &r in col_rows {
                    for rr in 0..3 {
                        pattern.push((3 * r as usize + rr, 3 * c + cc));
                    }
                }
            }
        }
        let locate = |r: u32, c: u32| -> [u32; 2] {
            let (lo, hi) = (col_ptr[c as usize], col_ptr[c as usize + 1]);
            let pos = rows[lo..hi].binary_search(&r).unwrap_or(0);
            [(9 * lo + 3 * pos) as u32, (3 * (hi - lo)) as u32]
        };
        let ff = ff
            .iter()
            .map(|s| {
                let [aa, ab, ba, bb] = [
                    locate(s.a, s.a),
                    locate(s.a, s.b),
                    locate(s.b, s.a),
                    locate(s.b, s.b),
                ];
                [aa[0], aa[1], ab[0], ab[1], ba[0], ba[1], bb[0], bb[1]]
            })
            .collect();
        let fp = fp.iter().map(|s| locate(s.a, s.a)).collect();
        let diag = if with_diag {
            (0..n_free as u32).map(|a| locate(a, a)).collect()
        } else {
            Vec::new()
        };
        JacobianLayout {
            pattern,
            ff,
            fp,
            diag,
        }
    }
}

#[inline]
pub(super) fn add_block(values: &mut [f64], [base, stride]: [u32; 2], m: &Matrix3<f64>, sign: f64) {
    let (base, stride) = (base as usize, stride as usize);
    for cc in 0..3 {
        let col = &mut values[base + cc * stride..base + cc * stride + 3];
        for rr in 0..3 {
            col[rr] += sign * m[(rr, cc)];
        }
    }
}

/// `∂F_a/∂x_b` of a spring with `d = x_b − x_a`: `(k/L)[(1 − L/ℓ) I + (L/ℓ) d̂d̂ᵀ]`;
/// `definite`: with `1 − L/ℓ` clamped at 0 (see
/// [`ClothModel::force_jacobian_values_definite`]).
#[inline]
pub(super) fn spring_block(d: &Vector3<f64>, kl: f64, rest: f64, definite: bool) -> Matrix3<f64> {
    let l = d.norm();
    let dh = d / l;
    let transverse = 1.0 - rest / l;
    let transverse = if definite {
        transverse.max(0.0)
    } else {
        transverse
    };
    Matrix3::from_diagonal_element(kl * transverse) + (dh * dh.transpose()) * (kl * rest / l)
}

impl ClothModel {
    /// The layout, with `values` (one per entry of its pattern) zeroed for
    /// an assembly: the start of every Jacobian-like matrix of the model.
    pub(super) fn cleared_values(&self, values: &mut [f64]) -> &JacobianLayout {
        let jac = self.jac();
        assert_eq!(
            values.len(),
            jac.pattern.len(),
            "values must match the Jacobian pattern"
        );
        values.fill(0.0);
        jac
    }

    /// `values` ← the 3×3 block `block(d, d₁, k/L, L)` of every spring at
    /// its places in the pattern, from zero: `d` the spring's vector at `q`,
    /// `d₁` at `q1` (a pinned end is its pin). The assembly of every
    /// two-configuration matrix (the average vector field's, the discrete
    /// gradient's); colliders add theirs afterwards where they have any.
    pub(super) fn add_spring_blocks(
        &self,
        q: &[f64],
        q1: &[f64],
        values: &mut [f64],
        block: impl Fn(Vector3<f64>, Vector3<f64>, f64, f64) -> Matrix3<f64>,
    ) {
        let jac = self.cleared_values(values);
        let q3 = self.chunks(q);
        let p3 = self.chunks(q1);
        for (s, loc) in self.ff.iter().zip(&jac.ff) {
            let (a, b) = (s.a as usize, s.b as usize);
            let d = Vector3::from(q3[b]) - Vector3::from(q3[a]);
            let d1 = Vector3::from(p3[b]) - Vector3::from(p3[a]);
            let k = block(d, d1, s.kl, s.rest);
            add_block(values, [loc[0], loc[1]], &k, -1.0);
            add_block(values, [loc[2], loc[3]], &k, 1.0);
            add_block(values, [loc[4], loc[5]], &k, 1.0);
            add_block(values, [loc[6], loc[7]], &k, -1.0);
        }
        for (s, &loc) in self.fp.iter().zip(&jac.fp) {
            let pin = Vector3::from(s.pin);
            let d = pin - Vector3::from(q3[s.a as usize]);
            let d1 = pin - Vector3::from(p3[s.a as usize]);
            add_block(values, loc, &block(d, d1, s.kl, s.rest), -1.0);
        }
    }

    /// The sparse layout of the force Jacobian, built on first use: only
    /// implicit methods (and tests) need it, and it costs about 50 times the
    /// memory of the springs (on a 2048 × 2048 grid, about 8 GB), so an
    /// explicit run never builds it.
    pub(super) fn jac(&self) -> &JacobianLayout {
        self.jac.get_or_init(|| {
            JacobianLayout::new(
                self.free_ids.len(),
                &self.ff,
                &self.fp,
                !self.colliders.is_empty(),
            )
        })
    }

    /// Whether the sparse Jacobian layout has been built: only once an
    /// implicit method (or a caller of
    /// [`force_jacobian_pattern`](Self::force_jacobian_pattern) and its
    /// kin) asked for it. An explicit run never does.
    pub fn jacobian_built(&self) -> bool {
        self.jac.get().is_some()
    }

    /// The positions (row, column) of the nonzero entries of the force
    /// Jacobian `∂F/∂q = −∇²V` (`3·free × 3·free`), each once, sorted by
    /// column and then row: the order of a compressed-sparse-column matrix's
    /// values, so a CSC matrix built from this pattern (e.g. faer's
    /// `SparseColMat::try_new_from_triplets`) can take
    /// [`force_jacobian_values`](Self::force_jacobian_values) into its value
    /// array as it is. The structure does not depend on the state; the
    /// blocks are 3×3, one per pair of particles coupled by a spring and one
    /// on the diagonal of every particle with a spring or (when the scene has
    /// colliders) any particle.
    pub fn force_jacobian_pattern(&self) -> Vec<(usize, usize)> {
        self.jac().pattern.clone()
    }

    /// The number of entries of [`force_jacobian_pattern`](Self::force_jacobian_pattern).
    pub fn force_jacobian_nnz(&self) -> usize {
        self.jac().pattern.len()
    }

    /// The values of `∂F/∂q` at `q`, in the order of
    /// [`force_jacobian_pattern`](Self::force_jacobian_pattern). Allocates nothing.
    ///
    /// # Panics
    /// If `values` is not exactly as long as the pattern or `q` shorter than `3·free`.
    pub fn force_jacobian_values(&self, q: &[f64], values: &mut [f64]) {
        self.jacobian_into(q, values, false, false);
    }

    /// [`force_jacobian_values`](Self::force_jacobian_values) with the
    /// transverse term `(k/L)(1 − L/ℓ)` of every compressed spring (`ℓ < L`)
    /// clamped to 0, so that `K = −∂F/∂q` is positive semidefinite (the
    /// springs and gravity; colliders as they are). This is the matrix the
    /// implicit stage solver factorises: a compressed spring makes the exact
    /// `K` indefinite, and then `I + h²M⁻¹K` can be nearly singular at large
    /// `h`, which sends Newton's corrections far off. Newton's method only
    /// needs an approximate Jacobian, so the converged steps are the same;
    /// only the iteration is better behaved (the clamp of Choi and Ko, 2002).
    pub fn force_jacobian_values_definite(&self, q: &[f64], values: &mut [f64]) {
        self.jacobian_into(q, values, true, false);
    }

    /// `−∇²V` projected so that `∇²V` is positive semidefinite, block by
    /// block, in the order of
    /// [`force_jacobian_pattern`](Self::force_jacobian_pattern): each
    /// spring's 3×3 block `(k/L)[(1 − L/ℓ)I + (L/ℓ)d̂d̂ᵀ]` has the
    /// eigenvalues `k/L` (along the spring) and `(k/L)(1 − L/ℓ)` (twice,
    /// across it), and the latter is clamped at 0 — exactly the projection
    /// of the block onto the PSD cone; a sphere collider's tangential term
    /// (negative curvature of `V`) is dropped, the normal term kept; plane
    /// colliders and gravity need nothing. The Hessian of the minimisation
    /// solvers ([`crate::step::minimise`]). Allocates nothing.
    pub fn force_jacobian_values_projected(&self, q: &[f64], values: &mut [f64]) {
        self.jacobian_into(q, values, true, true);
    }

    fn jacobian_into(&self, q: &[f64], values: &mut [f64], definite: bool, project: bool) {
        let jac = self.cleared_values(values);
        let q3 = self.chunks(q);
        for (s, loc) in self.ff.iter().zip(&jac.ff) {
            let d = Vector3::from(q3[s.b as usize]) - Vector3::from(q3[s.a as usize]);
            let k = spring_block(&d, s.kl, s.rest, definite);
            add_block(values, [loc[0], loc[1]], &k, -1.0);
            add_block(values, [loc[2], loc[3]], &k, 1.0);
            add_block(values, [loc[4], loc[5]], &k, 1.0);
            add_block(values, [loc[6], loc[7]], &k, -1.0);
        }
        for (s, &loc) in self.fp.iter().zip(&jac.fp) {
            let d = Vector3::from(s.pin) - Vector3::from(q3[s.a as usize]);
            add_block(values, loc, &spring_block(&d, s.kl, s.rest, definite), -1.0);
        }
        for (x, &loc) in q3.iter().zip(&jac.diag) {
            let x = Vector3::from(*x);
            for c in &self.colliders {
                add_block(values, loc, &c.force_jacobian_projected(&x, project), 1.0);
            }
        }
    }
}
