//! The tests that were `compare`'s unit tests, one module per source
//! module (`compare::nbody::bodies` → `nbody_bodies`). `compare` has no
//! unit-test harness (`[lib] test = false`): that harness compiled the
//! whole crate, every scheme on every problem, a second time, minutes of
//! CI (issue 35). The items they test are public, most of them already
//! part of the API, the rest `#[doc(hidden)]`.

mod adaptive;
mod builtin;
mod counting;
mod format;
mod guard;
mod library;
mod long;
mod nbody_bodies;
mod nbody_hexfloat;
mod output;
mod paper_oscillator;
mod peer_study;
mod plot;
mod rebound_names;
mod registry;
mod report;
mod sweep;
mod versus;
