//! REBOUND as a peer in the same run: the `rebound:NAME[:KEY=VALUE…]`
//! methods.
//!
//! REBOUND (the N-body code of celestial mechanics, Rein & Liu 2012) is run
//! through its Python package by a small script shipped with this crate,
//! `compare/peers/rebound_peer.py`, embedded in the binary and started as
//! `python3 -c SCRIPT` — one process per run, because WHFast512 leaves the
//! AVX upper registers dirty and sets flush-to-zero, which slows whatever runs
//! after it in the same process. The request and the answer are JSON on the
//! pipes; every double crosses them as a hexadecimal float ([`hex`],
//! [`unhex`]), so REBOUND starts from the bits of our initial state (read back
//! and checked by the script) and the final state is measured here with the
//! project's own error measure and reference ([`Setup::error`]), comparable bit
//! for bit with our rows. Only `sim.integrate` is timed, inside Python: one
//! untimed warm-up, then `repeats` runs on freshly built simulations, the
//! median reported, as [`sweep`](crate::sweep) times our methods.
//!
//! The interpreter is `$SYMLAB_PYTHON`, else `python3`. REBOUND is not a
//! dependency of this crate: where Python or the `rebound` package is missing,
//! a sweep leaves the REBOUND rows out and says how to install it
//! ([`INSTALL`]).
//!
//! A problem runs under REBOUND when it says what its bodies are
//! ([`Problem::rebound_bodies`]): the outer solar system (every body, momenta
//! `p = m v`) and the planar Kepler problems (a massless body about a unit
//! mass at rest, `G = 1`).

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use serde_json::{Value, json};

use crate::error::{CompareError, Result};
use crate::problem::{Family, Problem, Setup};
use crate::sweep::{Row, tolerance_range};

/// The Python script, as shipped in `compare/peers/`.
pub const SCRIPT: &str = include_str!("../peers/rebound_peer.py");

/// The REBOUND release the comparisons were measured with, and how to
/// install it.
pub const VERSION: &str = "5.2.2";
pub const INSTALL: &str = "pip install rebound==5.2.2";

/// The environment variable naming the Python interpreter (default
/// `python3`).
pub const PYTHON_VAR: &str = "SYMLAB_PYTHON";

/// States sampled by the observed run of each configuration for the energy
/// error (every step would cost a Python round trip per step).
pub const ENERGY_SAMPLES: usize = 100;

/// The interpreter: `$SYMLAB_PYTHON`, else `python3`.
pub fn python() -> PathBuf {
    std::env::var_os(PYTHON_VAR)
        .filter(|s| !s.is_empty())
        .map_or_else(|| PathBuf::from("python3"), PathBuf::from)
}

/// `x` as a hexadecimal float in the form Python's `float.hex` writes
/// (`0x1.8000000000000p+1`, `-0x0.0p+0`, `inf`, `nan`), which
/// `float.fromhex` reads back exactly.
pub fn hex(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    let sign = if x.is_sign_negative() { "-" } else { "" };
    if x.is_infinite() {
        return format!("{sign}inf");
    }
    let bits = x.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i64;
    let mant = bits & ((1u64 << 52) - 1);
    if exp == 0 && mant == 0 {
        return format!("{sign}0x0.0p+0");
    }
    let (lead, e) = if exp == 0 {
        (0, -1022)
    } else {
        (1, exp - 1023)
    };
    let esign = if e < 0 { '-' } else { '+' };
    format!("{sign}0x{lead}.{mant:013x}p{esign}{}", e.abs())
}

