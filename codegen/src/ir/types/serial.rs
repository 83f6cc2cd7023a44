//! The serial line: settings, timing, line-level facts, the character formats a setting
//! offers each protocol, station numbers and serial ports.

use crate::parse::model::{BitOrder, Duplex, Synchronisation, TimingField, Topology};
use serde::Serialize;
use vfd_runtime::serial::Parity;

/// The drive's serial ports, resolved to register codes.
#[derive(Debug, Clone, Serialize)]
pub struct PortsIr {
    /// Manual sections.
    pub source: String,
    /// Remarks.
    pub note: String,
    /// The ports, in file order.
    pub ports: Vec<PortIr>,
    /// Codes of the registers both ports share.
    pub shared: Vec<String>,
    /// Registers that exist once per port: each row holds one code per port, in port order.
    pub registers: Vec<Vec<String>>,
}

/// One serial port.
#[derive(Debug, Clone, Serialize)]
pub struct PortIr {
    /// Identifier (`two_wire`).
    pub id: String,
    /// Rust name of its constant (`TWO_WIRE`).
    pub const_name: String,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// The registers setting it: (what they set, register code), sorted by the first.
    pub settings: Vec<(String, String)>,
}

/// Line-level facts of the serial link; `None` where the description does not say.
#[derive(Debug, Clone, Default, Serialize)]
pub struct LineIr {
    /// Manual section.
    pub source: String,
    /// Half or full duplex.
    pub duplex: Option<Duplex>,
    /// Who controls the line.
    pub topology: Option<Topology>,
    /// Character synchronisation.
    pub synchronisation: Option<Synchronisation>,
    /// Bit order within a character.
    pub bit_order: Option<BitOrder>,
}

/// Serial line facts.
#[derive(Debug, Clone, Serialize)]
pub struct SerialIr {
    /// Manual section.
    pub source: String,
    /// Remarks.
    pub note: String,
    /// Supported baud rates.
    pub baud_rates: Vec<u32>,
    /// Supported parities.
    pub parities: Vec<Parity>,
    /// The data bits the drive can use (one when fixed; `[7, 8]` when a setting chooses).
    pub data_bits: Vec<u8>,
    /// The character formats a setting offers each protocol (from the code tables whose
    /// values set the line and choose a protocol), the factory one marked; other
    /// protocols speak the defaults below.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub protocol_lines: Vec<ProtocolLineIr>,
    /// Stop bits the drive sends.
    pub stop_bits_sent: u8,
    /// Stop bits the drive needs.
    pub stop_bits_received: u8,
    /// The stop bits the drive can be set to, when they are its choice (`[1, 2]`); empty:
    /// fixed as `stop_bits_sent` and `stop_bits_received`.
    pub stop_bits: Vec<u8>,
    /// Factory baud rate.
    pub default_baud: u32,
    /// Factory parity.
    pub default_parity: Parity,
    /// Factory data bits.
    pub default_data_bits: u8,
    /// Factory stop bits.
    pub default_stop_bits: u8,
    /// Silence after power-on, in ms.
    pub startup_delay_ms: u64,
    /// A frame not complete within this many ms is dropped.
    pub frame_abandon_ms: u64,
    /// Time the drive may take to start answering, in ms.
    pub processing_allowance_ms: u64,
    /// Timings that are placeholders or assumptions, not the manual's.
    pub assumed_timing: Vec<TimingField>,
    /// Line-level facts, when the description gives any.
    pub line: Option<LineIr>,
}

/// A character format a setting offers a protocol.
#[derive(Debug, Clone, Serialize)]
pub struct ProtocolLineIr {
    /// The protocol's id.
    pub protocol: String,
    /// Data bits.
    pub data_bits: u8,
    /// Parity.
    pub parity: Parity,
    /// Stop bits.
    pub stop_bits: u8,
    /// The code of the register whose value chooses it, and that value.
    pub selector: String,
    /// See `selector`.
    pub value: u16,
    /// The selector's factory value chooses it.
    pub factory: bool,
}

/// Station numbers.
#[derive(Debug, Clone, Serialize)]
pub struct AddressingIr {
    /// Lowest station number.
    pub min: u8,
    /// Highest station number.
    pub max: u8,
    /// Remarks.
    pub note: String,
    /// Id of the register holding the station number.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub register: Option<String>,
}
