//! Broadcast and group addressing: which stations a request addresses when it does not
//! name one, how that is held in a station field's value, and the drive's rule for which
//! commands may be broadcast and which station answers.
//!
//! The wire encodings come from the protocol file (`broadcast:` on the address part, see
//! [`BroadcastAddress`]); the rule from the drive's protocol entry ([`BroadcastRule`]).
//! Nothing here names a protocol: `**`, FFh and Modbus 0 are all data.

use crate::layout::{BroadcastAddress, FieldSpec, Format, List};
use std::fmt;

/// The stations a broadcast request addresses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Broadcast {
    /// Every station on the line.
    All,
    /// Every station whose number has the group's digits where the group gives them.
    Group(StationGroup),
}

/// A station number with some digits left open, as written in a group broadcast
/// (`*9`: every station whose last digit is 9; `1*`: every station whose first digit is 1).
/// Digits are in the radix of the station field (decimal for a two-digit ASCII field).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct StationGroup {
    /// The digits, most significant first (an open digit holds 0).
    digits: [u8; 7],
    /// How many digits.
    len: u8,
    /// Bit `i` set: the `i`-th digit from the right is open.
    open: u8,
}

/// Why a text is not a station group.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("`{text}` is not a station group: write the station's digits with `*` for each open digit (`*9`, `1*`, `**`)")]
pub struct GroupParseError {
    /// The text given.
    pub text: String,
}

impl StationGroup {
    /// Parses a group written with `*` for each open digit (`*9`, `1*`; `**` opens every
    /// digit). Digits may be hexadecimal; whether they fit the station field is checked
    /// when the group is encoded.
    pub fn parse(text: &str) -> Result<StationGroup, GroupParseError> {
        let error = || GroupParseError {
            text: text.to_owned(),
        };
        let bytes = text.as_bytes();
        if bytes.is_empty() || bytes.len() > 7 || !bytes.contains(&b'*') {
            return Err(error());
        }
        let mut group = StationGroup {
            digits: [0; 7],
            len: bytes.len() as u8,
            open: 0,
        };
        for (offset, byte) in bytes.iter().enumerate() {
            if *byte == b'*' {
                group.open |= 1 << (bytes.len() - 1 - offset);
            } else {
                group.digits[offset] = (*byte as char).to_digit(16).ok_or_else(error)? as u8;
            }
        }
        Ok(group)
    }

    /// Whether every digit is open (the group is every station).
    pub fn is_everyone(&self) -> bool {
        u32::from(self.open) == (1u32 << self.len) - 1
    }

    /// The number of digits.
    pub fn len(&self) -> usize {
        usize::from(self.len)
    }

    /// Whether the group has no digits (never true for a parsed group).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Whether `station` belongs to the group, its number written in `radix`.
    pub fn contains(&self, station: u8, radix: u32) -> bool {
        let mut rest = u32::from(station);
        for position in 0..self.len {
            let digit = rest % radix;
            rest /= radix;
            let index = usize::from(self.len - 1 - position);
            if self.open & (1 << position) == 0 && u32::from(self.digits[index]) != digit {
                return false;
            }
        }
        rest == 0
    }

    /// The lowest station of the group: its open digits 0 (`*9` -> 9, `1*` -> 10), in `radix`.
    pub fn lowest(&self, radix: u32) -> Option<u8> {
        let value = self.digits[..self.len()]
            .iter()
            .fold(0u32, |acc, digit| acc * radix + u32::from(*digit));
        u8::try_from(value).ok()
    }

    /// The value of a station field holding the group (see [`BroadcastAddress`]).
    fn field_value(&self, radix: u32) -> u32 {
        let closed = self.lowest(radix).map_or(0, u32::from);
        BroadcastAddress::OPEN | (u32::from(self.open) << BroadcastAddress::MASK_SHIFT) | closed
    }

    /// The group a station field's value holds, for a field of `width` digits in `radix`.
    fn from_field_value(value: u32, width: u8, radix: u32) -> StationGroup {
        let width = width.clamp(1, 7);
        let open = ((value >> BroadcastAddress::MASK_SHIFT) & 0x7F) as u8;
        let mut rest = value & ((1 << BroadcastAddress::MASK_SHIFT) - 1);
        let mut digits = [0u8; 7];
        for slot in digits[..usize::from(width)].iter_mut().rev() {
            *slot = (rest % radix) as u8;
            rest /= radix;
        }
        StationGroup {
            digits,
            len: width,
            open,
        }
    }
}