/// A hexadecimal float (`[-]0xH.HHHp[+-]E`, as [`hex`] and Python write
/// them, or `inf`/`nan`) read exactly; `None` if it is not one or has more
/// digits than a double holds.
pub fn unhex(s: &str) -> Option<f64> {
    let (neg, body) = match s.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, s.strip_prefix('+').unwrap_or(s)),
    };
    let signed = |x: f64| if neg { -x } else { x };
    match body {
        "inf" => return Some(signed(f64::INFINITY)),
        "nan" => return Some(f64::NAN),
        _ => {}
    }
    let body = body.strip_prefix("0x")?;
    let (digits, exp) = body.split_once('p')?;
    let exp: i64 = exp.parse().ok()?;
    let (int, frac) = digits.split_once('.').unwrap_or((digits, ""));
    if int.len() != 1 || frac.len() > 13 {
        return None;
    }
    let lead = u64::from_str_radix(int, 16).ok()?;
    if lead > 1 {
        return None;
    }
    let frac_bits = if frac.is_empty() {
        0
    } else {
        u64::from_str_radix(frac, 16).ok()? << (4 * (13 - frac.len()))
    };
    if lead == 0 {
        if frac_bits == 0 {
            return Some(signed(0.0));
        }
        // Subnormal: 0.f × 2^-1022 exactly.
        if exp != -1022 {
            return None;
        }
        return Some(signed(f64::from_bits(frac_bits)));
    }
    if !(-1022..=1023).contains(&exp) {
        return None;
    }
    let bits = (((exp + 1023) as u64) << 52) | frac_bits;
    Some(signed(f64::from_bits(bits)))
}

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
    fn request(&self) -> Value {
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

/// How a REBOUND method is swept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sweep {
    /// A fixed step: the sweep's step counts, `dt = T/n`, exactly `n` steps.
    Steps,
    /// IAS15: `epsilon` from 1 to 1e-9, one per decade (its error at the
    /// default 1e-9 is already near round-off).
    Ias15,
    /// Gragg–Bulirsch–Stoer: `eps_abs = eps_rel` over the sweep's DOP853
    /// tolerances.
    Bs,
}

/// A REBOUND integrator with its settings, as a method of a comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct ReboundMethod {
    /// `rebound:NAME[:KEY=VALUE…]`, as given.
    pub id: String,
    /// REBOUND's integrator name (`sim.integrator = …`).
    pub integrator: &'static str,
    /// `sim.integrator.KEY = VALUE`, in order (the defaults first).
    pub settings: Vec<(String, Value)>,
    /// Classical order in the step size (the corrected and near-integrable
    /// methods have higher orders in the small parameter).
    pub order: usize,
    pub symplectic: bool,
    pub sweep: Sweep,
    /// The interpreter ([`python`] by default).
    pub python: PathBuf,
}

/// A setting's accepted values.
enum Accepts {
    Ints(&'static [i64]),
    Names(&'static [&'static str]),
    Positive,
}

/// The settings each integrator accepts.
fn accepted(integrator: &str) -> &'static [(&'static str, Accepts)] {
    const WHFAST: &[(&str, Accepts)] = &[
        ("corrector", Accepts::Ints(&[0, 3, 5, 7, 11, 17])),
        ("corrector2", Accepts::Ints(&[0, 1])),
        (
            "kernel",
            Accepts::Names(&["default", "modifiedkick", "composition", "lazy"]),
        ),
        (
            "coordinates",
            Accepts::Names(&["jacobi", "democraticheliocentric", "whds", "barycentric"]),
        ),
        ("safe_mode", Accepts::Ints(&[0, 1])),
    ];
    const WHFAST512: &[(&str, Accepts)] = &[("corrector", Accepts::Ints(&[0, 17]))];
    const SAFE: &[(&str, Accepts)] = &[("safe_mode", Accepts::Ints(&[0, 1]))];
    const LEAPFROG: &[(&str, Accepts)] = &[("order", Accepts::Ints(&[2, 4, 6, 8]))];
    const MERCURIUS: &[(&str, Accepts)] = &[
        ("r_crit_hill", Accepts::Positive),
        ("safe_mode", Accepts::Ints(&[0, 1])),
    ];
    match integrator {
        "whfast" | "whckl" | "whckm" | "whckc" => WHFAST,
        "whfast512" => WHFAST512,
        "saba" => SAFE,
        "leapfrog" => LEAPFROG,
        "mercurius" => MERCURIUS,
        _ => &[],
    }
}

/// The names after `rebound:`, with REBOUND's integrator, the default
/// settings, the classical order, symplecticity and sweep.
struct Entry {
    name: &'static str,
    integrator: &'static str,
    defaults: &'static [(&'static str, &'static str)],
    order: usize,
    symplectic: bool,
    sweep: Sweep,
}

