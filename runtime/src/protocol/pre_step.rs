//! Steps a request needs done first, in another exchange ([`PreStep`]).

use crate::kinds::{DataType, Space};

/// Something a request needs done first, in another exchange.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum PreStep {
    /// Before an indexed access, write the index to this wire register (FC Modbus: 0008h).
    Index {
        /// Wire register that selects the index.
        register: u16,
    },
    /// Before a parameter write, select RAM or RAM + EEPROM by writing `ram` or
    /// `persistent` to `register` of `space` (FC Modbus: coil 65, 0000h or FF00h). Coil
    /// writes (process data) skip it.
    Persistence {
        /// Address space of the selector.
        space: Space,
        /// Selector register (number before mapping).
        register: u16,
        /// Data type of the selector.
        data_type: DataType,
        /// Value selecting RAM only.
        ram: u32,
        /// Value selecting RAM and EEPROM.
        persistent: u32,
    },
}
