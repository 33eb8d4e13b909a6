//! Isometric bending of the inextensible sheet: a quadratic energy
//! `E = ½·qᵀK·q` (plus terms linear in `q` from the pins) with a constant
//! sparse Hessian, after Bergou, Wardetzky, Harmon, Zorin and Grinspun, *A
//! Quadratic Bending Model for Inextensible Surfaces* (SGP 2006).
//!
//! **The energy.** For a surface bent without stretching, the Willmore-type
//! energy `½·B·∫ (κ₁ + κ₂)² dA` is, by Bergou et al.'s argument, quadratic
//! in the positions: the cotangent Laplacian `L` of a triangle mesh depends
//! only on its metric (edge lengths and angles), which an isometric motion
//! keeps, and `(L·x)_i ≈ A_i·Δ_S x = −A_i·(κ₁ + κ₂)·n` at an interior
//! vertex. So with `L` and the vertex areas `A_i` taken once from the flat
//! rest grid,
//!
//! ```text
//! E(x) = ½·B·Σ_{interior i} |(L·x)_i|² / A_i,   (L·x)_i = Σ_j w_ij·(x_j − x_i),
//! w_ij = ½·(cot α_ij + cot β_ij)
//! ```
//!
//! (`α_ij`, `β_ij` the angles opposite the edge `ij` in its two triangles,
//! `A_i` a third of the area of the triangles around `i`). **Convention:**
//! `B` is the bending rigidity in N·m, the continuum energy is
//! `½·B·∫ (κ₁ + κ₂)² dA = ½·B·∫ (2H)² dA` with `H = (κ₁ + κ₂)/2` the mean
//! curvature; a sheet rolled into a cylinder of radius `R` stores
//! `½·B·A/R²`, the energy per area `½·B·κ²` of a strip bent to curvature
//! `κ`, which is how the Kawabata KES-FB2 tester defines the bending
//! rigidity `B` it reports (moment per unit width = `B·κ`).
//!
//! **Why per vertex, not per edge.** Bergou et al. write the same family
//! of energies edge by edge, `Σ_e 3/A_e·|Σ K_e,i x_i|²` over each interior
//! edge's four-vertex stencil. On this grid's triangulation (every cell cut
//! by the diagonal `(i, j)–(i+1, j+1)`) that form is anisotropic: a sheet
//! rolled into a cylinder curving along a grid line converges to
//! `3·∫(2H)² dA`, one curving along the cut diagonal to `8.9·∫(2H)² dA` and
//! one curving along the other diagonal to `3.0·∫(2H)² dA` (measured with a
//! prototype at 65²). The
//! per-vertex form converges to `∫(2H)² dA` in every direction (0.938 at
//! 33² for all four of those directions: the ring of boundary vertices is
//! left out, see below), so it is the one used here.
//!
//! **Boundary.** Only interior vertices (the full fan of six triangles)
//! contribute: at a boundary vertex `(L·x)_i` is not a curvature (it does
//! not vanish on a flat sheet). Boundary vertices still enter the stencils
//! of their interior neighbours, so bending the outermost row of cells
//! costs energy; the missing half-cell strip along the edges makes the
//! energy of a uniformly curved sheet too small by `O(h)` (`1 −
//! (n−2)²/(n−1)²` of it on an `n × n` sheet).
//!
//! **Pins.** Row `i` of the energy is `v_i = Σ_k a_ik·x_k` with
//! `a_i = √(B/A_i)·(row i of L)`, so `E = ½·Σ_i |v_i|²`, `∇E = Aᵀv`,
//! `K = AᵀA` (times the 3×3 identity). A pinned particle is not an unknown:
//! its term `a_ik·x_k` is a constant of the row, added to `v_i`; a row with
//! no free particle is constant and left out of the energy, as springs
//! between two pins are.

use nalgebra::Vector3;

use super::PINNED;

