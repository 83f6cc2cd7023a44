//! The page view: the IR plus the words the templates print. Each view wraps its IR item
//! (flattened, so the template reads `r.code` and `r.range_display` alike) and adds only
//! text built for people.

use super::layouts::{part_view, PartView};
use crate::emit::words::{
    address_label, bit_order_text, default_text, duplex_text, inferred_text, meaning_text,
    range_text, shown_bytes, synchronisation_text, topology_text, value_text, value_type_text,
    warning_text,
};
use crate::ir::*;
use serde::Serialize;
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::{FrameLayout, Part, PreStep, Role, Space};

#[derive(Serialize)]
pub(super) struct DriveView<'a> {
    #[serde(flatten)]
    drive: &'a DriveIr,
    serial: SerialView<'a>,
    protocols: Vec<ProtocolView<'a>>,
    error_codes: ErrorCodesView<'a>,
    /// The protocols the drive's table does not apply to, with the tables they use.
    protocol_error_tables: Vec<ProtocolErrorsView<'a>>,
    registers: Vec<RegisterView<'a>>,
    bitfields: Vec<BitfieldView<'a>>,
    code_tables: Vec<CodeTableView<'a>>,
    reference_scaling: Option<ScalingView<'a>>,
    value_examples: Vec<ValueExampleView<'a>>,
    examples: Vec<ExampleView<'a>>,
    /// The multi-step examples, each with its frames shown.
    sequences: Vec<SequenceView<'a>>,
    /// The drive's warnings, then each register's, as sentences.
    warning_lines: Vec<WarningView>,
    /// The serial ports, when the drive has several.
    ports: Option<PortsView<'a>>,
    /// Live registers and the registers holding their value at a trip.
    held_pairs: Vec<HeldPairView>,
    /// The manual's formulas.
    conversions: Vec<ConversionView<'a>>,
}

#[derive(Serialize)]
struct PortsView<'a> {
    #[serde(flatten)]
    ports: &'a PortsIr,
    /// The settings' names (the columns of the ports table).
    setting_names: Vec<&'a str>,
    /// Per port: its id, names and the register setting each named setting.
    rows: Vec<(String, String, String, Vec<String>)>,
    /// Per-port register groups: (name of the first copy, the copies in port order).
    pairs: Vec<(String, Vec<String>)>,
}

#[derive(Serialize)]
struct HeldPairView {
    live: String,
    held: String,
    name: String,
    /// The held register keeps its value only while tripped (no live partner).
    live_except_while_tripped: bool,
}

#[derive(Serialize)]
struct ConversionView<'a> {
    #[serde(flatten)]
    conversion: &'a ConversionIr,
    inputs_display: String,
    when_display: String,
    examples_display: String,
}

#[derive(Serialize)]
struct WarningView {
    /// What it is about: empty for the drive, else the register's code.
    subject: String,
    text: String,
}

#[derive(Serialize)]
struct SerialView<'a> {
    #[serde(flatten)]
    serial: &'a SerialIr,
    /// Character time at the default settings, in microseconds.
    char_time_us: u128,
    /// Line facts as (setting, value) rows.
    line_rows: Vec<(&'static str, &'static str)>,
    /// Which timings are assumed, by their key.
    assumed: Vec<&'static str>,
}

#[derive(Serialize)]
struct ProtocolView<'a> {
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

#[derive(Serialize)]
struct ErrorCodesView<'a> {
    #[serde(flatten)]
    error_codes: &'a ErrorCodesIr,
    codes: Vec<ErrorCodeView<'a>>,
    /// The protocols it applies to, as `` `fc`, `modbus` ``.
    protocols_display: String,
}

#[derive(Serialize)]
struct ProtocolErrorsView<'a> {
    id: &'a str,
    name: &'a str,
    table: ErrorCodesView<'a>,
}

