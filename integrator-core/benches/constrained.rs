//! Per-step cost of the constrained Lobatto IIIA–IIIB pairs (dense Newton
//! with faer's LU, warm-started): a planar pendulum chain of 10 links
//! (d = 20, m = 10; Newton systems of size 30 for RATTLE, 60 for s = 3) and
//! the spherical pendulum; the s = 3 pair also with `curvature: false`
//! (simplified Newton on the multipliers alone, size 20). Each iteration is one step continuing the run,
//! at h = 2e-3 (chain) and 0.01 (sphere).
//!
//! `cargo bench -p integrator-core --bench constrained`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use integrator_core::constrained::{Constrained, ConstrainedPair, NewtonSettings};
use integrator_core::problems::{PendulumChain, SphericalPendulum};

fn one<S: Constrained, const K: usize>(
    c: &mut Criterion,
    id: &str,
    method: ConstrainedPair<K>,
    sys: &S,
    z0: Vec<f64>,
    h: f64,
) {
    let mut z = z0;
    let mut ws = method.workspace(sys);
    let mut t = 0.0;
    c.bench_function(id, |b| {
        b.iter(|| {
            method
                .step(sys, t, h, black_box(&mut z), &mut ws)
                .expect("the bench's steps converge");
            t += h;
        })
    });
}

fn bench(c: &mut Criterion) {
    let chain = PendulumChain::uniform(2, 10, 1.0, 9.81).unwrap();
    let angles: Vec<f64> = (0..10)
        .map(|i| 0.3 + 0.9 * (i as f64 * 0.7).sin())
        .collect();
    let rates: Vec<f64> = (0..10).map(|i| 0.5 * (i as f64 * 1.3).cos()).collect();
    let zc = chain.state(&angles, &rates);
    let sphere = SphericalPendulum::new(1.0, 1.0, 9.81);
    let zs = sphere.state(1.2, 0.3, 0.0, 2.0);
    one(
        c,
        "constrained/chain10/rattle",
        ConstrainedPair::rattle(),
        &chain,
        zc.clone(),
        2e-3,
    );
    one(
        c,
        "constrained/chain10/lobatto3a3b3",
        ConstrainedPair::lobatto3a3b3(),
        &chain,
        zc.clone(),
        2e-3,
    );
    let simplified = NewtonSettings {
        curvature: false,
        ..NewtonSettings::default()
    };
    one(
        c,
        "constrained/chain10/lobatto3a3b3-simplified",
        ConstrainedPair::lobatto3a3b3().with_settings(simplified),
        &chain,
        zc,
        2e-3,
    );
    one(
        c,
        "constrained/sphere/rattle",
        ConstrainedPair::rattle(),
        &sphere,
        zs.clone(),
        0.01,
    );
    one(
        c,
        "constrained/sphere/lobatto3a3b3",
        ConstrainedPair::lobatto3a3b3(),
        &sphere,
        zs,
        0.01,
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(Duration::from_secs(3)).sample_size(30);
    targets = bench
}
criterion_main!(benches);
