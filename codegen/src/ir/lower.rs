//! Lowers a checked description ([`Context`]) into the IR: Rust names chosen, ranges
//! resolved into raw bounds, protocols split into shared layouts and per-drive commands,
//! example frames taken from the one decoding done before validation.

use super::types::*;
use crate::frames::{register_of, DecodedFrame};
use crate::naming::{const_name, method_name, module_name, type_name};
use crate::parse::model::{BoundModel, DriveFile, ErrorCodeModel, FrameModel, RegisterModel};
use crate::protocols::{drive_table_applies, LoweredProtocol};
use crate::validate::ranges;
use crate::validate::{bit_span, Context};
use vfd_runtime::protocol::NotAnAnswer;
use vfd_runtime::units::Unit;
use vfd_runtime::{Access, DataType, FrameLayout, Space, TakesEffect};

/// Lowers a drive that passed validation.
pub(crate) fn lower(drive: &Context) -> DriveIr {
    let model = &drive.model;
    let serial = &model.serial;
    let index = ranges::RegisterIndex::new(model);
    let registers: Vec<RegisterIr> = model
        .registers
        .iter()
        .map(|r| lower_register(drive, &index, r))
        .collect();
    let mut ir = DriveIr {
        id: model.drive.id.clone(),
        module: module_name(&model.drive.id),
        vendor: model.drive.vendor.clone(),
        model: model.drive.model.clone(),
        name: model.drive.name.clone(),
        name_zh: model.drive.name_zh.clone(),
        manual: model.drive.manual.clone(),
        manual_title: model.drive.manual_title.trim().to_owned(),
        manual_title_zh: model.drive.manual_title_zh.trim().to_owned(),
        manual_document: model.drive.manual_document.trim().to_owned(),
        manual_note: model.drive.manual_note.trim().to_owned(),
        description: model.drive.description.trim().to_owned(),
        file: drive.source.path.display().to_string().replace('\\', "/"),
        serial: SerialIr {
            source: serial.source.clone(),
            note: serial.note.trim().to_owned(),
            baud_rates: serial.baud_rates.clone(),
            parities: serial.parities.clone(),
            data_bits: serial.data_bits.choices(),
            protocol_lines: super::protocol_lines::protocol_lines(model),
            // The drive's choice: it sends and needs what it is set to (the factory setting).
            stop_bits_sent: serial.stop_bits_sent.unwrap_or(serial.default.stop_bits),
            stop_bits_received: serial
                .stop_bits_received
                .unwrap_or(serial.default.stop_bits),
            stop_bits: serial.stop_bits.clone(),
            default_baud: serial.default.baud,
            default_parity: serial.default.parity,
            default_data_bits: serial.default.data_bits,
            default_stop_bits: serial.default.stop_bits,
            startup_delay_ms: serial.timing.startup_delay_ms,
            frame_abandon_ms: serial.timing.frame_abandon_ms,
            processing_allowance_ms: serial.timing.processing_allowance_ms,
            assumed_timing: serial.timing.assumed.clone(),
            line: serial.line.as_ref().map(|line| LineIr {
                source: line.source.clone(),
                duplex: line.duplex,
                topology: line.topology,
                synchronisation: line.synchronisation,
                bit_order: line.bit_order,
            }),
        },
        addressing: AddressingIr {
            min: model.addressing.min,
            max: model.addressing.max,
            note: model.addressing.note.trim().to_owned(),
            register: model
                .addressing
                .register
                .as_ref()
                .and_then(|name| index.find(name))
                .map(|r| r.id.clone()),
        },
        protocol_files: protocol_files(&drive.protocols),
        protocols: drive
            .protocols
            .iter()
            .map(|protocol| lower_protocol(model, protocol))
            .collect(),
        error_codes: ErrorCodesIr {
            source: model.error_codes.source.clone(),
            protocols: model
                .protocols
                .iter()
                .filter(|p| drive_table_applies(model, &p.id))
                .map(|p| p.id.clone())
                .collect(),
            codes: lower_error_codes(
                &model.error_codes.codes,
                model.error_codes.notation.as_ref(),
            ),
            silent: model.error_codes.silent.clone(),
        },
        code_tables: model
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
                        id: value.id.clone(),
                        variant: type_name(&value.id),
                        name: value.name.clone(),
                        name_zh: value.name_zh.clone(),
                        line: value.line.map(|l| LineSettingIr {
                            baud: l.baud,
                            data_bits: l.data_bits,
                            parity: l.parity,
                            stop_bits: l.stop_bits,
                        }),
                        protocol: value.protocol.clone(),
                    })
                    .collect(),
            })
            .collect(),
        bitfields: model
            .bitfields
            .iter()
            .map(|bitfield| BitfieldIr {
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
                fields: bitfield
                    .fields
                    .iter()
                    .map(|field| {
                        // Validation has checked the span.
                        let (lsb, width) =
                            bit_span(field.bit, field.bits.as_deref()).unwrap_or((0, 1));
                        let id = field
                            .id
                            .clone()
                            .unwrap_or_else(|| format!("reserved_{lsb}"));
                        BitIr {
                            method: method_name(&id),
                            id,
                            lsb,
                            width,
                            reserved: field.reserved,
                            name: field.name.clone(),
                            name_zh: field.name_zh.clone(),
                            zero: field.zero.clone(),
                            one: field.one.clone(),
                            zero_zh: field.zero_zh.clone(),
                            one_zh: field.one_zh.clone(),
                            code_table: field.code_table.clone(),
                            note: field.note.clone(),
                        }
                    })
                    .collect(),
                examples: bitfield
                    .examples
                    .iter()
                    .map(|e| BitExampleIr {
                        value: e.value as u16,
                        set: e.set.clone(),
                        fields: e
                            .fields
                            .iter()
                            .map(|(id, v)| (id.clone(), *v as u16))
                            .collect(),
                        description: e.description.clone(),
                        source: e.source.clone(),
                    })
                    .collect(),
            })
            .collect(),
        value_examples: model
            .value_examples
            .iter()
            .filter_map(|example| {
                let register = index.find(&example.register)?;
                Some(ValueExampleIr {
                    register: register.id.clone(),
                    value: example.value,
                    raw: example.raw,
                    source: example.source.clone(),
                    description: example.description.clone(),
                    given: example
                        .given
                        .iter()
                        .map(|(name, value)| (code_of(&index, name), *value))
                        .collect(),
                })
            })
            .collect(),
        reference_scaling: model.reference_scaling.as_ref().map(|scaling| {
            let id_of = |name: &str| {
                index
                    .find(name)
                    .map_or_else(|| name.to_owned(), |r| r.id.clone())
            };
            let end = |end: &BoundModel| match end {
                BoundModel::Number(value) => SpanEndIr::Number(*value),
                BoundModel::Register(name) => SpanEndIr::Register(id_of(name)),
            };
            ReferenceScalingIr {
                source: scaling.source.clone(),
                full_scale_raw: scaling.full_scale_raw,
                applies_to: scaling.applies_to.iter().map(|n| id_of(n)).collect(),
                selector: id_of(&scaling.selector),
                note: scaling.note.trim().to_owned(),
                modes: scaling
                    .modes
                    .iter()
                    .map(|mode| ScalingModeIr {
                        selector: mode.selector,
                        low: end(&mode.low),
                        high: end(&mode.high),
                        description: mode.description.clone(),
                    })
                    .collect(),
            }
        }),
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
        examples: lower_examples(drive, &registers),
        sequences: lower_sequences(drive, &registers),
        warnings: model.warnings.clone(),
        registers,
        behaviour: None,
        ports: lower_ports(model, &index),
        conversions: lower_conversions(model, &index),
        persistence: model.persistence.as_ref().map(|p| super::PersistenceIr {
            selector: code_of(&index, &p.selector),
            ram: p.ram,
            persistent: p.persistent,
            registers: p
                .registers
                .iter()
                .map(|span| (span.from, span.to))
                .collect(),
            source: p.source.clone(),
            note: p.note.trim().to_owned(),
        }),
        forbidden_combinations: lower_forbidden(model, &index),
    };
    ir.behaviour = model
        .behaviour
        .as_ref()
        .map(|behaviour| super::behaviour::lower(behaviour, &index, &ir));
    ir
}

