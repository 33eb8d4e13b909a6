//! Small systems: the library's fixed-size path (`StepFixed` on `[f64; 4]`)
//! against loops a numerical programmer writes by hand over arrays, with
//! the state in locals, on Kepler (2 degrees of freedom).
//!
//! Variants, per method (Störmer–Verlet leapfrog, RK4, Forest–Ruth):
//!
//! * `hand` / `hand-comp`: the method written out over `[f64; 2]` /
//!   `[f64; 4]` locals, with plain / compensated (Kahan) summation of the
//!   state updates, the same formula the library uses;
//! * `fixed` / `fixed-comp`: the library scheme's `step_fixed` in the same
//!   loop, plain / compensated (the flag is a run-time value, as it is for
//!   a user who reads it from settings);
//! * `integrate`: `integrate_fixed` (compensated, first same as last, the
//!   finiteness check after every step): what a user calls;
//! * `slice`: the slice path (`Step::step`, heap workspace, compensated),
//!   for reference.
//!
//! Each run takes `STEPS` steps from the same state. The variants run in
//! turn, `ROUNDS` times after a warm-up, so that a load that comes and goes
//! hits them alike; the table gives the median and the fastest round per
//! step, and the ratios of medians fixed/hand (target ≤ 1.05).
//!
//! ```text
//! cargo bench -p integrator-core --bench small
//! ```

use std::hint::black_box;
use std::time::Instant;

use integrator_core::fixed::{StepFixed, integrate_fixed};
use integrator_core::library::{ForestRuth, Leapfrog, Rk4};
use integrator_core::{Separable, Step};

const STEPS: usize = 10_000;
const ROUNDS: usize = 301;
const WARM_UP: usize = 20;
const H: f64 = 1e-3;
/// Kepler, e = 0.5, at pericentre.
const Z0: [f64; 4] = [0.5, 0.0, 0.0, 1.732_050_807_568_877_2];

/// `H = ½|p|² − 1/|q|`.
struct Kepler;

impl Separable for Kepler {
    fn dof(&self) -> usize {
        2
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        0.5 * (p[0] * p[0] + p[1] * p[1])
    }
    fn potential(&self, q: &[f64]) -> f64 {
        -1.0 / (q[0] * q[0] + q[1] * q[1]).sqrt()
    }
    #[inline]
    fn velocity(&self, p: &[f64], v: &mut [f64]) {
        v[0] = p[0];
        v[1] = p[1];
    }
    #[inline]
    fn force(&self, q: &[f64], f: &mut [f64]) {
        let r2 = q[0] * q[0] + q[1] * q[1];
        let s = 1.0 / (r2 * r2.sqrt());
        f[0] = -q[0] * s;
        f[1] = -q[1] * s;
    }
}

/// The force of [`Kepler`] on arrays, as the hand loops call it.
#[inline(always)]
fn force(q: &[f64; 2]) -> [f64; 2] {
    let r2 = q[0] * q[0] + q[1] * q[1];
    let s = 1.0 / (r2 * r2.sqrt());
    [-q[0] * s, -q[1] * s]
}

/// `x += c·v`, plain or compensated with the carried error `e`.
#[inline(always)]
fn update<const N: usize>(comp: bool, x: &mut [f64; N], e: &mut [f64; N], c: f64, v: &[f64; N]) {
    for i in 0..N {
        if comp {
            let inc = e[i] + c * v[i];
            let new = x[i] + inc;
            e[i] = (x[i] - new) + inc;
            x[i] = new;
        } else {
            x[i] += c * v[i];
        }
    }
}

// ---------------------------------------------------------------------------
// Hand-written loops. `COMP` is a type-level flag: a hand-written loop has
// no run-time switch.

#[inline(never)]
fn hand_leapfrog<const COMP: bool>(z0: [f64; 4], h: f64) -> [f64; 4] {
    let (mut q, mut p) = ([z0[0], z0[1]], [z0[2], z0[3]]);
    let (mut eq, mut ep) = ([0.0; 2], [0.0; 2]);
    let half = 0.5 * h;
    for _ in 0..STEPS {
        let v = p;
        update(COMP, &mut q, &mut eq, half, &v);
        let f = force(&q);
        update(COMP, &mut p, &mut ep, h, &f);
        let v = p;
        update(COMP, &mut q, &mut eq, half, &v);
    }
    [q[0], q[1], p[0], p[1]]
}

