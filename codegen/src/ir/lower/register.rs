//! Lowers a register: how its value is typed in Rust, its raw bounds, its scale choices,
//! its copies on each port and the facts the page marks inferred.

use super::code_of;
use super::relations::per_port;
use crate::ir::types::*;
use crate::naming::type_name;
use crate::parse::model::{BoundModel, RegisterModel};
use crate::validate::ranges;
use crate::validate::Context;
use vfd_runtime::units::Unit;
use vfd_runtime::{Access, DataType, Space, TakesEffect};

pub(super) fn lower_register(
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

/// The register's inferred facts as the page marks them: an `unknown` while-running flag
/// is shown as the library's assumption (not writable), so it is marked like a reading.
fn inferred_facts(register: &RegisterModel) -> Vec<InferredFact> {
    let mut facts = register.inferred.clone();
    if register.writable_while_running.is_unknown() {
        facts.push(InferredFact::WritableWhileRunning);
    }
    facts
}