const fn fixed(
    name: &'static str,
    integrator: &'static str,
    defaults: &'static [(&'static str, &'static str)],
    order: usize,
) -> Entry {
    Entry {
        name,
        integrator,
        defaults,
        order,
        symplectic: true,
        sweep: Sweep::Steps,
    }
}

/// `safe_mode = 0`: REBOUND's fast mode (no synchronisation, and no
/// corrector applied and undone, between steps; `integrate` synchronises at
/// its end), the way its documentation says to time it.
const FAST: &[(&str, &str)] = &[("safe_mode", "0")];

/// Every name `rebound:` takes.
const ENTRIES: &[Entry] = &[
    fixed("whfast", "whfast", FAST, 2),
    fixed("whckl", "whckl", FAST, 2),
    fixed("whckm", "whckm", FAST, 2),
    fixed("whckc", "whckc", FAST, 2),
    fixed("whfast512", "whfast512", &[], 2),
    fixed("saba1", "saba", &[("safe_mode", "0"), ("type", "1")], 2),
    fixed("saba2", "saba", &[("safe_mode", "0"), ("type", "2")], 2),
    fixed("saba3", "saba", &[("safe_mode", "0"), ("type", "3")], 2),
    fixed("saba4", "saba", &[("safe_mode", "0"), ("type", "4")], 2),
    fixed(
        "sabacm1",
        "saba",
        &[("safe_mode", "0"), ("type", "CM_1")],
        4,
    ),
    fixed(
        "sabacm2",
        "saba",
        &[("safe_mode", "0"), ("type", "CM_2")],
        4,
    ),
    fixed(
        "sabacm3",
        "saba",
        &[("safe_mode", "0"), ("type", "CM_3")],
        4,
    ),
    fixed(
        "sabacm4",
        "saba",
        &[("safe_mode", "0"), ("type", "CM_4")],
        4,
    ),
    fixed(
        "sabacl1",
        "saba",
        &[("safe_mode", "0"), ("type", "CL_1")],
        4,
    ),
    fixed(
        "sabacl2",
        "saba",
        &[("safe_mode", "0"), ("type", "CL_2")],
        4,
    ),
    fixed(
        "sabacl3",
        "saba",
        &[("safe_mode", "0"), ("type", "CL_3")],
        4,
    ),
    fixed(
        "sabacl4",
        "saba",
        &[("safe_mode", "0"), ("type", "CL_4")],
        4,
    ),
    fixed(
        "saba-10-4",
        "saba",
        &[("safe_mode", "0"), ("type", "10_4")],
        4,
    ),
    fixed(
        "saba-8-6-4",
        "saba",
        &[("safe_mode", "0"), ("type", "8_6_4")],
        4,
    ),
    fixed(
        "saba-10-6-4",
        "saba",
        &[("safe_mode", "0"), ("type", "10_6_4")],
        4,
    ),
    fixed(
        "sabah-8-4-4",
        "saba",
        &[("safe_mode", "0"), ("type", "H_8_4_4")],
        4,
    ),
    fixed(
        "sabah-8-6-4",
        "saba",
        &[("safe_mode", "0"), ("type", "H_8_6_4")],
        4,
    ),
    fixed(
        "sabah-10-6-4",
        "saba",
        &[("safe_mode", "0"), ("type", "H_10_6_4")],
        4,
    ),
    fixed("leapfrog", "leapfrog", &[], 2),
    fixed("mercurius", "mercurius", FAST, 2),
    Entry {
        name: "ias15",
        integrator: "ias15",
        defaults: &[],
        order: 15,
        symplectic: false,
        sweep: Sweep::Ias15,
    },
    Entry {
        name: "bs",
        integrator: "bs",
        defaults: &[],
        order: 0,
        symplectic: false,
        sweep: Sweep::Bs,
    },
];

/// The names `rebound:` takes.
pub fn names() -> Vec<&'static str> {
    ENTRIES.iter().map(|e| e.name).collect()
}