fn error_codes_view(table: &ErrorCodesIr) -> ErrorCodesView<'_> {
    ErrorCodesView {
        error_codes: table,
        codes: table
            .codes
            .iter()
            .map(|code| ErrorCodeView {
                code,
                code_hex: format!("{:04X}h", code.code),
            })
            .collect(),
        protocols_display: table
            .protocols
            .iter()
            .map(|id| format!("`{id}`"))
            .collect::<Vec<_>>()
            .join(", "),
    }
}

#[derive(Serialize)]
struct ErrorCodeView<'a> {
    #[serde(flatten)]
    code: &'a ErrorCodeIr,
    code_hex: String,
}

#[derive(Serialize)]
struct RegisterView<'a> {
    #[serde(flatten)]
    register: &'a RegisterIr,
    address_display: String,
    address_hex: String,
    scale_display: String,
    range_display: String,
    default_display: String,
    value_type_display: String,
    /// The inferred facts in words, empty when there are none.
    inferred_display: String,
    /// Its relations to other registers (held copy, scale selector, port copies), as
    /// sentences; empty when there are none.
    relations_display: String,
    /// The typed API's aliases of its type (`registers::P195`).
    alias_types: Vec<String>,
}

#[derive(Serialize)]
struct BitfieldView<'a> {
    #[serde(flatten)]
    bitfield: &'a BitfieldIr,
    fields: Vec<BitView<'a>>,
    examples: Vec<BitExampleView<'a>>,
}

#[derive(Serialize)]
struct BitView<'a> {
    #[serde(flatten)]
    field: &'a BitIr,
    bits_label: String,
    name: &'a str,
}

#[derive(Serialize)]
struct BitExampleView<'a> {
    #[serde(flatten)]
    example: &'a BitExampleIr,
    value_hex: String,
    /// The one-bit fields set and the multi-bit fields' values (`character = 30h`).
    fields_display: String,
}

#[derive(Serialize)]
struct CodeTableView<'a> {
    #[serde(flatten)]
    table: &'a CodeTableIr,
    values: Vec<CodeValueView<'a>>,
}

#[derive(Serialize)]
struct CodeValueView<'a> {
    #[serde(flatten)]
    value: &'a CodeValueIr,
    value_hex: String,
    /// What it sets on the line and which protocol it chooses, where it says.
    sets: String,
}

#[derive(Serialize)]
struct ScalingView<'a> {
    #[serde(flatten)]
    scaling: &'a ReferenceScalingIr,
    modes: Vec<ScalingModeView<'a>>,
}

#[derive(Serialize)]
struct ScalingModeView<'a> {
    selector: u32,
    low: String,
    high: String,
    description: &'a str,
}

#[derive(Serialize)]
struct ValueExampleView<'a> {
    #[serde(flatten)]
    example: &'a ValueExampleIr,
    register_code: String,
    value_display: String,
    raw_hex: String,
}

#[derive(Serialize)]
struct ExampleView<'a> {
    #[serde(flatten)]
    example: &'a ExampleIr,
    register_code: String,
    value_display: String,
    settings_display: String,
    request: Option<FrameView<'a>>,
    reply: Option<FrameView<'a>>,
    /// The request is never answered (its command's `reply: none`, or a write of a register
    /// with `no_reply: true`).
    unanswered: bool,
    /// The bytes of the request the drive ignores, for a table cell.
    ignored_shown: String,
}

#[derive(Serialize)]
struct FrameView<'a> {
    shown: String,
    meaning: String,
    printed: Option<PrintedView<'a>>,
}

#[derive(Serialize)]
struct PrintedView<'a> {
    #[serde(flatten)]
    printed: &'a PrintedIr,
    shown: String,
}

#[derive(Serialize)]
struct SequenceView<'a> {
    #[serde(flatten)]
    sequence: &'a crate::ir::SequenceIr,
    register_code: String,
    call_display: String,
    result_display: String,
    steps: Vec<SequenceStepView<'a>>,
}

#[derive(Serialize)]
struct SequenceStepView<'a> {
    number: usize,
    from: &'static str,
    shown: String,
    how: &'static str,
    note: &'a str,
}

