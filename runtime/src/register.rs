//! The traits that make register access typed. The metadata they carry lives in
//! [`crate::info`] and [`crate::kinds`] and is re-exported here.

use crate::error::ValueError;
pub use crate::info::RegisterInfo;
pub use crate::kinds::Access;

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
