//! Shared support for the workspace-level tests: expectation files for diagnostics and a
//! scripted peer for exchanges. The generated golden-frame tests call
//! `vfd_runtime::testing` (the runtime's `testing` feature).

pub mod expectations;
pub mod scripted_peer;
