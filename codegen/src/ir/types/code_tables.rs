//! Code tables: registers whose value is a code, and what each code means or sets.

use serde::Serialize;

/// A code table.
#[derive(Debug, Clone, Serialize)]
pub struct CodeTableIr {
    /// Identifier.
    pub id: String,
    /// Rust type name.
    pub type_name: String,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// Manual section.
    pub source: String,
    /// Whether the manual lists every value (only then is it a Rust enum).
    pub exhaustive: bool,
    /// Remarks.
    pub note: String,
    /// The values.
    pub values: Vec<CodeValueIr>,
}

/// One value of a code table.
#[derive(Debug, Clone, Serialize)]
pub struct CodeValueIr {
    /// The value.
    pub value: u16,
    /// Identifier.
    pub id: String,
    /// Rust variant name.
    pub variant: String,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// What it sets on the line: the baud rate and the parts of the character format.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub line: Option<LineSettingIr>,
    /// The id of the protocol it chooses.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub protocol: Option<String>,
}

/// What a code value sets on the line; each part `None` where it sets nothing of it.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
pub struct LineSettingIr {
    /// The baud rate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub baud: Option<u32>,
    /// Data bits per character.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub data_bits: Option<u8>,
    /// Parity.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parity: Option<vfd_runtime::serial::Parity>,
    /// Stop bits.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stop_bits: Option<u8>,
}

impl LineSettingIr {
    /// The whole character format (data bits, parity, stop bits), when it sets all of it.
    pub fn format(&self) -> Option<(u8, vfd_runtime::serial::Parity, u8)> {
        Some((self.data_bits?, self.parity?, self.stop_bits?))
    }
}