fn lower_register(
    drive: &Context,
    index: &ranges::RegisterIndex<'_>,
    register: &RegisterModel,
) -> RegisterIr {
    let model = &drive.model;
    let unit = register
        .unit
        .as_deref()
        .and_then(Unit::from_symbol)
        .unwrap_or(Unit::None);
    let scale = ranges::scale_of(register);
    let data_type = register.data_type.unwrap_or(DataType::Word);
    let value = if let Some(bitfield) = &register.bitfield {
        ValueKind::Bitfield(type_name(bitfield))
    } else if let Some(table) = &register.code_table {
        match model.codes.iter().find(|c| &c.id == table) {
            Some(found) if found.exhaustive => ValueKind::CodeTable(type_name(table)),
            _ => ValueKind::Raw,
        }
    } else if let Some(name) = unit.quantity_type() {
        ValueKind::Quantity(name.to_owned())
    } else if data_type == DataType::Text {
        ValueKind::Text
    } else if (scale - 1.0).abs() > f64::EPSILON {
        ValueKind::Scaled
    } else {
        match (register.signed, data_type == DataType::DoubleWord) {
            (true, true) => ValueKind::RawSignedDouble,
            (false, true) => ValueKind::RawDouble,
            (true, false) => ValueKind::RawSigned,
            (false, false) => ValueKind::Raw,
        }
    };
    let (raw_min, raw_max) = index.raw_range(register);
    let word = crate::validate::ranges::word_limits(register);
    RegisterIr {
        address: register.address as u16,
        id: register.id.clone(),
        type_name: type_name(&register.id),
        code: register.code.clone(),
        aliases: register.aliases.clone(),
        name: register.name.clone(),
        name_zh: register.name_zh.clone(),
        description: register.description.trim().to_owned(),
        note: register.note.trim().to_owned(),
        unit,
        scale,
        signed: register.signed,
        min: derived_bound(register.range.as_ref().map(|r| &r.min), raw_min, word.0),
        max: derived_bound(register.range.as_ref().map(|r| &r.max), raw_max, word.1),
        default: register.default,
        access: register.access.unwrap_or(Access::ReadWrite),
        ram_only: register.ram_only,
        persistent_write_to_ram: register.persistent_write_to_ram,
        writable_while_running: register.writable_while_running.writable(),
        while_running_unknown: register.writable_while_running.is_unknown(),
        panel_only: register.panel_only,
        takes_effect: register.takes_effect.unwrap_or(TakesEffect::Immediately),
        data_type,
        space: register.space.unwrap_or(Space::Parameter),
        array_len: register.array.unwrap_or(0),
        value,
        code_table: register.code_table.clone(),
        source: register.source.clone(),
        inferred: inferred_facts(register),
        warnings: register.warnings.clone(),
        no_reply: register.no_reply,
        wire_only: register.given_address.is_none() && register.on_page.is_empty(),
        on_page: register
            .on_page
            .iter()
            .map(|(protocol, place)| (protocol.clone(), place.page, place.offset))
            .collect(),
        held_at_trip_of: register
            .held_at_trip_of
            .as_ref()
            .map(|name| code_of(index, name)),
        shares_address_with: model
            .registers
            .iter()
            .find(|other| {
                other.address == register.address
                    && other.space == register.space
                    && other.id != register.id
            })
            .map(|other| other.code.clone()),
        live_except_while_tripped: register.live_except_while_tripped,
        scale_by: register.scale_by.as_ref().map(|scale_by| {
            // The register as it is with one choice: its scale, and its range where the
            // choice gives one.
            let chosen =
                |value: u32, scale: f64, range: Option<&crate::parse::model::RangeModel>| {
                    let mut chosen = register.clone();
                    chosen.scale = Some(scale);
                    if let Some(range) = range {
                        chosen.range = Some(range.clone());
                    }
                    chosen.scale_by = None;
                    let (raw_min, raw_max) = index.raw_range(&chosen);
                    ScaleChoiceIr {
                        value,
                        scale,
                        raw_min,
                        raw_max,
                    }
                };
            ScaleByIr {
                register: code_of(index, &scale_by.register),
                choices: scale_by
                    .values
                    .iter()
                    .map(|choice| chosen(choice.value, choice.scale, choice.range.as_ref()))
                    .collect(),
                otherwise: scale_by
                    .otherwise
                    .as_ref()
                    .map(|other| chosen(0, other.scale, other.range.as_ref())),
            }
        }),
        per_port: per_port(model, index, register),
        special_values: register
            .special_values
            .iter()
            .map(|special| SpecialValueIr {
                value: special.value,
                raw: special.raw,
                id: special.id.clone(),
                name: special.name.clone(),
                name_zh: special.name_zh.clone(),
            })
            .collect(),
    }
}

