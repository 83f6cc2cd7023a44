//! Shared support for the workspace-level tests: the golden-frame assertions that the
//! generated tests (one per manual example) call, expectation files for diagnostics, and a
//! scripted peer for exchanges, and the module-graph check that keeps each crate free of
//! import circles.

pub mod expectations;
pub mod golden;
pub mod module_graph;
pub mod scripted_peer;
