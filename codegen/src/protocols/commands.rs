//! Commands: each `commands:` entry lowered into a runtime [`CommandSpec`] (code, kind, data
//! types, space, address map, layouts, reply codes), then the commands checked against each
//! other and against their layouts; and the drive's own address maps.

use super::layouts::Layouts;
use super::lowered_command::LoweredCommand;
use super::{space_from_name, Input};
use crate::diagnostics::Diagnostics;
use crate::parse::model::{CommandModel, ProtocolRef};
use crate::parse::SourceFile;
use std::borrow::Cow;
use vfd_runtime::{AddressMap, CommandKind, CommandSpec, DataType, Role, Space};

/// Lowers every command; those with problems are reported and left out.
pub(super) fn lower_commands(
    input: &Input<'_>,
    layouts: &Layouts<'_>,
    out: &mut Diagnostics,
) -> Vec<LoweredCommand> {
    input
        .file
        .commands
        .iter()
        .enumerate()
        .filter_map(|(index, command)| {
            let spec = lower_command(index, command, input, layouts, out)?;
            Some(LoweredCommand {
                index,
                spec,
                has_code: command.code.is_some(),
            })
        })
        .collect()
}

/// Lowers one command, reporting every problem in it.
fn lower_command(
    index: usize,
    command: &CommandModel,
    input: &Input<'_>,
    layouts: &Layouts<'_>,
    out: &mut Diagnostics,
) -> Option<CommandSpec> {
    let source = input.source;
    let path = format!("commands[{index}]");
    let code = code(command, source, &path, out);
    let reply_codes = reply_codes(command, source, &path, out);
    let space = command.space.unwrap_or(Space::Parameter);
    let request = layouts.find(&command.request, &format!("{path}.request"), out);
    // `reply: none`: never answered; the request's layout stands in, never awaited.
    let no_reply = command.reply == NO_REPLY;
    let reply = if no_reply {
        request.clone()
    } else {
        layouts.find(&command.reply, &format!("{path}.reply"), out)
    };
    if no_reply && !command.reply_codes.is_empty() {
        out.push(
            source
                .error(
                    &format!("{path}.reply_codes"),
                    "reply codes for a command that is never answered (`reply: none`)",
                )
                .hint("leave `reply_codes` out, or name the reply's layout"),
        );
    }
    if let Some(request) = &request {
        if command.code.is_some() && !request.has(Role::Command) {
            out.push(
                source
                    .error(&format!("{path}.code"), format!("layout `{}` has no command field to carry the code", command.request))
                    .hint("leave `code` out for commands whose layout has no command (process telegrams)"),
            );
        }
    }
    Some(CommandSpec {
        code: code?,
        kind: command.kind,
        data_types: Cow::Owned(command.data_types.clone()),
        space,
        address_map: address_map(command, input.reference, space),
        request: request?,
        reply: reply?,
        reply_codes: Cow::Owned(reply_codes?),
        error_code: match &command.error_code {
            None => None,
            Some(code) => Some(code.value().or_else(|| {
                out.push(
                    source
                        .error(
                            &format!("{path}.error_code"),
                            "an error code is a number or a single character",
                        )
                        .hint("e.g. error_code: 0x83"),
                );
                None
            })?),
        },
        no_reply,
        extra: command.extra,
        lowercase_means_sender_tripped: command.lowercase_means
            == Some(crate::parse::model::LowercaseMeans::SenderTripped),
        registers: Cow::Borrowed(&[]),
        percent_of: None,
        follow_up: follow_up(command, layouts, &path, out)?,
        stored_by_instruction: storage_by_instruction(command, source, &path, out)?,
    })
}

/// The command's `follow_up` layouts (`Some(None)`: it has none; `None`: a layout is
/// missing, reported).
fn follow_up(
    command: &CommandModel,
    layouts: &Layouts<'_>,
    path: &str,
    out: &mut Diagnostics,
) -> Option<Option<vfd_runtime::protocol::FollowUp>> {
    let Some(model) = &command.follow_up else {
        return Some(None);
    };
    let ok = layouts.find(&model.ok, &format!("{path}.follow_up.ok"), out);
    let again = layouts.find(&model.again, &format!("{path}.follow_up.again"), out);
    Some(Some(vfd_runtime::protocol::FollowUp {
        ok: ok?,
        again: again?,
    }))
}

