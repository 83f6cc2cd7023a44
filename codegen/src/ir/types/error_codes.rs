//! The codes error replies carry, as a table and one by one.

use serde::Serialize;

/// The manual's error codes.
#[derive(Debug, Clone, Serialize)]
pub struct ErrorCodesIr {
    /// Manual section.
    pub source: String,
    /// Ids of the protocols whose error replies carry these codes.
    pub protocols: Vec<String>,
    /// The codes.
    pub codes: Vec<ErrorCodeIr>,
    /// Conditions under which the drive stays silent.
    pub silent: Vec<String>,
}

/// One error code.
#[derive(Debug, Clone, Serialize)]
pub struct ErrorCodeIr {
    /// The code.
    pub code: u16,
    /// Identifier.
    pub id: String,
    /// Rust variant name.
    pub variant: String,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// The manual's explanation.
    pub meaning: String,
    /// The code as the manual prints it (`H0C`), from its table's `notation`; empty when
    /// the table states none.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub printed: String,
}
