//! Stage 3a, protocol lowering: turns each protocol file a drive uses, plus the drive's
//! error table, addressing, address maps and pre-steps, into the runtime's [`Protocol`]:
//! the value the generated code embeds and the example frames are decoded with. Problems in
//! a protocol file are reported here, with the protocol file's positions.

use crate::diagnostics::{Diagnostic, Diagnostics};
use crate::load::LoadedDrive;
use crate::parse::model::{
    CodeModel, CountsModel, DriveFile, OptionalModel, PartModel, PartRefModel, ProtocolFile,
    ProtocolRef,
};
use crate::parse::SourceFile;
use std::borrow::Cow;
use vfd_runtime::layout::MAX_PARTS;
use vfd_runtime::{
    AddressMap, BitsSpec, ChecksumAlgorithm, ChecksumSpec, CommandKind, CommandSpec, Counts,
    DataType, ErrorCodeInfo, FieldSpec, Format, FrameLayout, LengthSpec, Part, PreStep, Presence,
    Protocol, Role, SizedBy, Space, WordSpec,
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
        Format::U32Be,
        Format::U32Le,
        Format::UintBe,
        Format::UintLe,
        Format::Bytes,
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
        Role::Index,
        Role::Process1,
        Role::Process2,
        Role::Text,
    ]
    .into_iter()
    .find(|role| role.as_str() == name)
}

/// Parses a command kind.
pub fn kind_from_name(name: &str) -> Option<CommandKind> {
    CommandKind::ALL
        .into_iter()
        .find(|kind| kind.as_str() == name)
}

/// Parses a data type.
pub fn data_type_from_name(name: &str) -> Option<DataType> {
    DataType::ALL.into_iter().find(|t| t.as_str() == name)
}

/// Reads an optional address-space name (default: parameters), reporting an unknown one at `path`.
fn space_at(
    name: Option<&str>,
    source: &SourceFile,
    path: &str,
    problems: &mut Vec<Diagnostic>,
) -> Option<Space> {
    let Some(name) = name else {
        return Some(Space::Parameter);
    };
    let space = space_from_name(name);
    if space.is_none() {
        problems.push(
            source
                .error(path, format!("unknown address space `{name}`"))
                .hint("use parameter or coil"),
        );
    }
    space
}

/// Reads a data-type name, reporting an unknown one at `path`.
fn data_type_at(
    name: &str,
    source: &SourceFile,
    path: &str,
    problems: &mut Vec<Diagnostic>,
) -> Option<DataType> {
    let data_type = data_type_from_name(name);
    if data_type.is_none() {
        problems.push(
            source
                .error(path, format!("unknown data type `{name}`"))
                .hint("use word, double_word, bit or text"),
        );
    }
    data_type
}

/// Parses an address space.
pub fn space_from_name(name: &str) -> Option<Space> {
    [Space::Parameter, Space::Coil]
        .into_iter()
        .find(|s| s.as_str() == name)
}

/// A protocol as one drive uses it, lowered into the runtime's terms.
#[derive(Debug, Clone)]
pub(crate) struct LoweredProtocol {
    /// Id within the drive (`ascii`).
    pub id: String,
    /// Protocol file id (`toshiba-ascii`).
    pub uses: String,
    /// Manual section describing it.
    pub source_section: String,
    /// Its parsed protocol file.
    pub file: ProtocolFile,
    /// The runtime protocol built from it.
    pub runtime: Protocol,
}

/// Lowers every protocol file the drive refers to; problems go to `out`, and a protocol
/// with problems is left out.
pub(crate) fn lower(drive: &LoadedDrive, out: &mut Diagnostics) -> Vec<LoweredProtocol> {
    let mut lowered = Vec::new();
    for protocol in &drive.protocol_files {
        let reference = &drive.model.protocols[protocol.reference];
        let reference_path = format!("protocols[{}]", protocol.reference);
        match build_protocol(
            reference,
            &reference_path,
            &protocol.file,
            &protocol.source,
            &drive.source,
            &drive.model,
        ) {
            Ok(runtime) => lowered.push(LoweredProtocol {
                id: reference.id.clone(),
                uses: reference.uses.clone(),
                source_section: reference.source.clone(),
                file: protocol.file.clone(),
                runtime,
            }),
            Err(problems) => problems.into_iter().for_each(|p| out.push(p)),
        }
    }
    lowered
}

