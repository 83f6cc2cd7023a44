//! Frame plans: a layout's parts reduced, once, to the steps a fast encoder and decoder run.
//!
//! The interpreter in [`crate::codec`] handles every layout a description can state, and
//! explains every frame that does not fit. A [`FramePlan`] covers the layouts most frames
//! use (binary layouts whose parts are literals, fixed-format or digit fields, words,
//! lengths and checksums, optional parts included) and only the frames that fit: it returns
//! `None` for anything else (a frame not complete yet, a wrong byte, a checksum that does
//! not match, a broadcast station written with open digits, a block of registers), and the
//! caller then runs the interpreter, which says what is wrong. When a plan does return a
//! frame, it is the frame the interpreter returns for the same bytes, value for value: the
//! differential tests (`tests/tests/fast_path.rs`) and the `plan_agreement` fuzz target
//! hold the two to that.
//!
//! The generator computes each layout's plan at build time ([`FramePlan::of`]) and writes it
//! into the generated layout as const data; a description loaded at run time gets its
//! plans from the same function. [`crate::Protocol`] uses them in
//! [`crate::Protocol::encode_request`], [`crate::Protocol::decode_reply`],
//! [`crate::Protocol::find_reply`] and [`crate::Protocol::search_reply`].

use crate::checksum;
use crate::codec::{FieldValue, FrameValues, Roles};
use crate::layout::{
    checksum_size, BroadcastAddress, ChecksumAlgorithm, Counts, Encoding, Format, FrameLayout,
    List, Part, Presence, Role, SizedBy, MAX_PARTS,
};

/// The steps of one layout, one per part, in wire order (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FramePlan {
    /// One step per part of the layout, at the part's index.
    pub steps: List<Step>,
}

/// What a plan does for one part. Lists (literal bytes, allowed values, bit fields,
/// markers) stay in the layout's part; a step holds what the fast path decides on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Step {
    /// Fixed bytes (the part's).
    Literal {
        /// Present on decode only when the next bytes equal them; on encode only when named
        /// among the protocol's default optional parts.
        optional: bool,
    },
    /// A value field.
    Field {
        /// What it means.
        role: Role,
        /// Wire format: a digit format, a fixed binary format, or `uint_be`/`uint_le`.
        format: Format,
        /// Digits or bytes written (and the most digits read).
        width: u8,
        /// The fewest digits read.
        min_width: u8,
        /// How a decoder tells it is there, when it may be left out.
        optional: Option<Presence>,
        /// Sized by the length part that covers it alone (a Modbus byte count).
        by_length: bool,
        /// The part lists the values it accepts.
        checked: bool,
        /// The part has broadcast encodings with open digits (`**`, `*9`): frames holding
        /// one go to the interpreter.
        open_digits: bool,
    },
    /// A word of bit fields, in a fixed binary format.
    Word {
        /// `u16be`, `u16le`, `u32be` or `u32le`.
        format: Format,
    },
    /// A computed length, in a fixed binary format.
    Length {
        /// `u8` or `u16be`.
        format: Format,
        /// What it counts.
        counts: Counts,
        /// See [`crate::LengthSpec::times`].
        times: u8,
        /// See [`crate::LengthSpec::per`].
        per: u8,
    },
    /// A checksum over earlier parts.
    Checksum {
        /// The algorithm.
        algorithm: ChecksumAlgorithm,
        /// `hex` (two digits) or a fixed binary format.
        format: Format,
        /// First part covered.
        covers_from: u8,
        /// Last part covered, when coverage stops before the checksum.
        covers_through: Option<u8>,
        /// May be left out (present when its marker is there).
        optional: bool,
    },
}

/// A frame decoded by a plan: what [`crate::codec::decode`] returns for it, with its
/// roles gathered as [`FrameValues::roles`] gathers them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlannedFrame {
    /// Every part's value.
    pub values: FrameValues,
    /// The values of the roles the frame carries.
    pub roles: Roles,
    /// Frame length in bytes.
    pub len: usize,
}

impl FrameLayout {
    /// This layout with its plan computed ([`FramePlan::of`]); `plan` is `None` when the
    /// layout has none.
    pub fn planned(mut self) -> FrameLayout {
        self.plan = FramePlan::of(&self);
        self
    }

    /// This layout without a plan: everything goes through the interpreter.
    pub fn unplanned(mut self) -> FrameLayout {
        self.plan = None;
        self
    }
}

