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

    /// The manual as people name it: `Title (标题), document D`; the file name when the
    /// description gives no title.
    pub fn manual_named(&self) -> String {
        let mut named = match (
            self.manual_title.is_empty(),
            self.manual_title_zh.is_empty(),
        ) {
            (true, true) => return self.manual.clone(),
            (false, true) => self.manual_title.clone(),
            (true, false) => self.manual_title_zh.clone(),
            (false, false) => format!("{} ({})", self.manual_title, self.manual_title_zh),
        };
        if !self.manual_document.is_empty() {
            named.push_str(&format!(", document {}", self.manual_document));
        }
        named
    }

    /// The manual as a citation beside each register (Markdown): `manual E6581315` by its
    /// document number when it has one, else by its English title in italics, else by its
    /// file name.
    pub fn manual_cited(&self) -> String {
        if !self.manual_document.is_empty() {
            format!("manual {}", self.manual_document)
        } else if !self.manual_title.is_empty() {
            format!("manual *{}*", self.manual_title)
        } else {
            format!("manual `{}`", self.manual)
        }
    }

    /// The IR as YAML, for people and snapshot tests.
    pub fn to_yaml(&self) -> String {
        yaml_serde::to_string(self).unwrap_or_else(|error| format!("# cannot serialise: {error}"))
    }
}
