//! The inextensible cloth's warp and weft edges as holonomic constraints,
//! their sparse Jacobian `G`, and the Gram matrix `G·Gᵀ` factorised by
//! faer's sparse Cholesky.
//!
//! Each edge `c` between particles `a` and `b` with rest length `L_c` is the
//! constraint `g_c(q) = |x_a − x_b|² − L_c² = 0`. This form rather than
//! `|x_a − x_b| − L_c`: it is a polynomial, so its Jacobian row
//! `∂g_c/∂x_a = 2(x_a − x_b)ᵀ = −∂g_c/∂x_b` is linear in `q` (no square
//! root, no division, defined at every configuration), `G(q)·v` and
//! `G(q)ᵀ·λ` are one multiply-add per edge and particle, and every entry of
//! `G(q)·G(q')ᵀ` is `±4·d_c·d'_e` with `d_c = x_a − x_b`: one dot product
//! of two edge vectors. A pinned particle is not an unknown: an edge with a
//! pinned end has one block in its row, an edge with both ends pinned is
//! checked once (it must have its length) and dropped.
//!
//! The mass matrix is `m·I`, so `G·M⁻¹·Gᵀ = G·Gᵀ/m`; the stepper scales its
//! multipliers to absorb `1/m` and factorises `G·Gᵀ`. Its sparsity pattern
//! (two edges are coupled when they share a free particle) never changes,
//! so the symbolic analysis (AMD ordering, elimination tree) is done once
//! per model and shared by every factorisation of every run.
//!
//! Where the per-edge loops run on both cores (`parallel`), they split the
//! edges (or the particles) into chunks of [`PARALLEL_CHUNK`]; each output
//! entry is written by one task, so the result is the same bits either way.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};
use integrator_core::constrained::rattle::{ConstraintSolver, KeptFactor, RattleSystem, Singular};
use nalgebra::Vector3;
use rayon::prelude::*;

use super::springs::grid_springs;
use super::{ClothModel, PINNED};
use crate::scene::{Scene, SceneError};

/// The round-off tolerance of a constraint, as a multiple of `ε`: edge `c`
/// holds when `|g_c| ≤ CONSTRAINT_TOLERANCE·L_c·(L_c + ‖q‖_∞)`, i.e.
/// `32·ε·L_c²·(1 + ‖q‖_∞/L_c)`. `ε·L_c²` is the round-off of `|d|² − L²`
/// itself; the positions are known to an ulp of `‖q‖_∞`, which moves
/// `|d|²` by about `2·√3·ε·‖q‖_∞·L_c`, so on a fine grid far from the origin
/// that term dominates (on the 64² sheet, `‖q‖_∞/L ≈ 63`). 32 leaves room
/// for the rounding of the update `q' = q̂ − Gᵀλ` itself.
pub const CONSTRAINT_TOLERANCE: f64 = 32.0 * f64::EPSILON;

/// Edges (or particles) per parallel task: below a few thousand the loops
/// cost less than handing them to a second thread.
pub const PARALLEL_CHUNK: usize = 2048;

/// One length constraint: the free particle `a` and the free particle `b`,
/// or a pin at `pin` when `b == PINNED`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Edge {
    pub(crate) a: u32,
    pub(crate) b: u32,
    pub(crate) pin: [f64; 3],
    /// `L` (m).
    pub(crate) rest: f64,
    /// `L²` (m²).
    pub(crate) rest2: f64,
}

/// An entry of the lower triangle of `G·Gᵀ`: `coef·d_c·d_e`.
#[derive(Clone, Copy, Debug)]
struct Entry {
    c: u32,
    e: u32,
    coef: f64,
}

/// The warp and weft constraints of a model.
#[derive(Debug)]
pub(crate) struct EdgeConstraints {
    pub(crate) edges: Vec<Edge>,
    /// Free particle → its edges with the sign of its block (`+1` for end
    /// `a`, `−1` for end `b`): `inc[inc_ptr[k]..inc_ptr[k + 1]]`.
    inc_ptr: Vec<u32>,
    inc: Vec<(u32, f64)>,
    /// The lower triangle of `G·Gᵀ` in compressed-column order, with 32-bit
    /// indices (as the particles and edges: a grid has at most 2²² particles,
    /// so fewer than 2²⁶ entries): the factor's row indices then take half
    /// the memory, and a numeric factorisation at 64² took 1.74 ms instead
    /// of 2.0 (Zen 5, 2026-11-30, under load), with the same arithmetic.
    pattern: SymbolicSparseColMat<u32>,
    entries: Vec<Entry>,
    /// The symbolic Cholesky of the pattern, computed once.
    symbolic: Arc<SymbolicCholesky<u32>>,
    /// Both triangles of the same pattern, for the true Newton matrix
    /// `G(q')·G(q)ᵀ` (not symmetric): `full_entries[k] = (row, column,
    /// coefficient)` with value `coef·d'_row·d_column`.
    full_pattern: SymbolicSparseColMat<usize>,
    full_entries: Vec<Entry>,
}

