//! Turns a protocol file plus a drive's error table and addressing into the runtime's
//! [`Protocol`]: the layouts the generated code embeds and the validator decodes examples with.

use crate::diagnostics::Diagnostic;
use crate::model::{DriveFile, OptionalModel, PartModel, PartRefModel, ProtocolFile};
use crate::parse::SourceFile;
use std::borrow::Cow;
use vfd_runtime::layout::MAX_PARTS;
use vfd_runtime::{
    ChecksumAlgorithm, ChecksumSpec, CommandKind, CommandSpec, ErrorCodeInfo, FieldSpec, Format,
    FrameLayout, Part, Presence, Protocol, Role,
};

/// Parses a format name.
pub fn format_from_name(name: &str) -> Option<Format> {
    [
        Format::Decimal,
        Format::Hex,
        Format::Char,
        Format::U8,
        Format::U16Be,
        Format::U16Le,
    ]
    .into_iter()
    .find(|format| format.as_str() == name)
}

/// Parses a role name.
pub fn role_from_name(name: &str) -> Option<Role> {
    [
        Role::Address,
        Role::Command,
        Role::Register,
        Role::Data,
        Role::ErrorCode,
    ]
    .into_iter()
    .find(|role| role.as_str() == name)
}

/// Parses a command kind.
pub fn kind_from_name(name: &str) -> Option<CommandKind> {
    [
        CommandKind::Read,
        CommandKind::WriteRam,
        CommandKind::WritePersistent,
    ]
    .into_iter()
    .find(|kind| kind.as_str() == name)
}

/// Builds the runtime protocol; every problem in the protocol file is reported.
pub fn build_protocol(
    id: &str,
    file: &ProtocolFile,
    source: &SourceFile,
    drive: &DriveFile,
) -> Result<Protocol, Vec<Diagnostic>> {
    let mut problems = Vec::new();
    let mut layouts: Vec<(String, FrameLayout)> = Vec::new();
    for (name, entries) in &file.layouts {
        match build_layout(name, entries, file, source) {
            Ok(layout) => layouts.push((name.clone(), layout)),
            Err(mut more) => problems.append(&mut more),
        }
    }
    let find = |name: &str, path: &str, problems: &mut Vec<Diagnostic>| -> Option<FrameLayout> {
        let found = layouts
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, l)| l.clone());
        if found.is_none() && file.layouts.contains_key(name) {
            return None; // Already reported while building it.
        }
        if found.is_none() {
            problems.push(
                source
                    .error(path, format!("layout `{name}` is not defined"))
                    .hint(format!(
                        "define it under `layouts:`; defined: {}",
                        names(file.layouts.keys())
                    )),
            );
        }
        found
    };
    let mut commands = Vec::new();
    for (index, command) in file.commands.iter().enumerate() {
        let path = format!("commands[{index}]");
        let letter = match command.letter.as_bytes() {
            [byte] if byte.is_ascii_graphic() => Some(*byte),
            _ => {
                problems.push(
                    source
                        .error(
                            &format!("{path}.letter"),
                            format!(
                                "command letter `{}` is not one ASCII character",
                                command.letter
                            ),
                        )
                        .hint("write the letter as it appears on the wire, e.g. R"),
                );
                None
            }
        };
        let kind = kind_from_name(&command.kind);
        if kind.is_none() {
            problems.push(
                source
                    .error(
                        &format!("{path}.kind"),
                        format!("unknown command kind `{}`", command.kind),
                    )
                    .hint("use read, write_ram or write_persistent"),
            );
        }
        let request = find(&command.request, &format!("{path}.request"), &mut problems);
        let reply = find(&command.reply, &format!("{path}.reply"), &mut problems);
        if let (Some(letter), Some(kind), Some(request), Some(reply)) =
            (letter, kind, request, reply)
        {
            commands.push(CommandSpec {
                letter,
                kind,
                request,
                reply,
            });
        }
    }
    let error_reply = match &file.error_reply {
        Some(name) => find(name, "error_reply", &mut problems),
        None => None,
    };
    for (index, name) in file.protocol.default_optional_parts.iter().enumerate() {
        let known = layouts
            .iter()
            .any(|(_, layout)| layout.parts.iter().any(|part| part.name() == name.as_str()));
        if !known {
            problems.push(
                source
                    .error(
                        &format!("protocol.default_optional_parts[{index}]"),
                        format!("no layout has a part named `{name}`"),
                    )
                    .hint("name an optional part of the layouts (e.g. sum, end)"),
            );
        }
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    Ok(Protocol {
        id: Cow::Owned(id.to_owned()),
        name: Cow::Owned(file.protocol.name.clone()),
        commands: Cow::Owned(commands),
        error_reply,
        lowercase_means_tripped: file.protocol.lowercase_means_tripped,
        max_frame_len: file.protocol.max_frame_len,
        address_range: (drive.addressing.min, drive.addressing.max),
        default_optional_parts: Cow::Owned(
            file.protocol
                .default_optional_parts
                .iter()
                .map(|p| Cow::Owned(p.clone()))
                .collect(),
        ),
        error_codes: Cow::Owned(
            drive
                .error_codes
                .codes
                .iter()
                .map(|code| ErrorCodeInfo {
                    code: code.code as u16,
                    id: Cow::Owned(code.id.clone()),
                    name: Cow::Owned(code.name.clone()),
                    name_zh: Cow::Owned(code.name_zh.clone()),
                    meaning: Cow::Owned(code.meaning.clone()),
                })
                .collect(),
        ),
    })
}