/// The code of the register `name` names (code or id), or `name` itself.
fn code_of(index: &ranges::RegisterIndex<'_>, name: &str) -> String {
    index
        .find(name)
        .map_or_else(|| name.to_owned(), |r| r.code.clone())
}

/// The register's copies on each port, when it is in a row of `ports.registers`.
fn per_port(
    model: &DriveFile,
    index: &ranges::RegisterIndex<'_>,
    register: &RegisterModel,
) -> Vec<(String, String)> {
    let Some(ports) = &model.ports else {
        return Vec::new();
    };
    let row = ports.registers.iter().find(|row| {
        row.values()
            .any(|name| index.find(name).is_some_and(|r| r.id == register.id))
    });
    let Some(row) = row else {
        return Vec::new();
    };
    ports
        .list
        .iter()
        .filter_map(|port| {
            let name = row.get(&port.id)?;
            Some((port.id.clone(), code_of(index, name)))
        })
        .collect()
}

/// The ports, resolved to register codes.
fn lower_ports(model: &DriveFile, index: &ranges::RegisterIndex<'_>) -> Option<PortsIr> {
    let ports = model.ports.as_ref()?;
    Some(PortsIr {
        source: ports.source.clone(),
        note: ports.note.trim().to_owned(),
        ports: ports
            .list
            .iter()
            .map(|port| PortIr {
                id: port.id.clone(),
                const_name: const_name(&port.id),
                name: port.name.clone(),
                name_zh: port.name_zh.clone(),
                settings: port
                    .settings
                    .iter()
                    .map(|(what, name)| (what.clone(), code_of(index, name)))
                    .collect(),
            })
            .collect(),
        shared: ports.shared.iter().map(|n| code_of(index, n)).collect(),
        registers: ports
            .registers
            .iter()
            .map(|row| {
                ports
                    .list
                    .iter()
                    .filter_map(|port| row.get(&port.id).map(|n| code_of(index, n)))
                    .collect()
            })
            .collect(),
    })
}

