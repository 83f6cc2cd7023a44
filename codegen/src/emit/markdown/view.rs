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
use vfd_runtime::{PreStep, Role, Space};

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
    /// What the virtual drive does and assumes.
    virtual_drive: VirtualDriveView<'a>,
    /// The registers other registers' ranges name (`FH`, `UL`), each once.
    bound_registers: Vec<String>,
    /// Some register has a fact the description infers.
    any_inferred: bool,
    /// The character format per protocol, where the drive's code tables say which format
    /// a protocol speaks; empty when the table's one format holds for every protocol.
    line_formats: Vec<(String, String)>,
    /// The code of the register holding the station number, when the description names one.
    station_register: Option<String>,
}

#[derive(Serialize)]
struct VirtualDriveView<'a> {
    /// The description's behaviour model, when it has one.
    behaviour: Option<&'a BehaviourIr>,
    /// Lines on what drives the simulated motor (command word, frequency, ramps).
    model_lines: Vec<String>,
    /// The refusals the model tells apart, as column titles.
    refusal_names: Vec<&'static str>,
    /// Per protocol: its id and the answer to each refusal, in the columns' order.
    refusals: Vec<(String, Vec<String>)>,
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

/// The error codes of `table`, each written with `digits` hex digits (the width of the
/// error-code field of the protocols it serves: `01h` for a Modbus byte, `0001h` for a
/// four-digit word).
fn error_codes_view(table: &ErrorCodesIr, digits: usize) -> ErrorCodesView<'_> {
    ErrorCodesView {
        error_codes: table,
        codes: table
            .codes
            .iter()
            .map(|code| ErrorCodeView {
                code,
                code_hex: if code.printed.is_empty() {
                    format!("{:0digits$X}h", code.code)
                } else {
                    code.printed.clone()
                },
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
    /// For a multi-bit field, the link to the code table naming its values (empty: none).
    values: String,
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
    /// The request is never answered (its command's `reply: none`, a write of a register
    /// with `no_reply: true`, or an example saying nothing comes back).
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
    /// The bytes as the manual prints them (its spacing, for hex frames).
    shown: String,
    /// Which layout the decoder took the printed bytes for, and why, when their command
    /// code chose another command's layout (empty otherwise).
    read_as: String,
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
            SequenceResultIr::Error(code, id) => {
                let shown = drive
                    .protocols
                    .iter()
                    .find(|p| p.id == sequence.protocol)
                    .map_or_else(
                        || format!("{code:02X}h"),
                        |p| printed_error(drive, p, *code),
                    );
                format!("refused with {shown} `{id}`")
            }
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
            virtual_drive: virtual_drive_view(drive),
            bound_registers: {
                let mut codes: Vec<String> = Vec::new();
                for r in &drive.registers {
                    for bound in [&r.min, &r.max].into_iter().flatten() {
                        if let Some(code) = &bound.register {
                            if !codes.contains(code) {
                                codes.push(code.clone());
                            }
                        }
                    }
                }
                codes
            },
            any_inferred: drive.registers.iter().any(|r| !r.inferred.is_empty()),
            line_formats: line_formats(drive),
            station_register: drive
                .addressing
                .register
                .as_deref()
                .and_then(|id| drive.register(id))
                .map(|r| r.code.clone()),
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
            error_codes: error_codes_view(
                &drive.error_codes,
                drive
                    .protocols
                    .iter()
                    .filter(|p| drive.error_codes.protocols.contains(&p.id))
                    .map(|p| error_code_digits(drive, p))
                    .max()
                    .unwrap_or(4),
            ),
            protocol_error_tables: drive
                .protocols
                .iter()
                .filter_map(|p| match &p.error_table {
                    ErrorTableIr::Drive => None,
                    ErrorTableIr::Protocol(table) => Some(ProtocolErrorsView {
                        id: &p.id,
                        name: &p.name,
                        table: error_codes_view(table, error_code_digits(drive, p)),
                    }),
                })
                .collect(),
            registers: drive
                .registers
                .iter()
                .map(|register| RegisterView {
                    register,
                    address_display: if register.wire_only {
                        "none: wire numbers only".to_owned()
                    } else {
                        let mut label = address_label(register);
                        for (protocol, page, offset) in &register.on_page {
                            label.push_str(&format!(
                                ", {protocol} page {page} offset {offset:02X}h"
                            ));
                        }
                        label
                    },
                    address_hex: format!("{:04X}", register.address),
                    scale_display: format!("{}", register.scale),
                    range_display: match code_table_link(drive, register.code_table.as_deref()) {
                        Some(link) => format!("codes: {link}"),
                        None => range_text(register),
                    },
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
                            values: if field.width > 1 {
                                code_table_link(drive, field.code_table.as_deref())
                                    .map_or_else(String::new, |link| format!("values: {link}"))
                            } else {
                                String::new()
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
                                .map_or_else(String::new, |r| without_port(&r.name, ports));
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
                            // An input read from a register is given as the register's
                            // value; scaled first, the formula's own input follows, so
                            // the example computes as written.
                            let args: Vec<String> = conversion
                                .inputs
                                .iter()
                                .zip(inputs)
                                .map(|(input, value)| match &input.register {
                                    Some(code) if (input.times - 1.0).abs() > f64::EPSILON => {
                                        format!(
                                            "{code} = {value}, so `{}` = {}",
                                            input.name,
                                            trimmed(value * input.times)
                                        )
                                    }
                                    Some(code) => format!("{code} = {value}"),
                                    None => format!("`{}` = {value}", input.name),
                                })
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
                    let protocol = drive.protocols.iter().find(|p| p.id == example.protocol);
                    let error_digits = protocol.map_or(4, |p| error_code_digits(drive, p));
                    let errors = match protocol.map(|p| &p.error_table) {
                        Some(ErrorTableIr::Protocol(table)) => table,
                        _ => &drive.error_codes,
                    };
                    let frame = |frame: &'a Option<FrameIr>| {
                        frame.as_ref().map(|frame| FrameView {
                            shown: shown(&frame.bytes),
                            meaning: meaning_text(drive, frame, errors, error_digits),
                            printed: frame.printed.as_ref().map(|printed| PrintedView {
                                printed,
                                shown: if printed.written.is_empty() {
                                    shown(&printed.bytes)
                                } else {
                                    format!("`{}`", printed.written)
                                },
                                read_as: printed_read_as(drive, example, frame, printed),
                            }),
                        })
                    };
                    let unanswered = example.no_reply
                        || example.request.as_ref().is_some_and(|frame| {
                            request_unanswered(drive, example, frame, described)
                        });
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

/// `code`, an error code of `protocol`, as the manual prints it (its table's `notation`:
/// the DV1's H0C), else in hex with [`error_code_digits`] digits and `h`.
fn printed_error(drive: &DriveIr, protocol: &ProtocolIr, code: u16) -> String {
    let table = match &protocol.error_table {
        ErrorTableIr::Drive => &drive.error_codes,
        ErrorTableIr::Protocol(table) => table,
    };
    table
        .codes
        .iter()
        .find(|c| c.code == code && !c.printed.is_empty())
        .map_or_else(
            || format!("{:0w$X}h", code, w = error_code_digits(drive, protocol)),
            |c| c.printed.clone(),
        )
}

/// How many hex digits an error code of `protocol` is written with: two when its error
/// reply carries the code in one byte (or two digits), else four.
fn error_code_digits(drive: &DriveIr, protocol: &ProtocolIr) -> usize {
    use vfd_runtime::layout::{Format, Part};
    let layout = protocol.error_reply.as_deref().and_then(|name| {
        drive
            .protocol_files
            .iter()
            .find(|f| f.id == protocol.uses)
            .and_then(|f| f.layouts.iter().find(|l| l.name == name))
    });
    let one_byte = layout.is_some_and(|layout| {
        layout.parts.iter().any(|part| {
            matches!(part, Part::Field(field) if field.role == Role::ErrorCode
                && (matches!(field.format, Format::U8 | Format::Char)
                    || (field.format.is_digits() && field.width <= 2)))
        })
    });
    if one_byte {
        2
    } else {
        4
    }
}

/// The command and status roles whose bits are held by a register of their own (a field of
/// another bit-field register, or a coil), with those bits, in the model's order.
fn held_elsewhere(behaviour: &BehaviourIr) -> Vec<(&'static str, &BitRefIr)> {
    let status = &behaviour.status;
    let mut roles: Vec<(&'static str, &BitRefIr)> = Vec::new();
    for (role, bit) in [
        ("run", &behaviour.run),
        ("reverse run", &behaviour.run_reverse),
        ("reverse", &behaviour.reverse),
        ("reset", &behaviour.reset),
        ("coast", &behaviour.coast),
    ] {
        roles.extend(bit.iter().map(|bit| (role, bit)));
    }
    let lists: [(&'static str, &Vec<BitRefIr>); 11] = [
        ("command required", &behaviour.command_require),
        ("frequency required", &behaviour.frequency_require),
        ("running", &status.running),
        ("reversing", &status.reverse),
        ("running forward", &status.forward),
        ("at the frequency command", &status.at_reference),
        ("tripped", &status.tripped),
        ("overload", &status.overload),
        ("frequency detected", &status.frequency_detected),
        ("enabled", &status.enabled),
        ("always", &status.always),
    ];
    for (role, bits) in lists {
        roles.extend(bits.iter().map(|bit| (role, bit)));
    }
    roles.retain(|(_, bit)| bit.register.is_some());
    roles
}

/// What the virtual drive built from the description does: its behaviour model's parts in
/// words and each protocol's answers to refused requests.
fn virtual_drive_view(drive: &DriveIr) -> VirtualDriveView<'_> {
    let Some(behaviour) = &drive.behaviour else {
        return VirtualDriveView {
            behaviour: None,
            model_lines: Vec::new(),
            refusal_names: Vec::new(),
            refusals: Vec::new(),
        };
    };
    let code = |id: &str| {
        drive
            .register(id)
            .map_or_else(|| id.to_owned(), |r| r.code.clone())
    };
    let codes = |ids: &[String]| ids.iter().map(|id| code(id)).collect::<Vec<_>>().join(", ");
    let amount = |a: &AmountIr, unit: &str| match a {
        AmountIr::Number(n) => format!("{} {unit}", trimmed(*n)),
        AmountIr::Register(id) => code(id),
    };
    let mut model_lines = vec![format!(
        "Commands: the command word is {}{}; the frequency command is {}.",
        code(&behaviour.command_register),
        match &behaviour.require_mode {
            Some((register, values)) => format!(
                ", taken only while {} = {}",
                code(register),
                values
                    .iter()
                    .map(|v| v.to_string())
                    .collect::<Vec<_>>()
                    .join(" or ")
            ),
            None => String::new(),
        },
        match &behaviour.frequency_percent_of {
            Some(full) => format!(
                "{}, a percentage of {}",
                code(&behaviour.frequency_command),
                amount(full, "Hz")
            ),
            None => code(&behaviour.frequency_command),
        }
    )];
    if let Some(c) = &behaviour.command_codes {
        let named = [
            ("run forward", &c.run),
            ("run in reverse", &c.run_reverse),
            ("stop", &c.stop),
            ("coast to a stop", &c.coast),
            ("reset a trip", &c.reset),
        ];
        let parts: Vec<String> = named
            .iter()
            .filter(|(_, values)| !values.is_empty())
            .map(|(what, values)| {
                let values: Vec<String> = values.iter().map(|v| format!("{v:04X}h")).collect();
                format!("{} {what}", values.join(" or "))
            })
            .collect();
        model_lines.push(format!(
            "Command codes: the command word holds a code, not bits: {}; any other value \
             changes nothing.",
            parts.join(", ")
        ));
    }
    if let Some(s) = &behaviour.status_state {
        model_lines.push(format!(
            "State register: {} holds {:04X}h while stopped, {:04X}h running forward, \
             {:04X}h running in reverse, {:04X}h tripped.",
            code(&s.register),
            s.stopped,
            s.forward,
            s.reverse,
            s.tripped
        ));
    }
    model_lines.push(format!(
        "Ramps: acceleration {}, deceleration {}, each for a change of {}.",
        amount(&behaviour.acceleration, "s"),
        amount(&behaviour.deceleration, "s"),
        amount(&behaviour.span, "Hz")
    ));
    if !behaviour.output.is_empty() {
        model_lines.push(format!(
            "Monitors following the output: {}.",
            codes(&behaviour.output)
        ));
    }
    if !behaviour.status_registers.is_empty() {
        model_lines.push(format!(
            "Status words: {}.",
            codes(&behaviour.status_registers)
        ));
    }
    let held = held_elsewhere(behaviour)
        .into_iter()
        .map(|(role, bit)| {
            let register = bit.register.as_deref().unwrap_or_default();
            let coil = drive
                .register(register)
                .is_some_and(|r| r.data_type == vfd_runtime::DataType::Bit);
            match bit.id.rsplit_once('.') {
                Some((_, field)) if !coil => format!("{role}: {} (`{field}`)", code(register)),
                _ => format!("{role}: coil {}", code(register)),
            }
        })
        .collect::<Vec<_>>();
    if !held.is_empty() {
        model_lines.push(format!(
            "Bits held by registers of their own: {}.",
            held.join("; ")
        ));
    }
    let mut levels = Vec::new();
    if let Some(level) = &behaviour.current_overload {
        levels.push(format!(
            "overload while the output current is at or above {}",
            amount(level, "").trim_end()
        ));
    }
    if let Some(level) = &behaviour.frequency_detection {
        levels.push(format!(
            "frequency detected while running at or above {}",
            amount(level, "Hz")
        ));
    }
    if !levels.is_empty() {
        model_lines.push(format!("Status levels: {}.", levels.join("; ")));
    }
    let answer = |protocol: &ProtocolIr, code: Option<u16>| match code {
        Some(code) => printed_error(drive, protocol, code),
        None => "no reply".to_owned(),
    };
    // The refusals every model tells apart, then those only some models give.
    type Cell = fn(&RefusalsIr) -> Option<u16>;
    let mut columns: Vec<(&'static str, Cell)> = vec![
        ("Unknown register", |r| r.unknown_register),
        ("Read-only register", |r| r.read_only),
        ("Out of range", |r| r.out_of_range),
        ("While running", |r| r.while_running),
        ("Bad checksum", |r| r.bad_checksum),
    ];
    if behaviour.require_mode.is_some() {
        columns.push(("Outside the required mode", |r| r.wrong_mode));
    }
    let optional: [(&'static str, Cell); 3] = [
        ("Bad character", |r| r.bad_character),
        ("Malformed frame", |r| r.malformed),
        ("Retries exceeded", |r| {
            r.retries_exceeded.as_ref().map(|(code, _)| *code)
        }),
    ];
    for (name, cell) in optional {
        if behaviour.refusals.iter().any(|r| cell(r).is_some()) {
            columns.push((name, cell));
        }
    }
    let refusal_names = columns.iter().map(|(name, _)| *name).collect();
    let refusals = drive
        .protocols
        .iter()
        .map(|protocol| {
            let entry = behaviour
                .refusals
                .iter()
                .find(|r| r.protocol == protocol.id);
            let cells: Vec<String> = columns
                .iter()
                .map(|(_, cell)| answer(protocol, entry.and_then(cell)))
                .collect();
            (protocol.id.clone(), cells)
        })
        .collect();
    for rule in &behaviour.refusals {
        if let Some((code, after)) = &rule.retries_exceeded {
            model_lines.push(format!(
                "Over `{}`, once more than {} unreadable frames (bad characters, malformed frames, bad checksums) came in a row, the next is answered {code:X}h.",
                rule.protocol,
                amount(after, "").trim_end()
            ));
        }
    }
    VirtualDriveView {
        behaviour: Some(behaviour),
        model_lines,
        refusal_names,
        refusals,
    }
}

/// The character format each protocol speaks, from the code tables whose values choose a
/// protocol and set the line, with the format of the selecting register's factory value;
/// empty when no code table says.
fn line_formats(drive: &DriveIr) -> Vec<(String, String)> {
    let format = |(data_bits, parity, stop_bits): (u8, vfd_runtime::serial::Parity, u8)| {
        let parity = match parity {
            vfd_runtime::serial::Parity::None => 'N',
            vfd_runtime::serial::Parity::Even => 'E',
            vfd_runtime::serial::Parity::Odd => 'O',
        };
        format!("{data_bits}{parity}{stop_bits}")
    };
    let mut rows = Vec::new();
    for protocol in &drive.protocols {
        for table in &drive.code_tables {
            let values: Vec<&CodeValueIr> = table
                .values
                .iter()
                .filter(|v| {
                    v.line.is_some_and(|l| l.format().is_some())
                        && v.protocol.as_deref() == Some(&protocol.id)
                })
                .collect();
            if values.is_empty() {
                continue;
            }
            let Some(selector) = drive
                .registers
                .iter()
                .find(|r| r.code_table.as_deref() == Some(&table.id))
            else {
                continue;
            };
            let factory = selector.default.map(|d| d as u16);
            let choices: Vec<String> = values
                .iter()
                .filter_map(|v| {
                    let line = format(v.line?.format()?);
                    Some(if Some(v.value) == factory {
                        format!(
                            "**{line}** ({} = {}, the factory setting)",
                            selector.code, v.value
                        )
                    } else {
                        format!("{line} ({} = {})", selector.code, v.value)
                    })
                })
                .collect();
            let mut row = choices.join(", ");
            if let Some(line) = drive
                .serial
                .protocol_lines
                .iter()
                .find(|l| l.protocol == protocol.id)
                .filter(|_| {
                    !drive
                        .serial
                        .protocol_lines
                        .iter()
                        .any(|l| l.protocol == protocol.id && l.factory)
                })
            {
                row.push_str(&format!(
                    "; the factory setting chooses another protocol: a master starts from {} ({} = {}, the first offered; assumed)",
                    format((line.data_bits, line.parity, line.stop_bits)),
                    line.selector,
                    line.value
                ));
            }
            rows.push((protocol.id.clone(), row));
        }
    }
    rows
}

/// When the decoder read printed bytes with the layout of another command than the
/// corrected frame's (their command code chose it), a sentence saying so: the rejection
/// then follows from that layout, not from the mistake the erratum names.
fn printed_read_as(
    drive: &DriveIr,
    example: &ExampleIr,
    frame: &FrameIr,
    printed: &PrintedIr,
) -> String {
    let Some(protocol) = drive.protocols.iter().find(|p| p.id == example.protocol) else {
        return String::new();
    };
    let Some(rest) = printed.rejection.split("failed with: ").nth(1) else {
        return String::new();
    };
    let Some(layout) = rest.split(':').next() else {
        return String::new();
    };
    let Some(command) = protocol
        .commands
        .iter()
        .find(|c| c.request == layout || c.reply == layout)
    else {
        return String::new();
    };
    let file = drive.protocol_files.iter().find(|f| f.id == protocol.uses);
    let has_command = file
        .and_then(|f| f.layouts.iter().find(|l| l.name == layout))
        .is_some_and(|l| l.has(Role::Command));
    let Some(corrected) = frame.meaning.code else {
        return String::new();
    };
    // The corrected frame's own command uses the layout too: the command code did not
    // choose another layout.
    let same_layout = protocol.commands.iter().any(|c| {
        (c.request == layout || c.reply == layout)
            && (c.code == corrected || c.reply_codes.contains(&corrected))
    });
    if !has_command || same_layout {
        return String::new();
    }
    let label = vfd_runtime::protocol::code_label(command.code);
    let code = if label.len() == 1 {
        format!("`{label}` ({:02X}h)", command.code)
    } else {
        format!("`{label}`")
    };
    let stop = if printed.rejection.ends_with('.') {
        ""
    } else {
        "."
    };
    format!(
        "{stop} The decoder chooses a layout by the command code: the printed {code} is the {} command's, so the bytes are read as `{layout}`, and that layout's check fails.",
        command.kind.as_str()
    )
}

/// A link to the code table `id` on the page (`[Trip codes](#code-table-trip_code)`), when
/// the drive has it.
fn code_table_link(drive: &DriveIr, id: Option<&str>) -> Option<String> {
    let table = drive
        .code_tables
        .iter()
        .find(|t| Some(t.id.as_str()) == id)?;
    Some(format!("[{}](#code-table-{})", table.name, table.id))
}

/// A register's name without the port it names at its end (`Command word 1 (2-wire
/// RS-485)` → `Command word 1`), for the table of per-port copies.
fn without_port(name: &str, ports: &PortsIr) -> String {
    ports
        .ports
        .iter()
        .find_map(|port| name.strip_suffix(&format!(" ({})", port.name)))
        .unwrap_or(name)
        .to_owned()
}

/// A number without float noise (`4`, `6000`, `0.5`).
fn trimmed(value: f64) -> String {
    let text = format!("{value:.6}");
    text.trim_end_matches('0').trim_end_matches('.').to_owned()
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

/// What a code value sets on the line and which protocol it chooses (` — line 7 data
/// bits, no parity, 2 stop bits; protocol `modbus_ascii``), empty when it says neither.
fn code_value_sets(value: &CodeValueIr) -> String {
    let mut parts = Vec::new();
    if let Some(line) = value.line {
        let mut sets = Vec::new();
        if let Some(baud) = line.baud {
            sets.push(format!("{baud} bps"));
        }
        if let Some(data_bits) = line.data_bits {
            sets.push(format!("{data_bits} data bits"));
        }
        if let Some(parity) = line.parity {
            sets.push(
                match parity {
                    vfd_runtime::serial::Parity::None => "no parity",
                    vfd_runtime::serial::Parity::Even => "even parity",
                    vfd_runtime::serial::Parity::Odd => "odd parity",
                }
                .to_owned(),
            );
        }
        if let Some(stop_bits) = line.stop_bits {
            let stops = if stop_bits == 1 {
                "stop bit"
            } else {
                "stop bits"
            };
            sets.push(format!("{stop_bits} {stops}"));
        }
        parts.push(format!("line: {}", sets.join(", ")));
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

/// One sentence per line rule the drive states for `protocol`.
fn link_rules(drive: &DriveIr, protocol: &ProtocolIr) -> Vec<String> {
    use vfd_runtime::serial::BeforeStart;
    let timing = &protocol.timing;
    let ms = |d: std::time::Duration| {
        let text = format!("{:.2}", d.as_secs_f64() * 1000.0);
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    };
    let mut rules = Vec::new();
    let chars = protocol.frame_gap_chars;
    match (chars > 0.0, timing.frame_gap_min.is_zero()) {
        (true, true) => rules.push(format!(
            "Frames are separated by {chars} character times of silence (derived from the baud rate)."
        )),
        (false, false) => rules.push(format!(
            "The silence between frames is at least {} ms whatever the baud rate.",
            ms(timing.frame_gap_min)
        )),
        (true, false) => {
            // Which of the two rules is the longer, at the baud rates the drive offers.
            let chars_time = |baud: u32| {
                SerialSettings {
                    baud,
                    data_bits: drive.serial.default_data_bits,
                    parity: drive.serial.default_parity,
                    stop_bits: drive.serial.default_stop_bits,
                }
                .char_time()
                .mul_f32(chars)
            };
            let floor_everywhere = drive
                .serial
                .baud_rates
                .iter()
                .all(|baud| chars_time(*baud) <= timing.frame_gap_min);
            rules.push(if floor_everywhere {
                format!(
                    "Frames are separated by at least {} ms of silence whatever the baud rate: longer than the protocol's {chars} character times at every baud rate the drive offers.",
                    ms(timing.frame_gap_min)
                )
            } else {
                format!(
                    "Frames are separated by {chars} character times of silence (derived from the baud rate), and by at least {} ms whatever the baud rate: the longer of the two applies.",
                    ms(timing.frame_gap_min)
                )
            });
        }
        (false, true) => {}
    }
    if timing.max_inner_gap_chars > 0.0 {
        rules.push(format!(
            "A frame may not hold a silence of {} character times or more: the drive drops it.",
            timing.max_inner_gap_chars
        ));
    }
    if begins_with_literal(drive, protocol) {
        rules.push(match timing.before_start {
            BeforeStart::Reject => {
                "Bytes before a frame's start sequence reject the frame (it is not answered)."
            }
            BeforeStart::Skip if protocol.before_start_stated => {
                "Bytes before a frame's start sequence are skipped: the frame begins at its start."
            }
            BeforeStart::Skip => {
                "Bytes before a frame's start sequence are skipped: the frame begins at its start (assumed: the library's default, not from the manual)."
            }
        }
        .to_owned());
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
            "Broadcasts: {} may be sent to every station{}; {answered}.",
            codes.join(", "),
            if station_wildcard(drive, protocol) {
                " or to a group of stations (`*` for an open digit of the station number)"
            } else {
                ""
            }
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

/// The layouts of the protocol's requests, from its protocol file.
fn request_layouts<'a>(
    drive: &'a DriveIr,
    protocol: &'a ProtocolIr,
) -> impl Iterator<Item = &'a vfd_runtime::FrameLayout> + 'a {
    let file = drive.protocol_files.iter().find(|f| f.id == protocol.uses);
    protocol.commands.iter().filter_map(move |command| {
        file.and_then(|f| f.layouts.iter().find(|l| l.name == command.request))
    })
}

/// Whether the protocol's requests begin with a start sequence (a literal).
fn begins_with_literal(drive: &DriveIr, protocol: &ProtocolIr) -> bool {
    let mut layouts = request_layouts(drive, protocol).peekable();
    layouts.peek().is_some()
        && layouts.all(|l| {
            matches!(
                l.parts.first(),
                Some(vfd_runtime::layout::Part::Literal { .. })
            )
        })
}

/// Whether a request's station field takes a wildcard digit (group broadcasts).
fn station_wildcard(drive: &DriveIr, protocol: &ProtocolIr) -> bool {
    request_layouts(drive, protocol).any(|layout| {
        layout.parts.iter().any(|part| {
            matches!(part, vfd_runtime::layout::Part::Field(field)
                if field.role == Role::Address
                    && field.broadcast.as_ref().is_some_and(|b| b.wildcard.is_some()))
        })
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
