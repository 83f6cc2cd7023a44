//! Plant files (placeholder on the `mqtt` branch: helper A's loader replaces this file).

#[allow(dead_code)]
pub mod model;
pub use model::*;
