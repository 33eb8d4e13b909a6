//! The paper reproduction (see the crate documentation).
