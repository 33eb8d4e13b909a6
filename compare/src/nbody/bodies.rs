//! A problem as REBOUND's point masses, and REBOUND's particles back as the
//! problem's state.

use serde_json::{Value, json};

use super::hex;

/// How a problem's state `z` maps to REBOUND's particles.
#[derive(Clone, Debug, PartialEq)]
pub enum Layout {
    /// Every body in the state, in 3D: `z = [q₀ … q_{N−1}; p₀ … p_{N−1}]`
    /// with momenta `pᵢ = mᵢ vᵢ` (the outer solar system).
    Momenta,
    /// The planar Kepler problem `H = ½|p|² − 1/|q|`: `z = [x, y, vx, vy]`
    /// of a massless body 1 about body 0 (unit mass, at rest at the origin,
    /// `G = 1`), which it does not move.
    PlanarTestParticle,
}

/// A problem as REBOUND's point masses: `G`, the masses, the initial
/// positions and velocities (exactly those REBOUND is given) and how its
/// particles map back to the problem's state.
#[derive(Clone, Debug, PartialEq)]
pub struct Bodies {
    pub g: f64,
    pub names: Vec<String>,
    pub masses: Vec<f64>,
    pub positions: Vec<[f64; 3]>,
    pub velocities: Vec<[f64; 3]>,
    pub layout: Layout,
}

impl Bodies {
    /// Bodies from a state `z = [q; p]` of `masses.len()` bodies in 3D with
    /// `p = m v`: the velocities are `p/m`, and each must give back `p`
    /// exactly (`m·(p/m) = p`), or REBOUND would start from another state
    /// than ours; the error names the body and the component.
    pub fn from_momenta(
        g: f64,
        names: &[&str],
        masses: &[f64],
        z: &[f64],
    ) -> std::result::Result<Self, String> {
        let n = masses.len();
        if names.len() != n || z.len() != 6 * n {
            return Err(format!(
                "{} names and {} masses for a state of {} numbers (6 per body)",
                names.len(),
                n,
                z.len()
            ));
        }
        let mut positions = Vec::with_capacity(n);
        let mut velocities = Vec::with_capacity(n);
        for (i, (&m, name)) in masses.iter().zip(names).enumerate() {
            if !(m.is_finite() && m > 0.0) {
                return Err(format!("body {i} ({name}): the mass is {m}, not > 0"));
            }
            let q = [z[3 * i], z[3 * i + 1], z[3 * i + 2]];
            let mut v = [0.0; 3];
            for k in 0..3 {
                let p = z[3 * n + 3 * i + k];
                v[k] = p / m;
                if m * v[k] != p {
                    return Err(format!(
                        "body {i} ({name}), momentum component {}: p/m = {} does not give back p = {} \
                         (m·(p/m) = {}); REBOUND, which holds velocities, would start from another state",
                        ["x", "y", "z"][k],
                        v[k],
                        p,
                        m * v[k]
                    ));
                }
            }
            positions.push(q);
            velocities.push(v);
        }
        Ok(Bodies {
            g,
            names: names.iter().map(|s| s.to_string()).collect(),
            masses: masses.to_vec(),
            positions,
            velocities,
            layout: Layout::Momenta,
        })
    }

    /// The planar Kepler problem from `z = [x, y, vx, vy]`.
    pub fn planar_kepler(z: &[f64]) -> std::result::Result<Self, String> {
        let [x, y, vx, vy] = z else {
            return Err(format!(
                "a planar Kepler state has 4 numbers, got {}",
                z.len()
            ));
        };
        Ok(Bodies {
            g: 1.0,
            names: vec!["centre".into(), "body".into()],
            masses: vec![1.0, 0.0],
            positions: vec![[0.0; 3], [*x, *y, 0.0]],
            velocities: vec![[0.0; 3], [*vx, *vy, 0.0]],
            layout: Layout::PlanarTestParticle,
        })
    }

    /// The problem's state from REBOUND's positions and velocities.
    pub fn state(&self, positions: &[[f64; 3]], velocities: &[[f64; 3]]) -> Vec<f64> {
        match self.layout {
            Layout::Momenta => {
                let n = self.masses.len();
                let mut z = vec![0.0; 6 * n];
                for i in 0..n {
                    for k in 0..3 {
                        z[3 * i + k] = positions[i][k];
                        z[3 * n + 3 * i + k] = self.masses[i] * velocities[i][k];
                    }
                }
                z
            }
            Layout::PlanarTestParticle => vec![
                positions[1][0],
                positions[1][1],
                velocities[1][0],
                velocities[1][1],
            ],
        }
    }

    /// The system part of a request.
    pub(crate) fn request(&self) -> Value {
        let triples = |v: &[[f64; 3]]| -> Vec<Vec<String>> {
            v.iter()
                .map(|p| p.iter().map(|&x| hex(x)).collect())
                .collect()
        };
        json!({
            "G": hex(self.g),
            "masses": self.masses.iter().map(|&m| hex(m)).collect::<Vec<_>>(),
            "positions": triples(&self.positions),
            "velocities": triples(&self.velocities),
        })
    }
}
