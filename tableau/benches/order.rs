//! Order analysis timings: a 7-stage explicit table and Gauss–Legendre 3 up
//! to order 8, partitioned pairs up to order 8, and a 35-factor composition
//! up to order 12.
//!
//! `rk_order` stops at the first failing order; the `*_weights` benchmarks
//! compute every elementary weight up to the limit, the full cost.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use num_bigint::BigInt;
use num_rational::BigRational;
use tableau::Number;
use tableau::order;
use tableau::table::{Composition, Prk, Rk};

fn r(n: i64, d: i64) -> Number {
    Number::ratio(n, d).unwrap()
}

fn dec(s: &str) -> Number {
    let (neg, s) = match s.strip_prefix('-') {
        Some(t) => (true, t),
        None => (false, s),
    };
    let (whole, frac) = s.split_once('.').unwrap_or((s, ""));
    let digits: BigInt = format!("{whole}{frac}").parse().unwrap();
    let den = BigInt::from(10).pow(frac.len() as u32);
    Number::from_rational(BigRational::new(if neg { -digits } else { digits }, den))
}

fn rows(a: &[&[(i64, i64)]]) -> Vec<Vec<Number>> {
    let s = a.len();
    a.iter()
        .map(|row| {
            let mut v: Vec<Number> = row.iter().map(|&(n, d)| r(n, d)).collect();
            v.resize(s, Number::zero());
            v
        })
        .collect()
}

/// Dormand–Prince 5(4): 7 stages, order 5.
fn dopri5() -> Rk {
    Rk {
        a: rows(&[
            &[],
            &[(1, 5)],
            &[(3, 40), (9, 40)],
            &[(44, 45), (-56, 15), (32, 9)],
            &[(19372, 6561), (-25360, 2187), (64448, 6561), (-212, 729)],
            &[
                (9017, 3168),
                (-355, 33),
                (46732, 5247),
                (49, 176),
                (-5103, 18656),
            ],
            &[
                (35, 384),
                (0, 1),
                (500, 1113),
                (125, 192),
                (-2187, 6784),
                (11, 84),
            ],
        ]),
        b: [
            (35, 384),
            (0, 1),
            (500, 1113),
            (125, 192),
            (-2187, 6784),
            (11, 84),
            (0, 1),
        ]
        .iter()
        .map(|&(n, d)| r(n, d))
        .collect(),
        c: None,
    }
}

/// Gauss–Legendre, 3 stages (entries in Q(√15)), order 6.
fn gauss3() -> Rk {
    let s = Number::from(15).sqrt().unwrap();
    let f = |n: i64, d: i64, k: i64, e: i64| &r(n, d) + &(&s * &r(k, e));
    Rk {
        a: vec![
            vec![r(5, 36), f(2, 9, -1, 15), f(5, 36, -1, 30)],
            vec![f(5, 36, 1, 24), r(2, 9), f(5, 36, -1, 24)],
            vec![f(5, 36, 1, 30), f(2, 9, 1, 15), r(5, 36)],
        ],
        b: vec![r(5, 18), r(4, 9), r(5, 18)],
        c: None,
    }
}

/// Lobatto IIIA–IIIB, 3 stages (rational), order 4 on general systems.
fn lobatto_pair3() -> Prk {
    let b = vec![r(1, 6), r(2, 3), r(1, 6)];
    Prk {
        q: Rk {
            a: rows(&[&[], &[(5, 24), (1, 3), (-1, 24)], &[(1, 6), (2, 3), (1, 6)]]),
            b: b.clone(),
            c: None,
        },
        p: Rk {
            a: rows(&[&[(1, 6), (-1, 6)], &[(1, 6), (1, 3)], &[(1, 6), (5, 6)]]),
            b,
            c: None,
        },
    }
}

