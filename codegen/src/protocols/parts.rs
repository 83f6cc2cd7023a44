//! Parts: one entry of a layout lowered into a runtime [`Part`], one function per kind
//! (literal, hex literal, word of bit fields, length, checksum, field).

use crate::diagnostics::{Diagnostic, Diagnostics};
use crate::parse::model::{BitsModel, CodeModel, CountsModel, OptionalModel, PartModel};
use crate::parse::SourceFile;
use std::borrow::Cow;
use vfd_runtime::{
    BitsSpec, BroadcastAddress, ChecksumAlgorithm, ChecksumSpec, Counts, FieldSpec, Format,
    LengthSpec, Part, Presence, Role, SizedBy, WordSpec,
};

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

/// A word of bit fields (`word: u16be` with `fields:`).
fn word(
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

/// A computed length (`length: u8` with `counts:`).
fn length(
    name: &str,
    format: Format,
    model: &PartModel,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<Part> {
    if !matches!(format, Format::U8 | Format::U16Be) {
        return context.fail(
            out,
            "length",
            format!("`length: {}` is not a length format", format.as_str()),
            "use u8 or u16be",
        );
    };
    let counts = match &model.counts {
        Some(CountsModel::DataSize) => Counts::DataSize,
        Some(CountsModel::Parts { from, through }) => counted_parts(from, through, context, out)?,
        None => {
            return context.fail(
                out,
                "counts",
                "a length needs `counts: { from: part, through: part }` or `counts: data_size`",
                "FC LGE: { from: addr, through: bcc }",
            )
        }
    };
    Some(Part::Length(LengthSpec {
        name: Cow::Owned(name.to_owned()),
        format,
        counts,
        times: model.times.unwrap_or(1),
        per: model.per.unwrap_or(1).max(1),
    }))
}

/// `counts: { from, through }`: two later parts of the layout, `from` first.
fn counted_parts(
    from: &str,
    through: &str,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<Counts> {
    let from_index = context.position_of(from).filter(|i| *i > context.index);
    let through_index = context
        .position_of(through)
        .filter(|i| Some(*i) >= from_index);
    if let (Some(from), Some(through)) = (from_index, through_index) {
        return Some(Counts::Parts {
            from: from as u8,
            through: through as u8,
        });
    }
    let layout = context.layout;
    let unknown: Vec<String> = [from, through]
        .into_iter()
        .filter(|n| context.position_of(n).is_none())
        .map(|n| format!("`{n}`"))
        .collect();
    let why = if unknown.is_empty() {
        "they must be later parts, `from` before `through`".to_owned()
    } else {
        format!(
            "layout `{layout}` has no part named {}",
            unknown.join(" or ")
        )
    };
    context.fail(
        out,
        "counts",
        format!("in layout `{layout}`, `counts: {{ from: {from}, through: {through} }}` does not fit: {why}"),
        format!("parts of layout `{layout}`: {}", context.names.join(", ")),
    )
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

/// A checksum (`checksum: sum8` with `format` and `covers_from`).
fn checksum(
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

/// A value field (`field: register` with `format` and, for digits, `width`).
fn field(
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

/// A station field's broadcast encodings: `literal` text or a `value` addressing every
/// station, and a `wildcard` character for groups (digit formats of fixed width only).
fn broadcast_address(
    model: &crate::parse::model::BroadcastAddressModel,
    role: Role,
    format: Format,
    width: u8,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<BroadcastAddress> {
    if role != Role::Address {
        return context.fail(
            out,
            "broadcast",
            format!(
                "`broadcast` belongs on the station address field, not on a {} field",
                role.as_str()
            ),
            "move it to the part with `field: address`",
        );
    }
    let all_bytes = model.literal.clone().unwrap_or_default().into_bytes();
    if model.literal.is_some() && model.value.is_some() {
        return context.fail(
            out,
            "broadcast",
            "`broadcast` gives both `literal` and `value`",
            "every station is addressed either by text in the field's place or by one value",
        );
    }
    if model.literal.as_deref() == Some("") {
        return context.fail(
            out,
            "broadcast.literal",
            "the broadcast text is empty",
            "e.g. literal: \"**\"",
        );
    }
    if let Some(value) = model.value {
        let fits = match format.fixed_len() {
            Some(len @ 1..=3) => value < 1 << (8 * len),
            Some(_) => true,
            None if format.is_digits() => {
                let radix: u64 = if format == Format::Hex { 16 } else { 10 };
                u64::from(value) < radix.pow(u32::from(width))
            }
            None => value < 1 << (8 * u32::from(width.min(3))),
        };
        if !fits {
            return context.fail(
                out,
                "broadcast.value",
                format!(
                    "broadcast value {value:#X} does not fit the {} field",
                    format.as_str()
                ),
                "give the station value the manual names for a broadcast",
            );
        }
    }
    let wildcard = match model.wildcard.as_deref() {
        None => None,
        Some(text) => {
            let [byte] = text.as_bytes() else {
                return context.fail(
                    out,
                    "broadcast.wildcard",
                    format!("wildcard `{text}` is not one character"),
                    "e.g. wildcard: \"*\"",
                );
            };
            if !format.is_digits() || width == 0 || width > 7 || byte.is_ascii_hexdigit() {
                return context.fail(
                    out,
                    "broadcast.wildcard",
                    format!("a wildcard digit needs a decimal or hex station field of 1-7 digits and a character that is no digit, not `{text}` in a {} field", format.as_str()),
                    "group addressing leaves digits of a text station number open; binary fields cannot carry it",
                );
            }
            Some(*byte)
        }
    };
    if all_bytes.is_empty() && model.value.is_none() && wildcard.is_none() {
        return context.fail(
            out,
            "broadcast",
            "`broadcast` gives no encoding",
            "give `literal` (\"**\"), `value` (0xFF) or `wildcard` (\"*\")",
        );
    }
    Some(BroadcastAddress {
        all_bytes: Cow::Owned(all_bytes),
        all_value: model.value,
        wildcard,
    })
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

#[cfg(test)]
mod tests {
    use super::super::test_support::{at, lowered, parts, problems, protocol_with, PROTOCOL};
    use super::*;

    fn field(name: &str, role: Role, format: Format, width: u8) -> FieldSpec {
        FieldSpec {
            name: name.to_owned().into(),
            role,
            format,
            width,
            min_width: width,
            optional: None,
            allowed: Vec::new().into(),
            fold_case: false,
            sized_by: SizedBy::Format,
            broadcast: None,
        }
    }

    #[test]
    fn a_text_layout_lowers_to_literals_fields_and_a_checksum() {
        let protocol = lowered(PROTOCOL);
        let expected = vec![
            literal("start", b"(".to_vec(), false),
            Part::Field(FieldSpec {
                optional: Some(Presence::IfFormatMatches),
                ..field("address", Role::Address, Format::Decimal, 2)
            }),
            Part::Field(FieldSpec {
                allowed: vec![u32::from(b'R')].into(),
                ..field("command", Role::Command, Format::Char, 1)
            }),
            Part::Field(field("register", Role::Register, Format::Hex, 4)),
            Part::Checksum(ChecksumSpec {
                name: "sum".into(),
                algorithm: ChecksumAlgorithm::Sum8,
                format: Format::Hex,
                marker: b"&".to_vec().into(),
                covers_from: 0,
                covers_through: None,
                optional: true,
            }),
            literal("cr", b"\r".to_vec(), false),
        ];
        assert_eq!(parts(&protocol, "read_request"), expected.as_slice());
    }

    #[test]
    fn binary_parts_lower_to_a_length_a_word_and_a_hex_literal() {
        let yaml = protocol_with(&[
            ("text: true", "text: false"),
            (
                "  read_request: [start, address, { field: command, format: char, allowed: [R] }, register, sum, cr]",
                "  read_request:\n    - { literal_hex: \"02\", name: stx }\n    - { length: u8, name: lge, counts: { from: addr, through: bcc } }\n    - { field: address, name: addr, format: u8 }\n    - { word: u16be, name: pke, fields: [{ field: command, name: ak, bits: \"15:12\", allowed: [1] }, { field: register, name: pnu, bits: \"10:0\" }] }\n    - { field: data, format: uint_be, size: rest }\n    - { checksum: xor8, name: bcc, format: u8, covers_from: stx }",
            ),
            ("{ code: R, kind: read,", "{ code: 1, kind: read,"),
        ]);
        let protocol = lowered(&yaml);
        let parts = parts(&protocol, "read_request");
        assert_eq!(parts[0], literal("stx", vec![0x02], false));
        assert_eq!(
            parts[1],
            Part::Length(LengthSpec {
                name: "lge".into(),
                format: Format::U8,
                counts: Counts::Parts {
                    from: 2,
                    through: 5
                },
                times: 1,
                per: 1,
            })
        );
        let Part::Word(word) = &parts[3] else {
            panic!("not a word: {:?}", parts[3]);
        };
        assert_eq!(word.format, Format::U16Be);
        let bits: Vec<(&str, Role, u8, u8)> = word
            .fields
            .iter()
            .map(|b| (b.name.as_ref(), b.role, b.lsb, b.width))
            .collect();
        assert_eq!(
            bits,
            [("ak", Role::Command, 12, 4), ("pnu", Role::Register, 0, 11)]
        );
        assert_eq!(
            parts[4],
            Part::Field(FieldSpec {
                min_width: 1,
                sized_by: SizedBy::Rest,
                broadcast: None,
                ..field("data", Role::Data, Format::UintBe, 4)
            })
        );
        assert!(
            matches!(&parts[5], Part::Checksum(c) if c.algorithm == ChecksumAlgorithm::Xor8 && c.covers_from == 0)
        );
    }

    #[test]
    fn a_part_of_two_kinds_is_reported_at_the_part() {
        let yaml = protocol_with(&[(
            "cr: { literal: \"\\r\" }",
            "cr: { literal: \"\\r\", field: data }",
        )]);
        assert_eq!(
            problems(&yaml),
            [format!("{} parts.cr: a part must be exactly one of `literal`, `literal_hex`, `field`, `checksum`, `word` or `length`", at(&yaml, "cr: {"))]
        );
    }

    #[test]
    fn each_part_reports_its_first_problem_at_its_key() {
        let yaml = protocol_with(&[
            ("width: 2, optional", "width: 12, optional"),
            (
                "cr: { literal: \"\\r\" }",
                "cr: { literal: \"\\r\", optional: { if_byte_at_most: 3 } }",
            ),
            ("covers_from: start", "covers_from: cr"),
            (
                "{ field: data, format: hex, width: 4 }, sum, cr]\n  reply",
                "{ field: data, format: hex, width: 4, size: rest }, sum, cr]\n  reply",
            ),
        ]);
        assert_eq!(
            problems(&yaml),
            [
                format!("{} parts.address.width: `width: 12` is out of range for decimal", at(&yaml, "12")),
                format!("{} parts.sum.covers_from: `covers_from: cr` does not name an earlier part of the layout", at(&yaml, "cr, optional")),
                format!("{} parts.cr.optional: `optional: {{ if_byte_at_most: ... }}` is a rule for fields; a literal or checksum is optional with `optional: true`", at(&yaml, "optional: { if_byte_at_most")),
                format!("{} layouts.write_request[4].size: `size` applies to uint_be, uint_le and bytes fields, not hex", at(&yaml, "rest")),
            ]
        );
    }

    #[test]
    fn words_and_lengths_check_their_formats_and_bits() {
        let yaml = protocol_with(&[(
            "  read_request: [start, address, { field: command, format: char, allowed: [R] }, register, sum, cr]",
            "  read_request:\n    - start\n    - { word: u8, name: w1 }\n    - { word: u16be, name: w2, fields: [{ field: command, bits: \"15:8\" }, { field: register, bits: \"8:0\" }] }\n    - { length: u32be, counts: data_size }\n    - { length: u8, name: n }\n    - cr",
        )]);
        assert_eq!(
            problems(&yaml),
            [
                format!("{} layouts.read_request[1].word: `word: u8` is not a word format", at(&yaml, "u8, name: w1")),
                format!("{} layouts.read_request[2].fields[1].bits: bit field `register` overlaps an earlier field of word `w2`", at(&yaml, "\"8:0\"")),
                format!("{} layouts.read_request[3].length: `length: u32be` is not a length format", at(&yaml, "u32be")),
                format!("{} layouts.read_request[4].counts: a length needs `counts: {{ from: part, through: part }}` or `counts: data_size`", at(&yaml, "length: u8, name: n")),
            ]
        );
    }

    #[test]
    fn a_misspelt_value_is_reported_at_its_key() {
        let yaml = protocol_with(&[(
            "format: hex, width: 4 }, sum, cr]\n  error",
            "format: u16bee, width: 4 }, sum, cr]\n  error",
        )]);
        assert_eq!(
            problems(&yaml),
            [format!(
                "{} layouts.reply[4].format: unknown value `u16bee`",
                at(&yaml, "u16bee")
            )]
        );
        let yaml = protocol_with(&[("optional: if_format_matches", "optional: sometimes")]);
        assert_eq!(
            problems(&yaml),
            [format!("{} parts.address.optional: invalid value: string \"sometimes\", expected true, false, `if_format_matches` or `{{ if_byte_at_most: N }}`", at(&yaml, "sometimes"))]
        );
        let yaml = protocol_with(&[("checksum: sum8", "checksum: sum16")]);
        assert_eq!(
            problems(&yaml),
            [format!(
                "{} parts.sum.checksum: unknown value `sum16`",
                at(&yaml, "sum16")
            )]
        );
    }

    #[test]
    fn counts_name_what_is_wrong_with_them() {
        let yaml = protocol_with(&[(
            "register, sum, cr]\n  write",
            "register, { length: u8, counts: bytes }, sum, cr]\n  write",
        )]);
        assert_eq!(
            problems(&yaml),
            [format!("{} layouts.read_request[4].counts: invalid value: string \"bytes\", expected `data_size` or `{{ from: part, through: part }}`", at(&yaml, "bytes"))]
        );
        let yaml = protocol_with(&[(
            "register, sum, cr]\n  write",
            "register, { length: u8, counts: { from: sum } }, sum, cr]\n  write",
        )]);
        assert_eq!(
            problems(&yaml),
            [format!(
                "{} layouts.read_request[4].counts: missing key `through`",
                at(&yaml, "counts: { from: sum }")
            )]
        );
    }

    #[test]
    fn bits_and_hex_parse() {
        assert_eq!(parse_bits("15:12"), Some((12, 4)));
        assert_eq!(parse_bits(" 7 "), Some((7, 1)));
        assert_eq!(parse_bits("3:4"), None);
        assert_eq!(parse_bits("255:0"), None);
        assert_eq!(parse_bits("x"), None);
        assert_eq!(parse_hex("2F 50fa"), Ok(vec![0x2F, 0x50, 0xFA]));
        assert_eq!(
            parse_hex("2F5"),
            Err("`2F5` has an odd number of hex digits".to_owned())
        );
        assert_eq!(
            parse_hex("2G"),
            Err("`2G` in `2G` is not a hex byte".to_owned())
        );
    }
}
