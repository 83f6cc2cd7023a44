//! Digits on the wire: a hex-pairs frame's bytes to and from their wire form, and the
//! radix of a digits format.

use crate::error::DecodeError;
use crate::layout::{Format, FrameLayout};

/// The radix of a digit format.
pub(super) fn digit_radix(format: Format) -> Option<u32> {
    match format {
        Format::Decimal => Some(10),
        Format::Hex => Some(16),
        _ => None,
    }
}

/// The longest frame, in bytes before hex digits, a [`Encoding::HexPairs`] layout handles.
pub(crate) const MAX_HEX_FRAME: usize = 300;

/// Writes a [`Encoding::HexPairs`] frame's `bytes` into `out`: the verbatim ends as they
/// are, every byte between them as two hex digits. `None` when `out` is too small.
pub(crate) fn hex_expand(layout: &FrameLayout, bytes: &[u8], out: &mut [u8]) -> Option<usize> {
    let len = bytes.len();
    let (head, tail) = layout.verbatim_ends();
    let middle = &bytes[head.len().min(len)..len.saturating_sub(tail.len()).max(head.len())];
    let needed = head.len() + 2 * middle.len() + tail.len();
    if needed > out.len() {
        return None;
    }
    out[..head.len()].copy_from_slice(head);
    let mut at = head.len();
    for byte in middle {
        out[at] = HEX_DIGITS[usize::from(byte >> 4)];
        out[at + 1] = HEX_DIGITS[usize::from(byte & 0x0F)];
        at += 2;
    }
    out[at..at + tail.len()].copy_from_slice(tail);
    Some(needed)
}

const HEX_DIGITS: &[u8; 16] = b"0123456789ABCDEF";

fn hex_value(digit: u8) -> Option<u8> {
    char::from(digit).to_digit(16).map(|value| value as u8)
}

/// The bytes a [`Encoding::HexPairs`] frame carries, from its wire form: the verbatim head,
/// each pair of hex digits as one byte, and the verbatim tail once it arrives. Stops at
/// the first character that is neither (the decoder then reports the byte where the frame
/// goes wrong). Returns how many bytes were written to `out`, and where in `wire` the tail
/// begins and ends in both forms, when it was found.
pub(crate) fn hex_pairs_to_bytes(
    layout: &FrameLayout,
    wire: &[u8],
    out: &mut [u8; MAX_HEX_FRAME],
) -> Result<HexFrame, DecodeError> {
    let (head, tail) = layout.verbatim_ends();
    let head_len = head.len().min(wire.len());
    out[..head_len].copy_from_slice(&wire[..head_len]);
    let mut frame = HexFrame {
        len: head_len,
        head: head.len(),
        tail_at: None,
    };
    let mut at = head_len;
    while at < wire.len() && frame.len < MAX_HEX_FRAME {
        let rest = &wire[at..];
        if !tail.is_empty() && rest.starts_with(tail) {
            frame.tail_at = Some(frame.len);
            let n = tail.len().min(MAX_HEX_FRAME - frame.len);
            out[frame.len..frame.len + n].copy_from_slice(&tail[..n]);
            frame.len += n;
            break;
        }
        if !tail.is_empty() && tail.starts_with(rest) {
            break; // the tail's first characters: the frame is not finished
        }
        match (hex_value(rest[0]), rest.get(1).map(|d| hex_value(*d))) {
            (Some(high), Some(Some(low))) => {
                out[frame.len] = high << 4 | low;
                frame.len += 1;
                at += 2;
            }
            (Some(_), None) => break, // half a pair so far
            _ => {
                let bad = usize::from(hex_value(rest[0]).is_some());
                return Err(DecodeError::UnexpectedByte {
                    layout: layout.name.clone(),
                    part: "hex digits".into(),
                    offset: at + bad,
                    found: rest[bad],
                    expected: "a hex digit (0-9, A-F)".to_owned(),
                });
            }
        }
    }
    Ok(frame)
}

/// Where a [`Encoding::HexPairs`] frame's parts lie, in bytes before hex digits.
pub(crate) struct HexFrame {
    /// Bytes recovered.
    pub(crate) len: usize,
    /// Length of the verbatim head.
    pub(super) head: usize,
    /// Where the verbatim tail begins, once it arrived.
    pub(super) tail_at: Option<usize>,
}

impl HexFrame {
    /// The wire offset of byte `at` of the recovered frame.
    pub(crate) fn wire_offset(&self, at: usize) -> usize {
        let middle_end = self.tail_at.unwrap_or(self.len);
        if at <= self.head {
            at
        } else if at <= middle_end {
            self.head + 2 * (at - self.head)
        } else {
            self.head + 2 * (middle_end - self.head) + (at - middle_end)
        }
    }
}

/// Turns pairs of hex digits into bytes, as many as fit `out`; stops at the first
/// character that is not a hex digit. Returns the number of bytes written.
pub fn hex_digits_to_bytes(digits: &[u8], out: &mut [u8]) -> usize {
    let mut n = 0;
    for (pair, slot) in digits.chunks_exact(2).zip(out.iter_mut()) {
        match (hex_value(pair[0]), hex_value(pair[1])) {
            (Some(high), Some(low)) => *slot = high << 4 | low,
            _ => break,
        }
        n += 1;
    }
    n
}
