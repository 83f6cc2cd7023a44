//! Stage 5: the intermediate representation, the only input of every emitter.
//!
//! Its `lower` function turns a checked description into a [`DriveIr`]: plain, ordered, typed data
//! (enums for every enumerated key, the runtime's own layouts and frame meanings), with Rust
//! names chosen and ranges resolved. It serialises; `vfd generate --dump-ir DRIVE` prints it.

mod lower;
mod types;

pub(crate) use lower::lower;
pub use types::*;

impl DriveIr {
    /// The IR as YAML, for people and snapshot tests.
    pub fn to_yaml(&self) -> String {
        serde_yaml::to_string(self).unwrap_or_else(|error| format!("# cannot serialise: {error}"))
    }
}