/// Run `f` on chunks of `out` (with the index of each chunk's first entry),
/// on both cores when `parallel` and the work is large enough.
#[inline]
fn chunked<T: Send>(out: &mut [T], parallel: bool, f: impl Fn(usize, &mut [T]) + Sync + Send) {
    if parallel && out.len() > PARALLEL_CHUNK {
        out.par_chunks_mut(PARALLEL_CHUNK)
            .enumerate()
            .for_each(|(k, chunk)| f(k * PARALLEL_CHUNK, chunk));
    } else {
        f(0, out);
    }
}

#[inline]
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl EdgeConstraints {
    pub(crate) fn len(&self) -> usize {
        self.edges.len()
    }

    /// The longest rest length.
    pub(crate) fn max_rest(&self) -> f64 {
        self.edges.iter().map(|e| e.rest).fold(0.0, f64::max)
    }

    /// The edge vectors `d_c = x_a − x_b` at `q`.
    pub(crate) fn edge_vectors(&self, q: &[f64], d: &mut [[f64; 3]], parallel: bool) {
        let q3 = q.as_chunks::<3>().0;
        let edges = &self.edges;
        chunked(d, parallel, |start, out| {
            for (o, e) in out.iter_mut().zip(&edges[start..]) {
                let xb = if e.b == PINNED {
                    e.pin
                } else {
                    q3[e.b as usize]
                };
                *o = sub(q3[e.a as usize], xb);
            }
        });
    }

    /// `g_c = |d_c|² − L_c²` into `g`; returns the scaled residual
    /// `max_c |g_c|/(L_c·(L_c + q_max))` (compare with
    /// [`CONSTRAINT_TOLERANCE`]).
    pub(crate) fn residuals(
        &self,
        d: &[[f64; 3]],
        q_max: f64,
        g: &mut [f64],
        parallel: bool,
    ) -> f64 {
        let edges = &self.edges;
        let worst = |start: usize, out: &[f64]| {
            out.iter()
                .zip(&edges[start..])
                .map(|(r, e)| r.abs() / (e.rest * (e.rest + q_max)))
                .fold(0.0f64, f64::max)
        };
        chunked(g, parallel, |start, out| {
            for ((o, dc), e) in out.iter_mut().zip(&d[start..]).zip(&edges[start..]) {
                *o = dot(*dc, *dc) - e.rest2;
            }
        });
        if parallel && g.len() > PARALLEL_CHUNK {
            g.par_chunks(PARALLEL_CHUNK)
                .enumerate()
                .map(|(k, c)| worst(k * PARALLEL_CHUNK, c))
                .reduce(|| 0.0, f64::max)
        } else {
            worst(0, g)
        }
    }

    /// `out = G(q)ᵀ·λ` (one 3-vector per free particle) with `d` the edge
    /// vectors at `q`: `Σ_c ±2·d_c·λ_c` over a particle's edges.
    pub(crate) fn apply_gt(&self, d: &[[f64; 3]], lambda: &[f64], out: &mut [f64], parallel: bool) {
        let (inc_ptr, inc) = (&self.inc_ptr, &self.inc);
        let out3 = out.as_chunks_mut::<3>().0;
        chunked(out3, parallel, |start, o3| {
            for (k, o) in o3.iter_mut().enumerate() {
                let v = start + k;
                let mut acc = [0.0; 3];
                for &(c, s) in &inc[inc_ptr[v] as usize..inc_ptr[v + 1] as usize] {
                    let w = 2.0 * s * lambda[c as usize];
                    let dc = d[c as usize];
                    acc = [acc[0] + w * dc[0], acc[1] + w * dc[1], acc[2] + w * dc[2]];
                }
                *o = acc;
            }
        });
    }

    /// `out = G(q)·v` with `d` the edge vectors at `q`: `2·d_c·(v_a − v_b)`.
    pub(crate) fn apply_g(&self, d: &[[f64; 3]], v: &[f64], out: &mut [f64], parallel: bool) {
        let v3 = v.as_chunks::<3>().0;
        let edges = &self.edges;
        chunked(out, parallel, |start, o| {
            for ((o, dc), e) in o.iter_mut().zip(&d[start..]).zip(&edges[start..]) {
                let va = v3[e.a as usize];
                let rel = if e.b == PINNED {
                    va
                } else {
                    sub(va, v3[e.b as usize])
                };
                *o = 2.0 * dot(*dc, rel);
            }
        });
    }

    /// The largest transverse-wave number `h·ω` of the sheet under the
    /// tensions of the scaled multipliers `Λ = h²λ/(2m)`, over the free
    /// particles: `4·√(½·Σ_c Λ_c)` over a particle's edges in tension.
    ///
    /// An edge in tension `T_c = 2·L_c·λ_c = 4·m·L_c·Λ_c/h²` carries
    /// transverse waves of a chain of particles of mass `m`; their fastest
    /// grid mode has `ω = 2·√(T/(m·L))`, so `h·ω = 4·√Λ`, a number free of
    /// units. A particle pulled along both grid directions adds the two
    /// (`ω² = 4(T_x + T_y)/(m·L)`; each direction's tension the mean of its
    /// two edges, hence the ½). RATTLE takes the constraint forces'
    /// directions from the start of a step, so these waves are stepped
    /// explicitly, as by Störmer–Verlet, which is stable only for
    /// `h·ω < 2`.
    pub(crate) fn wave_number(&self, lambda: &[f64]) -> f64 {
        let (inc_ptr, inc) = (&self.inc_ptr, &self.inc);
        let mut worst = 0.0f64;
        for v in 0..inc_ptr.len() - 1 {
            let sum: f64 = inc[inc_ptr[v] as usize..inc_ptr[v + 1] as usize]
                .iter()
                .map(|&(c, _)| lambda[c as usize].max(0.0))
                .sum();
            worst = worst.max(sum);
        }
        4.0 * (0.5 * worst).sqrt()
    }

    /// The values of the lower triangle of `G(q)·G(q)ᵀ` in the pattern's
    /// order, `d` the edge vectors at `q`.
    fn assemble(&self, d: &[[f64; 3]], values: &mut [f64], parallel: bool) {
        let entries = &self.entries;
        chunked(values, parallel, |start, out| {
            for (o, en) in out.iter_mut().zip(&entries[start..]) {
                *o = en.coef * dot(d[en.c as usize], d[en.e as usize]);
            }
        });
    }

    /// The largest `|ℓ − L|/L` over the edges at `q`.
    pub(crate) fn max_strain(&self, q: &[f64]) -> f64 {
        let q3 = q.as_chunks::<3>().0;
        self.edges
            .iter()
            .map(|e| {
                let xb = if e.b == PINNED {
                    e.pin
                } else {
                    q3[e.b as usize]
                };
                let l = dot(sub(q3[e.a as usize], xb), sub(q3[e.a as usize], xb)).sqrt();
                (l - e.rest).abs() / e.rest
            })
            .fold(0.0, f64::max)
    }
}