/// Builds the runtime protocol; every problem in the protocol file is reported.
fn build_protocol(
    reference: &ProtocolRef,
    reference_path: &str,
    file: &ProtocolFile,
    source: &SourceFile,
    drive_source: &SourceFile,
    drive: &DriveFile,
) -> Result<Protocol, Vec<Diagnostic>> {
    let id = reference.id.as_str();
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
                        names_of(file.layouts.keys())
                    )),
            );
        }
        found
    };
    let mut commands = Vec::new();
    for (index, command) in file.commands.iter().enumerate() {
        let path = format!("commands[{index}]");
        let code = match &command.code {
            None => Some(0),
            Some(code) => {
                match code.value() {
                    Some(value) => Some(value),
                    None => {
                        problems.push(
                        source
                            .error(&format!("{path}.code"), format!("command code `{}` is not one character or a number", code.shown()))
                            .hint("write a letter as it appears on the wire (R) or a number (0x03)"),
                    );
                        None
                    }
                }
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
                    .hint("use read, write_ram, write_persistent, read_text or process"),
            );
        }
        let data_types: Vec<DataType> = command
            .data_types
            .iter()
            .enumerate()
            .filter_map(|(i, name)| {
                data_type_at(
                    name,
                    source,
                    &format!("{path}.data_types[{i}]"),
                    &mut problems,
                )
            })
            .collect();
        let space = space_at(
            command.space.as_deref(),
            source,
            &format!("{path}.space"),
            &mut problems,
        );
        let reply_codes: Vec<u32> = command
            .reply_codes
            .iter()
            .filter_map(|c| c.value())
            .collect();
        if reply_codes.len() != command.reply_codes.len() {
            problems.push(
                source
                    .error(
                        &format!("{path}.reply_codes"),
                        "reply codes are numbers or single characters",
                    )
                    .hint("e.g. reply_codes: [1, 2]"),
            );
        }
        // The drive's own numbering for the command's space wins over the protocol file's.
        let drive_map = space.and_then(|space| reference.address_maps.get(space.as_str()));
        let address_map = drive_map
            .or(command.address_map.as_ref())
            .map(|m| AddressMap {
                multiply: m.multiply.max(1),
                offset: m.offset,
            })
            .unwrap_or(AddressMap::IDENTITY);
        let request = find(&command.request, &format!("{path}.request"), &mut problems);
        let reply = find(&command.reply, &format!("{path}.reply"), &mut problems);
        if let (Some(request), Some(_)) = (&request, &command.code) {
            if !request.has(Role::Command) {
                problems.push(
                    source
                        .error(&format!("{path}.code"), format!("layout `{}` has no command field to carry the code", command.request))
                        .hint("leave `code` out for commands whose layout has no command (process telegrams)"),
                );
            }
        }
        if let (Some(code), Some(kind), Some(space), Some(request), Some(reply)) =
            (code, kind, space, request, reply)
        {
            commands.push(CommandSpec {
                code,
                kind,
                data_types: Cow::Owned(data_types),
                space,
                address_map,
                request,
                reply,
                reply_codes: Cow::Owned(reply_codes),
            });
        }
    }
    for (key, map) in reference.address_maps.iter() {
        if map.multiply == 0 {
            problems.push(
                drive_source
                    .error(
                        &format!("{reference_path}.address_maps.{key}.multiply"),
                        "`multiply: 0` maps every register to the same wire address",
                    )
                    .hint("use 1 for numbers that go on the wire as they are"),
            );
        }
        if space_from_name(key).is_none() {
            problems.push(
                drive_source
                    .error(
                        &format!("{reference_path}.address_maps.{key}"),
                        format!("unknown address space `{key}`"),
                    )
                    .hint("use parameter or coil"),
            );
        }
    }
    check_commands(file, source, &commands, &mut problems);
    if file.protocol.text {
        check_text_protocol(&layouts, source, &mut problems);
    }
    if file.protocol.id != reference.uses {
        problems.push(
            source
                .error(
                    "protocol.id",
                    format!(
                        "the file is `{}.yaml` but says `id: {}`",
                        reference.uses, file.protocol.id
                    ),
                )
                .hint("make the id match the file name, which is how drive files refer to it"),
        );
    }
    let mut pre_steps = Vec::new();
    let steps = file
        .protocol
        .pre_steps
        .iter()
        .enumerate()
        .map(|(index, step)| (source, format!("protocol.pre_steps[{index}]"), step))
        .chain(reference.pre_steps.iter().enumerate().map(|(index, step)| {
            (
                drive_source,
                format!("{reference_path}.pre_steps[{index}]"),
                step,
            )
        }));
    for (source, path, step) in steps {
        match step.step.as_str() {
            "index" => pre_steps.push(PreStep::Index {
                register: step.register,
            }),
            "persistence" => {
                let space = space_at(
                    step.space.as_deref(),
                    source,
                    &format!("{path}.space"),
                    &mut problems,
                );
                let data_type = match step.data_type.as_deref() {
                    None => Some(DataType::Word),
                    Some(name) => {
                        data_type_at(name, source, &format!("{path}.data_type"), &mut problems)
                    }
                };
                let missing: Vec<&str> = [
                    ("ram", step.ram.is_none()),
                    ("persistent", step.persistent.is_none()),
                ]
                .into_iter()
                .filter_map(|(key, absent)| absent.then_some(key))
                .collect();
                if !missing.is_empty() {
                    problems.push(
                        source
                            .error(&path, format!("the persistence step lacks `{}`", missing.join("` and `")))
                            .hint("give the values that select RAM only and RAM + EEPROM, e.g. ram: 0x0000, persistent: 0xFF00"),
                    );
                }
                if let (Some(space), Some(data_type), Some(ram), Some(persistent)) =
                    (space, data_type, step.ram, step.persistent)
                {
                    pre_steps.push(PreStep::Persistence {
                        space,
                        register: step.register,
                        data_type,
                        ram,
                        persistent,
                    });
                }
            }
            other => problems.push(
                source
                    .error(&format!("{path}.step"), format!("unknown step `{other}`"))
                    .hint("use index or persistence"),
            ),
        }
    }
    let error_reply = match &file.error_reply {
        Some(name) => find(name, "error_reply", &mut problems),
        None => None,
    };
    for (index, name) in file.protocol.default_optional_parts.iter().enumerate() {
        // Judge by the names the layouts list, so a part that failed to build is not
        // reported a second time as missing.
        let known = file.layouts.values().any(|entries| {
            entries.iter().enumerate().any(|(i, entry)| match entry {
                PartRefModel::Named(key) => {
                    key == name || file.parts.get(key).and_then(|p| p.name.as_ref()) == Some(name)
                }
                PartRefModel::Inline(_) => entry_name(entry, i) == *name,
            })
        });
        let required = file.layouts.values().flatten().any(|entry| match entry {
            PartRefModel::Named(key) => {
                key == name
                    && file.parts.get(key).is_some_and(|p| {
                        matches!(p.optional, None | Some(OptionalModel::Flag(false)))
                            && p.field.is_none()
                    })
            }
            PartRefModel::Inline(_) => false,
        });
        if known && required {
            problems.push(
                source
                    .error(
                        &format!("protocol.default_optional_parts[{index}]"),
                        format!("part `{name}` is not optional; it is always sent"),
                    )
                    .hint("list only parts marked `optional: true`"),
            );
        }
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
        pre_steps: Cow::Owned(pre_steps),
        default_process: file.protocol.default_process.unwrap_or([0, 0]),
        frame_gap_chars: file.protocol.frame_gap_chars,
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

fn names_of<'a>(names: impl Iterator<Item = &'a String>) -> String {
    names.map(String::as_str).collect::<Vec<_>>().join(", ")
}

