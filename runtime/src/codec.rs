//! Encodes and decodes frames by interpreting a [`FrameLayout`], without heap allocation.
//!
//! Decoding distinguishes three outcomes: a complete frame, "more bytes needed"
//! ([`DecodeStatus::Incomplete`]) and a [`DecodeError`] that says which part, at which
//! offset, did not fit. The transaction engine relies on that difference to wait for the
//! rest of a reply without waiting on garbage.
//!
//! Encoding runs in three passes: parts are written (lengths and checksums reserved),
//! lengths are filled in, then checksums are computed, so a checksum may cover a length.

use crate::checksum;
use crate::error::{DecodeError, EncodeError};
use crate::layout::{
    checksum_size, BitsSpec, BroadcastAddress, ChecksumSpec, Counts, Encoding, FieldSpec, Format,
    FrameLayout, LengthSpec, Part, Presence, Role, SizedBy, WordSpec, MAX_PARTS,
};

pub use crate::layout::{FieldValue, FrameValues, Roles};

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

/// Encodes a frame into `out`, returning the number of bytes written. `payload` supplies
/// the bytes of a bytes field (text), if the layout has one.
///
/// Required parts are always written; optional ones only when their slot in `values` is
/// marked present. Lengths and checksums are computed.
pub fn encode(
    layout: &FrameLayout,
    values: &FrameValues,
    out: &mut [u8],
) -> Result<usize, EncodeError> {
    encode_with_payload(layout, values, &[], out)
}

/// [`encode`] with the bytes of the layout's bytes field, or of its data field when that
/// carries a block of registers (`values.data_size` above 4: a read of several registers,
/// each in the field's byte order, in address order).
pub fn encode_with_payload(
    layout: &FrameLayout,
    values: &FrameValues,
    payload: &[u8],
    out: &mut [u8],
) -> Result<usize, EncodeError> {
    crate::tally::encoding();
    if layout.encoding == Encoding::HexPairs {
        return encode_hex_pairs(layout, values, payload, out);
    }
    encode_binary(layout, values, payload, out)
}

/// The longest frame, in bytes before hex digits, a [`Encoding::HexPairs`] layout handles.
pub(crate) const MAX_HEX_FRAME: usize = 300;

/// Encodes the frame's bytes, then writes those between its verbatim ends as hex digits.
fn encode_hex_pairs(
    layout: &FrameLayout,
    values: &FrameValues,
    payload: &[u8],
    out: &mut [u8],
) -> Result<usize, EncodeError> {
    let mut bytes = [0u8; MAX_HEX_FRAME];
    let len = encode_binary(layout, values, payload, &mut bytes)?;
    hex_expand(layout, &bytes[..len], out).ok_or_else(|| EncodeError::BufferTooSmall {
        layout: layout.name.clone(),
        capacity: out.len(),
    })
}

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