/// A numeric Cholesky factor of `G·Gᵀ` on the shared symbolic analysis, with its storage kept between
/// factorisations.
pub(crate) struct Gram {
    constraints: Arc<EdgeConstraints>,
    values: Vec<f64>,
    factor: Vec<f64>,
    mem: MemBuffer,
    par: Par,
    parallel: bool,
    /// The permuted right-hand side of [`solve`](Self::solve).
    work: Vec<f64>,
}

/// `G·Gᵀ` was not numerically positive definite: the constraints are
/// dependent (or nearly so) at this configuration.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NotPositive;

impl Gram {
    /// Storage for the factors of `constraints`' Gram matrix; `parallel`:
    /// assemble and factorise on both cores.
    pub(crate) fn new(constraints: Arc<EdgeConstraints>, parallel: bool) -> Gram {
        let par = if parallel { Par::rayon(0) } else { Par::Seq };
        let sym = &constraints.symbolic;
        let mem = MemBuffer::new(StackReq::any_of(&[
            sym.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
            sym.solve_in_place_scratch::<f64>(1, par),
        ]));
        Gram {
            values: vec![0.0; constraints.entries.len()],
            factor: vec![0.0; sym.len_val()],
            work: vec![0.0; sym.nrows()],
            constraints,
            mem,
            par,
            parallel,
        }
    }

    /// Factorise `G(q)·G(q)ᵀ`, `d` the edge vectors at `q`.
    pub(crate) fn factorize(&mut self, d: &[[f64; 3]]) -> Result<(), NotPositive> {
        let c = &self.constraints;
        c.assemble(d, &mut self.values, self.parallel);
        let a = SparseColMatRef::new(c.pattern.as_ref(), &self.values);
        c.symbolic
            .factorize_numeric_llt(
                &mut self.factor,
                a,
                Side::Lower,
                LltRegularization::default(),
                self.par,
                MemStack::new(&mut self.mem),
                Default::default(),
            )
            .map(|_| ())
            .map_err(|_| NotPositive)
    }

    /// The numeric factor's values (a checkpoint saves them: the factor
    /// is of an older configuration than the current one).
    pub(crate) fn factor(&self) -> &[f64] {
        &self.factor
    }
    pub(crate) fn factor_mut(&mut self) -> &mut [f64] {
        &mut self.factor
    }

