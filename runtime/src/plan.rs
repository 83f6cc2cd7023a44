//! Frame plans: a layout's parts reduced, once, to the steps a fast encoder and decoder run.
//!
//! The interpreter in [`crate::codec`] handles every layout a description can state, and
//! explains every frame that does not fit. A [`FramePlan`] covers the layouts most frames
//! use (layouts whose parts are literals, fixed-format or digit fields, words, lengths and
//! checksums, optional parts included; binary, or written as hex pairs) and only the frames
//! that fit: it returns `None` for anything else (a frame not complete yet, a wrong byte, a
//! checksum that does not match, a broadcast station written with open digits, a block of
//! registers, text), and the caller then runs the interpreter, which says what is wrong. When a plan does return a
//! frame, it is the frame the interpreter returns for the same bytes, value for value: the
//! differential tests (`tests/tests/fast_path.rs`) and the `plan_agreement` fuzz target
//! hold the two to that.
//!
//! The generator computes each layout's plan at build time ([`FramePlan::of`]) and writes it
//! into the generated layout as const data, with two functions that run its steps through
//! [`Decoder`] and [`Encoder`] with every argument a constant (so the compiler makes
//! straight-line code for the layout); a description loaded at run time gets its plans
//! from the same function and runs their steps one by one through the same methods. [`crate::Protocol`] uses them in
//! [`crate::Protocol::encode_request`], [`crate::Protocol::decode_reply`],
//! [`crate::Protocol::find_reply`] and [`crate::Protocol::search_reply`].

use crate::checksum;
use crate::layout::{
    checksum_size, BitsSpec, BroadcastAddress, Counts, Encoding, FieldValue, Format, FrameLayout,
    FrameValues, List, Part, Presence, Role, Roles, SizedBy, MAX_PARTS,
};

pub use crate::layout::{
    ChecksumStep, Compiled, EncodeFn, FieldStep, FramePlan, LengthStep, PlannedFrame, Step,
};

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
    /// The plan of `layout`, when every part is one a plan handles: at most [`MAX_PARTS`]
    /// parts, no text or words fields, no field sized by the rest of the
    /// frame, lengths and checksums that cover parts before them. `None` otherwise (the
    /// interpreter then handles every frame of the layout). The plan has no compiled
    /// functions: the generator adds them to the layouts it writes.
    pub fn of(layout: &FrameLayout) -> Option<FramePlan> {
        if layout.parts.is_empty() || layout.parts.len() > MAX_PARTS {
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
                    Step::Field(FieldStep {
                        role: field.role,
                        format: field.format,
                        width: field.width,
                        min_width: field.min_width,
                        optional: field.optional,
                        by_length,
                        checked: !field.allowed.is_empty(),
                        open_digits,
                    })
                }
                Part::Word(word) => {
                    fixed(word.format)?;
                    if word
                        .fields
                        .iter()
                        .any(|bits| bits.width == 0 || bits.width > 32 || bits.lsb >= 32)
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
                    Step::Length(LengthStep {
                        format: length.format,
                        counts: length.counts,
                        times: length.times,
                        per: length.per,
                    })
                }
                Part::Checksum(spec) => {
                    if spec.format != Format::Hex && fixed(spec.format).is_none() {
                        return None;
                    }
                    if usize::from(spec.covers_from) >= index
                        || spec
                            .covers_through
                            .is_some_and(|through| through < spec.covers_from)
                        || spec
                            .covers_through
                            .is_some_and(|through| usize::from(through) >= index)
                    {
                        return None;
                    }
                    Step::Checksum(ChecksumStep {
                        algorithm: spec.algorithm,
                        format: spec.format,
                        covers_from: spec.covers_from,
                        covers_through: spec.covers_through,
                        optional: spec.optional,
                    })
                }
            };
            steps.push(step);
        }
        Some(FramePlan {
            steps: List::Owned(steps),
            compiled: None,
        })
    }

    /// Decodes the frame at the start of `bytes` with `layout` (the layout this plan was
    /// made from). `Some` only when the frame is complete and sound, and then it is what
    /// the interpreter returns; `None` for everything else.
    #[inline]
    pub fn decode(&self, layout: &FrameLayout, bytes: &[u8]) -> Option<PlannedFrame> {
        match &self.compiled {
            Some(compiled) => through_hex_pairs(layout, bytes, compiled.decode),
            None => through_hex_pairs(layout, bytes, |bytes| self.run_decode(layout, bytes)),
        }
    }

    /// [`FramePlan::decode`] step by step, without the compiled functions.
    pub fn decode_steps(&self, layout: &FrameLayout, bytes: &[u8]) -> Option<PlannedFrame> {
        through_hex_pairs(layout, bytes, |bytes| self.run_decode(layout, bytes))
    }

    /// The steps on the frame's bytes (for [`Encoding::HexPairs`], after the hex digits are
    /// turned back into bytes).
    fn run_decode(&self, layout: &FrameLayout, bytes: &[u8]) -> Option<PlannedFrame> {
        let steps: &[Step] = &self.steps;
        let parts: &[Part] = &layout.parts;
        if steps.len() != parts.len() || steps.len() > MAX_PARTS {
            return None;
        }
        let mut decoder = Decoder::new(bytes);
        for (index, (step, part)) in steps.iter().zip(parts).enumerate() {
            match (*step, part) {
                (Step::Literal { optional }, Part::Literal { bytes, .. }) => {
                    decoder.literal(index, bytes, optional)?
                }
                (Step::Field(step), Part::Field(field)) => decoder.field(
                    index,
                    step,
                    &field.allowed,
                    field.fold_case,
                    field.broadcast.as_ref(),
                )?,
                (Step::Word { format }, Part::Word(word)) => {
                    decoder.word(index, format, &word.fields)?
                }
                (Step::Length(step), Part::Length(_)) => {
                    decoder.length(index, step, parts.len())?
                }
                (Step::Checksum(step), Part::Checksum(spec)) => {
                    decoder.checksum(index, step, &spec.marker)?
                }
                _ => return None,
            }
        }
        for (index, step) in steps.iter().enumerate() {
            if let Step::Length(step) = *step {
                decoder.check_length(index, step)?;
            }
        }
        Some(decoder.finish())
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
        match &self.compiled {
            Some(compiled) => in_hex_pairs(layout, out, |out| {
                (compiled.encode)(roles, data_size, include, out)
            }),
            None => in_hex_pairs(layout, out, |out| {
                self.run_encode(layout, roles, data_size, include, out)
            }),
        }
    }

    /// [`FramePlan::encode`] step by step, without the compiled functions.
    pub fn encode_steps(
        &self,
        layout: &FrameLayout,
        roles: &Roles,
        data_size: u8,
        include: &[crate::layout::Text],
        out: &mut [u8],
    ) -> Option<usize> {
        in_hex_pairs(layout, out, |out| {
            self.run_encode(layout, roles, data_size, include, out)
        })
    }

    /// The steps writing the frame's bytes (for [`Encoding::HexPairs`], before they are
    /// written as hex digits).
    fn run_encode(
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
        let mut encoder = Encoder::new(out);
        for (index, (step, part)) in steps.iter().zip(parts).enumerate() {
            let included = || included(include, part.name());
            match (*step, part) {
                (Step::Literal { optional }, Part::Literal { bytes, .. }) => {
                    encoder.literal(index, bytes, !optional || included())?
                }
                (Step::Field(step), Part::Field(field)) => {
                    let value = roles.value(step.role);
                    let present = step.optional.is_none() || value.is_some() || included();
                    encoder.field(
                        index,
                        step,
                        value,
                        present,
                        data_size,
                        field.broadcast.is_some(),
                    )?
                }
                (Step::Word { format }, Part::Word(word)) => {
                    encoder.word(index, format, &word.fields, roles)?
                }
                (Step::Length(step), Part::Length(_)) => encoder.length(index, step.format)?,
                (Step::Checksum(step), Part::Checksum(spec)) => {
                    encoder.checksum(index, step, &spec.marker, !step.optional || included())?
                }
                _ => return None,
            }
        }
        for (index, step) in steps.iter().enumerate() {
            if let Step::Length(step) = *step {
                encoder.fill_length(index, step, data_size)?;
            }
        }
        for (index, (step, part)) in steps.iter().zip(parts).enumerate() {
            if let (Step::Checksum(step), Part::Checksum(spec)) = (*step, part) {
                encoder.fill_checksum(index, step, spec.marker.len())?;
            }
        }
        Some(encoder.finish())
    }
}

