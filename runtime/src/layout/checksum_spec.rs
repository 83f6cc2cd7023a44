//! Checksum parts: a [`ChecksumSpec`] and the algorithms the runtime supplies.

use std::borrow::Cow;

use super::borrowed::{List, Text};
use super::format::Format;

/// Checksum algorithms the runtime supplies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum ChecksumAlgorithm {
    /// Low byte of the arithmetic sum of the covered bytes.
    Sum8,
    /// Exclusive-or of the covered bytes.
    Xor8,
    /// CRC-16 as Modbus RTU defines it (polynomial A001h reflected, initial FFFFh),
    /// sent low byte first.
    Crc16Modbus,
    /// Two's complement of the byte sum (Modbus ASCII LRC).
    Lrc8,
}

impl ChecksumAlgorithm {
    /// Every algorithm.
    pub const ALL: [ChecksumAlgorithm; 4] = [
        ChecksumAlgorithm::Sum8,
        ChecksumAlgorithm::Xor8,
        ChecksumAlgorithm::Crc16Modbus,
        ChecksumAlgorithm::Lrc8,
    ];

    /// Name as written in protocol description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            ChecksumAlgorithm::Sum8 => "sum8",
            ChecksumAlgorithm::Xor8 => "xor8",
            ChecksumAlgorithm::Crc16Modbus => "crc16_modbus",
            ChecksumAlgorithm::Lrc8 => "lrc8",
        }
    }
}

/// A checksum part.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ChecksumSpec {
    /// Name used in error messages, e.g. `sum`.
    pub name: Text,
    /// The algorithm.
    pub algorithm: ChecksumAlgorithm,
    /// `Hex` (two ASCII digits), `U8` (one byte) or `U16Le` (CRC-16).
    pub format: Format,
    /// Bytes that announce the checksum (`"&"`); they are covered by it.
    pub marker: List<u8>,
    /// Index of the first part covered; coverage runs up to the checksum value.
    pub covers_from: u8,
    /// Index of the last part covered, where coverage ends before the checksum (an ETX
    /// between the data and the sum that the sum leaves out); `None`: up to the value.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub covers_through: Option<u8>,
    /// Whether the checksum (with its marker) may be left out.
    pub optional: bool,
}

impl ChecksumSpec {
    /// A checksum covering the parts from `covers_from` to the byte before it, always
    /// present, with no marker.
    pub const fn new(
        name: &'static str,
        algorithm: ChecksumAlgorithm,
        format: Format,
        covers_from: u8,
    ) -> ChecksumSpec {
        ChecksumSpec {
            name: Cow::Borrowed(name),
            algorithm,
            format,
            marker: Cow::Borrowed(&[]),
            covers_from,
            covers_through: None,
            optional: false,
        }
    }

    /// Covers the parts up to and including the one at `index` only.
    pub const fn with_covers_through(mut self, index: u8) -> ChecksumSpec {
        self.covers_through = Some(index);
        self
    }

    /// Announced by these bytes.
    pub const fn with_marker(mut self, marker: &'static [u8]) -> ChecksumSpec {
        // A const fn cannot drop the old value, so it is forgotten: nothing to free when it
        // is borrowed, as in generated code (an owned one would leak).
        core::mem::forget(core::mem::replace(&mut self.marker, Cow::Borrowed(marker)));
        self
    }

    /// May be left out.
    pub const fn with_optional(mut self) -> ChecksumSpec {
        self.optional = true;
        self
    }
}