fn sequence_view<'a>(drive: &'a DriveIr, sequence: &'a crate::ir::SequenceIr) -> SequenceView<'a> {
    use crate::ir::{SequenceCallIr, SequenceResultIr};
    use crate::parse::model::{Sender, Shown};
    let register = drive.register(&sequence.register);
    let code = register.map_or_else(|| sequence.register.clone(), |r| r.code.clone());
    let value = |v: f64| register.map_or_else(|| v.to_string(), |r| value_text(r, v));
    SequenceView {
        sequence,
        call_display: match sequence.call {
            SequenceCallIr::Read => format!("read {code}"),
            SequenceCallIr::Write(v) => format!("write {} to {code}", value(v)),
            SequenceCallIr::WriteRaw(raw) => format!("write the raw word {raw:04X}h to {code}"),
        },
        result_display: match &sequence.result {
            SequenceResultIr::Value(v) => value(*v),
            SequenceResultIr::Written => "written".to_owned(),
            SequenceResultIr::Error(code, id) => format!("refused with {code:02X}h `{id}`"),
        },
        register_code: code,
        steps: sequence
            .steps
            .iter()
            .enumerate()
            .map(|(index, step)| SequenceStepView {
                number: index + 1,
                from: match step.from {
                    Sender::Master => "master",
                    Sender::Drive => "drive",
                },
                shown: shown(&step.bytes),
                how: match step.shown {
                    Shown::Printed => "printed",
                    Shown::Elided => "elided (略)",
                    Shown::Derived => "not printed",
                },
                note: &step.note,
            })
            .collect(),
    }
}

/// `` `bytes` `` for a table cell: text with `<CR>`, or hex pairs.
fn shown(bytes: &[u8]) -> String {
    format!("`{}`", shown_bytes(bytes))
}

