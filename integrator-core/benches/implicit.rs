//! Per-step cost of the implicit stage solvers.
//!
//! * `implicit/oscillator`, `implicit/kepler`: Gauss–Legendre 2 and 3 with
//!   simplified Newton and with fixed-point iteration, both to round-off;
//!   fixed point in the symplectic form (`fixed_point`, the default for
//!   Gauss tables: `μ` coefficients, double-double state) and as for any
//!   table (`fixed_point_a_form`: `Settings::symplectic_form` off).
//! * `implicit/sdirk`: the paper's SDIRK (A = [[1/4, 0], [1/2, 1/4]]) on a
//!   stiff spring chain of `d = 2n` unknowns, stage by stage (two solves of
//!   size `d`, one factorisation) against the stacked solve (size `2d`);
//!   with the factorisation kept (linear system) and with a new Jacobian and
//!   factorisation at every step.
//! * `implicit/sparse`: GL2 on the same chain, dense LU against faer's
//!   sparse LU (symbolic factorisation once, numeric per Jacobian).
//!
//! `cargo bench -p integrator-core --bench implicit`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use integrator_core::OdeSystem;
use integrator_core::implicit::{
    self, ImplicitTable, ImplicitWorkspace, Settings, Solver, SparseJacobian, SparseWorkspace,
    Structure,
};

fn gauss2() -> ImplicitTable<2> {
    let r = 3f64.sqrt() / 6.0;
    ImplicitTable::new(
        [[0.25, 0.25 - r], [0.25 + r, 0.25]],
        [0.5, 0.5],
        [0.5 - r, 0.5 + r],
    )
}

fn gauss3() -> ImplicitTable<3> {
    let r = 15f64.sqrt();
    ImplicitTable::new(
        [
            [5.0 / 36.0, 2.0 / 9.0 - r / 15.0, 5.0 / 36.0 - r / 30.0],
            [5.0 / 36.0 + r / 24.0, 2.0 / 9.0, 5.0 / 36.0 - r / 24.0],
            [5.0 / 36.0 + r / 30.0, 2.0 / 9.0 + r / 15.0, 5.0 / 36.0],
        ],
        [5.0 / 18.0, 4.0 / 9.0, 5.0 / 18.0],
        [0.5 - r / 10.0, 0.5, 0.5 + r / 10.0],
    )
}

fn sdirk() -> ImplicitTable<2> {
    ImplicitTable::new([[0.25, 0.0], [0.5, 0.25]], [0.5, 0.5], [0.25, 0.75])
}

/// `q' = p, p' = −q`.
struct Oscillator;

impl OdeSystem for Oscillator {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, z: &[f64], dz: &mut [f64]) {
        dz[0] = z[1];
        dz[1] = -z[0];
    }
    fn jacobian(&self, _t: f64, _z: &[f64], jac: &mut [f64]) -> bool {
        jac.copy_from_slice(&[0.0, 1.0, -1.0, 0.0]);
        true
    }
}

/// Kepler, `z = [q₁, q₂, p₁, p₂]`, with its analytic Jacobian.
struct Kepler;

impl OdeSystem for Kepler {
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&self, _t: f64, z: &[f64], dz: &mut [f64]) {
        let r2 = z[0] * z[0] + z[1] * z[1];
        let r3 = r2 * r2.sqrt();
        dz[0] = z[2];
        dz[1] = z[3];
        dz[2] = -z[0] / r3;
        dz[3] = -z[1] / r3;
    }
    fn jacobian(&self, _t: f64, z: &[f64], jac: &mut [f64]) -> bool {
        let r2 = z[0] * z[0] + z[1] * z[1];
        let r = r2.sqrt();
        let (r3, r5) = (r2 * r, r2 * r2 * r);
        jac.fill(0.0);
        jac[2] = 1.0;
        jac[7] = 1.0;
        for a in 0..2 {
            for b in 0..2 {
                let delta = if a == b { 1.0 } else { 0.0 };
                jac[(2 + a) * 4 + b] = -delta / r3 + 3.0 * z[a] * z[b] / r5;
            }
        }
        true
    }
}

/// A chain of `n` unit masses joined by springs of stiffness `k` (fixed
/// ends): `q' = p, p' = −K·q`, `K` tridiagonal. Stiff for large `k`.
struct Chain {
    n: usize,
    k: f64,
}

impl OdeSystem for Chain {
    fn dim(&self) -> usize {
        2 * self.n
    }
    fn rhs(&self, _t: f64, z: &[f64], dz: &mut [f64]) {
        let n = self.n;
        let (q, p) = z.split_at(n);
        let (dq, dp) = dz.split_at_mut(n);
        dq.copy_from_slice(p);
        for i in 0..n {
            let left = if i > 0 { q[i - 1] } else { 0.0 };
            let right = if i + 1 < n { q[i + 1] } else { 0.0 };
            dp[i] = self.k * (left - 2.0 * q[i] + right);
        }
    }
    fn jacobian(&self, _t: f64, _z: &[f64], jac: &mut [f64]) -> bool {
        let n = self.n;
        let d = 2 * n;
        jac.fill(0.0);
        for i in 0..n {
            jac[i * d + n + i] = 1.0;
            jac[(n + i) * d + i] = -2.0 * self.k;
            if i > 0 {
                jac[(n + i) * d + i - 1] = self.k;
            }
            if i + 1 < n {
                jac[(n + i) * d + i + 1] = self.k;
            }
        }
        true
    }
}