/// The forbidden combinations, each condition's register resolved to its code and its
/// values to raw words (validation has checked both).
fn lower_forbidden(
    model: &DriveFile,
    index: &ranges::RegisterIndex<'_>,
) -> Vec<ForbiddenCombinationIr> {
    model
        .forbidden_combinations
        .iter()
        .map(|combination| ForbiddenCombinationIr {
            id: combination.id.clone(),
            rule: combination.rule.trim().to_owned(),
            meaning: combination.meaning.trim().to_owned(),
            source: combination.source.clone(),
            when: combination
                .when
                .iter()
                .filter_map(|condition| {
                    let register = index.find(&condition.register)?;
                    let scale = ranges::scale_of(register);
                    let raw = condition
                        .values
                        .iter()
                        .map(|v| (v / scale).round() as u32)
                        .collect();
                    Some((register.code.clone(), raw))
                })
                .collect(),
        })
        .collect()
}

/// The conversions, their formulas parsed (validation has checked they parse).
fn lower_conversions(model: &DriveFile, index: &ranges::RegisterIndex<'_>) -> Vec<ConversionIr> {
    model
        .conversions
        .iter()
        .filter_map(|conversion| {
            let names: Vec<&str> = conversion.inputs.iter().map(|i| i.name.as_str()).collect();
            let program = crate::validate::formula::parse(&conversion.formula, &names).ok()?;
            Some(ConversionIr {
                id: conversion.id.clone(),
                name: conversion.name.clone(),
                source: conversion.source.clone(),
                formula: conversion.formula.clone(),
                program,
                inputs: conversion
                    .inputs
                    .iter()
                    .map(|input| ConversionInputIr {
                        name: input.name.clone(),
                        register: input.register.as_ref().map(|n| code_of(index, n)),
                        times: input.times.unwrap_or(1.0),
                        description: input.description.clone(),
                    })
                    .collect(),
                unit: conversion
                    .unit
                    .as_deref()
                    .and_then(Unit::from_symbol)
                    .unwrap_or(Unit::None),
                result: conversion.result.as_ref().map(|n| code_of(index, n)),
                truncate: conversion.rounding.is_some(),
                when: conversion.when.as_ref().map(|when| {
                    let value = match &when.value {
                        crate::parse::model::ConditionValueModel::Value(value) => Some(*value),
                        crate::parse::model::ConditionValueModel::Word(_) => None,
                    };
                    (code_of(index, &when.register), value)
                }),
                note: conversion.note.trim().to_owned(),
                examples: conversion
                    .examples
                    .iter()
                    .map(|example| {
                        let inputs = conversion
                            .inputs
                            .iter()
                            .map(|input| example.inputs.get(&input.name).copied().unwrap_or(0.0))
                            .collect();
                        (inputs, example.result, example.source.clone())
                    })
                    .collect(),
            })
        })
        .collect()
}

