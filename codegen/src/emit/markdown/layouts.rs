//! Frame layouts in words: one table row per part (what it is, how it is encoded, its size,
//! when it is present), for the reference pages.

use crate::emit::words::{hex, shown_bytes};
use serde::Serialize;
use vfd_runtime::layout::{Format, Part, Presence, Role};

/// A part of a layout, described for people.
#[derive(Debug, Clone, Serialize)]
pub(super) struct PartView {
    /// Its name.
    pub name: String,
    /// Literal, field (role), checksum (algorithm), bit-field word or length.
    pub kind: String,
    /// How it is written on the wire.
    pub encoding: String,
    /// Bytes or digits.
    pub size: String,
    /// When it is present (empty: always).
    pub optional: String,
    /// Allowed values, what a length counts, what a checksum covers.
    pub notes: String,
}

/// One part of a layout, in words. `used`: the command codes the drive's commands put in
/// this layout (empty: unknown, every code the layout allows is shown); a command field
/// lists only those, so a shared layout does not offer functions the drive lacks.
pub(super) fn part_view(part: &Part, parts: &[Part], used: &[u32]) -> PartView {
    match part {
        Part::Literal {
            name,
            bytes,
            optional,
        } => PartView {
            name: name.to_string(),
            kind: "literal".into(),
            encoding: if bytes.iter().all(|b| b.is_ascii_graphic()) {
                format!("`{}` ({})", hex(bytes), quoted(bytes))
            } else {
                format!("`{}`", hex(bytes))
            },
            size: format!("{}", bytes.len()),
            optional: if *optional {
                "optional".into()
            } else {
                String::new()
            },
            notes: String::new(),
        },
        Part::Field(field) => {
            let size = match (field.format.fixed_len(), field.sized_by) {
                (Some(len), vfd_runtime::SizedBy::Length) if field.role == Role::Words => {
                    format!("{len} per word, given by its length")
                }
                (Some(len), vfd_runtime::SizedBy::Rest) if field.role == Role::Words => {
                    format!("{len} per word, rest of the frame")
                }
                (Some(len), _) => len.to_string(),
                (None, vfd_runtime::SizedBy::Rest) => "rest of the frame".into(),
                (None, vfd_runtime::SizedBy::Length) => "given by its length".into(),
                (None, _) if field.min_width == field.width => field.width.to_string(),
                (None, _) => format!("{}–{}", field.min_width, field.width),
            };
            let allowed: Vec<String> = field
                .allowed
                .iter()
                .filter(|v| field.role != Role::Command || used.is_empty() || used.contains(v))
                .map(|v| match char::from_u32(*v) {
                    // Letters are shown as letters; binary codes (Modbus 01h) as hex.
                    Some(letter) if field.format == Format::Char && letter.is_ascii_graphic() => {
                        format!("`{letter}`")
                    }
                    _ => format!("{v:02X}h"),
                })
                .collect();
            let mut notes = Vec::new();
            if !allowed.is_empty() {
                notes.push(format!(
                    "one of {}{}",
                    allowed.join(", "),
                    if field.fold_case {
                        " (lower case: tripped)"
                    } else {
                        ""
                    }
                ));
            }
            PartView {
                name: field.name.to_string(),
                kind: format!("field ({})", field.role.as_str()),
                encoding: describe_format(field.format),
                size,
                optional: match field.optional {
                    None => String::new(),
                    Some(Presence::IfFormatMatches) => {
                        "optional (present when the next byte fits)".into()
                    }
                    Some(Presence::IfByteAtMost(limit)) => {
                        format!("optional (present when the next byte ≤ {limit:02X}h)")
                    }
                },
                notes: notes.join("; "),
            }
        }
        Part::Word(word) => PartView {
            name: word.name.to_string(),
            kind: "bit-field word".into(),
            encoding: describe_format(word.format),
            size: word.format.fixed_len().unwrap_or(0).to_string(),
            optional: String::new(),
            notes: word
                .fields
                .iter()
                .map(|bits| {
                    let span = if bits.width == 1 {
                        format!("bit {}", bits.lsb)
                    } else {
                        format!("bits {}:{}", bits.lsb + bits.width - 1, bits.lsb)
                    };
                    let allowed: Vec<String> =
                        bits.allowed.iter().map(|v| format!("{v:X}h")).collect();
                    let allowed = if allowed.is_empty() {
                        String::new()
                    } else {
                        format!(", one of {}", allowed.join(", "))
                    };
                    format!("{span}: {} ({}){allowed}", bits.name, bits.role.as_str())
                })
                .collect::<Vec<_>>()
                .join("; "),
        },
        Part::Length(length) => PartView {
            name: length.name.to_string(),
            kind: "length".into(),
            encoding: describe_format(length.format),
            size: length.format.fixed_len().unwrap_or(0).to_string(),
            optional: String::new(),
            notes: {
                let counted = match length.counts {
                    vfd_runtime::Counts::Parts { from, through } if from == through => {
                        format!(
                            "bytes of `{}`",
                            parts.get(usize::from(from)).map(|p| p.name()).unwrap_or("")
                        )
                    }
                    vfd_runtime::Counts::Parts { from, through } => format!(
                        "bytes from `{}` through `{}`",
                        parts.get(usize::from(from)).map(|p| p.name()).unwrap_or(""),
                        parts
                            .get(usize::from(through))
                            .map(|p| p.name())
                            .unwrap_or("")
                    ),
                    vfd_runtime::Counts::DataSize => "bytes of the requested data".to_owned(),
                };
                match (length.times, length.per) {
                    (1, 1) => format!("computed: {counted}"),
                    (times, 1) => format!("computed: {counted} × {times}"),
                    (1, per) => format!("computed: {counted} ÷ {per}"),
                    (times, per) => format!("computed: {counted} × {times} ÷ {per}"),
                }
            },
        },
        Part::Checksum(spec) => PartView {
            name: spec.name.to_string(),
            kind: format!("checksum ({})", spec.algorithm.as_str()),
            encoding: describe_format(spec.format),
            // Two hex digits, or the binary format's own size (CRC-16: 2 bytes).
            size: vfd_runtime::layout::checksum_size(spec.format).to_string(),
            optional: if spec.optional {
                "optional".into()
            } else {
                String::new()
            },
            notes: format!(
                "{}covers `{}` through {}",
                if spec.marker.is_empty() {
                    String::new()
                } else {
                    format!("announced by {}; ", quoted(&spec.marker))
                },
                parts
                    .get(usize::from(spec.covers_from))
                    .map(|p| p.name().to_owned())
                    .unwrap_or_default(),
                match spec.covers_through.and_then(|t| parts.get(usize::from(t))) {
                    Some(last) => format!("`{}` (the parts after it are not summed)", last.name()),
                    None => "the byte before the sum".to_owned(),
                }
            ),
        },
    }
}

fn describe_format(format: Format) -> String {
    match format {
        Format::Decimal => "ASCII decimal digits".into(),
        Format::Hex => "ASCII hex digits".into(),
        Format::Char => "ASCII character".into(),
        Format::U8 => "byte".into(),
        Format::U16Be => "16-bit word, high byte first".into(),
        Format::U16Le => "16-bit word, low byte first".into(),
        Format::U32Be => "32-bit double word, high byte first".into(),
        Format::U32Le => "32-bit double word, low byte first".into(),
        Format::UintBe => "unsigned integer, high byte first".into(),
        Format::UintLe => "unsigned integer, low byte first (byte-swapped)".into(),
        Format::Bytes => "raw bytes (text)".into(),
    }
}

/// Bytes for people, in backticks.
fn quoted(bytes: &[u8]) -> String {
    format!("`{}`", shown_bytes(bytes))
}
