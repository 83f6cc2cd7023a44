//! Lowers a checked description ([`Context`]) into the IR: Rust names chosen, ranges
//! resolved into raw bounds, protocols split into shared layouts and per-drive commands,
//! example frames taken from the one decoding done before validation.
//!
//! The drive as a whole is lowered here; its registers in `register.rs`, what relates
//! registers to one another in `relations.rs`, its protocols in `protocols.rs` and its
//! examples and sequences in `examples.rs`.

mod examples;
mod protocols;
mod register;
mod relations;

use super::types::*;
use crate::naming::{method_name, module_name, type_name};
use crate::parse::model::BoundModel;
use crate::protocols::drive_table_applies;
use crate::validate::ranges;
use crate::validate::{bit_span, Context};
use examples::{lower_examples, lower_sequences};
use protocols::{lower_error_codes, lower_protocol, protocol_files};
use register::lower_register;
use relations::{lower_conversions, lower_forbidden, lower_ports};

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

/// The code of the register `name` names (code or id), or `name` itself.
fn code_of(index: &ranges::RegisterIndex<'_>, name: &str) -> String {
    index
        .find(name)
        .map_or_else(|| name.to_owned(), |r| r.code.clone())
}
