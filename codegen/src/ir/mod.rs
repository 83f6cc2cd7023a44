//! Stage 3: the intermediate representation. Everything the emitters need, resolved and
//! in a fixed order (file order), as plain serialisable data: ranges as raw bounds, Rust
//! names chosen, example frames decoded. Dump it with [`DriveIr::to_yaml`].

use crate::frames::{register_of, DecodedFrame};
use crate::naming::{const_name, method_name, type_name};
use crate::parse::model::{FrameModel, RegisterModel};
use crate::protocols::LoweredProtocol;
use crate::validate::ranges;
use crate::validate::{bit_span, Context};
use serde::Serialize;
use vfd_runtime::layout::{Format, Part, Presence};
use vfd_runtime::units::Unit;
use vfd_runtime::Protocol;

/// One drive, ready to emit.
#[derive(Debug, Clone, Serialize)]
pub struct DriveIr {
    pub id: String,
    pub module: String,
    pub vendor: String,
    pub model: String,
    pub name: String,
    pub name_zh: String,
    pub manual: String,
    pub description: String,
    /// The drive file's path as given to the generator.
    pub file: String,
    pub serial: SerialIr,
    pub addressing: AddressingIr,
    pub protocols: Vec<ProtocolIr>,
    pub error_codes: ErrorCodesIr,
    pub code_tables: Vec<CodeTableIr>,
    pub bitfields: Vec<BitfieldIr>,
    pub registers: Vec<RegisterIr>,
    pub value_examples: Vec<ValueExampleIr>,
    pub reference_scaling: Option<crate::parse::model::ReferenceScalingModel>,
    pub manual_errata: Vec<ManualErratumIr>,
    pub examples: Vec<ExampleIr>,
}

#[derive(Debug, Clone, Serialize)]
pub struct SerialIr {
    pub source: String,
    pub note: String,
    pub baud_rates: Vec<u32>,
    pub parities: Vec<String>,
    pub data_bits: u8,
    pub stop_bits_sent: u8,
    pub stop_bits_received: u8,
    pub default_baud: u32,
    pub default_parity: String,
    pub default_data_bits: u8,
    pub default_stop_bits: u8,
    pub startup_delay_ms: u64,
    pub frame_abandon_ms: u64,
    pub processing_allowance_ms: u64,
    /// Character time at the default settings, in microseconds.
    pub char_time_us: u64,
}