/// The bending energy's rows: `v_i = fixed_i + Σ coef·q[col]`.
#[derive(Clone, Debug)]
pub(crate) struct Bending {
    /// `B` (N·m).
    stiffness: f64,
    /// Row `r` has entries `ptr[r]..ptr[r + 1]` of `cols`/`coef`.
    ptr: Vec<u32>,
    /// Free index of each entry.
    cols: Vec<u32>,
    /// `a_ik = √(B/A_i)·L_ik` of each entry (√(N·m)/m).
    coef: Vec<f64>,
    /// The pinned particles' part of each row, `Σ_pinned a_ik·x_k`.
    fixed: Vec<[f64; 3]>,
    /// Gershgorin's bound of `λ_max(K)` (N/m), computed once.
    bound: f64,
}

impl Bending {
    /// The bending rows of an `nx × ny` grid of spacing `dx`, `dy` (the
    /// flat rest configuration; the triangulation is the model's, two
    /// triangles per cell cut by `(i, j)–(i+1, j+1)`, as in
    /// [`ClothModel::triangles`](super::ClothModel::triangles)), with the
    /// pinned particles at `start`. `None` when `stiffness` is 0.
    pub(crate) fn new(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        stiffness: f64,
        start: &[Vector3<f64>],
        free_index: &[u32],
    ) -> Option<Bending> {
        if stiffness == 0.0 || nx < 3 || ny < 3 {
            return None;
        }
        let rest = |id: usize| Vector3::new((id % nx) as f64 * dx, (id / nx) as f64 * dy, 0.0);
        // Cotangent weights of every (directed) edge, and vertex areas, from
        // the triangles of the flat grid.
        let n = nx * ny;
        let mut area = vec![0.0; n];
        // Neighbour weights per vertex: a vertex of the grid has at most 6.
        let mut nbr: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        let add = |i: usize, j: usize, w: f64, nbr: &mut Vec<Vec<(usize, f64)>>| {
            if let Some(slot) = nbr[i].iter_mut().find(|(k, _)| *k == j) {
                slot.1 += w;
            } else {
                nbr[i].push((j, w));
            }
        };
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let a = j * nx + i;
                let (b, c, d) = (a + 1, a + nx, a + nx + 1);
                for t in [[a, b, d], [a, d, c]] {
                    let x = t.map(rest);
                    let tri_area = 0.5 * (x[1] - x[0]).cross(&(x[2] - x[0])).norm();
                    for k in 0..3 {
                        let (p, q, o) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                        let (xp, xq, xo) = (x[k], x[(k + 1) % 3], x[(k + 2) % 3]);
                        let (u, v) = (xp - xo, xq - xo);
                        let w = 0.5 * u.dot(&v) / u.cross(&v).norm();
                        add(p, q, w, &mut nbr);
                        add(q, p, w, &mut nbr);
                        area[o] += tri_area / 3.0;
                    }
                }
            }
        }
        let mut ptr = vec![0u32];
        let mut cols = Vec::new();
        let mut coef = Vec::new();
        let mut fixed = Vec::new();
        for jj in 1..ny - 1 {
            for ii in 1..nx - 1 {
                let i = jj * nx + ii;
                let s = (stiffness / area[i]).sqrt();
                let mut row: Vec<(usize, f64)> = Vec::with_capacity(7);
                let mut diag = 0.0;
                for &(k, w) in &nbr[i] {
                    // The diagonals of a square grid have opposite right
                    // angles: weight exactly 0, no entry.
                    if w != 0.0 {
                        row.push((k, s * w));
                        diag += w;
                    }
                }
                row.push((i, -s * diag));
                let mut pinned = Vector3::zeros();
                let before = cols.len();
                for (k, a) in row {
                    match free_index[k] {
                        PINNED => pinned += start[k] * a,
                        f => {
                            cols.push(f);
                            coef.push(a);
                        }
                    }
                }
                if cols.len() > before {
                    ptr.push(cols.len() as u32);
                    fixed.push(pinned.into());
                }
            }
        }
        let free = free_index.iter().filter(|&&k| k != PINNED).count();
        let mut b = Bending {
            stiffness,
            ptr,
            cols,
            coef,
            fixed,
            bound: 0.0,
        };
        b.bound = b.gershgorin(free);
        Some(b)
    }

    pub(crate) fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// Gershgorin's bound of the largest eigenvalue of `K` (N/m).
    pub(crate) fn hessian_bound(&self) -> f64 {
        self.bound
    }

    /// The rows with a free particle.
    pub(crate) fn rows(&self) -> usize {
        self.fixed.len()
    }

    #[inline]
    fn row(&self, r: usize, q3: &[[f64; 3]], with_fixed: bool) -> [f64; 3] {
        let mut v = if with_fixed { self.fixed[r] } else { [0.0; 3] };
        for e in self.ptr[r] as usize..self.ptr[r + 1] as usize {
            let (x, a) = (q3[self.cols[e] as usize], self.coef[e]);
            v[0] += a * x[0];
            v[1] += a * x[1];
            v[2] += a * x[2];
        }
        v
    }

    /// `E(q) = ½·Σ_i |v_i|²` (J).
    pub(crate) fn energy(&self, q3: &[[f64; 3]]) -> f64 {
        (0..self.rows())
            .map(|r| {
                let v = self.row(r, q3, true);
                0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
            })
            .sum()
    }

    /// `out −= ∇E(q)` (adds the bending force); returns the largest
    /// `|a_ik·v_i|`, one entry's pull (N), for the force scale.
    pub(crate) fn add_force(&self, q3: &[[f64; 3]], out: &mut [[f64; 3]]) -> f64 {
        let mut scale: f64 = 0.0;
        for r in 0..self.rows() {
            let v = self.row(r, q3, true);
            let vn = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            for e in self.ptr[r] as usize..self.ptr[r + 1] as usize {
                let (k, a) = (self.cols[e] as usize, self.coef[e]);
                scale = scale.max((a * vn).abs());
                out[k][0] -= a * v[0];
                out[k][1] -= a * v[1];
                out[k][2] -= a * v[2];
            }
        }
        scale
    }

    /// `out = K·x` for a displacement `x` of the free particles (the pins
    /// held: the Hessian, without the constant part).
    pub(crate) fn apply_hessian(&self, x3: &[[f64; 3]], out: &mut [[f64; 3]]) {
        out.fill([0.0; 3]);
        for r in 0..self.rows() {
            let v = self.row(r, x3, false);
            for e in self.ptr[r] as usize..self.ptr[r + 1] as usize {
                let (k, a) = (self.cols[e] as usize, self.coef[e]);
                out[k][0] += a * v[0];
                out[k][1] += a * v[1];
                out[k][2] += a * v[2];
            }
        }
    }

    /// The scalar Hessian `K = AᵀA` over free particles as `(row, column,
    /// value)` with every pair once per row of `A` (duplicates summed by
    /// the caller); the 3N × 3N Hessian is `K ⊗ I₃`.
    pub(crate) fn hessian_entries(&self) -> Vec<(usize, usize, f64)> {
        let mut out = Vec::new();
        for r in 0..self.rows() {
            let range = self.ptr[r] as usize..self.ptr[r + 1] as usize;
            for e in range.clone() {
                for f in range.clone() {
                    out.push((
                        self.cols[e] as usize,
                        self.cols[f] as usize,
                        self.coef[e] * self.coef[f],
                    ));
                }
            }
        }
        out
    }

    /// An upper bound of the largest eigenvalue of `K` (Gershgorin: the
    /// largest absolute row sum of `AᵀA`, bounded by `Σ_i |a_ik|·‖a_i‖₁`),
    /// N/m.
    fn gershgorin(&self, free: usize) -> f64 {
        let mut sum = vec![0.0; free];
        for r in 0..self.rows() {
            let range = self.ptr[r] as usize..self.ptr[r + 1] as usize;
            let l1: f64 = self.coef[range.clone()].iter().map(|a| a.abs()).sum();
            for e in range {
                sum[self.cols[e] as usize] += self.coef[e].abs() * l1;
            }
        }
        sum.into_iter().fold(0.0, f64::max)
    }
}

