//! Decoding the parts that check or describe others: bit words, lengths and checksums.

use super::cursor::{mismatch_at, Cursor, PartOutcome};
use super::decode_fields::decode_value;
use crate::checksum;
use crate::error::DecodeError;
use crate::layout::{
    BitsSpec, ChecksumSpec, Counts, FieldValue, Format, FrameLayout, FrameValues, LengthSpec,
    WordSpec, MAX_PARTS,
};

pub(super) fn decode_word(
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

pub(super) fn decode_length(
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

pub(super) fn decode_checksum(
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
