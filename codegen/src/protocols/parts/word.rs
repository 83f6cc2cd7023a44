//! A word of bit fields (`word: u16be` with `fields:`).

use super::{codes, parse_bits, PartContext};
use crate::diagnostics::Diagnostics;
use crate::parse::model::{BitsModel, PartModel};
use std::borrow::Cow;
use vfd_runtime::{BitsSpec, Format, Part, WordSpec};

/// A word of bit fields (`word: u16be` with `fields:`).
pub(super) fn word(
    name: &str,
    format: Format,
    model: &PartModel,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<Part> {
    let word_format = matches!(
        format,
        Format::U16Be | Format::U16Le | Format::U32Be | Format::U32Le
    );
    if !word_format {
        return context.fail(
            out,
            "word",
            format!("`word: {}` is not a word format", format.as_str()),
            "use u16be, u16le, u32be or u32le",
        );
    };
    let word_bits = if matches!(format, Format::U16Be | Format::U16Le) {
        16
    } else {
        32
    };
    let fields = model
        .fields
        .iter()
        .enumerate()
        .map(|(index, bits)| bit_field(index, bits, word_bits, context, out))
        .collect::<Option<Vec<_>>>()?;
    let mut used = 0u32;
    for (index, field) in fields.iter().enumerate() {
        if used & field.mask() != 0 {
            return context.fail(
                out,
                &format!("fields[{index}].bits"),
                format!(
                    "bit field `{}` overlaps an earlier field of word `{name}`",
                    field.name
                ),
                "the bit fields of a word must not share bits",
            );
        }
        used |= field.mask();
    }
    Some(Part::Word(WordSpec {
        name: Cow::Owned(name.to_owned()),
        format,
        fields: Cow::Owned(fields),
    }))
}

/// One entry of a word's `fields:`.
fn bit_field(
    index: usize,
    bits: &BitsModel,
    word_bits: u32,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<BitsSpec> {
    let key = format!("fields[{index}]");
    let Some((lsb, width)) = parse_bits(&bits.bits)
        .filter(|(lsb, width)| u32::from(*lsb) + u32::from(*width) <= word_bits)
    else {
        return context.fail(
            out,
            &format!("{key}.bits"),
            format!(
                "`bits: {}` is not \"msb:lsb\" within the {word_bits}-bit word",
                bits.bits
            ),
            "e.g. bits: \"15:12\"",
        );
    };
    let allowed = match codes(&bits.allowed) {
        Ok(allowed) => allowed,
        Err(shown) => {
            return context.fail(
                out,
                &format!("{key}.allowed"),
                format!("`{shown}` is not a number or one character"),
                "e.g. allowed: [1, 2]",
            )
        }
    };
    Some(BitsSpec {
        name: Cow::Owned(
            bits.name
                .clone()
                .unwrap_or_else(|| bits.field.as_str().to_owned()),
        ),
        role: bits.field,
        lsb,
        width,
        allowed: Cow::Owned(allowed),
    })
}
