//! Lowers a drive's `behaviour:` section: register names (codes or ids) become ids, and
//! bit ids become masks within the bit field of the word they belong to.

use super::types::*;
use crate::parse::model::{BehaviourModel, BitRefModel, BoundModel};
use crate::validate::ranges::RegisterIndex;

/// Lowers a behaviour model that passed validation (`ir` holds the lowered registers and
/// bit fields).
pub(crate) fn lower(
    model: &BehaviourModel,
    index: &RegisterIndex<'_>,
    ir: &DriveIr,
) -> BehaviourIr {
    let id_of = |name: &str| {
        index
            .find(name)
            .map_or_else(|| name.to_owned(), |r| r.id.clone())
    };
    let ids = |names: &[String]| names.iter().map(|n| id_of(n)).collect::<Vec<_>>();
    let amount = |amount: &BoundModel| match amount {
        BoundModel::Number(value) => AmountIr::Number(*value),
        BoundModel::Register(name) => AmountIr::Register(id_of(name)),
    };
    let command_bits = bitfield_of(ir, &id_of(&model.command.register));
    let status_bits = model
        .status
        .registers
        .first()
        .and_then(|name| bitfield_of(ir, &id_of(name)));
    let command_bit = |bit: &BitRefModel| resolve(index, ir, command_bits, bit);
    let command_list = |bits: &[BitRefModel]| bits.iter().map(command_bit).collect::<Vec<_>>();
    let status_list = |bits: &[BitRefModel]| {
        bits.iter()
            .map(|bit| resolve(index, ir, status_bits, bit))
            .collect::<Vec<_>>()
    };
    let status = &model.status;
    BehaviourIr {
        source: model.source.clone(),
        note: model.note.trim().to_owned(),
        command_register: id_of(&model.command.register),
        command_require: command_list(&model.command.require),
        run: model.command.run.as_ref().map(command_bit),
        command_codes: model.command.codes.as_ref().map(|c| CommandCodesIr {
            run: c.run.clone(),
            run_reverse: c.run_reverse.clone(),
            stop: c.stop.clone(),
            coast: c.coast.clone(),
            reset: c.reset.clone(),
        }),
        run_reverse: model.command.run_reverse.as_ref().map(command_bit),
        reverse: model.command.reverse.as_ref().map(command_bit),
        reset: model.command.reset.as_ref().map(command_bit),
        reset_by_write: model
            .command
            .reset_by_write
            .as_ref()
            .map(|w| (id_of(&w.register), w.value)),
        coast: model.command.coast.as_ref().map(command_bit),
        require_mode: model
            .command
            .require_mode
            .as_ref()
            .map(|m| (id_of(&m.register), m.values.clone())),
        frequency_command: id_of(&model.frequency.command),
        frequency_require: command_list(&model.frequency.require),
        acceleration: amount(&model.frequency.acceleration),
        deceleration: amount(&model.frequency.deceleration),
        span: amount(&model.frequency.span),
        output: ids(&model.frequency.output),
        reference: ids(&model.frequency.reference),
        current: model
            .current
            .as_ref()
            .map(|c| (ids(&c.registers), c.at_zero, c.at_span)),
        current_overload: model
            .current
            .as_ref()
            .and_then(|c| c.overload.as_ref())
            .map(amount),
        frequency_detection: model.frequency.detection.as_ref().map(amount),
        frequency_percent_of: model.frequency.percent_of.as_ref().map(amount),
        status_registers: ids(&status.registers),
        status: StatusBitsIr {
            running: status_list(&status.running),
            reverse: status_list(&status.reverse),
            forward: status_list(&status.forward),
            at_reference: status_list(&status.at_reference),
            tripped: status_list(&status.tripped),
            overload: status_list(&status.overload),
            frequency_detected: status_list(&status.frequency_detected),
            enabled: status_list(&status.enabled),
            always: status_list(&status.always),
        },
        status_state: status.state.as_ref().map(|s| StatusStateIr {
            register: id_of(&s.register),
            stopped: s.stopped,
            forward: s.forward,
            reverse: s.reverse.unwrap_or(s.forward),
            tripped: s.tripped.unwrap_or(s.stopped),
        }),
        trip_code: ids(&model.trip.code),
        trip_history: model
            .trip
            .history
            .iter()
            .map(|name| trip_slot(index, ir, name))
            .collect(),
        trip_clear_by_write: model
            .trip
            .clear_by_write
            .as_ref()
            .map(|w| (id_of(&w.register), w.value)),
        process: model.process.as_ref().map(|p| {
            [
                id_of(&p.control),
                id_of(&p.reference),
                id_of(&p.status),
                id_of(&p.output),
            ]
        }),
        refusals: model
            .refusals
            .iter()
            .map(|(protocol, r)| RefusalsIr {
                protocol: protocol.clone(),
                unknown_register: r.unknown_register,
                read_only: r.read_only,
                out_of_range: r.out_of_range,
                while_running: r.while_running,
                bad_checksum: r.bad_checksum,
                wrong_mode: r.wrong_mode,
                bad_character: r.bad_character,
                malformed: r.malformed,
                retries_exceeded: r
                    .retries_exceeded
                    .as_ref()
                    .map(|rule| (rule.code, amount(&rule.after))),
            })
            .collect(),
    }
}