/// A range bound as written; without a range, the raw bound an exhaustive code table gives
/// (when narrower than the word).
fn derived_bound(written: Option<&BoundModel>, raw: i64, word: i64) -> Option<BoundIr> {
    match written {
        Some(bound) => Some(BoundIr {
            raw,
            register: match bound {
                BoundModel::Register(name) => Some(name.clone()),
                BoundModel::Number(_) => None,
            },
        }),
        None => (raw != word).then_some(BoundIr {
            raw,
            register: None,
        }),
    }
}

/// Each protocol file once, with every layout its commands and error reply use.
fn protocol_files(protocols: &[LoweredProtocol]) -> Vec<ProtocolFileIr> {
    let mut files: Vec<ProtocolFileIr> = Vec::new();
    for protocol in protocols {
        if files.iter().any(|f| f.id == protocol.uses) {
            continue;
        }
        let mut layouts: Vec<FrameLayout> = Vec::new();
        let runtime = &protocol.runtime;
        let used = runtime
            .commands
            .iter()
            .flat_map(|c| {
                [&c.request, &c.reply]
                    .into_iter()
                    .chain(c.follow_up.iter().flat_map(|f| [&f.ok, &f.again]))
            })
            .chain(runtime.error_reply.iter());
        for layout in used {
            if !layouts.iter().any(|l| l.name == layout.name) {
                layouts.push(layout.clone());
            }
        }
        let meta = &protocol.file.protocol;
        files.push(ProtocolFileIr {
            id: protocol.uses.clone(),
            module: module_name(&protocol.uses),
            name: meta.name.clone(),
            name_zh: meta.name_zh.clone(),
            description: meta.description.trim().to_owned(),
            text: meta.text,
            layouts,
            based_on: protocol.file.based_on.as_ref().map(|b| b.protocol.clone()),
        });
    }
    files
}

