//! [`Decoder`]: the decoding state of one frame, which a plan's steps advance part by part.

use crate::checksum;
use crate::layout::{
    BitsSpec, BroadcastAddress, Counts, FieldValue, Format, FrameValues, Presence, Role, Roles,
    MAX_PARTS,
};
use crate::layout::{ChecksumStep, FieldStep, LengthStep, PlannedFrame};

/// Decoding state of one frame: what a plan's steps read so far. Each method runs one
/// step at the current position and returns `None` when the frame is not one the plan
/// decodes (the interpreter then takes it); a plan run step by step and the generator's
/// compiled plans call the same methods, so the two decode alike.
#[derive(Debug)]
pub struct Decoder<'b> {
    bytes: &'b [u8],
    pos: usize,
    values: FrameValues,
    roles: Roles,
    starts: [usize; MAX_PARTS],
    ends: [usize; MAX_PARTS],
    sized: [u16; MAX_PARTS],
    frame_end: usize,
}

impl<'b> Decoder<'b> {
    /// Starts decoding a frame at `bytes[0]`.
    #[inline(always)]
    pub fn new(bytes: &'b [u8]) -> Decoder<'b> {
        Decoder {
            bytes,
            pos: 0,
            values: FrameValues::default(),
            roles: Roles::default(),
            starts: [0; MAX_PARTS],
            ends: [0; MAX_PARTS],
            sized: [u16::MAX; MAX_PARTS],
            frame_end: usize::MAX,
        }
    }

    /// The bytes from the current position.
    #[inline(always)]
    fn rest(&self) -> &'b [u8] {
        self.bytes.get(self.pos..).unwrap_or(&[])
    }

    /// Ends part `index` at the current position.
    #[inline(always)]
    fn end(&mut self, index: usize) -> Option<()> {
        *self.ends.get_mut(index)? = self.pos;
        (self.pos <= self.frame_end).then_some(())
    }

    /// Part `index` is the literal `literal`.
    #[inline(always)]
    pub fn literal(&mut self, index: usize, literal: &[u8], optional: bool) -> Option<()> {
        *self.starts.get_mut(index)? = self.pos;
        let rest = self.rest();
        if rest.starts_with(literal) {
            self.values.parts.get_mut(index)?.present = true;
            self.pos += literal.len();
        } else if !optional || literal.starts_with(rest) {
            return None;
        }
        self.end(index)
    }

    /// Part `index` is a field: `allowed`, `fold_case` and `broadcast` are the part's.
    #[inline(always)]
    pub fn field(
        &mut self,
        index: usize,
        step: FieldStep,
        allowed: &[u32],
        fold_case: bool,
        broadcast: Option<&BroadcastAddress>,
    ) -> Option<()> {
        *self.starts.get_mut(index)? = self.pos;
        let rest = self.rest();
        let format = step.format;
        if let Some(presence) = step.optional {
            let &next = rest.first()?;
            let present = match presence {
                Presence::IfFormatMatches => format.accepts_digit(next),
                Presence::IfByteAtMost(limit) => next <= limit,
            } || broadcast.is_some_and(|b| b.starts_with(next));
            if !present {
                return self.end(index);
            }
        }
        if step.open_digits {
            let broadcast = broadcast?;
            let all: &[u8] = &broadcast.all_bytes;
            if !all.is_empty() && !rest.is_empty() {
                let compared = rest.len().min(all.len());
                if rest[..compared] == all[..compared] {
                    return None;
                }
            }
            if let Some(wildcard) = broadcast.wildcard {
                if rest[..rest.len().min(usize::from(step.width))].contains(&wildcard) {
                    return None;
                }
            }
        }
        let (value, used, slot_width) = match format {
            Format::UintBe | Format::UintLe => {
                let size = if step.by_length {
                    let size = *self.sized.get(index)?;
                    if size == u16::MAX {
                        return None;
                    }
                    usize::from(size)
                } else {
                    usize::from(step.width)
                };
                if size < usize::from(step.min_width) || size > 4 {
                    return None;
                }
                let held = rest.get(..size)?;
                let value = if format == Format::UintLe {
                    held.iter()
                        .rev()
                        .fold(0u32, |acc, b| (acc << 8) | u32::from(*b))
                } else {
                    held.iter().fold(0u32, |acc, b| (acc << 8) | u32::from(*b))
                };
                if step.role == Role::Data {
                    self.values.data_size = size as u8;
                }
                (value, size, size as u8)
            }
            Format::Decimal | Format::Hex => {
                let (value, used) = digits(format, step.min_width, step.width, rest)?;
                (value, used, used as u8)
            }
            _ => {
                let (value, used) = binary(format, rest)?;
                (value, used, 0)
            }
        };
        // A station with the open-digits flag is a broadcast's, never a reply's: the
        // interpreter's callers decide about it.
        if (step.checked && !allowed_value(allowed, fold_case, value))
            || (step.role == Role::Address && BroadcastAddress::is_open(value))
        {
            return None;
        }
        *self.values.parts.get_mut(index)? = FieldValue {
            present: true,
            value,
            width: slot_width,
        };
        if let Some(target) = self.roles.slot(step.role) {
            *target = Some(value);
        }
        self.pos += used;
        self.end(index)
    }

