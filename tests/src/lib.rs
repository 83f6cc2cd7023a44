//! Shared support for the workspace-level tests: expectation files for diagnostics, a
//! scripted peer for exchanges, the faults and subjects the fault matrix and the soak share,
//! a drive's typed protocols as one list, and the module-graph check that keeps each crate
//! free of import circles, and the outcomes of exchanges tests assert on. The generated
//! golden-frame tests call `vfd_runtime::testing` (the runtime's `testing` feature).

#![warn(missing_docs)]

pub mod drive_protocols;
pub mod expectations;
pub mod fault_cases;
pub mod linuxcnc;
pub mod masters;
pub mod module_graph;
pub mod out_of_tree;
pub mod outcomes;
pub mod random;
pub mod scripted_peer;
pub mod slack;
pub mod virtual_port;
pub mod watched;
