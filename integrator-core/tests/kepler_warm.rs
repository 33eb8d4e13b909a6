//! The Kepler solver's warm start (`KeplerSolver::drift_warm`, and the
//! Wisdom–Holman runs that carry a `KeplerHistory`): as accurate as the
//! cold drift over e = 0 … 0.9 and steps 0.01 … 0.9 of a period; the same
//! bits on every SIMD level; a run resumed from a checkpoint of its state
//! and history gives the uninterrupted run's bits; and the evaluations it
//! saves (or costs) at long steps, counted.

use crate::double_double;
use crate::kepler_flow::{C, kappa, scaled_error, state};
use integrator_core::checkpoint::{Decoder, Encoder};
use integrator_core::kepler::{KeplerSolver, WarmStart};
use integrator_core::problems::OuterSolarSystem;
use integrator_core::problems::wisdom_holman::{Jacobi, KeplerHistory, WarmJacobi};
use integrator_core::scheme::SplitWorkspace;
use integrator_core::sequence::Sequence;
use integrator_core::simd::{Level, Simd};
use integrator_core::split::Split;
use std::f64::consts::PI;

const EPS: f64 = f64::EPSILON;

/// The steps of the grid, as fractions of the period.
const FRACTIONS: [f64; 8] = [0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9];

/// Steps along one orbit (GM = 1, a = 1) at `frac` of its period from the
/// true anomaly 0.3: at each, the state, the warm start the previous
/// solve left, and that solve's step. The states are the cold drift's.
fn trajectory(e: f64, frac: f64, steps: usize) -> Vec<([f64; 3], [f64; 3], WarmStart)> {
    let solver = KeplerSolver::default();
    let h = frac * 2.0 * PI;
    let (mut x, mut v) = state(1.0, 1.0, e, 0.3);
    let mut warm = WarmStart::NONE;
    let mut out = Vec::new();
    for _ in 0..steps {
        out.push((x, v, warm));
        let (mut xw, mut vw) = (x, v);
        solver
            .drift_warm(1.0, h, &mut xw, &mut vw, &mut warm)
            .unwrap();
        solver.drift(1.0, h, &mut x, &mut v).unwrap();
    }
    out
}

#[test]
fn the_warm_drift_meets_the_cold_drifts_accuracy_over_the_grid() {
    // e = 0 … 0.9, steps 0.01 … 0.9 P, six consecutive steps each: the
    // warm-started drift from each state (with the history of the
    // previous step) is within the bound every drift meets, C·ε·(1 + κ) of
    // the double-double flow, and within twice that of the cold drift.
    let solver = KeplerSolver::default();
    let mut worst = (0.0f64, String::new());
    let mut warm_solves = 0;
    for e in (0..10).map(|k| 0.1 * k as f64) {
        for frac in FRACTIONS {
            let h = frac * 2.0 * PI;
            for (k, (x, v, warm)) in trajectory(e, frac, 6).into_iter().enumerate() {
                let (mut xw, mut vw, mut after) = (x, v, warm);
                solver
                    .drift_warm(1.0, h, &mut xw, &mut vw, &mut after)
                    .unwrap();
                let (mut xc, mut vc) = (x, v);
                solver.drift(1.0, h, &mut xc, &mut vc).unwrap();
                let (xr, vr) = double_double::flow(1.0, h, x, v).unwrap();
                let k1 = 1.0 + kappa(1.0, h, x, v);
                let err = scaled_error(&xw, &vw, &xr, &vr);
                let what = format!("e = {e:.1}, h = {frac} P, step {k}");
                assert!(
                    err <= C * EPS * k1,
                    "{what}: warm error {err:e} > C·ε·(1 + κ) = {:e}",
                    C * EPS * k1
                );
                let dx = (0..3).map(|i| (xw[i] - xc[i]).abs()).fold(0.0, f64::max);
                let dv = (0..3).map(|i| (vw[i] - vc[i]).abs()).fold(0.0, f64::max);
                let nx = xc.iter().map(|c| c * c).sum::<f64>().sqrt();
                let nv = vc.iter().map(|c| c * c).sum::<f64>().sqrt();
                let diff = (dx / nx).max(dv / nv);
                assert!(
                    diff <= 2.0 * C * EPS * k1,
                    "{what}: warm and cold differ by {diff:e}"
                );
                if diff / (EPS * k1) > worst.0 {
                    worst = (diff / (EPS * k1), what.clone());
                }
                // Steps of half a period and more are long from every
                // point of these orbits: each solve after the first
                // started from the previous root and left its own.
                if frac >= 0.5 {
                    assert!(after.s().is_finite() && after.h() == h, "{what}");
                    if k > 0 {
                        assert_eq!(warm.h(), h, "{what}: no warm start");
                        warm_solves += 1;
                    }
                }
            }
        }
    }
    println!(
        "warm against cold: at most {:.2} ε(1 + κ) ({}); {warm_solves} warm-started solves",
        worst.0, worst.1
    );
    assert_eq!(warm_solves, 10 * 3 * 5);
}