impl fmt::Display for StationGroup {
    /// As written: the digits, `*` where one is open.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for index in 0..self.len {
            if self.open & (1 << (self.len - 1 - index)) != 0 {
                f.write_str("*")?;
            } else {
                write!(f, "{:X}", self.digits[usize::from(index)])?;
            }
        }
        Ok(())
    }
}

impl fmt::Display for Broadcast {
    /// `all`, or the group as written (`*9`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Broadcast::All => f.write_str("all"),
            Broadcast::Group(group) => group.fmt(f),
        }
    }
}

impl std::str::FromStr for Broadcast {
    type Err = GroupParseError;

    /// `all`, or a group written with `*` for open digits (`**` is every station too).
    fn from_str(text: &str) -> Result<Broadcast, GroupParseError> {
        if text.eq_ignore_ascii_case("all") {
            return Ok(Broadcast::All);
        }
        let group = StationGroup::parse(text)?;
        Ok(if group.is_everyone() {
            Broadcast::All
        } else {
            Broadcast::Group(group)
        })
    }
}

/// The radix a station field's digits are written in (decimal and hex digit fields; binary
/// fields count in 10 for groups, which they cannot carry anyway).
pub fn field_radix(field: &FieldSpec) -> u32 {
    match field.format {
        Format::Hex => 16,
        _ => 10,
    }
}

/// Whether the field can carry `broadcast`: every station needs broadcast bytes, a value or
/// a wildcard; a group needs a wildcard and as many digits as the field has.
pub fn field_carries(field: &FieldSpec, broadcast: &Broadcast) -> bool {
    let Some(encoding) = &field.broadcast else {
        return false;
    };
    match broadcast {
        Broadcast::All => {
            !encoding.all_bytes.is_empty()
                || encoding.all_value.is_some()
                || encoding.wildcard.is_some()
        }
        Broadcast::Group(group) => {
            encoding.wildcard.is_some()
                && field.format.is_digits()
                && group.len() == usize::from(field.width)
        }
    }
}

/// The station field value that carries `broadcast` (check [`field_carries`] first).
pub fn field_value(field: &FieldSpec, broadcast: &Broadcast) -> u32 {
    let radix = field_radix(field);
    match (broadcast, &field.broadcast) {
        (Broadcast::All, Some(encoding)) if encoding.all_bytes.is_empty() => {
            match encoding.all_value {
                Some(value) => value,
                None => {
                    let mask = (1u32 << field.width.clamp(1, 7)) - 1;
                    BroadcastAddress::OPEN | (mask << BroadcastAddress::MASK_SHIFT)
                }
            }
        }
        (Broadcast::All, _) => {
            let mask = (1u32 << field.width.clamp(1, 7)) - 1;
            BroadcastAddress::OPEN | (mask << BroadcastAddress::MASK_SHIFT)
        }
        (Broadcast::Group(group), _) => group.field_value(radix),
    }
}

/// The broadcast a decoded station field value stands for, if it is one.
pub fn from_field_value(field: &FieldSpec, value: u32) -> Option<Broadcast> {
    let encoding = field.broadcast.as_ref()?;
    if BroadcastAddress::is_open(value) {
        let group = StationGroup::from_field_value(value, field.width, field_radix(field));
        return Some(if group.is_everyone() {
            Broadcast::All
        } else {
            Broadcast::Group(group)
        });
    }
    (encoding.all_value == Some(value)).then_some(Broadcast::All)
}

/// Which station answers a broadcast, by the drive's description.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum BroadcastAnswer {
    /// No station answers (Modbus).
    None,
    /// The lowest station the broadcast addresses answers, if the installation has it:
    /// the lowest of the protocol's station range for every station (00), the group's
    /// number with its open digits 0 for a group (`*9`: 09). Every other station stays
    /// silent.
    LowestMatching,
}

impl BroadcastAnswer {
    /// Every rule.
    pub const ALL: [BroadcastAnswer; 2] = [BroadcastAnswer::None, BroadcastAnswer::LowestMatching];

    /// The rule's name as description files write it.
    pub const fn as_str(self) -> &'static str {
        match self {
            BroadcastAnswer::None => "none",
            BroadcastAnswer::LowestMatching => "lowest_matching",
        }
    }
}

/// A drive's broadcast rule for one protocol (drive file: `protocols[].broadcast`).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BroadcastRule {
    /// The command codes the drive carries out when broadcast (writes only).
    pub commands: List<u32>,
    /// Which station answers.
    pub answered_by: BroadcastAnswer,
}