fn lower_error_codes(
    codes: &[ErrorCodeModel],
    notation: Option<&crate::parse::model::CodeNotationModel>,
) -> Vec<ErrorCodeIr> {
    codes
        .iter()
        .map(|c| ErrorCodeIr {
            code: c.code as u16,
            id: c.id.clone(),
            variant: type_name(&c.id),
            name: c.name.clone(),
            name_zh: c.name_zh.clone(),
            meaning: c.meaning.clone(),
            printed: notation.map_or_else(String::new, |n| n.print(c.code)),
        })
        .collect()
}

/// The drive's `block:` on the protocol with this id.
fn block_model<'m>(model: &'m DriveFile, id: &str) -> Option<&'m crate::parse::model::BlockModel> {
    model
        .protocols
        .iter()
        .find(|p| p.id == id)
        .and_then(|p| p.block.as_ref())
}

fn lower_protocol(model: &DriveFile, protocol: &LoweredProtocol) -> ProtocolIr {
    let runtime = &protocol.runtime;
    let reference = model.protocols.iter().find(|p| p.id == protocol.id);
    let own_table = reference.and_then(|r| r.error_codes.as_ref());
    ProtocolIr {
        id: protocol.id.clone(),
        const_name: const_name(&protocol.id),
        uses: protocol.uses.clone(),
        source: protocol.source_section.clone(),
        name: runtime.name.to_string(),
        commands: runtime
            .commands
            .iter()
            .map(|c| CommandIr {
                code: c.code,
                kind: c.kind,
                data_types: c.data_types.to_vec(),
                space: c.space,
                address_map: c.address_map,
                request: c.request.name.to_string(),
                reply: c.reply.name.to_string(),
                reply_codes: c.reply_codes.to_vec(),
                error_code: c.error_code,
                no_reply: c.no_reply,
                extra: c.extra,
                lowercase_means_sender_tripped: c.lowercase_means_sender_tripped,
                stored_by_instruction: c.stored_by_instruction,
                registers: c.registers.to_vec(),
                percent_of: c.percent_of.as_ref().map(|p| {
                    (
                        p.register.to_string(),
                        p.step,
                        p.received_by.iter().map(|id| id.to_string()).collect(),
                    )
                }),
                follow_up: c
                    .follow_up
                    .as_ref()
                    .map(|f| (f.ok.name.to_string(), f.again.name.to_string())),
            })
            .collect(),
        error_reply: runtime.error_reply.as_ref().map(|l| l.name.to_string()),
        lowercase_means_tripped: runtime.lowercase_means_tripped,
        max_frame_len: runtime.max_frame_len,
        address_range: runtime.address_range,
        default_optional_parts: runtime
            .default_optional_parts
            .iter()
            .map(|p| p.to_string())
            .collect(),
        pre_steps: runtime.pre_steps.to_vec(),
        default_process: protocol.file.protocol.default_process,
        frame_gap_chars: runtime.frame_gap_chars,
        max_words_per_read: runtime.max_words_per_read,
        max_words_per_write: runtime.max_words_per_write,
        partial_blocks: runtime.partial_blocks,
        block: runtime.block.clone(),
        block_source: block_model(model, &protocol.id).map_or_else(String::new, |b| {
            let modes: Vec<&str> = b.modes.iter().map(|m| m.source.as_str()).collect();
            if modes.is_empty() {
                b.source.clone()
            } else {
                format!("{}; modes: {}", b.source, modes.join(", "))
            }
        }),
        block_note: block_model(model, &protocol.id)
            .map_or_else(String::new, |b| b.note.trim().to_owned()),
        timing: runtime.timing.clone(),
        before_start_stated: model
            .protocols
            .iter()
            .any(|p| p.id == protocol.id && p.before_start.is_some()),
        broadcast: runtime.broadcast.clone(),
        wire_numbers: runtime.wire_numbers.to_vec(),
        paging: runtime.paging.clone(),
        pages_doc: model
            .protocols
            .iter()
            .find(|p| p.id == protocol.id)
            .and_then(|p| p.pages.as_ref())
            .map(|pages| PagesDocIr {
                source: pages.source.clone(),
                range_names: pages.ranges.iter().map(|r| r.name.clone()).collect(),
                assumed: pages.assumed.clone(),
                note: pages.note.trim().to_owned(),
            }),
        persistence: runtime.persistence.clone(),
        error_table: if let Some(table) = own_table {
            ErrorTableIr::Protocol(ErrorCodesIr {
                source: table.source.clone(),
                protocols: vec![protocol.id.clone()],
                codes: lower_error_codes(&table.codes, table.notation.as_ref()),
                silent: Vec::new(),
            })
        } else if drive_table_applies(model, &protocol.id) {
            ErrorTableIr::Drive
        } else {
            ErrorTableIr::Protocol(protocol.file.error_codes.as_ref().map_or_else(
                || ErrorCodesIr {
                    source: String::new(),
                    protocols: vec![protocol.id.clone()],
                    codes: Vec::new(),
                    silent: Vec::new(),
                },
                |table| ErrorCodesIr {
                    source: table.source.clone(),
                    protocols: vec![protocol.id.clone()],
                    codes: lower_error_codes(&table.codes, table.notation.as_ref()),
                    silent: Vec::new(),
                },
            ))
        },
        variants: runtime.variants.clone(),
        unsupported_function: runtime.unsupported_function.and_then(|error_code| {
            let entry = model
                .protocols
                .iter()
                .find(|p| p.id == protocol.id)?
                .unsupported_function
                .as_ref()?;
            Some(UnsupportedFunctionIr {
                error_code,
                source: entry.source.clone(),
            })
        }),
    }
}