/// A setting's value as the script passes it to REBOUND: an integer, a
/// number, or an option's name (REBOUND matches those case-insensitively).
fn setting_value(
    id: &str,
    integrator: &str,
    key: &str,
    value: &str,
) -> std::result::Result<Value, String> {
    let table = accepted(integrator);
    let Some((_, accepts)) = table.iter().find(|(k, _)| *k == key) else {
        let keys: Vec<&str> = table.iter().map(|(k, _)| *k).collect();
        return Err(if keys.is_empty() {
            format!("method '{id}' (--methods): REBOUND's {integrator} takes no settings here")
        } else {
            format!(
                "method '{id}' (--methods): unknown setting '{key}' of REBOUND's {integrator}; it takes {}",
                keys.join(", ")
            )
        });
    };
    let bad = |valid: String| {
        format!("method '{id}' (--methods): {key} = '{value}' is not accepted; {key} takes {valid}")
    };
    match accepts {
        Accepts::Ints(valid) => match value.parse::<i64>() {
            Ok(v) if valid.contains(&v) => Ok(json!(v)),
            _ => Err(bad(valid
                .iter()
                .map(|v| v.to_string())
                .collect::<Vec<_>>()
                .join(", "))),
        },
        Accepts::Names(valid) => {
            let lower = value.to_ascii_lowercase();
            if valid.contains(&lower.as_str()) {
                Ok(json!(lower.to_ascii_uppercase()))
            } else {
                Err(bad(valid.join(", ")))
            }
        }
        Accepts::Positive => match value.parse::<f64>() {
            Ok(v) if v.is_finite() && v > 0.0 => Ok(json!(hex(v))),
            _ => Err(bad("a finite number > 0".into())),
        },
    }
}

impl ReboundMethod {
    /// `rebound:NAME[:KEY=VALUE…]` (`id` with or without the prefix). The
    /// error names the method and lists the valid names, settings or values.
    pub fn parse(id: &str) -> Result<Self> {
        let spec = id.strip_prefix("rebound:").unwrap_or(id);
        let full = format!("rebound:{spec}");
        let mut parts = spec.split(':');
        let name = parts.next().unwrap_or_default();
        let Some(entry) = ENTRIES.iter().find(|e| e.name == name) else {
            return Err(CompareError::method(
                &full,
                format!(
                    "method '{full}' (--methods): unknown REBOUND integrator '{name}'; rebound: takes {} \
                     (settings as rebound:NAME:KEY=VALUE, e.g. rebound:whfast:corrector=11)",
                    names().join(", ")
                ),
            ));
        };
        let mut settings: Vec<(String, Value)> = entry
            .defaults
            .iter()
            .map(|(k, v)| {
                let value = v.parse::<i64>().map_or_else(|_| json!(v), |n| json!(n));
                (k.to_string(), value)
            })
            .collect();
        for part in parts {
            let Some((key, value)) = part.split_once('=') else {
                return Err(CompareError::method(
                    &full,
                    format!(
                        "method '{full}' (--methods): '{part}' is not a setting KEY=VALUE (e.g. rebound:whfast:corrector=11)"
                    ),
                ));
            };
            let value = setting_value(&full, entry.integrator, key, value)
                .map_err(|why| CompareError::method(&full, why))?;
            settings.retain(|(k, _)| k != key);
            settings.push((key.to_string(), value));
        }
        Ok(ReboundMethod {
            id: full,
            integrator: entry.integrator,
            settings,
            order: entry.order,
            symplectic: entry.symplectic,
            sweep: entry.sweep,
            python: python(),
        })
    }

    /// The same method run by another interpreter.
    pub fn with_python(mut self, python: impl Into<PathBuf>) -> Self {
        self.python = python.into();
        self
    }

    /// Whether this is WHFast512 (AVX-512 only).
    pub fn is_whfast512(&self) -> bool {
        self.integrator == "whfast512"
    }

    /// The points of a sweep: step counts, or tolerances.
    pub fn points(&self, steps: &[u64], tolerances: &[f64]) -> Vec<Point> {
        match self.sweep {
            Sweep::Steps => steps.iter().map(|&n| Point::Steps(n)).collect(),
            Sweep::Ias15 => tolerance_range(10, 0, 9)
                .into_iter()
                .map(Point::Tolerance)
                .collect(),
            Sweep::Bs => tolerances.iter().map(|&t| Point::Tolerance(t)).collect(),
        }
    }
}

