//! Decoding fields: fixed and open digits, binary numbers, bytes and words, each checked
//! against its allowed values.

use super::cursor::{length_error, Cursor, PartOutcome};
use super::hex::digit_radix;
use crate::error::DecodeError;
use crate::layout::{
    BroadcastAddress, FieldSpec, FieldValue, Format, FrameLayout, FrameValues, Presence, Role,
    SizedBy,
};

pub(super) fn decode_field(
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
pub(super) fn decode_value(
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
