//! What a generated drive module exposes about itself, so tools can work with any
//! described drive without naming it.

use crate::behaviour::Behaviour;
use crate::conversion::Conversion;
use crate::info::{PortInfo, Ports, RegisterInfo};
use crate::protocol::Protocol;
use crate::register::Request;
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
    /// Source manual: its file name.
    pub manual: &'static str,
    /// The manual as people name it: its title (with the title it prints, in Chinese) and
    /// document number; the file name when the description gives no title.
    pub manual_title: &'static str,
    /// Serial settings.
    pub serial: &'static SerialSpec,
    /// Protocols, by id.
    pub protocols: &'static [&'static Protocol],
    /// Registers, in the manual's order.
    pub registers: &'static [&'static RegisterInfo],
    /// The behaviour model the virtual drive follows, when the description declares one.
    pub behaviour: Option<&'static Behaviour>,
    /// The serial ports, when the drive has several.
    pub ports: Option<&'static Ports>,
    /// The manual's formulas between registers.
    pub conversions: &'static [Conversion],
    /// Combinations of register values the manual forbids (see
    /// [`DriveInfo::check_combinations`]); empty for most drives.
    pub forbidden: &'static [crate::combination::ForbiddenCombination],
    /// Id of the register holding the drive's station number, when the description names
    /// one (`addressing.register`): the virtual drive answers at the station it holds.
    pub station_register: Option<&'static str>,
}

/// One port of a drive, chosen once: requests for a register that exists once per port go
/// to this port's copy ([`Port::map`]). A [`crate::transaction::Master`] given a port
/// (`with_port`) maps every request it sends.
#[derive(Debug, Clone, Copy)]
pub struct Port {
    /// The drive.
    pub drive: &'static DriveInfo,
    /// The port's identifier (`two_wire`).
    pub id: &'static str,
}

impl Port {
    /// The port `name` (identifier or English name) of `drive`, if it has one.
    pub fn of(drive: &'static DriveInfo, name: &str) -> Option<Port> {
        let port = drive.ports?.port(name)?;
        Some(Port { drive, id: port.id })
    }

    /// The port's description.
    pub fn info(&self) -> Option<&'static PortInfo> {
        self.drive.ports?.port(self.id)
    }

    /// This port's copy of `info` (`info` itself when it is not per port).
    pub fn register(&self, info: &'static RegisterInfo) -> &'static RegisterInfo {
        self.drive.on_port(info, self.id)
    }

    /// `request` aimed at this port's copy of its register (unchanged when the register
    /// is not per port, or the request was not built from a described register).
    pub fn map(&self, request: Request) -> Request {
        let Some(info) = request.info else {
            return request;
        };
        let mapped = self.register(info);
        if std::ptr::eq(mapped, info) {
            return request;
        }
        Request {
            register: mapped.address,
            space: mapped.space,
            info: Some(mapped),
            ..request
        }
    }
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

    /// The register at `address` in `space` that a read (`writing` false) or a write
    /// reaches. Two registers share an address only when one is read-only and the other
    /// write-only (1001h read as a status word, written as a run command): the one whose
    /// access allows the direction; otherwise the register at the address, as
    /// [`DriveInfo::register_at`] finds it.
    pub fn register_for(
        &self,
        space: crate::kinds::Space,
        address: u16,
        writing: bool,
    ) -> Option<&'static RegisterInfo> {
        let blocked = if writing {
            crate::kinds::Access::ReadOnly
        } else {
            crate::kinds::Access::WriteOnly
        };
        self.registers
            .iter()
            .copied()
            .find(|r| r.space == space && r.address == address && r.access != blocked)
            .or_else(|| self.register_at(space, address))
    }

    /// The other register at the address of `info`, when two share it (one read-only,
    /// one write-only: see [`DriveInfo::register_for`]).
    pub fn sharing_address(&self, info: &RegisterInfo) -> Option<&'static RegisterInfo> {
        self.registers
            .iter()
            .copied()
            .find(|r| r.space == info.space && r.address == info.address && r.id != info.id)
    }

    /// The copy of `info` on the port `port` (its id), when `info` exists once per port;
    /// otherwise `info` itself.
    pub fn on_port(&self, info: &'static RegisterInfo, port: &str) -> &'static RegisterInfo {
        let code = info.code_on_port(port);
        if code == info.code {
            return info;
        }
        self.register(code).unwrap_or(info)
    }

    /// The conversion with this identifier.
    pub fn conversion(&self, id: &str) -> Option<&'static Conversion> {
        self.conversions.iter().find(|c| c.id == id)
    }

    /// The register with this manual code (case-insensitive) or identifier, else the one
    /// with this alias (case-insensitive: `p.195` names the DV1's 02-15).
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
            .or_else(|| {
                self.registers.iter().copied().find(|r| {
                    r.aliases
                        .iter()
                        .any(|alias| alias.eq_ignore_ascii_case(name))
                })
            })
    }
}

impl DriveInfo {
    /// Checks writing `raw` to `register` against the drive's forbidden combinations, the
    /// other registers holding what `raw_of` gives (by code; `None`: not known, which
    /// fulfils no condition). The first combination the write would make is the error.
    pub fn check_combinations(
        &self,
        register: &'static RegisterInfo,
        raw: u32,
        raw_of: impl Fn(&str) -> Option<u32>,
    ) -> Result<(), crate::combination::CombinationError> {
        let after = |code: &str| {
            if code == register.code {
                Some(raw)
            } else {
                raw_of(code)
            }
        };
        match self
            .forbidden
            .iter()
            .find(|c| c.involves(register) && c.holds(after))
        {
            Some(combination) => Err(crate::combination::CombinationError {
                register,
                raw,
                combination,
            }),
            None => Ok(()),
        }
    }

    /// The forbidden combinations one of whose conditions is about `register`.
    pub fn combinations_of(
        &self,
        register: &RegisterInfo,
    ) -> impl Iterator<Item = &'static crate::combination::ForbiddenCombination> + '_ {
        let code = register.code;
        self.forbidden
            .iter()
            .filter(move |c| c.when.iter().any(|w| w.register == code))
    }
}