    /// `rhs ← A⁻¹·rhs` with the last factor.
    ///
    /// For faer's simplicial factor (what it chooses for a grid's pattern)
    /// the two triangular solves are done here ([`simplicial_solve`]):
    /// faer's solve with `Lᵀ` sums each column's products into one
    /// accumulator, so every column waits on the latency of its ~18
    /// additions one after the other; four interleaved partial sums (a
    /// fixed order, so fixed bits, which differ from faer's in the last
    /// places) took a solve at 64² from about 0.163 ms to 0.137 ms and the
    /// 45° sheet's 600 frames from 33.3 and 32.9 to 30.4 and 29.9 ms per
    /// frame (Zen 5, quiet, alternated runs). The solve with `L` is
    /// faer's, operation for operation.
    pub(crate) fn solve(&mut self, rhs: &mut [f64]) {
        let sym = &self.constraints.symbolic;
        if let (SymbolicCholeskyRaw::Simplicial(simplicial), Some(perm)) = (sym.raw(), sym.perm()) {
            let (fwd, inv) = perm.arrays();
            simplicial_solve(
                simplicial.col_ptr(),
                simplicial.row_idx(),
                &self.factor,
                fwd,
                inv,
                rhs,
                &mut self.work,
            );
            return;
        }
        let n = rhs.len();
        LltRef::new(&self.constraints.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            self.par,
            MemStack::new(&mut self.mem),
        );
    }
}

/// `rhs ← A⁻¹·rhs`: the solve of `A·x = rhs` with `A = Pᵀ·L·Lᵀ·P`, `L`
/// simplicial in compressed columns (the diagonal first in each column),
/// `fwd`/`inv` the permutation's arrays as faer keeps them; `x` is
/// scratch of the same length.
fn simplicial_solve(
    col_ptr: &[u32],
    row_idx: &[u32],
    values: &[f64],
    fwd: &[u32],
    inv: &[u32],
    rhs: &mut [f64],
    x: &mut [f64],
) {
    let n = rhs.len();
    for (xi, &f) in x.iter_mut().zip(fwd) {
        *xi = rhs[f as usize];
    }
    // L·y = x, by columns: as faer does it.
    for j in 0..n {
        let (s, e) = (col_ptr[j] as usize, col_ptr[j + 1] as usize);
        let xj = x[j] * values[s].recip();
        x[j] = xj;
        for (&i, &l) in row_idx[s + 1..e].iter().zip(&values[s + 1..e]) {
            x[i as usize] -= l * xj;
        }
    }
    // Lᵀ·x = y, by rows of Lᵀ (columns of L), four partial sums.
    for j in (0..n).rev() {
        let (s, e) = (col_ptr[j] as usize, col_ptr[j + 1] as usize);
        let (rows, vals) = (&row_idx[s + 1..e], &values[s + 1..e]);
        let mut acc = [0.0f64; 4];
        let (rc, rr) = rows.as_chunks::<4>();
        let (vc, vr) = vals.as_chunks::<4>();
        for (r, v) in rc.iter().zip(vc) {
            for k in 0..4 {
                acc[k] += v[k] * x[r[k] as usize];
            }
        }
        for (&r, &v) in rr.iter().zip(vr) {
            acc[0] += v * x[r as usize];
        }
        let sum = (acc[0] + acc[1]) + (acc[2] + acc[3]);
        x[j] = (x[j] - sum) * values[s].recip();
    }
    for (r, &i) in rhs.iter_mut().zip(inv) {
        *r = x[i as usize];
    }
}

/// The cloth's linear algebra for the one RATTLE
/// ([`ConstraintSolver`]): the sparse Cholesky of `G·Gᵀ` on the symbolic
/// analysis made once with the model, and the sparse LU of the true
/// Jacobian `G(q')·G(q)ᵀ` for the refreshes. It lives here, not in
/// `integrator_core`, because it assembles both from the edge vectors on
/// the grid's pattern (`±4·d_c·d_e` where two edges share a particle).
pub(crate) struct SparseGram {
    gram: Gram,
    jacobian: Jacobian,
}

impl SparseGram {
    pub(crate) fn new(constraints: Arc<EdgeConstraints>, parallel: bool) -> SparseGram {
        SparseGram {
            gram: Gram::new(constraints.clone(), parallel),
            jacobian: Jacobian::new(constraints, parallel),
        }
    }
}

impl KeptFactor for SparseGram {
    fn factor_values(&self) -> &[f64] {
        self.gram.factor()
    }
    fn factor_values_mut(&mut self) -> &mut [f64] {
        self.gram.factor_mut()
    }
}

