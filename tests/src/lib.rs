//! Shared support for the workspace-level tests: the golden-frame assertions that the
//! generated tests (one per manual example) call, expectation files for diagnostics, and a
//! scripted peer for exchanges.

pub mod expectations;
pub mod golden;
pub mod scripted_peer;
