//! Words whose bits hold several fields: a [`WordSpec`] and its [`BitsSpec`]s.

use std::borrow::Cow;

use super::borrowed::{List, Text};
use super::format::Format;
use super::role::Role;

/// A word whose bits hold several fields (the FC PKE: command nibble + parameter number).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct WordSpec {
    /// Name used in error messages, e.g. `pke`.
    pub name: Text,
    /// `U16Be`, `U16Le`, `U32Be` or `U32Le`.
    pub format: Format,
    /// The fields, each a run of bits.
    pub fields: List<BitsSpec>,
}

/// A run of bits inside a [`WordSpec`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BitsSpec {
    /// Field name, e.g. `ak`.
    pub name: Text,
    /// What it means.
    pub role: Role,
    /// Lowest bit.
    pub lsb: u8,
    /// Bit count.
    pub width: u8,
    /// Values the decoder accepts; empty means any.
    pub allowed: List<u32>,
}

impl BitsSpec {
    /// The bits' mask within the word.
    #[inline]
    pub const fn mask(&self) -> u32 {
        (((1u64 << self.width) - 1) << self.lsb) as u32
    }
}

impl BitsSpec {
    /// `width` bits from `lsb`, any value.
    pub const fn new(name: &'static str, role: Role, lsb: u8, width: u8) -> BitsSpec {
        BitsSpec {
            name: Cow::Borrowed(name),
            role,
            lsb,
            width,
            allowed: Cow::Borrowed(&[]),
        }
    }

    /// Only these values are accepted.
    pub const fn with_allowed(mut self, allowed: &'static [u32]) -> BitsSpec {
        // A const fn cannot drop the old value, so it is forgotten: nothing to free when it
        // is borrowed, as in generated code (an owned one would leak).
        core::mem::forget(core::mem::replace(
            &mut self.allowed,
            Cow::Borrowed(allowed),
        ));
        self
    }
}
