//! Stage 5: the intermediate representation, the only input of every emitter.
//!
//! Its `lower` function turns a checked description into a [`DriveIr`]: plain, ordered, typed data
//! (enums for every enumerated key, the runtime's own layouts and frame meanings), with Rust
//! names chosen and ranges resolved. It serialises; `vfd generate --dump-ir DRIVE` prints it.

mod behaviour;
mod lower;
mod protocol_lines;
mod types;

pub(crate) use lower::lower;
pub use types::*;

impl DriveIr {
    /// The register with this id.
    pub fn register(&self, id: &str) -> Option<&RegisterIr> {
        self.registers.iter().find(|r| r.id == id)
    }

    /// The register at `address` (before any protocol's address map) in `space`.
    pub fn register_at(&self, space: vfd_runtime::Space, address: u16) -> Option<&RegisterIr> {
        self.registers
            .iter()
            .find(|r| r.space == space && r.address == address)
    }

    /// The IR as YAML, for people and snapshot tests.
    pub fn to_yaml(&self) -> String {
        yaml_serde::to_string(self).unwrap_or_else(|error| format!("# cannot serialise: {error}"))
    }
}
