//! The behaviour model as a run-time value: the `vfd_runtime::behaviour::Behaviour` the
//! virtual drive follows, as `emit/rust/behaviour.rs` writes it.

use super::{list, text, texts};
use crate::ir::{AmountIr, BehaviourIr, BitRefIr, TripSlotIr};
use vfd_runtime::behaviour::{
    Amount, Behaviour, Bit, CommandBehaviour, CommandCodes, CurrentBehaviour, FrequencyBehaviour,
    ModeRequirement, ProcessBehaviour, Refusals, StatusBehaviour, StatusState, TripBehaviour,
    TripSlot, WrittenValue,
};

/// The behaviour model of `b`.
pub(super) fn behaviour(b: &BehaviourIr) -> Behaviour {
    let s = &b.status;
    Behaviour {
        source: text(&b.source),
        command: CommandBehaviour {
            register: text(&b.command_register),
            require: bits(&b.command_require),
            run: b.run.as_ref().map_or(Bit::NONE, bit),
            run_reverse: b.run_reverse.as_ref().map(bit),
            reverse: b.reverse.as_ref().map(bit),
            reset: b.reset.as_ref().map(bit),
            reset_by_write: b.reset_by_write.as_ref().map(written_value),
            coast: b.coast.as_ref().map(bit),
            require_mode: b
                .require_mode
                .as_ref()
                .map(|(register, values)| ModeRequirement {
                    register: text(register),
                    values: list(values.clone()),
                }),
            codes: b.command_codes.as_ref().map(|c| CommandCodes {
                run: list(c.run.clone()),
                run_reverse: list(c.run_reverse.clone()),
                stop: list(c.stop.clone()),
                coast: list(c.coast.clone()),
                reset: list(c.reset.clone()),
            }),
        },
        frequency: FrequencyBehaviour {
            command: text(&b.frequency_command),
            require: bits(&b.frequency_require),
            acceleration: amount(&b.acceleration),
            deceleration: amount(&b.deceleration),
            span: amount(&b.span),
            output: texts(&b.output),
            reference: texts(&b.reference),
            detection: b.frequency_detection.as_ref().map(amount),
            percent_of: b.frequency_percent_of.as_ref().map(amount),
        },
        current: b
            .current
            .as_ref()
            .map(|(registers, at_zero, at_span)| CurrentBehaviour {
                registers: texts(registers),
                at_zero: *at_zero,
                at_span: *at_span,
                overload: b.current_overload.as_ref().map(amount),
            }),
        status: StatusBehaviour {
            registers: texts(&b.status_registers),
            running: bits(&s.running),
            reverse: bits(&s.reverse),
            forward: bits(&s.forward),
            at_reference: bits(&s.at_reference),
            tripped: bits(&s.tripped),
            overload: bits(&s.overload),
            frequency_detected: bits(&s.frequency_detected),
            enabled: bits(&s.enabled),
            always: bits(&s.always),
            state: b.status_state.as_ref().map(|s| StatusState {
                register: text(&s.register),
                stopped: s.stopped,
                forward: s.forward,
                reverse: s.reverse,
                tripped: s.tripped,
            }),
        },
        trip: TripBehaviour {
            code: texts(&b.trip_code),
            history: list(
                b.trip_history
                    .iter()
                    .map(|slot| match slot {
                        TripSlotIr::Register(id) => TripSlot::whole(text(id)),
                        TripSlotIr::Field { register, mask, .. } => TripSlot {
                            register: text(register),
                            mask: *mask,
                        },
                    })
                    .collect(),
            ),
            clear_by_write: b.trip_clear_by_write.as_ref().map(written_value),
        },
        process: b
            .process
            .as_ref()
            .map(|[control, reference, status, output]| ProcessBehaviour {
                control: text(control),
                reference: text(reference),
                status: text(status),
                output: text(output),
            }),
        refusals: list(
            b.refusals
                .iter()
                .map(|r| Refusals {
                    protocol: text(&r.protocol),
                    unknown_register: r.unknown_register,
                    read_only: r.read_only,
                    out_of_range: r.out_of_range,
                    while_running: r.while_running,
                    bad_checksum: r.bad_checksum,
                    wrong_mode: r.wrong_mode,
                    bad_character: r.bad_character,
                    malformed: r.malformed,
                    retries_exceeded: r.retries_exceeded.as_ref().map(|(code, after)| {
                        vfd_runtime::behaviour::RetriesExceeded {
                            code: *code,
                            after: amount(after),
                        }
                    }),
                })
                .collect(),
        ),
    }
}

fn bit(bit: &BitRefIr) -> Bit {
    let level = if bit.active_low {
        Bit::low(bit.mask)
    } else {
        Bit::high(bit.mask)
    };
    match &bit.register {
        Some(register) => level.in_register(text(register)),
        None => level,
    }
}

fn bits(list_of: &[BitRefIr]) -> &'static [Bit] {
    list(list_of.iter().map(bit).collect())
}

fn amount(amount: &AmountIr) -> Amount {
    match amount {
        AmountIr::Number(value) => Amount::Value(*value),
        AmountIr::Register(id) => Amount::Register(text(id)),
    }
}

fn written_value((register, value): &(String, u32)) -> WrittenValue {
    WrittenValue {
        register: text(register),
        value: *value,
    }
}