/// A trip-history entry: a register, or `register.field` (validation has checked it).
fn trip_slot(index: &RegisterIndex<'_>, ir: &DriveIr, name: &str) -> TripSlotIr {
    if let Some(register) = index.find(name) {
        return TripSlotIr::Register(register.id.clone());
    }
    let Some((register, field)) = split_field(index, name) else {
        return TripSlotIr::Register(name.to_owned());
    };
    let mask = bitfield_of(ir, &register)
        .and_then(|b| b.fields.iter().find(|f| f.id == field))
        .map_or(0, |f| ((1u32 << f.width) - 1) << f.lsb);
    TripSlotIr::Field {
        register,
        field: field.to_owned(),
        mask,
    }
}

/// `register.field` as the register's id and the field's id, when the part before the
/// last `.` names a register.
pub(crate) fn split_field<'n>(
    index: &RegisterIndex<'_>,
    name: &'n str,
) -> Option<(String, &'n str)> {
    let (register, field) = name.rsplit_once('.')?;
    Some((index.find(register)?.id.clone(), field))
}

/// The bit field of the register with this id.
fn bitfield_of<'a>(ir: &'a DriveIr, register: &str) -> Option<&'a BitfieldIr> {
    let name = ir.register(register).and_then(|r| match &r.value {
        ValueKind::Bitfield(type_name) => Some(type_name.clone()),
        _ => None,
    })?;
    ir.bitfields.iter().find(|b| b.type_name == name)
}

/// A bit by id within `bitfield`, the bit field of its role's word; or, where the word has
/// no such field, a field of another bit-field register as `register.field`, or a coil of
/// its own (validation has checked that it is one of them).
fn resolve(
    index: &RegisterIndex<'_>,
    ir: &DriveIr,
    bitfield: Option<&BitfieldIr>,
    bit: &BitRefModel,
) -> BitRefIr {
    let mask_of = |b: &BitfieldIr, id: &str| {
        b.fields
            .iter()
            .find(|f| f.id == id)
            .map(|f| ((1u32 << f.width) - 1) << f.lsb)
    };
    let own = bitfield.and_then(|b| mask_of(b, bit.id()));
    let (mask, register) = match own {
        Some(mask) => (mask, None),
        None => match elsewhere(index, ir, bit.id()) {
            Some(Elsewhere::Field { register, mask }) => (mask, Some(register)),
            Some(Elsewhere::Coil { register }) => (COIL_ON, Some(register)),
            None => (0, None),
        },
    };
    BitRefIr {
        id: bit.id().to_owned(),
        mask,
        active_low: bit.active_low(),
        register,
    }
}

/// The bits of a coil's word that are set while it is on (FF00h, as a Modbus write of
/// one coil carries it).
pub(crate) const COIL_ON: u32 = 0xFF00;

/// A bit held by a register other than its role's word.
pub(crate) enum Elsewhere {
    /// A field of another bit-field register (`register.field`).
    Field { register: String, mask: u32 },
    /// A coil (a register of `data_type: bit`): on while it holds FF00h.
    Coil { register: String },
}

/// What `name` names outside its role's word: `register.field`, a field of another
/// bit-field register, or a coil by code or id.
pub(crate) fn elsewhere(index: &RegisterIndex<'_>, ir: &DriveIr, name: &str) -> Option<Elsewhere> {
    if let Some((register, field)) = split_field(index, name) {
        let mask = bitfield_of(ir, &register)
            .and_then(|b| b.fields.iter().find(|f| f.id == field))
            .map(|f| ((1u32 << f.width) - 1) << f.lsb)?;
        return Some(Elsewhere::Field { register, mask });
    }
    let register = index.find(name)?;
    (register.data_type == Some(vfd_runtime::DataType::Bit)).then(|| Elsewhere::Coil {
        register: register.id.clone(),
    })
}
