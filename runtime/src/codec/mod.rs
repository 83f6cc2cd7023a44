//! Encodes and decodes frames by interpreting a [`FrameLayout`], without heap allocation.
//!
//! Decoding distinguishes three outcomes: a complete frame, "more bytes needed"
//! ([`DecodeStatus::Incomplete`]) and a [`DecodeError`] that says which part, at which
//! offset, did not fit. The transaction engine relies on that difference to wait for the
//! rest of a reply without waiting on garbage.
//!
//! Encoding runs in three passes: parts are written (lengths and checksums reserved),
//! lengths are filled in, then checksums are computed, so a checksum may cover a length.
//!
//! [`FrameLayout`]: crate::layout::FrameLayout
//! [`DecodeError`]: crate::error::DecodeError

// Layers, each file using only those above it: `hex` (digits) and `cursor` (decoding
// state); `words`; `encode`; `decode_fields`, then `decode_checks`; `decode` on top.
mod cursor;
mod decode;
mod decode_checks;
mod decode_fields;
mod encode;
#[cfg(test)]
mod frame_tests;
mod hex;
#[cfg(test)]
mod sample_layouts;
mod words;

pub use decode::{decode, decode_prefix, DecodeStatus, Progress};
pub use encode::{encode, encode_with_payload};
pub use hex::hex_digits_to_bytes;
pub(crate) use hex::{hex_expand, hex_pairs_to_bytes, MAX_HEX_FRAME};
pub use words::{Words, MAX_WORDS};

pub use crate::layout::{FieldValue, FrameValues, Roles};
