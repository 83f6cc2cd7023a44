//! Value fields: a [`FieldSpec`], its presence, its size and its broadcast addresses.

use std::borrow::Cow;

use super::borrowed::{List, Text};
use super::format::Format;
use super::role::Role;

/// How a decoder decides whether an optional field is present.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Presence {
    /// Present when the next byte can start a value of the field's format
    /// (a digit for decimal fields).
    IfFormatMatches,
    /// Present when the next byte is at most this value (binary station addresses
    /// 0x00-0x3F never collide with command letters).
    IfByteAtMost(u8),
}

/// Where a variable-size field's size comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum SizedBy {
    /// The format: fixed bytes, or as many digits as are there (`min_width..=width`).
    Format,
    /// Whatever the frame's length part leaves between this field and the fixed-size
    /// parts after it (FC text blocks).
    Rest,
    /// A length part that covers exactly this field (Modbus byte count).
    Length,
}

impl SizedBy {
    /// Every rule.
    pub const ALL: [SizedBy; 3] = [SizedBy::Format, SizedBy::Rest, SizedBy::Length];

    /// Name of the rule: `rest` and `length` as written under `size:` in protocol
    /// description files; `format` is what leaving `size` out means.
    pub const fn as_str(self) -> &'static str {
        match self {
            SizedBy::Format => "format",
            SizedBy::Rest => "rest",
            SizedBy::Length => "length",
        }
    }
}

/// A value field.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FieldSpec {
    /// Field name, e.g. `register`.
    pub name: Text,
    /// What the field means.
    pub role: Role,
    /// Wire format.
    pub format: Format,
    /// Digit count on encode, and the most digits accepted on decode (digit formats only).
    pub width: u8,
    /// The fewest digits accepted on decode (digit formats only; equals `width` when fixed).
    pub min_width: u8,
    /// `Some` when the field may be left out.
    pub optional: Option<Presence>,
    /// Values the decoder accepts; empty means any.
    pub allowed: List<u32>,
    /// Compare `allowed` character values without regard to ASCII case.
    pub fold_case: bool,
    /// Where the field's size comes from.
    pub sized_by: SizedBy,
    /// How a station address field addresses several stations at once (broadcast and
    /// group addressing); `None` for other fields and for protocols without broadcasts.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub broadcast: Option<BroadcastAddress>,
}

/// The broadcast encodings of a station address field (protocol file: `broadcast:` on the
/// address part): what stands in the field's place to address every station, and the
/// character that leaves one digit open to address a group.
///
/// In [`crate::codec::FrameValues`] a station number with open digits (a group, or every
/// station written as `**`) is held as [`BroadcastAddress::OPEN`] | the open digits' mask
/// (bit 0: the last digit) << [`BroadcastAddress::MASK_SHIFT`] | the value of the closed
/// digits; [`crate::broadcast`] converts it.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BroadcastAddress {
    /// Bytes written instead of the station number to address every station (`"**"`);
    /// empty when a value does it.
    pub all_bytes: List<u8>,
    /// The station value that addresses every station (FFh; Modbus 0), when a value does.
    pub all_value: Option<u32>,
    /// A character standing for any one digit of a digit-format station number (`*`):
    /// group addressing (`*9`: every station whose last digit is 9).
    pub wildcard: Option<u8>,
}

impl BroadcastAddress {
    /// Flag of a field value holding open digits.
    pub const OPEN: u32 = 1 << 31;
    /// Position of the open digits' mask in a field value.
    pub const MASK_SHIFT: u32 = 24;

    /// Every station is addressed by `bytes` in the field's place.
    pub const fn bytes(bytes: &'static [u8]) -> BroadcastAddress {
        BroadcastAddress {
            all_bytes: Cow::Borrowed(bytes),
            all_value: None,
            wildcard: None,
        }
    }

    /// Every station is addressed by the field value `value`.
    pub const fn value(value: u32) -> BroadcastAddress {
        BroadcastAddress {
            all_bytes: Cow::Borrowed(&[]),
            all_value: Some(value),
            wildcard: None,
        }
    }

    /// `character` leaves one digit open (group addressing).
    pub const fn with_wildcard(mut self, character: u8) -> BroadcastAddress {
        self.wildcard = Some(character);
        self
    }

    /// Whether a field value holds open digits.
    #[inline]
    pub const fn is_open(value: u32) -> bool {
        value & Self::OPEN != 0
    }

    /// Whether `byte` can begin a broadcast station field.
    #[inline]
    pub fn starts_with(&self, byte: u8) -> bool {
        self.all_bytes.first() == Some(&byte)
            || self.wildcard == Some(byte)
            || self.all_value == Some(u32::from(byte))
    }
}

impl FieldSpec {
    /// A field of exactly `width` digits or bytes, always present, any value, sized by its
    /// format.
    pub const fn new(name: &'static str, role: Role, format: Format, width: u8) -> FieldSpec {
        FieldSpec {
            name: Cow::Borrowed(name),
            role,
            format,
            width,
            min_width: width,
            optional: None,
            allowed: Cow::Borrowed(&[]),
            fold_case: false,
            sized_by: SizedBy::Format,
            broadcast: None,
        }
    }

    /// A station address that may also address every station, or a group.
    pub const fn with_broadcast(mut self, broadcast: BroadcastAddress) -> FieldSpec {
        // A const fn cannot drop the old value; it is `None` when built by `new`.
        core::mem::forget(self.broadcast.replace(broadcast));
        self
    }

    /// Accepts as few as `min_width` digits or bytes on decode.
    pub const fn with_min_width(mut self, min_width: u8) -> FieldSpec {
        self.min_width = min_width;
        self
    }

    /// Present only when `presence` says so.
    pub const fn with_optional(mut self, presence: Presence) -> FieldSpec {
        self.optional = Some(presence);
        self
    }

    /// Only these values are accepted.
    pub const fn with_allowed(mut self, allowed: &'static [u32]) -> FieldSpec {
        // A const fn cannot drop the old value, so it is forgotten: nothing to free when it
        // is borrowed, as in generated code (an owned one would leak).
        core::mem::forget(core::mem::replace(
            &mut self.allowed,
            Cow::Borrowed(allowed),
        ));
        self
    }

    /// A lower-case letter is accepted and means "tripped".
    pub const fn with_fold_case(mut self) -> FieldSpec {
        self.fold_case = true;
        self
    }

    /// Sized other than by its format.
    pub const fn with_sized_by(mut self, sized_by: SizedBy) -> FieldSpec {
        self.sized_by = sized_by;
        self
    }
}
