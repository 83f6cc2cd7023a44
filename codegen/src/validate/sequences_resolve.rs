//! Check: every multi-step example (`sequences[]`) names a protocol, a register and an
//! error code the drive has, makes one call, and each of its frames is one the protocol
//! can carry in that direction (a request or a follow-up from the master, a reply from the
//! drive), starting with the master's.

use crate::diagnostics::Diagnostics;
use crate::frames::frame_bytes;
use crate::parse::model::{Sender, SequenceModel};
use crate::validate::{ranges, Context};
use vfd_runtime::{Protocol, Role};

/// Every sequence resolves and its frames decode.
pub fn sequences_resolve(drive: &Context, out: &mut Diagnostics) {
    for (index, sequence) in drive.model.sequences.iter().enumerate() {
        let base = format!("sequences[{index}]");
        let mut error = |key: &str, message: String, hint: &str| {
            out.push(
                drive
                    .source
                    .error(&format!("{base}{key}"), message)
                    .hint(hint.to_owned()),
            );
        };
        let Some(protocol) = drive.protocols.iter().find(|p| p.id == sequence.protocol) else {
            if !drive
                .model
                .protocols
                .iter()
                .any(|p| p.id == sequence.protocol)
            {
                error(
                    ".protocol",
                    format!("unknown protocol `{}`", sequence.protocol),
                    "use one of the drive's protocol ids",
                );
            }
            continue;
        };
        // The frames are in the variant the sequence names (the first when it names none).
        let in_variant = match &sequence.variant {
            Some(variant) => match crate::frames::in_variant(&protocol.runtime, variant) {
                Some(found) => Some(found),
                None => {
                    out.push(crate::validate::examples_decode::unknown_variant(
                        drive,
                        &format!("{base}.variant"),
                        &protocol.runtime,
                        variant,
                    ));
                    continue;
                }
            },
            None => None,
        };
        let mut error = |key: &str, message: String, hint: &str| {
            out.push(
                drive
                    .source
                    .error(&format!("{base}{key}"), message)
                    .hint(hint.to_owned()),
            );
        };
        let runtime = in_variant.as_ref().unwrap_or(&protocol.runtime);
        check_call(drive, sequence, &mut error);
        if sequence.given.len() > 1 {
            error(
                ".given",
                format!("{} values given", sequence.given.len()),
                "a master can be told one value: the persistence selector's",
            );
        }
        let registers = ranges::RegisterIndex::new(&drive.model);
        let selector = drive
            .model
            .persistence
            .as_ref()
            .and_then(|p| registers.find(&p.selector));
        for name in sequence.given.keys() {
            let is_selector = registers
                .find(name)
                .zip(selector)
                .is_some_and(|(r, s)| std::ptr::eq(r, s));
            if !is_selector {
                error(
                    &format!(".given.{name}"),
                    format!("`{name}` is not the drive's persistence selector"),
                    "a master can be told only the persistence selector's value",
                );
            }
        }
        check_result(sequence, runtime, &mut error);
        if sequence
            .steps
            .first()
            .is_some_and(|s| s.from != Sender::Master)
        {
            error(
                ".steps[0].from",
                "the first frame is the drive's".into(),
                "a sequence starts with the master's frame",
            );
        }
        if sequence.steps.is_empty() {
            error(
                ".steps",
                "a sequence without frames".into(),
                "list every frame on the line, in order",
            );
        }
        // Steps in another variant share one cause (the sequence names no `variant`): the
        // first such step reports it.
        let mut variant_reported = false;
        for (at, step) in sequence.steps.iter().enumerate() {
            let key = format!(".steps[{at}]");
            let bytes = match frame_bytes(&step.ascii, &step.hex) {
                Ok(bytes) => bytes,
                Err(message) => {
                    error(&key, message, "give the frame as `ascii:` or `hex:`");
                    continue;
                }
            };
            if let Err(message) = carried(runtime, step.from, &bytes) {
                let others = if sequence.variant.is_none() {
                    crate::frames::other_variants_where(runtime, |other| {
                        carried(other, step.from, &bytes).is_ok()
                    })
                } else {
                    Vec::new()
                };
                if others.is_empty() {
                    error(
                        &key,
                        message,
                        "a master sends requests and follow-ups, a drive replies",
                    );
                } else if !std::mem::replace(&mut variant_reported, true) {
                    error(
                        &key,
                        format!(
                            "the frame is in variant `{}` of the protocol, not in its first variant{} ({message})",
                            others.join("` or `"),
                            crate::validate::examples_decode::protocol_variant_label(Some(runtime)),
                        ),
                        &format!(
                            "not a manual mistake: state the variant on the sequence, `variant: {}`",
                            others[0]
                        ),
                    );
                }
                continue;
            }
            // The master's requests carry the wait the sequence states (0 when it states none).
            if step.from == Sender::Master {
                if let Ok(request) = runtime.decode_request_exact(&bytes) {
                    let printed = request
                        .values
                        .get(&request.command.request, Role::ReplyWait);
                    let stated = u32::from(sequence.reply_wait.unwrap_or(0));
                    if let Some(printed) = printed.filter(|printed| *printed != stated) {
                        error(
                            &key,
                            format!(
                                "the request's reply-wait field is {printed}, the sequence states {stated}"
                            ),
                            &format!("state the wait the frames print on the sequence: `reply_wait: {printed}`"),
                        );
                    }
                }
            }
        }
    }
}