impl SparseJacobian for Chain {
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        let n = self.n;
        let mut pattern = Vec::with_capacity(4 * n);
        for i in 0..n {
            pattern.push((i, n + i));
            pattern.push((n + i, i));
            if i > 0 {
                pattern.push((n + i, i - 1));
            }
            if i + 1 < n {
                pattern.push((n + i, i + 1));
            }
        }
        pattern
    }
    fn jacobian_values(&self, _t: f64, _z: &[f64], values: &mut [f64]) {
        let n = self.n;
        let mut k = 0;
        for i in 0..n {
            values[k] = 1.0;
            values[k + 1] = -2.0 * self.k;
            k += 2;
            if i > 0 {
                values[k] = self.k;
                k += 1;
            }
            if i + 1 < n {
                values[k] = self.k;
                k += 1;
            }
        }
    }
}

fn report(s: &implicit::Stats) {
    let steps = s.steps.max(1) as f64;
    eprintln!(
        "    per step: {:.2} Newton + {:.2} fixed-point iterations, {:.2} f-evaluations, {:.4} factorisations",
        s.newton_iterations as f64 / steps,
        s.fixed_point_iterations as f64 / steps,
        s.rhs_evaluations as f64 / steps,
        s.factorizations as f64 / steps,
    );
}

fn per_step<Sys: OdeSystem + ?Sized, const S: usize>(
    c: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: BenchmarkId,
    table: &ImplicitTable<S>,
    sys: &Sys,
    z0: &[f64],
    h: f64,
    settings: Settings,
) {
    let mut ws = ImplicitWorkspace::new(z0.len(), S).with_settings(settings);
    let mut z = z0.to_vec();
    let mut t = 0.0;
    c.bench_function(id, |b| {
        b.iter(|| {
            implicit::step(table, sys, t, h, black_box(&mut z), &mut ws).expect("step");
            t += h;
        })
    });
    report(ws.stats());
}

fn solvers() -> [(&'static str, Settings); 3] {
    [
        (
            "newton",
            Settings {
                solver: Solver::Newton,
                ..Settings::default()
            },
        ),
        (
            "fixed_point",
            Settings {
                solver: Solver::FixedPoint,
                ..Settings::default()
            },
        ),
        (
            "fixed_point_a_form",
            Settings {
                solver: Solver::FixedPoint,
                symplectic_form: false,
                ..Settings::default()
            },
        ),
    ]
}

fn bench(c: &mut Criterion) {
    for (name, sys, z0, h) in [
        (
            "oscillator",
            &Oscillator as &dyn OdeSystem,
            vec![1.0, 0.0],
            0.1,
        ),
        ("kepler", &Kepler, vec![0.4, 0.0, 0.0, 2.0], 0.05),
    ] {
        let mut group = c.benchmark_group(format!("implicit/{name}"));
        group.warm_up_time(Duration::from_millis(300));
        group.measurement_time(Duration::from_secs(1));
        group.sample_size(20);
        for (solver, settings) in solvers() {
            per_step(
                &mut group,
                BenchmarkId::new("gl2", solver),
                &gauss2(),
                sys,
                &z0,
                h,
                settings,
            );
            per_step(
                &mut group,
                BenchmarkId::new("gl3", solver),
                &gauss3(),
                sys,
                &z0,
                h,
                settings,
            );
        }
        group.finish();
    }

    let mut group = c.benchmark_group("implicit/sdirk");
    group.warm_up_time(Duration::from_millis(300));
    group.measurement_time(Duration::from_secs(1));
    group.sample_size(20);
    for n in [5usize, 50] {
        let sys = Chain { n, k: 1e4 };
        let z0: Vec<f64> = (0..2 * n).map(|i| (0.37 * i as f64).sin()).collect();
        for (reuse, what) in [(true, "kept_lu"), (false, "new_lu")] {
            let settings = Settings {
                solver: Solver::Newton,
                reuse_jacobian: reuse,
                ..Settings::default()
            };
            per_step(
                &mut group,
                BenchmarkId::new(format!("stage_by_stage/{what}"), 2 * n),
                &sdirk(),
                &sys,
                &z0,
                0.01,
                settings,
            );
            per_step(
                &mut group,
                BenchmarkId::new(format!("stacked/{what}"), 2 * n),
                &sdirk().with_structure(Structure::Full),
                &sys,
                &z0,
                0.01,
                settings,
            );
        }
    }
    group.finish();

    let mut group = c.benchmark_group("implicit/sparse");
    group.warm_up_time(Duration::from_millis(300));
    group.measurement_time(Duration::from_secs(1));
    group.sample_size(10);
    for n in [50usize, 500] {
        let sys = Chain { n, k: 1e4 };
        let z0: Vec<f64> = (0..2 * n).map(|i| (0.37 * i as f64).sin()).collect();
        for (reuse, what) in [(true, "kept_lu"), (false, "new_lu")] {
            let settings = Settings {
                solver: Solver::Newton,
                reuse_jacobian: reuse,
                ..Settings::default()
            };
            if n <= 50 {
                per_step(
                    &mut group,
                    BenchmarkId::new(format!("dense/{what}"), 2 * n),
                    &gauss2(),
                    &sys,
                    &z0,
                    0.01,
                    settings,
                );
            }
            let mut ws = SparseWorkspace::new(2 * n, 2).with_settings(settings);
            let mut z = z0.clone();
            let mut t = 0.0;
            group.bench_function(BenchmarkId::new(format!("sparse/{what}"), 2 * n), |b| {
                b.iter(|| {
                    implicit::step_sparse(&gauss2(), &sys, t, 0.01, black_box(&mut z), &mut ws)
                        .expect("step");
                    t += 0.01;
                })
            });
            report(ws.stats());
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