    /// Part `index` is a word of the bit fields `bits`.
    #[inline(always)]
    pub fn word(&mut self, index: usize, format: Format, bits: &[BitsSpec]) -> Option<()> {
        *self.starts.get_mut(index)? = self.pos;
        let (value, used) = binary(format, self.rest())?;
        for bits in bits {
            let field = (value & bits.mask()) >> bits.lsb;
            if !bits.allowed.is_empty() && !bits.allowed.contains(&field) {
                return None;
            }
            if let Some(target) = self.roles.slot(bits.role) {
                *target = Some(field);
            }
        }
        *self.values.parts.get_mut(index)? = FieldValue {
            present: true,
            value,
            width: 0,
        };
        self.pos += used;
        self.end(index)
    }

    /// Part `index` (of `count` parts) is a length.
    #[inline(always)]
    pub fn length(&mut self, index: usize, step: LengthStep, count: usize) -> Option<()> {
        *self.starts.get_mut(index)? = self.pos;
        let (value, used) = binary(step.format, self.rest())?;
        *self.values.parts.get_mut(index)? = FieldValue {
            present: true,
            value,
            width: 0,
        };
        self.pos += used;
        let counted =
            value as usize * usize::from(step.per.max(1)) / usize::from(step.times.max(1));
        match step.counts {
            Counts::DataSize => {
                self.values.data_size = u8::try_from(counted).unwrap_or(u8::MAX);
            }
            Counts::Parts { from, through } => {
                if usize::from(from) == index + 1 && usize::from(through) + 1 == count {
                    self.frame_end = self.pos + counted;
                } else if from == through {
                    *self.sized.get_mut(usize::from(from))? =
                        u16::try_from(counted).unwrap_or(u16::MAX - 1);
                }
            }
        }
        self.end(index)
    }

    /// Part `index` is a checksum announced by `marker`.
    #[inline(always)]
    pub fn checksum(&mut self, index: usize, step: ChecksumStep, marker: &[u8]) -> Option<()> {
        *self.starts.get_mut(index)? = self.pos;
        let rest = self.rest();
        if !rest.starts_with(marker) {
            if step.optional && !marker.starts_with(rest) {
                return self.end(index);
            }
            return None;
        }
        let value_at = self.pos + marker.len();
        let after = self.bytes.get(value_at..)?;
        let (received, used) = if step.format == Format::Hex {
            digits(Format::Hex, 2, 2, after)?
        } else {
            binary(step.format, after)?
        };
        let covered_end = match step.covers_through {
            Some(through) => *self.starts.get(usize::from(through) + 1)?,
            None => value_at,
        };
        let from = *self.starts.get(usize::from(step.covers_from))?;
        if checksum::compute(step.algorithm, self.bytes.get(from..covered_end)?) != received {
            return None;
        }
        *self.values.parts.get_mut(index)? = FieldValue {
            present: true,
            value: received,
            width: 0,
        };
        self.pos = value_at + used;
        self.end(index)
    }

    /// After the last part: the length at `index` counted what the frame holds.
    #[inline(always)]
    pub fn check_length(&self, index: usize, step: LengthStep) -> Option<()> {
        if let Counts::Parts { from, through } = step.counts {
            let counted = self
                .ends
                .get(usize::from(through))?
                .checked_sub(*self.starts.get(usize::from(from))?)?;
            let expected =
                (counted * usize::from(step.times) / usize::from(step.per.max(1))) as u32;
            if self.values.parts.get(index)?.value != expected {
                return None;
            }
        }
        Some(())
    }

    /// The decoded frame.
    #[inline(always)]
    pub fn finish(self) -> PlannedFrame {
        PlannedFrame {
            values: self.values,
            roles: self.roles,
            len: self.pos,
        }
    }
}

/// Whether `value` is among `allowed`, ASCII case folded when `fold_case` says so.
#[inline(always)]
fn allowed_value(allowed: &[u32], fold_case: bool, value: u32) -> bool {
    let fold = |v: u32| {
        if fold_case {
            u8::try_from(v).map_or(v, |b| u32::from(b.to_ascii_uppercase()))
        } else {
            v
        }
    };
    allowed.is_empty() || allowed.iter().any(|a| fold(*a) == fold(value))
}

/// `min_width..=width` digits of `format` at the start of `rest`: the value and the digits
/// used. `None` when more bytes are needed or too few digits are there.
#[inline(always)]
fn digits(format: Format, min_width: u8, width: u8, rest: &[u8]) -> Option<(u32, usize)> {
    let radix = if format == Format::Hex { 16 } else { 10 };
    let mut value: u32 = 0;
    let mut used = 0usize;
    while used < usize::from(width) {
        let &byte = rest.get(used)?;
        let Some(digit) = (byte as char).to_digit(radix) else {
            break;
        };
        value = value.wrapping_mul(radix).wrapping_add(digit);
        used += 1;
    }
    (used >= usize::from(min_width)).then_some((value, used))
}

/// A fixed binary value at the start of `rest`: the value and its byte count.
#[inline(always)]
fn binary(format: Format, rest: &[u8]) -> Option<(u32, usize)> {
    Some(match format {
        Format::Char | Format::U8 => (u32::from(*rest.first()?), 1),
        Format::U16Be => (u32::from(u16::from_be_bytes(*rest.first_chunk()?)), 2),
        Format::U16Le => (u32::from(u16::from_le_bytes(*rest.first_chunk()?)), 2),
        Format::U32Be => (u32::from_be_bytes(*rest.first_chunk()?), 4),
        Format::U32Le => (u32::from_le_bytes(*rest.first_chunk()?), 4),
        _ => return None,
    })
}