#[test]
fn a_short_step_is_the_cold_drift_bit_for_bit_and_leaves_the_history() {
    // The lanes take only short steps: with or without a history (even
    // one for the same h), a short step is the cold drift's bits.
    let solver = KeplerSolver::default();
    for e in [0.0, 0.05, 0.3, 0.6] {
        let (x0, v0) = state(1.0, 1.0, e, 1.1);
        let h = 0.01 * 2.0 * PI;
        let mut warm = WarmStart::new(h, 0.9 * h);
        let (mut xw, mut vw) = (x0, v0);
        solver
            .drift_warm(1.0, h, &mut xw, &mut vw, &mut warm)
            .unwrap();
        let (mut xc, mut vc) = (x0, v0);
        solver.drift(1.0, h, &mut xc, &mut vc).unwrap();
        assert_eq!(xw.map(f64::to_bits), xc.map(f64::to_bits), "e = {e}");
        assert_eq!(vw.map(f64::to_bits), vc.map(f64::to_bits), "e = {e}");
        assert_eq!(warm, WarmStart::new(h, 0.9 * h), "e = {e}");
    }
}

/// The fewest evaluations with which a solve succeeds (`max_iterations`
/// probed from 1), cold and warm.
fn evaluations(h: f64, x: [f64; 3], v: [f64; 3], warm: WarmStart) -> (usize, usize) {
    let fewest = |use_warm: bool| {
        (1..=KeplerSolver::DEFAULT_MAX_ITERATIONS)
            .find(|&k| {
                let solver = KeplerSolver {
                    max_iterations: k,
                    ..KeplerSolver::default()
                };
                let (mut xs, mut vs, mut w) = (x, v, warm);
                if use_warm {
                    solver.drift_warm(1.0, h, &mut xs, &mut vs, &mut w).is_ok()
                } else {
                    solver.drift(1.0, h, &mut xs, &mut vs).is_ok()
                }
            })
            .expect("every solve converges")
    };
    (fewest(false), fewest(true))
}

#[test]
fn at_long_steps_the_previous_root_costs_more_evaluations_than_the_cold_starter() {
    // Planet-like orbits (e ≤ 0.1) and eccentric ones at long steps (0.3 …
    // 0.9 P), 12 consecutive steps each: the evaluations per solve, cold
    // and warm. Measured: the previous root is off by about e·nh of s
    // (the phase moves by nh between steps), where the cold starter
    // (Danby's, refined by two Newton steps on Kepler's equation) is
    // nearly the root, so the warm start takes about twice the
    // evaluations (planets: 390 against 180 over 60 solves). Why the warm
    // start is off by default (`KEPLER_WARM_START_DEFAULT`).
    let mut rows = Vec::new();
    for e in [0.0, 0.05, 0.1, 0.3, 0.6, 0.9] {
        for frac in [0.3, 0.4, 0.5, 0.7, 0.9] {
            let h = frac * 2.0 * PI;
            let (mut cold, mut warm, mut n) = (0, 0, 0);
            for (x, v, w) in trajectory(e, frac, 13).into_iter().skip(1) {
                let (c, wm) = evaluations(h, x, v, w);
                cold += c;
                warm += wm;
                n += 1;
            }
            println!(
                "e = {e:.2}, h = {frac} P: evaluations per solve cold {:.2}, warm {:.2}",
                cold as f64 / n as f64,
                warm as f64 / n as f64
            );
            rows.push((e, frac, cold, warm, n));
        }
    }
    let planets: (usize, usize) = rows
        .iter()
        .filter(|r| r.0 <= 0.1)
        .fold((0, 0), |a, r| (a.0 + r.2, a.1 + r.3));
    let all: (usize, usize) = rows.iter().fold((0, 0), |a, r| (a.0 + r.2, a.1 + r.3));
    println!("planets (e ≤ 0.1): cold {}, warm {}", planets.0, planets.1);
    println!("all: cold {}, warm {}", all.0, all.1);
    assert!(planets.1 > planets.0, "planets: cold {planets:?}");
    assert!(all.1 > all.0, "all: {all:?}");
}

