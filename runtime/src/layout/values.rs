//! The decoded values of a frame's parts, and of its roles, held without allocation.

use super::role::Role;

/// The most parts one layout may have; decoded values live in a fixed array of this size.
pub const MAX_PARTS: usize = 16;

/// The value of one part of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FieldValue {
    /// Whether the part is in the frame (always true for required parts after decoding).
    pub present: bool,
    /// The value: a field's number, a word's bits, a checksum's or length's received
    /// value, the offset of a bytes field in the frame; 0 for literals.
    pub value: u32,
    /// Digits (digit formats) or bytes (variable binary formats) on the wire; 0 means
    /// the layout's width.
    pub width: u8,
}

/// Values of every part of one frame, indexed like the layout's parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameValues {
    /// One slot per layout part.
    pub parts: [FieldValue; MAX_PARTS],
    /// Size in bytes of the request's data, for length parts that count it (Modbus
    /// quantity) and for variable-width data fields. Above 4, the data field carries a
    /// block of registers: its slot holds the block's offset in the frame and its width,
    /// as a bytes field does ([`FrameValues::bytes`] gives the bytes).
    pub data_size: u8,
}

/// The values of every role of a frame, gathered in one pass over the layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Roles {
    /// Station address.
    pub address: Option<u32>,
    /// Command code.
    pub command: Option<u32>,
    /// Register (wire number).
    pub register: Option<u32>,
    /// Array index.
    pub index: Option<u32>,
    /// Data.
    pub data: Option<u32>,
    /// Error code.
    pub error_code: Option<u32>,
    /// First process word.
    pub process_1: Option<u32>,
    /// Second process word.
    pub process_2: Option<u32>,
    /// Decimal places of the data.
    pub decimals: Option<u32>,
}

impl Roles {
    /// The value given for `role`, for the roles this type holds.
    #[inline]
    pub fn value(&self, role: Role) -> Option<u32> {
        match role {
            Role::Address => self.address,
            Role::Command => self.command,
            Role::Register => self.register,
            Role::Index => self.index,
            Role::Data => self.data,
            Role::ErrorCode => self.error_code,
            Role::Process1 => self.process_1,
            Role::Process2 => self.process_2,
            Role::Decimals => self.decimals,
            Role::Text | Role::Words | Role::ReadCount | Role::WriteStatus | Role::ReplyWait => {
                None
            }
        }
    }

    #[inline]
    pub(crate) fn slot(&mut self, role: Role) -> Option<&mut Option<u32>> {
        match role {
            Role::Address => Some(&mut self.address),
            Role::Command => Some(&mut self.command),
            Role::Register => Some(&mut self.register),
            Role::Index => Some(&mut self.index),
            Role::Data => Some(&mut self.data),
            Role::ErrorCode => Some(&mut self.error_code),
            Role::Process1 => Some(&mut self.process_1),
            Role::Process2 => Some(&mut self.process_2),
            Role::Decimals => Some(&mut self.decimals),
            Role::Text | Role::Words | Role::ReadCount | Role::WriteStatus | Role::ReplyWait => {
                None
            }
        }
    }
}