impl BroadcastRule {
    /// Which station answers `broadcast` by this rule, in a protocol whose station numbers
    /// run from `min`, written in `radix`; `None` when none does.
    pub fn responder(&self, broadcast: &Broadcast, min: u8, radix: u32) -> Option<u8> {
        match (self.answered_by, broadcast) {
            (BroadcastAnswer::None, _) => None,
            (BroadcastAnswer::LowestMatching, Broadcast::All) => Some(min),
            (BroadcastAnswer::LowestMatching, Broadcast::Group(group)) => {
                group.lowest(radix).map(|lowest| lowest.max(min))
            }
        }
    }
}

/// Whether `station` is among the stations `broadcast` addresses, its number written in
/// `radix`.
pub fn addresses(broadcast: &Broadcast, station: u8, radix: u32) -> bool {
    match broadcast {
        Broadcast::All => true,
        Broadcast::Group(group) => group.contains(station, radix),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_parse_match_and_show_as_written() {
        let units = StationGroup::parse("*9").unwrap();
        assert!(units.contains(9, 10) && units.contains(19, 10) && units.contains(99, 10));
        assert!(!units.contains(8, 10) && !units.contains(90, 10));
        assert_eq!(units.lowest(10), Some(9));
        assert_eq!(units.to_string(), "*9");
        let tens = StationGroup::parse("1*").unwrap();
        assert!(tens.contains(10, 10) && tens.contains(19, 10) && !tens.contains(1, 10));
        assert_eq!(tens.lowest(10), Some(10));
        assert_eq!("**".parse::<Broadcast>(), Ok(Broadcast::All));
        assert_eq!("all".parse::<Broadcast>(), Ok(Broadcast::All));
        assert!("19".parse::<Broadcast>().is_err());
        assert!("*x".parse::<Broadcast>().is_err());
    }

    /// `(` station `R` `)`: a two-digit station with `**` and the wildcard `*`.
    fn layout() -> crate::layout::FrameLayout {
        use crate::layout::{FrameLayout, Part, Presence, Role};
        FrameLayout {
            name: "test".into(),
            encoding: crate::layout::Encoding::Binary,
            plan: None,
            parts: std::borrow::Cow::Owned(vec![
                Part::literal("start", b"("),
                Part::Field(
                    FieldSpec::new("address", Role::Address, Format::Decimal, 2)
                        .with_optional(Presence::IfFormatMatches)
                        .with_broadcast(BroadcastAddress::bytes(b"**").with_wildcard(b'*')),
                ),
                Part::Field(FieldSpec::new("command", Role::Command, Format::Char, 1)),
                Part::literal("end", b")"),
            ]),
        }
    }

    #[test]
    fn open_digits_encode_and_decode_through_the_codec() {
        use crate::codec::{decode, encode, DecodeStatus, FrameValues};
        use crate::layout::Role;
        let layout = layout();
        let field = layout.field(Role::Address).unwrap().clone();
        let mut out = [0u8; 16];
        for (broadcast, wire) in [
            (Broadcast::All, &b"(**R)"[..]),
            ("*9".parse().unwrap(), b"(*9R)"),
            ("1*".parse().unwrap(), b"(1*R)"),
        ] {
            let mut values = FrameValues::default();
            values.set(&layout, Role::Address, field_value(&field, &broadcast));
            values.set(&layout, Role::Command, u32::from(b'R'));
            let len = encode(&layout, &values, &mut out).unwrap();
            assert_eq!(&out[..len], wire);
            let DecodeStatus::Complete { values, .. } = decode(&layout, wire).unwrap() else {
                panic!("{wire:?} is a whole frame");
            };
            let value = values.get(&layout, Role::Address).unwrap();
            assert_eq!(from_field_value(&field, value), Some(broadcast));
        }
        // An ordinary station is no broadcast; a half-written one waits; a stray byte fails.
        let DecodeStatus::Complete { values, .. } = decode(&layout, b"(19R)").unwrap() else {
            panic!("a whole frame");
        };
        assert_eq!(values.get(&layout, Role::Address), Some(19));
        assert_eq!(from_field_value(&field, 19), None);
        assert_eq!(decode(&layout, b"(*").unwrap(), DecodeStatus::Incomplete);
        assert!(decode(&layout, b"(*xR)").is_err());
    }

    #[test]
    fn the_lowest_matching_station_answers() {
        let rule = BroadcastRule {
            commands: std::borrow::Cow::Borrowed(&[]),
            answered_by: BroadcastAnswer::LowestMatching,
        };
        let group = "*9".parse::<Broadcast>().unwrap();
        assert_eq!(rule.responder(&group, 0, 10), Some(9));
        assert_eq!(rule.responder(&Broadcast::All, 0, 10), Some(0));
        let silent = BroadcastRule {
            answered_by: BroadcastAnswer::None,
            ..rule
        };
        assert_eq!(silent.responder(&Broadcast::All, 1, 10), None);
    }
}