/// θ = 1/(2 − ∛2).
const FR_THETA: f64 = 1.351_207_191_959_657_6;

#[inline(never)]
fn hand_forest_ruth<const COMP: bool>(z0: [f64; 4], h: f64) -> [f64; 4] {
    let (mut q, mut p) = ([z0[0], z0[1]], [z0[2], z0[3]]);
    let (mut eq, mut ep) = ([0.0; 2], [0.0; 2]);
    let (c1, c2) = (0.5 * FR_THETA * h, 0.5 * (1.0 - FR_THETA) * h);
    let (d1, d2) = (FR_THETA * h, (1.0 - 2.0 * FR_THETA) * h);
    for _ in 0..STEPS {
        let v = p;
        update(COMP, &mut q, &mut eq, c1, &v);
        update(COMP, &mut p, &mut ep, d1, &force(&q));
        let v = p;
        update(COMP, &mut q, &mut eq, c2, &v);
        update(COMP, &mut p, &mut ep, d2, &force(&q));
        let v = p;
        update(COMP, &mut q, &mut eq, c2, &v);
        update(COMP, &mut p, &mut ep, d1, &force(&q));
        let v = p;
        update(COMP, &mut q, &mut eq, c1, &v);
    }
    [q[0], q[1], p[0], p[1]]
}

/// `f(z) = [p; F(q)]` on the whole state.
#[inline(always)]
fn rhs(z: &[f64; 4]) -> [f64; 4] {
    let f = force(&[z[0], z[1]]);
    [z[2], z[3], f[0], f[1]]
}

#[inline(always)]
fn stage(z: &[f64; 4], c: f64, k: &[f64; 4]) -> [f64; 4] {
    std::array::from_fn(|i| z[i] + c * k[i])
}

#[inline(never)]
fn hand_rk4<const COMP: bool>(z0: [f64; 4], h: f64) -> [f64; 4] {
    let mut z = z0;
    let mut e = [0.0; 4];
    let (half, h6, h3) = (0.5 * h, h / 6.0, h / 3.0);
    for _ in 0..STEPS {
        let k1 = rhs(&z);
        let k2 = rhs(&stage(&z, half, &k1));
        let k3 = rhs(&stage(&z, half, &k2));
        let k4 = rhs(&stage(&z, h, &k3));
        for i in 0..4 {
            let inc = h6 * k1[i] + h3 * k2[i] + h3 * k3[i] + h6 * k4[i];
            if COMP {
                let inc = e[i] + inc;
                let new = z[i] + inc;
                e[i] = (z[i] - new) + inc;
                z[i] = new;
            } else {
                z[i] += inc;
            }
        }
    }
    z
}

// ---------------------------------------------------------------------------
// The library.

#[inline(never)]
fn fixed<M: StepFixed<Kepler, 4>>(m: &M, z0: [f64; 4], h: f64, comp: bool) -> [f64; 4] {
    let mut carry = m.carry(comp);
    let mut z = z0;
    for k in 0..STEPS {
        m.step_fixed(&Kepler, k as f64 * h, h, &mut z, &mut carry, false)
            .expect("explicit");
    }
    z
}

#[inline(never)]
fn integrate<M: StepFixed<Kepler, 4>>(m: &M, z0: [f64; 4], h: f64) -> [f64; 4] {
    let mut z = z0;
    integrate_fixed(m, &Kepler, &mut z, 0.0, h, STEPS, |_, _, _| {}).expect("Kepler at e = 0.5");
    z
}

#[inline(never)]
fn slice<M: Step<Kepler>>(m: &M, z0: [f64; 4], h: f64) -> [f64; 4] {
    let mut ws = m.workspace(&Kepler);
    let mut z = z0;
    for k in 0..STEPS {
        m.step(&Kepler, k as f64 * h, h, &mut z, &mut ws)
            .expect("explicit");
    }
    z
}

// ---------------------------------------------------------------------------
// Timing.

