//! Code tables (`codes:`): registers whose value is a code, and what each code means or
//! sets.

use super::defaults::yes;
use schemars::JsonSchema;
use serde::Deserialize;
use vfd_runtime::serial::Parity;

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CodeTableModel {
    /// Lower snake case: registers and bit fields name the table by it; it becomes a Rust enum.
    pub id: String,
    /// The table's name in English.
    pub name: String,
    /// The table's name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// The manual section the values come from.
    pub source: String,
    /// Whether the values listed are all there are (default true): a register using an exhaustive table and giving no `range` accepts writes from its lowest to its highest value only. False: registers using the table read as plain numbers.
    #[serde(default = "yes")]
    pub exhaustive: bool,
    /// Anything the manual says about the table that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// The codes and their meanings.
    pub values: Vec<CodeValueModel>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CodeValueModel {
    /// The raw value.
    pub value: u32,
    /// Lower snake case name of the value (a Rust enum variant).
    pub id: String,
    /// What the value means, in English.
    pub name: String,
    /// What the value means, as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// The register (code or id) this value selects, in a code table of selector registers
    /// (a block transfer's: F870 = 1 selects FA00).
    pub register: Option<String>,
    /// What this value sets on the line, in a code table of a line setting: the whole
    /// character format (DV1 07-07 = 0: `{ data_bits: 7, parity: none, stop_bits: 2 }`) or
    /// the part one register sets (a baud-rate register's `{ baud: 9600 }`, a parity
    /// register's `{ parity: even }`).
    pub line: Option<LineFormatModel>,
    /// The id of the drive's protocol this value chooses (DV1 07-07 = 0-2: `modbus_ascii`).
    pub protocol: Option<String>,
}

/// What a code value sets on the line (`codes[].values[].line`): any of the baud rate and
/// the character format's data bits, parity and stop bits, at least one.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LineFormatModel {
    /// The baud rate (one of `serial.baud_rates`).
    pub baud: Option<u32>,
    /// Data bits per character (7 or 8).
    pub data_bits: Option<u8>,
    /// `none`, `even` or `odd`.
    pub parity: Option<Parity>,
    /// Stop bits (1 or 2).
    pub stop_bits: Option<u8>,
}