fn entry_name(entry: &PartRefModel, index: usize) -> String {
    match entry {
        PartRefModel::Named(name) => name.clone(),
        PartRefModel::Inline(model) => model
            .name
            .clone()
            .or_else(|| model.field.clone())
            .or_else(|| model.checksum.as_ref().map(|_| "checksum".to_owned()))
            .or_else(|| model.length.as_ref().map(|_| "length".to_owned()))
            .unwrap_or_else(|| format!("part{index}")),
    }
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
    let names: Vec<String> = entries
        .iter()
        .enumerate()
        .map(|(i, e)| entry_name(e, i))
        .collect();
    for (index, entry) in entries.iter().enumerate() {
        let entry_path = format!("layouts.{name}[{index}]");
        let (model, path) = match entry {
            PartRefModel::Named(part_name) => match file.parts.get(part_name) {
                Some(model) => (model, format!("parts.{part_name}")),
                None => {
                    problems.push(
                        source
                            .error(&entry_path, format!("part `{part_name}` is not defined"))
                            .hint(format!(
                                "define it under `parts:`; defined: {}",
                                names_of(file.parts.keys())
                            )),
                    );
                    continue;
                }
            },
            PartRefModel::Inline(model) => (&**model, entry_path.clone()),
        };
        let name_of_part = match entry {
            PartRefModel::Named(key) => model.name.clone().unwrap_or_else(|| key.clone()),
            PartRefModel::Inline(_) => names[index].clone(),
        };
        let context = PartContext {
            layout: name,
            index,
            names: &names,
            path: &path,
            source,
        };
        match build_part(&name_of_part, model, &context) {
            Ok(part) => parts.push(part),
            Err(problem) => problems.push(problem),
        }
    }
    if problems.is_empty() {
        let layout = FrameLayout {
            name: Cow::Owned(name.to_owned()),
            parts: Cow::Owned(parts),
        };
        check_sizes(&layout, name, source).map_err(|p| vec![p])?;
        Ok(layout)
    } else {
        Err(problems)
    }
}