#[derive(Debug, Clone, Serialize)]
pub struct AddressingIr {
    pub min: u8,
    pub max: u8,
    pub note: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct ProtocolIr {
    pub id: String,
    pub const_name: String,
    pub uses: String,
    pub name: String,
    pub name_zh: String,
    pub description: String,
    pub source: String,
    pub text: bool,
    pub max_frame_len: u16,
    pub lowercase_means_tripped: bool,
    pub default_optional_parts: Vec<String>,
    pub layouts: Vec<LayoutIr>,
    pub commands: Vec<CommandIr>,
    pub error_reply: Option<String>,
    pub pre_steps: Vec<String>,
    pub frame_gap_chars: f32,
    pub default_process: Option<[u16; 2]>,
    #[serde(skip)]
    pub runtime: Protocol,
}

#[derive(Debug, Clone, Serialize)]
pub struct LayoutIr {
    pub name: String,
    pub parts: Vec<PartIr>,
}

#[derive(Debug, Clone, Serialize)]
pub struct PartIr {
    pub name: String,
    pub kind: String,
    pub encoding: String,
    pub size: String,
    pub optional: String,
    pub notes: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct CommandIr {
    pub code: String,
    pub kind: String,
    pub data_types: String,
    pub space: String,
    pub address_map: String,
    pub reply_codes: String,
    pub request: String,
    pub reply: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct ErrorCodesIr {
    pub source: String,
    pub codes: Vec<ErrorCodeIr>,
    pub silent: Vec<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct ErrorCodeIr {
    pub code: u16,
    pub code_hex: String,
    pub id: String,
    pub variant: String,
    pub name: String,
    pub name_zh: String,
    pub meaning: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct CodeTableIr {
    pub id: String,
    pub type_name: String,
    pub name: String,
    pub name_zh: String,
    pub source: String,
    pub exhaustive: bool,
    pub note: String,
    pub values: Vec<CodeValueIr>,
}

#[derive(Debug, Clone, Serialize)]
pub struct CodeValueIr {
    pub value: u16,
    pub value_hex: String,
    pub id: String,
    pub variant: String,
    pub name: String,
    pub name_zh: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct BitfieldIr {
    pub id: String,
    pub type_name: String,
    pub name: String,
    pub name_zh: String,
    pub source: String,
    pub note: String,
    pub registers: Vec<String>,
    pub fields: Vec<BitIr>,
    pub reserved_mask: u16,
    pub examples: Vec<BitExampleIr>,
}

#[derive(Debug, Clone, Serialize)]
pub struct BitIr {
    pub id: String,
    pub method: String,
    pub lsb: u8,
    pub width: u8,
    pub mask: u16,
    pub bits_label: String,
    pub reserved: bool,
    pub name: String,
    pub name_zh: String,
    pub zero: String,
    pub one: String,
    pub zero_zh: String,
    pub one_zh: String,
    pub note: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct BitExampleIr {
    pub value: u16,
    pub value_hex: String,
    pub set: Vec<String>,
    pub description: String,
    pub source: String,
}

/// How a register's value is typed in Rust.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[serde(tag = "kind", content = "type")]
pub enum ValueKind {
    /// A runtime quantity (`Hertz`).
    Quantity(String),
    /// A generated code-table enum.
    CodeTable(String),
    /// A generated bit-field word.
    Bitfield(String),
    /// A plain unsigned word.
    Raw,
    /// A plain signed word.
    RawSigned,
    /// A plain number with a scale other than 1.
    Scaled,
    /// A plain unsigned double word.
    RawDouble,
    /// A plain signed double word.
    RawSignedDouble,
    /// Text.
    Text,
}

#[derive(Debug, Clone, Serialize)]
pub struct RegisterIr {
    pub address: u16,
    pub address_hex: String,
    /// How the manual numbers it: `FA01`, `303` (decimal parameter) or `coil 17`.
    pub address_display: String,
    pub id: String,
    pub type_name: String,
    pub code: String,
    pub name: String,
    pub name_zh: String,
    pub description: String,
    pub note: String,
    pub unit: String,
    pub unit_variant: String,
    pub scale: f64,
    pub scale_display: String,
    pub decimals: u8,
    pub signed: bool,
    pub raw_min: i64,
    pub raw_max: i64,
    pub min_bound: Option<String>,
    pub max_bound: Option<String>,
    pub range_display: String,
    pub default_display: String,
    pub access: String,
    pub writable: bool,
    pub ram_only: bool,
    pub writable_while_running: bool,
    pub panel_only: bool,
    pub takes_effect: String,
    pub data_type: String,
    pub space: String,
    pub array_len: u8,
    pub value_kind: ValueKind,
    pub value_type_display: String,
    pub source: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct ValueExampleIr {
    pub register_code: String,
    pub register_type: String,
    pub value: f64,
    pub value_display: String,
    pub raw: u32,
    pub raw_hex: String,
    pub source: String,
    pub description: String,
    pub value_kind: ValueKind,
}

#[derive(Debug, Clone, Serialize)]
pub struct ManualErratumIr {
    pub source: String,
    pub printed: String,
    pub corrected: String,
    pub reason: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct ExampleIr {
    pub id: String,
    pub protocol: String,
    pub protocol_const: String,
    pub source: String,
    pub description: String,
    pub description_zh: String,
    pub request: Option<FrameIr>,
    pub reply: Option<FrameIr>,
    pub value: Option<f64>,
    pub value_display: String,
    /// The register the example's data belongs to, when it is described.
    pub register_type: Option<String>,
    pub register_code: Option<String>,
    pub value_kind: Option<ValueKind>,
    pub register_writable: bool,
    pub register_persistable: bool,
    pub register_array: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct FrameIr {
    pub bytes: Vec<u8>,
    pub shown: String,
    pub hex: String,
    pub text: bool,
    pub expect: ExpectIr,
    pub meaning: String,
    pub printed: Option<PrintedIr>,
}

#[derive(Debug, Clone, Serialize)]
pub struct ExpectIr {
    pub address: Option<u8>,
    /// Command code as received.
    pub code: Option<u32>,
    pub command_kind: Option<String>,
    pub space: Option<String>,
    pub register: Option<u32>,
    pub wire_register: Option<u32>,
    pub index: Option<u32>,
    pub data: Option<u32>,
    pub error_code: Option<u32>,
    pub process: Option<[u32; 2]>,
    pub text: Option<String>,
    pub tripped: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct PrintedIr {
    pub bytes: Vec<u8>,
    pub shown: String,
    pub hex: String,
    pub erratum: String,
    pub rejected_as: String,
    pub rejection: String,
}

impl DriveIr {
    /// The IR as YAML, for debugging and snapshot tests.
    pub fn to_yaml(&self) -> String {
        serde_yaml::to_string(self).unwrap_or_else(|error| format!("# cannot serialise: {error}"))
    }

    /// The register at `address`.
    pub fn register(&self, address: u32) -> Option<&RegisterIr> {
        self.registers
            .iter()
            .find(|r| u32::from(r.address) == address)
    }
}

/// Lowers a validated drive into its IR.
pub(crate) fn lower(drive: &Context) -> DriveIr {
    let model = &drive.model;
    let serial = &model.serial;
    let parity = |name: &str| match name {
        "none" => vfd_runtime::serial::Parity::None,
        "odd" => vfd_runtime::serial::Parity::Odd,
        _ => vfd_runtime::serial::Parity::Even,
    };
    let settings = vfd_runtime::serial::SerialSettings {
        baud: serial.default.baud,
        data_bits: serial.default.data_bits,
        parity: parity(&serial.default.parity),
        stop_bits: serial.default.stop_bits,
    };
    let code_tables: Vec<CodeTableIr> = model
        .codes
        .iter()
        .map(|table| CodeTableIr {
            id: table.id.clone(),
            type_name: type_name(&table.id),
            name: table.name.clone(),
            name_zh: table.name_zh.clone(),
            source: table.source.clone(),
            exhaustive: table.exhaustive,
            note: table.note.clone(),
            values: table
                .values
                .iter()
                .map(|value| CodeValueIr {
                    value: value.value as u16,
                    value_hex: format!("{:04X}h", value.value),
                    id: value.id.clone(),
                    variant: type_name(&value.id),
                    name: value.name.clone(),
                    name_zh: value.name_zh.clone(),
                })
                .collect(),
        })
        .collect();
    let registers: Vec<RegisterIr> = model
        .registers
        .iter()
        .map(|r| lower_register(drive, r))
        .collect();
    let bitfields = model
        .bitfields
        .iter()
        .map(|bitfield| {
            let fields: Vec<BitIr> = bitfield
                .fields
                .iter()
                .map(|field| {
                    let (lsb, width) = bit_span(field.bit, field.bits.as_deref()).unwrap_or((0, 1));
                    let mask = (((1u32 << width) - 1) << lsb) as u16;
                    let id = field
                        .id
                        .clone()
                        .unwrap_or_else(|| format!("reserved_{lsb}"));
                    BitIr {
                        method: method_name(&id),
                        id,
                        lsb,
                        width,
                        mask,
                        bits_label: if width == 1 {
                            format!("{lsb}")
                        } else {
                            format!("{}:{lsb}", lsb + width - 1)
                        },
                        reserved: field.reserved,
                        name: if field.reserved && field.name.is_empty() {
                            "Reserved".into()
                        } else {
                            field.name.clone()
                        },
                        name_zh: field.name_zh.clone(),
                        zero: field.zero.clone(),
                        one: field.one.clone(),
                        zero_zh: field.zero_zh.clone(),
                        one_zh: field.one_zh.clone(),
                        note: field.note.clone(),
                    }
                })
                .collect();
            let reserved_mask = fields
                .iter()
                .filter(|f| f.reserved)
                .fold(0u16, |m, f| m | f.mask);
            BitfieldIr {
                id: bitfield.id.clone(),
                type_name: type_name(&bitfield.id),
                name: bitfield.name.clone(),
                name_zh: bitfield.name_zh.clone(),
                source: bitfield.source.clone(),
                note: bitfield.note.clone(),
                registers: model
                    .registers
                    .iter()
                    .filter(|r| r.bitfield.as_deref() == Some(&bitfield.id))
                    .map(|r| r.code.clone())
                    .collect(),
                fields,
                reserved_mask,
                examples: bitfield
                    .examples
                    .iter()
                    .map(|e| BitExampleIr {
                        value: e.value as u16,
                        value_hex: format!("{:04X}h", e.value),
                        set: e.set.clone(),
                        description: e.description.clone(),
                        source: e.source.clone(),
                    })
                    .collect(),
            }
        })
        .collect();
    let value_examples = model
        .value_examples
        .iter()
        .filter_map(|example| {
            let register = ranges::find_register(model, &example.register)?;
            let lowered = registers.iter().find(|r| r.id == register.id)?;
            Some(ValueExampleIr {
                register_code: register.code.clone(),
                register_type: lowered.type_name.clone(),
                value: example.value,
                value_display: format!(
                    "{:.*} {}",
                    usize::from(lowered.decimals),
                    example.value,
                    lowered.unit
                )
                .trim()
                .to_owned(),
                raw: example.raw,
                raw_hex: format!("{:04X}h", example.raw),
                source: example.source.clone(),
                description: example.description.clone(),
                value_kind: lowered.value_kind.clone(),
            })
        })
        .collect();
    let examples: Vec<ExampleIr> = model
        .examples
        .iter()
        .zip(&drive.frames)
        .map(|(example, decoded)| {
            let protocol = decoded.protocol.map(|index| &drive.protocols[index]);
            let frame = |model: &Option<FrameModel>, frame: &Option<DecodedFrame>| match (
                model, frame, protocol,
            ) {
                (Some(model), Some(frame), Some(protocol)) => {
                    Some(lower_frame(drive, protocol, model, frame))
                }
                _ => None,
            };
            let register = decoded
                .reply_then_request()
                .filter_map(DecodedFrame::decoded)
                .find_map(|meaning| register_of(&drive.model, meaning))
                .and_then(|found| registers.iter().find(|r| r.id == found.id));
            ExampleIr {
                id: example.id.clone(),
                protocol: example.protocol.clone(),
                protocol_const: const_name(&example.protocol),
                source: example.source.clone(),
                description: example.description.clone(),
                description_zh: example.description_zh.clone(),
                request: frame(&example.request, &decoded.request),
                reply: frame(&example.reply, &decoded.reply),
                value: example.value,
                value_display: match (example.value, register) {
                    (Some(value), Some(r)) => {
                        format!("{:.*} {}", usize::from(r.decimals), value, r.unit)
                            .trim()
                            .to_owned()
                    }
                    _ => String::new(),
                },
                register_type: register.map(|r| r.type_name.clone()),
                register_code: register.map(|r| r.code.clone()),
                value_kind: register.map(|r| r.value_kind.clone()),
                register_writable: register.is_some_and(|r| r.writable),
                register_persistable: register.is_some_and(|r| r.writable && !r.ram_only),
                register_array: register.is_some_and(|r| r.array_len > 0),
            }
        })
        .collect();
    DriveIr {
        id: model.drive.id.clone(),
        module: model.drive.id.clone(),
        vendor: model.drive.vendor.clone(),
        model: model.drive.model.clone(),
        name: model.drive.name.clone(),
        name_zh: model.drive.name_zh.clone(),
        manual: model.drive.manual.clone(),
        description: model.drive.description.trim().to_owned(),
        file: drive.source.path.display().to_string(),
        serial: SerialIr {
            source: serial.source.clone(),
            note: serial.note.trim().to_owned(),
            baud_rates: serial.baud_rates.clone(),
            parities: serial.parities.clone(),
            data_bits: serial.data_bits,
            stop_bits_sent: serial.stop_bits_sent,
            stop_bits_received: serial.stop_bits_received,
            default_baud: serial.default.baud,
            default_parity: serial.default.parity.clone(),
            default_data_bits: serial.default.data_bits,
            default_stop_bits: serial.default.stop_bits,
            startup_delay_ms: serial.timing.startup_delay_ms,
            frame_abandon_ms: serial.timing.frame_abandon_ms,
            processing_allowance_ms: serial.timing.processing_allowance_ms,
            char_time_us: settings.char_time().as_micros() as u64,
        },
        addressing: AddressingIr {
            min: model.addressing.min,
            max: model.addressing.max,
            note: model.addressing.note.clone(),
        },
        protocols: drive.protocols.iter().map(lower_protocol).collect(),
        error_codes: ErrorCodesIr {
            source: model.error_codes.source.clone(),
            codes: model
                .error_codes
                .codes
                .iter()
                .map(|c| ErrorCodeIr {
                    code: c.code as u16,
                    code_hex: format!("{:04X}h", c.code),
                    id: c.id.clone(),
                    variant: type_name(&c.id),
                    name: c.name.clone(),
                    name_zh: c.name_zh.clone(),
                    meaning: c.meaning.clone(),
                })
                .collect(),
            silent: model.error_codes.silent.clone(),
        },
        code_tables,
        bitfields,
        registers,
        value_examples,
        reference_scaling: model.reference_scaling.clone(),
        manual_errata: model
            .manual_errata
            .iter()
            .map(|e| ManualErratumIr {
                source: e.source.clone(),
                printed: e.printed.clone(),
                corrected: e.corrected.clone(),
                reason: e.reason.clone(),
            })
            .collect(),
        examples,
    }
}

fn lower_register(drive: &Context, register: &RegisterModel) -> RegisterIr {
    let model = &drive.model;
    let unit = register
        .unit
        .as_deref()
        .and_then(Unit::from_symbol)
        .unwrap_or(Unit::None);
    let scale = ranges::scale_of(register);
    let decimals = vfd_runtime::units::decimals_of(scale);
    let (raw_min, raw_max, min_bound, max_bound) = ranges::raw_range(model, register);
    let value_kind = if let Some(bitfield) = &register.bitfield {
        ValueKind::Bitfield(type_name(bitfield))
    } else if let Some(table) = &register.code_table {
        match model.codes.iter().find(|c| &c.id == table) {
            Some(found) if found.exhaustive => ValueKind::CodeTable(type_name(table)),
            _ => ValueKind::Raw,
        }
    } else if let Some(name) = unit.quantity_type() {
        ValueKind::Quantity(name.to_owned())
    } else if register.data_type.as_deref() == Some("text") {
        ValueKind::Text
    } else if (scale - 1.0).abs() > f64::EPSILON {
        ValueKind::Scaled
    } else {
        match (
            register.signed,
            register.data_type.as_deref() == Some("double_word"),
        ) {
            (true, true) => ValueKind::RawSignedDouble,
            (false, true) => ValueKind::RawDouble,
            (true, false) => ValueKind::RawSigned,
            (false, false) => ValueKind::Raw,
        }
    };
    let show = |raw: i64| format!("{:.*}", usize::from(decimals), raw as f64 * scale);
    let range_display = match &register.range {
        None => "—".to_owned(),
        Some(range) => {
            let end = |bound: &crate::parse::model::BoundModel, raw: i64| match bound {
                crate::parse::model::BoundModel::Register(name) => {
                    format!("{name} (≤ {})", show(raw))
                }
                crate::parse::model::BoundModel::Number(_) => show(raw),
            };
            let low = match &range.min {
                crate::parse::model::BoundModel::Register(name) => {
                    format!("{name} (≥ {})", show(raw_min))
                }
                crate::parse::model::BoundModel::Number(_) => show(raw_min),
            };
            format!("{low} … {}", end(&range.max, raw_max))
        }
    };
    let access = register
        .access
        .clone()
        .unwrap_or_else(|| "read-write".to_owned());
    let value_type_display = match &value_kind {
        ValueKind::Quantity(name) => format!("`{name}`"),
        ValueKind::CodeTable(name) | ValueKind::Bitfield(name) => format!("`{name}`"),
        ValueKind::Raw => "`u16`".to_owned(),
        ValueKind::RawSigned => "`i16`".to_owned(),
        ValueKind::Scaled => "`f64`".to_owned(),
        ValueKind::RawDouble => "`u32`".to_owned(),
        ValueKind::RawSignedDouble => "`i32`".to_owned(),
        ValueKind::Text => "`String`".to_owned(),
    };
    RegisterIr {
        address: register.address as u16,
        address_hex: format!("{:04X}", register.address),
        address_display: address_display(register),
        id: register.id.clone(),
        type_name: type_name(&register.id),
        code: register.code.clone(),
        name: register.name.clone(),
        name_zh: register.name_zh.clone(),
        description: register.description.clone(),
        note: register.note.clone(),
        unit: unit.symbol().to_owned(),
        unit_variant: format!("{unit:?}"),
        scale,
        scale_display: format!("{scale}"),
        decimals,
        signed: register.signed,
        raw_min,
        raw_max,
        min_bound,
        max_bound,
        range_display,
        default_display: register
            .default
            .map(|d| format!("{d:.*}", usize::from(decimals)))
            .unwrap_or_else(|| "—".to_owned()),
        writable: access != "read-only" && register.data_type.as_deref() != Some("text"),
        access,
        ram_only: register.ram_only,
        writable_while_running: register.writable_while_running,
        panel_only: register.panel_only,
        takes_effect: register
            .takes_effect
            .clone()
            .unwrap_or_else(|| "immediately".to_owned()),
        data_type: register
            .data_type
            .clone()
            .unwrap_or_else(|| "word".to_owned()),
        space: register
            .space
            .clone()
            .unwrap_or_else(|| "parameter".to_owned()),
        array_len: register.array.unwrap_or(0),
        value_kind,
        value_type_display,
        source: register.source.clone(),
    }
}

fn lower_protocol(protocol: &LoweredProtocol) -> ProtocolIr {
    let runtime = &protocol.runtime;
    let mut layouts: Vec<LayoutIr> = Vec::new();
    let mut add = |layout: &vfd_runtime::FrameLayout| {
        if layouts.iter().any(|l| l.name == layout.name) {
            return;
        }
        layouts.push(LayoutIr {
            name: layout.name.to_string(),
            parts: layout
                .parts
                .iter()
                .map(|p| lower_part(p, &layout.parts))
                .collect(),
        });
    };
    for command in runtime.commands.iter() {
        add(&command.request);
        add(&command.reply);
    }
    if let Some(error) = &runtime.error_reply {
        add(error);
    }
    ProtocolIr {
        id: protocol.id.clone(),
        const_name: const_name(&protocol.id),
        uses: protocol.uses.clone(),
        name: protocol.file.protocol.name.clone(),
        name_zh: protocol.file.protocol.name_zh.clone(),
        description: protocol.file.protocol.description.trim().to_owned(),
        source: protocol.source_section.clone(),
        text: protocol.file.protocol.text,
        max_frame_len: protocol.file.protocol.max_frame_len,
        lowercase_means_tripped: protocol.file.protocol.lowercase_means_tripped,
        default_optional_parts: protocol.file.protocol.default_optional_parts.clone(),
        layouts,
        commands: runtime
            .commands
            .iter()
            .map(|c| CommandIr {
                code: if c.request.has(vfd_runtime::Role::Command) {
                    c.code_label()
                } else {
                    "—".to_owned()
                },
                data_types: if c.data_types.is_empty() {
                    "any".to_owned()
                } else {
                    c.data_types
                        .iter()
                        .map(|t| t.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                },
                space: c.space.as_str().to_owned(),
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
                kind: c.kind.as_str().to_owned(),
                request: c.request.name.to_string(),
                reply: c.reply.name.to_string(),
            })
            .collect(),
        error_reply: runtime.error_reply.as_ref().map(|l| l.name.to_string()),
        pre_steps: runtime
            .pre_steps
            .iter()
            .map(|step| match *step {
                vfd_runtime::PreStep::Index { register } => {
                    format!("Before an indexed (array) access: write the index to wire register {register:04X}h.")
                }
                vfd_runtime::PreStep::Persistence { space, register, ram, persistent, .. } => format!(
                    "Before a parameter write: write {ram:04X}h (RAM only) or {persistent:04X}h (RAM and EEPROM) to {} {register}.",
                    space.as_str()
                ),
            })
            .collect(),
        frame_gap_chars: runtime.frame_gap_chars,
        default_process: protocol.file.protocol.default_process,
        runtime: runtime.clone(),
    }
}

fn lower_part(part: &Part, parts: &[Part]) -> PartIr {
    match part {
        Part::Literal {
            name,
            bytes,
            optional,
        } => PartIr {
            name: name.to_string(),
            kind: "literal".into(),
            encoding: if bytes.iter().all(|b| b.is_ascii_graphic()) {
                format!(
                    "`{}` ({})",
                    vfd_runtime::error::hex(bytes),
                    shown_bytes(bytes)
                )
            } else {
                format!("`{}`", vfd_runtime::error::hex(bytes))
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
                (Some(len), _) => len.to_string(),
                (None, vfd_runtime::SizedBy::Rest) => "rest of the frame".into(),
                (None, vfd_runtime::SizedBy::Length) => "given by its length".into(),
                (None, _) if field.min_width == field.width => field.width.to_string(),
                (None, _) => format!("{}–{}", field.min_width, field.width),
            };
            let allowed: Vec<String> = field
                .allowed
                .iter()
                .map(|v| format!("`{}`", char::from_u32(*v).unwrap_or('?')))
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
            PartIr {
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
        Part::Word(word) => PartIr {
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
        Part::Length(length) => PartIr {
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
        Part::Checksum(spec) => PartIr {
            name: spec.name.to_string(),
            kind: format!("checksum ({})", spec.algorithm.as_str()),
            encoding: describe_format(spec.format),
            size: if spec.format == Format::Hex {
                "2".into()
            } else {
                "1".into()
            },
            optional: if spec.optional {
                "optional".into()
            } else {
                String::new()
            },
            notes: format!(
                "{}covers `{}` through the byte before the sum",
                if spec.marker.is_empty() {
                    String::new()
                } else {
                    format!("announced by {}; ", shown_bytes(&spec.marker))
                },
                parts
                    .get(usize::from(spec.covers_from))
                    .map(|p| p.name().to_owned())
                    .unwrap_or_default()
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

/// How the manual numbers a register: coils by number, decimal parameters (FC 303) as
/// written, communication numbers in hex (FA01).
pub fn address_display(register: &RegisterModel) -> String {
    if register.space.as_deref() == Some("coil") {
        format!("coil {}", register.address)
    } else if register.code.parse::<u32>().ok() == Some(register.address) {
        register.address.to_string()
    } else {
        format!("{:04X}", register.address)
    }
}

/// Shows frame bytes for people: text with `\r` as `<CR>`, or hex pairs.
pub fn shown_bytes(bytes: &[u8]) -> String {
    if bytes
        .iter()
        .all(|b| b.is_ascii_graphic() || *b == b' ' || *b == b'\r' || *b == b'\n')
    {
        let text = String::from_utf8_lossy(bytes)
            .replace('\r', "<CR>")
            .replace('\n', "<LF>");
        format!("`{text}`")
    } else {
        format!("`{}`", vfd_runtime::error::hex(bytes))
    }
}

fn lower_frame(
    drive: &Context,
    protocol: &LoweredProtocol,
    model: &FrameModel,
    frame: &DecodedFrame,
) -> FrameIr {
    // Validation has passed, so the bytes are there and decode.
    let bytes = frame.bytes.clone().unwrap_or_default();
    let decoded = frame.decoded().cloned().unwrap_or_default();
    let label = |code: u32| vfd_runtime::protocol::code_label(code);
    let meaning = match decoded.error_code {
        Some(code) => {
            let entry = protocol.runtime.error_code(code);
            format!(
                "error reply{}: error {code}{}",
                decoded
                    .code
                    .map(|c| format!(" `{}`", label(c)))
                    .unwrap_or_default(),
                entry
                    .map(|e| format!(" {} ({})", e.name, e.name_zh))
                    .unwrap_or_default()
            )
        }
        None => {
            let mut parts = Vec::new();
            let kind = decoded.kind.map(|k| k.as_str()).unwrap_or("?");
            match decoded.code {
                Some(code) => parts.push(format!("`{}` ({kind})", label(code))),
                None => parts.push(kind.to_owned()),
            }
            if let Some(address) = decoded.address {
                parts.push(format!("station {address}"));
            }
            let described = register_of(&drive.model, &decoded);
            match (described, decoded.register, decoded.wire_register) {
                (Some(register), _, Some(wire))
                    if address_display(register) != format!("{wire:04X}") =>
                {
                    parts.push(
                        format!(
                            "{} {} (wire {wire:04X}h)",
                            if register.space.as_deref() == Some("coil") {
                                ""
                            } else {
                                "register"
                            },
                            address_display(register)
                        )
                        .trim()
                        .to_owned(),
                    )
                }
                (Some(register), _, _) => {
                    parts.push(format!("register {}", address_display(register)))
                }
                (None, Some(register), _) => parts.push(format!("register {register}")),
                (None, None, Some(wire)) => parts.push(format!("wire register {wire:04X}h")),
                _ => {}
            }
            if let Some(index) = decoded.index {
                parts.push(format!("index {index}"));
            }
            if let Some(data) = decoded.data {
                parts.push(if data > 9 {
                    format!("data {data:04X}h ({data})")
                } else {
                    format!("data {data}")
                });
            }
            if let Some([first, second]) = decoded.process {
                parts.push(format!("process words {first:04X}h {second:04X}h"));
            }
            if let Some(text) = &decoded.text {
                parts.push(format!("text {text:?}"));
            }
            if decoded.tripped {
                parts.push("drive tripped".to_owned());
            }
            parts.join(", ")
        }
    };
    let printed = frame.printed.as_ref().map(|printed| {
        let printed_bytes = printed.bytes.clone().unwrap_or_default();
        let rejection = match &printed.meaning {
            Some(Err(error)) => error.to_string(),
            _ => String::new(),
        };
        PrintedIr {
            shown: shown_bytes(&printed_bytes),
            hex: vfd_runtime::error::hex(&printed_bytes),
            bytes: printed_bytes,
            erratum: model.erratum.clone().unwrap_or_default(),
            rejected_as: model.printed_rejected_as.clone().unwrap_or_default(),
            rejection,
        }
    });
    FrameIr {
        shown: shown_bytes(&bytes),
        hex: vfd_runtime::error::hex(&bytes),
        text: model.ascii.is_some(),
        bytes,
        expect: ExpectIr {
            address: decoded.address,
            code: decoded.code,
            command_kind: decoded.kind.map(|k| k.as_str().to_owned()),
            space: decoded.space.map(|s| s.as_str().to_owned()),
            register: decoded.register.map(u32::from),
            wire_register: decoded.wire_register.map(u32::from),
            index: decoded.index.map(u32::from),
            data: decoded.data,
            error_code: decoded.error_code.map(u32::from),
            process: decoded.process.map(|[a, b]| [u32::from(a), u32::from(b)]),
            text: decoded.text,
            tripped: decoded.tripped,
        },
        meaning,
        printed,
    }
}
