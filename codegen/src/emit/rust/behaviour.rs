//! Emits a drive's behaviour model as one `BEHAVIOUR` static of the runtime's
//! `vfd_runtime::behaviour::Behaviour`, for the virtual drive.

use super::*;
use crate::ir::{AmountIr, BehaviourIr, BitRefIr, TripSlotIr};

fn bit(bit: &BitRefIr) -> TokenStream {
    let mask = int_literal(bit.mask);
    let level = if bit.active_low {
        quote!(Bit::low(#mask))
    } else {
        quote!(Bit::high(#mask))
    };
    match &bit.register {
        Some(register) => quote!(#level.in_register(#register)),
        None => level,
    }
}

fn bits(list: &[BitRefIr]) -> TokenStream {
    let list = list.iter().map(bit);
    quote!(&[#(#list),*])
}

fn optional_bit(value: Option<&BitRefIr>) -> TokenStream {
    match value {
        Some(value) => {
            let value = bit(value);
            quote!(Some(#value))
        }
        None => quote!(None),
    }
}

fn amount(amount: &AmountIr) -> TokenStream {
    match amount {
        AmountIr::Number(value) => {
            let value = f64_literal(*value);
            quote!(Amount::Value(#value))
        }
        AmountIr::Register(id) => quote!(Amount::Register(#id)),
    }
}

fn written_value(value: Option<&(String, u32)>) -> TokenStream {
    match value {
        Some((register, value)) => {
            let value = int_literal(*value);
            quote!(Some(WrittenValue { register: #register, value: #value }))
        }
        None => quote!(None),
    }
}

fn ids(ids: &[String]) -> TokenStream {
    quote!(&[#(#ids),*])
}

fn code(code: Option<u16>) -> TokenStream {
    match code {
        Some(code) => {
            let code = int_literal(code);
            quote!(Some(#code))
        }
        None => quote!(None),
    }
}

/// `pub static BEHAVIOUR` and the `DriveInfo::behaviour` value naming it (`None` when the
/// drive declares no behaviour).
pub(super) fn behaviour_static(drive: &DriveIr) -> (TokenStream, TokenStream) {
    let Some(b) = &drive.behaviour else {
        return (quote!(), quote!(None));
    };
    (behaviour_tokens(b), quote!(Some(&BEHAVIOUR)))
}

fn behaviour_tokens(b: &BehaviourIr) -> TokenStream {
    let source = &b.source;
    let (register, require) = (&b.command_register, bits(&b.command_require));
    let run = match &b.run {
        Some(run) => bit(run),
        None => quote!(Bit::NONE),
    };
    let list = |values: &[u32]| {
        let values = values.iter().map(|v| int_literal(*v));
        quote!(&[#(#values),*])
    };
    let command_codes = match &b.command_codes {
        Some(c) => {
            let (run, run_reverse, stop, coast, reset) = (
                list(&c.run),
                list(&c.run_reverse),
                list(&c.stop),
                list(&c.coast),
                list(&c.reset),
            );
            quote!(Some(CommandCodes { run: #run, run_reverse: #run_reverse, stop: #stop, coast: #coast, reset: #reset }))
        }
        None => quote!(None),
    };
    let status_state = match &b.status_state {
        Some(s) => {
            let register = &s.register;
            let (stopped, forward, reverse, tripped) = (
                int_literal(s.stopped),
                int_literal(s.forward),
                int_literal(s.reverse),
                int_literal(s.tripped),
            );
            quote!(Some(StatusState { register: #register, stopped: #stopped, forward: #forward, reverse: #reverse, tripped: #tripped }))
        }
        None => quote!(None),
    };
    let (run_reverse, reverse, reset, coast) = (
        optional_bit(b.run_reverse.as_ref()),
        optional_bit(b.reverse.as_ref()),
        optional_bit(b.reset.as_ref()),
        optional_bit(b.coast.as_ref()),
    );
    let reset_by_write = written_value(b.reset_by_write.as_ref());
    let require_mode = match &b.require_mode {
        Some((register, values)) => {
            let values = values.iter().map(|v| int_literal(*v));
            quote!(Some(ModeRequirement { register: #register, values: &[#(#values),*] }))
        }
        None => quote!(None),
    };
    let (command, frequency_require) = (&b.frequency_command, bits(&b.frequency_require));
    let (acceleration, deceleration, span) = (
        amount(&b.acceleration),
        amount(&b.deceleration),
        amount(&b.span),
    );
    let (output, reference) = (ids(&b.output), ids(&b.reference));
    let optional_amount = |value: Option<&AmountIr>| match value {
        Some(value) => {
            let value = amount(value);
            quote!(Some(#value))
        }
        None => quote!(None),
    };
    let detection = optional_amount(b.frequency_detection.as_ref());
    let percent_of = optional_amount(b.frequency_percent_of.as_ref());
    let current = match &b.current {
        Some((registers, at_zero, at_span)) => {
            let registers = ids(registers);
            let (at_zero, at_span) = (f64_literal(*at_zero), f64_literal(*at_span));
            let overload = optional_amount(b.current_overload.as_ref());
            quote!(Some(CurrentBehaviour { registers: #registers, at_zero: #at_zero, at_span: #at_span, overload: #overload }))
        }
        None => quote!(None),
    };
    let status_registers = ids(&b.status_registers);
    let s = &b.status;
    let (running, reverse_bits, forward_bits, at_reference, tripped, enabled, always) = (
        bits(&s.running),
        bits(&s.reverse),
        bits(&s.forward),
        bits(&s.at_reference),
        bits(&s.tripped),
        bits(&s.enabled),
        bits(&s.always),
    );
    let (overload, frequency_detected) = (bits(&s.overload), bits(&s.frequency_detected));
    let trip_code = ids(&b.trip_code);
    let slots = b.trip_history.iter().map(|slot| match slot {
        TripSlotIr::Register(id) => quote!(TripSlot::whole(#id)),
        TripSlotIr::Field { register, mask, .. } => {
            let mask = int_literal(*mask);
            quote!(TripSlot { register: #register, mask: #mask })
        }
    });
    let trip_history = quote!(&[#(#slots),*]);
    let trip_clear = written_value(b.trip_clear_by_write.as_ref());
    let process = match &b.process {
        Some([control, reference, status, output]) => quote!(Some(ProcessBehaviour {
            control: #control, reference: #reference, status: #status, output: #output
        })),
        None => quote!(None),
    };
    let refusals = b.refusals.iter().map(|r| {
        let protocol = &r.protocol;
        let (unknown, read_only, out_of_range, while_running, bad_checksum, wrong_mode) = (
            code(r.unknown_register),
            code(r.read_only),
            code(r.out_of_range),
            code(r.while_running),
            code(r.bad_checksum),
            code(r.wrong_mode),
        );
        let (bad_character, malformed) = (code(r.bad_character), code(r.malformed));
        let retries_exceeded = match &r.retries_exceeded {
            Some((code, after)) => {
                let (code, after) = (int_literal(*code), amount(after));
                quote!(Some(RetriesExceeded { code: #code, after: #after }))
            }
            None => quote!(None),
        };
        quote!(Refusals {
            protocol: #protocol,
            unknown_register: #unknown,
            read_only: #read_only,
            out_of_range: #out_of_range,
            while_running: #while_running,
            bad_checksum: #bad_checksum,
            wrong_mode: #wrong_mode,
            bad_character: #bad_character,
            malformed: #malformed,
            retries_exceeded: #retries_exceeded,
        })
    });
    let doc = doc_text(format!(
        "The behaviour model the virtual drive follows (manual: {}). {}",
        b.source, b.note
    ));
    quote! {
        #[doc = #doc]
        pub static BEHAVIOUR: ::vfd_runtime::behaviour::Behaviour = {
            use ::vfd_runtime::behaviour::*;
            Behaviour {
                source: #source,
                command: CommandBehaviour {
                    register: #register,
                    require: #require,
                    run: #run,
                    run_reverse: #run_reverse,
                    reverse: #reverse,
                    reset: #reset,
                    reset_by_write: #reset_by_write,
                    coast: #coast,
                    require_mode: #require_mode,
                    codes: #command_codes,
                },
                frequency: FrequencyBehaviour {
                    command: #command,
                    require: #frequency_require,
                    acceleration: #acceleration,
                    deceleration: #deceleration,
                    span: #span,
                    output: #output,
                    reference: #reference,
                    detection: #detection,
                    percent_of: #percent_of,
                },
                current: #current,
                status: StatusBehaviour {
                    registers: #status_registers,
                    running: #running,
                    reverse: #reverse_bits,
                    forward: #forward_bits,
                    at_reference: #at_reference,
                    tripped: #tripped,
                    overload: #overload,
                    frequency_detected: #frequency_detected,
                    enabled: #enabled,
                    always: #always,
                    state: #status_state,
                },
                trip: TripBehaviour { code: #trip_code, history: #trip_history, clear_by_write: #trip_clear },
                process: #process,
                refusals: &[#(#refusals),*],
            }
        };
    }
}
