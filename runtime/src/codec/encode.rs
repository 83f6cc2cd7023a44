//! Encoding a frame: parts written, lengths filled in, then checksums computed.

use super::hex::{digit_radix, hex_expand, MAX_HEX_FRAME};
use crate::checksum;
use crate::error::EncodeError;
use crate::layout::{
    checksum_size, BroadcastAddress, Counts, Encoding, FieldSpec, FieldValue, Format, FrameLayout,
    FrameValues, Part, Role, MAX_PARTS,
};

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::codec::sample_layouts::*;
    use crate::layout::*;

    #[test]
    fn a_value_too_wide_for_its_digits_is_refused() {
        let layout = toshiba_ascii_read();
        let mut values = FrameValues::default();
        values.set(&layout, Role::Command, u32::from(b'R'));
        values.set(&layout, Role::Register, 0x1_0000);
        let error = encode(&layout, &values, &mut [0u8; 32]).unwrap_err();
        assert!(matches!(error, EncodeError::ValueTooWide { .. }), "{error}");
    }
}
