//! One Python process per request: the script's answer or why there is
//! none, the probes (REBOUND's version, WHFast512), and what a sweep can run.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use serde_json::{Value, json};

use super::{Bodies, INSTALL, PYTHON_VAR, ReboundMethod, SCRIPT, unhex};

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
    // Both pipes read at most a bound each, stderr on a thread of its own
    // (so a script that fills one pipe while we wait on the other cannot
    // block us both). A pipe past its bound is closed: the interpreter then
    // fails on its next write, and one flooding stdout is killed.
    let stderr_pipe = child.stderr.take();
    let stderr_reader = std::thread::spawn(move || {
        stderr_pipe.map_or((Vec::new(), false), |p| read_capped(p, MAX_STDERR_BYTES))
    });
    let (stdout_bytes, flooded) = child
        .stdout
        .take()
        .map_or((Vec::new(), false), |p| read_capped(p, MAX_ANSWER_BYTES));
    if flooded {
        let _ = child.kill();
    }
    let status = child.wait().map_err(|e| Failure {
        missing: false,
        message: format!("waiting for '{}': {e}", python.display()),
    })?;
    let (stderr_bytes, _) = stderr_reader.join().unwrap_or_default();
    if flooded {
        return Err(Failure {
            missing: false,
            message: format!(
                "the REBOUND script under '{}' wrote more than {MAX_ANSWER_BYTES} bytes; an answer is far smaller, so it was stopped",
                python.display()
            ),
        });
    }
    let out = std::process::Output {
        status,
        stdout: stdout_bytes,
        stderr: stderr_bytes,
    };
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

/// The most bytes of an answer read from the script: a run's answer holds
/// the end state and [`super::ENERGY_SAMPLES`] sampled states of a few
/// bodies, a few hundred kilobytes at most.
pub const MAX_ANSWER_BYTES: u64 = 64 << 20;

/// The most bytes of the script's standard error kept (its last line is
/// shown when there is no answer).
pub const MAX_STDERR_BYTES: u64 = 1 << 20;

/// At most `limit` bytes of `pipe`, and whether it had more (then the rest
/// is not read, and the pipe is closed when it is dropped here).
fn read_capped(pipe: impl std::io::Read, limit: u64) -> (Vec<u8>, bool) {
    use std::io::Read as _;
    let mut buf = Vec::new();
    let _ = pipe.take(limit + 1).read_to_end(&mut buf);
    let over = buf.len() as u64 > limit;
    buf.truncate(limit as usize);
    (buf, over)
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