/// A fixed binary format's byte count, for formats a plan reads whole.
fn fixed(format: Format) -> Option<u8> {
    format.fixed_len().map(|n| n as u8)
}

impl FramePlan {
    /// The plan of `layout`, when every part is one a plan handles: a binary encoding, at
    /// most [`MAX_PARTS`] parts, no text or words fields, no field sized by the rest of the
    /// frame, lengths and checksums that cover parts before them. `None` otherwise (the
    /// interpreter then handles every frame of the layout).
    pub fn of(layout: &FrameLayout) -> Option<FramePlan> {
        if layout.encoding != Encoding::Binary
            || layout.parts.is_empty()
            || layout.parts.len() > MAX_PARTS
        {
            return None;
        }
        let count = layout.parts.len();
        let mut steps = Vec::with_capacity(count);
        for (index, part) in layout.parts.iter().enumerate() {
            let step = match part {
                Part::Literal {
                    bytes, optional, ..
                } if !bytes.is_empty() => Step::Literal {
                    optional: *optional,
                },
                Part::Literal { .. } => return None,
                Part::Field(field) => {
                    if matches!(field.role, Role::Words | Role::Text) {
                        return None;
                    }
                    let by_length = match (field.sized_by, field.format) {
                        (SizedBy::Rest, _) | (_, Format::Bytes) => return None,
                        (SizedBy::Length, Format::UintBe | Format::UintLe) => true,
                        (SizedBy::Length, _) => return None,
                        (SizedBy::Format, Format::UintBe | Format::UintLe) => {
                            if field.width == 0 || field.width > 4 || field.min_width > field.width
                            {
                                return None;
                            }
                            false
                        }
                        (SizedBy::Format, format) if format.is_digits() => {
                            if field.width == 0 || field.width > 10 || field.min_width > field.width
                            {
                                return None;
                            }
                            false
                        }
                        (SizedBy::Format, _) => false,
                    };
                    // A length must size the field from an earlier part.
                    if by_length
                        && !layout.parts[..index].iter().any(|p| {
                            matches!(p, Part::Length(l) if l.counts == Counts::Parts {
                                from: index as u8,
                                through: index as u8,
                            })
                        })
                    {
                        return None;
                    }
                    let open_digits = field
                        .broadcast
                        .as_ref()
                        .is_some_and(|b| !b.all_bytes.is_empty() || b.wildcard.is_some());
                    Step::Field {
                        role: field.role,
                        format: field.format,
                        width: field.width,
                        min_width: field.min_width,
                        optional: field.optional,
                        by_length,
                        checked: !field.allowed.is_empty(),
                        open_digits,
                    }
                }
                Part::Word(word) => {
                    fixed(word.format)?;
                    if word
                        .fields
                        .iter()
                        .any(|bits| bits.width == 0 || bits.width > 32)
                    {
                        return None;
                    }
                    Step::Word {
                        format: word.format,
                    }
                }
                Part::Length(length) => {
                    fixed(length.format)?;
                    if let Counts::Parts { from, through } = length.counts {
                        if from > through || usize::from(through) >= count {
                            return None;
                        }
                    }
                    Step::Length {
                        format: length.format,
                        counts: length.counts,
                        times: length.times,
                        per: length.per,
                    }
                }
                Part::Checksum(spec) => {
                    if spec.format != Format::Hex && fixed(spec.format).is_none() {
                        return None;
                    }
                    if usize::from(spec.covers_from) >= index
                        || spec
                            .covers_through
                            .is_some_and(|through| usize::from(through) >= index)
                    {
                        return None;
                    }
                    Step::Checksum {
                        algorithm: spec.algorithm,
                        format: spec.format,
                        covers_from: spec.covers_from,
                        covers_through: spec.covers_through,
                        optional: spec.optional,
                    }
                }
            };
            steps.push(step);
        }
        Some(FramePlan {
            steps: List::Owned(steps),
        })
    }