impl<Sys: RattleSystem<Geometry = Vec<[f64; 3]>>> ConstraintSolver<Sys> for SparseGram {
    fn factorize(&mut self, _sys: &Sys, geo: &Vec<[f64; 3]>) -> Result<(), Singular> {
        self.gram.factorize(geo).map_err(|_| Singular)
    }
    fn solve(&mut self, rhs: &mut [f64]) {
        self.gram.solve(rhs);
    }
    fn factorize_jacobian(
        &mut self,
        _sys: &Sys,
        geo: &Vec<[f64; 3]>,
        geo1: &Vec<[f64; 3]>,
    ) -> Result<bool, Singular> {
        self.jacobian.factorize(geo, geo1).map_err(|_| Singular)
    }
    fn solve_jacobian(&mut self, rhs: &mut [f64]) {
        self.jacobian.solve(rhs);
    }
}

/// A scene error naming `field`.
fn field_err(scene: &Scene, field: &str, message: String) -> SceneError {
    SceneError::Field {
        file: scene.name.clone(),
        field: field.to_string(),
        message,
    }
}

/// The warp and weft constraints of an inextensible scene. Refused, naming
/// the field: an edge whose `L²` is not a positive normal number
/// (`cloth.width`/`cloth.height`), two pins of one edge at a distance other
/// than its length (`pins`), a start off the constraints
/// (`cloth.prestretch`, or `cloth.origin` when rounding moved the grid), a
/// Gram matrix that is singular at the start (`pins`: a straight line of
/// edges held taut between two pins needs infinite tension).
pub(super) fn build(
    scene: &Scene,
    dx: f64,
    dy: f64,
    start: &[Vector3<f64>],
    free_index: &[u32],
) -> Result<EdgeConstraints, SceneError> {
    let (nx, ny) = (scene.cloth.nx, scene.cloth.ny);
    let grid = |id: usize| (id % nx, id / nx);
    let mut edges = Vec::with_capacity((nx - 1) * ny + nx * (ny - 1));
    let mut problem: Option<SceneError> = None;
    grid_springs(nx, ny, dx, dy, [true, false, false], |a, b, _, rest| {
        if problem.is_some() {
            return;
        }
        let rest2 = rest * rest;
        if !(rest2.is_normal() && rest2 > 0.0) {
            let field = if grid(a).1 == grid(b).1 {
                "cloth.width"
            } else {
                "cloth.height"
            };
            problem = Some(field_err(
                scene,
                field,
                format!(
                    "an edge of length {rest:e} m has L² = {rest2:e} m²: a length constraint needs a positive normal L²"
                ),
            ));
            return;
        }
        let apart = start[a] - start[b];
        let scale = rest * (rest + start[a].amax().max(start[b].amax()));
        let off = (apart.norm_squared() - rest2).abs() / scale;
        match (free_index[a], free_index[b]) {
            (PINNED, PINNED) => {
                if off > CONSTRAINT_TOLERANCE {
                    // With a prestretch the pinned pair sits off its edge's
                    // length because of the prestretch, which is the field
                    // to change (an inextensible cloth cannot be
                    // prestretched); without one, the pins are.
                    let (field, why) = if scene.cloth.prestretch != 1.0 {
                        (
                            "cloth.prestretch",
                            format!(
                                "; prestretch {} put them there (an inextensible cloth starts on its constraints, so it takes prestretch = 1), or unpin one of them",
                                scene.cloth.prestretch
                            ),
                        )
                    } else {
                        ("pins", String::new())
                    };
                    problem = Some(field_err(
                        scene,
                        field,
                        format!(
                            "particles {:?} and {:?} are both pinned {:e} m apart, but the inextensible edge between them has length {rest:e} m: the constraint cannot hold{why}",
                            grid(a),
                            grid(b),
                            apart.norm()
                        ),
                    ));
                }
            }
            (fa, fb) => {
                if off > CONSTRAINT_TOLERANCE {
                    let (field, why) = if scene.cloth.prestretch != 1.0 {
                        (
                            "cloth.prestretch",
                            format!("prestretch {} moves it off", scene.cloth.prestretch),
                        )
                    } else {
                        (
                            "cloth.origin",
                            "rounding of the grid positions moves it off".to_string(),
                        )
                    };
                    problem = Some(field_err(
                        scene,
                        field,
                        format!(
                            "an inextensible cloth starts on its constraints, but the edge {:?}–{:?} starts {:e} m long, not {rest:e} m ({why})",
                            grid(a),
                            grid(b),
                            apart.norm()
                        ),
                    ));
                    return;
                }
                // The free end first: a pin is always `b`.
                let (a, b, pin) = if fa == PINNED {
                    (fb, PINNED, start[a])
                } else {
                    (fa, fb, start[b])
                };
                edges.push(Edge {
                    a,
                    b,
                    pin: pin.into(),
                    rest,
                    rest2,
                });
            }
        }
    });
    if let Some(err) = problem {
        return Err(err);
    }
    let free = free_index.iter().filter(|&&k| k != PINNED).count();
    let (inc_ptr, inc) = incidence(&edges, free);
    let (pattern, entries) = gram_pattern(&edges, &inc_ptr, &inc);
    let (full_pattern, full_entries) = full_gram_pattern(edges.len(), &entries);
    let symbolic = factorize_symbolic_cholesky(
        pattern.as_ref(),
        Side::Lower,
        SymmetricOrdering::Amd,
        Default::default(),
    )
    .map_err(|e| {
        field_err(
            scene,
            "cloth",
            format!("the symbolic Cholesky of the constraints' Gram matrix failed: {e:?}"),
        )
    })?;
    let constraints = EdgeConstraints {
        edges,
        inc_ptr,
        inc,
        pattern,
        entries,
        symbolic: Arc::new(symbolic),
        full_pattern,
        full_entries,
    };
    Ok(constraints)
}

