//! Commands: each `commands:` entry lowered into a runtime [`CommandSpec`] (code, kind, data
//! types, space, address map, layouts, reply codes), then the commands checked against each
//! other and against their layouts; and the drive's own address maps.

use super::layouts::Layouts;
use super::{space_from_name, Input};
use crate::diagnostics::Diagnostics;
use crate::parse::model::{CommandModel, ProtocolRef};
use crate::parse::SourceFile;
use std::borrow::Cow;
use vfd_runtime::{AddressMap, CommandKind, CommandSpec, Part, Role, Space};

/// A command that lowered, with its index under `commands:`.
pub(super) struct LoweredCommand {
    /// Index in the protocol file's `commands:`.
    pub index: usize,
    /// The runtime command.
    pub spec: CommandSpec,
}

impl LoweredCommand {
    fn path(&self) -> String {
        format!("commands[{}]", self.index)
    }
}

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
            Some(LoweredCommand { index, spec })
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
    let reply = layouts.find(&command.reply, &format!("{path}.reply"), out);
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
    })
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
        check_not_repeated(command, &commands[..position], source, out);
    }
}

/// The request layout's command field accepts the command's code.
fn check_code_is_allowed(command: &LoweredCommand, source: &SourceFile, out: &mut Diagnostics) {
    let spec = &command.spec;
    if !spec.request.has(Role::Command) {
        return;
    }
    let allowed: Vec<u32> = spec
        .request
        .parts
        .iter()
        .flat_map(|part| match part {
            Part::Field(field) if field.role == Role::Command => field.allowed.to_vec(),
            Part::Word(word) => word
                .fields
                .iter()
                .filter(|bits| bits.role == Role::Command)
                .flat_map(|bits| bits.allowed.to_vec())
                .collect(),
            _ => Vec::new(),
        })
        .collect();
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

/// No earlier command has the same code, kind, space and data types.
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
    if let Some(first) = first {
        out.push(
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
                .hint("remove one of them"),
        );
    }
}
