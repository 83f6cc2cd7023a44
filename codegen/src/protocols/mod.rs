//! Stage 3a, protocol lowering: turns each protocol file a drive uses, plus the drive's
//! error table, addressing, address maps and pre-steps, into the runtime's [`Protocol`]:
//! the value the generated code embeds and the example frames are decoded with. Problems in
//! a protocol file are reported here, with the protocol file's positions.
//!
//! A file `based_on` another comes merged with its base ([`crate::load::based_on`]). One
//! module per thing lowered: [`layouts`] (layouts and their sizes), [`parts`] (one
//! function per kind of part), [`commands`] (commands, codes and address maps),
//! [`pre_steps`], [`error_codes`] (which table names the error replies) and [`text`] (what
//! `text: true` forbids). Every function reports into one
//! [`Diagnostics`] and returns `None` when it cannot produce a value.

mod block;
mod commands;
mod error_codes;
mod frame_len;
mod layouts;
mod link;
mod lowered_command;
mod pages;
mod parts;
mod pre_steps;
mod text;
mod unsupported_function;
mod variants;

use crate::diagnostics::Diagnostics;
use crate::load::LoadedDrive;
use crate::parse::model::{DriveFile, ProtocolFile, ProtocolRef};
use crate::parse::SourceFile;
use std::borrow::Cow;
use vfd_runtime::protocol::VariantCache;
use vfd_runtime::{Protocol, Space};

/// Parses an address space.
pub fn space_from_name(name: &str) -> Option<Space> {
    Space::ALL.into_iter().find(|s| s.as_str() == name)
}

pub(crate) use error_codes::{check_notation, drive_table_applies};
pub use parts::parse_hex;

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
    drive
        .protocol_files
        .iter()
        .filter_map(|protocol| {
            let reference = &drive.model.protocols[protocol.reference];
            let input = Input {
                reference,
                reference_path: format!("protocols[{}]", protocol.reference),
                file: &protocol.file,
                source: &protocol.source,
                drive_source: &drive.source,
                drive: &drive.model,
            };
            let before = out.items.len();
            let runtime = lower_protocol(&input, out);
            if let Some(inherited) = &protocol.inherited {
                for item in &mut out.items[before..] {
                    inherited.relocate(&protocol.source, item);
                }
            }
            let runtime = runtime?;
            Some(LoweredProtocol {
                id: reference.id.clone(),
                uses: reference.uses.clone(),
                source_section: reference.source.clone(),
                file: protocol.file.clone(),
                runtime,
            })
        })
        .collect()
}

/// What lowering one protocol reads: the protocol file, and the drive file that refers to it.
pub(super) struct Input<'a> {
    /// The drive's entry under `protocols:`.
    pub reference: &'a ProtocolRef,
    /// Its YAML path in the drive file (`protocols[0]`).
    pub reference_path: String,
    /// The parsed protocol file.
    pub file: &'a ProtocolFile,
    /// The protocol file's text and positions.
    pub source: &'a SourceFile,
    /// The drive file's text and positions.
    pub drive_source: &'a SourceFile,
    /// The parsed drive file.
    pub drive: &'a DriveFile,
}