impl<'a> DriveView<'a> {
    pub(super) fn new(drive: &'a DriveIr) -> Self {
        let register = |id: &str| drive.register(id);
        DriveView {
            drive,
            serial: SerialView {
                serial: &drive.serial,
                char_time_us: SerialSettings {
                    baud: drive.serial.default_baud,
                    data_bits: drive.serial.default_data_bits,
                    parity: drive.serial.default_parity,
                    stop_bits: drive.serial.default_stop_bits,
                }
                .char_time()
                .as_micros(),
                line_rows: drive.serial.line.as_ref().map_or_else(Vec::new, |line| {
                    let mut rows = Vec::new();
                    if let Some(duplex) = line.duplex {
                        rows.push(("Transmission", duplex_text(duplex)));
                    }
                    if let Some(topology) = line.topology {
                        rows.push(("Line control", topology_text(topology)));
                    }
                    if let Some(sync) = line.synchronisation {
                        rows.push(("Synchronisation", synchronisation_text(sync)));
                    }
                    if let Some(order) = line.bit_order {
                        rows.push(("Bit order", bit_order_text(order)));
                    }
                    rows
                }),
                assumed: drive
                    .serial
                    .assumed_timing
                    .iter()
                    .map(|field| match field {
                        TimingField::StartupDelayMs => "startup_delay_ms",
                        TimingField::FrameAbandonMs => "frame_abandon_ms",
                        TimingField::ProcessingAllowanceMs => "processing_allowance_ms",
                    })
                    .collect(),
            },
            warning_lines: drive
                .warnings
                .iter()
                .map(|w| (String::new(), w))
                .chain(drive.registers.iter().flat_map(|r| {
                    r.warnings.iter().map(move |w| {
                        let label = address_label(r);
                        let subject = if label == r.code {
                            r.code.clone()
                        } else {
                            format!("{} ({label})", r.code)
                        };
                        (subject, w)
                    })
                }))
                .map(|(subject, warning)| WarningView {
                    subject,
                    text: warning_text(warning),
                })
                .collect(),
            protocols: drive
                .protocols
                .iter()
                .map(|p| protocol_view(drive, p))
                .collect(),
            error_codes: error_codes_view(&drive.error_codes),
            protocol_error_tables: drive
                .protocols
                .iter()
                .filter_map(|p| match &p.error_table {
                    ErrorTableIr::Drive => None,
                    ErrorTableIr::Protocol(table) => Some(ProtocolErrorsView {
                        id: &p.id,
                        name: &p.name,
                        table: error_codes_view(table),
                    }),
                })
                .collect(),
            registers: drive
                .registers
                .iter()
                .map(|register| RegisterView {
                    register,
                    address_display: address_label(register),
                    address_hex: format!("{:04X}", register.address),
                    scale_display: format!("{}", register.scale),
                    range_display: range_text(register),
                    default_display: default_text(register),
                    value_type_display: format!("`{}`", value_type_text(register)),
                    inferred_display: inferred_text(&register.inferred),
                    relations_display: crate::emit::rust::relation_lines(register).join(" "),
                    alias_types: register
                        .aliases
                        .iter()
                        .filter_map(|alias| crate::naming::alias_type_name(alias))
                        .map(|name| format!("registers::{name}"))
                        .collect(),
                })
                .collect(),
            bitfields: drive
                .bitfields
                .iter()
                .map(|bitfield| BitfieldView {
                    bitfield,
                    fields: bitfield
                        .fields
                        .iter()
                        .map(|field| BitView {
                            field,
                            bits_label: if field.width == 1 {
                                field.lsb.to_string()
                            } else {
                                format!("{}:{}", field.lsb + field.width - 1, field.lsb)
                            },
                            name: if field.reserved && field.name.is_empty() {
                                "Reserved"
                            } else {
                                &field.name
                            },
                        })
                        .collect(),
                    examples: bitfield
                        .examples
                        .iter()
                        .map(|example| BitExampleView {
                            example,
                            value_hex: format!("{:04X}h", example.value),
                            fields_display: example
                                .set
                                .iter()
                                .cloned()
                                .chain(
                                    example
                                        .fields
                                        .iter()
                                        .map(|(id, v)| format!("{id} = {v:X}h")),
                                )
                                .collect::<Vec<_>>()
                                .join(", "),
                        })
                        .collect(),
                })
                .collect(),
            code_tables: drive
                .code_tables
                .iter()
                .map(|table| CodeTableView {
                    table,
                    values: table
                        .values
                        .iter()
                        .map(|value| CodeValueView {
                            value,
                            value_hex: format!("{:04X}h", value.value),
                            sets: code_value_sets(value),
                        })
                        .collect(),
                })
                .collect(),
            reference_scaling: drive.reference_scaling.as_ref().map(|scaling| {
                let end = |end: &SpanEndIr| match end {
                    SpanEndIr::Number(value) => format!("{value:?}"),
                    SpanEndIr::Register(id) => id.clone(),
                };
                ScalingView {
                    scaling,
                    modes: scaling
                        .modes
                        .iter()
                        .map(|mode| ScalingModeView {
                            selector: mode.selector,
                            low: end(&mode.low),
                            high: end(&mode.high),
                            description: &mode.description,
                        })
                        .collect(),
                }
            }),
            value_examples: drive
                .value_examples
                .iter()
                .filter_map(|example| {
                    let register = register(&example.register)?;
                    let given: Vec<String> = example
                        .given
                        .iter()
                        .map(|(code, value)| format!("{code} = {value}"))
                        .collect();
                    let value = value_text(register, example.value);
                    Some(ValueExampleView {
                        example,
                        register_code: register.code.clone(),
                        value_display: if given.is_empty() {
                            value
                        } else {
                            format!("{value} (with {})", given.join(", "))
                        },
                        raw_hex: format!("{:04X}h", example.raw),
                    })
                })
                .collect(),
            ports: drive.ports.as_ref().map(|ports| {
                let setting_names: Vec<&str> = ports
                    .ports
                    .first()
                    .map(|p| p.settings.iter().map(|(name, _)| name.as_str()).collect())
                    .unwrap_or_default();
                PortsView {
                    ports,
                    rows: ports
                        .ports
                        .iter()
                        .map(|port| {
                            (
                                port.id.clone(),
                                port.name.clone(),
                                port.name_zh.clone(),
                                setting_names
                                    .iter()
                                    .map(|name| {
                                        port.settings.iter().find(|(n, _)| n == name).map_or_else(
                                            || "—".to_owned(),
                                            |(_, code)| code.clone(),
                                        )
                                    })
                                    .collect(),
                            )
                        })
                        .collect(),
                    setting_names,
                    pairs: ports
                        .registers
                        .iter()
                        .map(|row| {
                            let name = row
                                .first()
                                .and_then(|code| drive.registers.iter().find(|r| &r.code == code))
                                .map_or_else(String::new, |r| r.name.clone());
                            (name, row.clone())
                        })
                        .collect(),
                }
            }),
            held_pairs: drive
                .registers
                .iter()
                .filter_map(|r| {
                    if let Some(live) = &r.held_at_trip_of {
                        Some(HeldPairView {
                            live: live.clone(),
                            held: r.code.clone(),
                            name: r.name.clone(),
                            live_except_while_tripped: false,
                        })
                    } else if r.live_except_while_tripped {
                        Some(HeldPairView {
                            live: r.code.clone(),
                            held: r.code.clone(),
                            name: r.name.clone(),
                            live_except_while_tripped: true,
                        })
                    } else {
                        None
                    }
                })
                .collect(),
            conversions: drive
                .conversions
                .iter()
                .map(|conversion| ConversionView {
                    conversion,
                    inputs_display: conversion
                        .inputs
                        .iter()
                        .map(|input| match &input.register {
                            Some(code) if (input.times - 1.0).abs() > f64::EPSILON => {
                                format!("`{}` = {} × {code}", input.name, input.times)
                            }
                            Some(code) => format!("`{}` = {code}", input.name),
                            None => format!("`{}`: {}", input.name, input.description),
                        })
                        .collect::<Vec<_>>()
                        .join("; "),
                    when_display: match &conversion.when {
                        Some((code, Some(value))) => format!("{code} = {value}"),
                        Some((code, None)) => format!("{code} ≠ 0"),
                        None => "always".to_owned(),
                    },
                    examples_display: conversion
                        .examples
                        .iter()
                        .map(|(inputs, result, source)| {
                            let args: Vec<String> = conversion
                                .inputs
                                .iter()
                                .zip(inputs)
                                .map(|(input, value)| format!("{} = {value}", input.name))
                                .collect();
                            format!("{} → {result} ({source})", args.join(", "))
                        })
                        .collect::<Vec<_>>()
                        .join("; "),
                })
                .collect(),
            sequences: drive
                .sequences
                .iter()
                .map(|sequence| sequence_view(drive, sequence))
                .collect(),
            examples: drive
                .examples
                .iter()
                .map(|example| {
                    let described = example.register.as_deref().and_then(register);
                    let frame = |frame: &'a Option<FrameIr>| {
                        frame.as_ref().map(|frame| FrameView {
                            shown: shown(&frame.bytes),
                            meaning: meaning_text(drive, frame),
                            printed: frame.printed.as_ref().map(|printed| PrintedView {
                                printed,
                                shown: shown(&printed.bytes),
                            }),
                        })
                    };
                    let unanswered = example
                        .request
                        .as_ref()
                        .is_some_and(|frame| request_unanswered(drive, example, frame, described));
                    ExampleView {
                        unanswered,
                        ignored_shown: example
                            .ignored_request
                            .as_ref()
                            .map_or_else(String::new, |ignored| shown(&ignored.bytes)),
                        example,
                        register_code: described.map(|r| r.code.clone()).unwrap_or_default(),
                        value_display: match (example.value, described) {
                            (Some(value), Some(r)) => value_text(r, value),
                            _ => String::new(),
                        },
                        settings_display: example
                            .settings
                            .iter()
                            .map(|(code, value)| format!("{code} = {value}"))
                            .collect::<Vec<_>>()
                            .join(", "),
                        request: frame(&example.request),
                        reply: frame(&example.reply),
                    }
                })
                .collect(),
        }
    }
}

