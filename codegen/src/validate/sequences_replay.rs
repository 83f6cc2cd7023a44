//! Check: every multi-step example (`sequences[]`) replays as its golden test replays it:
//! a master over the lowered protocol, fed the manual's drive frames
//! (`vfd_runtime::golden::Script`), makes the one call, sends exactly the manual's frames
//! of its own and gets the stated result.

use crate::diagnostics::Diagnostics;
use crate::frames::{frame_bytes, space_of};
use crate::parse::model::{RegisterModel, Sender, SequenceModel};
use crate::validate::{ranges, Context};
use std::time::Duration;
use vfd_runtime::golden::Script;
use vfd_runtime::serial::{DriveTiming, SerialSettings};
use vfd_runtime::transaction::Master;
use vfd_runtime::{
    Access, CommandKind, DataType, Protocol, RegisterInfo, Request, TransactionErrorKind,
};

/// Every sequence that resolves (see `sequences_resolve`) replays.
pub fn sequences_replay(drive: &Context, out: &mut Diagnostics) {
    let registers = ranges::RegisterIndex::new(&drive.model);
    // A sequence with problems of its own is not replayed: its failure would only follow
    // from them.
    let mut problems = Diagnostics::default();
    super::sequences_resolve::sequences_resolve(drive, &mut problems);
    for (index, sequence) in drive.model.sequences.iter().enumerate() {
        let at = format!("sequences[{index}]");
        if problems
            .items
            .iter()
            .any(|p| p.path == at || p.path.starts_with(&format!("{at}.")))
        {
            continue;
        }
        let Some(protocol) = drive.protocols.iter().find(|p| p.id == sequence.protocol) else {
            continue;
        };
        let name = sequence.call.read.as_ref().or(sequence.call.write.as_ref());
        let Some(register) = name.and_then(|name| registers.find(name)) else {
            continue;
        };
        // A register whose scale another chooses: its golden test states the choice in
        // Rust; nothing here knows it.
        if register.scale_by.is_some() {
            continue;
        }
        let Some(steps) = sequence
            .steps
            .iter()
            .map(|step| {
                frame_bytes(&step.ascii, &step.hex)
                    .ok()
                    .map(|bytes| (step.from == Sender::Master, bytes))
            })
            .collect::<Option<Vec<_>>>()
        else {
            continue;
        };
        if let Err(problem) = replay(drive, &protocol.runtime, sequence, register, &steps) {
            out.push(
                drive
                    .source
                    .error(
                        &format!("sequences[{index}]"),
                        format!("its golden test would fail: {problem}"),
                    )
                    .hint("the golden test makes the call with a master over the protocol and the manual's drive frames; it must send the manual's frames and get `result`: check the steps, `given` and `address` against the manual"),
            );
        }
    }
}

