//! Parts: one entry of a layout lowered into a runtime [`Part`], one function per kind
//! (literal, hex literal, word of bit fields, length, checksum, field).
//!
//! Here: where a part sits, its kind, literals and what the kinds share; words of bit
//! fields in `word.rs`, lengths in `length.rs`, checksums in `checksum.rs`, value fields
//! in `field.rs` and a station field's broadcast encodings in `broadcast.rs`.

mod broadcast;
mod checksum;
mod field;
mod length;
#[cfg(test)]
mod tests;
mod word;

use crate::diagnostics::{Diagnostic, Diagnostics};
use crate::parse::model::{CodeModel, OptionalModel, PartModel};
use crate::parse::SourceFile;
use checksum::checksum;
use field::field;
use length::length;
use std::borrow::Cow;
use vfd_runtime::{ChecksumAlgorithm, Format, Part, Role};
use word::word;

const FORMATS_HINT: &str =
    "use decimal, hex, char, u8, u16be, u16le, u32be, u32le, uint_be, uint_le or bytes";

/// Where a part sits: its layout, its neighbours' names and the YAML path of its keys.
pub(super) struct PartContext<'a> {
    /// The layout's name.
    pub layout: &'a str,
    /// The part's index in the layout.
    pub index: usize,
    /// The names of the layout's parts, in order.
    pub names: &'a [String],
    /// YAML path of the part's mapping (`parts.sum`, `layouts.reply[3]`).
    pub path: &'a str,
    /// The protocol file.
    pub source: &'a SourceFile,
}

impl PartContext<'_> {
    /// A diagnostic at the part's key `key` (the part itself when empty).
    fn error(&self, key: &str, message: impl Into<String>) -> Diagnostic {
        let path = if key.is_empty() {
            self.path.to_owned()
        } else {
            format!("{}.{key}", self.path)
        };
        self.source.error(&path, message)
    }

    /// Reports a problem at the part's key `key` and gives `None`.
    fn fail<T>(
        &self,
        out: &mut Diagnostics,
        key: &str,
        message: impl Into<String>,
        hint: impl Into<String>,
    ) -> Option<T> {
        out.push(self.error(key, message).hint(hint));
        None
    }

    /// The index of the layout's part called `name`.
    fn position_of(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
}

/// The kind of a part, from the one key that names it.
enum PartKind<'m> {
    Literal(&'m str),
    LiteralHex(&'m str),
    Field(Role),
    Checksum(ChecksumAlgorithm),
    Word(Format),
    Length(Format),
}

/// Lowers one part; the first problem in it is reported.
pub(super) fn lower_part(
    name: &str,
    model: &PartModel,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<Part> {
    let kind = part_kind(model, context, out)?;
    let optional = optional_flag(model, context, out)?;
    match kind {
        PartKind::Literal(text) => Some(literal(name, text.as_bytes().to_vec(), optional)),
        PartKind::LiteralHex(hex) => {
            let bytes = match parse_hex(hex) {
                Ok(bytes) => bytes,
                Err(message) => {
                    return context.fail(
                        out,
                        "literal_hex",
                        message,
                        "write hex pairs separated by spaces, e.g. \"2F\"",
                    )
                }
            };
            Some(literal(name, bytes, optional))
        }
        PartKind::Word(format) => word(name, format, model, context, out),
        PartKind::Length(format) => length(name, format, model, context, out),
        PartKind::Checksum(algorithm) => checksum(name, algorithm, model, optional, context, out),
        PartKind::Field(role) => field(name, role, model, context, out),
    }
}

/// The part's kind: exactly one of `literal`, `literal_hex`, `field`, `checksum`, `word` and
/// `length` must be given.
fn part_kind<'m>(
    model: &'m PartModel,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<PartKind<'m>> {
    let given = [
        model.literal.as_deref().map(PartKind::Literal),
        model.literal_hex.as_deref().map(PartKind::LiteralHex),
        model.field.map(PartKind::Field),
        model.checksum.map(PartKind::Checksum),
        model.word.map(PartKind::Word),
        model.length.map(PartKind::Length),
    ];
    let mut given = given.into_iter().flatten();
    match (given.next(), given.next()) {
        (Some(kind), None) => Some(kind),
        _ => context.fail(
            out,
            "",
            "a part must be exactly one of `literal`, `literal_hex`, `field`, `checksum`, `word` or `length`",
            "e.g. { literal: \"(\" } or { field: register, format: hex, width: 4 }",
        ),
    }
}

/// Whether a literal or checksum may be left out. Presence rules make sense only for
/// fields, which are decided by their value.
fn optional_flag(
    model: &PartModel,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<bool> {
    match model.optional {
        None | Some(OptionalModel::Flag(false)) => Some(false),
        Some(OptionalModel::Flag(true)) => Some(true),
        Some(_) if model.field.is_some() => Some(true),
        Some(rule) => {
            let rule = match rule {
                OptionalModel::IfByteAtMost(_) => "{ if_byte_at_most: ... }",
                _ => "if_format_matches",
            };
            context.fail(
                out,
                "optional",
                format!("`optional: {rule}` is a rule for fields; a literal or checksum is optional with `optional: true`"),
                "write optional: true",
            )
        }
    }
}

fn literal(name: &str, bytes: Vec<u8>, optional: bool) -> Part {
    Part::Literal {
        name: Cow::Owned(name.to_owned()),
        bytes: Cow::Owned(bytes),
        optional,
    }
}

/// The `format` a checksum or field needs.
fn required_format(
    model: &PartModel,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<Format> {
    if model.format.is_none() {
        return context.fail(out, "", "this part needs a `format`", FORMATS_HINT);
    }
    model.format
}

/// The values of `allowed` codes, or the first that is neither a number nor one character.
fn codes(models: &[CodeModel]) -> Result<Vec<u32>, String> {
    models
        .iter()
        .map(|m| m.value().ok_or_else(|| m.shown()))
        .collect()
}

/// Parses `"15:12"` or `"7"` into (lsb, width).
pub(super) fn parse_bits(text: &str) -> Option<(u8, u8)> {
    match text.split_once(':') {
        Some((msb, lsb)) => {
            let (msb, lsb): (u8, u8) = (msb.trim().parse().ok()?, lsb.trim().parse().ok()?);
            Some((lsb, msb.checked_sub(lsb)?.checked_add(1)?))
        }
        None => text.trim().parse().ok().map(|bit| (bit, 1)),
    }
}

/// Parses `"2F 50 FA"` (spaces optional between pairs).
pub fn parse_hex(text: &str) -> Result<Vec<u8>, String> {
    let digits: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    if !digits.len().is_multiple_of(2) {
        return Err(format!("`{text}` has an odd number of hex digits"));
    }
    (0..digits.len())
        .step_by(2)
        .map(|i| {
            u8::from_str_radix(&digits[i..i + 2], 16)
                .map_err(|_| format!("`{}` in `{text}` is not a hex byte", &digits[i..i + 2]))
        })
        .collect()
}