/// Whether the request `frame` of `example` is never answered: its command says so, or it
/// writes a register whose writes are not answered.
fn request_unanswered(
    drive: &DriveIr,
    example: &ExampleIr,
    frame: &FrameIr,
    register: Option<&RegisterIr>,
) -> bool {
    let meaning = &frame.meaning;
    let command = drive
        .protocols
        .iter()
        .find(|p| p.id == example.protocol)
        .and_then(|p| {
            p.commands.iter().find(|c| {
                Some(c.kind) == meaning.kind
                    && meaning.code.is_some_and(|code| {
                        code == c.code
                            || (c.lowercase_means_sender_tripped
                                && u8::try_from(code)
                                    .is_ok_and(|b| u32::from(b.to_ascii_uppercase()) == c.code))
                    })
            })
        });
    command.is_some_and(|c| c.no_reply)
        || (meaning.kind.is_some_and(|k| k.is_write()) && register.is_some_and(|r| r.no_reply))
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
    if command.lowercase_means_sender_tripped {
        notes.push("lower case: the sender (master) has tripped".to_owned());
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

/// What a code value sets on the line and which protocol it chooses (` — line 7 data
/// bits, no parity, 2 stop bits; protocol `modbus_ascii``), empty when it says neither.
fn code_value_sets(value: &CodeValueIr) -> String {
    let mut parts = Vec::new();
    if let Some((data_bits, parity, stop_bits)) = value.line {
        let parity = match parity {
            vfd_runtime::serial::Parity::None => "no parity",
            vfd_runtime::serial::Parity::Even => "even parity",
            vfd_runtime::serial::Parity::Odd => "odd parity",
        };
        let stops = if stop_bits == 1 {
            "stop bit"
        } else {
            "stop bits"
        };
        parts.push(format!(
            "line: {data_bits} data bits, {parity}, {stop_bits} {stops}"
        ));
    }
    if let Some(protocol) = &value.protocol {
        parts.push(format!("protocol `{protocol}`"));
    }
    if parts.is_empty() {
        String::new()
    } else {
        format!(" — {}", parts.join("; "))
    }
}

/// The code of the parameter register at `number`, or the number in hex when none is
/// described there.
fn parameter_code(drive: &DriveIr, number: u16) -> String {
    drive
        .register_at(Space::Parameter, number)
        .map_or_else(|| format!("{number:04X}h"), |r| r.code.clone())
}

/// One paragraph on a protocol's pages: the ranges, the page register, what resets it.
fn pages_rule(
    drive: &DriveIr,
    paging: &vfd_runtime::protocol::Paging,
    doc: &crate::ir::PagesDocIr,
) -> String {
    let ranges: Vec<String> = paging
        .ranges
        .iter()
        .zip(&doc.range_names)
        .map(|(range, name)| {
            let last_page = range.first_page + (range.last - range.first) / range.size;
            let missing = if range.missing.is_empty() {
                String::new()
            } else {
                let pages: Vec<String> = range.missing.iter().map(|p| p.to_string()).collect();
                format!(" (no page {})", pages.join(", "))
            };
            format!(
                "{name}: registers {:04X}h-{:04X}h, {} to a page, pages {}-{last_page}{missing}",
                range.first, range.last, range.size, range.first_page
            )
        })
        .collect();
    let select = match paging.select_read {
        Some(read) => format!("read {read:02X}h, write {:02X}h", paging.select_write),
        None => format!("write {:02X}h", paging.select_write),
    };
    let forgotten: Vec<String> = paging
        .forgotten_after
        .iter()
        .map(|number| parameter_code(drive, *number))
        .collect();
    let mut text = format!(
        "Parameter pages (manual section {}): {}. A request carries a paged register's offset in its page; the master first writes the page to the page register ({select}), only when the station is not known to be on that page, and forgets the page after any error",
        doc.source,
        ranges.join("; ")
    );
    if !forgotten.is_empty() {
        text.push_str(&format!(" and after writing {}", forgotten.join(", ")));
    }
    text.push_str(&format!(
        ". A drive starts on page {}{}.",
        paging.initial,
        if doc.assumed.iter().any(|a| a == "initial") {
            " (an assumption: the manual does not say)"
        } else {
            ""
        }
    ));
    if !doc.note.is_empty() {
        text.push(' ');
        text.push_str(&doc.note);
    }
    text
}

fn protocol_view<'a>(drive: &'a DriveIr, protocol: &'a ProtocolIr) -> ProtocolView<'a> {
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
                let parts = drive_error_functions(protocol, layout);
                LayoutView {
                    name: layout.name.to_string(),
                    parts: parts.iter().map(|part| part_view(part, &parts)).collect(),
                }
            })
            .collect(),
    }
}