/// Builds the runtime protocol, reporting every problem found; `None` when there was one.
fn lower_protocol(input: &Input<'_>, out: &mut Diagnostics) -> Option<Protocol> {
    let (file, source) = (input.file, input.source);
    let before = out.items.len();
    let layouts = layouts::lower_layouts(file, source, out);
    layouts::check_rust_names(&input.reference.id, file, source, out);
    let commands = commands::lower_commands(input, &layouts, out);
    let file_writes_blocks = commands.iter().any(writes_blocks);
    let mut commands = commands::drive_subset(commands, input, out);
    commands::apply_command_registers(&mut commands, input, out);
    let block = block::lower_block(input, &commands, out);
    // Without a block selection the drive has no block transfer: its command is dropped.
    let commands: Vec<_> = commands
        .into_iter()
        .filter(|c| {
            c.spec.kind != vfd_runtime::CommandKind::Block || input.reference.block.is_some()
        })
        .collect();
    let error_reply = file
        .error_reply
        .as_ref()
        .and_then(|name| layouts.find(name, "error_reply", out));
    commands::check_error_codes(&commands, error_reply.as_ref(), source, out);
    commands::check_address_maps(input, out);
    commands::check_commands(&commands, source, out);
    layouts::check_frame_sizes(&commands, file, source, out);
    if file.protocol.text {
        text::check_text_protocol(&layouts, source, out);
    }
    check_id(input, out);
    let pre_steps = pre_steps::lower_pre_steps(input, out);
    layouts::check_default_optional_parts(file, source, out);
    error_codes::check_error_codes(input, out);
    let out_of_band = check_station_range(input, out);
    let max_words_per_read = max_words_per_read(input, &commands, out);
    let max_words_per_write = max_words_per_write(input, &commands, file_writes_blocks, out);
    let max_frame_len = frame_len::max_frame_len(
        input,
        &commands,
        max_words_per_read,
        max_words_per_write,
        out,
    );
    let frame_gap_chars = link::frame_gap_chars(input, out);
    let timing = link::timing(input, out);
    let broadcast = link::broadcast(input, &commands, out);
    let wire_numbers = wire_numbers(input, out);
    let paging = pages::paging(input, &commands, out);
    if out.items.len() > before {
        return None;
    }
    let meta = &file.protocol;
    let mut protocol = Protocol {
        id: Cow::Owned(input.reference.id.clone()),
        name: Cow::Owned(meta.name.clone()),
        commands: Cow::Owned(commands.into_iter().map(|c| c.spec).collect()),
        error_reply,
        lowercase_means_tripped: meta.lowercase_means_tripped,
        max_frame_len,
        address_range: station_range(input, out_of_band),
        default_optional_parts: Cow::Owned(
            meta.default_optional_parts
                .iter()
                .map(|p| Cow::Owned(p.clone()))
                .collect(),
        ),
        pre_steps: Cow::Owned(pre_steps),
        default_process: meta.default_process.unwrap_or([0, 0]),
        frame_gap_chars,
        max_words_per_read,
        max_words_per_write,
        partial_blocks: input.reference.partial_blocks,
        timing,
        broadcast,
        error_codes: Cow::Owned(error_codes::error_table(input)),
        block,
        wire_numbers: Cow::Owned(wire_numbers),
        paging,
        persistence: persistence(input.drive),
        variants: None,
        unsupported_function: None,
        variant_cache: VariantCache::new(),
    };
    protocol.unsupported_function =
        unsupported_function::unsupported_function(input, &protocol, &protocol.error_codes, out);
    protocol.variants = variants::lower_variants(input, &protocol, out);
    (out.items.len() == before).then_some(protocol)
}

/// The drive's persistence selector (`persistence:`), the same in each of its protocols;
/// `None` when it has none or its register is not found (which the checks report once).
fn persistence(drive: &crate::parse::model::DriveFile) -> Option<vfd_runtime::PersistenceSelector> {
    let model = drive.persistence.as_ref()?;
    let register = drive
        .registers
        .iter()
        .find(|r| r.is_named(&model.selector))?;
    Some(vfd_runtime::PersistenceSelector {
        register: u16::try_from(register.address).ok()?,
        space: register.space.unwrap_or(vfd_runtime::Space::Parameter),
        data_type: register.data_type.unwrap_or(vfd_runtime::DataType::Word),
        ram: model.ram,
        persistent: model.persistent,
        registers: Cow::Owned(
            model
                .registers
                .iter()
                .map(|span| (span.from, span.to))
                .collect(),
        ),
    })
}

