//! One step of a plan on its part, for decoding and encoding: what a plan run step by step
//! does in a loop, and what a compiled plan ([`crate::compiled_plan!`]) does once per part
//! with the step and the part constants, so the two cannot differ.

use super::{included, Decoder, Encoder, Step};
use crate::layout::{Part, Roles, Text};

/// Decodes part `index` (`step` is its plan step, `count` the layout's part count); `None`
/// when the frame is not one the plan decodes.
#[inline(always)]
pub fn decode_part(
    decoder: &mut Decoder<'_>,
    index: usize,
    step: Step,
    part: &Part,
    count: usize,
) -> Option<()> {
    match (step, part) {
        (Step::Literal { optional }, Part::Literal { bytes, .. }) => {
            decoder.literal(index, bytes, optional)
        }
        (Step::Field(step), Part::Field(field)) => decoder.field(
            index,
            step,
            &field.allowed,
            field.fold_case,
            field.broadcast.as_ref(),
        ),
        (Step::Word { format }, Part::Word(word)) => decoder.word(index, format, &word.fields),
        (Step::Length(step), Part::Length(_)) => decoder.length(index, step, count),
        (Step::Checksum(step), Part::Checksum(spec)) => decoder.checksum(index, step, &spec.marker),
        _ => None,
    }
}

/// After every part is decoded: checks the length at `index`, when `step` is a length.
#[inline(always)]
pub fn check_length_part(decoder: &Decoder<'_>, index: usize, step: Step) -> Option<()> {
    match step {
        Step::Length(step) => decoder.check_length(index, step),
        _ => Some(()),
    }
}

/// Writes part `index` (`step` is its plan step) carrying `roles`, with `data_size` bytes
/// of data and the optional parts `include` names; `None` when the interpreter is to
/// write the frame.
#[inline(always)]
pub fn encode_part(
    encoder: &mut Encoder<'_>,
    index: usize,
    step: Step,
    part: &Part,
    roles: &Roles,
    data_size: u8,
    include: &[Text],
) -> Option<()> {
    let named = || included(include, part.name());
    match (step, part) {
        (Step::Literal { optional }, Part::Literal { bytes, .. }) => {
            encoder.literal(index, bytes, !optional || named())
        }
        (Step::Field(step), Part::Field(field)) => {
            let value = roles.value(step.role);
            let present = step.optional.is_none() || value.is_some() || named();
            encoder.field(
                index,
                step,
                value,
                present,
                data_size,
                field.broadcast.is_some(),
            )
        }
        (Step::Word { format }, Part::Word(word)) => {
            encoder.word(index, format, &word.fields, roles)
        }
        (Step::Length(step), Part::Length(_)) => encoder.length(index, step.format),
        (Step::Checksum(step), Part::Checksum(spec)) => {
            encoder.checksum(index, step, &spec.marker, !step.optional || named())
        }
        _ => None,
    }
}

/// After every part is written: fills in the length at `index`, when `step` is a length.
#[inline(always)]
pub fn fill_length_part(
    encoder: &mut Encoder<'_>,
    index: usize,
    step: Step,
    data_size: u8,
) -> Option<()> {
    match step {
        Step::Length(step) => encoder.fill_length(index, step, data_size),
        _ => Some(()),
    }
}

/// After every length is filled in: fills in the checksum at `index`, when `step` is one.
#[inline(always)]
pub fn fill_checksum_part(
    encoder: &mut Encoder<'_>,
    index: usize,
    step: Step,
    part: &Part,
) -> Option<()> {
    match (step, part) {
        (Step::Checksum(step), Part::Checksum(spec)) => {
            encoder.fill_checksum(index, step, spec.marker.len())
        }
        _ => Some(()),
    }
}