/// `layout`'s parts as this drive sends them: in the error reply, the function field
/// allows only the error codes of the drive's own commands (the FC 51 sends no 88h: it has
/// no function 08), when each command names one; as the protocol file gives them otherwise.
fn drive_error_functions(protocol: &ProtocolIr, layout: &FrameLayout) -> Vec<Part> {
    let mut parts = layout.parts.to_vec();
    if protocol.error_reply.as_deref() != Some(layout.name.as_ref()) {
        return parts;
    }
    let codes: Option<Vec<u32>> = protocol.commands.iter().map(|c| c.error_code).collect();
    let Some(codes) = codes.filter(|codes| !codes.is_empty()) else {
        return parts;
    };
    for part in &mut parts {
        if let Part::Field(field) = part {
            if field.role == Role::Command && !field.allowed.is_empty() {
                let kept: Vec<u32> = field
                    .allowed
                    .iter()
                    .copied()
                    .filter(|code| codes.contains(code))
                    .collect();
                field.allowed = std::borrow::Cow::Owned(kept);
            }
        }
    }
    parts
}

/// One sentence per line rule the drive states for `protocol`.
fn link_rules(drive: &DriveIr, protocol: &ProtocolIr) -> Vec<String> {
    use vfd_runtime::serial::BeforeStart;
    let timing = &protocol.timing;
    let ms = |d: std::time::Duration| {
        let text = format!("{:.2}", d.as_secs_f64() * 1000.0);
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    };
    let mut rules = Vec::new();
    if !timing.frame_gap_min.is_zero() {
        rules.push(format!(
            "The silence between frames is at least {} ms whatever the baud rate.",
            ms(timing.frame_gap_min)
        ));
    }
    if timing.max_inner_gap_chars > 0.0 {
        rules.push(format!(
            "A frame may not hold a silence of {} character times or more: the drive drops it.",
            timing.max_inner_gap_chars
        ));
    }
    if timing.before_start == BeforeStart::Reject {
        rules.push(
            "Bytes before a frame's start sequence reject the frame (it is not answered)."
                .to_owned(),
        );
    }
    if let Some(delay) = &timing.reply_delay {
        let names: Vec<String> = delay
            .registers
            .iter()
            .map(|number| parameter_code(drive, *number))
            .collect();
        rules.push(format!(
            "Every reply waits the time set by {} (0-{} ms in steps of {} ms, factory setting {} ms); the master adds it to the reply timeout{}.",
            names.join(" / "),
            ms(delay.max),
            ms(delay.step),
            ms(delay.default),
            if names.len() > 1 { ", the longer of them" } else { "" }
        ));
    }
    if let (Some(paging), Some(doc)) = (&protocol.paging, &protocol.pages_doc) {
        rules.push(pages_rule(drive, paging, doc));
    }
    if let Some(rule) = &protocol.broadcast {
        let codes: Vec<String> = rule
            .commands
            .iter()
            .map(|c| format!("`{}`", vfd_runtime::protocol::code_label(*c)))
            .collect();
        let answered = match rule.answered_by {
            vfd_runtime::BroadcastAnswer::None => "no station answers".to_owned(),
            vfd_runtime::BroadcastAnswer::LowestMatching => {
                "only the lowest station addressed answers, if it exists".to_owned()
            }
        };
        rules.push(format!(
            "Broadcasts: {} may be sent to every station (or a group, where the station field has a wildcard); {answered}.",
            codes.join(", ")
        ));
    }
    if let Some(variants) = &protocol.variants {
        rules.push(variants_rule(drive, protocol, variants));
    }
    rules.extend(unsupported_function_rule(drive, protocol));
    rules
}

