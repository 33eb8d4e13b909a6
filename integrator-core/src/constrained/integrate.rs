//! Stepping a constrained system many times with an observer, after the
//! checks a caller should not have to write.

use super::dense_lu::DenseLu;
use super::error::{ConstrainedError, Where};
use super::step::{ConstrainedPair, NewtonSettings};
use super::system::{Constrained, residuals};

/// The checks before the first step: dimensions, step size, finite values,
/// positive masses, `G(q₀)` of full rank (naming a constraint whose gradient
/// vanishes), `g(q₀) = 0` and `G(q₀)M⁻¹p₀ = 0` to within
/// `settings.start_tolerance` round-off units (naming the worst constraint).
///
/// The initial state is not projected silently: a state off the manifold is
/// the caller's error, and the message says which constraint it violates.
pub fn check_start<Sys: Constrained + ?Sized>(
    sys: &Sys,
    z: &[f64],
    h: f64,
    settings: &NewtonSettings,
) -> Result<(), ConstrainedError> {
    let (d, m) = (sys.dof(), sys.constraints());
    if m == 0 || m > d {
        return Err(ConstrainedError::ConstraintCount { m, d });
    }
    if z.len() != 2 * d {
        return Err(ConstrainedError::Dimension {
            expected: 2 * d,
            got: z.len(),
        });
    }
    if h == 0.0 || !h.is_finite() {
        return Err(ConstrainedError::StepSize(h));
    }
    if let Some(index) = z.iter().position(|x| !x.is_finite()) {
        return Err(ConstrainedError::NonFiniteInitial {
            index,
            value: z[index],
        });
    }
    let mut minv = vec![0.0; d];
    sys.inverse_mass(&mut minv);
    if let Some(index) = minv.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
        return Err(ConstrainedError::Mass {
            index,
            value: minv[index],
        });
    }
    // Rank of G: a vanishing row first (named), then G M⁻¹ Gᵀ.
    let q = &z[..d];
    let mut gq = vec![0.0; m * d];
    sys.constraint_jacobian(q, &mut gq);
    let norms: Vec<f64> = (0..m)
        .map(|l| gq[l * d..(l + 1) * d].iter().map(|x| x.abs()).sum())
        .collect();
    let biggest = norms.iter().fold(0.0f64, |a, &b| a.max(b));
    if let Some(l) = norms
        .iter()
        .position(|&n| n <= f64::EPSILON * biggest || n == 0.0)
    {
        return Err(ConstrainedError::Degenerate {
            where_: Where::Start,
            detail: format!("{} has a zero gradient", sys.constraint_name(l)),
        });
    }
    let mut lu = DenseLu::new(m);
    for l in 0..m {
        for k in 0..m {
            let x: f64 = (0..d)
                .map(|a| gq[l * d + a] * minv[a] * gq[k * d + a])
                .sum();
            lu.set(l, k, x);
        }
    }
    if let Some(k) = lu.factor(4.0 * m as f64 * f64::EPSILON) {
        return Err(ConstrainedError::Degenerate {
            where_: Where::Start,
            detail: format!(
                "G M⁻¹ Gᵀ is singular at pivot {k} of {m}: the constraint gradients are dependent"
            ),
        });
    }
    let res = residuals(sys, z);
    let tol = settings.start_tolerance;
    let (l, worst) = res.worst_position();
    if worst > tol {
        let r = res.position[l];
        return Err(ConstrainedError::OffManifold {
            constraint: l,
            name: sys.constraint_name(l),
            value: r.value,
            tolerance: tol * f64::EPSILON * r.scale,
            ulps: tol,
        });
    }
    let (l, worst) = res.worst_velocity();
    if worst > tol {
        let r = res.velocity[l];
        return Err(ConstrainedError::OffTangent {
            constraint: l,
            name: sys.constraint_name(l),
            value: r.value,
            tolerance: tol * f64::EPSILON * r.scale,
            ulps: tol,
        });
    }
    Ok(())
}

/// Integrate `n` steps of size `h` from `(t0, z)` with `method`, calling
/// `observe(step, t, z)` before the first step and after every step. The
/// first step starts cold; every later one is warm-started from the
/// multipliers of the step before. Stops with an error that names the step
/// and its time at the first step that fails (Newton's cap, a singular
/// matrix, a non-finite value); `z` then holds the state before that step.
pub fn integrate_constrained<Sys: Constrained + ?Sized, const S: usize>(
    method: &ConstrainedPair<S>,
    sys: &Sys,
    z: &mut [f64],
    t0: f64,
    h: f64,
    n: usize,
    mut observe: impl FnMut(usize, f64, &[f64]),
) -> Result<(), ConstrainedError> {
    check_start(sys, z, h, &method.settings)?;
    let mut ws = method.workspace(sys);
    observe(0, t0, z);
    for k in 0..n {
        let t = t0 + k as f64 * h;
        method.step(sys, t, h, z, &mut ws)?;
        observe(k + 1, t0 + (k + 1) as f64 * h, z);
    }
    Ok(())
}
