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
//! A layout's parts are lowered to steps by one `const fn` ([`step_of`]). The generator
//! writes each layout's parts once; the compiler lowers them to its steps ([`steps`]), and
//! [`crate::compiled_plan!`] writes two functions that run the steps through [`Decoder`]
//! and [`Encoder`] part by part with the step and the part constants (so the compiler makes
//! straight-line code for the layout). A description loaded at run time gets its plans
//! from the same function ([`FramePlan::of`]) and runs its steps in a loop through the
//! same per-part functions ([`decode_part`], [`encode_part`], ...). [`crate::Protocol`] uses them in
//! [`crate::Protocol::encode_request`], [`crate::Protocol::decode_reply`],
//! [`crate::Protocol::find_reply`] and [`crate::Protocol::search_reply`].

mod compiled;
mod decoder;
mod encoder;
mod lower;
mod part;

use crate::layout::{Encoding, FrameLayout, List, Part, Roles, MAX_PARTS};

pub use decoder::Decoder;
pub use encoder::Encoder;
use lower::fixed;
pub use lower::{step_of, steps};
pub use part::{check_length_part, decode_part, encode_part, fill_checksum_part, fill_length_part};

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

impl FramePlan {
    /// The plan of `layout`, when every part is one a plan handles: at most [`MAX_PARTS`]
    /// parts, no text or words fields, no field sized by the rest of the
    /// frame, lengths and checksums that cover parts before them. `None` otherwise (the
    /// interpreter then handles every frame of the layout). The plan has no compiled
    /// functions: the generator adds them to the layouts it writes.
    pub fn of(layout: &FrameLayout) -> Option<FramePlan> {
        let steps = (0..layout.parts.len())
            .map(|index| step_of(&layout.parts, index))
            .collect::<Option<Vec<Step>>>()?;
        if steps.is_empty() {
            return None;
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
            decode_part(&mut decoder, index, *step, part, parts.len())?;
        }
        for (index, step) in steps.iter().enumerate() {
            check_length_part(&decoder, index, *step)?;
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
            encode_part(&mut encoder, index, *step, part, roles, data_size, include)?;
        }
        for (index, step) in steps.iter().enumerate() {
            fill_length_part(&mut encoder, index, *step, data_size)?;
        }
        for (index, (step, part)) in steps.iter().zip(parts).enumerate() {
            fill_checksum_part(&mut encoder, index, *step, part)?;
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