/// Yoshida's sixth-order composition as decimals; its drift–kick form is an
/// 8-stage explicit pair.
fn yoshida6() -> Composition {
    let w = [
        dec("0.78451361047755726382"),
        dec("0.23557321335935813368"),
        dec("-1.17767998417887100695"),
        dec("1.3151863206839"),
    ];
    let gamma = [0, 1, 2, 3, 2, 1, 0]
        .iter()
        .map(|&i| w[i].clone())
        .collect();
    Composition { gamma }
}

/// Sofroniou–Spaletta: 35 factors, order 10, 32-digit decimals.
fn sofroniou_spaletta10() -> Composition {
    let half = [
        "0.078795722521686419263907679337684",
        "0.31309610341510852776481247192647",
        "0.027918383235078066109520273275299",
        "-0.22959284159390709415121339679655",
        "0.13096206107716486317465685927961",
        "-0.26973340565451071434460973222411",
        "0.074973343155891435666137105641410",
        "0.11199342399981020488957508073640",
        "0.36613344954622675119314812353150",
        "-0.39910563013603589787862981058340",
        "0.10308739852747107731580277001372",
        "0.41143087395589023782070411897608",
        "-0.0048663605831352617621956593099771",
        "-0.39203335370863990644808193642610",
        "0.051942502962449647037182904015976",
        "0.050665090759924496335874344156866",
        "0.049674370639729879054568800279461",
        "0.049317735759594537917680008339338",
    ];
    let mut gamma: Vec<Number> = half.iter().map(|s| dec(s)).collect();
    let mirror: Vec<Number> = gamma[..17].iter().rev().cloned().collect();
    gamma.extend(mirror);
    Composition { gamma }
}

fn runge_kutta(c: &mut Criterion) {
    let dp = dopri5();
    let gl = gauss3();
    c.bench_function("rk_order dopri5 (7 stages) limit 8", |b| {
        b.iter(|| order::rk_order(black_box(&dp), 8, None))
    });
    c.bench_function("rk_elementary_weights dopri5 (7 stages) to 8", |b| {
        b.iter(|| order::rk_elementary_weights(black_box(&dp), 8))
    });
    c.bench_function("rk_order gauss3 limit 8", |b| {
        b.iter(|| order::rk_order(black_box(&gl), 8, None))
    });
    c.bench_function("rk_elementary_weights gauss3 to 8", |b| {
        b.iter(|| order::rk_elementary_weights(black_box(&gl), 8))
    });
}

fn partitioned(c: &mut Criterion) {
    let lob = lobatto_pair3();
    let yo = yoshida6().to_splitting().to_prk();
    let bound = dec("0.000000000001");
    c.bench_function("prk_order lobatto IIIA-IIIB s=3 limit 8", |b| {
        b.iter(|| order::prk_order(black_box(&lob), 8, None))
    });
    c.bench_function("prk_elementary_weights lobatto IIIA-IIIB s=3 to 8", |b| {
        b.iter(|| order::prk_elementary_weights(black_box(&lob), 8))
    });
    c.bench_function(
        "prk_order_separable yoshida6 (8 stages, decimals) limit 8",
        |b| b.iter(|| order::prk_order_separable(black_box(&yo), 8, Some(&bound))),
    );
    let mut group = c.benchmark_group("slow");
    group.sample_size(10);
    group.bench_function(
        "prk_elementary_weights yoshida6 (8 stages, decimals) to 8",
        |b| b.iter(|| order::prk_elementary_weights(black_box(&yo), 8)),
    );
    group.finish();
}

fn compositions(c: &mut Criterion) {
    let ss = sofroniou_spaletta10();
    let bound = dec("0.0000000000000000000001");
    c.bench_function(
        "composition_order sofroniou-spaletta (35 factors) limit 12",
        |b| b.iter(|| order::composition_order(black_box(&ss), 12, Some(&bound))),
    );
    c.bench_function("composition_coefficients sofroniou-spaletta to 12", |b| {
        b.iter(|| order::composition_coefficients(black_box(&ss), 12))
    });
}

criterion_group!(benches, runge_kutta, partitioned, compositions);
criterion_main!(benches);