/// A Jacobi run of the outer solar system with the warm start on: `n`
/// leapfrog steps merged across steps (`Sequence::steps_merged`, the
/// register loop where the lanes hold every planet), on `simd`.
fn warm_run(simd: Simd, h: f64, n: usize) -> (Vec<f64>, KeplerHistory) {
    let split = Jacobi::outer_solar()
        .with_simd(simd)
        .with_kepler_warm_start(true);
    let z = OuterSolarSystem.initial_state();
    let mut w = vec![0.0; z.len()];
    split.from_inertial(&z, &mut w).unwrap();
    let run = WarmJacobi::new(&split);
    let seq = Sequence::from_catalogue("leapfrog").unwrap();
    let mut ws = SplitWorkspace::new(run.buffer_len());
    seq.steps_merged(&run, h, n, &mut w, &mut ws).unwrap();
    (w, run.history())
}

fn bits(a: &[f64]) -> Vec<u64> {
    a.iter().map(|x| x.to_bits()).collect()
}

fn same_bits_as_portable(simd: Simd) {
    println!("warm start: {:?} against the portable lanes", simd.level());
    // 2000 and 1500 days: Jupiter's merged drift is long (warm-started),
    // the other planets' short (in the lanes where the level has them);
    // 300 days: every drift short.
    for h in [2000.0, 1500.0, -1800.0, 300.0] {
        let (a, ha) = warm_run(simd, h, 300);
        let (b, hb) = warm_run(Simd::Portable, h, 300);
        assert_eq!(bits(&a), bits(&b), "{simd:?}, h = {h}");
        assert_eq!(ha.to_f64s().len(), hb.to_f64s().len());
        assert_eq!(
            bits(&ha.to_f64s()),
            bits(&hb.to_f64s()),
            "{simd:?}, h = {h}"
        );
        // Jupiter (body 1) warm-started where its drift is long.
        assert_eq!(
            ha.get(1, h).s().is_finite(),
            h.abs() > 1000.0,
            "{simd:?}, h = {h}"
        );
    }
}

#[test]
fn the_warm_start_on_the_portable_lanes_is_the_scalar_path() {
    // The portable level against itself through the other entry: the
    // plain flows with a history, one by one, give the merged run's bits.
    let split = Jacobi::outer_solar()
        .with_simd(Simd::Portable)
        .with_kepler_warm_start(true);
    let z = OuterSolarSystem.initial_state();
    let h = 2000.0;
    let n = 200;
    let mut w = vec![0.0; z.len()];
    split.from_inertial(&z, &mut w).unwrap();
    let mut history = KeplerHistory::new(split.bodies());
    split
        .kepler_flow_warm(0.5 * h, &mut w, &mut history)
        .unwrap();
    for k in 0..n {
        split.interaction_kick(h, &mut w).unwrap();
        let d = if k + 1 < n { h } else { 0.5 * h };
        split.kepler_flow_warm(d, &mut w, &mut history).unwrap();
    }
    let (u, hu) = warm_run(Simd::Portable, h, n);
    assert_eq!(bits(&w), bits(&u));
    assert_eq!(history, hu);
}

#[test]
#[cfg_attr(
    not(symlab_avx512),
    ignore = "this machine has no AVX-512F (found when the tests were built)"
)]
fn avx512_warm_started_runs_give_the_portable_bits() {
    assert!(
        Level::Avx512.available(),
        "the tests were built where this processor had AVX-512, and run where it has not: rebuild them here"
    );
    same_bits_as_portable(Simd::Avx512);
}

#[test]
#[cfg_attr(
    not(symlab_avx2),
    ignore = "this machine has no AVX2 (found when the tests were built)"
)]
fn avx2_warm_started_runs_give_the_portable_bits() {
    assert!(
        Level::Avx2.available(),
        "the tests were built where this processor had AVX2, and run where it has not: rebuild them here"
    );
    same_bits_as_portable(Simd::Avx2);
}

