//! Encodes and decodes frames by interpreting a [`FrameLayout`], without heap allocation.
//!
//! Decoding distinguishes three outcomes: a complete frame, "more bytes needed"
//! ([`DecodeStatus::Incomplete`]) and a [`DecodeError`] that says which part, at which
//! offset, did not fit. The transaction engine relies on that difference to wait for the
//! rest of a reply without waiting on garbage.

use crate::checksum;
use crate::error::{DecodeError, EncodeError};
use crate::layout::{
    ChecksumSpec, FieldSpec, Format, FrameLayout, Part, Presence, Role, MAX_PARTS,
};

/// The value of one part of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FieldValue {
    /// Whether the part is in the frame (always true for required parts after decoding).
    pub present: bool,
    /// The value: a field's number, a checksum's received value; 0 for literals.
    pub value: u32,
    /// Digits used on the wire for digit formats; 0 means the layout's width.
    pub width: u8,
}

/// Values of every part of one frame, indexed like the layout's parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameValues {
    /// One slot per layout part.
    pub parts: [FieldValue; MAX_PARTS],
}

impl FrameValues {
    /// Sets the field with `role` to `value` and marks it present. Returns false when the
    /// layout has no such field.
    pub fn set(&mut self, layout: &FrameLayout, role: Role, value: u32) -> bool {
        match layout.index_of(role) {
            Some(index) => {
                self.parts[index].present = true;
                self.parts[index].value = value;
                true
            }
            None => false,
        }
    }

    /// The value of the field with `role`, when the layout has it and the frame carries it.
    pub fn get(&self, layout: &FrameLayout, role: Role) -> Option<u32> {
        let index = layout.index_of(role)?;
        let slot = self.parts[index];
        slot.present.then_some(slot.value)
    }

    /// Marks every optional part named in `names` present (e.g. `["sum", "end"]`).
    pub fn include(&mut self, layout: &FrameLayout, names: &[&str]) {
        for (index, part) in layout.parts.iter().enumerate() {
            if names.iter().any(|name| *name == part.name()) {
                self.parts[index].present = true;
            }
        }
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

/// Encodes a frame into `out`, returning the number of bytes written.
///
/// Required parts are always written; optional ones only when their slot in `values` is
/// marked present. Checksums are computed.
pub fn encode(
    layout: &FrameLayout,
    values: &FrameValues,
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
    let mut part_offsets = [0usize; MAX_PARTS];
    for (index, part) in layout.parts.iter().enumerate() {
        part_offsets[index] = writer.len;
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
                if field.optional.is_some() && !slot.present {
                    continue;
                }
                encode_field(&mut writer, field, slot)?;
            }
            Part::Checksum(spec) => {
                if spec.optional && !slot.present {
                    continue;
                }
                writer.put(&spec.marker)?;
                let from = part_offsets[usize::from(spec.covers_from)];
                let sum = checksum::compute(spec.algorithm, &writer.out[from..writer.len]);
                let width = match spec.format {
                    Format::Hex => 2,
                    _ => 0,
                };
                writer.put_value(&spec.name, spec.format, sum, width)?;
            }
        }
    }
    Ok(writer.len)
}

fn encode_field(
    writer: &mut Writer<'_, '_>,
    field: &FieldSpec,
    slot: FieldValue,
) -> Result<(), EncodeError> {
    let width = if slot.width == 0 {
        field.width
    } else {
        slot.width
    };
    writer.put_value(&field.name, field.format, slot.value, width)
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
            Format::U16Be => {
                let word = u16::try_from(value).map_err(|_| too_wide())?;
                self.put(&word.to_be_bytes())
            }
            Format::U16Le => {
                let word = u16::try_from(value).map_err(|_| too_wide())?;
                self.put(&word.to_le_bytes())
            }
        }
    }
}