/// The sequences, as the checks left them valid (one call, one result, frames that parse).
fn lower_sequences(drive: &Context, registers: &[RegisterIr]) -> Vec<SequenceIr> {
    drive
        .model
        .sequences
        .iter()
        .filter_map(|sequence| {
            let call = &sequence.call;
            let name = call.read.as_ref().or(call.write.as_ref())?;
            let id = &drive.model.registers.iter().find(|r| r.is_named(name))?.id;
            let register = registers.iter().find(|r| r.id == *id)?;
            let call_ir = match (&call.read, call.value, call.raw) {
                (Some(_), _, _) => SequenceCallIr::Read,
                (None, Some(value), _) => SequenceCallIr::Write(value),
                (None, None, Some(raw)) => SequenceCallIr::WriteRaw(raw),
                _ => return None,
            };
            let protocol = drive.protocols.iter().find(|p| p.id == sequence.protocol)?;
            let result = &sequence.result;
            let result = match (&result.error, result.value) {
                (Some(id), _) => {
                    let code = protocol
                        .runtime
                        .error_codes
                        .iter()
                        .find(|c| c.id == id.as_str())?;
                    SequenceResultIr::Error(code.code, id.clone())
                }
                (None, Some(value)) => SequenceResultIr::Value(value),
                (None, None) => SequenceResultIr::Written,
            };
            let steps = sequence
                .steps
                .iter()
                .map(|step| {
                    crate::frames::frame_bytes(&step.ascii, &step.hex)
                        .ok()
                        .map(|bytes| SequenceStepIr {
                            from: step.from,
                            bytes,
                            shown: step.shown,
                            note: step.note.clone(),
                        })
                })
                .collect::<Option<Vec<_>>>()?;
            Some(SequenceIr {
                id: sequence.id.clone(),
                protocol: sequence.protocol.clone(),
                source: sequence.source.clone(),
                description: sequence.description.trim().to_owned(),
                description_zh: sequence.description_zh.clone(),
                address: sequence.address,
                register: register.id.clone(),
                call: call_ir,
                persistent: call.persistent,
                selector_given: sequence.given.values().next().copied(),
                result,
                steps,
                variant: sequence.variant.clone(),
                reply_wait: sequence.reply_wait,
            })
        })
        .collect()
}