/// The registers' own numbers on the wire in this protocol (`registers[].wire_numbers`),
/// each fitting 16 bits; registers may name only the drive's protocols. Two registers at
/// one address (one read-only, one write-only) make one entry.
fn wire_numbers(
    input: &Input<'_>,
    out: &mut Diagnostics,
) -> Vec<vfd_runtime::protocol::WireNumber> {
    let mut numbers = Vec::new();
    let none = crate::parse::model::WireNumberModel {
        read: None,
        write: None,
    };
    for (index, register) in input.drive.registers.iter().enumerate() {
        let own = match register.wire_numbers.get(&input.reference.id) {
            Some(own) => own,
            // A register without an address of its own is reached only where its wire
            // numbers or its place on a page say: on any other protocol, not at all.
            None if register.given_address.is_none()
                && !register.on_page.contains_key(&input.reference.id) =>
            {
                &none
            }
            None => continue,
        };
        let mut fit = |key: &str, value: Option<u32>| match value {
            Some(value) if value > u32::from(u16::MAX) => {
                out.push(
                    input
                        .drive_source
                        .error(
                            &format!(
                                "registers[{index}].wire_numbers.{}.{key}",
                                input.reference.id
                            ),
                            format!("{value:#X} does not fit the 16 bits of a register number"),
                        )
                        .hint("give the number as the protocol carries it, 0x0000-0xFFFF"),
                );
                None
            }
            other => other.map(|v| v as u16),
        };
        let (read, write) = (fit("read", own.read), fit("write", own.write));
        let address = register.address as u16;
        // Two registers sharing an address (one read, the other written) give one entry:
        // each its own direction.
        match numbers
            .iter_mut()
            .find(|n: &&mut vfd_runtime::protocol::WireNumber| n.register == address)
        {
            Some(shared) => {
                shared.read = shared.read.or(read);
                shared.write = shared.write.or(write);
            }
            None => numbers.push(vfd_runtime::protocol::WireNumber {
                register: address,
                read,
                write,
                data: Cow::Owned(Vec::new()),
            }),
        }
    }
    shared_write_numbers(input, &mut numbers, out);
    numbers
}

/// Registers sharing one write number (the DV1's parameter clears 1102h-1106h are all
/// Eaton HFC): the data picks the register, so each must have a code table and no value may
/// be in two of them; each entry then lists its values. A read number cannot be shared (a
/// read carries no data).
fn shared_write_numbers(
    input: &Input<'_>,
    numbers: &mut [vfd_runtime::protocol::WireNumber],
    out: &mut Diagnostics,
) {
    let protocol = &input.reference.id;
    // The register an entry stands for in one direction (two registers may share an
    // address, one read and one written).
    let index_of = |address: u16, read: bool| {
        input
            .drive
            .registers
            .iter()
            .position(|r| {
                r.address == u32::from(address)
                    && r.wire_numbers.get(protocol).is_some_and(|own| {
                        if read {
                            own.read.is_some()
                        } else {
                            own.write.is_some()
                        }
                    })
            })
            .unwrap_or(0)
    };
    for read in [true, false] {
        let number_of = |w: &vfd_runtime::protocol::WireNumber| if read { w.read } else { w.write };
        let mut seen: Vec<u16> = Vec::new();
        for i in 0..numbers.len() {
            let Some(wire) = number_of(&numbers[i]) else {
                continue;
            };
            if seen.contains(&wire) {
                continue;
            }
            seen.push(wire);
            let sharing: Vec<usize> = (i..numbers.len())
                .filter(|&j| number_of(&numbers[j]) == Some(wire))
                .collect();
            if sharing.len() < 2 {
                continue;
            }
            let key = if read { "read" } else { "write" };
            let mut taken: Vec<u32> = Vec::new();
            for &j in &sharing {
                let index = index_of(numbers[j].register, read);
                let register = &input.drive.registers[index];
                let path = format!("registers[{index}].wire_numbers.{protocol}.{key}");
                if read {
                    out.push(
                        input
                            .drive_source
                            .error(&path, format!("read number {wire:04X}h is shared by {} registers: a read carries no data to tell them apart", sharing.len()))
                            .hint("give each register its own read number; only write numbers may be shared, the data picking the register"),
                    );
                    break;
                }
                let table = register
                    .code_table
                    .as_deref()
                    .and_then(|id| input.drive.codes.iter().find(|t| t.id == id));
                let Some(table) = table else {
                    out.push(
                        input
                            .drive_source
                            .error(&path, format!("write number {wire:04X}h is shared with other registers, but `{}` has no code table: the data cannot tell which register is meant", register.id))
                            .hint("give each register sharing a write number a code table of the values it takes (the data picks the register)"),
                    );
                    continue;
                };
                let values: Vec<u32> = table.values.iter().map(|v| v.value).collect();
                if let Some(twice) = values.iter().find(|v| taken.contains(v)) {
                    out.push(
                        input
                            .drive_source
                            .error(&path, format!("value {twice:#06X} of `{}` is also a value of another register sharing write number {wire:04X}h: the data cannot tell them apart", register.id))
                            .hint("registers sharing a write number must take different values"),
                    );
                }
                taken.extend(&values);
                numbers[j].data = Cow::Owned(values);
            }
        }
    }
}