/// The method `rebound:…` for `sys`: an error when the problem has no
/// bodies for REBOUND.
pub fn method<P: Problem>(id: &str, sys: &P) -> Result<ReboundMethod> {
    let m = ReboundMethod::parse(id)?;
    match sys.rebound_bodies(&sys.start()) {
        Some(Ok(_)) => Ok(m),
        Some(Err(why)) => Err(CompareError::method(
            &m.id,
            format!(
                "method '{}': the {} problem cannot be given to REBOUND: {why}",
                m.id,
                sys.name()
            ),
        )),
        None => Err(CompareError::method(
            &m.id,
            format!(
                "method '{}': REBOUND integrates point masses under gravity; the {} problem is not one \
                 (rebound: methods run on outer-solar, kepler and kepler-hard)",
                m.id,
                sys.name()
            ),
        )),
    }
}

/// One run's point on the sweep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Point {
    Steps(u64),
    Tolerance(f64),
}

/// Why a request got no answer: the interpreter or REBOUND is missing
/// (`missing`), or the script said why.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    pub missing: bool,
    pub message: String,
}

/// Run the script with one request; its JSON answer (`ok: true`) or why not.
pub fn request(python: &Path, req: &Value) -> std::result::Result<Value, Failure> {
    let spawned = Command::new(python)
        .arg("-c")
        .arg(SCRIPT)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn();
    let mut child = match spawned {
        Ok(c) => c,
        Err(e) => {
            return Err(Failure {
                missing: true,
                message: format!(
                    "cannot start the Python interpreter '{}' ({e}; set {PYTHON_VAR} to another)",
                    python.display()
                ),
            });
        }
    };
    let text = req.to_string();
    if let Some(mut stdin) = child.stdin.take() {
        // A script that died early closes its end; its answer says why.
        let _ = stdin.write_all(text.as_bytes());
    }
    let out = child.wait_with_output().map_err(|e| Failure {
        missing: false,
        message: format!("waiting for '{}': {e}", python.display()),
    })?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let answer: Value = match serde_json::from_str(stdout.trim()) {
        Ok(v) => v,
        Err(_) => {
            let stderr = String::from_utf8_lossy(&out.stderr);
            let last = stderr.lines().last().unwrap_or("").trim().to_string();
            return Err(Failure {
                missing: false,
                message: format!(
                    "the REBOUND script under '{}' gave no answer ({}{})",
                    python.display(),
                    out.status,
                    if last.is_empty() {
                        String::new()
                    } else {
                        format!(": {last}")
                    }
                ),
            });
        }
    };
    if answer["ok"] == json!(true) {
        Ok(answer)
    } else {
        Err(Failure {
            missing: answer["missing"] == json!(true),
            message: answer["error"]
                .as_str()
                .unwrap_or("the script failed without saying why")
                .to_string(),
        })
    }
}

/// REBOUND's version under `python`, or the message saying what is missing
/// and how to install it.
pub fn probe(python: &Path) -> std::result::Result<String, String> {
    match request(python, &json!({"probe": "version"})) {
        Ok(a) => Ok(a["rebound"].as_str().unwrap_or("unknown").to_string()),
        Err(f) if f.missing => Err(format!(
            "REBOUND is not available: {}. Install it with `{INSTALL}` (and Python 3 if it is missing)",
            f.message
        )),
        Err(f) => Err(format!("REBOUND does not answer: {}", f.message)),
    }
}

/// Whether this CPU has AVX-512 (Linux: `avx512f` in `/proc/cpuinfo`).
pub fn cpu_has_avx512() -> bool {
    std::fs::read_to_string("/proc/cpuinfo")
        .map(|s| {
            s.lines()
                .filter(|l| l.starts_with("flags"))
                .any(|l| l.split_whitespace().any(|f| f == "avx512f"))
        })
        .unwrap_or(false)
}

/// Whether WHFast512 runs here: AVX-512 on the CPU, and a few steps of it in
/// the installed package.
pub fn probe_whfast512(python: &Path) -> std::result::Result<(), String> {
    if !cpu_has_avx512() {
        return Err(
            "WHFast512 needs AVX-512, which this CPU does not have (no avx512f in /proc/cpuinfo)"
                .into(),
        );
    }
    request(python, &json!({"probe": "whfast512"}))
        .map(|_| ())
        .map_err(|f| format!("WHFast512 does not run here: {}", f.message))
}