/// `decode` on the frame's bytes: `wire` itself, or for a [`Encoding::HexPairs`] layout the
/// bytes its hex digits carry, as the interpreter recovers them (the length is then given
/// on the wire again).
#[inline(always)]
fn through_hex_pairs(
    layout: &FrameLayout,
    wire: &[u8],
    decode: impl FnOnce(&[u8]) -> Option<PlannedFrame>,
) -> Option<PlannedFrame> {
    if layout.encoding != Encoding::HexPairs {
        return decode(wire);
    }
    let mut bytes = [0u8; crate::codec::MAX_HEX_FRAME];
    let frame = crate::codec::hex_pairs_to_bytes(layout, wire, &mut bytes).ok()?;
    let mut planned = decode(&bytes[..frame.len])?;
    planned.len = frame.wire_offset(planned.len);
    Some(planned)
}

/// `encode` into `out`: directly, or for a [`Encoding::HexPairs`] layout into a buffer whose
/// bytes are then written as the interpreter writes them (verbatim ends, hex digits).
#[inline(always)]
fn in_hex_pairs(
    layout: &FrameLayout,
    out: &mut [u8],
    encode: impl FnOnce(&mut [u8]) -> Option<usize>,
) -> Option<usize> {
    if layout.encoding != Encoding::HexPairs {
        return encode(out);
    }
    let mut bytes = [0u8; crate::codec::MAX_HEX_FRAME];
    let len = encode(&mut bytes)?;
    crate::codec::hex_expand(layout, &bytes[..len], out)
}

/// Whether the part `name` is among the optional parts `include` names.
#[inline]
pub fn included(include: &[crate::layout::Text], name: &str) -> bool {
    include.iter().any(|included| included == name)
}

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

/// Encoding state of one frame: a plan's steps write it part by part, then fill in its
/// lengths and checksums. Like [`Decoder`], shared by plans run step by step and the
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
