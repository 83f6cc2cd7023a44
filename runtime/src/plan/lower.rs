//! A layout's parts lowered to plan steps, by `const fn`: the generator's layouts get their
//! steps from the compiler ([`steps`]), a description loaded at run time gets them from the
//! same function ([`step_of`], through [`FramePlan::of`](super::FramePlan::of)).

use std::borrow::Cow;

use crate::layout::{
    ChecksumStep, Counts, FieldStep, Format, LengthStep, List, Part, Role, SizedBy, Step, MAX_PARTS,
};

/// A list's items, whether borrowed (generated code) or owned (a description read at run
/// time).
const fn items<T: Clone>(list: &List<T>) -> &[T] {
    match list {
        Cow::Borrowed(items) => items,
        Cow::Owned(items) => items.as_slice(),
    }
}

/// A fixed binary format's byte count, for formats a plan reads whole.
pub(super) const fn fixed(format: Format) -> Option<u8> {
    match format.fixed_len() {
        Some(len) => Some(len as u8),
        None => None,
    }
}

/// Whether a field of `format`, `width` and `min_width` sized as `sized_by` is one a plan
/// reads: `Some(by_length)` (sized by the length part that covers it alone), `None` when
/// the interpreter must read it.
const fn field_sizing(sized_by: SizedBy, format: Format, width: u8, min_width: u8) -> Option<bool> {
    match (sized_by, format) {
        (SizedBy::Rest, _) | (_, Format::Bytes) => None,
        (SizedBy::Length, Format::UintBe | Format::UintLe) => Some(true),
        (SizedBy::Length, _) => None,
        (SizedBy::Format, Format::UintBe | Format::UintLe) => {
            if width == 0 || width > 4 || min_width > width {
                None
            } else {
                Some(false)
            }
        }
        (SizedBy::Format, Format::Decimal | Format::Hex) => {
            if width == 0 || width > 10 || min_width > width {
                None
            } else {
                Some(false)
            }
        }
        (SizedBy::Format, _) => Some(false),
    }
}

/// Whether a length part before `index` counts part `index` alone.
const fn sized_by_a_length(parts: &[Part], index: usize) -> bool {
    let mut at = 0;
    while at < index {
        if let Part::Length(length) = &parts[at] {
            if let Counts::Parts { from, through } = length.counts {
                if from as usize == index && through as usize == index {
                    return true;
                }
            }
        }
        at += 1;
    }
    false
}

/// The step of part `index` of a layout made of `parts`: `None` when the part is one a plan
/// leaves to the interpreter (text and word-list fields, fields sized by the rest of the
/// frame, a length or checksum that does not cover earlier parts, more than
/// [`MAX_PARTS`] parts). A layout has a plan when every part has a step.
pub const fn step_of(parts: &[Part], index: usize) -> Option<Step> {
    let count = parts.len();
    if count == 0 || count > MAX_PARTS || index >= count {
        return None;
    }
    Some(match &parts[index] {
        Part::Literal {
            bytes, optional, ..
        } => {
            if items(bytes).is_empty() {
                return None;
            }
            Step::Literal {
                optional: *optional,
            }
        }
        Part::Field(field) => {
            if matches!(field.role, Role::Words | Role::Text) {
                return None;
            }
            let Some(by_length) =
                field_sizing(field.sized_by, field.format, field.width, field.min_width)
            else {
                return None;
            };
            // A length must size the field from an earlier part.
            if by_length && !sized_by_a_length(parts, index) {
                return None;
            }
            let open_digits = match &field.broadcast {
                Some(broadcast) => {
                    !items(&broadcast.all_bytes).is_empty() || broadcast.wildcard.is_some()
                }
                None => false,
            };
            Step::Field(FieldStep {
                role: field.role,
                format: field.format,
                width: field.width,
                min_width: field.min_width,
                optional: field.optional,
                by_length,
                checked: !items(&field.allowed).is_empty(),
                open_digits,
            })
        }
        Part::Word(word) => {
            if fixed(word.format).is_none() {
                return None;
            }
            let bits = items(&word.fields);
            let mut at = 0;
            while at < bits.len() {
                let field = &bits[at];
                if field.width == 0 || field.width > 32 || field.lsb >= 32 {
                    return None;
                }
                at += 1;
            }
            Step::Word {
                format: word.format,
            }
        }
        Part::Length(length) => {
            if fixed(length.format).is_none() {
                return None;
            }
            if let Counts::Parts { from, through } = length.counts {
                if from > through || through as usize >= count {
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
            if !matches!(spec.format, Format::Hex) && fixed(spec.format).is_none() {
                return None;
            }
            if spec.covers_from as usize >= index {
                return None;
            }
            if let Some(through) = spec.covers_through {
                if through < spec.covers_from || through as usize >= index {
                    return None;
                }
            }
            Step::Checksum(ChecksumStep {
                algorithm: spec.algorithm,
                format: spec.format,
                covers_from: spec.covers_from,
                covers_through: spec.covers_through,
                optional: spec.optional,
            })
        }
    })
}

/// The `N` steps of a layout of `N` parts, for a `const` in generated code: the generator
/// writes a layout's parts once and the compiler lowers them. Compilation stops with a
/// message when the layout has no plan or `N` is not its part count (the generator writes
/// this only for layouts with one).
pub const fn steps<const N: usize>(parts: &[Part]) -> [Step; N] {
    assert!(
        parts.len() == N,
        "the step count is not the layout's part count"
    );
    let mut steps = [Step::Literal { optional: false }; N];
    let mut index = 0;
    while index < N {
        steps[index] = match step_of(parts, index) {
            Some(step) => step,
            None => panic!("a part of this layout has no plan step"),
        };
        index += 1;
    }
    steps
}
