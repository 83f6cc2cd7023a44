//! The 16-bit words a frame carries: a words field's, or the registers of a data field.

use super::hex::hex_digits_to_bytes;
use crate::layout::{Encoding, Format, FrameLayout, FrameValues, Role};

impl FrameValues {
    /// The 16-bit words of the words field ([`Role::Words`]) in `frame` (the frame these
    /// values were decoded from), each in the field's byte order; empty when the layout has
    /// none or the frame carries none.
    pub fn words(&self, layout: &FrameLayout, frame: &[u8]) -> Words {
        let little_endian = layout
            .field(Role::Words)
            .is_some_and(|field| field.format == Format::U16Le);
        self.words_of(layout, Role::Words, frame, little_endian)
    }

    /// The 16-bit registers of a data field that carries several (`data_size` above 4: a
    /// Modbus write of several registers), in `frame` (the frame these values were decoded
    /// from), in frame order, each in the data field's byte order; empty when the data is a
    /// number (4 bytes or fewer) or more than [`MAX_WORDS`] words.
    pub fn data_words(&self, layout: &FrameLayout, frame: &[u8]) -> Words {
        if self.data_size <= 4 || usize::from(self.data_size) > 2 * MAX_WORDS {
            return Words::default();
        }
        let little_endian = layout
            .field(Role::Data)
            .is_some_and(|field| field.format == Format::UintLe);
        self.words_of(layout, Role::Data, frame, little_endian)
    }

    /// The words of the field with `role`, read from the wire (hex digits turned back into
    /// bytes for an [`Encoding::HexPairs`] layout).
    fn words_of(
        &self,
        layout: &FrameLayout,
        role: Role,
        frame: &[u8],
        little_endian: bool,
    ) -> Words {
        let wire = self.bytes(layout, role, frame).unwrap_or(&[]);
        let mut decoded = [0u8; 2 * MAX_WORDS];
        let bytes = if layout.encoding == Encoding::HexPairs {
            let n = hex_digits_to_bytes(wire, &mut decoded);
            &decoded[..n]
        } else {
            wire
        };
        let mut words = Words::default();
        for pair in bytes.chunks_exact(2).take(MAX_WORDS) {
            let pair = [pair[0], pair[1]];
            words.words[usize::from(words.len)] = if little_endian {
                u16::from_le_bytes(pair)
            } else {
                u16::from_be_bytes(pair)
            };
            words.len += 1;
        }
        words
    }
}

/// The most words a [`Words`] list holds: a words field's ([`Role::Words`]), or the
/// registers of a data field carrying several (a Modbus 10h write: at most 123).
pub const MAX_WORDS: usize = 128;

/// The words a frame's words field carries (a block transfer's), or the registers a data
/// field carries, held without allocation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Words {
    words: [u16; MAX_WORDS],
    len: u8,
}

impl Default for Words {
    fn default() -> Self {
        Words {
            words: [0; MAX_WORDS],
            len: 0,
        }
    }
}

impl Words {
    /// The words, in frame order.
    pub fn as_slice(&self) -> &[u16] {
        &self.words[..usize::from(self.len)]
    }

    /// These words; `None` when there are more than [`MAX_WORDS`].
    pub fn from_slice(words: &[u16]) -> Option<Words> {
        if words.len() > MAX_WORDS {
            return None;
        }
        let mut list = Words {
            len: words.len() as u8,
            ..Words::default()
        };
        list.words[..words.len()].copy_from_slice(words);
        Some(list)
    }

    /// Writes the words into `out` as the payload of `layout`'s words field (each in the
    /// field's byte order) and returns the byte count, without allocating; `out` holds
    /// [`MAX_WORDS`] words.
    pub fn write_payload(&self, layout: &FrameLayout, out: &mut [u8; 2 * MAX_WORDS]) -> usize {
        let little_endian = layout
            .field(Role::Words)
            .is_some_and(|field| field.format == Format::U16Le);
        for (word, pair) in self.as_slice().iter().zip(out.chunks_exact_mut(2)) {
            let bytes = if little_endian {
                word.to_le_bytes()
            } else {
                word.to_be_bytes()
            };
            pair.copy_from_slice(&bytes);
        }
        self.as_slice().len() * 2
    }

    /// The words as the payload of `layout`'s words field: each in the field's byte order.
    pub fn payload(&self, layout: &FrameLayout) -> Vec<u8> {
        let little_endian = layout
            .field(Role::Words)
            .is_some_and(|field| field.format == Format::U16Le);
        self.as_slice()
            .iter()
            .flat_map(|word| {
                if little_endian {
                    word.to_le_bytes()
                } else {
                    word.to_be_bytes()
                }
            })
            .collect()
    }
}
