//! Shared support for the workspace-level tests: the golden-frame assertions that the
//! generated tests (one per manual example) call, and a scripted peer for exchanges.

pub mod golden;
pub mod scripted_peer;
