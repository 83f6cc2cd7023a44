//! A value field (`field: register` with `format` and, for digits, `width`): its widths,
//! how a decoder tells an optional one is there, and its allowed values.

use super::broadcast::broadcast_address;
use super::{codes, required_format, PartContext};
use crate::diagnostics::Diagnostics;
use crate::parse::model::{OptionalModel, PartModel};
use std::borrow::Cow;
use vfd_runtime::{FieldSpec, Format, Part, Presence, Role, SizedBy};

/// A value field (`field: register` with `format` and, for digits, `width`).
pub(super) fn field(
    name: &str,
    role: Role,
    model: &PartModel,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<Part> {
    let format = required_format(model, context, out)?;
    let sized_by = model.size.unwrap_or(SizedBy::Format);
    let (width, min_width) = widths(format, sized_by, model, context, out)?;
    let variable = matches!(format, Format::UintBe | Format::UintLe | Format::Bytes);
    if role == Role::Words {
        if !matches!(format, Format::U16Be | Format::U16Le) {
            return context.fail(
                out,
                "format",
                format!(
                    "a words field is a run of 16-bit words: u16be or u16le, not {}",
                    format.as_str()
                ),
                "format: u16be",
            );
        }
        if sized_by == SizedBy::Format {
            return context.fail(
                out,
                "size",
                "a words field needs `size: length` (a length part counting it) or `size: rest`",
                "add size: length, and a length part with counts: { from: words, through: words }",
            );
        }
    } else if sized_by != SizedBy::Format && !variable {
        return context.fail(
            out,
            "size",
            format!(
                "`size` applies to uint_be, uint_le and bytes fields, not {}",
                format.as_str()
            ),
            "remove `size`",
        );
    }
    let optional = presence(model.optional);
    let allowed = match codes(&model.allowed) {
        Ok(allowed) => allowed,
        Err(shown) => {
            return context.fail(
                out,
                "allowed",
                format!("allowed value `{shown}` is not a number or one character"),
                "`allowed` lists command letters or codes",
            )
        }
    };
    let broadcast = match &model.broadcast {
        Some(encoding) => Some(broadcast_address(
            encoding, role, format, width, context, out,
        )?),
        None => None,
    };
    Some(Part::Field(FieldSpec {
        name: Cow::Owned(name.to_owned()),
        role,
        format,
        width,
        min_width,
        optional,
        allowed: Cow::Owned(allowed),
        fold_case: model.fold_case,
        sized_by,
        broadcast,
    }))
}

/// A field's `width` and `min_width`: fixed by binary formats, given for digits, a most and
/// fewest byte count for variable binary fields.
fn widths(
    format: Format,
    sized_by: SizedBy,
    model: &PartModel,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<(u8, u8)> {
    let variable = matches!(format, Format::UintBe | Format::UintLe | Format::Bytes);
    let sized_elsewhere = variable && sized_by != SizedBy::Format;
    let width = match (format.fixed_len(), model.width) {
        (Some(len), _) => len as u8,
        (None, Some(width)) if variable && (1..=255).contains(&width) => width,
        (None, Some(width)) if (1..=10).contains(&width) => width,
        (None, None) if sized_elsewhere => {
            if format == Format::Bytes {
                255
            } else {
                4
            }
        }
        (None, Some(width)) => {
            return context.fail(
                out,
                "width",
                format!("`width: {width}` is out of range for {}", format.as_str()),
                "ASCII digit fields take 1 to 10 digits; uint_be/uint_le up to 4 bytes; bytes up to 255",
            )
        }
        (None, None) => {
            return context.fail(
                out,
                "width",
                "this format needs a `width` (digits, or the most bytes)",
                "e.g. width: 4 for a 16-bit word in hex",
            )
        }
    };
    let min_width = match model.min_width {
        Some(min_width) => min_width,
        None if sized_elsewhere => u8::from(format != Format::Bytes),
        None => width,
    };
    if (min_width == 0 && format != Format::Bytes) || min_width > width {
        return context.fail(
            out,
            "min_width",
            format!("min_width {min_width} must be from 1 to width {width}"),
            "leave it out for fixed-width fields",
        );
    }
    Some((width, min_width))
}

/// How a decoder tells an optional field is there (`None`: always there).
fn presence(optional: Option<OptionalModel>) -> Option<Presence> {
    match optional? {
        OptionalModel::Flag(false) => None,
        OptionalModel::Flag(true) | OptionalModel::IfFormatMatches => {
            Some(Presence::IfFormatMatches)
        }
        OptionalModel::IfByteAtMost(limit) => Some(Presence::IfByteAtMost(limit)),
    }
}
