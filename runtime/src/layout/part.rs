//! One part of a frame: a literal, a field, a word of bits, a length or a checksum.

use std::borrow::Cow;

use super::bits::WordSpec;
use super::borrowed::{List, Text};
use super::checksum_spec::ChecksumSpec;
use super::field::{FieldSpec, SizedBy};
use super::format::{checksum_size, Format};
use super::length::LengthSpec;
use super::role::Role;

// Sizes of fixed parts, used by the codec to size rest-of-frame fields.
impl Part {
    /// The part's size in bytes when it does not depend on the frame, `None` otherwise.
    pub fn fixed_size(&self) -> Option<usize> {
        match self {
            Part::Literal {
                bytes,
                optional: false,
                ..
            } => Some(bytes.len()),
            Part::Literal { .. } => None,
            Part::Field(field) if field.optional.is_some() || field.role == Role::Words => None,
            Part::Field(field) => match field.format {
                Format::Decimal | Format::Hex if field.min_width == field.width => {
                    Some(usize::from(field.width))
                }
                Format::UintBe | Format::UintLe | Format::Bytes
                    if field.sized_by == SizedBy::Format && field.min_width == field.width =>
                {
                    Some(usize::from(field.width))
                }
                format => format.fixed_len(),
            },
            Part::Checksum(spec) if !spec.optional => {
                Some(spec.marker.len() + checksum_size(spec.format))
            }
            Part::Checksum(_) => None,
            Part::Word(word) => word.format.fixed_len(),
            Part::Length(length) => length.format.fixed_len(),
        }
    }
}

/// One part of a frame.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Part {
    /// Fixed bytes, such as a start character or a terminator.
    Literal {
        /// Name used in error messages, e.g. `start`.
        name: Text,
        /// The bytes.
        bytes: List<u8>,
        /// An optional literal is present on decode when the next bytes equal it.
        optional: bool,
    },
    /// A value carried by the frame.
    Field(FieldSpec),
    /// A checksum over earlier bytes.
    Checksum(ChecksumSpec),
    /// A word made of bit fields.
    Word(WordSpec),
    /// A computed length.
    Length(LengthSpec),
}

impl Part {
    /// The part's name.
    pub fn name(&self) -> &str {
        match self {
            Part::Literal { name, .. } => name,
            Part::Field(field) => &field.name,
            Part::Checksum(checksum) => &checksum.name,
            Part::Word(word) => &word.name,
            Part::Length(length) => &length.name,
        }
    }
}

/// Const constructors: generated code writes each part as one of these followed by the
/// `with_*` calls for what differs from the defaults, so layouts stay short and readable.
impl Part {
    /// Fixed bytes that are always present.
    pub const fn literal(name: &'static str, bytes: &'static [u8]) -> Part {
        Part::Literal {
            name: Cow::Borrowed(name),
            bytes: Cow::Borrowed(bytes),
            optional: false,
        }
    }

    /// Fixed bytes that may be left out (present on decode when the next bytes equal them).
    pub const fn optional_literal(name: &'static str, bytes: &'static [u8]) -> Part {
        Part::Literal {
            name: Cow::Borrowed(name),
            bytes: Cow::Borrowed(bytes),
            optional: true,
        }
    }
}
