//! Per-step cost on the linear gyroscopic model: Gauss–Legendre 2 and 3
//! with simplified Newton (the LU cached while h is unchanged), with fixed
//! point, and through the one-step propagator R(hH), against one dense
//! matrix–vector product of the same size. Medians of repeated timings after
//! a warm-up step (which factorises). Run with
//! `cargo run --release -p integrator-core --example linear_timing -- 100`.

use std::time::Instant;

use faer::{Col, Mat};
use integrator_core::implicit::Solver;
use integrator_core::library::{GaussLegendre2, GaussLegendre3};
use integrator_core::linear::{Propagator, gyroscopic};
use integrator_core::{OdeSystem, Step};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn time_steps<M: Step<integrator_core::linear::LinearHamiltonian>>(
    m: &M,
    sys: &integrator_core::linear::LinearHamiltonian,
    h: f64,
    solver: Option<Solver>,
    reps: usize,
    set: impl Fn(&mut M::Workspace, Solver),
) -> (f64, f64) {
    let mut ws = m.workspace(sys);
    if let Some(s) = solver {
        set(&mut ws, s);
    }
    let mut z: Vec<f64> = (0..sys.dim())
        .map(|i| ((i % 7) as f64 - 3.0) / 10.0)
        .collect();
    let t0 = Instant::now();
    m.step(sys, 0.0, h, &mut z, &mut ws).expect("first step");
    let first = t0.elapsed().as_secs_f64();
    let times = (0..reps)
        .map(|_| {
            let t = Instant::now();
            m.step(sys, 0.0, h, &mut z, &mut ws).expect("step");
            t.elapsed().as_secs_f64()
        })
        .collect();
    (first, median(times))
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .map_or(100, |a| a.parse().expect("dof"));
    let gl3 = std::env::args().nth(2).is_none_or(|a| a != "no-gl3");
    let sys = gyroscopic(n, 1, 10.0).expect("model");
    let h = 0.01;
    let dim = sys.dim();
    let reps = if n >= 1000 { 15 } else { 200 };
    // One dense matvec of the state's size.
    let a = Mat::<f64>::from_fn(dim, dim, |i, j| ((i * 31 + j * 17) % 13) as f64 / 13.0);
    let x = Col::<f64>::from_fn(dim, |i| i as f64);
    let mut y = Col::<f64>::zeros(dim);
    let mv = median(
        (0..reps)
            .map(|_| {
                let t = Instant::now();
                faer::linalg::matmul::matmul(
                    y.as_mut(),
                    faer::Accum::Replace,
                    a.as_ref(),
                    x.as_ref(),
                    1.0,
                    faer::Par::Seq,
                );
                std::hint::black_box(&y);
                t.elapsed().as_secs_f64()
            })
            .collect(),
    );
    println!("linear gyroscopic model, {n} dof (state {dim}), h = {h}");
    println!("  dense matvec {dim}×{dim}: {:.3e} s", mv);
    let set = |ws: &mut integrator_core::implicit::ImplicitWorkspace, s: Solver| {
        ws.settings_mut().solver = s
    };
    let mut rows = Vec::new();
    for (name, solver) in [
        ("Newton (cached LU)", Solver::Newton),
        ("fixed point", Solver::FixedPoint),
    ] {
        let (f, s) = time_steps(&GaussLegendre2, &sys, h, Some(solver), reps, set);
        rows.push((format!("gauss2 {name}"), f, s));
        if gl3 {
            let (f, s) = time_steps(&GaussLegendre3, &sys, h, Some(solver), reps, set);
            rows.push((format!("gauss3 {name}"), f, s));
        }
    }
    for (name, p, q) in [
        (
            "gauss2 propagator",
            &GaussLegendre2::STABILITY_P[..],
            &GaussLegendre2::STABILITY_Q[..],
        ),
        (
            "gauss3 propagator",
            &GaussLegendre3::STABILITY_P[..],
            &GaussLegendre3::STABILITY_Q[..],
        ),
    ] {
        let t = Instant::now();
        let prop = Propagator::new(&sys, h, p, q).expect("propagator");
        let build = t.elapsed().as_secs_f64();
        let (_, s) = time_steps(&prop, &sys, h, None, reps, |_, _| {});
        rows.push((name.to_string(), build, s));
    }
    for (name, first, step) in rows {
        println!(
            "  {name:<28} first step / build {first:.3e} s, then {step:.3e} s per step = {:.2} matvecs",
            step / mv
        );
    }
}