/// What REBOUND can run in a sweep: its version, and a note for each method
/// left out and why.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Availability {
    pub version: Option<String>,
    pub notes: Vec<String>,
    /// The ids of the methods left out.
    pub left_out: Vec<String>,
}

/// Probe once per interpreter (and WHFast512 once) for `methods`.
pub fn availability<'a>(methods: impl IntoIterator<Item = &'a ReboundMethod>) -> Availability {
    let mut out = Availability::default();
    let mut probed: Vec<(PathBuf, std::result::Result<String, String>)> = Vec::new();
    let mut w512: Option<std::result::Result<(), String>> = None;
    let mut missing: Vec<(String, Vec<String>)> = Vec::new();
    for m in methods {
        let version = match probed.iter().find(|(p, _)| *p == m.python) {
            Some((_, v)) => v.clone(),
            None => {
                let v = probe(&m.python);
                probed.push((m.python.clone(), v.clone()));
                v
            }
        };
        let why = match version {
            Err(why) => Some(why),
            Ok(v) => {
                out.version.get_or_insert(v);
                if m.is_whfast512() {
                    w512.get_or_insert_with(|| probe_whfast512(&m.python))
                        .clone()
                        .err()
                } else {
                    None
                }
            }
        };
        if let Some(why) = why {
            out.left_out.push(m.id.clone());
            match missing.iter_mut().find(|(w, _)| *w == why) {
                Some((_, ids)) => ids.push(m.id.clone()),
                None => missing.push((why, vec![m.id.clone()])),
            }
        }
    }
    for (why, ids) in missing {
        out.notes.push(format!(
            "{why}; left out: {}; the other methods ran.",
            ids.join(", ")
        ));
    }
    out
}

/// The state in a `positions`/`velocities` pair of an answer.
fn triples(v: &Value, what: &str) -> std::result::Result<Vec<[f64; 3]>, String> {
    let rows = v
        .as_array()
        .ok_or_else(|| format!("the answer has no {what}"))?;
    rows.iter()
        .enumerate()
        .map(|(i, r)| {
            let c = r
                .as_array()
                .filter(|c| c.len() == 3)
                .ok_or_else(|| format!("{what} of body {i}: not three numbers"))?;
            let mut out = [0.0; 3];
            for (k, x) in c.iter().enumerate() {
                out[k] = x
                    .as_str()
                    .and_then(unhex)
                    .ok_or_else(|| format!("{what} of body {i}: {x} is not a hexadecimal float"))?;
            }
            Ok(out)
        })
        .collect()
}

/// The problem's state from an answer's (or a sample's) particles.
pub fn state_of(bodies: &Bodies, v: &Value) -> std::result::Result<Vec<f64>, String> {
    let p = triples(&v["positions"], "positions")?;
    let w = triples(&v["velocities"], "velocities")?;
    if p.len() != bodies.masses.len() || w.len() != bodies.masses.len() {
        return Err(format!(
            "the answer has {} bodies, the request {}",
            p.len(),
            bodies.masses.len()
        ));
    }
    Ok(bodies.state(&p, &w))
}

/// The particles REBOUND holds after building `bodies`, read back as the
/// problem's state (the round trip of the initial state).
pub fn echo(python: &Path, bodies: &Bodies) -> std::result::Result<Vec<f64>, String> {
    let a = request(python, &json!({"echo": bodies.request()})).map_err(|f| f.message)?;
    state_of(bodies, &a)
}

/// What one REBOUND run gave.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The problem's state at the end.
    pub end: Vec<f64>,
    /// The problem's state at the sampled points of the observed run.
    pub samples: Vec<Vec<f64>>,
    pub steps: u64,
    /// Wall times of the timed `integrate` calls, seconds.
    pub times: Vec<f64>,
    /// The timed runs ended on the warm-up's bits.
    pub reproducible: bool,
    pub version: String,
}

