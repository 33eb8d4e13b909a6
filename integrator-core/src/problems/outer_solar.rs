//! The outer solar system (Hairer–Lubich–Wanner, *Geometric Numerical
//! Integration*, 2nd ed., I.2.3, Table 2.1): the Sun (with the inner
//! planets' mass added) and Jupiter, Saturn, Uranus, Neptune and Pluto as
//! six point masses in 3D,
//!
//! ```text
//! H = ½ Σᵢ |pᵢ|²/mᵢ − G Σ_{i<j} mᵢmⱼ/|qᵢ − qⱼ|,
//! ```
//!
//! masses relative to the Sun, distances in AU, time in Earth days,
//! `G = 2.95912208286e-4`. The initial values are HLW's (positions and
//! velocities at 5 September 1994, 0h00 GST), digit for digit; they were
//! cross-checked against two public transcriptions of the same table
//! (SciML's DiffEqDocs "Simulating the Outer Solar System" and the MatMol
//! group's `G_solar.m`, which cite HLW). The state is `z = [q; p]` with
//! `q = (q₀, …, q₅)` (18 numbers) and momenta `pᵢ = mᵢ vᵢ`.

use crate::system::Separable;

/// `G` in AU³/(solar mass · day²).
pub const G: f64 = 2.95912208286e-4;

/// The masses: Sun (+ inner planets), Jupiter, Saturn, Uranus, Neptune,
/// Pluto.
pub const MASSES: [f64; 6] = [
    1.00000597682,
    0.000954786104043,
    0.000285583733151,
    0.0000437273164546,
    0.0000517759138449,
    1.0 / 1.3e8,
];

/// The bodies' names, in the order of [`MASSES`].
pub const NAMES: [&str; 6] = ["Sun", "Jupiter", "Saturn", "Uranus", "Neptune", "Pluto"];

/// Initial positions (AU).
pub const POSITIONS: [[f64; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [-3.5023653, -3.8169847, -1.5507963],
    [9.0755314, -3.0458353, -1.6483708],
    [8.3101420, -16.2901086, -7.2521278],
    [11.4707666, -25.7294829, -10.8169456],
    [-15.5387357, -25.2225594, -3.1902382],
];

/// Initial velocities (AU/day).
pub const VELOCITIES: [[f64; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [0.00565429, -0.00412490, -0.00190589],
    [0.00168318, 0.00483525, 0.00192462],
    [0.00354178, 0.00137102, 0.00055029],
    [0.00288930, 0.00114527, 0.00039677],
    [0.00276725, -0.00170702, -0.00136504],
];

/// The six-body problem of the outer solar system (see the [module
/// documentation](self)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OuterSolarSystem;

impl OuterSolarSystem {
    /// HLW's initial state `[q; p]` (36 numbers, `p = m·v`).
    pub fn initial_state(&self) -> Vec<f64> {
        let mut z = vec![0.0; 36];
        for i in 0..6 {
            for k in 0..3 {
                z[3 * i + k] = POSITIONS[i][k];
                z[18 + 3 * i + k] = MASSES[i] * VELOCITIES[i][k];
            }
        }
        z
    }

    /// The total angular momentum `Σ qᵢ × pᵢ`.
    pub fn angular_momentum(z: &[f64]) -> [f64; 3] {
        let mut l = [0.0; 3];
        for i in 0..6 {
            let q = &z[3 * i..3 * i + 3];
            let p = &z[18 + 3 * i..18 + 3 * i + 3];
            l[0] += q[1] * p[2] - q[2] * p[1];
            l[1] += q[2] * p[0] - q[0] * p[2];
            l[2] += q[0] * p[1] - q[1] * p[0];
        }
        l
    }
}

impl Separable for OuterSolarSystem {
    fn dof(&self) -> usize {
        18
    }
    fn kinetic(&self, p: &[f64]) -> f64 {
        (0..6)
            .map(|i| {
                let pi = &p[3 * i..3 * i + 3];
                0.5 * (pi[0] * pi[0] + pi[1] * pi[1] + pi[2] * pi[2]) / MASSES[i]
            })
            .sum()
    }
    fn potential(&self, q: &[f64]) -> f64 {
        let mut v = 0.0;
        for i in 1..6 {
            for j in 0..i {
                let d = [
                    q[3 * i] - q[3 * j],
                    q[3 * i + 1] - q[3 * j + 1],
                    q[3 * i + 2] - q[3 * j + 2],
                ];
                v -= MASSES[i] * MASSES[j] / (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            }
        }
        G * v
    }
    fn velocity(&self, p: &[f64], out: &mut [f64]) {
        for i in 0..6 {
            for k in 0..3 {
                out[3 * i + k] = p[3 * i + k] / MASSES[i];
            }
        }
    }
    fn force(&self, q: &[f64], out: &mut [f64]) {
        out[..18].fill(0.0);
        for i in 1..6 {
            for j in 0..i {
                let d = [
                    q[3 * i] - q[3 * j],
                    q[3 * i + 1] - q[3 * j + 1],
                    q[3 * i + 2] - q[3 * j + 2],
                ];
                let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                let s = G * MASSES[i] * MASSES[j] / (r2 * r2.sqrt());
                for k in 0..3 {
                    out[3 * i + k] -= s * d[k];
                    out[3 * j + k] += s * d[k];
                }
            }
        }
    }
}