/// The most registers one write carries: the protocol file's `max_words_per_write`,
/// lowered by the drive's. Above 1, a RAM write command's data field must be sized by a
/// length part, and a block must fit the one byte a frame's data size is held in.
/// Whether a lowered command is a RAM write that can carry several registers.
fn writes_blocks(command: &lowered_command::LoweredCommand) -> bool {
    command.spec.kind == vfd_runtime::CommandKind::WriteRam
        && vfd_runtime::protocol::command_writes_blocks(&command.spec)
}

/// (A drive whose subset of the file's commands leaves out every such write, the VF-AS1's
/// Modbus with 03 and 06 only, writes one register at a time without saying so.)
fn max_words_per_write(
    input: &Input<'_>,
    commands: &[lowered_command::LoweredCommand],
    file_writes_blocks: bool,
    out: &mut Diagnostics,
) -> u16 {
    let file = input.file.protocol.max_words_per_write;
    let drive = input.reference.max_words_per_write;
    if word_limit(input, "max_words_per_write", file, drive, "write", out).is_none() {
        return 1;
    }
    let value = drive.or(file).unwrap_or(1);
    let drive_writes_blocks = commands.iter().any(writes_blocks);
    if value > 1 && drive.is_none() && file_writes_blocks && !drive_writes_blocks {
        return 1;
    }
    if value > 1 && !drive_writes_blocks {
        let (source, path) = match drive {
            Some(_) => (
                input.drive_source,
                format!("{}.max_words_per_write", input.reference_path),
            ),
            None => (input.source, "protocol.max_words_per_write".to_owned()),
        };
        out.push(
            source
                .error(
                    &path,
                    format!("max_words_per_write is {value}, but no RAM write command can carry several registers"),
                )
                .hint(
                    "a RAM write's request needs a data field with `size: length` (a length part counting it); \
                     or leave max_words_per_write out",
                ),
        );
        return 1;
    }
    value
}

/// The most registers one read carries: the protocol file's `max_words_per_read`, lowered
/// by the drive's. Above 1, a read command must count its data, and a block must fit the
/// one byte a frame's data size is held in (127 words).
fn max_words_per_read(
    input: &Input<'_>,
    commands: &[lowered_command::LoweredCommand],
    out: &mut Diagnostics,
) -> u16 {
    let file = input.file.protocol.max_words_per_read;
    let drive = input.reference.max_words_per_read;
    if word_limit(input, "max_words_per_read", file, drive, "read", out).is_none() {
        return 1;
    }
    let value = drive.or(file).unwrap_or(1);
    if value > 1
        && !commands.iter().any(|c| {
            c.spec.kind == vfd_runtime::CommandKind::Read
                && vfd_runtime::protocol::command_reads_blocks(&c.spec)
        })
    {
        let (source, path) = match drive {
            Some(_) => (
                input.drive_source,
                format!("{}.max_words_per_read", input.reference_path),
            ),
            None => (input.source, "protocol.max_words_per_read".to_owned()),
        };
        out.push(
            source
                .error(
                    &path,
                    format!("max_words_per_read is {value}, but no read command can carry a count"),
                )
                .hint(
                    "a read's request needs a length part with `counts: data_size` and its reply a \
                     data field with `size: length`; or leave max_words_per_read out",
                ),
        );
        return 1;
    }
    value
}

/// The stations this protocol reaches: the reference's `addressing`, else the drive's.
fn station_range(input: &Input<'_>, checked: Option<(u8, u8)>) -> (u8, u8) {
    checked.unwrap_or((input.drive.addressing.min, input.drive.addressing.max))
}

