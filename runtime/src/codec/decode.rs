//! Decoding a frame: complete, more bytes needed, or an error that places the wrong byte.

use super::cursor::{length_error, mismatch_at, Cursor, PartOutcome};
use super::decode_checks::{decode_checksum, decode_length, decode_word};
use super::decode_fields::decode_field;
use super::hex::{hex_pairs_to_bytes, HexFrame, MAX_HEX_FRAME};
use crate::error::DecodeError;
use crate::layout::{Counts, Encoding, FrameLayout, FrameValues, Part, MAX_PARTS};

/// Outcome of [`decode`] when the bytes are not wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DecodeStatus {
    /// A whole frame: its values and its length in bytes.
    Complete {
        /// Decoded values.
        values: FrameValues,
        /// Bytes the frame occupies from the start of the input.
        len: usize,
    },
    /// The bytes so far fit the layout but the frame is not finished.
    Incomplete,
}
/// Decodes one frame that starts at `bytes[0]`.
///
/// Returns [`DecodeStatus::Incomplete`] while `bytes` is a proper prefix of a frame that
/// fits the layout, and an error as soon as a byte cannot belong to one.
pub fn decode(layout: &FrameLayout, bytes: &[u8]) -> Result<DecodeStatus, DecodeError> {
    Ok(match decode_prefix(layout, bytes)? {
        Progress::Complete { values, len } => DecodeStatus::Complete { values, len },
        Progress::Incomplete { .. } => DecodeStatus::Incomplete,
    })
}

/// How far [`decode_prefix`] got.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Progress {
    /// A whole frame, as [`DecodeStatus::Complete`].
    Complete {
        /// Decoded values.
        values: FrameValues,
        /// Bytes the frame occupies from the start of the input.
        len: usize,
    },
    /// The bytes so far fit the layout: the values of the parts they hold whole (marked
    /// present), so a caller can tell early that a frame cannot be the one it waits for.
    Incomplete {
        /// Values of the parts decoded so far.
        values: FrameValues,
    },
}

/// [`decode`], with the values of the parts already decoded when the frame is not finished.
pub fn decode_prefix(layout: &FrameLayout, bytes: &[u8]) -> Result<Progress, DecodeError> {
    if layout.encoding == Encoding::HexPairs {
        return decode_hex_pairs(layout, bytes);
    }
    decode_binary(layout, bytes)
}

/// Turns the hex digits back into bytes and decodes those; the frame's length and the
/// offsets in errors are given on the wire.
fn decode_hex_pairs(layout: &FrameLayout, wire: &[u8]) -> Result<Progress, DecodeError> {
    let mut bytes = [0u8; MAX_HEX_FRAME];
    let frame = hex_pairs_to_bytes(layout, wire, &mut bytes)?;
    match decode_binary(layout, &bytes[..frame.len]) {
        Ok(Progress::Complete { values, len }) => Ok(Progress::Complete {
            values,
            len: frame.wire_offset(len),
        }),
        Ok(incomplete) => Ok(incomplete),
        // The closing literal came before the parts were complete: the frame is short,
        // whatever the parts made of the closing bytes.
        Err(_)
            if frame.tail_at.is_some_and(|tail| frame.len > tail)
                && short(layout, &bytes, &frame) =>
        {
            Err(DecodeError::Truncated {
                layout: layout.name.clone(),
                len: frame.wire_offset(frame.len),
            })
        }
        Err(error) => Err(error.at_offset(|offset| frame.wire_offset(offset))),
    }
}

fn decode_binary(layout: &FrameLayout, bytes: &[u8]) -> Result<Progress, DecodeError> {
    let mut values = FrameValues::default();
    let mut starts = [0usize; MAX_PARTS];
    let mut ends = [0usize; MAX_PARTS];
    let mut cursor = Cursor {
        bytes,
        pos: 0,
        frame_end: None,
        sized: [u16::MAX; MAX_PARTS],
    };
    let parts = &layout.parts[..layout.parts.len().min(MAX_PARTS)];
    for (index, part) in parts.iter().enumerate() {
        starts[index] = cursor.pos;
        let outcome = decode_part(layout, index, part, &mut cursor, &starts, &mut values)?;
        if outcome == PartOutcome::Incomplete {
            return Ok(Progress::Incomplete { values });
        }
        ends[index] = cursor.pos;
        if let Some(end) = cursor.frame_end {
            if cursor.pos > end {
                return Err(length_error(layout, part.name(), end, cursor.pos));
            }
        }
    }
    for (index, part) in parts.iter().enumerate() {
        if let Part::Length(length) = part {
            if let Counts::Parts { from, through } = length.counts {
                let counted = ends[usize::from(through)] - starts[usize::from(from)];
                let expected =
                    (counted * usize::from(length.times) / usize::from(length.per.max(1))) as u32;
                if values.parts[index].value != expected {
                    return Err(DecodeError::LengthMismatch {
                        layout: layout.name.clone(),
                        part: length.name.clone(),
                        offset: starts[index],
                        received: values.parts[index].value,
                        actual: expected,
                    });
                }
            }
        }
    }
    Ok(Progress::Complete {
        values,
        len: cursor.pos,
    })
}