/// Where a [`Encoding::HexPairs`] frame's parts lie, in bytes before hex digits.
pub(crate) struct HexFrame {
    /// Bytes recovered.
    pub(crate) len: usize,
    /// Length of the verbatim head.
    head: usize,
    /// Where the verbatim tail begins, once it arrived.
    tail_at: Option<usize>,
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

fn encode_binary(
    layout: &FrameLayout,
    values: &FrameValues,
    payload: &[u8],
    out: &mut [u8],
) -> Result<usize, EncodeError> {
    if layout.parts.len() > MAX_PARTS {
        return Err(EncodeError::TooManyParts {
            layout: layout.name.clone(),
        });
    }
    let mut writer = Writer {
        out,
        len: 0,
        layout,
    };
    let mut starts = [0usize; MAX_PARTS];
    let mut ends = [0usize; MAX_PARTS];
    for (index, part) in layout.parts.iter().enumerate() {
        starts[index] = writer.len;
        let slot = values.parts[index];
        match part {
            Part::Literal {
                bytes, optional, ..
            } => {
                if !optional || slot.present {
                    writer.put(bytes)?;
                }
            }
            Part::Field(field) => {
                if field.optional.is_none() || slot.present {
                    encode_field(&mut writer, field, slot, values.data_size, payload)?;
                }
            }
            Part::Word(word) => writer.put_value(&word.name, word.format, slot.value, 0)?,
            Part::Length(length) => writer.reserve(length.format.fixed_len().unwrap_or(1))?,
            Part::Checksum(spec) => {
                if !spec.optional || slot.present {
                    writer.put(&spec.marker)?;
                    writer.reserve(checksum_size(spec.format))?;
                }
            }
        }
        ends[index] = writer.len;
    }
    for (index, part) in layout.parts.iter().enumerate() {
        if let Part::Length(length) = part {
            let counted = match length.counts {
                Counts::Parts { from, through } => {
                    ends[usize::from(through)] - starts[usize::from(from)]
                }
                Counts::DataSize => usize::from(values.data_size),
            };
            let value =
                (counted * usize::from(length.times) / usize::from(length.per.max(1))) as u32;
            writer.len = starts[index];
            writer.put_value(&length.name, length.format, value, 0)?;
        }
    }
    for (index, part) in layout.parts.iter().enumerate() {
        if let Part::Checksum(spec) = part {
            if ends[index] == starts[index] {
                continue;
            }
            let value_at = starts[index] + spec.marker.len();
            let covered_end = spec
                .covers_through
                .map_or(value_at, |through| ends[usize::from(through)]);
            let sum = checksum::compute(
                spec.algorithm,
                &writer.out[starts[usize::from(spec.covers_from)]..covered_end],
            );
            writer.len = value_at;
            writer.put_value(&spec.name, spec.format, sum, 2)?;
        }
    }
    Ok(layout
        .parts
        .len()
        .checked_sub(1)
        .map_or(0, |last| ends[last]))
}

fn encode_field(
    writer: &mut Writer<'_, '_>,
    field: &FieldSpec,
    slot: FieldValue,
    data_size: u8,
    payload: &[u8],
) -> Result<(), EncodeError> {
    if field.role == Role::Words {
        // The words of a block transfer: the payload holds them, each in the field's format.
        return writer.put(payload);
    }
    match field.format {
        Format::Bytes => writer.put(payload),
        // A block of registers: the payload holds them, each in the field's byte order.
        Format::UintBe | Format::UintLe
            if field.role == Role::Data
                && data_size > 4
                && payload.len() == usize::from(data_size) =>
        {
            writer.put(payload)
        }
        Format::UintBe | Format::UintLe => {
            let width = match (slot.width, data_size) {
                (0, 0) => field.width,
                (0, size) => size,
                (width, _) => width,
            };
            writer.put_value(&field.name, field.format, slot.value, width)
        }
        _ => {
            let width = if slot.width == 0 {
                field.width
            } else {
                slot.width
            };
            match &field.broadcast {
                Some(broadcast) if BroadcastAddress::is_open(slot.value) => {
                    encode_open_digits(writer, field, broadcast, slot.value)
                }
                _ => writer.put_value(&field.name, field.format, slot.value, width),
            }
        }
    }
}

/// A station number with open digits: the broadcast bytes when every digit is open and the
/// field has them, else the digits with the wildcard character in the open places.
fn encode_open_digits(
    writer: &mut Writer<'_, '_>,
    field: &FieldSpec,
    broadcast: &BroadcastAddress,
    value: u32,
) -> Result<(), EncodeError> {
    let width = usize::from(field.width);
    let mask = (value >> BroadcastAddress::MASK_SHIFT) & 0x7F;
    let all = (1u32 << width.min(7)) - 1;
    let too_wide = || EncodeError::ValueTooWide {
        layout: writer.layout.name.clone(),
        field: field.name.clone(),
        value,
        format: field.format,
        width: field.width,
    };
    if mask == all && !broadcast.all_bytes.is_empty() {
        return writer.put(&broadcast.all_bytes);
    }
    let (Some(wildcard), Some(radix)) = (broadcast.wildcard, digit_radix(field.format)) else {
        return Err(too_wide());
    };
    if width == 0 || width > 7 {
        return Err(too_wide());
    }
    let mut digits = [0u8; 7];
    let mut rest = value & ((1 << BroadcastAddress::MASK_SHIFT) - 1);
    for (position, slot) in digits[..width].iter_mut().rev().enumerate() {
        let digit = (rest % radix) as u8;
        rest /= radix;
        *slot = if mask & (1 << position) != 0 {
            wildcard
        } else if digit < 10 {
            b'0' + digit
        } else {
            b'A' + digit - 10
        };
    }
    if rest != 0 {
        return Err(too_wide());
    }
    writer.put(&digits[..width])
}

/// The radix of a digit format.
fn digit_radix(format: Format) -> Option<u32> {
    match format {
        Format::Decimal => Some(10),
        Format::Hex => Some(16),
        _ => None,
    }
}

struct Writer<'o, 'l> {
    out: &'o mut [u8],
    len: usize,
    layout: &'l FrameLayout,
}

impl Writer<'_, '_> {
    fn put(&mut self, bytes: &[u8]) -> Result<(), EncodeError> {
        let end = self.len + bytes.len();
        if end > self.out.len() {
            return Err(EncodeError::BufferTooSmall {
                layout: self.layout.name.clone(),
                capacity: self.out.len(),
            });
        }
        self.out[self.len..end].copy_from_slice(bytes);
        self.len = end;
        Ok(())
    }

    fn reserve(&mut self, count: usize) -> Result<(), EncodeError> {
        let zeros = [0u8; 8];
        self.put(&zeros[..count.min(8)])
    }

