//! Bit-field words: what every generated word type shares. A generated type (one per
//! bit-field layout of a manual) is a `u16` newtype with a mask constant and an accessor
//! pair per field; the bit arithmetic, conversions and display live here once.

use crate::error::ValueError;
use crate::info::RegisterInfo;
use std::fmt;

/// A word made of named bit fields.
pub trait BitWord: Copy {
    /// Named fields and their masks, from the most significant bit down.
    const FIELDS: &'static [(&'static str, u16)];
    /// The word with these bits.
    fn from_bits(bits: u16) -> Self;
    /// The raw word.
    fn bits(self) -> u16;
    /// Names of the fields with any bit set, from the most significant bit down.
    fn set_fields(self) -> impl Iterator<Item = &'static str> {
        let bits = self.bits();
        Self::FIELDS
            .iter()
            .filter(move |(_, mask)| bits & mask != 0)
            .map(|(name, _)| *name)
    }
}

/// Whether any bit of `mask` is set in `word`.
pub const fn flag(word: u16, mask: u16) -> bool {
    word & mask != 0
}

/// `word` with the bits of `mask` set (`on`) or cleared.
pub const fn with_flag(word: u16, mask: u16, on: bool) -> u16 {
    if on {
        word | mask
    } else {
        word & !mask
    }
}

/// The value of the field `mask` in `word`, shifted down to bit 0.
pub const fn field(word: u16, mask: u16) -> u16 {
    if mask == 0 {
        0
    } else {
        (word & mask) >> mask.trailing_zeros()
    }
}

/// `word` with the field `mask` set to `value` (bits beyond the field's width dropped).
pub const fn with_field(word: u16, mask: u16, value: u16) -> u16 {
    if mask == 0 {
        word
    } else {
        (word & !mask) | ((value << mask.trailing_zeros()) & mask)
    }
}

/// The raw register value of a word (bit-field words are one word wide, never scaled).
pub fn to_raw<W: BitWord>(word: W, _info: &'static RegisterInfo) -> Result<u32, ValueError> {
    Ok(u32::from(word.bits()))
}

/// A word from a raw register value, keeping the low 16 bits.
pub fn from_raw<W: BitWord>(raw: u32, _info: &'static RegisterInfo) -> Result<W, ValueError> {
    Ok(W::from_bits(raw as u16))
}

/// Writes the fields that are set (`run | command_enabled`), or `-` when none is.
pub fn fmt_fields<W: BitWord>(word: W, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    let mut first = true;
    for name in word.set_fields() {
        if !first {
            f.write_str(" | ")?;
        }
        f.write_str(name)?;
        first = false;
    }
    if first {
        f.write_str("-")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Clone, Copy, PartialEq)]
    struct Word(u16);

    impl BitWord for Word {
        const FIELDS: &'static [(&'static str, u16)] = &[("run", 0x8000), ("speed", 0x0030)];
        fn from_bits(bits: u16) -> Self {
            Word(bits)
        }
        fn bits(self) -> u16 {
            self.0
        }
    }

    impl fmt::Display for Word {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            fmt_fields(*self, f)
        }
    }

    #[test]
    fn flags_and_fields_read_and_write_their_bits() {
        assert!(flag(0x8001, 0x8000));
        assert!(!flag(0x0001, 0x8000));
        assert_eq!(with_flag(0x0001, 0x8000, true), 0x8001);
        assert_eq!(with_flag(0x8001, 0x8000, false), 0x0001);
        assert_eq!(field(0x0020, 0x0030), 2);
        assert_eq!(with_field(0xFFFF, 0x0030, 1), 0xFFDF);
        assert_eq!(
            with_field(0, 0x0030, 7),
            0x0030,
            "bits beyond the width are dropped"
        );
    }

    #[test]
    fn display_lists_the_fields_that_are_set() {
        assert_eq!(Word(0x8010).to_string(), "run | speed");
        assert_eq!(Word(0).to_string(), "-");
        assert_eq!(Word(0x8000).set_fields().collect::<Vec<_>>(), ["run"]);
    }
}
