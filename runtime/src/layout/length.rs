//! Length parts: a [`LengthSpec`] and what it [`Counts`].

use std::borrow::Cow;

use super::borrowed::Text;
use super::format::Format;

/// A length computed on encode and checked on decode: the byte count of a run of parts
/// (FC LGE, Modbus byte count), or the size of the request's data (Modbus quantity).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct LengthSpec {
    /// Name used in error messages, e.g. `lge`.
    pub name: Text,
    /// `U8` or `U16Be`.
    pub format: Format,
    /// What is counted.
    pub counts: Counts,
    /// The value is the byte count times `times` divided by `per` (16 coils per 2 bytes:
    /// times 8; registers: per 2).
    pub times: u8,
    /// See `times`.
    pub per: u8,
}

/// What a [`LengthSpec`] counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Counts {
    /// The bytes of parts `from..=through` (indexes into the layout).
    Parts {
        /// First counted part.
        from: u8,
        /// Last counted part.
        through: u8,
    },
    /// The size of the request's data (its data type), which the frame itself does not carry.
    DataSize,
}

impl LengthSpec {
    /// A length in `format` counting `counts` one for one.
    pub const fn new(name: &'static str, format: Format, counts: Counts) -> LengthSpec {
        LengthSpec {
            name: Cow::Borrowed(name),
            format,
            counts,
            times: 1,
            per: 1,
        }
    }

    /// The count is multiplied by `times` and divided by `per`.
    pub const fn with_ratio(mut self, times: u8, per: u8) -> LengthSpec {
        self.times = times;
        self.per = per;
        self
    }
}