/// Power iterations of [`ClothModel::bending_rate`](crate::ClothModel::bending_rate): the start vector is
/// the grid's checkerboard, close to the top mode of the discrete
/// biharmonic, so the Rayleigh quotient settles within a few dozen.
pub const BENDING_POWER_ITERATIONS: usize = 200;

/// The bending's fastest rate, `ω_max = √λ_max(M⁻¹K)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BendingRate {
    /// The power iteration's Rayleigh quotient, a lower bound of `ω_max`
    /// (rad/s).
    pub estimate: f64,
    /// Gershgorin's upper bound of `ω_max` (rad/s): a step with
    /// `h·bound ≤ 2` is stable for the bending alone.
    pub bound: f64,
    /// The power iterations made.
    pub iterations: usize,
}

impl super::ClothModel {
    /// The bending rigidity `B` (N·m), 0 without bending.
    pub fn bending_stiffness(&self) -> f64 {
        self.bending.as_ref().map_or(0.0, |b| b.stiffness())
    }

    /// The bending energy at `q` (J; 0 without bending).
    pub fn bending_energy(&self, q: &[f64]) -> f64 {
        self.bending
            .as_ref()
            .map_or(0.0, |b| b.energy(self.chunks(q)))
    }

    /// Adds the bending force `−∇E_bend(q)` to `out` (nothing without
    /// bending); returns the largest pull of one stencil entry (N).
    pub fn add_bending_force(&self, q: &[f64], out: &mut [f64]) -> f64 {
        let Some(b) = &self.bending else {
            return 0.0;
        };
        let n = self.free_count();
        b.add_force(self.chunks(q), &mut out.as_chunks_mut::<3>().0[..n])
    }