/// Free particle → its edges and signs, in compressed rows.
fn incidence(edges: &[Edge], free: usize) -> (Vec<u32>, Vec<(u32, f64)>) {
    let mut count = vec![0u32; free + 1];
    for e in edges {
        count[e.a as usize + 1] += 1;
        if e.b != PINNED {
            count[e.b as usize + 1] += 1;
        }
    }
    for k in 0..free {
        count[k + 1] += count[k];
    }
    let mut fill = count.clone();
    let mut inc = vec![(0u32, 0.0); count[free] as usize];
    for (c, e) in edges.iter().enumerate() {
        for (v, s) in [(e.a, 1.0), (e.b, -1.0)] {
            if v != PINNED {
                inc[fill[v as usize] as usize] = (c as u32, s);
                fill[v as usize] += 1;
            }
        }
    }
    (count, inc)
}

/// The lower triangle of `G·Gᵀ`: the diagonal `4·(free ends)·|d_c|²`, and
/// for two edges sharing a free particle `±4·d_c·d_e` (two edges of a grid
/// share at most one particle, so each entry comes from one).
fn gram_pattern(
    edges: &[Edge],
    inc_ptr: &[u32],
    inc: &[(u32, f64)],
) -> (SymbolicSparseColMat<u32>, Vec<Entry>) {
    let n = edges.len();
    // (column, row, coefficient) with row ≥ column.
    let mut all: Vec<(usize, usize, f64)> = edges
        .iter()
        .enumerate()
        .map(|(c, e)| (c, c, if e.b == PINNED { 4.0 } else { 8.0 }))
        .collect();
    for v in 0..inc_ptr.len() - 1 {
        let here = &inc[inc_ptr[v] as usize..inc_ptr[v + 1] as usize];
        for (i, &(c, sc)) in here.iter().enumerate() {
            for &(e, se) in &here[i + 1..] {
                let (lo, hi) = if c < e { (c, e) } else { (e, c) };
                all.push((lo as usize, hi as usize, 4.0 * sc * se));
            }
        }
    }
    all.sort_unstable_by_key(|&(c, r, _)| (c, r));
    let mut col_ptr = vec![0usize; n + 1];
    for &(c, _, _) in &all {
        col_ptr[c + 1] += 1;
    }
    for c in 0..n {
        col_ptr[c + 1] += col_ptr[c];
    }
    let row_idx: Vec<u32> = all.iter().map(|&(_, r, _)| r as u32).collect();
    let col_ptr: Vec<u32> = col_ptr.iter().map(|&k| k as u32).collect();
    let entries = all
        .iter()
        .map(|&(c, r, coef)| Entry {
            c: c as u32,
            e: r as u32,
            coef,
        })
        .collect();
    (
        SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx),
        entries,
    )
}

/// Both triangles of the Gram pattern, as `(row, column, coefficient)` in
/// compressed-column order.
fn full_gram_pattern(n: usize, lower: &[Entry]) -> (SymbolicSparseColMat<usize>, Vec<Entry>) {
    let mut all: Vec<(u32, u32, f64)> = Vec::with_capacity(2 * lower.len());
    for en in lower {
        // `c` is the column, `e ≥ c` the row of a lower entry.
        all.push((en.c, en.e, en.coef));
        if en.c != en.e {
            all.push((en.e, en.c, en.coef));
        }
    }
    all.sort_unstable_by_key(|&(col, row, _)| (col, row));
    let mut col_ptr = vec![0usize; n + 1];
    for &(col, _, _) in &all {
        col_ptr[col as usize + 1] += 1;
    }
    for c in 0..n {
        col_ptr[c + 1] += col_ptr[c];
    }
    let row_idx = all.iter().map(|&(_, row, _)| row as usize).collect();
    let entries = all
        .iter()
        .map(|&(col, row, coef)| Entry {
            c: row,
            e: col,
            coef,
        })
        .collect();
    (
        SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx),
        entries,
    )
}

