//! What a generated drive module exposes about itself, so tools can work with any
//! described drive without naming it.

use crate::behaviour::Behaviour;
use crate::info::RegisterInfo;
use crate::protocol::Protocol;
use crate::serial::SerialSpec;

/// One described drive.
#[derive(Debug)]
pub struct DriveInfo {
    /// Identifier (`yd1000`).
    pub id: &'static str,
    /// Vendor.
    pub vendor: &'static str,
    /// Model.
    pub model: &'static str,
    /// English name.
    pub name: &'static str,
    /// The manual's Chinese name.
    pub name_zh: &'static str,
    /// Source manual.
    pub manual: &'static str,
    /// Serial settings.
    pub serial: &'static SerialSpec,
    /// Protocols, by id.
    pub protocols: &'static [&'static Protocol],
    /// Registers, in the manual's order.
    pub registers: &'static [&'static RegisterInfo],
    /// The behaviour model the virtual drive follows, when the description declares one.
    pub behaviour: Option<&'static Behaviour>,
}

impl DriveInfo {
    /// The protocol with this id (`ascii`).
    pub fn protocol(&self, id: &str) -> Option<&'static Protocol> {
        self.protocols.iter().copied().find(|p| p.id == id)
    }

    /// The register at `address` (before any protocol's address map), in `space`.
    pub fn register_at(
        &self,
        space: crate::kinds::Space,
        address: u16,
    ) -> Option<&'static RegisterInfo> {
        self.registers
            .iter()
            .copied()
            .find(|r| r.space == space && r.address == address)
    }

    /// The register with this manual code (case-insensitive) or identifier.
    pub fn register(&self, name: &str) -> Option<&'static RegisterInfo> {
        self.registers
            .iter()
            .copied()
            .find(|r| r.code == name || r.id == name)
            .or_else(|| {
                self.registers
                    .iter()
                    .copied()
                    .find(|r| r.code.eq_ignore_ascii_case(name))
            })
    }
}