/// Every variable-size field can be sized when decoding.
fn check_sizes(layout: &FrameLayout, name: &str, source: &SourceFile) -> Result<(), Diagnostic> {
    for (index, part) in layout.parts.iter().enumerate() {
        let Part::Field(field) = part else { continue };
        let path = format!("layouts.{name}[{index}]");
        match field.sized_by {
            SizedBy::Rest => {
                let framed = layout.parts[..index].iter().any(|p| {
                    matches!(p, Part::Length(LengthSpec { counts: Counts::Parts { through, .. }, .. }) if usize::from(*through) + 1 == layout.parts.len())
                });
                let tail_fixed = layout.parts[index + 1..]
                    .iter()
                    .all(|p| p.fixed_size().is_some());
                if !framed || !tail_fixed {
                    return Err(source
                        .error(&path, format!("`{}` takes the rest of the frame, but no earlier length covers the frame to its end, or a later part has no fixed size", field.name))
                        .hint("put a length counting `from` the next part `through` the last part before it, and only fixed-size parts after it"));
                }
            }
            SizedBy::Length => {
                let covered = layout.parts[..index].iter().any(|p| {
                    matches!(p, Part::Length(LengthSpec { counts: Counts::Parts { from, through }, .. }) if usize::from(*from) == index && from == through)
                });
                if !covered {
                    return Err(source
                        .error(&path, format!("`{}` is sized by a length, but no earlier length covers exactly it", field.name))
                        .hint("add a length part with counts: { from: this, through: this } before it"));
                }
            }
            SizedBy::Format => {}
        }
    }
    Ok(())
}

struct PartContext<'a> {
    layout: &'a str,
    index: usize,
    names: &'a [String],
    path: &'a str,
    source: &'a SourceFile,
}

impl PartContext<'_> {
    fn error(&self, key: &str, message: impl Into<String>) -> Diagnostic {
        let path = if key.is_empty() {
            self.path.to_owned()
        } else {
            format!("{}.{key}", self.path)
        };
        self.source.error(&path, message)
    }

    fn position_of(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
}