/// A sparse LU of the true Newton matrix of the position solve,
/// `J = G(q')·G(q)ᵀ`, for when the Cholesky of `G(q)·G(q)ᵀ` stops
/// contracting: its symbolic analysis is made on first use and kept for the
/// run.
pub(crate) struct Jacobian {
    constraints: Arc<EdgeConstraints>,
    symbolic: Option<SymbolicLu<usize>>,
    numeric: NumericLu<usize, f64>,
    values: Vec<f64>,
    mem: MemBuffer,
    par: Par,
    parallel: bool,
}

impl Jacobian {
    pub(crate) fn new(constraints: Arc<EdgeConstraints>, parallel: bool) -> Jacobian {
        Jacobian {
            values: vec![0.0; constraints.full_entries.len()],
            constraints,
            symbolic: None,
            numeric: NumericLu::new(),
            mem: MemBuffer::new(StackReq::empty()),
            par: if parallel { Par::rayon(0) } else { Par::Seq },
            parallel,
        }
    }

    /// Factorise `G(q1)·G(q)ᵀ` (`d` the edge vectors at `q`, `d1` at `q1`);
    /// `Ok(true)` when the symbolic analysis was made now.
    pub(crate) fn factorize(
        &mut self,
        d: &[[f64; 3]],
        d1: &[[f64; 3]],
    ) -> Result<bool, NotPositive> {
        let c = &self.constraints;
        let mut fresh = false;
        if self.symbolic.is_none() {
            let sym = factorize_symbolic_lu(c.full_pattern.as_ref(), Default::default())
                .map_err(|_| NotPositive)?;
            self.mem = MemBuffer::new(StackReq::any_of(&[
                sym.factorize_numeric_lu_scratch::<f64>(self.par, Default::default()),
                sym.solve_in_place_scratch::<f64>(1, self.par),
            ]));
            self.symbolic = Some(sym);
            fresh = true;
        }
        let entries = &c.full_entries;
        chunked(&mut self.values, self.parallel, |start, out| {
            for (o, en) in out.iter_mut().zip(&entries[start..]) {
                *o = en.coef * dot(d1[en.c as usize], d[en.e as usize]);
            }
        });
        let sym = self.symbolic.as_ref().expect("made above");
        let a = SparseColMatRef::new(c.full_pattern.as_ref(), &self.values);
        sym.factorize_numeric_lu(
            &mut self.numeric,
            a,
            self.par,
            MemStack::new(&mut self.mem),
            Default::default(),
        )
        .map_err(|_| NotPositive)?;
        Ok(fresh)
    }

    /// `rhs ← J⁻¹·rhs` with the last factor.
    pub(crate) fn solve(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        let sym = self.symbolic.as_ref().expect("factorised before solving");
        LuRef::new_unchecked(sym, &self.numeric).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            self.par,
            MemStack::new(&mut self.mem),
        );
    }
}

impl ClothModel {
    /// The length constraints of an inextensible scene.
    pub(crate) fn constraints(&self) -> Option<&Arc<EdgeConstraints>> {
        self.constraints.as_ref()
    }

    /// Whether the warp and weft edges are length constraints
    /// (`material.stretch = "inextensible"`).
    pub fn is_inextensible(&self) -> bool {
        self.constraints.is_some()
    }

    /// The length constraints with a free end (0 for the spring model).
    pub fn constraint_count(&self) -> usize {
        self.constraints.as_ref().map_or(0, |c| c.len())
    }

    /// How far `q` is from the constraints: `max_c |g_c|/(L_c·(L_c +
    /// ‖q‖_∞))`, to compare with [`CONSTRAINT_TOLERANCE`] (`None` for the
    /// spring model).
    pub fn constraint_residual(&self, q: &[f64]) -> Option<f64> {
        let c = self.constraints.as_ref()?;
        let mut d = vec![[0.0; 3]; c.len()];
        let mut g = vec![0.0; c.len()];
        c.edge_vectors(q, &mut d, false);
        Some(c.residuals(&d, q_max(q), &mut g, false))
    }