fn names<'a>(names: impl Iterator<Item = &'a String>) -> String {
    names.map(String::as_str).collect::<Vec<_>>().join(", ")
}

fn build_layout(
    name: &str,
    entries: &[PartRefModel],
    file: &ProtocolFile,
    source: &SourceFile,
) -> Result<FrameLayout, Vec<Diagnostic>> {
    let mut problems = Vec::new();
    let mut parts: Vec<Part> = Vec::new();
    if entries.len() > MAX_PARTS {
        problems.push(
            source
                .error(
                    &format!("layouts.{name}"),
                    format!(
                        "layout `{name}` has {} parts; the runtime supports {MAX_PARTS}",
                        entries.len()
                    ),
                )
                .hint("merge fields or split the frame"),
        );
    }
    for (index, entry) in entries.iter().enumerate() {
        let entry_path = format!("layouts.{name}[{index}]");
        let (part_name, model, path) = match entry {
            PartRefModel::Named(part_name) => match file.parts.get(part_name) {
                Some(model) => (part_name.clone(), model, format!("parts.{part_name}")),
                None => {
                    problems.push(
                        source
                            .error(&entry_path, format!("part `{part_name}` is not defined"))
                            .hint(format!(
                                "define it under `parts:`; defined: {}",
                                names(file.parts.keys())
                            )),
                    );
                    continue;
                }
            },
            PartRefModel::Inline(model) => {
                let part_name = model
                    .field
                    .clone()
                    .or_else(|| model.checksum.clone())
                    .unwrap_or_else(|| format!("part{index}"));
                (part_name, model, entry_path.clone())
            }
        };
        match build_part(&part_name, model, &path, source, &parts, file, entries) {
            Ok(part) => parts.push(part),
            Err(problem) => problems.push(problem),
        }
    }
    if problems.is_empty() {
        Ok(FrameLayout {
            name: Cow::Owned(name.to_owned()),
            parts: Cow::Owned(parts),
        })
    } else {
        Err(problems)
    }
}