fn build_part(
    name: &str,
    model: &PartModel,
    context: &PartContext<'_>,
) -> Result<Part, Diagnostic> {
    let kinds = [
        model.literal.is_some(),
        model.literal_hex.is_some(),
        model.field.is_some(),
        model.checksum.is_some(),
        model.word.is_some(),
        model.length.is_some(),
    ];
    if kinds.iter().filter(|k| **k).count() != 1 {
        return Err(context
            .error("", "a part must be exactly one of `literal`, `literal_hex`, `field`, `checksum`, `word` or `length`")
            .hint("e.g. { literal: \"(\" } or { field: register, format: hex, width: 4 }"));
    }
    let optional_flag = match &model.optional {
        None | Some(OptionalModel::Flag(false)) => false,
        Some(OptionalModel::Flag(true)) => true,
        // Presence rules only make sense for fields, which are decided by their value.
        Some(rule) if model.field.is_none() => {
            return Err(context
                .error("optional", format!("`optional: {}` is a rule for fields; a literal or checksum is optional with `optional: true`", match rule {
                    OptionalModel::Rule(text) => text.clone(),
                    _ => "{ if_byte_at_most: ... }".to_owned(),
                }))
                .hint("write optional: true"))
        }
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
            context
                .error("literal_hex", message)
                .hint("write hex pairs separated by spaces, e.g. \"2F\"")
        })?;
        return Ok(Part::Literal {
            name: Cow::Owned(name.to_owned()),
            bytes: Cow::Owned(bytes),
            optional: optional_flag,
        });
    }
    if let Some(format_name) = &model.word {
        let format = format_from_name(format_name)
            .filter(|f| {
                matches!(
                    f,
                    Format::U16Be | Format::U16Le | Format::U32Be | Format::U32Le
                )
            })
            .ok_or_else(|| {
                context
                    .error(
                        "word",
                        format!("`word: {format_name}` is not a word format"),
                    )
                    .hint("use u16be, u16le, u32be or u32le")
            })?;
        let word_bits = if matches!(format, Format::U16Be | Format::U16Le) {
            16
        } else {
            32
        };
        let mut fields = Vec::new();
        for (index, bits) in model.fields.iter().enumerate() {
            let key = format!("fields[{index}]");
            let role = role_from_name(&bits.field).ok_or_else(|| {
                context
                    .error(
                        &format!("{key}.field"),
                        format!("unknown field role `{}`", bits.field),
                    )
                    .hint(ROLES_HINT)
            })?;
            let (lsb, width) = parse_bits(&bits.bits)
                .filter(|(lsb, width)| u32::from(*lsb) + u32::from(*width) <= word_bits)
                .ok_or_else(|| {
                    context
                        .error(
                            &format!("{key}.bits"),
                            format!(
                                "`bits: {}` is not \"msb:lsb\" within the {word_bits}-bit word",
                                bits.bits
                            ),
                        )
                        .hint("e.g. bits: \"15:12\"")
                })?;
            let allowed = codes(&bits.allowed).map_err(|shown| {
                context
                    .error(
                        &format!("{key}.allowed"),
                        format!("`{shown}` is not a number or one character"),
                    )
                    .hint("e.g. allowed: [1, 2]")
            })?;
            fields.push(BitsSpec {
                name: Cow::Owned(bits.name.clone().unwrap_or_else(|| bits.field.clone())),
                role,
                lsb,
                width,
                allowed: Cow::Owned(allowed),
            });
        }
        let mut used = 0u32;
        for (index, field) in fields.iter().enumerate() {
            if used & field.mask() != 0 {
                return Err(context
                    .error(
                        &format!("fields[{index}].bits"),
                        format!(
                            "bit field `{}` overlaps an earlier field of word `{name}`",
                            field.name
                        ),
                    )
                    .hint("the bit fields of a word must not share bits"));
            }
            used |= field.mask();
        }
        return Ok(Part::Word(WordSpec {
            name: Cow::Owned(name.to_owned()),
            format,
            fields: Cow::Owned(fields),
        }));
    }
    if let Some(format_name) = &model.length {
        let format = format_from_name(format_name)
            .filter(|f| matches!(f, Format::U8 | Format::U16Be))
            .ok_or_else(|| {
                context
                    .error(
                        "length",
                        format!("`length: {format_name}` is not a length format"),
                    )
                    .hint("use u8 or u16be")
            })?;
        let counts = match &model.counts {
            Some(CountsModel::Keyword(word)) if word == "data_size" => Counts::DataSize,
            Some(CountsModel::Parts { from, through }) => {
                let from_index = context.position_of(from).filter(|i| *i > context.index);
                let through_index = context
                    .position_of(through)
                    .filter(|i| Some(*i) >= from_index);
                match (from_index, through_index) {
                    (Some(from), Some(through)) => Counts::Parts {
                        from: from as u8,
                        through: through as u8,
                    },
                    _ => {
                        let unknown: Vec<&str> = [from.as_str(), through.as_str()]
                            .into_iter()
                            .filter(|n| context.position_of(n).is_none())
                            .collect();
                        let why = if unknown.is_empty() {
                            "they must be later parts, `from` before `through`".to_owned()
                        } else {
                            format!(
                                "layout `{}` has no part named {}",
                                context.layout,
                                unknown
                                    .iter()
                                    .map(|n| format!("`{n}`"))
                                    .collect::<Vec<_>>()
                                    .join(" or ")
                            )
                        };
                        return Err(context
                            .error("counts", format!("in layout `{}`, `counts: {{ from: {from}, through: {through} }}` does not fit: {why}", context.layout))
                            .hint(format!("parts of layout `{}`: {}", context.layout, context.names.join(", "))));
                    }
                }
            }
            _ => return Err(context
                .error(
                    "counts",
                    "a length needs `counts: { from: part, through: part }` or `counts: data_size`",
                )
                .hint("FC LGE: { from: addr, through: bcc }")),
        };
        return Ok(Part::Length(LengthSpec {
            name: Cow::Owned(name.to_owned()),
            format,
            counts,
            times: model.times.unwrap_or(1),
            per: model.per.unwrap_or(1).max(1),
        }));
    }
    let Some(format_name) = model.format.as_deref() else {
        return Err(context.error("", "this part needs a `format`").hint(
            "use decimal, hex, char, u8, u16be, u16le, u32be, u32le, uint_be, uint_le or bytes",
        ));
    };
    let format = format_from_name(format_name).ok_or_else(|| {
        context
            .error("format", format!("unknown format `{format_name}`"))
            .hint(
                "use decimal, hex, char, u8, u16be, u16le, u32be, u32le, uint_be, uint_le or bytes",
            )
    })?;
    if let Some(algorithm) = &model.checksum {
        let algorithm = match algorithm.as_str() {
            "sum8" => ChecksumAlgorithm::Sum8,
            "xor8" => ChecksumAlgorithm::Xor8,
            "crc16_modbus" => ChecksumAlgorithm::Crc16Modbus,
            "lrc8" => ChecksumAlgorithm::Lrc8,
            other => {
                return Err(context
                    .error("checksum", format!("unknown checksum algorithm `{other}`"))
                    .hint("the runtime supplies sum8, xor8, crc16_modbus and lrc8"))
            }
        };
        let fits = match algorithm {
            ChecksumAlgorithm::Crc16Modbus => matches!(format, Format::U16Le | Format::U16Be),
            _ => matches!(format, Format::Hex | Format::U8),
        };
        if !fits {
            return Err(context
                .error(
                    "format",
                    format!(
                        "a {} checksum cannot be written as {}",
                        algorithm.as_str(),
                        format.as_str()
                    ),
                )
                .hint("8-bit sums: hex (two digits) or u8; crc16_modbus: u16le (Modbus sends the low byte first) or u16be"));
        }
        let from_name = model.covers_from.as_deref().unwrap_or("");
        let covers_from = context.position_of(from_name).filter(|position| *position < context.index).ok_or_else(|| {
            context
                .error("covers_from", format!("`covers_from: {from_name}` does not name an earlier part of the layout"))
                .hint("name the first covered part, e.g. covers_from: start")
        })?;
        let marker = model.marker.clone().unwrap_or_default().into_bytes();
        if optional_flag && marker.is_empty() {
            return Err(context
                .error("optional", "an optional checksum needs a `marker`")
                .hint("the decoder can only tell it is there by its marker, e.g. marker: \"&\""));
        }
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
        context
            .error("field", format!("unknown field role `{role_name}`"))
            .hint(ROLES_HINT)
    })?;
    let sized_by = match model.size.as_deref() {
        None => SizedBy::Format,
        Some("rest") => SizedBy::Rest,
        Some("length") => SizedBy::Length,
        Some(other) => {
            return Err(context
                .error("size", format!("unknown size rule `{other}`"))
                .hint("use rest or length, or leave `size` out"))
        }
    };
    let variable = matches!(format, Format::UintBe | Format::UintLe | Format::Bytes);
    let width = match (format.fixed_len(), model.width) {
        (Some(len), _) => len as u8,
        (None, Some(width)) if variable && (1..=255).contains(&width) => width,
        (None, Some(width)) if (1..=10).contains(&width) => width,
        (None, None) if variable && sized_by != SizedBy::Format => {
            if format == Format::Bytes {
                255
            } else {
                4
            }
        }
        (None, Some(width)) => {
            return Err(context
                .error("width", format!("`width: {width}` is out of range for {}", format.as_str()))
                .hint("ASCII digit fields take 1 to 10 digits; uint_be/uint_le up to 4 bytes; bytes up to 255"))
        }
        (None, _) => {
            return Err(context
                .error(
                    "width",
                    "this format needs a `width` (digits, or the most bytes)",
                )
                .hint("e.g. width: 4 for a 16-bit word in hex"))
        }
    };
    let min_width = model
        .min_width
        .unwrap_or(if variable && sized_by != SizedBy::Format {
            if format == Format::Bytes {
                0
            } else {
                1
            }
        } else {
            width
        });
    if (min_width == 0 && format != Format::Bytes) || min_width > width {
        return Err(context
            .error(
                "min_width",
                format!("min_width {min_width} must be from 1 to width {width}"),
            )
            .hint("leave it out for fixed-width fields"));
    }
    if sized_by != SizedBy::Format && !variable {
        return Err(context
            .error(
                "size",
                format!(
                    "`size` applies to uint_be, uint_le and bytes fields, not {}",
                    format.as_str()
                ),
            )
            .hint("remove `size`"));
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
            return Err(context
                .error("optional", format!("unknown presence rule `{rule}`"))
                .hint("use true, if_format_matches or { if_byte_at_most: N }"))
        }
    };
    let allowed = codes(&model.allowed).map_err(|shown| {
        context
            .error(
                "allowed",
                format!("allowed value `{shown}` is not a number or one character"),
            )
            .hint("`allowed` lists command letters or codes")
    })?;
    Ok(Part::Field(FieldSpec {
        name: Cow::Owned(name.to_owned()),
        role,
        format,
        width,
        min_width,
        optional,
        allowed: Cow::Owned(allowed),
        fold_case: model.fold_case,
        sized_by,
    }))
}