    /// Decodes the frame at the start of `bytes` with `layout` (the layout this plan was
    /// made from). `Some` only when the frame is complete and sound, and then it is what
    /// the interpreter returns; `None` for everything else.
    #[inline]
    pub fn decode(&self, layout: &FrameLayout, bytes: &[u8]) -> Option<PlannedFrame> {
        let steps: &[Step] = &self.steps;
        let parts: &[Part] = &layout.parts;
        if steps.len() != parts.len() || steps.len() > MAX_PARTS {
            return None;
        }
        let mut values = FrameValues::default();
        let mut roles = Roles::default();
        let mut starts = [0usize; MAX_PARTS];
        let mut ends = [0usize; MAX_PARTS];
        let mut sized = [u16::MAX; MAX_PARTS];
        let mut frame_end = usize::MAX;
        let mut pos = 0usize;
        for (index, (step, part)) in steps.iter().zip(parts).enumerate() {
            starts[index] = pos;
            let rest = bytes.get(pos..)?;
            match (*step, part) {
                (Step::Literal { optional }, Part::Literal { bytes: literal, .. }) => {
                    if rest.starts_with(literal) {
                        values.parts[index].present = true;
                        pos += literal.len();
                    } else if !optional || literal.starts_with(rest) {
                        return None;
                    }
                }
                (
                    Step::Field {
                        role,
                        format,
                        width,
                        min_width,
                        optional,
                        by_length,
                        checked,
                        open_digits,
                    },
                    Part::Field(field),
                ) => {
                    if let Some(presence) = optional {
                        let &next = rest.first()?;
                        let present = match presence {
                            Presence::IfFormatMatches => format.accepts_digit(next),
                            Presence::IfByteAtMost(limit) => next <= limit,
                        } || field
                            .broadcast
                            .as_ref()
                            .is_some_and(|b| b.starts_with(next));
                        if !present {
                            ends[index] = pos;
                            continue;
                        }
                    }
                    if open_digits {
                        let broadcast = field.broadcast.as_ref()?;
                        let all: &[u8] = &broadcast.all_bytes;
                        if !all.is_empty() && !rest.is_empty() {
                            let compared = rest.len().min(all.len());
                            if rest[..compared] == all[..compared] {
                                return None;
                            }
                        }
                        if let Some(wildcard) = broadcast.wildcard {
                            if rest[..rest.len().min(usize::from(width))].contains(&wildcard) {
                                return None;
                            }
                        }
                    }
                    let (value, used, slot_width) = match format {
                        Format::UintBe | Format::UintLe => {
                            let size = if by_length {
                                let size = sized[index];
                                if size == u16::MAX {
                                    return None;
                                }
                                usize::from(size)
                            } else {
                                usize::from(width)
                            };
                            if size < usize::from(min_width) || size > 4 {
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
                            if role == Role::Data {
                                values.data_size = size as u8;
                            }
                            (value, size, size as u8)
                        }
                        Format::Decimal | Format::Hex => {
                            let (value, used) = digits(format, min_width, width, rest)?;
                            (value, used, used as u8)
                        }
                        _ => {
                            let (value, used) = binary(format, rest)?;
                            (value, used, 0)
                        }
                    };
                    // A station with the open-digits flag is a broadcast's, never a
                    // reply's: the interpreter's callers decide about it.
                    if (checked && !allowed(field, value))
                        || (role == Role::Address && BroadcastAddress::is_open(value))
                    {
                        return None;
                    }
                    values.parts[index] = FieldValue {
                        present: true,
                        value,
                        width: slot_width,
                    };
                    if let Some(target) = roles.slot(role) {
                        *target = Some(value);
                    }
                    pos += used;
                }
                (Step::Word { format }, Part::Word(word)) => {
                    let (value, used) = binary(format, rest)?;
                    for bits in word.fields.iter() {
                        let field = (value & bits.mask()) >> bits.lsb;
                        if !bits.allowed.is_empty() && !bits.allowed.contains(&field) {
                            return None;
                        }
                        if let Some(target) = roles.slot(bits.role) {
                            *target = Some(field);
                        }
                    }
                    values.parts[index] = FieldValue {
                        present: true,
                        value,
                        width: 0,
                    };
                    pos += used;
                }
                (
                    Step::Length {
                        format,
                        counts,
                        times,
                        per,
                    },
                    Part::Length(_),
                ) => {
                    let (value, used) = binary(format, rest)?;
                    values.parts[index] = FieldValue {
                        present: true,
                        value,
                        width: 0,
                    };
                    pos += used;
                    let bytes_counted =
                        value as usize * usize::from(per.max(1)) / usize::from(times.max(1));
                    match counts {
                        Counts::DataSize => {
                            values.data_size = u8::try_from(bytes_counted).unwrap_or(u8::MAX);
                        }
                        Counts::Parts { from, through } => {
                            if usize::from(from) == index + 1
                                && usize::from(through) + 1 == parts.len()
                            {
                                frame_end = pos + bytes_counted;
                            } else if from == through {
                                sized[usize::from(from)] =
                                    u16::try_from(bytes_counted).unwrap_or(u16::MAX - 1);
                            }
                        }
                    }
                }
                (
                    Step::Checksum {
                        algorithm,
                        format,
                        covers_from,
                        covers_through,
                        optional,
                    },
                    Part::Checksum(spec),
                ) => {
                    let marker: &[u8] = &spec.marker;
                    if !rest.starts_with(marker) {
                        if optional && !marker.starts_with(rest) {
                            ends[index] = pos;
                            continue;
                        }
                        return None;
                    }
                    let value_at = pos + marker.len();
                    let after = &bytes[value_at..];
                    let (received, used) = if format == Format::Hex {
                        digits(Format::Hex, 2, 2, after)?
                    } else {
                        binary(format, after)?
                    };
                    let covered_end =
                        covers_through.map_or(value_at, |through| starts[usize::from(through) + 1]);
                    let from = starts[usize::from(covers_from)];
                    if checksum::compute(algorithm, bytes.get(from..covered_end)?) != received {
                        return None;
                    }
                    values.parts[index] = FieldValue {
                        present: true,
                        value: received,
                        width: 0,
                    };
                    pos = value_at + used;
                }
                _ => return None,
            }
            ends[index] = pos;
            if pos > frame_end {
                return None;
            }
        }
        for (index, step) in steps.iter().enumerate() {
            if let Step::Length {
                counts: Counts::Parts { from, through },
                times,
                per,
                ..
            } = *step
            {
                let counted = ends[usize::from(through)] - starts[usize::from(from)];
                let expected = (counted * usize::from(times) / usize::from(per.max(1))) as u32;
                if values.parts[index].value != expected {
                    return None;
                }
            }
        }
        Some(PlannedFrame {
            values,
            roles,
            len: pos,
        })
    }

    /// Encodes a frame of `layout` (the layout this plan was made from) carrying `roles`,
    /// with `data_size` bytes of data, the optional parts named in `include` and the
    /// optional fields whose role has a value: what [`crate::codec::encode`] writes for
    /// the frame values [`crate::FrameValues::fill`] and [`crate::FrameValues::include`]
    /// make of them. `None` when the interpreter would refuse the values (too wide for
    /// their field, `out` too small) or when they are ones a plan leaves to it.
    #[inline]
    pub fn encode(
        &self,
        layout: &FrameLayout,
        roles: &Roles,
        data_size: u8,
        include: &[crate::layout::Text],
        out: &mut [u8],
    ) -> Option<usize> {
        let steps: &[Step] = &self.steps;
        let parts: &[Part] = &layout.parts;
        if steps.len() != parts.len() || steps.len() > MAX_PARTS || data_size > 4 {
            return None;
        }
        let included = |part: &Part| include.iter().any(|name| name == part.name());
        let mut starts = [0usize; MAX_PARTS];
        let mut ends = [0usize; MAX_PARTS];
        let mut pos = 0usize;
        for (index, (step, part)) in steps.iter().zip(parts).enumerate() {
            starts[index] = pos;
            match (*step, part) {
                (Step::Literal { optional }, Part::Literal { bytes, .. }) => {
                    if !optional || included(part) {
                        pos = put(out, pos, bytes)?;
                    }
                }
                (
                    Step::Field {
                        role,
                        format,
                        width,
                        optional,
                        ..
                    },
                    Part::Field(field),
                ) => {
                    let value = roles.value(role);
                    if optional.is_some() && value.is_none() && !included(part) {
                        ends[index] = pos;
                        continue;
                    }
                    let value = value.unwrap_or(0);
                    let width = match format {
                        Format::UintBe | Format::UintLe if data_size != 0 => data_size,
                        _ => width,
                    };
                    if field.broadcast.is_some() && BroadcastAddress::is_open(value) {
                        return None;
                    }
                    pos = put_value(out, pos, format, value, width)?;
                }
                (Step::Word { format }, Part::Word(word)) => {
                    let mut value = 0u32;
                    for bits in word.fields.iter() {
                        if let Some(field) = roles.value(bits.role) {
                            value = (value & !bits.mask()) | ((field << bits.lsb) & bits.mask());
                        }
                    }
                    pos = put_value(out, pos, format, value, 0)?;
                }
                (Step::Length { format, .. }, Part::Length(_)) => {
                    pos = put(out, pos, &[0; 4][..usize::from(fixed(format)?)])?;
                }
                (
                    Step::Checksum {
                        format, optional, ..
                    },
                    Part::Checksum(spec),
                ) => {
                    if !optional || included(part) {
                        pos = put(out, pos, &spec.marker)?;
                        pos = put(out, pos, &[0; 2][..checksum_size(format)])?;
                    }
                }
                _ => return None,
            }
            ends[index] = pos;
        }
        for (index, step) in steps.iter().enumerate() {
            if let Step::Length {
                format,
                counts,
                times,
                per,
            } = *step
            {
                let counted = match counts {
                    Counts::Parts { from, through } => {
                        ends[usize::from(through)] - starts[usize::from(from)]
                    }
                    Counts::DataSize => usize::from(data_size),
                };
                let value = (counted * usize::from(times) / usize::from(per.max(1))) as u32;
                put_value(out, starts[index], format, value, 0)?;
            }
        }
        for (index, (step, part)) in steps.iter().zip(parts).enumerate() {
            if let (
                Step::Checksum {
                    algorithm,
                    format,
                    covers_from,
                    covers_through,
                    ..
                },
                Part::Checksum(spec),
            ) = (*step, part)
            {
                if ends[index] == starts[index] {
                    continue;
                }
                let value_at = starts[index] + spec.marker.len();
                let covered_end = covers_through.map_or(value_at, |t| ends[usize::from(t)]);
                let sum = checksum::compute(
                    algorithm,
                    out.get(starts[usize::from(covers_from)]..covered_end)?,
                );
                put_value(out, value_at, format, sum, 2)?;
            }
        }
        Some(pos)
    }
}

/// Whether `field` accepts `value` (its allowed list, folded as it says).
fn allowed(field: &crate::layout::FieldSpec, value: u32) -> bool {
    let fold = |v: u32| {
        if field.fold_case {
            u8::try_from(v).map_or(v, |b| u32::from(b.to_ascii_uppercase()))
        } else {
            v
        }
    };
    field.allowed.is_empty() || field.allowed.iter().any(|a| fold(*a) == fold(value))
}

/// `min_width..=width` digits of `format` at the start of `rest`: the value and the digits
/// used. `None` when more bytes are needed or too few digits are there.
#[inline]
fn digits(format: Format, min_width: u8, width: u8, rest: &[u8]) -> Option<(u32, usize)> {
    let radix = if format == Format::Hex { 16 } else { 10 };
    let mut value: u32 = 0;
    let mut used = 0usize;
    while used < usize::from(width) {
        let &byte = rest.get(used)?;
        let Some(digit) = (byte as char).to_digit(radix) else {
            break;
        };
        value = value * radix + digit;
        used += 1;
    }
    (used >= usize::from(min_width)).then_some((value, used))
}

/// A fixed binary value at the start of `rest`: the value and its byte count.
#[inline]
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

/// Writes `bytes` at `at`; the position after them.
#[inline]
fn put(out: &mut [u8], at: usize, bytes: &[u8]) -> Option<usize> {
    let end = at + bytes.len();
    out.get_mut(at..end)?.copy_from_slice(bytes);
    Some(end)
}

/// Writes `value` in `format` at `at` (`width`: digits, or bytes of `uint_be`/`uint_le`);
/// `None` when it does not fit the format or `out`.
#[inline]
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

/// [`crate::codec::decode_prefix`] through the layout's plan when it has one and the plan
/// decodes the frame; the interpreter otherwise. The outcome is the interpreter's.
#[inline]
pub fn decode_prefix(
    layout: &FrameLayout,
    bytes: &[u8],
) -> Result<crate::codec::Progress, crate::error::DecodeError> {
    match layout
        .plan
        .as_ref()
        .and_then(|plan| plan.decode(layout, bytes))
    {
        Some(frame) => Ok(crate::codec::Progress::Complete {
            values: frame.values,
            len: frame.len,
        }),
        None => crate::codec::decode_prefix(layout, bytes),
    }
}

/// [`crate::codec::decode`] through the layout's plan, as [`decode_prefix`].
#[inline]
pub fn decode(
    layout: &FrameLayout,
    bytes: &[u8],
) -> Result<crate::codec::DecodeStatus, crate::error::DecodeError> {
    match layout
        .plan
        .as_ref()
        .and_then(|plan| plan.decode(layout, bytes))
    {
        Some(frame) => Ok(crate::codec::DecodeStatus::Complete {
            values: frame.values,
            len: frame.len,
        }),
        None => crate::codec::decode(layout, bytes),
    }
}
