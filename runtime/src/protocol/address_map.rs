//! How a command maps register numbers to the numbers on the wire (`address_map:`).

/// How a command turns a register number into the number on the wire:
/// `wire = number * multiply + offset` (Modbus holding register = parameter x 10 - 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct AddressMap {
    /// Factor.
    pub multiply: u16,
    /// Offset added after multiplying.
    pub offset: i32,
}

impl AddressMap {
    /// The identity map.
    pub const IDENTITY: AddressMap = AddressMap {
        multiply: 1,
        offset: 0,
    };

    /// The wire number of `number`, if it fits 16 bits.
    pub fn to_wire(self, number: u16) -> Option<u16> {
        u16::try_from(i64::from(number) * i64::from(self.multiply) + i64::from(self.offset)).ok()
    }

    /// The register number of a wire number, if it maps back exactly.
    pub fn from_wire(self, wire: u16) -> Option<u16> {
        let shifted = i64::from(wire) - i64::from(self.offset);
        let multiply = i64::from(self.multiply.max(1));
        (shifted % multiply == 0)
            .then(|| u16::try_from(shifted / multiply).ok())
            .flatten()
    }
}
