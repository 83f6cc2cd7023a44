//! Register metadata and the traits that make register access typed.

use crate::error::ValueError;
use crate::protocol::{DataType, Space};
use crate::units::Unit;

/// Whether a register can be read, written or both over the serial link.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Read only (monitors, status words).
    ReadOnly,
    /// Read and write.
    ReadWrite,
    /// Write only.
    WriteOnly,
}

impl Access {
    /// Name as written in drive files.
    pub const fn as_str(self) -> &'static str {
        match self {
            Access::ReadOnly => "read-only",
            Access::ReadWrite => "read-write",
            Access::WriteOnly => "write-only",
        }
    }
}

/// Everything the manual says about one register, as static data.
#[derive(Debug, Clone, PartialEq)]
pub struct RegisterInfo {
    /// Communication number, parameter number or coil number (before any protocol's address map).
    pub address: u16,
    /// Identifier in the drive file (`deceleration_time_1`).
    pub id: &'static str,
    /// The manual's code or mnemonic (`Dec`, `F800`, `FA01`).
    pub code: &'static str,
    /// English name.
    pub name: &'static str,
    /// The manual's Chinese name.
    pub name_zh: &'static str,
    /// Engineering unit.
    pub unit: Unit,
    /// Engineering value of one raw step (0.01 for 0.01 Hz).
    pub scale: f64,
    /// Whether the raw word is two's-complement signed.
    pub signed: bool,
    /// Lowest raw value accepted (static bound).
    pub raw_min: i64,
    /// Highest raw value accepted (static bound).
    pub raw_max: i64,
    /// Shape on the wire (word, double word, text).
    pub data_type: DataType,
    /// Address space of `address` (parameters, coils).
    pub space: Space,
    /// Number of array elements for indexed parameters; 0 when it is not an array.
    pub array_len: u8,
    /// Code of the register that bounds the value from below at run time (`LL`), if any.
    pub min_bound: Option<&'static str>,
    /// Code of the register that bounds the value from above at run time (`FH`), if any.
    pub max_bound: Option<&'static str>,
    /// Access over the serial link.
    pub access: Access,
    /// Writes go to RAM only; a persistent (EEPROM) write is not allowed.
    pub ram_only: bool,
    /// May be written while the motor runs.
    pub writable_while_running: bool,
    /// Only effective when set from the operator panel.
    pub panel_only: bool,
}

impl RegisterInfo {
    /// `register 0011 FH (Maximum frequency / 最高频率)`: how errors name the register.
    /// The code is left out when it only repeats the address (`FA01`).
    pub fn label(&self) -> String {
        if self.space == Space::Coil {
            return format!(
                "coil {} {} ({} / {})",
                self.address, self.code, self.name, self.name_zh
            );
        }
        if self.code.parse::<u16>().ok() == Some(self.address) {
            // Parameters numbered in decimal (FC 303).
            return format!("parameter {} ({} / {})", self.code, self.name, self.name_zh);
        }
        let address = format!("{:04X}", self.address);
        if self.code.eq_ignore_ascii_case(&address) {
            format!("register {address} ({} / {})", self.name, self.name_zh)
        } else {
            format!(
                "register {address} {} ({} / {})",
                self.code, self.name, self.name_zh
            )
        }
    }

    /// The unit's symbol.
    pub fn unit_symbol(&self) -> &'static str {
        self.unit.symbol()
    }

    /// Decimal places implied by the scale (0.01 -> 2).
    pub fn decimals(&self) -> u8 {
        crate::units::decimals_of(self.scale)
    }

    /// Explains run-time bounds named after other registers, for error messages.
    pub fn bound_note(&self) -> String {
        match (self.min_bound, self.max_bound) {
            (None, None) => String::new(),
            (Some(low), None) => format!(" (at run time the lower bound is {low})"),
            (None, Some(high)) => format!(" (at run time the upper bound is {high})"),
            (Some(low), Some(high)) => format!(" (at run time the bounds are {low} and {high})"),
        }
    }
}

/// A value that can be stored in a register: a quantity, a code-table enum, a bit-field
/// word or a raw number.
pub trait RegisterValue: Sized {
    /// Converts to the raw value (a word or a double word), refusing values outside the
    /// register's range.
    fn to_raw(&self, info: &'static RegisterInfo) -> Result<u32, ValueError>;
    /// Converts a raw value read from the drive.
    fn from_raw(raw: u32, info: &'static RegisterInfo) -> Result<Self, ValueError>;
}

/// A register of a described drive. Generated code implements it for one unit struct per register.
pub trait Register {
    /// The register's metadata.
    const INFO: &'static RegisterInfo;
    /// The typed value read from and written to it.
    type Value: RegisterValue;
}

/// A register that may be written (implemented only for writable registers, so writing a
/// read-only register does not compile).
pub trait Writable: Register {}

/// A register whose value may be written persistently (EEPROM); not implemented for
/// RAM-only registers.
pub trait Persistable: Writable {}
