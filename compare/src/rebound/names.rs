//! The names after `rebound:`: REBOUND's integrator, its settings and what
//! each accepts, the classical order and how the method is swept.

use std::path::PathBuf;

use serde_json::{Value, json};

use super::{Point, hex, python};
use crate::error::{CompareError, Result};
use crate::peer::tolerance_range;

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
