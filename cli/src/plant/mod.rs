//! Plant files (placeholder on the `mqtt` branch: helper A's loader replaces this file).
#![allow(rustdoc::broken_intra_doc_links)] // `load` is helper A's

#[allow(dead_code)]
pub mod model;
pub use model::*;