fn build_part(
    name: &str,
    model: &PartModel,
    path: &str,
    source: &SourceFile,
    earlier: &[Part],
    file: &ProtocolFile,
    entries: &[PartRefModel],
) -> Result<Part, Diagnostic> {
    let kinds = [
        model.literal.is_some(),
        model.literal_hex.is_some(),
        model.field.is_some(),
        model.checksum.is_some(),
    ];
    if kinds.iter().filter(|k| **k).count() != 1 {
        return Err(source
            .error(
                path,
                "a part must be exactly one of `literal`, `literal_hex`, `field` or `checksum`",
            )
            .hint("e.g. { literal: \"(\" } or { field: register, format: hex, width: 4 }"));
    }
    let optional_flag = match &model.optional {
        None | Some(OptionalModel::Flag(false)) => false,
        Some(_) => true,
    };
    if let Some(text) = &model.literal {
        return Ok(Part::Literal {
            name: Cow::Owned(name.to_owned()),
            bytes: Cow::Owned(text.as_bytes().to_vec()),
            optional: optional_flag,
        });
    }
    if let Some(hex) = &model.literal_hex {
        let bytes = parse_hex(hex).map_err(|message| {
            source
                .error(&format!("{path}.literal_hex"), message)
                .hint("write hex pairs separated by spaces, e.g. \"2F\"")
        })?;
        return Ok(Part::Literal {
            name: Cow::Owned(name.to_owned()),
            bytes: Cow::Owned(bytes),
            optional: optional_flag,
        });
    }
    let format_name = model.format.as_deref().unwrap_or("");
    let format = format_from_name(format_name).ok_or_else(|| {
        source
            .error(
                &format!("{path}.format"),
                format!("unknown format `{format_name}`"),
            )
            .hint("use decimal, hex, char, u8, u16be or u16le")
    })?;
    if let Some(algorithm) = &model.checksum {
        let algorithm = match algorithm.as_str() {
            "sum8" => ChecksumAlgorithm::Sum8,
            "xor8" => ChecksumAlgorithm::Xor8,
            other => {
                return Err(source
                    .error(
                        &format!("{path}.checksum"),
                        format!("unknown checksum algorithm `{other}`"),
                    )
                    .hint("the runtime supplies sum8 and xor8"))
            }
        };
        if !matches!(format, Format::Hex | Format::U8) {
            return Err(source
                .error(
                    &format!("{path}.format"),
                    "a checksum is written as `hex` (two digits) or `u8`",
                )
                .hint("use format: hex or format: u8"));
        }
        let from_name = model.covers_from.as_deref().unwrap_or("");
        let covers_from = entries
            .iter()
            .position(|entry| match entry {
                PartRefModel::Named(n) => n == from_name,
                PartRefModel::Inline(inline) => inline.field.as_deref() == Some(from_name),
            })
            .filter(|position| *position < earlier.len())
            .ok_or_else(|| {
                source
                    .error(&format!("{path}.covers_from"), format!("`covers_from: {from_name}` does not name an earlier part of the layout"))
                    .hint("name the first covered part, e.g. covers_from: start")
            })?;
        let marker = model.marker.clone().unwrap_or_default().into_bytes();
        if optional_flag && marker.is_empty() {
            return Err(source
                .error(
                    &format!("{path}.optional"),
                    "an optional checksum needs a `marker`",
                )
                .hint("the decoder can only tell it is there by its marker, e.g. marker: \"&\""));
        }
        let _ = file;
        return Ok(Part::Checksum(ChecksumSpec {
            name: Cow::Owned(name.to_owned()),
            algorithm,
            format,
            marker: Cow::Owned(marker),
            covers_from: covers_from as u8,
            optional: optional_flag,
        }));
    }
    let role_name = model.field.as_deref().unwrap_or("");
    let role = role_from_name(role_name).ok_or_else(|| {
        source
            .error(
                &format!("{path}.field"),
                format!("unknown field role `{role_name}`"),
            )
            .hint("use address, command, register, data or error_code")
    })?;
    let width = match (format.fixed_len(), model.width) {
        (Some(len), _) => len as u8,
        (None, Some(width)) if (1..=10).contains(&width) => width,
        (None, _) => {
            return Err(source
                .error(
                    &format!("{path}.width"),
                    "digit formats need a `width` from 1 to 10",
                )
                .hint("e.g. width: 4 for a 16-bit word in hex"))
        }
    };
    let min_width = model.min_width.unwrap_or(width);
    if min_width == 0 || min_width > width {
        return Err(source
            .error(
                &format!("{path}.min_width"),
                format!("min_width {min_width} must be from 1 to width {width}"),
            )
            .hint("leave it out for fixed-width fields"));
    }
    let optional = match &model.optional {
        None | Some(OptionalModel::Flag(false)) => None,
        Some(OptionalModel::Flag(true)) => Some(Presence::IfFormatMatches),
        Some(OptionalModel::Rule(rule)) if rule == "if_format_matches" => {
            Some(Presence::IfFormatMatches)
        }
        Some(OptionalModel::ByteAtMost { if_byte_at_most }) => {
            Some(Presence::IfByteAtMost(*if_byte_at_most))
        }
        Some(OptionalModel::Rule(rule)) => {
            return Err(source
                .error(
                    &format!("{path}.optional"),
                    format!("unknown presence rule `{rule}`"),
                )
                .hint("use true, if_format_matches or { if_byte_at_most: N }"))
        }
    };
    let mut allowed = Vec::new();
    for (index, value) in model.allowed.iter().enumerate() {
        match (format, value.as_bytes()) {
            (Format::Char, [byte]) => allowed.push(u32::from(*byte)),
            _ => {
                return Err(source
                    .error(
                        &format!("{path}.allowed[{index}]"),
                        format!("allowed value `{value}` is not a single character"),
                    )
                    .hint("`allowed` lists command letters of a char field"))
            }
        }
    }
    Ok(Part::Field(FieldSpec {
        name: Cow::Owned(name.to_owned()),
        role,
        format,
        width,
        min_width,
        optional,
        allowed: Cow::Owned(allowed),
        fold_case: model.fold_case,
    }))
}

/// Parses `"2F 50 FA"` (spaces optional between pairs).
pub fn parse_hex(text: &str) -> Result<Vec<u8>, String> {
    let digits: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    if digits.len() % 2 != 0 {
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