    /// How far the velocity of `z = [q; p]` is from the tangent space:
    /// `max_c |d_c·(v_a − v_b)| / (L_c·‖v‖_∞)`, the rate of change of an
    /// edge's length relative to the fastest particle (`None` for the
    /// spring model; 0 at rest).
    pub fn constraint_velocity_residual(&self, z: &[f64]) -> Option<f64> {
        let c = self.constraints.as_ref()?;
        let (q, p) = z.split_at(z.len() / 2);
        let mut d = vec![[0.0; 3]; c.len()];
        let mut gv = vec![0.0; c.len()];
        c.edge_vectors(q, &mut d, false);
        c.apply_g(&d, p, &mut gv, false);
        let v_max = q_max(p) * self.inv_mass;
        if v_max == 0.0 {
            return Some(0.0);
        }
        Some(
            gv.iter()
                .zip(&c.edges)
                .map(|(x, e)| (0.5 * x * self.inv_mass).abs() / (e.rest * v_max))
                .fold(0.0, f64::max),
        )
    }
}

/// `‖x‖_∞`.
pub(crate) fn q_max(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

impl ClothModel {
    /// Each collider's rate `√stiffness` (rad/s): a particle deep in
    /// contact oscillates at it, whatever the resolution.
    pub(crate) fn collider_rates(&self) -> Vec<f64> {
        self.colliders
            .iter()
            .map(|c| (c.kappa() * self.inv_mass).sqrt())
            .collect()
    }
}

impl ClothModel {
    /// The step the tension waves of an inextensible sheet allow, roughly:
    /// `ℓ/√(|g|·L)`, with `ℓ` the shortest edge and `L` the sheet's longer
    /// side. A sheet hanging under gravity carries a tension of about the
    /// weight below, so transverse waves run at `√(T/ρ) ≈ √(|g|·L)` at its
    /// top; RATTLE takes the constraint forces' directions from the start
    /// of a step, so these waves are stepped explicitly and a step must not
    /// let one cross an edge. `None` for the spring model or without gravity.
    pub fn tension_wave_step(&self) -> Option<f64> {
        let c = self.constraints.as_ref()?;
        let g = self.gravity.norm();
        if g == 0.0 {
            return None;
        }
        let shortest = c.edges.iter().map(|e| e.rest).fold(f64::INFINITY, f64::min);
        let (nx, ny) = (self.nx, self.ny);
        let side = |k: usize| (self.start[k] - self.start[0]).norm();
        let longer = side(nx - 1).max(side((ny - 1) * nx));
        Some(shortest / (g * longer).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 12² sheet of the RATTLE tests, released 45° from hanging.
    fn sheet() -> ClothModel {
        let scene = Scene::from_toml(
            r#"
            gravity = [0.0, -6.9367, 6.9367]
            [cloth]
            width = 1.0
            height = 1.0
            nx = 12
            ny = 12
            plane = "vertical"
            [material]
            density = 0.01378
            stretch = "inextensible"
            shear = 0.002
            [pins]
            edges = ["top"]
            [simulation]
            frames = 1
            method = "rattle"
        "#,
            "sheet.toml",
        )
        .unwrap();
        ClothModel::new(&scene).unwrap()
    }

    #[test]
    fn the_simplicial_solve_agrees_with_faers_to_round_off() {
        let model = sheet();
        let c = model.constraints().unwrap().clone();
        assert!(matches!(
            c.symbolic.raw(),
            SymbolicCholeskyRaw::Simplicial(_)
        ));
        // A configuration off the flat start, so that G·Gᵀ is not just a
        // multiple of the grid's Laplacian: each particle moved a little.
        let q: Vec<f64> = model
            .initial_state()
            .iter()
            .take(3 * model.free_count())
            .enumerate()
            .map(|(k, x)| x + 0.003 * ((k * 7919 % 101) as f64 / 101.0 - 0.5))
            .collect();
        let mut d = vec![[0.0; 3]; c.len()];
        c.edge_vectors(&q, &mut d, false);
        let mut gram = Gram::new(c.clone(), false);
        gram.factorize(&d).unwrap();
        let rhs: Vec<f64> = (0..c.len())
            .map(|k| ((k * 104729 % 211) as f64 / 211.0) - 0.3)
            .collect();
        let mut ours = rhs.clone();
        gram.solve(&mut ours);
        let mut faers = rhs.clone();
        let n = faers.len();
        LltRef::new(&c.symbolic, &gram.factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut faers, n, 1),
            Par::Seq,
            MemStack::new(&mut gram.mem),
        );
        let scale = faers.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let worst = ours
            .iter()
            .zip(&faers)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f64, f64::max);
        assert!(scale > 0.0);
        assert!(worst <= 1e-12 * scale, "{worst:e} of {scale:e}");
        // And it is a solve: G·Gᵀ·x = rhs to round-off.
        let mut gt = vec![0.0; 3 * model.free_count()];
        let mut back = vec![0.0; c.len()];
        c.apply_gt(&d, &ours, &mut gt, false);
        c.apply_g(&d, &gt, &mut back, false);
        let res = back
            .iter()
            .zip(&rhs)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f64, f64::max);
        assert!(res <= 1e-10, "residual {res:e}");
    }
}