/// Whether the command's storage is the instruction's (`storage: by_instruction`), which
/// only a plain write (`kind: write_ram`) can have; `None` when it is on another kind
/// (reported).
fn storage_by_instruction(
    command: &CommandModel,
    source: &crate::parse::SourceFile,
    path: &str,
    out: &mut Diagnostics,
) -> Option<bool> {
    match command.storage {
        None => Some(false),
        Some(_) if command.kind == vfd_runtime::CommandKind::WriteRam => Some(true),
        Some(_) => {
            out.push(
                source
                    .error(
                        &format!("{path}.storage"),
                        format!(
                            "`storage: by_instruction` on a `{}` command",
                            command.kind.as_str()
                        ),
                    )
                    .hint("only a plain write (`kind: write_ram`) leaves its storage to the instruction; a `write_persistent` command always stores in EEPROM"),
            );
            None
        }
    }
}

/// The word `reply:` takes for a command that is never answered.
pub(super) const NO_REPLY: &str = "none";

/// The commands the drive carries out, with the data types it carries
/// (`protocols[].commands`, `protocols[].data_types`); a command left with no data type is
/// dropped. A code the protocol file does not have is reported.
pub(super) fn drive_subset(
    commands: Vec<LoweredCommand>,
    input: &Input<'_>,
    out: &mut Diagnostics,
) -> Vec<LoweredCommand> {
    let reference = input.reference;
    let mut codes = Vec::new();
    for (index, code) in reference.commands.iter().flatten().enumerate() {
        let value = code.value();
        let known = value.is_some_and(|v| commands.iter().any(|c| c.spec.code == v));
        if known {
            codes.extend(value);
        } else {
            out.push(
                input
                    .drive_source
                    .error(
                        &format!("{}.commands[{index}]", input.reference_path),
                        format!(
                            "protocol file `{}` has no command {}",
                            reference.uses,
                            code.shown()
                        ),
                    )
                    .hint("list codes of the protocol file's `commands`; see its page for them"),
            );
        }
    }
    commands
        .into_iter()
        .filter(|c| match &reference.commands {
            None => !c.spec.extra,
            Some(_) => codes.contains(&c.spec.code),
        })
        .filter_map(|mut c| {
            let Some(allowed) = &reference.data_types else {
                return Some(c);
            };
            let carried: Vec<DataType> = if c.spec.data_types.is_empty() {
                allowed.clone()
            } else {
                c.spec
                    .data_types
                    .iter()
                    .copied()
                    .filter(|t| allowed.contains(t))
                    .collect()
            };
            if carried.is_empty() {
                return None;
            }
            c.spec.data_types = Cow::Owned(carried);
            Some(c)
        })
        .collect()
}

