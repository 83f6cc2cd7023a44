//! One protocol as the drive speaks it: its commands in words, pre-steps, block transfer
//! and layouts part by part.

use super::link_rules::link_rules;
use crate::emit::markdown::layouts::{part_view, PartView};
use crate::ir::*;
use serde::Serialize;
use vfd_runtime::{PreStep, Role, Space};

#[derive(Serialize)]
pub(super) struct ProtocolView<'a> {
    #[serde(flatten)]
    protocol: &'a ProtocolIr,
    name_zh: &'a str,
    description: &'a str,
    commands: Vec<CommandView<'a>>,
    pre_steps: Vec<String>,
    block: Vec<String>,
    /// The drive's own line rules (gap floor, inner gap, bytes before the start, reply
    /// delay, broadcasts), one sentence each.
    link_rules: Vec<String>,
    layouts: Vec<LayoutView>,
}

#[derive(Serialize)]
struct CommandView<'a> {
    code: String,
    kind: &'a str,
    data_types: String,
    space: &'a str,
    address_map: String,
    reply_codes: String,
    error_code: String,
    request: &'a str,
    reply: &'a str,
    /// What sets the command apart (extra, never answered, registers, percentage), in
    /// words; empty for an ordinary command.
    notes: String,
}

#[derive(Serialize)]
struct LayoutView {
    name: String,
    parts: Vec<PartView>,
}

/// What sets a command apart, in words (empty for an ordinary one).
fn command_notes(drive: &DriveIr, command: &CommandIr) -> String {
    let mut notes = Vec::new();
    let label = |number: u16| {
        drive
            .registers
            .iter()
            .find(|r| r.address == number && r.space == command.space)
            .map_or_else(|| format!("{number:04X}h"), |r| r.code.clone())
    };
    if command.extra {
        let verb = if command.kind.is_write() {
            "write"
        } else {
            "read"
        };
        notes.push(format!(
            "extra: used only when a request names it (`Request::using`, `vfd {verb} --command {}`)",
            vfd_runtime::protocol::code_label(command.code)
        ));
    }
    if command.no_reply {
        notes.push(
            "never answered: sending returns once the frame is on the line (wire time and frame gap)"
                .to_owned(),
        );
    }
    if command.space == Space::Coil && coil_data_low_byte_first(drive, command) {
        notes.push(
            "coil data: the first coil is the lowest bit of the first byte, so 16 coils read as a word arrive low byte first"
                .to_owned(),
        );
    }
    if command.lowercase_means_sender_tripped {
        notes.push("lower case: the sender (master) has tripped".to_owned());
    }
    if command.stored_by_instruction {
        notes.push(
            "storage by instruction: a RAM-only register's write goes to RAM, any other's to RAM and EEPROM (a persistent write is sent with it; a RAM write of such a register is refused before sending)"
                .to_owned(),
        );
    }
    if !command.registers.is_empty() {
        let names: Vec<String> = command.registers.iter().map(|r| label(*r)).collect();
        notes.push(format!("addresses only {}", names.join(", ")));
    }
    if let Some((register, step, _)) = &command.percent_of {
        notes.push(format!(
            "data in {step} % of {register}, not in the register's unit"
        ));
    }
    notes.join("; ")
}

/// Whether a coil command's data travels low byte first (`uint_le`) in its request or
/// reply, as the protocol file lays it out.
fn coil_data_low_byte_first(drive: &DriveIr, command: &CommandIr) -> bool {
    use vfd_runtime::layout::{Format, Part};
    drive
        .protocol_files
        .iter()
        .flat_map(|f| f.layouts.iter())
        .filter(|l| l.name == command.request || l.name == command.reply)
        .flat_map(|l| l.parts.iter())
        .any(|part| {
            matches!(part, Part::Field(field) if field.role == Role::Data && field.format == Format::UintLe)
        })
}

