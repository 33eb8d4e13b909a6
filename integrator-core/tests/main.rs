//! Integration tests of `integrator-core`, one test binary: each module is one of the
//! files beside this one (`cargo test --test integration MODULE::`).
//! One binary links the crate and its dependencies once, where a binary
//! per file linked them once per file (the README's test command took
//! about 30 minutes on a clean 2-core machine, mostly compiling and
//! linking test binaries).
//! The tests that install a global allocator of their own keep a binary
//! each: `implicit`.

mod common;
mod double_double;
mod quartic;

mod adaptive;
mod bad_input;
mod brouwer;
mod constrained_accuracy;
mod constrained_bad_input;
mod constrained_geometry;
mod convergence;
mod fixed;
mod fsal;
mod generated_schemes;
mod gradient_kicks;
mod hard_problems;
mod high_precision;
mod implicit_library;
mod kepler_flow;
mod kepler_warm;
mod linear;
mod macro_constants;
mod midpoint_weights;
mod minimise;
mod near_integrable_claims;
mod near_integrable_scaling;
mod outer_solar;
mod processed;
mod registry;
mod reversibility;
mod root_schemes;
mod simd_lanes;
mod split_systems;
mod symplectic_in_fact;
mod time_transform;
mod wisdom_holman;
