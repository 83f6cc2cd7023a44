//! [`Encoder`]: the encoding state of one frame, which a plan's steps write part by part.

use super::fixed;
use crate::checksum;
use crate::layout::{checksum_size, BitsSpec, BroadcastAddress, Counts, Format, Roles, MAX_PARTS};
use crate::layout::{ChecksumStep, FieldStep, LengthStep};

/// Encoding state of one frame: a plan's steps write it part by part, then fill in its
/// lengths and checksums. Like [`Decoder`](super::Decoder), shared by plans run step by step and the
/// generator's compiled plans; each method returns `None` when the interpreter is to
/// write the frame instead (a value too wide for its field, `out` too small).
#[derive(Debug)]
pub struct Encoder<'o> {
    out: &'o mut [u8],
    pos: usize,
    starts: [usize; MAX_PARTS],
    ends: [usize; MAX_PARTS],
}

impl<'o> Encoder<'o> {
    /// Starts writing a frame into `out`.
    #[inline(always)]
    pub fn new(out: &'o mut [u8]) -> Encoder<'o> {
        Encoder {
            out,
            pos: 0,
            starts: [0; MAX_PARTS],
            ends: [0; MAX_PARTS],
        }
    }

    /// Part `index` spans from `start` to the current position.
    #[inline(always)]
    fn span(&mut self, index: usize, start: usize) -> Option<()> {
        *self.starts.get_mut(index)? = start;
        *self.ends.get_mut(index)? = self.pos;
        Some(())
    }

    /// Part `index` is the literal `bytes`, written when `present`.
    #[inline(always)]
    pub fn literal(&mut self, index: usize, bytes: &[u8], present: bool) -> Option<()> {
        let start = self.pos;
        if present {
            self.pos = put(self.out, start, bytes)?;
        }
        self.span(index, start)
    }

    /// Part `index` is a field holding `value` (0 when `None`), written when `present`;
    /// `broadcast`: the part has broadcast encodings.
    #[inline(always)]
    pub fn field(
        &mut self,
        index: usize,
        step: FieldStep,
        value: Option<u32>,
        present: bool,
        data_size: u8,
        broadcast: bool,
    ) -> Option<()> {
        let start = self.pos;
        if present {
            let value = value.unwrap_or(0);
            let width = match step.format {
                Format::UintBe | Format::UintLe if data_size != 0 => data_size,
                _ => step.width,
            };
            if broadcast && BroadcastAddress::is_open(value) {
                return None;
            }
            self.pos = put_value(self.out, start, step.format, value, width)?;
        }
        self.span(index, start)
    }

    /// Part `index` is a word of the bit fields `bits`, holding the values `roles` gives.
    #[inline(always)]
    pub fn word(
        &mut self,
        index: usize,
        format: Format,
        bits: &[BitsSpec],
        roles: &Roles,
    ) -> Option<()> {
        let start = self.pos;
        let mut value = 0u32;
        for bits in bits {
            if let Some(field) = roles.value(bits.role) {
                value = (value & !bits.mask()) | ((field << bits.lsb) & bits.mask());
            }
        }
        self.pos = put_value(self.out, start, format, value, 0)?;
        self.span(index, start)
    }

    /// Part `index` is a length in `format`, filled in by [`Encoder::fill_length`].
    #[inline(always)]
    pub fn length(&mut self, index: usize, format: Format) -> Option<()> {
        let start = self.pos;
        self.pos = put(self.out, start, &[0; 4][..usize::from(fixed(format)?)])?;
        self.span(index, start)
    }

    /// Part `index` is a checksum announced by `marker`, written when `present` and filled
    /// in by [`Encoder::fill_checksum`].
    #[inline(always)]
    pub fn checksum(
        &mut self,
        index: usize,
        step: ChecksumStep,
        marker: &[u8],
        present: bool,
    ) -> Option<()> {
        let start = self.pos;
        if present {
            self.pos = put(self.out, start, marker)?;
            self.pos = put(self.out, self.pos, &[0; 2][..checksum_size(step.format)])?;
        }
        self.span(index, start)
    }

    /// Fills in the length at `index`.
    #[inline(always)]
    pub fn fill_length(&mut self, index: usize, step: LengthStep, data_size: u8) -> Option<()> {
        let counted = match step.counts {
            Counts::Parts { from, through } => self
                .ends
                .get(usize::from(through))?
                .checked_sub(*self.starts.get(usize::from(from))?)?,
            Counts::DataSize => usize::from(data_size),
        };
        let value = (counted * usize::from(step.times) / usize::from(step.per.max(1))) as u32;
        put_value(self.out, *self.starts.get(index)?, step.format, value, 0).map(|_| ())
    }

    /// Fills in the checksum at `index`, whose marker is `marker_len` bytes long.
    #[inline(always)]
    pub fn fill_checksum(
        &mut self,
        index: usize,
        step: ChecksumStep,
        marker_len: usize,
    ) -> Option<()> {
        let (start, end) = (*self.starts.get(index)?, *self.ends.get(index)?);
        if start == end {
            return Some(());
        }
        let value_at = start + marker_len;
        let covered_end = match step.covers_through {
            Some(through) => *self.ends.get(usize::from(through))?,
            None => value_at,
        };
        let from = *self.starts.get(usize::from(step.covers_from))?;
        let sum = checksum::compute(step.algorithm, self.out.get(from..covered_end)?);
        put_value(self.out, value_at, step.format, sum, 2).map(|_| ())
    }

    /// The frame's length.
    #[inline(always)]
    pub fn finish(self) -> usize {
        self.pos
    }
}

/// Writes `bytes` at `at`; the position after them.
#[inline(always)]
fn put(out: &mut [u8], at: usize, bytes: &[u8]) -> Option<usize> {
    let end = at + bytes.len();
    out.get_mut(at..end)?.copy_from_slice(bytes);
    Some(end)
}

/// Writes `value` in `format` at `at` (`width`: digits, or bytes of `uint_be`/`uint_le`);
/// `None` when it does not fit the format or `out`.
#[inline(always)]
fn put_value(out: &mut [u8], at: usize, format: Format, value: u32, width: u8) -> Option<usize> {
    match format {
        Format::Decimal | Format::Hex => {
            let radix: u32 = if format == Format::Hex { 16 } else { 10 };
            let width = usize::from(width);
            if width == 0 || width > 10 {
                return None;
            }
            let slots = out.get_mut(at..at + width)?;
            let mut rest = value;
            for slot in slots.iter_mut().rev() {
                let digit = (rest % radix) as u8;
                *slot = if digit < 10 {
                    b'0' + digit
                } else {
                    b'A' + digit - 10
                };
                rest /= radix;
            }
            (rest == 0).then_some(at + width)
        }
        Format::Char | Format::U8 => put(out, at, &[u8::try_from(value).ok()?]),
        Format::U16Be => put(out, at, &u16::try_from(value).ok()?.to_be_bytes()),
        Format::U16Le => put(out, at, &u16::try_from(value).ok()?.to_le_bytes()),
        Format::U32Be => put(out, at, &value.to_be_bytes()),
        Format::U32Le => put(out, at, &value.to_le_bytes()),
        Format::UintBe | Format::UintLe => {
            let width = usize::from(width);
            if width == 0 || width > 4 || (width < 4 && value >> (8 * width) != 0) {
                return None;
            }
            let be = value.to_be_bytes();
            let mut bytes = [0u8; 4];
            bytes[..width].copy_from_slice(&be[4 - width..]);
            if format == Format::UintLe {
                bytes[..width].reverse();
            }
            put(out, at, &bytes[..width])
        }
        Format::Bytes => None,
    }
}