#[test]
fn a_run_resumed_from_its_checkpoint_gives_the_same_bits() {
    // 150 merged leapfrog steps at 2000 days, then 150 more: once in one
    // process, once through a checkpoint payload (the Jacobi state and the
    // history as exact doubles) into a fresh run.
    let split = Jacobi::outer_solar().with_kepler_warm_start(true);
    let z = OuterSolarSystem.initial_state();
    let h = 2000.0;
    let seq = Sequence::from_catalogue("leapfrog").unwrap();
    let mut w0 = vec![0.0; z.len()];
    split.from_inertial(&z, &mut w0).unwrap();

    let first = |w: &mut Vec<f64>| {
        let run = WarmJacobi::new(&split);
        let mut ws = SplitWorkspace::new(run.buffer_len());
        seq.steps_merged(&run, h, 150, w, &mut ws).unwrap();
        run
    };
    // Uninterrupted: the same run goes on.
    let mut w = w0.clone();
    let run = first(&mut w);
    let mut ws = SplitWorkspace::new(run.buffer_len());
    seq.steps_merged(&run, h, 150, &mut w, &mut ws).unwrap();

    // Checkpointed.
    let mut u = w0.clone();
    let stopped = first(&mut u);
    let mut e = Encoder::new();
    e.f64s(&u).f64s(&stopped.history().to_f64s());
    let payload = e.finish();
    drop(stopped);
    let path = std::path::Path::new("checkpoint.symlab");
    // The same state resumed without its history.
    let cold = WarmJacobi::new(&split);
    let mut v = u.clone();
    seq.steps_merged(&cold, h, 150, &mut v, &mut ws).unwrap();
    let mut d = Decoder::new(path, &payload);
    let mut resumed_w = d.f64s("state").unwrap();
    let history = KeplerHistory::from_f64s(&d.f64s("history").unwrap()).unwrap();
    d.end().unwrap();
    assert!(history.get(1, h).s().is_finite(), "Jupiter's root is saved");
    let resumed = WarmJacobi::with_history(&split, history);
    seq.steps_merged(&resumed, h, 150, &mut resumed_w, &mut ws)
        .unwrap();
    assert_eq!(bits(&resumed_w), bits(&w));
    assert_eq!(resumed.history(), run.history());
    // Without its history the resumed run differs (at round-off): the
    // history is part of the run's state and must be saved.
    assert_ne!(bits(&v), bits(&w), "the history changes no bit");
}

/// `max |u − w| / max |w|` over positions and over momenta, the larger.
fn rel_dist(u: &[f64], w: &[f64]) -> f64 {
    let half = w.len() / 2;
    let part = |r: std::ops::Range<usize>| {
        let d = r.clone().map(|i| (u[i] - w[i]).abs()).fold(0.0, f64::max);
        let s = r.map(|i| w[i].abs()).fold(0.0, f64::max);
        d / s
    };
    part(0..half).max(part(half..w.len()))
}

#[test]
fn a_warm_started_run_is_time_reversible_to_round_off() {
    // The Wisdom–Holman step A(h/2) B(h) A(h/2) at h = 3000 days (every
    // half drift of Jupiter long, so warm-started after the first), 50
    // steps forward and 50 back with the run's history carried throughout:
    // home to round-off, as the cold run (the bound of
    // `wisdom_holman::the_kernels_are_symplectic_in_fact_and_time_reversible`).
    // The control, the unsymmetric Lie–Trotter step with the same warm
    // flows, misses by far more.
    let split = Jacobi::outer_solar().with_kepler_warm_start(true);
    let z = OuterSolarSystem.initial_state();
    let mut w0 = vec![0.0; z.len()];
    split.from_inertial(&z, &mut w0).unwrap();
    let h = 3000.0;
    let there_and_back = |symmetric: bool, warm: bool| {
        let mut history = KeplerHistory::new(split.bodies());
        let mut u = w0.clone();
        let mut a = |d: f64, u: &mut [f64]| {
            if warm {
                split.kepler_flow_warm(d, u, &mut history).unwrap()
            } else {
                split.kepler_flow(d, u).unwrap()
            }
        };
        for sign in [1.0, -1.0] {
            let h = sign * h;
            for _ in 0..50 {
                if symmetric {
                    a(0.5 * h, &mut u);
                    split.interaction_kick(h, &mut u).unwrap();
                    a(0.5 * h, &mut u);
                } else {
                    a(h, &mut u);
                    split.interaction_kick(h, &mut u).unwrap();
                }
            }
        }
        let jupiter = history.get(1, 0.5 * h);
        (rel_dist(&u, &w0), jupiter)
    };
    let (warm, jupiter) = there_and_back(true, true);
    let (cold, _) = there_and_back(true, false);
    let (control, _) = there_and_back(false, true);
    println!(
        "50 steps there and back at 3000 days: warm {warm:e}, cold {cold:e}, Lie–Trotter {control:e}"
    );
    assert!(
        jupiter.s().is_finite(),
        "Jupiter's drifts were warm-started"
    );
    assert!(warm < 1e-11, "warm: {warm:e}");
    assert!(cold < 1e-11, "cold: {cold:e}");
    assert!(control > 1e-6, "the control comes back: {control:e}");
}