/// Whether `bytes` is a frame `from` sends in `protocol`; the decoder's reason if not.
fn carried(protocol: &Protocol, from: Sender, bytes: &[u8]) -> Result<(), String> {
    match from {
        Sender::Master => {
            let follow_up = protocol
                .commands
                .iter()
                .filter_map(|c| c.follow_up.as_ref())
                .any(|f| matches!(f.recognise(bytes), Some((_, _, len)) if len == bytes.len()));
            if follow_up {
                return Ok(());
            }
            protocol
                .decode_request_exact(bytes)
                .map(|_| ())
                .map_err(|e| format!("the master's frame is not a request or follow-up: {e}"))
        }
        Sender::Drive => protocol
            .decode_reply_exact(None, bytes)
            .map(|_| ())
            .map_err(|e| format!("the drive's frame is not a reply: {e}")),
    }
}

/// One call: a read, or a write of one value or raw word, of a described register.
fn check_call(
    drive: &Context,
    sequence: &SequenceModel,
    error: &mut impl FnMut(&str, String, &str),
) {
    let call = &sequence.call;
    let registers = ranges::RegisterIndex::new(&drive.model);
    let (key, name) = match (&call.read, &call.write) {
        (Some(name), None) => ("read", name),
        (None, Some(name)) => ("write", name),
        _ => {
            return error(
                ".call",
                "a call reads or writes one register".into(),
                "call: { read: 02-15 } or { write: 02-15, value: 50.0 }",
            )
        }
    };
    if registers.find(name).is_none() {
        error(
            &format!(".call.{key}"),
            format!("no register `{name}`"),
            "name a described register by its code or id",
        );
    }
    let written = call.value.is_some() as u8 + call.raw.is_some() as u8;
    match key {
        "write" if written != 1 => error(
            ".call",
            "a write gives one `value` or one `raw` word".into(),
            "value: in the register's unit (range checked); raw: the word as sent",
        ),
        "read" if written != 0 || call.persistent => error(
            ".call",
            "a read gives no value and is not persistent".into(),
            "leave `value`, `raw` and `persistent` out of a read",
        ),
        _ => {}
    }
}

/// One result, and an error code the protocol's replies carry.
fn check_result(
    sequence: &SequenceModel,
    protocol: &Protocol,
    error: &mut impl FnMut(&str, String, &str),
) {
    let result = &sequence.result;
    let given = result.value.is_some() as u8 + result.written as u8 + result.error.is_some() as u8;
    if given != 1 {
        error(
            ".result",
            "a result is one `value`, `written: true` or one `error`".into(),
            "result: { value: 60.0 }",
        );
    }
    let reads = sequence.call.read.is_some();
    if reads && result.written {
        error(
            ".result.written",
            "a read does not write".into(),
            "a read's result is `value:` (or `error:`)",
        );
    }
    if !reads && result.value.is_some() {
        error(
            ".result.value",
            "a write returns no value".into(),
            "a write's result is `written: true` (or `error:`)",
        );
    }
    if let Some(id) = &result.error {
        if !protocol.error_codes.iter().any(|c| c.id == id.as_str()) {
            let known: Vec<&str> = protocol.error_codes.iter().map(|c| c.id.as_ref()).collect();
            error(
                ".result.error",
                format!("no error code `{id}` in protocol `{}`", sequence.protocol),
                &format!("one of: {}", known.join(", ")),
            );
        }
    }
}
