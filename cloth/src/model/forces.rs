//! The potential and its force: springs, gravity and colliders. The spring
//! loops here walk the lists (energy, strain, the force with its scale, the
//! two-configuration forces); the force of every explicit step is the
//! stencil kernel ([`super::stencil`]) plus the colliders. None allocates.

use nalgebra::Vector3;

use super::{ClothModel, PinSpring, Spring};

impl ClothModel {
    /// The elastic energy the springs with a free end store when every one
    /// of them is stretched by the relative amount `strain`:
    /// `Σ ½·k·L·strain²` (J). An energy scale of the material alone, for
    /// measuring energy errors of a scene that has no other (no gravity,
    /// starting at rest).
    pub fn elastic_energy_scale(&self, strain: f64) -> f64 {
        let kl2 = |kl: f64, rest: f64| kl * rest * rest;
        let sum: f64 = self.ff.iter().map(|s| kl2(s.kl, s.rest)).sum::<f64>()
            + self.fp.iter().map(|s| kl2(s.kl, s.rest)).sum::<f64>();
        0.5 * sum * strain * strain
    }

    /// The largest relative elongation or compression `|ℓ − L|/L` over all springs.
    pub fn max_strain(&self, q: &[f64]) -> f64 {
        let q3 = self.chunks(q);
        let mut m = self.pp_strain;
        for s in &self.ff {
            let d = Vector3::from(q3[s.b as usize]) - Vector3::from(q3[s.a as usize]);
            m = m.max((d.norm() - s.rest).abs() / s.rest);
        }
        for s in &self.fp {
            let d = Vector3::from(s.pin) - Vector3::from(q3[s.a as usize]);
            m = m.max((d.norm() - s.rest).abs() / s.rest);
        }
        if let Some(c) = &self.constraints {
            m = m.max(c.max_strain(q));
        }
        m
    }

    /// Springs, gravity and collider potential at `q`.
    pub(crate) fn potential_terms(&self, q: &[f64]) -> (f64, f64, f64) {
        let q3 = self.chunks(q);
        let mut springs = 0.0;
        for s in &self.ff {
            let d = Vector3::from(q3[s.b as usize]) - Vector3::from(q3[s.a as usize]);
            let e = d.norm() - s.rest;
            springs += 0.5 * s.kl * e * e;
        }
        for s in &self.fp {
            let d = Vector3::from(s.pin) - Vector3::from(q3[s.a as usize]);
            let e = d.norm() - s.rest;
            springs += 0.5 * s.kl * e * e;
        }
        let mut gravity = 0.0;
        let mut colliders = 0.0;
        let w = Vector3::from(self.weight);
        for x in q3 {
            let x = Vector3::from(*x);
            gravity -= w.dot(&x);
            for c in &self.colliders {
                colliders += c.energy(&x);
            }
        }
        (springs, gravity, colliders)
    }

    /// The springs with a free end: free–free and free–pinned.
    pub(crate) fn springs(&self) -> (&[Spring], &[PinSpring]) {
        (&self.ff, &self.fp)
    }

    /// The force of gravity and of every spring evaluated between two
    /// configurations `q` and `q1` into `out`: `pair(d, d1, k/L, L)` is the
    /// pull on a spring's second end given its vector `d` in `q` and `d1` in
    /// `q1` (for a pin spring, from the particle to the pin), and the first
    /// end gets its opposite. The one loop of the discrete gradients
    /// ([`avf_force`](Self::avf_force),
    /// [`discrete_gradient_force`](Self::discrete_gradient_force)), which
    /// differ only in `pair`. Returns the largest weight or pull, and the
    /// largest `k/L`.
    #[inline(always)]
    pub(crate) fn two_configuration_force(
        &self,
        q: &[f64],
        q1: &[f64],
        out: &mut [f64],
        pair: impl Fn(Vector3<f64>, Vector3<f64>, f64, f64) -> Vector3<f64>,
    ) -> (f64, f64) {
        let n = self.free_count();
        let q3 = &q.as_chunks::<3>().0[..n];
        let p3 = &q1.as_chunks::<3>().0[..n];
        let f3 = &mut out.as_chunks_mut::<3>().0[..n];
        f3.fill(self.weight);
        let mut scale = Vector3::from(self.weight).norm();
        let mut kappa: f64 = 0.0;
        for s in &self.ff {
            let (a, b) = (s.a as usize, s.b as usize);
            let d = Vector3::from(q3[b]) - Vector3::from(q3[a]);
            let d1 = Vector3::from(p3[b]) - Vector3::from(p3[a]);
            let g = pair(d, d1, s.kl, s.rest);
            kappa = kappa.max(s.kl);
            scale = scale.max(g.norm());
            f3[a] = (Vector3::from(f3[a]) + g).into();
            f3[b] = (Vector3::from(f3[b]) - g).into();
        }
        for s in &self.fp {
            let a = s.a as usize;
            let pin = Vector3::from(s.pin);
            let d = pin - Vector3::from(q3[a]);
            let d1 = pin - Vector3::from(p3[a]);
            let g = pair(d, d1, s.kl, s.rest);
            kappa = kappa.max(s.kl);
            scale = scale.max(g.norm());
            f3[a] = (Vector3::from(f3[a]) + g).into();
        }
        (scale, kappa)
    }

