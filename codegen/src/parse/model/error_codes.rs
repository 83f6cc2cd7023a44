//! The codes error replies carry: a drive's table (`error_codes:`), a protocol's own, and
//! how a manual prints them.

use super::defaults::one;
use schemars::JsonSchema;
use serde::Deserialize;

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ErrorCodesModel {
    /// The manual section listing the codes.
    pub source: String,
    /// The drive's protocols (their ids under `protocols`) whose error replies carry these
    /// codes; left out: every one of them. A protocol not listed names its error codes
    /// from its protocol file's own `error_codes`.
    pub protocols: Option<Vec<String>>,
    /// How the manual prints the codes (`{ prefix: H, digits: 2 }`: H0C); left out:
    /// two hex digits and `h` (0Ch).
    pub notation: Option<CodeNotationModel>,
    /// The codes an error reply may carry.
    pub codes: Vec<ErrorCodeModel>,
    /// Conditions in which the drive does not answer at all (documentation only).
    #[serde(default)]
    pub silent: Vec<String>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ErrorCodeModel {
    /// The code carried by the error reply.
    pub code: u32,
    /// Lower snake case name for the code in Rust.
    pub id: String,
    /// Short English name.
    pub name: String,
    /// The name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// What the code means and what to do about it.
    pub meaning: String,
}

/// A protocol's own error codes.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProtocolErrorCodesModel {
    /// Where the codes are defined (a specification, or the manuals that print them).
    pub source: String,
    /// How the manual or specification prints the codes (`{ digits: 2 }`: 01); left out:
    /// two hex digits and `h` (01h).
    pub notation: Option<CodeNotationModel>,
    /// The codes an error reply may carry.
    pub codes: Vec<ErrorCodeModel>,
}

/// How a manual prints a table's codes: in hex (`H0C`, `000Ch`, `01`) or decimal (`17`),
/// at least `digits` digits, between a prefix and a suffix.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CodeNotationModel {
    /// `hex` (the default) or `decimal`.
    #[serde(default)]
    pub base: CodeBase,
    /// The fewest digits printed (leading zeros); default 1.
    #[serde(default = "one")]
    pub digits: u8,
    /// Text before the digits (`H` for H0C).
    #[serde(default)]
    pub prefix: String,
    /// Text after the digits (`h` for 000Ch).
    #[serde(default)]
    pub suffix: String,
}

impl CodeNotationModel {
    /// `code` as the manual prints it.
    pub fn print(&self, code: u32) -> String {
        let width = usize::from(self.digits);
        let digits = match self.base {
            CodeBase::Hex => format!("{code:0width$X}"),
            CodeBase::Decimal => format!("{code:0width$}"),
        };
        format!("{}{digits}{}", self.prefix, self.suffix)
    }
}

/// The base a manual prints codes in.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum CodeBase {
    /// Hexadecimal digits, upper case.
    #[default]
    Hex,
    /// Decimal digits.
    Decimal,
}