    fn put_value(
        &mut self,
        name: &str,
        format: Format,
        value: u32,
        width: u8,
    ) -> Result<(), EncodeError> {
        let too_wide = || EncodeError::ValueTooWide {
            layout: self.layout.name.clone(),
            field: name.to_owned().into(),
            value,
            format,
            width,
        };
        match format {
            Format::Decimal | Format::Hex => {
                let radix: u32 = if format == Format::Hex { 16 } else { 10 };
                let mut digits = [0u8; 10];
                let width = usize::from(width);
                if width == 0 || width > digits.len() {
                    return Err(too_wide());
                }
                let mut rest = value;
                for slot in digits[..width].iter_mut().rev() {
                    let digit = (rest % radix) as u8;
                    *slot = if digit < 10 {
                        b'0' + digit
                    } else {
                        b'A' + digit - 10
                    };
                    rest /= radix;
                }
                if rest != 0 {
                    return Err(too_wide());
                }
                self.put(&digits[..width])
            }
            Format::Char | Format::U8 => {
                let byte = u8::try_from(value).map_err(|_| too_wide())?;
                self.put(&[byte])
            }
            Format::U16Be | Format::U16Le => {
                let word = u16::try_from(value).map_err(|_| too_wide())?;
                let bytes = if format == Format::U16Be {
                    word.to_be_bytes()
                } else {
                    word.to_le_bytes()
                };
                self.put(&bytes)
            }
            Format::U32Be => self.put(&value.to_be_bytes()),
            Format::U32Le => self.put(&value.to_le_bytes()),
            Format::UintBe | Format::UintLe => {
                let width = usize::from(width);
                if width == 0 || width > 4 || (width < 4 && value >> (8 * width) != 0) {
                    return Err(too_wide());
                }
                let be = value.to_be_bytes();
                let mut bytes = [0u8; 4];
                bytes[..width].copy_from_slice(&be[4 - width..]);
                if format == Format::UintLe {
                    bytes[..width].reverse();
                }
                self.put(&bytes[..width])
            }
            Format::Bytes => Err(too_wide()),
        }
    }
}

/// Decoding state shared by the parts of one frame.
struct Cursor<'b> {
    bytes: &'b [u8],
    pos: usize,
    /// End of the frame, once a length part covering the last part has been read.
    frame_end: Option<usize>,
    /// Sizes fixed by length parts that cover exactly one later part (`u16::MAX`: none).
    sized: [u16; MAX_PARTS],
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

fn length_error(layout: &FrameLayout, part: &str, end: usize, pos: usize) -> DecodeError {
    DecodeError::LengthMismatch {
        layout: layout.name.clone(),
        part: part.to_owned().into(),
        offset: end,
        received: end as u32,
        actual: pos as u32,
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PartOutcome {
    Done,
    Incomplete,
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

fn decode_field(
    layout: &FrameLayout,
    index: usize,
    field: &FieldSpec,
    cursor: &mut Cursor<'_>,
    values: &mut FrameValues,
) -> Result<PartOutcome, DecodeError> {
    let rest = &cursor.bytes[cursor.pos..];
    if let Some(presence) = field.optional {
        let Some(&next) = rest.first() else {
            return Ok(PartOutcome::Incomplete);
        };
        let present = match presence {
            Presence::IfFormatMatches => field.format.accepts_digit(next),
            Presence::IfByteAtMost(limit) => next <= limit,
        } || field
            .broadcast
            .as_ref()
            .is_some_and(|b| b.starts_with(next));
        if !present {
            return Ok(PartOutcome::Done);
        }
    }
    if field.role == Role::Words {
        return decode_words(layout, index, field, cursor, values);
    }
    if let Some(broadcast) = &field.broadcast {
        if let Some(outcome) = decode_open_digits(layout, field, broadcast, index, cursor, values)?
        {
            return Ok(outcome);
        }
    }
    let size = match (field.sized_by, field.format) {
        (SizedBy::Rest, _) => Some(rest_size(layout, index, cursor)?),
        (SizedBy::Length, _) => {
            (cursor.sized[index] != u16::MAX).then_some(usize::from(cursor.sized[index]))
        }
        (SizedBy::Format, Format::UintBe | Format::UintLe | Format::Bytes) => {
            Some(usize::from(field.width))
        }
        (SizedBy::Format, _) => None,
    };
    if let Some(size) = size {
        // A data field sized by a length part may carry a block of registers (a Modbus
        // read of several): wider than a number, it is held like a bytes field.
        let block = field.role == Role::Data
            && field.sized_by == SizedBy::Length
            && matches!(field.format, Format::UintBe | Format::UintLe)
            && size > 4;
        if size < usize::from(field.min_width)
            || (field.format != Format::Bytes && size > 4 && !block)
            || size > usize::from(u8::MAX)
        {
            return Err(DecodeError::LengthMismatch {
                layout: layout.name.clone(),
                part: field.name.clone(),
                offset: cursor.pos,
                received: size as u32,
                actual: u32::from(field.width),
            });
        }
        if rest.len() < size {
            return Ok(PartOutcome::Incomplete);
        }
        let value = match field.format {
            _ if block => cursor.pos as u32,
            Format::Bytes => cursor.pos as u32,
            Format::UintLe => rest[..size]
                .iter()
                .rev()
                .fold(0u32, |acc, b| (acc << 8) | u32::from(*b)),
            _ => rest[..size]
                .iter()
                .fold(0u32, |acc, b| (acc << 8) | u32::from(*b)),
        };
        if field.format != Format::Bytes && !block {
            check_allowed(layout, field, value, cursor.pos)?;
        }
        if field.role == Role::Data {
            values.data_size = size as u8;
        }
        values.parts[index] = FieldValue {
            present: true,
            value,
            width: size as u8,
        };
        cursor.pos += size;
        return Ok(PartOutcome::Done);
    }
    match decode_value(
        layout,
        &field.name,
        field.format,
        field.min_width,
        field.width,
        rest,
        cursor.pos,
    )? {
        None => Ok(PartOutcome::Incomplete),
        Some((value, used)) => {
            check_allowed(layout, field, value, cursor.pos)?;
            values.parts[index] = FieldValue {
                present: true,
                value,
                width: if field.format.is_digits() {
                    used as u8
                } else {
                    0
                },
            };
            cursor.pos += used;
            Ok(PartOutcome::Done)
        }
    }
}

/// A run of words sized by a length part (a block transfer's words): held as its offset
/// and byte count; the count must be whole words.
fn decode_words(
    layout: &FrameLayout,
    index: usize,
    field: &FieldSpec,
    cursor: &mut Cursor<'_>,
    values: &mut FrameValues,
) -> Result<PartOutcome, DecodeError> {
    let rest = &cursor.bytes[cursor.pos..];
    let word = field.format.fixed_len().unwrap_or(2);
    let size = match field.sized_by {
        SizedBy::Length if cursor.sized[index] != u16::MAX => usize::from(cursor.sized[index]),
        SizedBy::Rest => rest_size(layout, index, cursor)?,
        _ => usize::from(field.width),
    };
    if size % word != 0 || size > usize::from(u8::MAX) {
        return Err(DecodeError::LengthMismatch {
            layout: layout.name.clone(),
            part: field.name.clone(),
            offset: cursor.pos,
            received: size as u32,
            actual: (size - size % word) as u32,
        });
    }
    if rest.len() < size {
        return Ok(PartOutcome::Incomplete);
    }
    values.parts[index] = FieldValue {
        present: true,
        value: cursor.pos as u32,
        width: size as u8,
    };
    cursor.pos += size;
    Ok(PartOutcome::Done)
}

/// A station field written with open digits (`**`, `*9`): `Some` when the bytes at the
/// cursor are (or may still become) one, `None` when they are an ordinary value.
fn decode_open_digits(
    layout: &FrameLayout,
    field: &FieldSpec,
    broadcast: &BroadcastAddress,
    index: usize,
    cursor: &mut Cursor<'_>,
    values: &mut FrameValues,
) -> Result<Option<PartOutcome>, DecodeError> {
    let rest = &cursor.bytes[cursor.pos..];
    let width = usize::from(field.width);
    let all_bytes: &[u8] = &broadcast.all_bytes;
    if !all_bytes.is_empty() {
        let compared = rest.len().min(all_bytes.len());
        if compared > 0 && rest[..compared] == all_bytes[..compared] {
            if compared < all_bytes.len() {
                return Ok(Some(PartOutcome::Incomplete));
            }
            let mask = (1u32 << width.clamp(1, 7)) - 1;
            values.parts[index] = FieldValue {
                present: true,
                value: BroadcastAddress::OPEN | (mask << BroadcastAddress::MASK_SHIFT),
                width: field.width,
            };
            cursor.pos += all_bytes.len();
            return Ok(Some(PartOutcome::Done));
        }
    }
    let (Some(wildcard), Some(radix)) = (broadcast.wildcard, digit_radix(field.format)) else {
        return Ok(None);
    };
    if width == 0 || width > 7 {
        return Ok(None);
    }
    let shown = &rest[..rest.len().min(width)];
    if !shown.contains(&wildcard) {
        return Ok(None);
    }
    let mut mask = 0u32;
    let mut value = 0u32;
    for (offset, &byte) in shown.iter().enumerate() {
        let digit = if byte == wildcard {
            mask |= 1 << (width - 1 - offset);
            0
        } else {
            match (byte as char).to_digit(radix) {
                Some(digit) => digit,
                None => {
                    return Err(DecodeError::UnexpectedByte {
                        layout: layout.name.clone(),
                        part: field.name.clone(),
                        offset: cursor.pos + offset,
                        found: byte,
                        expected: format!("a digit or {}", byte_shown(wildcard)),
                    })
                }
            }
        };
        value = value.wrapping_mul(radix).wrapping_add(digit);
    }
    if shown.len() < width {
        return Ok(Some(PartOutcome::Incomplete));
    }
    values.parts[index] = FieldValue {
        present: true,
        value: BroadcastAddress::OPEN | (mask << BroadcastAddress::MASK_SHIFT) | value,
        width: field.width,
    };
    cursor.pos += width;
    Ok(Some(PartOutcome::Done))
}

fn byte_shown(byte: u8) -> String {
    crate::error::describe_bytes(&[byte])
}

/// Size of a rest-of-frame field: up to the frame end, less the fixed parts after it.
fn rest_size(
    layout: &FrameLayout,
    index: usize,
    cursor: &Cursor<'_>,
) -> Result<usize, DecodeError> {
    let tail: usize = layout.parts[index + 1..]
        .iter()
        .map(|p| p.fixed_size().unwrap_or(0))
        .sum();
    let end = cursor
        .frame_end
        .ok_or_else(|| DecodeError::LengthMismatch {
            layout: layout.name.clone(),
            part: layout.parts[index].name().to_owned().into(),
            offset: cursor.pos,
            received: 0,
            actual: 0,
        })?;
    end.checked_sub(cursor.pos + tail)
        .ok_or_else(|| length_error(layout, layout.parts[index].name(), end, cursor.pos + tail))
}

fn decode_word(
    layout: &FrameLayout,
    index: usize,
    word: &WordSpec,
    cursor: &mut Cursor<'_>,
    values: &mut FrameValues,
) -> Result<PartOutcome, DecodeError> {
    let rest = &cursor.bytes[cursor.pos..];
    let Some((value, used)) =
        decode_value(layout, &word.name, word.format, 0, 0, rest, cursor.pos)?
    else {
        return Ok(PartOutcome::Incomplete);
    };
    for bits in word.fields.iter() {
        check_bits(layout, bits, value, cursor.pos)?;
    }
    values.parts[index] = FieldValue {
        present: true,
        value,
        width: 0,
    };
    cursor.pos += used;
    Ok(PartOutcome::Done)
}

fn check_bits(
    layout: &FrameLayout,
    bits: &BitsSpec,
    word: u32,
    offset: usize,
) -> Result<(), DecodeError> {
    let value = (word & bits.mask()) >> bits.lsb;
    if bits.allowed.is_empty() || bits.allowed.contains(&value) {
        return Ok(());
    }
    Err(DecodeError::NotAllowed {
        layout: layout.name.clone(),
        part: bits.name.clone(),
        offset,
        value,
        format: Format::U8,
    })
}

fn decode_length(
    layout: &FrameLayout,
    index: usize,
    length: &LengthSpec,
    cursor: &mut Cursor<'_>,
    values: &mut FrameValues,
) -> Result<PartOutcome, DecodeError> {
    let rest = &cursor.bytes[cursor.pos..];
    let Some((value, used)) =
        decode_value(layout, &length.name, length.format, 0, 0, rest, cursor.pos)?
    else {
        return Ok(PartOutcome::Incomplete);
    };
    values.parts[index] = FieldValue {
        present: true,
        value,
        width: 0,
    };
    cursor.pos += used;
    if length.counts == Counts::DataSize {
        // A count beyond what a frame holds saturates (the reader refuses it).
        values.data_size = u8::try_from(
            value as usize * usize::from(length.per.max(1)) / usize::from(length.times.max(1)),
        )
        .unwrap_or(u8::MAX);
    }
    if let Counts::Parts { from, through } = length.counts {
        let bytes =
            value as usize * usize::from(length.per.max(1)) / usize::from(length.times.max(1));
        if usize::from(from) == index + 1 && usize::from(through) + 1 == layout.parts.len() {
            cursor.frame_end = Some(cursor.pos + bytes);
        } else if from == through {
            cursor.sized[usize::from(from)] = u16::try_from(bytes).unwrap_or(u16::MAX - 1);
        }
    }
    Ok(PartOutcome::Done)
}

fn decode_checksum(
    layout: &FrameLayout,
    index: usize,
    spec: &ChecksumSpec,
    cursor: &mut Cursor<'_>,
    starts: &[usize; MAX_PARTS],
    values: &mut FrameValues,
) -> Result<PartOutcome, DecodeError> {
    let bytes = cursor.bytes;
    let pos = cursor.pos;
    let rest = &bytes[pos..];
    let marker = &spec.marker[..];
    let compared = rest.len().min(marker.len());
    if rest[..compared] != marker[..compared] {
        if spec.optional {
            return Ok(PartOutcome::Done);
        }
        let at = mismatch_at(rest, marker);
        return Err(DecodeError::UnexpectedByte {
            layout: layout.name.clone(),
            part: spec.name.clone(),
            offset: pos + at,
            found: rest[at],
            expected: crate::error::describe_bytes(marker),
        });
    }
    if compared < marker.len() {
        return Ok(PartOutcome::Incomplete);
    }
    let value_at = pos + marker.len();
    let width = if spec.format == Format::Hex { 2 } else { 0 };
    let Some((received, used)) = decode_value(
        layout,
        &spec.name,
        spec.format,
        width,
        width,
        &bytes[value_at..],
        value_at,
    )?
    else {
        return Ok(PartOutcome::Incomplete);
    };
    // The end of the last covered part is where the next part starts.
    let covered_end = spec
        .covers_through
        .map_or(value_at, |through| starts[usize::from(through) + 1]);
    let computed = checksum::compute(
        spec.algorithm,
        &bytes[starts[usize::from(spec.covers_from)]..covered_end],
    );
    if computed != received {
        return Err(DecodeError::ChecksumMismatch {
            layout: layout.name.clone(),
            part: spec.name.clone(),
            offset: value_at,
            algorithm: spec.algorithm,
            computed,
            received,
        });
    }
    values.parts[index] = FieldValue {
        present: true,
        value: received,
        width: 0,
    };
    cursor.pos = value_at + used;
    Ok(PartOutcome::Done)
}

fn check_allowed(
    layout: &FrameLayout,
    field: &FieldSpec,
    value: u32,
    offset: usize,
) -> Result<(), DecodeError> {
    if field.allowed.is_empty() {
        return Ok(());
    }
    let fold = |v: u32| {
        if field.fold_case {
            u8::try_from(v).map_or(v, |b| u32::from(b.to_ascii_uppercase()))
        } else {
            v
        }
    };
    if field
        .allowed
        .iter()
        .any(|allowed| fold(*allowed) == fold(value))
    {
        return Ok(());
    }
    Err(DecodeError::NotAllowed {
        layout: layout.name.clone(),
        part: field.name.clone(),
        offset,
        value,
        format: field.format,
    })
}

/// Decodes one fixed-format or digit value; `None` means more bytes are needed.
fn decode_value(
    layout: &FrameLayout,
    name: &str,
    format: Format,
    min_width: u8,
    width: u8,
    rest: &[u8],
    offset: usize,
) -> Result<Option<(u32, usize)>, DecodeError> {
    let take = |n: usize| (rest.len() >= n).then(|| &rest[..n]);
    match format {
        Format::Decimal | Format::Hex => {
            let radix = if format == Format::Hex { 16 } else { 10 };
            let mut value: u32 = 0;
            let mut used = 0usize;
            while used < usize::from(width) {
                let Some(&byte) = rest.get(used) else {
                    return Ok(None);
                };
                let Some(digit) = (byte as char).to_digit(radix) else {
                    break;
                };
                value = value.wrapping_mul(radix).wrapping_add(digit);
                used += 1;
            }
            if used < usize::from(min_width) {
                return Err(DecodeError::UnexpectedByte {
                    layout: layout.name.clone(),
                    part: name.to_owned().into(),
                    offset: offset + used,
                    found: rest[used],
                    expected: format!(
                        "{} {} digit{}",
                        if min_width == width {
                            format!("{width}")
                        } else {
                            format!("{min_width} to {width}")
                        },
                        format.as_str(),
                        if width == 1 { "" } else { "s" }
                    ),
                });
            }
            Ok(Some((value, used)))
        }
        Format::Char | Format::U8 => Ok(take(1).map(|b| (u32::from(b[0]), 1))),
        Format::U16Be => Ok(take(2).map(|b| (u32::from(u16::from_be_bytes([b[0], b[1]])), 2))),
        Format::U16Le => Ok(take(2).map(|b| (u32::from(u16::from_le_bytes([b[0], b[1]])), 2))),
        Format::U32Be => Ok(take(4).map(|b| (u32::from_be_bytes([b[0], b[1], b[2], b[3]]), 4))),
        Format::U32Le => Ok(take(4).map(|b| (u32::from_le_bytes([b[0], b[1], b[2], b[3]]), 4))),
        Format::UintBe | Format::UintLe | Format::Bytes => Ok(None),
    }
}

fn mismatch_at(rest: &[u8], literal: &[u8]) -> usize {
    rest.iter()
        .zip(literal)
        .position(|(a, b)| a != b)
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{ChecksumAlgorithm, List};
    use std::borrow::Cow;

    fn toshiba_ascii_read() -> FrameLayout {
        FrameLayout {
            name: "read_request".into(),
            encoding: Encoding::Binary,
            plan: None,
            parts: List::Owned(vec![
                Part::Literal {
                    name: "start".into(),
                    bytes: Cow::Borrowed(b"("),
                    optional: false,
                },
                Part::Field(FieldSpec {
                    name: "address".into(),
                    role: Role::Address,
                    format: Format::Decimal,
                    width: 2,
                    min_width: 2,
                    optional: Some(Presence::IfFormatMatches),
                    allowed: Cow::Borrowed(&[]),
                    fold_case: false,
                    sized_by: crate::layout::SizedBy::Format,
                    broadcast: None,
                }),
                Part::Field(FieldSpec {
                    name: "command".into(),
                    role: Role::Command,
                    format: Format::Char,
                    width: 1,
                    min_width: 1,
                    optional: None,
                    allowed: Cow::Borrowed(&[b'R' as u32]),
                    fold_case: true,
                    sized_by: crate::layout::SizedBy::Format,
                    broadcast: None,
                }),
                Part::Field(FieldSpec {
                    name: "register".into(),
                    role: Role::Register,
                    format: Format::Hex,
                    width: 4,
                    min_width: 4,
                    optional: None,
                    allowed: Cow::Borrowed(&[]),
                    fold_case: false,
                    sized_by: crate::layout::SizedBy::Format,
                    broadcast: None,
                }),
                Part::Checksum(ChecksumSpec {
                    name: "sum".into(),
                    algorithm: ChecksumAlgorithm::Sum8,
                    format: Format::Hex,
                    marker: Cow::Borrowed(b"&"),
                    covers_from: 0,
                    covers_through: None,
                    optional: true,
                }),
                Part::Literal {
                    name: "end".into(),
                    bytes: Cow::Borrowed(b")"),
                    optional: true,
                },
                Part::Literal {
                    name: "cr".into(),
                    bytes: Cow::Borrowed(b"\r"),
                    optional: false,
                },
            ]),
        }
    }

    fn hex_field(name: &'static str, role: Role, width: u8) -> Part {
        Part::Field(FieldSpec {
            name: name.into(),
            role,
            format: Format::Hex,
            width,
            min_width: width,
            optional: None,
            allowed: Cow::Borrowed(&[]),
            fold_case: false,
            sized_by: crate::layout::SizedBy::Format,
            broadcast: None,
        })
    }

    /// An Eaton-style data reply: STX, station, data, a unit digit, ETX, then a sum that
    /// covers station through unit digit but not ETX (DV1 manual, 例三 step 4).
    fn etx_outside_the_sum(covers_through: Option<u8>) -> FrameLayout {
        FrameLayout {
            name: "data_reply".into(),
            encoding: Encoding::Binary,
            plan: None,
            parts: Cow::Owned(vec![
                Part::Literal {
                    name: "stx".into(),
                    bytes: Cow::Borrowed(b"\x02"),
                    optional: false,
                },
                hex_field("station", Role::Address, 2),
                hex_field("data", Role::Data, 4),
                hex_field("unit", Role::Index, 1),
                Part::Literal {
                    name: "etx".into(),
                    bytes: Cow::Borrowed(b"\x03"),
                    optional: false,
                },
                Part::Checksum(ChecksumSpec {
                    name: "sum".into(),
                    algorithm: ChecksumAlgorithm::Sum8,
                    format: Format::Hex,
                    marker: Cow::Borrowed(b""),
                    covers_from: 1,
                    covers_through,
                    optional: false,
                }),
                Part::Literal {
                    name: "cr".into(),
                    bytes: Cow::Borrowed(b"\r"),
                    optional: false,
                },
            ]),
        }
    }

    #[test]
    fn a_sum_may_stop_before_the_parts_ahead_of_it() {
        let frame = b"\x0200" as &[u8];
        let frame = [frame, b"17702\x0361\r"].concat();
        let layout = etx_outside_the_sum(Some(3));
        let DecodeStatus::Complete { values, len } = decode(&layout, &frame).unwrap() else {
            panic!("incomplete")
        };
        assert_eq!(len, frame.len());
        assert_eq!(values.get(&layout, Role::Data), Some(0x1770));
        let mut out = [0u8; 32];
        let n = encode(&layout, &values, &mut out).unwrap();
        assert_eq!(&out[..n], &frame[..]);
        // Summing through ETX as well gives 64h, not the 61h the manual prints.
        let error = decode(&etx_outside_the_sum(None), &frame).unwrap_err();
        assert_eq!(
            error.kind(),
            crate::error::DecodeErrorKind::ChecksumMismatch
        );
    }

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
    fn a_wrong_checksum_is_reported_with_both_values() {
        let layout = toshiba_ascii_read();
        let error = decode(&layout, b"(R0000&61)\r").unwrap_err();
        assert!(
            matches!(
                error,
                DecodeError::ChecksumMismatch {
                    computed: 0x60,
                    received: 0x61,
                    ..
                }
            ),
            "{error}"
        );
    }

    #[test]
    fn a_command_outside_the_allowed_set_is_rejected_at_its_offset() {
        let layout = toshiba_ascii_read();
        let error = decode(&layout, b"(X0000)\r").unwrap_err();
        assert!(
            matches!(error, DecodeError::NotAllowed { offset: 1, .. }),
            "{error}"
        );
    }

    /// A block-transfer reply: start, command, a count of words, a status byte, the words
    /// (each high byte first), a sum.
    fn block_reply() -> FrameLayout {
        let field = |name: &'static str, role: Role, format: Format| {
            Part::Field(FieldSpec {
                sized_by: if role == Role::Words {
                    SizedBy::Length
                } else {
                    SizedBy::Format
                },
                ..FieldSpec::new(name, role, format, 1)
            })
        };
        FrameLayout {
            name: "block_reply".into(),
            encoding: Encoding::Binary,
            plan: None,
            parts: List::Owned(vec![
                Part::literal("start", b"/"),
                field("command", Role::Command, Format::Char),
                Part::Length(
                    LengthSpec::new(
                        "count",
                        Format::U8,
                        Counts::Parts {
                            from: 4,
                            through: 4,
                        },
                    )
                    .with_ratio(1, 2),
                ),
                field("write_status", Role::WriteStatus, Format::U8),
                field("words", Role::Words, Format::U16Be),
                Part::Checksum(ChecksumSpec::new(
                    "sum",
                    ChecksumAlgorithm::Sum8,
                    Format::U8,
                    0,
                )),
            ]),
        }
    }

    #[test]
    fn a_words_field_holds_as_many_words_as_its_length_says() {
        let layout = block_reply();
        let frame = [
            0x2F, 0x59, 0x05, 0x00, 0x64, 0x00, 0x17, 0x70, 0x1A, 0x8A, 0x24, 0xFD, 0x00, 0x00,
            0x3D,
        ];
        for end in 0..frame.len() {
            assert_eq!(decode(&layout, &frame[..end]), Ok(DecodeStatus::Incomplete));
        }
        let DecodeStatus::Complete { values, len } = decode(&layout, &frame).unwrap() else {
            panic!("incomplete")
        };
        assert_eq!(len, frame.len());
        let words = values.words(&layout, &frame);
        assert_eq!(words.as_slice(), [0x6400, 0x1770, 0x1A8A, 0x24FD, 0x0000]);
        assert_eq!(values.get(&layout, Role::WriteStatus), Some(0));
        // Encoding computes the count from the words.
        let mut built = FrameValues::default();
        built.set(&layout, Role::Command, u32::from(b'Y'));
        built.set(&layout, Role::WriteStatus, 0);
        let mut out = [0u8; 32];
        let n = encode_with_payload(&layout, &built, &words.payload(&layout), &mut out).unwrap();
        assert_eq!(&out[..n], &frame[..]);
        // No words at all: a count of 0.
        let empty = [0x2F, 0x59, 0x00, 0x00, 0x88];
        let DecodeStatus::Complete { values, .. } = decode(&layout, &empty).unwrap() else {
            panic!("incomplete")
        };
        assert!(values.words(&layout, &empty).as_slice().is_empty());
    }

    #[test]
    fn a_words_field_of_half_a_word_is_refused() {
        // A count is in words here, so a half word cannot arise from it: a length counting
        // bytes can.
        let mut layout = block_reply();
        if let Part::Length(length) = &mut layout.parts.to_mut()[2] {
            length.per = 1;
        }
        let error = decode(&layout, &[0x2F, 0x59, 0x03, 0x00, 0x01, 0x02, 0x03, 0x00]).unwrap_err();
        assert_eq!(error.kind(), crate::error::DecodeErrorKind::LengthMismatch);
    }

    #[test]
    fn a_value_too_wide_for_its_digits_is_refused() {
        let layout = toshiba_ascii_read();
        let mut values = FrameValues::default();
        values.set(&layout, Role::Command, u32::from(b'R'));
        values.set(&layout, Role::Register, 0x1_0000);
        let error = encode(&layout, &values, &mut [0u8; 32]).unwrap_err();
        assert!(matches!(error, EncodeError::ValueTooWide { .. }), "{error}");
    }

    /// Modbus ASCII's write-register frame: ":", address, function, register, data, LRC, CR LF.
    fn hex_pairs_write() -> FrameLayout {
        let field = |name: &'static str, role, format, width| {
            Part::Field(FieldSpec {
                name: name.into(),
                role,
                format,
                width,
                min_width: width,
                optional: None,
                allowed: Cow::Borrowed(&[]),
                fold_case: false,
                sized_by: crate::layout::SizedBy::Format,
                broadcast: None,
            })
        };
        let literal = |name: &'static str, bytes: &'static [u8]| Part::Literal {
            name: name.into(),
            bytes: Cow::Borrowed(bytes),
            optional: false,
        };
        FrameLayout {
            name: "write_register".into(),
            encoding: Encoding::HexPairs,
            plan: None,
            parts: Cow::Owned(vec![
                literal("start", b":"),
                field("address", Role::Address, Format::U8, 1),
                field("function", Role::Command, Format::U8, 1),
                field("register", Role::Register, Format::U16Be, 2),
                field("data", Role::Data, Format::U16Be, 2),
                Part::Checksum(ChecksumSpec {
                    name: "lrc".into(),
                    algorithm: ChecksumAlgorithm::Lrc8,
                    format: Format::U8,
                    marker: Cow::Borrowed(b""),
                    covers_from: 1,
                    covers_through: None,
                    optional: false,
                }),
                literal("end", b"\r\n"),
            ]),
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