fn lower_examples(drive: &Context, registers: &[RegisterIr]) -> Vec<ExampleIr> {
    drive
        .model
        .examples
        .iter()
        .zip(&drive.frames)
        .map(|(example, decoded)| {
            let frame = |model: &Option<FrameModel>,
                         frame: &Option<DecodedFrame>,
                         answers: Option<&Result<(), NotAnAnswer>>| {
                match (model, frame) {
                    (Some(model), Some(frame)) => lower_frame(model, frame, answers),
                    _ => None,
                }
            };
            let register = decoded
                .reply_then_request()
                .filter_map(DecodedFrame::as_stated)
                .find_map(|meaning| register_of(&drive.model, &meaning))
                .and_then(|found| registers.iter().find(|r| r.id == found.id));
            ExampleIr {
                id: example.id.clone(),
                protocol: example.protocol.clone(),
                source: example.source.clone(),
                description: example.description.clone(),
                description_zh: example.description_zh.clone(),
                request: frame(&example.request, &decoded.request, None),
                reply: frame(
                    &example.reply,
                    &decoded.reply,
                    decoded.printed_answers.as_ref(),
                ),
                answers: decoded.answers.as_ref().is_some_and(Result::is_ok),
                no_reply: example.no_reply,
                ignored_request: match (&example.unanswered_request, &decoded.unanswered) {
                    (Some(model), Some(frame)) => match (&frame.bytes, &frame.meaning) {
                        (Ok(bytes), Some(Err(error))) => Some(UnansweredIr {
                            bytes: bytes.clone(),
                            rejected_as: model.rejected_as,
                            rejection: error.to_string(),
                            reason: model.reason.clone(),
                        }),
                        _ => None,
                    },
                    _ => None,
                },
                value: example.value,
                register: register.map(|r| r.id.clone()),
                settings: example
                    .settings
                    .iter()
                    .map(|(name, value)| {
                        let code = drive
                            .model
                            .registers
                            .iter()
                            .find(|r| r.is_named(name))
                            .map_or_else(|| name.clone(), |r| r.code.clone());
                        (code, *value)
                    })
                    .collect(),
                not_simulated: example.not_simulated.clone(),
                variant: example.variant.clone(),
                page: example.page,
            }
        })
        .collect()
}

/// A frame that validation has accepted: its bytes decoded, and a printed erratum rejected
/// for its stated reason (`printed_answers`: whether the printed reply answers the
/// example's request).
fn lower_frame(
    model: &FrameModel,
    frame: &DecodedFrame,
    printed_answers: Option<&Result<(), NotAnAnswer>>,
) -> Option<FrameIr> {
    let bytes = frame.bytes.clone().ok()?;
    let meaning = frame.decoded()?.clone();
    let printed = match (&frame.printed, model.printed_rejected_as) {
        (Some(printed), Some(rejected_as)) => {
            let rejection = match (&printed.meaning, rejected_as, printed_answers) {
                (Some(Err(error)), _, _) => error.to_string(),
                (Some(Ok(_)), PrintedRejection::DoesNotAnswerRequest, Some(Err(why))) => {
                    why.to_string()
                }
                (Some(Ok(_)), PrintedRejection::ContradictsExpect, _) => {
                    "the frame decodes, but not to what the manual says it means".to_owned()
                }
                _ => return None,
            };
            Some(PrintedIr {
                bytes: printed.bytes.clone().ok()?,
                erratum: model.erratum.clone().unwrap_or_default(),
                rejected_as,
                rejection,
                written: model
                    .printed
                    .as_ref()
                    .and_then(|p| p.hex.as_deref())
                    .map(|hex| hex.split_whitespace().collect::<Vec<_>>().join(" "))
                    .unwrap_or_default(),
            })
        }
        _ => None,
    };
    Some(FrameIr {
        bytes,
        text: model.ascii.is_some(),
        meaning,
        printed,
    })
}

/// The register's inferred facts as the page marks them: an `unknown` while-running flag
/// is shown as the library's assumption (not writable), so it is marked like a reading.
fn inferred_facts(register: &RegisterModel) -> Vec<InferredFact> {
    let mut facts = register.inferred.clone();
    if register.writable_while_running.is_unknown() {
        facts.push(InferredFact::WritableWhileRunning);
    }
    facts
}