/// One REBOUND run of `m` on `bodies` over `[0, t_end]` at `point`:
/// observed, warmed up and timed `repeats` times in one process.
pub fn run_bodies(
    bodies: &Bodies,
    m: &ReboundMethod,
    t_end: f64,
    point: Point,
    h_guess: f64,
    repeats: usize,
) -> std::result::Result<Outcome, String> {
    let (steps, tolerance, dt) = match point {
        Point::Steps(n) => (json!(n), Value::Null, t_end / n as f64),
        Point::Tolerance(t) => (Value::Null, json!(hex(t)), h_guess),
    };
    let req = json!({
        "run": bodies.request(),
        "integrator": m.integrator,
        "settings": m.settings.iter().map(|(k, v)| json!([k, v])).collect::<Vec<_>>(),
        "steps": steps,
        "tolerance": tolerance,
        "dt": hex(dt),
        "t_end": hex(t_end),
        "repeats": repeats,
        "samples": ENERGY_SAMPLES,
    });
    let a = request(&m.python, &req).map_err(|f| f.message)?;
    let end = state_of(bodies, &a)?;
    let samples = a["samples"]
        .as_array()
        .map(|s| s.iter().map(|x| state_of(bodies, x)).collect())
        .unwrap_or_else(|| Ok(vec![]))?;
    let times = a["times"]
        .as_array()
        .map(|t| t.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default();
    Ok(Outcome {
        end,
        samples,
        steps: a["steps"].as_u64().unwrap_or(0),
        times,
        reproducible: a["reproducible"] == json!(true),
        version: a["rebound"].as_str().unwrap_or("unknown").to_string(),
    })
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

/// One row of a sweep: `m` on `setup` at `point`, the error measured here
/// against the setup's reference, the energy error over the sampled states
/// and the end, the median of the timed `integrate` calls. `h_guess` is the
/// first step of an adaptive integrator.
pub fn row<P: Problem>(
    setup: &Setup<P>,
    m: &ReboundMethod,
    point: Point,
    h_guess: f64,
    repeats: usize,
) -> Row {
    let mut row = Row {
        problem: setup.name.clone(),
        method: m.id.clone(),
        family: Family::Rebound,
        order: m.order,
        symplectic: m.symplectic,
        h: f64::NAN,
        tol: f64::NAN,
        steps: 0,
        error: f64::NAN,
        energy_error: f64::NAN,
        time_s: f64::NAN,
        evals: 0,
        newton_iterations: 0,
        fixed_point_iterations: 0,
        factorizations: 0,
        status: String::new(),
        interpreted: false,
    };
    match point {
        Point::Steps(n) => {
            row.steps = n;
            row.h = setup.t_end / n as f64;
        }
        Point::Tolerance(t) => row.tol = t,
    }
    let bodies = match setup.sys.rebound_bodies(&setup.z0) {
        Some(Ok(b)) => b,
        Some(Err(why)) => {
            row.status = format!("not run: {why}");
            return row;
        }
        None => {
            row.status = "not run: the problem has no bodies for REBOUND".into();
            return row;
        }
    };
    let outcome = match run_bodies(&bodies, m, setup.t_end, point, h_guess, repeats) {
        Ok(o) => o,
        Err(why) => {
            row.status = format!("rebound failed: {why}");
            return row;
        }
    };
    row.steps = outcome.steps;
    if outcome.steps > 0 {
        row.h = setup.t_end / outcome.steps as f64;
    }
    row.energy_error = outcome
        .samples
        .iter()
        .chain(std::iter::once(&outcome.end))
        .map(|z| setup.energy_error(z))
        .fold(0.0, f64::max);
    let error = setup.error(&outcome.end);
    if !(error.is_finite() && row.energy_error.is_finite()) {
        row.status = format!(
            "diverged at step {}: the error or the energy is not finite",
            outcome.steps
        );
    } else if !outcome.reproducible {
        row.status = "rebound failed: the timed runs did not end on the warm-up's bits".into();
    } else {
        row.error = error;
        row.time_s = median(outcome.times);
        row.status = "ok".into();
    }
    row
}

/// Whether a row's method is one of REBOUND's.
pub fn is_rebound(method: &str) -> bool {
    method.starts_with("rebound:")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_matches_python_float_hex() {
        assert_eq!(hex(1.0), "0x1.0000000000000p+0");
        assert_eq!(hex(-0.5), "-0x1.0000000000000p-1");
        assert_eq!(hex(0.0), "0x0.0p+0");
        assert_eq!(hex(-0.0), "-0x0.0p+0");
        assert_eq!(hex(5e-324), "0x0.0000000000001p-1022");
        assert_eq!(hex(0.1), "0x1.999999999999ap-4");
        assert_eq!(hex(f64::MAX), "0x1.fffffffffffffp+1023");
    }

    #[test]
    fn unhex_reads_back_every_kind_of_double() {
        for x in [
            1.0,
            -0.5,
            0.1,
            2.95912208286e-4,
            1.0 / 1.3e8,
            5e-324,
            -2.2250738585072014e-308 / 3.0,
            f64::MAX,
            f64::MIN_POSITIVE,
            f64::INFINITY,
        ] {
            let back = unhex(&hex(x)).unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x}");
        }
        assert_eq!(unhex("-0x0.0p+0").unwrap().to_bits(), (-0.0f64).to_bits());
        assert_eq!(unhex("0x1.8p+1"), Some(3.0));
        assert!(unhex("nan").unwrap().is_nan());
        for bad in [
            "",
            "1.0",
            "0x2.0p+0",
            "0x1.0p",
            "0x1.00000000000000p+0",
            "0x1.0p+1024",
        ] {
            assert_eq!(unhex(bad), None, "{bad}");
        }
    }

    #[test]
    fn names_settings_and_their_errors() {
        let m = ReboundMethod::parse("rebound:whfast:corrector=11").unwrap();
        assert_eq!(m.integrator, "whfast");
        assert!(m.settings.contains(&("corrector".into(), json!(11))));
        assert!(m.settings.contains(&("safe_mode".into(), json!(0))));
        let m = ReboundMethod::parse("rebound:whfast:kernel=Lazy:safe_mode=1").unwrap();
        assert!(m.settings.contains(&("kernel".into(), json!("LAZY"))));
        assert!(m.settings.contains(&("safe_mode".into(), json!(1))));
        assert!(!m.settings.contains(&("safe_mode".into(), json!(0))));
        let s = ReboundMethod::parse("rebound:saba-10-6-4").unwrap();
        assert_eq!(s.integrator, "saba");
        assert!(s.settings.contains(&("type".into(), json!("10_6_4"))));
        assert_eq!(
            ReboundMethod::parse("rebound:ias15").unwrap().sweep,
            Sweep::Ias15
        );
        let e = ReboundMethod::parse("rebound:whfastt")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("rebound:whfastt") && e.contains("--methods") && e.contains("whckl"),
            "{e}"
        );
        let e = ReboundMethod::parse("rebound:whfast:corrector=4")
            .unwrap_err()
            .to_string();
        assert!(e.contains("corrector") && e.contains("11, 17"), "{e}");
        let e = ReboundMethod::parse("rebound:whfast:order=4")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("unknown setting 'order'") && e.contains("kernel"),
            "{e}"
        );
        let e = ReboundMethod::parse("rebound:ias15:epsilon=1e-9")
            .unwrap_err()
            .to_string();
        assert!(e.contains("takes no settings"), "{e}");
        let e = ReboundMethod::parse("rebound:whfast:corrector")
            .unwrap_err()
            .to_string();
        assert!(e.contains("KEY=VALUE"), "{e}");
    }

    #[test]
    fn bodies_round_trip_the_momenta_or_name_the_body() {
        let z = [1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.5, 0.25, 0.0, 0.0, 0.0, 0.0];
        let b = Bodies::from_momenta(1.0, &["a", "b"], &[2.0, 1.0], &z).unwrap();
        assert_eq!(b.velocities[0], [0.25, 0.125, 0.0]);
        assert_eq!(b.state(&b.positions, &b.velocities), z.to_vec());
        let e = Bodies::from_momenta(1.0, &["a", "b"], &[2.0, 0.0], &z).unwrap_err();
        assert!(e.contains("body 1 (b)") && e.contains("mass"), "{e}");
        // 0.1 / 3 × 3 ≠ 0.1 in doubles: no velocity gives back that momentum.
        let mut w = z;
        w[6] = 0.1;
        let m = (1..1000)
            .map(|k| 1.0 + k as f64 * 1e-3)
            .find(|m| m * (0.1 / m) != 0.1)
            .unwrap();
        let e = Bodies::from_momenta(1.0, &["a", "b"], &[m, 1.0], &w).unwrap_err();
        assert!(e.contains("body 0 (a), momentum component x"), "{e}");
    }
}
