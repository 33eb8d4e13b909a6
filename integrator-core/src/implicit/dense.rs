//! Dense Jacobians and faer's partial-pivoting LU, factorised in place into
//! storage made once, so that stepping does not allocate.

// The assembly indexes the Jacobian and the matrix with the same indices.
#![allow(clippy::needless_range_loop)]

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{Mat, MatMut, Par};

use super::iteration::{Caches, Coefs, Linear, Slot};
use super::settings::{Settings, Stats};
use crate::error::SolveError;
use crate::system::OdeSystem;

fn par(settings: &Settings) -> Par {
    if settings.parallel {
        Par::rayon(0)
    } else {
        Par::Seq
    }
}

/// One factorisation: `LU` in place, its row permutation, its scratch, and
/// what it was made from.
struct DenseLu {
    lu: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: MemBuffer,
    valid: bool,
    version: u64,
    h: f64,
    diag: (f64, f64),
}

impl DenseLu {
    fn new(n: usize) -> Self {
        // (the scratch does not depend on the parallelism)
        let req = StackReq::any_of(&[
            factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default()),
            solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
        ]);
        DenseLu {
            lu: Mat::zeros(n, n),
            perm: vec![0; n],
            perm_inv: vec![0; n],
            mem: MemBuffer::new(req),
            valid: false,
            version: 0,
            h: f64::NAN,
            diag: (f64::NAN, f64::NAN),
        }
    }
}

/// The dense linear algebra of [`ImplicitWorkspace`](super::ImplicitWorkspace).
pub(crate) struct DenseLinear {
    d: usize,
    s: usize,
    /// `∂f/∂z`, row-major `d × d`.
    jac: Vec<f64>,
    version: u64,
    stamp: u64,
    analytic: Option<bool>,
    f0: Vec<f64>,
    f1: Vec<f64>,
    y: Vec<f64>,
    /// `s` stage-matrix slots (DIRK), then the stacked one; made at first use.
    slots: Vec<Option<DenseLu>>,
}

impl DenseLinear {
    pub fn new(d: usize, s: usize) -> Self {
        DenseLinear {
            d,
            s,
            jac: vec![0.0; d * d],
            version: 0,
            stamp: 0,
            analytic: None,
            f0: vec![0.0; d],
            f1: vec![0.0; d],
            y: vec![0.0; d],
            slots: (0..=s).map(|_| None).collect(),
        }
    }

    fn index(&self, slot: Slot) -> usize {
        match slot {
            Slot::Stacked => self.s,
            Slot::Diag(i) => i,
        }
    }

    /// Forward differences, `J[:, e] ≈ (f(z + δ·eₑ) − f(z))/δ`.
    fn finite_differences<Sys: OdeSystem + ?Sized>(
        &mut self,
        sys: &Sys,
        t: f64,
        z: &[f64],
        stats: &mut Stats,
    ) {
        let d = self.d;
        sys.rhs(t, z, &mut self.f0);
        self.y.copy_from_slice(z);
        for e in 0..d {
            let ze = z[e];
            let step = (f64::EPSILON * ze.abs().max(1e-5)).sqrt();
            self.y[e] = ze + step;
            let delta = self.y[e] - ze;
            sys.rhs(t, &self.y, &mut self.f1);
            for r in 0..d {
                self.jac[r * d + e] = (self.f1[r] - self.f0[r]) / delta;
            }
            self.y[e] = ze;
        }
        stats.rhs_evaluations += d + 1;
    }
}

impl<Sys: OdeSystem + ?Sized> Linear<Sys> for DenseLinear {
    fn probe(&mut self, sys: &Sys, t: f64, z: &[f64], attempt: u64, stats: &mut Stats) -> bool {
        if let Some(a) = self.analytic {
            return a;
        }
        let a = sys.jacobian(t, z, &mut self.jac);
        self.analytic = Some(a);
        if a {
            self.version += 1;
            self.stamp = attempt;
            stats.jacobian_evaluations += 1;
        }
        a
    }

    fn evaluate(
        &mut self,
        sys: &Sys,
        t: f64,
        z: &[f64],
        attempt: u64,
        settings: &Settings,
        stats: &mut Stats,
    ) -> Result<(), SolveError> {
        let analytic = self.analytic != Some(false) && sys.jacobian(t, z, &mut self.jac);
        if self.analytic.is_none() {
            self.analytic = Some(analytic);
        }
        if !analytic {
            if !settings.finite_differences {
                return Err(SolveError::NoJacobian);
            }
            self.finite_differences(sys, t, z, stats);
        }
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
        let idx = self.index(slot);
        let diag = match slot {
            Slot::Diag(_) => (coefs.q[0], coefs.p[0]),
            Slot::Stacked => (0.0, 0.0),
        };
        let n = coefs.m * d;
        let version = self.version;
        let lu = self.slots[idx].get_or_insert_with(|| DenseLu::new(n));
        if lu.valid && lu.version == version && lu.h.to_bits() == h.to_bits() && lu.diag == diag {
            return Ok(());
        }
        lu.valid = false;
        // M = I − h·(C⊗J), block (i, j) row k: δᵢⱼδₖₑ − h·cᵢⱼ(k)·J[k][e].
        for i in 0..coefs.m {
            for j in 0..coefs.m {
                for e in 0..d {
                    let col = lu
                        .lu
                        .col_mut(j * d + e)
                        .try_as_col_major_mut()
                        .unwrap()
                        .as_slice_mut();
                    for k in 0..d {
                        let hc = h * coefs.get(i, j, k);
                        let id = if i == j && k == e { 1.0 } else { 0.0 };
                        col[i * d + k] = id - hc * self.jac[k * d + e];
                    }
                }
            }
        }
        let par = par(settings);
        factor::lu_in_place(
            lu.lu.as_mut(),
            &mut lu.perm,
            &mut lu.perm_inv,
            par,
            MemStack::new(&mut lu.mem),
            Default::default(),
        );
        stats.factorizations += 1;
        if (0..n).any(|k| {
            let u = lu.lu[(k, k)];
            u == 0.0 || !u.is_finite()
        }) {
            return Err(SolveError::Singular);
        }
        lu.valid = true;
        lu.version = version;
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
        let idx = self.index(slot);
        let lu = self.slots[idx].as_mut().expect("prepared before solving");
        let n = rhs.len();
        let perm = PermRef::new_checked(&lu.perm, &lu.perm_inv, n);
        solve::solve_in_place(
            lu.lu.as_ref(),
            lu.lu.as_ref(),
            perm,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            par(settings),
            MemStack::new(&mut lu.mem),
        );
        if rhs.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(SolveError::Singular)
        }
    }
}

impl Caches for DenseLinear {
    fn clear(&mut self) {
        for lu in self.slots.iter_mut().flatten() {
            lu.valid = false;
        }
    }

    fn reset(&mut self) {
        self.clear();
        self.version = 0;
        self.stamp = 0;
        self.analytic = None;
    }
}