/// One sentence on what the drive answers to a function it lacks, for protocols whose
/// error replies mark the request's function one way for every command (Modbus: function
/// + 80h): the manual's error code, or that the manual does not say.
fn unsupported_function_rule(drive: &DriveIr, protocol: &ProtocolIr) -> Option<String> {
    let mut offsets = protocol
        .commands
        .iter()
        .map(|c| c.error_code.map(|e| e.wrapping_sub(c.code)));
    let offset = offsets.next()??;
    if protocol.error_reply.is_none() || !offsets.all(|o| o == Some(offset)) {
        return None;
    }
    let codes: Vec<String> = protocol
        .commands
        .iter()
        .map(|c| format!("`{}`", vfd_runtime::protocol::code_label(c.code)))
        .collect();
    let lacked = format!(
        "a well-formed request with a function the drive does not carry out (any but {})",
        codes.join(", ")
    );
    let sentence = |rest: String| format!("A{} {rest}", &lacked[1..]);
    Some(match &protocol.unsupported_function {
        Some(entry) => {
            let table = match &protocol.error_table {
                ErrorTableIr::Drive => &drive.error_codes.codes,
                ErrorTableIr::Protocol(table) => &table.codes,
            };
            let name = table
                .iter()
                .find(|c| c.code == entry.error_code)
                .map_or_else(String::new, |c| {
                    if c.name_zh.is_empty() {
                        format!(" ({})", c.name)
                    } else {
                        format!(" ({}, {})", c.name, c.name_zh)
                    }
                });
            sentence(format!(
                "gets an error reply: the function + {offset:02X}h and error code {:02X}h{name} ({}).",
                entry.error_code, entry.source
            ))
        }
        None => sentence(
            "gets no answer from the library's virtual drive, so a master waits for its time-out: the manual does not say what the drive does with one.".to_owned(),
        ),
    })
}