/// What the block transfer writes and reads, one line each, registers by code.
fn block_lines(drive: &DriveIr, protocol: &ProtocolIr) -> Vec<String> {
    let Some(block) = &protocol.block else {
        return Vec::new();
    };
    let code = |address: u16| {
        drive
            .registers
            .iter()
            .find(|r| r.address == address)
            .map_or_else(|| format!("{address:04X}h"), |r| r.code.clone())
    };
    let list = |addresses: &mut dyn Iterator<Item = u16>| {
        addresses.map(code).collect::<Vec<_>>().join(", ")
    };
    let choices = |choices: &[vfd_runtime::BlockChoice]| {
        choices
            .iter()
            .map(|c| match c.register {
                Some(r) => format!("{} = {}", c.value, code(r)),
                None => format!("{} = none", c.value),
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut lines = vec![
        format!(
            "Block transfer (manual section {}): the words written go, in order, to the registers {} select ({}); the words read come from the registers {} select ({}). The selectors are read at a reset. Reply write status: bit n set = word n not written.",
            protocol.block_source,
            list(&mut block.write.iter().map(|s| s.register)),
            choices(&block.write_choices),
            list(&mut block.read.iter().map(|s| s.register)),
            choices(&block.read_choices),
        ),
    ];
    for mode in block.modes.iter() {
        lines.push(format!(
            "While {} = {}: the words written go to {}; the words read come from {}.",
            code(mode.register),
            mode.value,
            list(&mut mode.write.iter().copied()),
            list(&mut mode.read.iter().copied()),
        ));
    }
    if !protocol.block_note.is_empty() {
        lines.push(protocol.block_note.clone());
    }
    lines
}

pub(super) fn protocol_view<'a>(drive: &'a DriveIr, protocol: &'a ProtocolIr) -> ProtocolView<'a> {
    let file = drive.protocol_files.iter().find(|f| f.id == protocol.uses);
    let layout = |name: &str| file.and_then(|f| f.layouts.iter().find(|l| l.name == name));
    let mut names: Vec<&str> = Vec::new();
    for command in &protocol.commands {
        for name in [&command.request, &command.reply] {
            if !names.contains(&name.as_str()) {
                names.push(name);
            }
        }
    }
    if let Some(error) = &protocol.error_reply {
        if !names.contains(&error.as_str()) {
            names.push(error);
        }
    }
    ProtocolView {
        protocol,
        name_zh: file.map_or("", |f| f.name_zh.as_str()),
        description: file.map_or("", |f| f.description.as_str()),
        commands: protocol
            .commands
            .iter()
            .map(|c| CommandView {
                code: if layout(&c.request).is_some_and(|l| l.has(Role::Command)) {
                    vfd_runtime::protocol::code_label(c.code)
                } else {
                    "—".to_owned()
                },
                kind: c.kind.as_str(),
                data_types: if c.data_types.is_empty() {
                    "any".to_owned()
                } else {
                    c.data_types
                        .iter()
                        .map(|t| t.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                },
                space: c.space.as_str(),
                address_map: match (c.address_map.multiply, c.address_map.offset) {
                    (1, 0) => "as is".to_owned(),
                    (1, offset) => format!("number {offset:+}"),
                    (multiply, 0) => format!("number × {multiply}"),
                    (multiply, offset) => format!("number × {multiply} {offset:+}"),
                },
                reply_codes: if c.reply_codes.is_empty() {
                    "same".to_owned()
                } else {
                    c.reply_codes
                        .iter()
                        .map(|r| vfd_runtime::protocol::code_label(*r))
                        .collect::<Vec<_>>()
                        .join(", ")
                },
                error_code: c
                    .error_code
                    .map_or_else(|| "—".to_owned(), vfd_runtime::protocol::code_label),
                request: &c.request,
                reply: if c.no_reply { "none (never answered)" } else { &c.reply },
                notes: command_notes(drive, c),
            })
            .collect(),
        link_rules: link_rules(drive, protocol),
        pre_steps: protocol
            .pre_steps
            .iter()
            .map(|step| match *step {
                PreStep::Index { register } => format!(
                    "Before an indexed (array) access: write the index to wire register {register:04X}h."
                ),
                PreStep::Persistence {
                    space,
                    register,
                    ram,
                    persistent,
                    ..
                } => format!(
                    "Before a parameter write: write {ram:04X}h (RAM only) or {persistent:04X}h (RAM and EEPROM) to {} {register}.",
                    space.as_str()
                ),
            })
            .chain(drive.persistence.as_ref().map(|p| {
                let spans: Vec<String> = p
                    .registers
                    .iter()
                    .map(|(from, to)| format!("{from:04X}h-{to:04X}h"))
                    .collect();
                format!(
                    "Parameter writes{} go where {} says ({}: RAM only, {}: RAM and EEPROM; {}): \
                     the master sets it to {} before a RAM write (stored in the EEPROM too when {} \
                     was in force), and around a persistent write to {} and back, so that the \
                     EEPROM's copy of {} ends as it was (drives/README.md, \"Persistence chosen \
                     by a register\").",
                    if spans.is_empty() {
                        String::new()
                    } else {
                        format!(" (registers {})", spans.join(", "))
                    },
                    p.selector,
                    p.ram,
                    p.persistent,
                    p.source,
                    p.ram,
                    p.persistent,
                    p.persistent,
                    p.selector,
                )
            }))
            .collect(),
        block: block_lines(drive, protocol),
        layouts: names
            .into_iter()
            .filter_map(layout)
            .map(|layout| {
                let used = codes_in_layout(protocol, &layout.name);
                let lacking = lacking_function_note(protocol, &layout.name);
                LayoutView {
                    name: layout.name.to_string(),
                    parts: layout
                        .parts
                        .iter()
                        .map(|part| {
                            let mut view = part_view(part, &layout.parts, &used);
                            let is_command = matches!(part, vfd_runtime::layout::Part::Field(f) if f.role == Role::Command);
                            if let (true, Some(note)) = (is_command, &lacking) {
                                view.notes = if view.notes.is_empty() {
                                    note.clone()
                                } else {
                                    format!("{}; {note}", view.notes)
                                };
                            }
                            view
                        })
                        .collect(),
                }
            })
            .collect(),
    }
}

/// For the error reply of a protocol whose drive answers functions it lacks: that its
/// function field then carries any other function, marked as the commands' are (Modbus:
/// + 80h), with the `unsupported_function` error code.
fn lacking_function_note(protocol: &ProtocolIr, name: &str) -> Option<String> {
    let entry = protocol.unsupported_function.as_ref()?;
    if protocol.error_reply.as_deref() != Some(name) {
        return None;
    }
    let first = protocol.commands.first()?;
    let offset = first.error_code?.wrapping_sub(first.code);
    Some(format!(
        "or any other function + {offset:02X}h, with error code {:02X}h: the reply to a function the drive lacks",
        entry.error_code
    ))
}

/// The command codes the drive's commands of `protocol` put in the layout `name`: their
/// own codes in their requests, their reply codes in their replies, their error codes in
/// the error reply. Empty when one of them leaves its code unknown (then the layout's own
/// list stands).
fn codes_in_layout(protocol: &ProtocolIr, name: &str) -> Vec<u32> {
    let mut used = Vec::new();
    for command in &protocol.commands {
        if command.request == name {
            used.push(command.code);
        }
        if command.reply == name && !command.no_reply {
            if command.reply_codes.is_empty() {
                used.push(command.code);
            } else {
                used.extend(command.reply_codes.iter().copied());
            }
        }
        if protocol.error_reply.as_deref() == Some(name) {
            match command.error_code {
                Some(code) => used.push(code),
                None => return Vec::new(),
            }
        }
    }
    used
}