/// Applies the drive's `command_registers`: the registers each command may address and
/// what its data is a percentage of, resolved from the drive's registers. A code that is
/// not among the drive's commands, an unknown register or a percentage of a register in
/// another unit is reported.
pub(super) fn apply_command_registers(
    commands: &mut [LoweredCommand],
    input: &Input<'_>,
    out: &mut Diagnostics,
) {
    let registers = &input.drive.registers;
    let find = |name: &str| registers.iter().find(|r| r.is_named(name));
    for (index, entry) in input.reference.command_registers.iter().enumerate() {
        let path = format!("{}.command_registers[{index}]", input.reference_path);
        let error = |key: &str, message: String, hint: &str| {
            input
                .drive_source
                .error(&format!("{path}.{key}"), message)
                .hint(hint)
        };
        let value = entry.code.value();
        let Some(command) = commands
            .iter_mut()
            .find(|c| value.is_some_and(|v| c.spec.code == v))
        else {
            out.push(error(
                "code",
                format!(
                    "protocol `{}` as this drive uses it has no command {}",
                    input.reference.uses,
                    entry.code.shown()
                ),
                "name a command of the protocol file (an extra one must also be listed in `commands`)",
            ));
            continue;
        };
        let mut numbers = Vec::new();
        let mut units = Vec::new();
        for (position, name) in entry.registers.iter().enumerate() {
            match find(name) {
                Some(register) => {
                    numbers.push(register.address as u16);
                    units.push((position, register.unit.clone()));
                }
                None => out.push(error(
                    &format!("registers[{position}]"),
                    format!("no register has the code or id `{name}`"),
                    "name registers of this drive file by code (FA01) or id",
                )),
            }
        }
        command.spec.registers = Cow::Owned(numbers);
        if entry.step.is_some() && entry.percent_of.is_none() {
            out.push(error(
                "step",
                "a step without `percent_of`".to_owned(),
                "`step` is the percentage one raw step stands for: give `percent_of` too, or leave it out",
            ));
        }
        let Some(name) = &entry.percent_of else {
            continue;
        };
        if !command.spec.kind.is_write() {
            out.push(error(
                "percent_of",
                format!(
                    "command {} is a {}: only a write's data can be a percentage",
                    entry.code.shown(),
                    command.spec.kind.as_str()
                ),
                "leave `percent_of` out for this command",
            ));
            continue;
        }
        let Some(reference) = find(name) else {
            out.push(error(
                "percent_of",
                format!("no register has the code or id `{name}`"),
                "name the register whose value is 100 % by code (FH) or id",
            ));
            continue;
        };
        for (position, unit) in units {
            if unit != reference.unit {
                out.push(error(
                    &format!("registers[{position}]"),
                    format!(
                        "register `{}` is in {}, but `{}` (100 %) is in {}",
                        entry.registers[position],
                        unit.as_deref().unwrap_or("no unit"),
                        name,
                        reference.unit.as_deref().unwrap_or("no unit")
                    ),
                    "a percentage converts between registers of the same unit",
                ));
            }
        }
        let step = entry.step.unwrap_or(0.01);
        if !(step > 0.0 && step.is_finite()) {
            out.push(error(
                "step",
                format!("step {step} is not a positive number"),
                "the percentage one raw step stands for, e.g. 0.01",
            ));
            continue;
        }
        for (position, id) in entry.received_by.iter().enumerate() {
            if !input.drive.conversions.iter().any(|c| &c.id == id) {
                out.push(error(
                    &format!("received_by[{position}]"),
                    format!("no conversion has the id `{id}`"),
                    "name conversions of this drive file (`conversions[].id`)",
                ));
            }
        }
        command.spec.percent_of = Some(vfd_runtime::protocol::PercentOf {
            register: Cow::Owned(reference.code.clone()),
            step,
            received_by: Cow::Owned(
                entry
                    .received_by
                    .iter()
                    .map(|id| Cow::Owned(id.clone()))
                    .collect(),
            ),
        });
    }
}

/// Each command's `error_code` is one the error reply layout allows.
pub(super) fn check_error_codes(
    commands: &[LoweredCommand],
    error_reply: Option<&vfd_runtime::FrameLayout>,
    source: &SourceFile,
    out: &mut Diagnostics,
) {
    for command in commands {
        let Some(code) = command.spec.error_code else {
            continue;
        };
        let path = format!("{}.error_code", command.path());
        match error_reply {
            None => out.push(
                source
                    .error(&path, "an error code, but the protocol has no `error_reply` layout")
                    .hint("name the error reply's layout under `error_reply`, or leave `error_code` out"),
            ),
            Some(layout) => {
                let allowed = layout.allowed_commands();
                if !allowed.is_empty() && !allowed.contains(&code) {
                    out.push(
                        source
                            .error(
                                &path,
                                format!(
                                    "error code {} is not among the codes layout `{}` allows",
                                    vfd_runtime::protocol::code_label(code),
                                    layout.name
                                ),
                            )
                            .hint("add it to the error layout's `allowed` list, or fix the code"),
                    );
                }
            }
        }
    }
}

/// The command's code on the wire (0 for layouts without a command field).
fn code(
    command: &CommandModel,
    source: &SourceFile,
    path: &str,
    out: &mut Diagnostics,
) -> Option<u32> {
    let Some(code) = &command.code else {
        return Some(0);
    };
    let value = code.value();
    if value.is_none() {
        out.push(
            source
                .error(
                    &format!("{path}.code"),
                    format!(
                        "command code `{}` is not one character or a number",
                        code.shown()
                    ),
                )
                .hint("write a letter as it appears on the wire (R) or a number (0x03)"),
        );
    }
    value
}