    /// The force `F(q) = −∇V` into `out` (as
    /// [`Separable::force`](integrator_core::Separable::force)), and the
    /// force scale at `q`: the size of the terms whose round-off `F` carries.
    /// That is the largest of a particle's weight, a spring's tension
    /// `(k/L)|ℓ − L|`, a collider's push, and `κ·‖q‖_∞` with `κ` the largest
    /// spring constant `k/L`: positions are known to an ulp of `‖q‖_∞`, and
    /// an ulp of position moves a force by `κ` times it, so no `F` computed
    /// in `f64` is more accurate than a few `ε·κ·‖q‖_∞`. A gradient measured
    /// against this scale can be asked to vanish down to a small multiple of
    /// `ε` whatever the net forces are (a hanging sheet's net forces are tiny
    /// beside the tensions that balance them).
    pub fn force_and_scale(&self, q: &[f64], out: &mut [f64]) -> f64 {
        let n = self.free_count();
        let q3 = &q.as_chunks::<3>().0[..n];
        let f3 = &mut out.as_chunks_mut::<3>().0[..n];
        f3.fill(self.weight);
        let mut scale = Vector3::from(self.weight).norm();
        let mut kappa: f64 = 0.0;
        for s in &self.ff {
            let (a, b) = (s.a as usize, s.b as usize);
            let d = Vector3::from(q3[b]) - Vector3::from(q3[a]);
            let l = d.norm();
            let fd = d * (s.kl - s.kl * s.rest / l);
            kappa = kappa.max(s.kl);
            scale = scale.max((s.kl * (l - s.rest)).abs());
            f3[a] = (Vector3::from(f3[a]) + fd).into();
            f3[b] = (Vector3::from(f3[b]) - fd).into();
        }
        for s in &self.fp {
            let a = s.a as usize;
            let d = Vector3::from(s.pin) - Vector3::from(q3[a]);
            let l = d.norm();
            kappa = kappa.max(s.kl);
            scale = scale.max((s.kl * (l - s.rest)).abs());
            f3[a] = (Vector3::from(f3[a]) + d * (s.kl - s.kl * s.rest / l)).into();
        }
        for c in &self.colliders {
            for (f, x) in f3.iter_mut().zip(q3) {
                let push = c.force(&Vector3::from(*x));
                scale = scale.max(push.norm());
                *f = (Vector3::from(*f) + push).into();
            }
        }
        // The bending rows are linear in `q`: an ulp of `‖q‖_∞` moves a
        // pull by about the largest `Σ|a|²` of a row, which Gershgorin's
        // bound of `K` covers.
        if let Some(b) = &self.bending {
            scale = scale.max(self.add_bending_force(q, out));
            kappa = kappa.max(b.hessian_bound());
        }
        let q_max = q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        scale.max(kappa * q_max)
    }
}

impl integrator_core::Separable for ClothModel {
    fn dof(&self) -> usize {
        3 * self.free_ids.len()
    }

    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * self.inv_mass * p.iter().map(|x| x * x).sum::<f64>()
    }

    fn potential(&self, q: &[f64]) -> f64 {
        let (springs, gravity, colliders) = self.potential_terms(q);
        springs + gravity + colliders + self.bending_energy(q)
    }

    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        let n = self.dof();
        let inv = self.inv_mass;
        for (o, x) in out[..n].iter_mut().zip(&p[..n]) {
            *o = inv * x;
        }
    }

    /// The stencil kernel (`model/stencil.rs`): the springs' forces as
    /// [`force_and_scale`](ClothModel::force_and_scale) computes them from
    /// the lists, to round-off, in vectorised loops.
    fn force(&self, q: &[f64], out: &mut [f64]) {
        let n = self.free_count();
        self.stencil.force(
            q,
            out,
            &self.free_index,
            &self.free_ids,
            &self.start,
            self.weight,
        );
        let q3 = &q.as_chunks::<3>().0[..n];
        let f3 = &mut out.as_chunks_mut::<3>().0[..n];
        for c in &self.colliders {
            for (f, x) in f3.iter_mut().zip(q3) {
                *f = (Vector3::from(*f) + c.force(&Vector3::from(*x))).into();
            }
        }
        self.add_bending_force(q, out);
    }
}
