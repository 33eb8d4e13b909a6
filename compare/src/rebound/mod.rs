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
//! project's own error measure and reference ([`Setup::error`](crate::Setup::error)), comparable bit
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

mod names;
mod process;
mod run;

use std::path::PathBuf;

use crate::error::{CompareError, Result};
use crate::problem::Problem;

pub use crate::nbody::{Bodies, Layout, hex, unhex};
pub use names::{ReboundMethod, Sweep, names};
pub use process::{
    Availability, Failure, availability, cpu_has_avx512, echo, probe, probe_whfast512, request,
    state_of,
};
pub use run::{Outcome, row, run_bodies};

/// The Python script, as shipped in `compare/peers/`.
pub const SCRIPT: &str = include_str!("../../peers/rebound_peer.py");
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

/// The method `rebound:…` for `sys`: an error when the problem has no
/// bodies for REBOUND.
pub fn method<P: Problem>(id: &str, sys: &P, problem: &str) -> Result<ReboundMethod> {
    let m = ReboundMethod::parse(id)?;
    match sys.rebound_bodies(&sys.start()) {
        Some(Ok(_)) => Ok(m),
        Some(Err(why)) => Err(CompareError::method(
            &m.id,
            format!(
                "method '{}': the {problem} problem cannot be given to REBOUND: {why}",
                m.id,
            ),
        )),
        None => Err(CompareError::method(
            &m.id,
            format!(
                "method '{}': REBOUND integrates point masses under gravity; the {problem} problem is not one \
                 (rebound: methods run on outer-solar, kepler and kepler-hard)",
                m.id,
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

/// Whether a row's method is one of REBOUND's.
pub fn is_rebound(method: &str) -> bool {
    method.starts_with("rebound:")
}