    /// `out = K·x`: the bending Hessian (constant) applied to a
    /// displacement of the free particles (zero without bending).
    pub fn bending_hessian_apply(&self, x: &[f64], out: &mut [f64]) {
        let n = self.free_count();
        let out3 = &mut out.as_chunks_mut::<3>().0[..n];
        match &self.bending {
            Some(b) => b.apply_hessian(self.chunks(x), out3),
            None => out3.fill([0.0; 3]),
        }
    }

    /// The scalar bending Hessian over the free particles as `(k, l,
    /// value)` triplets, duplicates to be summed (the Hessian of the energy
    /// in `q` is this matrix times the 3×3 identity); empty without bending.
    pub fn bending_hessian_entries(&self) -> Vec<(usize, usize, f64)> {
        self.bending
            .as_ref()
            .map_or_else(Vec::new, |b| b.hessian_entries())
    }

    /// The bending's fastest rate `ω_max` of `M⁻¹K` (`None` without
    /// bending): `K` is constant, so this is computed once per model, by
    /// power iteration from the checkerboard (its Rayleigh quotient, a
    /// lower bound) and by Gershgorin's theorem (an upper bound).
    pub fn bending_rate(&self) -> Option<BendingRate> {
        let b = self.bending.as_ref()?;
        let n = self.free_count();
        let mut x = vec![0.0; 3 * n];
        for (k, &id) in self.free_ids.iter().enumerate() {
            let (i, j) = self.grid_index(id as usize);
            let s = if (i + j) % 2 == 0 { 1.0 } else { -1.0 };
            x[3 * k] = s;
            x[3 * k + 1] = 0.5 * s;
            x[3 * k + 2] = 0.25 * s;
        }
        let mut y = vec![0.0; 3 * n];
        let mut lambda: f64 = 0.0;
        let mut iterations = 0;
        for _ in 0..BENDING_POWER_ITERATIONS {
            let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            if norm == 0.0 {
                break;
            }
            x.iter_mut().for_each(|v| *v /= norm);
            self.bending_hessian_apply(&x, &mut y);
            lambda = x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>();
            std::mem::swap(&mut x, &mut y);
            iterations += 1;
        }
        let inv_m = self.inverse_mass();
        Some(BendingRate {
            estimate: (lambda.max(0.0) * inv_m).sqrt(),
            bound: (b.hessian_bound() * inv_m).sqrt(),
            iterations,
        })
    }
}