/// Codes a normal reply may carry (empty: the request's code).
fn reply_codes(
    command: &CommandModel,
    source: &SourceFile,
    path: &str,
    out: &mut Diagnostics,
) -> Option<Vec<u32>> {
    let codes: Option<Vec<u32>> = command.reply_codes.iter().map(|c| c.value()).collect();
    if codes.is_none() {
        out.push(
            source
                .error(
                    &format!("{path}.reply_codes"),
                    "reply codes are numbers or single characters",
                )
                .hint("e.g. reply_codes: [1, 2]"),
        );
    }
    codes
}

/// How the command numbers registers on the wire: the drive's numbering for the command's
/// space wins over the protocol file's.
fn address_map(command: &CommandModel, reference: &ProtocolRef, space: Space) -> AddressMap {
    reference
        .address_maps
        .get(space.as_str())
        .or(command.address_map.as_ref())
        .map(|map| AddressMap {
            multiply: map.multiply.max(1),
            offset: map.offset,
        })
        .unwrap_or(AddressMap::IDENTITY)
}

/// The drive's `address_maps` name known spaces and multiply by at least 1.
pub(super) fn check_address_maps(input: &Input<'_>, out: &mut Diagnostics) {
    let path = format!("{}.address_maps", input.reference_path);
    for (key, map) in &input.reference.address_maps {
        if map.multiply == 0 {
            out.push(
                input
                    .drive_source
                    .error(
                        &format!("{path}.{key}.multiply"),
                        "`multiply: 0` maps every register to the same wire address",
                    )
                    .hint("use 1 for numbers that go on the wire as they are"),
            );
        }
        if space_from_name(key).is_none() {
            out.push(
                input
                    .drive_source
                    .error(
                        &format!("{path}.{key}"),
                        format!("unknown address space `{key}`"),
                    )
                    .hint("use parameter or coil"),
            );
        }
    }
}

/// Commands that cannot work as written: a code the layout refuses, a read or write with
/// nowhere to put the register, the same command twice.
pub(super) fn check_commands(
    commands: &[LoweredCommand],
    source: &SourceFile,
    out: &mut Diagnostics,
) {
    for (position, command) in commands.iter().enumerate() {
        check_code_is_allowed(command, source, out);
        check_register_field(command, source, out);
        check_block_fields(command, source, out);
        check_not_repeated(command, &commands[..position], source, out);
    }
}

/// The request layout's command field accepts the command's code.
fn check_code_is_allowed(command: &LoweredCommand, source: &SourceFile, out: &mut Diagnostics) {
    let spec = &command.spec;
    if !spec.request.has(Role::Command) {
        return;
    }
    let allowed = spec.request.allowed_commands();
    if !allowed.is_empty() && !allowed.contains(&spec.code) {
        out.push(
            source
                .error(
                    &format!("{}.code", command.path()),
                    format!(
                        "code {} is not among the codes layout `{}` allows",
                        spec.code_label(),
                        spec.request.name
                    ),
                )
                .hint("add it to the layout's `allowed` list, or use another layout"),
        );
    }
}

/// Reads and writes name a register, so their request needs a register field.
fn check_register_field(command: &LoweredCommand, source: &SourceFile, out: &mut Diagnostics) {
    let spec = &command.spec;
    let needs_register = matches!(
        spec.kind,
        CommandKind::Read
            | CommandKind::ReadText
            | CommandKind::WriteRam
            | CommandKind::WritePersistent
    );
    if needs_register && !spec.request.has(Role::Register) {
        out.push(
            source
                .error(
                    &format!("{}.request", command.path()),
                    format!(
                        "a {} command needs a register field, and layout `{}` has none",
                        spec.kind.as_str(),
                        spec.request.name
                    ),
                )
                .hint("add a `field: register` part to the request layout"),
        );
    }
}

/// A block transfer's request carries the words written and the count asked back, and its
/// reply the words read.
fn check_block_fields(command: &LoweredCommand, source: &SourceFile, out: &mut Diagnostics) {
    let spec = &command.spec;
    if spec.kind != CommandKind::Block {
        return;
    }
    for (key, layout, roles) in [
        (
            "request",
            &spec.request,
            &[Role::Words, Role::ReadCount][..],
        ),
        ("reply", &spec.reply, &[Role::Words][..]),
    ] {
        for role in roles {
            if !layout.has(*role) {
                out.push(
                    source
                        .error(
                            &format!("{}.{key}", command.path()),
                            format!(
                                "a block command needs a `{}` field, and layout `{}` has none",
                                role.as_str(),
                                layout.name
                            ),
                        )
                        .hint("a block request carries `words` (sized by a length) and `read_count`; its reply `words`"),
                );
            }
        }
    }
}