/// Whether the bytes before a hex-pairs frame's closing literal are fewer than its parts
/// need: decoding them alone, without the closing bytes, runs out.
fn short(layout: &FrameLayout, bytes: &[u8; MAX_HEX_FRAME], frame: &HexFrame) -> bool {
    let Some(tail) = frame.tail_at else {
        return false;
    };
    matches!(
        decode_binary(layout, &bytes[..tail]),
        Ok(Progress::Incomplete { .. })
    )
}

fn decode_part(
    layout: &FrameLayout,
    index: usize,
    part: &Part,
    cursor: &mut Cursor<'_>,
    starts: &[usize; MAX_PARTS],
    values: &mut FrameValues,
) -> Result<PartOutcome, DecodeError> {
    let rest = &cursor.bytes[cursor.pos..];
    match part {
        Part::Literal {
            bytes: literal,
            optional,
            name,
        } => {
            let compared = rest.len().min(literal.len());
            if rest[..compared] != literal[..compared] {
                if *optional {
                    return Ok(PartOutcome::Done);
                }
                let at = mismatch_at(rest, literal);
                return Err(DecodeError::UnexpectedByte {
                    layout: layout.name.clone(),
                    part: name.clone(),
                    offset: cursor.pos + at,
                    found: rest[at],
                    expected: crate::error::describe_bytes(literal),
                });
            }
            if compared < literal.len() {
                return Ok(PartOutcome::Incomplete);
            }
            values.parts[index].present = true;
            cursor.pos += literal.len();
            Ok(PartOutcome::Done)
        }
        Part::Field(field) => decode_field(layout, index, field, cursor, values),
        Part::Word(word) => decode_word(layout, index, word, cursor, values),
        Part::Length(length) => decode_length(layout, index, length, cursor, values),
        Part::Checksum(spec) => decode_checksum(layout, index, spec, cursor, starts, values),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::codec::encode;
    use crate::codec::sample_layouts::*;
    use crate::layout::*;

    #[test]
    fn decodes_and_reencodes_a_frame_with_checksum() {
        let layout = toshiba_ascii_read();
        let DecodeStatus::Complete { values, len } = decode(&layout, b"(R0000&60)\r").unwrap()
        else {
            panic!("incomplete")
        };
        assert_eq!(len, 11);
        assert_eq!(values.get(&layout, Role::Register), Some(0));
        let mut out = [0u8; 32];
        let n = encode(&layout, &values, &mut out).unwrap();
        assert_eq!(&out[..n], b"(R0000&60)\r");
    }

    #[test]
    fn every_proper_prefix_is_incomplete() {
        let layout = toshiba_ascii_read();
        let frame = b"(12R0501&C9)\r";
        for end in 0..frame.len() {
            let outcome = decode(&layout, &frame[..end]);
            assert_eq!(
                outcome,
                Ok(DecodeStatus::Incomplete),
                "prefix of {end} bytes"
            );
        }
    }

    #[test]
    fn hex_pairs_frames_carry_each_byte_as_two_digits_and_sum_the_bytes() {
        // DV1 example 3: write 1388h to 00C3h; LRC over the bytes is 9Bh.
        let layout = hex_pairs_write();
        let mut values = FrameValues::default();
        values.fill(
            &layout,
            &Roles {
                address: Some(1),
                command: Some(6),
                register: Some(0xC3),
                data: Some(0x1388),
                ..Roles::default()
            },
        );
        let mut out = [0u8; 64];
        let len = encode(&layout, &values, &mut out).unwrap();
        assert_eq!(&out[..len], b":010600C313889B\r\n");
        let DecodeStatus::Complete { values, len } = decode(&layout, &out[..len]).unwrap() else {
            panic!("incomplete")
        };
        assert_eq!(len, 17, "the length on the wire");
        assert_eq!(values.get(&layout, Role::Data), Some(0x1388));
        // Lower-case digits are read too.
        assert!(matches!(
            decode(&layout, b":010600c313889b\r\n"),
            Ok(DecodeStatus::Complete { len: 17, .. })
        ));
    }

    #[test]
    fn hex_pairs_prefixes_wait_and_bad_characters_are_placed_on_the_wire() {
        let layout = hex_pairs_write();
        for prefix in [
            &b":"[..],
            b":0",
            b":0106",
            b":010600C313889B",
            b":010600C313889B\r",
        ] {
            assert_eq!(
                decode(&layout, prefix),
                Ok(DecodeStatus::Incomplete),
                "{prefix:?}"
            );
        }
        let error = decode(&layout, b":01G6").unwrap_err();
        assert_eq!(
            (error.kind(), error.offset()),
            (crate::DecodeErrorKind::UnexpectedByte, 3)
        );
        // CR LF before the parts are complete: a short frame, not a wrong LRC.
        let error = decode(&layout, b":010600C31388\r\n").unwrap_err();
        assert_eq!(error.kind(), crate::DecodeErrorKind::Truncated, "{error}");
        // A wrong LRC is reported at its digits: byte 6 of the bytes, character 13.
        let error = decode(&layout, b":010600C313889C\r\n").unwrap_err();
        assert_eq!(
            (error.kind(), error.offset()),
            (crate::DecodeErrorKind::ChecksumMismatch, 13)
        );
    }
}