/// A protocol's own station range lies within the drive's and is not empty; returns it.
fn check_station_range(input: &Input<'_>, out: &mut Diagnostics) -> Option<(u8, u8)> {
    let range = input.reference.addressing?;
    let drive = &input.drive.addressing;
    let path = format!("{}.addressing", input.reference_path);
    if range.min > range.max || range.min < drive.min || range.max > drive.max {
        out.push(
            input
                .drive_source
                .error(
                    &path,
                    format!(
                        "station range {}-{} of protocol `{}` is not within the drive's {}-{}",
                        range.min, range.max, input.reference.id, drive.min, drive.max
                    ),
                )
                .hint("a protocol may reach fewer stations than the drive, not more: check `addressing` and this range against the manual"),
        );
        return None;
    }
    Some((range.min, range.max))
}

/// The protocol file's id must be its file name, which is how drive files name it.
fn check_id(input: &Input<'_>, out: &mut Diagnostics) {
    let (said, uses) = (&input.file.protocol.id, &input.reference.uses);
    if said != uses {
        out.push(
            input
                .source
                .error(
                    "protocol.id",
                    format!("the file is `{uses}.yaml` but says `id: {said}`"),
                )
                .hint("make the id match the file name, which is how drive files refer to it"),
        );
    }
}

/// `a, b, c`: names for a hint.
fn names_of<'a>(names: impl Iterator<Item = &'a String>) -> String {
    names.map(String::as_str).collect::<Vec<_>>().join(", ")
}

#[cfg(test)]
mod test_support;

/// Checks a limit of words per request (`key`: `max_words_per_read` or
/// `max_words_per_write`) as the protocol file (`file`) and the drive (`drive`) give it:
/// each 1 to 127 (a frame's data size is one byte), the drive's at most the file's.
/// `None` when a problem was reported.
fn word_limit(
    input: &Input<'_>,
    key: &str,
    file: Option<u16>,
    drive: Option<u16>,
    what: &str,
    out: &mut Diagnostics,
) -> Option<()> {
    for (value, source, path) in [
        (file, input.source, format!("protocol.{key}")),
        (
            drive,
            input.drive_source,
            format!("{}.{key}", input.reference_path),
        ),
    ] {
        if value.is_some_and(|v| v == 0 || v > 127) {
            out.push(
                source
                    .error(&path, format!("{key} must be 1 to 127"))
                    .hint(format!(
                        "a {what}'s data size is one byte: at most 127 registers of 2 bytes"
                    )),
            );
            return None;
        }
    }
    if let (Some(drive), file) = (drive, file.unwrap_or(1)) {
        if drive > file {
            out.push(
                input
                    .drive_source
                    .error(
                        &format!("{}.{key}", input.reference_path),
                        format!("{key} {drive} is above the protocol file's {file}"),
                    )
                    .hint("a drive may only lower the protocol's limit"),
            );
            return None;
        }
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::test_support::{at, lowered, problems, protocol_with, PROTOCOL};

    #[test]
    fn a_protocol_file_lowers_with_the_drive_addressing_and_error_codes() {
        let protocol = lowered(PROTOCOL);
        assert_eq!(
            (protocol.id.as_ref(), protocol.name.as_ref()),
            ("ascii", "Test ASCII")
        );
        assert_eq!(protocol.max_frame_len, 17);
        assert_eq!(protocol.address_range, (0, 31));
        assert_eq!(protocol.commands.len(), 2);
        assert_eq!(
            protocol.error_reply.as_ref().map(|l| l.name.as_ref()),
            Some("error_reply")
        );
        assert_eq!(protocol.default_optional_parts.as_ref(), ["sum"]);
        assert_eq!(protocol.default_process, [0, 0]);
        let codes: Vec<(u16, &str)> = protocol
            .error_codes
            .iter()
            .map(|c| (c.code, c.id.as_ref()))
            .collect();
        assert_eq!(codes, [(1, "data_error")]);
    }

    #[test]
    fn the_id_must_be_the_file_name() {
        let yaml = protocol_with(&[("  id: test\n", "  id: tset\n")]);
        assert_eq!(
            problems(&yaml),
            [format!(
                "{} protocol.id: the file is `test.yaml` but says `id: tset`",
                at(&yaml, "tset")
            )]
        );
    }
}