/// No earlier command has the same code, kind, space and data types. Two commands without
/// a code (their layouts have no command field) are not "the same command": nothing
/// tells them apart, so a request of their kind always takes the first; the message says
/// so instead of showing the code 00h neither has.
fn check_not_repeated(
    command: &LoweredCommand,
    earlier: &[LoweredCommand],
    source: &SourceFile,
    out: &mut Diagnostics,
) {
    let spec = &command.spec;
    let first = earlier.iter().find(|other| {
        let other = &other.spec;
        other.code == spec.code
            && other.kind == spec.kind
            && other.space == spec.space
            && other.data_types == spec.data_types
    });
    let Some(first) = first else {
        return;
    };
    let diagnostic = if !command.has_code && !first.has_code {
        let data_types = match spec.data_types.as_ref() {
            [] => "any data type".to_owned(),
            types => types
                .iter()
                .map(|t| t.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        };
        source
            .error(
                &command.path(),
                format!(
                    "nothing tells this command from {}: neither has a code, and both are {} commands of the {} space carrying {data_types} (layouts `{}` and `{}`)",
                    first.path(),
                    spec.kind.as_str(),
                    spec.space.as_str(),
                    first.spec.request.name,
                    spec.request.name,
                ),
            )
            .hint(format!(
                "a command without a code is chosen by its kind, space and data types alone, so a {} request always goes out as {}; give them different `data_types` where the type of their data tells them apart, or keep one",
                spec.kind.as_str(),
                first.path()
            ))
    } else {
        source
            .error(
                &command.path(),
                format!(
                    "the same command as {} (code {}, {})",
                    first.path(),
                    spec.code_label(),
                    spec.kind.as_str()
                ),
            )
            .hint("remove one of them")
    };
    out.push(diagnostic);
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{
        at, drive_with, lower_both, lowered, problems, problems_of, protocol_with, PROTOCOL,
    };
    use super::*;
    use vfd_runtime::DataType;

    #[test]
    fn a_command_lowers_with_its_code_kind_space_and_layouts() {
        let yaml = protocol_with(&[(
            "{ code: W, kind: write_persistent,",
            "{ code: W, kind: write_persistent, data_types: [word, double_word], space: coil, address_map: { multiply: 2, offset: -1 }, reply_codes: [W, 0x77],",
        )]);
        let protocol = lowered(&yaml);
        let [read, write] = &protocol.commands[..] else {
            panic!("two commands expected: {:?}", protocol.commands);
        };
        assert_eq!(
            (read.code, read.kind, read.space, read.address_map),
            (
                0x52,
                CommandKind::Read,
                Space::Parameter,
                AddressMap::IDENTITY
            )
        );
        assert!(read.data_types.is_empty() && read.reply_codes.is_empty());
        assert_eq!(
            (read.request.name.as_ref(), read.reply.name.as_ref()),
            ("read_request", "reply")
        );
        assert_eq!(
            (write.kind, write.space),
            (CommandKind::WritePersistent, Space::Coil)
        );
        assert_eq!(
            write.data_types.as_ref(),
            [DataType::Word, DataType::DoubleWord]
        );
        assert_eq!(
            write.address_map,
            AddressMap {
                multiply: 2,
                offset: -1
            }
        );
        assert_eq!(write.reply_codes.as_ref(), [0x57, 0x77]);
    }

    #[test]
    fn the_drive_numbering_of_a_space_wins_over_the_protocol_file() {
        let yaml = protocol_with(&[(
            "{ code: W, kind: write_persistent,",
            "{ code: W, kind: write_persistent, address_map: { multiply: 2, offset: 0 },",
        )]);
        let drive = drive_with("    address_maps:\n      parameter: { multiply: 10, offset: -1 }");
        let protocol = lower_both(&drive, &yaml).unwrap();
        for command in protocol.commands.iter() {
            assert_eq!(
                command.address_map,
                AddressMap {
                    multiply: 10,
                    offset: -1
                }
            );
        }
    }

    #[test]
    fn every_problem_of_a_command_is_reported() {
        let yaml = protocol_with(&[(
            "{ code: W, kind: write_persistent, request: write_request, reply: reply }",
            "{ code: WW, kind: write_persistent, request: write_request, reply: replie, reply_codes: [WW] }",
        )]);
        assert_eq!(
            problems(&yaml),
            [
                format!(
                    "{} commands[1].code: command code `WW` is not one character or a number",
                    at(&yaml, "WW, kind")
                ),
                format!(
                    "{} commands[1].reply: layout `replie` is not defined",
                    at(&yaml, "replie")
                ),
                format!(
                    "{} commands[1].reply_codes: reply codes are numbers or single characters",
                    at(&yaml, "reply_codes")
                ),
            ]
        );
    }

    #[test]
    fn commands_that_cannot_work_are_reported() {
        let yaml = protocol_with(&[(
            "  - { code: W, kind: write_persistent, request: write_request, reply: reply }\n",
            "  - { code: P, kind: write_persistent, request: write_request, reply: reply }\n  - { code: R, kind: read_text, request: error_reply, reply: reply }\n  - { code: R, kind: read, request: read_request, reply: reply }\n  - { code: 1, kind: process, request: fixed, reply: fixed }\n",
        ), ("  reply:", "  fixed: [start, register, cr]\n  reply:")]);
        let repeated = yaml
            .lines()
            .enumerate()
            .filter(|(_, line)| {
                *line == "  - { code: R, kind: read, request: read_request, reply: reply }"
            })
            .map(|(index, _)| index + 1)
            .nth(1)
            .unwrap();
        assert_eq!(
            problems(&yaml),
            [
                format!("{} commands[1].code: code P is not among the codes layout `write_request` allows", at(&yaml, "P, kind")),
                format!("{} commands[2].code: code R is not among the codes layout `error_reply` allows", at(&yaml, "R, kind: read_text")),
                format!("{} commands[2].request: a read_text command needs a register field, and layout `error_reply` has none", at(&yaml, "error_reply, reply")),
                format!("{repeated}:7 commands[3]: the same command as commands[0] (code R, read)"),
                format!("{} commands[4].code: layout `fixed` has no command field to carry the code", at(&yaml, "1, kind")),
            ]
        );
    }

    #[test]
    fn an_extra_command_reaches_only_drives_that_list_it() {
        let yaml = protocol_with(&[(
            "{ code: W, kind: write_persistent, request: write_request, reply: reply }",
            "{ code: W, kind: write_persistent, request: write_request, reply: none, extra: true, lowercase_means: sender_tripped }",
        )]);
        let codes = |protocol: &vfd_runtime::Protocol| -> Vec<u32> {
            protocol.commands.iter().map(|c| c.code).collect()
        };
        // Not listed: the drive does not get it.
        assert_eq!(codes(&lowered(&yaml)), [u32::from(b'R')]);
        let drive = drive_with("    commands: [R, W]");
        let protocol = lower_both(&drive, &yaml).unwrap();
        assert_eq!(codes(&protocol), [u32::from(b'R'), u32::from(b'W')]);
        let write = &protocol.commands[1];
        assert!(write.extra && write.no_reply && write.lowercase_means_sender_tripped);
        // Never answered: the request's layout stands in for the reply, never awaited.
        assert_eq!(write.reply.name, write.request.name);
        // A request names it, or does not get it.
        assert!(protocol
            .command_for(
                CommandKind::WritePersistent,
                Space::Parameter,
                DataType::Word
            )
            .is_none());
    }

    #[test]
    fn the_drive_address_maps_are_checked_in_the_drive_file() {
        let drive = drive_with("    address_maps:\n      parameter: { multiply: 0, offset: 0 }\n      holding: { multiply: 1, offset: 0 }");
        assert_eq!(
            problems_of(lower_both(&drive, PROTOCOL)),
            [
                format!("{} protocols[0].address_maps.parameter.multiply: `multiply: 0` maps every register to the same wire address", at(&drive, "0, offset")),
                format!("{} protocols[0].address_maps.holding: unknown address space `holding`", at(&drive, "holding")),
            ]
        );
    }
}