/// Makes the sequence's call against its drive frames; the first difference if any.
fn replay(
    drive: &Context,
    protocol: &Protocol,
    sequence: &SequenceModel,
    register: &RegisterModel,
    steps: &[(bool, Vec<u8>)],
) -> Result<(), String> {
    let info = register_info(drive, register);
    let call = &sequence.call;
    let (kind, data) = match (&call.read, call.value, call.raw) {
        (Some(_), _, _) if info.data_type == DataType::Text => (CommandKind::ReadText, 0),
        (Some(_), _, _) => (CommandKind::Read, 0),
        (None, value, raw) => {
            let kind = if call.persistent {
                CommandKind::WritePersistent
            } else {
                CommandKind::WriteRam
            };
            let data = match (value, raw) {
                (_, Some(raw)) => raw,
                (Some(value), None) => raw_of(info, value),
                (None, None) => return Ok(()), // Reported by sequences_resolve.
            };
            (kind, data)
        }
    };
    let request = Request::for_register(kind, info, data);
    let steps: Vec<(bool, &[u8])> = steps.iter().map(|(m, b)| (*m, b.as_slice())).collect();
    // The master holds its protocol for as long as it lives: a copy for this replay, in the
    // sequence's variant when it names one.
    let in_variant = sequence
        .variant
        .as_deref()
        .and_then(|id| crate::frames::in_variant(protocol, id));
    let protocol: &'static Protocol =
        Box::leak(Box::new(in_variant.unwrap_or_else(|| protocol.clone())));
    let serial = &drive.model.serial;
    let settings = SerialSettings {
        baud: serial.default.baud,
        data_bits: serial.default.data_bits,
        parity: serial.default.parity,
        stop_bits: serial.default.stop_bits,
    };
    let timing = DriveTiming {
        startup_delay: Duration::from_millis(serial.timing.startup_delay_ms),
        processing_allowance: Duration::from_millis(serial.timing.processing_allowance_ms),
        frame_abandon: Duration::from_millis(serial.timing.frame_abandon_ms),
    };
    let mut master = Master::for_protocol(Script::new(&steps), protocol, settings, timing)
        .with_address(sequence.address);
    if let Some(wait) = sequence.reply_wait {
        // The reply-wait digit counts tens of milliseconds, as the golden test asks for it.
        master = master.with_reply_wait(Duration::from_millis(10 * u64::from(wait)));
    }
    if let Some(value) = sequence.given.values().next() {
        master.assume_persistence_selector(*value);
    }
    let outcome = master.transact(&request);
    let result = &sequence.result;
    match (&outcome, &result.error, result.value) {
        (Err(error), Some(id), _) => {
            let code = protocol
                .error_codes
                .iter()
                .find(|c| c.id == id.as_str())
                .map(|c| c.code);
            match (&error.kind, code) {
                (TransactionErrorKind::Rejected { code: got, .. }, Some(code)) if *got == code => {}
                _ => {
                    return Err(format!(
                        "the call fails otherwise than with `{id}`: {error}"
                    ))
                }
            }
        }
        (Err(error), None, _) => return Err(format!("the call fails: {error}")),
        (Ok(_), Some(id), _) => {
            return Err(format!("the call succeeds where the result is `{id}`"))
        }
        (Ok(answer), None, Some(value)) => {
            let raw = answer.data.unwrap_or(0);
            let read = value_of(info, raw);
            if (read - value).abs() > info.scale / 2.0 + 1e-9 {
                return Err(format!(
                    "the call reads {read} (raw {raw:04X}h), not {value}"
                ));
            }
        }
        (Ok(_), None, None) => {}
    }
    master.transport().followed().map_err(|m| m.to_string())
}

/// The register as its generated `RegisterInfo` describes it, for what a master reads of
/// it (address, space, shape, scale, access and storage).
fn register_info(drive: &Context, register: &RegisterModel) -> &'static RegisterInfo {
    let text = |s: &str| -> &'static str { Box::leak(s.to_owned().into_boxed_str()) };
    let (raw_min, raw_max) = ranges::RegisterIndex::new(&drive.model).raw_range(register);
    Box::leak(Box::new(RegisterInfo {
        address: u16::try_from(register.address).unwrap_or(u16::MAX),
        id: text(&register.id),
        code: text(&register.code),
        name: text(&register.name),
        scale: ranges::scale_of(register),
        signed: register.signed,
        raw_min,
        raw_max,
        data_type: register.data_type.unwrap_or(DataType::Word),
        space: space_of(register),
        array_len: register.array.unwrap_or(0),
        access: register.access.unwrap_or(Access::ReadWrite),
        ram_only: register.ram_only,
        no_reply: register.no_reply,
        ..RegisterInfo::DEFAULT
    }))
}

/// The raw word for an engineering value (two's complement when signed).
fn raw_of(info: &RegisterInfo, value: f64) -> u32 {
    let raw = (value / info.scale).round() as i64;
    match info.data_type.size() {
        4 => raw as i32 as u32,
        _ => u32::from(raw as i16 as u16),
    }
}

/// The engineering value of a raw word.
fn value_of(info: &RegisterInfo, raw: u32) -> f64 {
    let raw = match (info.signed, info.data_type.size()) {
        (true, 4) => f64::from(raw as i32),
        (true, _) => f64::from(raw as u16 as i16),
        (false, _) => f64::from(raw),
    };
    raw * info.scale
}
