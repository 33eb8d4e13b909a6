//! The design crate's integration tests, one binary (see the workspace's
//! convention): the conditions against tableau's own order theory, the
//! recovery of published methods from random starts, the certificates, the
//! family files, and the second-corrector family.

mod certificate;
mod common;
mod conditions;
mod effective;
mod families;
mod processed;
mod recover;
mod stability;