const VARIANTS: [&str; 6] = [
    "hand",
    "fixed",
    "hand-comp",
    "fixed-comp",
    "integrate",
    "slice",
];

/// Median and fastest ns per step of each runner over `ROUNDS` interleaved
/// rounds, after `WARM_UP` untimed ones.
fn time(mut runners: [&mut dyn FnMut() -> [f64; 4]; 6]) -> [(f64, f64); 6] {
    let mut samples: Vec<Vec<f64>> = (0..6).map(|_| Vec::with_capacity(ROUNDS)).collect();
    for round in 0..WARM_UP + ROUNDS {
        for (s, run) in samples.iter_mut().zip(runners.iter_mut()) {
            let t0 = Instant::now();
            black_box(run());
            let ns = t0.elapsed().as_secs_f64() * 1e9 / STEPS as f64;
            if round >= WARM_UP {
                s.push(ns);
            }
        }
    }
    std::array::from_fn(|i| {
        let s = &mut samples[i];
        s.sort_by(f64::total_cmp);
        (s[s.len() / 2], s[0])
    })
}

fn row<M: StepFixed<Kepler, 4> + Step<Kepler>>(
    name: &str,
    m: M,
    hand_plain: fn([f64; 4], f64) -> [f64; 4],
    hand_comp: fn([f64; 4], f64) -> [f64; 4],
) {
    let (z0, h) = (|| black_box(Z0), || black_box(H));
    // The flag is read at run time (black_box), as from a settings struct.
    let (off, on) = (|| black_box(false), || black_box(true));
    // Same arithmetic, same result: the plain variants agree to the bit
    // where the coefficients are the same doubles, and to round-off
    // otherwise; print the difference so that a wrong loop shows.
    let diff = (0..4)
        .map(|i| (hand_plain(Z0, H)[i] - fixed(&m, Z0, H, false)[i]).abs())
        .fold(0.0, f64::max);
    let t = time([
        &mut || hand_plain(z0(), h()),
        &mut || fixed(&m, z0(), h(), off()),
        &mut || hand_comp(z0(), h()),
        &mut || fixed(&m, z0(), h(), on()),
        &mut || integrate(&m, z0(), h()),
        &mut || slice(&m, z0(), h()),
    ]);
    print!("{name:<15}");
    for (med, min) in t {
        print!(" {med:>6.2} ({min:>5.2})");
    }
    let flag = |r: f64| if r <= 1.05 { ' ' } else { '!' };
    let (p, c) = (t[1].0 / t[0].0, t[3].0 / t[2].0);
    println!(
        " | {p:>5.3}{} {c:>5.3}{} {:>5.3} {:>5.3} | {diff:.1e}",
        flag(p),
        flag(c),
        t[4].0 / t[0].0,
        t[5].0 / t[3].0
    );
}

fn main() {
    // `cargo test --benches` runs this with `--bench` absent: do one quick
    // round of each loop there, to check that it runs, and time nothing.
    if !std::env::args().any(|a| a == "--bench") {
        for (a, b) in [
            (
                hand_leapfrog::<false>(Z0, H),
                fixed(&Leapfrog, Z0, H, false),
            ),
            (hand_rk4::<false>(Z0, H), fixed(&Rk4, Z0, H, false)),
        ] {
            assert!((0..4).all(|i| (a[i] - b[i]).abs() < 1e-9), "{a:?} vs {b:?}");
        }
        return;
    }
    println!(
        "Kepler (e = 0.5), {STEPS} steps of h = {H}; ns per step, median (fastest) of {ROUNDS} interleaved rounds."
    );
    print!("{:<15}", "method");
    for v in VARIANTS {
        print!(" {v:>14}");
    }
    println!(" | fix/hand comp/comp integ/hand slice/fixc | max|Δz| plain");
    row(
        "stormer-verlet",
        Leapfrog,
        hand_leapfrog::<false>,
        hand_leapfrog::<true>,
    );
    row("rk4", Rk4, hand_rk4::<false>, hand_rk4::<true>);
    row(
        "forest-ruth",
        ForestRuth,
        hand_forest_ruth::<false>,
        hand_forest_ruth::<true>,
    );
    println!("Target: fixed/hand <= 1.05, plain and compensated ('!' where missed).");
}