const ROLES_HINT: &str =
    "use address, command, register, index, data, error_code, process_1, process_2 or text";

fn codes(models: &[CodeModel]) -> Result<Vec<u32>, String> {
    models
        .iter()
        .map(|m| m.value().ok_or_else(|| m.shown()))
        .collect()
}

/// Parses `"15:12"` or `"7"` into (lsb, width).
pub fn parse_bits(text: &str) -> Option<(u8, u8)> {
    match text.split_once(':') {
        Some((msb, lsb)) => {
            let (msb, lsb): (u8, u8) = (msb.trim().parse().ok()?, lsb.trim().parse().ok()?);
            (msb >= lsb).then_some((lsb, msb - lsb + 1))
        }
        None => text.trim().parse().ok().map(|bit| (bit, 1)),
    }
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

/// Commands that cannot work as written: a code the layout refuses, a read or write with
/// nowhere to put the register, the same command twice, frames longer than `max_frame_len`.
fn check_commands(
    file: &ProtocolFile,
    source: &SourceFile,
    commands: &[CommandSpec],
    problems: &mut Vec<Diagnostic>,
) {
    let paths: Vec<usize> = file
        .commands
        .iter()
        .enumerate()
        .filter(|(_, c)| c.code.as_ref().is_none_or(|code| code.value().is_some()))
        .map(|(index, _)| index)
        .collect();
    for (position, command) in commands.iter().enumerate() {
        let index = paths.get(position).copied().unwrap_or(position);
        let path = format!("commands[{index}]");
        if command.request.has(Role::Command) {
            let allowed: Vec<u32> = command
                .request
                .parts
                .iter()
                .flat_map(|part| match part {
                    Part::Field(field) if field.role == Role::Command => field.allowed.to_vec(),
                    Part::Word(word) => word
                        .fields
                        .iter()
                        .filter(|b| b.role == Role::Command)
                        .flat_map(|b| b.allowed.to_vec())
                        .collect(),
                    _ => Vec::new(),
                })
                .collect();
            if !allowed.is_empty() && !allowed.contains(&command.code) {
                problems.push(
                    source
                        .error(
                            &format!("{path}.code"),
                            format!(
                                "code {} is not among the codes layout `{}` allows",
                                command.code_label(),
                                command.request.name
                            ),
                        )
                        .hint("add it to the layout's `allowed` list, or use another layout"),
                );
            }
        }
        let needs_register = matches!(
            command.kind,
            CommandKind::Read
                | CommandKind::ReadText
                | CommandKind::WriteRam
                | CommandKind::WritePersistent
        );
        if needs_register && !command.request.has(Role::Register) {
            problems.push(
                source
                    .error(
                        &format!("{path}.request"),
                        format!(
                            "a {} command needs a register field, and layout `{}` has none",
                            command.kind.as_str(),
                            command.request.name
                        ),
                    )
                    .hint("add a `field: register` part to the request layout"),
            );
        }
        if let Some(first) = commands[..position].iter().position(|other| {
            other.code == command.code
                && other.kind == command.kind
                && other.space == command.space
                && other.data_types == command.data_types
        }) {
            problems.push(
                source
                    .error(
                        &path,
                        format!(
                            "the same command as commands[{}] (code {}, {})",
                            paths.get(first).copied().unwrap_or(first),
                            command.code_label(),
                            command.kind.as_str()
                        ),
                    )
                    .hint("remove one of them"),
            );
        }
    }
    let mut seen = std::collections::BTreeSet::new();
    for layout in commands.iter().flat_map(|c| [&c.request, &c.reply]) {
        if !seen.insert(layout.name.clone()) {
            continue;
        }
        let fixed: Option<usize> = layout.parts.iter().map(|p| p.fixed_size()).sum();
        if let Some(size) = fixed.filter(|size| *size > usize::from(file.protocol.max_frame_len)) {
            problems.push(
                source
                    .error(
                        "protocol.max_frame_len",
                        format!(
                            "layout `{}` is {size} bytes, longer than max_frame_len {}",
                            layout.name, file.protocol.max_frame_len
                        ),
                    )
                    .hint("raise max_frame_len: it sizes buffers and reply timeouts"),
            );
        }
    }
}

/// A protocol declared `text: true` carries printable ASCII only: no binary fields and no
/// non-printable literals other than line ends.
fn check_text_protocol(
    layouts: &[(String, FrameLayout)],
    source: &SourceFile,
    problems: &mut Vec<Diagnostic>,
) {
    for (name, layout) in layouts {
        for (index, part) in layout.parts.iter().enumerate() {
            let binary = match part {
                Part::Literal { bytes, .. } => bytes
                    .iter()
                    .any(|b| !(b.is_ascii_graphic() || *b == b' ' || *b == b'\r' || *b == b'\n')),
                Part::Field(field) => {
                    !matches!(field.format, Format::Decimal | Format::Hex | Format::Char)
                }
                Part::Checksum(spec) => spec.format != Format::Hex,
                Part::Word(_) | Part::Length(_) => true,
            };
            if binary {
                problems.push(
                    source
                        .error(&format!("layouts.{name}[{index}]"), format!("part `{}` of layout `{name}` is binary, but the protocol says `text: true`", part.name()))
                        .hint("use decimal, hex or char fields and hex checksums, or set `text: false`"),
                );
            }
        }
    }
}