/// One sentence on a protocol's variants: each with its bytes, the register selecting one
/// and the error a frame in another variant's form gets.
fn variants_rule(
    drive: &DriveIr,
    protocol: &ProtocolIr,
    variants: &vfd_runtime::variant::Variants,
) -> String {
    let hex = |bytes: &[u8]| {
        bytes
            .iter()
            .map(|b| format!("{b:02X}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let choices: Vec<String> = variants
        .choices
        .iter()
        .map(|choice| {
            let zh = if choice.name_zh.is_empty() {
                String::new()
            } else {
                format!(", {}", choice.name_zh)
            };
            let literals: Vec<String> = choice
                .literals
                .iter()
                .map(|l| format!("`{}` = {}", l.part, hex(&l.bytes)))
                .collect();
            format!(
                "`{}` ({}{zh}: {})",
                choice.id,
                choice.name,
                literals.join(", ")
            )
        })
        .collect();
    let mut sentence = format!(
        "Variants: {}; the first is the layouts as shown, a master is told another with `{}.variant(\"ID\")` / `Master::with_variant` (`vfd --variant ID`)",
        choices.join(", "),
        protocol.const_name
    );
    if let Some(selector) = &variants.selected_by {
        let register = drive
            .register_at(Space::Parameter, selector.register)
            .map_or_else(|| format!("{:04X}h", selector.register), |r| r.code.clone());
        let values: Vec<String> = selector
            .values
            .iter()
            .filter_map(|v| {
                let id = variants.choices.get(usize::from(v.variant))?.id.as_ref();
                Some(format!("{} selects `{id}`", v.value))
            })
            .collect();
        sentence.push_str(&format!(
            "; the drive speaks the one {register} selects ({})",
            values.join(", ")
        ));
    }
    if let Some(code) = variants.mismatch_error {
        sentence.push_str(&format!(
            ", and answers a frame in another variant's form with error code {code:02X}h"
        ));
    }
    sentence.push('.');
    sentence
}