/// Decodes one frame that starts at `bytes[0]`.
///
/// Returns [`DecodeStatus::Incomplete`] while `bytes` is a proper prefix of a frame that
/// fits the layout, and an error as soon as a byte cannot belong to one.
pub fn decode(layout: &FrameLayout, bytes: &[u8]) -> Result<DecodeStatus, DecodeError> {
    let mut values = FrameValues::default();
    let mut part_offsets = [0usize; MAX_PARTS];
    let mut pos = 0usize;
    for (index, part) in layout.parts.iter().enumerate().take(MAX_PARTS) {
        part_offsets[index] = pos;
        let rest = &bytes[pos..];
        match part {
            Part::Literal {
                bytes: literal,
                optional,
                name,
            } => {
                let compared = rest.len().min(literal.len());
                if rest[..compared] != literal[..compared] {
                    if *optional {
                        continue;
                    }
                    return Err(DecodeError::UnexpectedByte {
                        layout: layout.name.clone(),
                        part: name.clone(),
                        offset: pos + mismatch_at(rest, literal),
                        found: rest[mismatch_at(rest, literal)],
                        expected: describe_literal(literal),
                    });
                }
                if compared < literal.len() {
                    return Ok(DecodeStatus::Incomplete);
                }
                values.parts[index].present = true;
                pos += literal.len();
            }
            Part::Field(field) => {
                if let Some(presence) = field.optional {
                    let Some(&next) = rest.first() else {
                        return Ok(DecodeStatus::Incomplete);
                    };
                    let present = match presence {
                        Presence::IfFormatMatches => field.format.accepts_digit(next),
                        Presence::IfByteAtMost(limit) => next <= limit,
                    };
                    if !present {
                        continue;
                    }
                }
                match decode_value(
                    layout,
                    &field.name,
                    field.format,
                    field.min_width,
                    field.width,
                    rest,
                    pos,
                )? {
                    None => return Ok(DecodeStatus::Incomplete),
                    Some((value, used)) => {
                        check_allowed(layout, field, value, pos)?;
                        values.parts[index] = FieldValue {
                            present: true,
                            value,
                            width: if field.format.is_digits() {
                                used as u8
                            } else {
                                0
                            },
                        };
                        pos += used;
                    }
                }
            }
            Part::Checksum(spec) => match decode_checksum(layout, spec, bytes, pos, &part_offsets)?
            {
                ChecksumOutcome::Absent => continue,
                ChecksumOutcome::Incomplete => return Ok(DecodeStatus::Incomplete),
                ChecksumOutcome::Present { value, end } => {
                    values.parts[index] = FieldValue {
                        present: true,
                        value,
                        width: 0,
                    };
                    pos = end;
                }
            },
        }
    }
    Ok(DecodeStatus::Complete { values, len: pos })
}

enum ChecksumOutcome {
    Absent,
    Incomplete,
    Present { value: u32, end: usize },
}

fn decode_checksum(
    layout: &FrameLayout,
    spec: &ChecksumSpec,
    bytes: &[u8],
    pos: usize,
    part_offsets: &[usize; MAX_PARTS],
) -> Result<ChecksumOutcome, DecodeError> {
    let rest = &bytes[pos..];
    let marker = &spec.marker[..];
    let compared = rest.len().min(marker.len());
    if rest[..compared] != marker[..compared] {
        if spec.optional {
            return Ok(ChecksumOutcome::Absent);
        }
        let at = mismatch_at(rest, marker);
        return Err(DecodeError::UnexpectedByte {
            layout: layout.name.clone(),
            part: spec.name.clone(),
            offset: pos + at,
            found: rest[at],
            expected: describe_literal(marker),
        });
    }
    if compared < marker.len() {
        return Ok(ChecksumOutcome::Incomplete);
    }
    if spec.optional && rest.is_empty() && marker.is_empty() {
        return Ok(ChecksumOutcome::Incomplete);
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
        return Ok(ChecksumOutcome::Incomplete);
    };
    let from = part_offsets[usize::from(spec.covers_from)];
    let computed = checksum::compute(spec.algorithm, &bytes[from..value_at]);
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
    Ok(ChecksumOutcome::Present {
        value: received,
        end: value_at + used,
    })
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

/// Decodes one value; `None` means more bytes are needed.
fn decode_value(
    layout: &FrameLayout,
    name: &str,
    format: Format,
    min_width: u8,
    width: u8,
    rest: &[u8],
    offset: usize,
) -> Result<Option<(u32, usize)>, DecodeError> {
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
                value = value * radix + digit;
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
        Format::Char | Format::U8 => Ok(rest.first().map(|b| (u32::from(*b), 1))),
        Format::U16Be => {
            Ok((rest.len() >= 2).then(|| (u32::from(u16::from_be_bytes([rest[0], rest[1]])), 2)))
        }
        Format::U16Le => {
            Ok((rest.len() >= 2).then(|| (u32::from(u16::from_le_bytes([rest[0], rest[1]])), 2)))
        }
    }
}

fn mismatch_at(rest: &[u8], literal: &[u8]) -> usize {
    rest.iter()
        .zip(literal)
        .position(|(a, b)| a != b)
        .unwrap_or(0)
}

fn describe_literal(literal: &[u8]) -> String {
    crate::error::describe_bytes(literal)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{ChecksumAlgorithm, List};
    use std::borrow::Cow;

    fn toshiba_ascii_read() -> FrameLayout {
        FrameLayout {
            name: "read_request".into(),
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
                }),
                Part::Checksum(ChecksumSpec {
                    name: "sum".into(),
                    algorithm: ChecksumAlgorithm::Sum8,
                    format: Format::Hex,
                    marker: Cow::Borrowed(b"&"),
                    covers_from: 0,
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
