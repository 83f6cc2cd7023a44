//! A checksum (`checksum: sum8` with `format` and `covers_from`).

use super::{required_format, PartContext};
use crate::diagnostics::Diagnostics;
use crate::parse::model::PartModel;
use std::borrow::Cow;
use vfd_runtime::{ChecksumAlgorithm, ChecksumSpec, Format, Part};

/// A checksum (`checksum: sum8` with `format` and `covers_from`).
pub(super) fn checksum(
    name: &str,
    algorithm: ChecksumAlgorithm,
    model: &PartModel,
    optional: bool,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<Part> {
    let format = required_format(model, context, out)?;
    let fits = match algorithm {
        ChecksumAlgorithm::Crc16Modbus => matches!(format, Format::U16Le | Format::U16Be),
        _ => matches!(format, Format::Hex | Format::U8),
    };
    if !fits {
        return context.fail(
            out,
            "format",
            format!(
                "a {} checksum cannot be written as {}",
                algorithm.as_str(),
                format.as_str()
            ),
            "8-bit sums: hex (two digits) or u8; crc16_modbus: u16le (Modbus sends the low byte first) or u16be",
        );
    }
    let from_name = model.covers_from.as_deref().unwrap_or("");
    let covers_from = context
        .position_of(from_name)
        .filter(|position| *position < context.index);
    let Some(covers_from) = covers_from else {
        return context.fail(
            out,
            "covers_from",
            format!("`covers_from: {from_name}` does not name an earlier part of the layout"),
            "name the first covered part, e.g. covers_from: start",
        );
    };
    let covers_through = match model.covers_through.as_deref() {
        None => None,
        Some(through) => {
            let position = context
                .position_of(through)
                .filter(|position| *position < context.index && *position >= covers_from);
            let Some(position) = position else {
                return context.fail(
                    out,
                    "covers_through",
                    format!("`covers_through: {through}` does not name a part between `covers_from` and the checksum"),
                    "name the last covered part, e.g. covers_through: unit (an ETX after it is then left out)",
                );
            };
            Some(position as u8)
        }
    };
    let marker = model.marker.clone().unwrap_or_default().into_bytes();
    if optional && marker.is_empty() {
        return context.fail(
            out,
            "optional",
            "an optional checksum needs a `marker`",
            "the decoder can only tell it is there by its marker, e.g. marker: \"&\"",
        );
    }
    Some(Part::Checksum(ChecksumSpec {
        name: Cow::Owned(name.to_owned()),
        algorithm,
        format,
        marker: Cow::Owned(marker),
        covers_from: covers_from as u8,
        covers_through,
        optional,
    }))
}
