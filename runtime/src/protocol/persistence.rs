//! The register choosing where parameter writes go ([`PersistenceSelector`],
//! `persistence:`).

use crate::kinds::{CommandKind, DataType, Space};
use crate::layout::List;
use crate::register::Request;

/// A register of the drive whose value chooses where parameter writes over the link go
/// (DV1 07-11 / P.34: 0 RAM and EEPROM, 1 RAM only). Writing the selector is itself a
/// parameter write, governed by the value it has before the write.
///
/// [`crate::transaction::Master`] remembers the selector's value and sets it before a write
/// it governs: to `ram` before a RAM write (which stores `ram` in the EEPROM too when the
/// selector held `persistent`), and around a persistent write to `persistent` and back
/// (the value written back is stored in the EEPROM, which held it already). See
/// drives/README.md, "Persistence chosen by a register".
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct PersistenceSelector {
    /// The selector's register number (before the address map).
    pub register: u16,
    /// The selector's address space.
    pub space: Space,
    /// The selector's data type.
    pub data_type: DataType,
    /// The value with which parameter writes go to RAM only.
    pub ram: u32,
    /// The value with which parameter writes go to RAM and EEPROM.
    pub persistent: u32,
    /// The register numbers (first, last) whose writes it governs; empty: every parameter.
    pub registers: List<(u16, u16)>,
}

impl PersistenceSelector {
    /// Whether a write of register `register` in `space` goes where the selector says:
    /// a parameter (not RAM only) among the governed numbers.
    pub fn governs(&self, space: Space, register: u16, ram_only: bool) -> bool {
        space == Space::Parameter
            && !ram_only
            && (self.registers.is_empty()
                || self
                    .registers
                    .iter()
                    .any(|&(from, to)| (from..=to).contains(&register)))
    }

    /// Whether `request` is a write the selector governs: a write of a described register
    /// (a request built from its [`crate::info::RegisterInfo`]) that it governs. Requests
    /// by number alone ([`Request::raw`]) go as they are: their number may not be a
    /// parameter at all (the Eaton page switch 7Fh is P.127's number).
    pub fn governs_request(&self, request: &Request) -> bool {
        request.kind.is_write()
            && request
                .info
                .is_some_and(|info| self.governs(request.space, request.register, info.ram_only))
    }

    /// Whether `request` is addressed to the selector itself.
    pub fn is_selector(&self, request: &Request) -> bool {
        request.space == self.space && request.register == self.register
    }

    /// A request writing `value` to the selector.
    pub fn write(&self, value: u32) -> Request {
        Request::raw(CommandKind::WriteRam, self.register, value)
            .in_space(self.space)
            .with_data_type(self.data_type)
    }

    /// A request reading the selector.
    pub fn read(&self) -> Request {
        Request::raw(CommandKind::Read, self.register, 0)
            .in_space(self.space)
            .with_data_type(self.data_type)
    }
}
