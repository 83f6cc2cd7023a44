//! Registers as run-time values: each `RegisterInfo` with its bit-field layout, code table,
//! scale choices and special values, as `emit/rust/registers.rs` writes them.

use super::{leak, list, text, texts};
use crate::ir::{BitfieldIr, BoundIr, CodeTableIr, DriveIr, RegisterIr, ValueKind};
use std::collections::HashMap;
use vfd_runtime::info::{BitFieldInfo, BitWordInfo, CodeInfo, CodeTableInfo};
use vfd_runtime::{RegisterInfo, ScaleBy, ScaleChoice, SpecialValue};

/// The code tables and bit-field layouts as data, by id.
struct Tables {
    codes: HashMap<String, &'static CodeTableInfo>,
    bits: HashMap<String, &'static BitWordInfo>,
}

/// Every register of `ir`, in the manual's order.
pub(super) fn registers(ir: &DriveIr) -> &'static [&'static RegisterInfo] {
    let codes: HashMap<String, &'static CodeTableInfo> = ir
        .code_tables
        .iter()
        .map(|table| (table.id.clone(), leak(code_table(table))))
        .collect();
    let bits = ir
        .bitfields
        .iter()
        .map(|bitfield| (bitfield.id.clone(), leak(bit_word(bitfield, &codes))))
        .collect();
    let tables = Tables { codes, bits };
    list(
        ir.registers
            .iter()
            .map(|register| {
                let mut info = info(ir, register, &tables);
                if let Some(scale_by) = scale_by(ir, register, &tables) {
                    info = info.with_scale_by(leak(scale_by));
                }
                leak(info)
            })
            .collect(),
    )
}

/// A code table as data (`CodeTableInfo`).
fn code_table(table: &CodeTableIr) -> CodeTableInfo {
    CodeTableInfo {
        id: text(&table.id),
        name: text(&table.name),
        name_zh: text(&table.name_zh),
        exhaustive: table.exhaustive,
        values: list(
            table
                .values
                .iter()
                .map(|v| CodeInfo {
                    value: v.value,
                    id: text(&v.id),
                    name: text(&v.name),
                    name_zh: text(&v.name_zh),
                })
                .collect(),
        ),
    }
}

/// A bit-field layout as data (`BitWordInfo`), reserved bits left out.
fn bit_word(bitfield: &BitfieldIr, codes: &HashMap<String, &'static CodeTableInfo>) -> BitWordInfo {
    BitWordInfo {
        id: text(&bitfield.id),
        name: text(&bitfield.name),
        name_zh: text(&bitfield.name_zh),
        fields: list(
            bitfield
                .fields
                .iter()
                .filter(|f| !f.reserved)
                .map(|f| BitFieldInfo {
                    id: text(&f.id),
                    name: text(&f.name),
                    name_zh: text(&f.name_zh),
                    mask: f.mask(),
                    zero: text(&f.zero),
                    one: text(&f.one),
                    codes: f.code_table.as_ref().and_then(|t| codes.get(t).copied()),
                })
                .collect(),
        ),
    }
}

/// The register's `RegisterInfo`, without its scale choices.
fn info(ir: &DriveIr, register: &RegisterIr, tables: &Tables) -> RegisterInfo {
    let mut info = RegisterInfo::new(register.address, text(&register.code), text(&register.id))
        .with_names(text(&register.name), text(&register.name_zh))
        .with_aliases(texts(&register.aliases))
        .with_unit(register.unit, register.scale)
        .with_data_type(register.data_type)
        .with_access(register.access)
        .with_takes_effect(register.takes_effect)
        .with_space(register.space)
        .with_array(register.array_len);
    let (raw_min, raw_max) = register.raw_range();
    info = info.with_raw_range(raw_min, raw_max);
    info.signed = register.signed;
    info.ram_only = register.ram_only;
    info.persistent_write_to_ram = register.persistent_write_to_ram;
    info.has_address = !register.wire_only;
    info.writable_while_running = register.writable_while_running;
    info.while_running_unknown = register.while_running_unknown;
    info.panel_only = register.panel_only;
    info.no_reply = register.no_reply;
    info.live_except_while_tripped = register.live_except_while_tripped;
    info.min_bound = bound_register(register.min.as_ref());
    info.max_bound = bound_register(register.max.as_ref());
    info.default_raw = register.default_raw();
    if let ValueKind::Bitfield(type_name) = &register.value {
        info.bits = ir
            .bitfields
            .iter()
            .find(|b| &b.type_name == type_name)
            .and_then(|b| tables.bits.get(&b.id).copied());
    }
    info.codes = register
        .code_table
        .as_ref()
        .and_then(|id| tables.codes.get(id).copied());
    let words: Vec<&str> = [register.description.as_str(), register.note.as_str()]
        .into_iter()
        .filter(|t| !t.is_empty())
        .collect();
    info.text = text(&words.join(" "));
    info.held_at_trip_of = register.held_at_trip_of.as_deref().map(text);
    info.special_values = list(
        register
            .special_values
            .iter()
            .map(|special| SpecialValue {
                value: special.value,
                raw: special.raw,
                id: text(&special.id),
                name: text(&special.name),
            })
            .collect(),
    );
    info.per_port = list(
        register
            .per_port
            .iter()
            .map(|(port, code)| (text(port), text(code)))
            .collect(),
    );
    info
}

/// The code of the register setting a bound at run time, if any.
fn bound_register(bound: Option<&BoundIr>) -> Option<&'static str> {
    bound.and_then(|b| b.register.as_deref()).map(text)
}

/// The register's scale choices, when another register chooses its scale: per choice, the
/// register's info with that choice's scale and raw range (and no default).
fn scale_by(ir: &DriveIr, register: &RegisterIr, tables: &Tables) -> Option<ScaleBy> {
    let scale_by = register.scale_by.as_ref()?;
    let info_of = |choice: &crate::ir::ScaleChoiceIr| {
        leak(info(ir, &register.with_scale_choice(choice), tables))
    };
    Some(ScaleBy {
        register: text(&scale_by.register),
        choices: list(
            scale_by
                .choices
                .iter()
                .map(|choice| ScaleChoice {
                    value: choice.value,
                    info: info_of(choice),
                })
                .collect(),
        ),
        otherwise: scale_by.otherwise.as_ref().map(info_of),
    })
}
