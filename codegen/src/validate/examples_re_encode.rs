//! Check: every example frame re-encodes to its printed bytes the way its golden test
//! re-encodes it (the same `vfd_runtime::golden` functions): a request from its meaning,
//! and through the typed API when the example names a value; a reply from its decoded
//! values.

use crate::diagnostics::Diagnostics;
use crate::frames::{register_of, space_of, typed_request_kind, DecodedFrame};
use crate::validate::Context;
use vfd_runtime::golden::{self, Mismatch};
use vfd_runtime::{Access, CommandKind, DataType, Protocol, Request};

/// What the golden test rebuilds from an example's meaning: the command, register, index,
/// data and the example's stated field values; every other field of the layout takes the
/// protocol's default.
const REBUILT: &str = "the golden test builds the request from the example's meaning (command, register, index, data, process words) and the protocol's defaults for every other field of the layout";

/// Every decoded example frame re-encodes to the printed bytes.
pub fn examples_re_encode(drive: &Context, out: &mut Diagnostics) {
    for (index, (example, decoded)) in drive.model.examples.iter().zip(&drive.frames).enumerate() {
        let Some(lowered) = decoded.protocol.map(|at| &drive.protocols[at].runtime) else {
            continue;
        };
        // In a named variant, the golden test re-encodes in that variant's bytes.
        let in_variant = example
            .variant
            .as_deref()
            .and_then(|id| crate::frames::in_variant(lowered, id));
        let protocol = in_variant.as_ref().unwrap_or(lowered);
        let stated = &decoded.stated;
        let base = format!("examples[{index}]");
        let mut report = |key: &str, mismatch: Mismatch, tail: &str| {
            let hint = match &mismatch.cause {
                Some(cause) => format!("{cause}; {tail}"),
                None => tail.to_owned(),
            };
            out.push(
                drive
                    .source
                    .error(
                        &format!("{base}.{key}"),
                        format!("its golden test would fail: {}", mismatch.message),
                    )
                    .hint(hint),
            );
        };
        if let Some((bytes, meaning)) = decoded.request.as_ref().and_then(parts) {
            let result = golden::request_round_trips(protocol, bytes, meaning, stated);
            match result {
                Err(mismatch) => report("request", mismatch, REBUILT),
                Ok(()) if example.value.is_some() => {
                    let typed = typed_request(drive, decoded, protocol, bytes);
                    if let Some(Err(mismatch)) = typed.map(|request| {
                        golden::typed_request_encodes(protocol, &request, stated, bytes)
                    }) {
                        report("request", mismatch, "the golden test builds this request through the register's typed API (its address, space, data type and the protocol's first command of the kind), which must give the printed frame");
                    }
                }
                Ok(()) => {}
            }
        }
        if let Some((bytes, meaning)) = decoded.reply.as_ref().and_then(parts) {
            if let Err(mismatch) = golden::reply_round_trips(protocol, bytes, meaning) {
                report(
                    "reply",
                    mismatch,
                    "the golden test re-encodes the reply from its decoded values; check the bytes against the manual",
                );
            }
        }
    }
}

/// The bytes and meaning of a frame that decoded (others are reported elsewhere).
fn parts(frame: &DecodedFrame) -> Option<(&[u8], &vfd_runtime::meaning::FrameMeaning)> {
    Some((frame.bytes.as_deref().ok()?, frame.decoded()?))
}

/// The request the golden test builds through the typed API for an example stating a
/// value (as `emit/tests.rs` writes it), or `None` where it builds none.
fn typed_request(
    drive: &Context,
    decoded: &crate::frames::DecodedExample,
    protocol: &Protocol,
    bytes: &[u8],
) -> Option<Request> {
    // As the emitter names it (a paged offset as the register it reaches on its page).
    let register = decoded
        .reply_then_request()
        .filter_map(DecodedFrame::as_stated)
        .find_map(|meaning| register_of(&drive.model, &meaning))?;
    let meaning = decoded.request.as_ref()?.decoded()?;
    let data_type = register.data_type.unwrap_or(DataType::Word);
    let writable = register.access != Some(Access::ReadOnly) && data_type != DataType::Text;
    let kind = match typed_request_kind(meaning.kind, writable, writable && !register.ram_only)? {
        // `Request::read` reads text with its own command.
        CommandKind::Read if data_type == DataType::Text => CommandKind::ReadText,
        kind => kind,
    };
    let data = match kind {
        CommandKind::WriteRam | CommandKind::WritePersistent => decoded
            .reply
            .as_ref()
            .and_then(DecodedFrame::decoded)
            .and_then(|m| m.data)
            .or(meaning.data)
            .unwrap_or(0),
        _ => 0,
    };
    let index = match meaning.index {
        Some(index) if index > 0 || register.array.unwrap_or(0) > 0 => Some(index),
        _ => None,
    };
    // An extra command (a second read) is reached only by naming its code.
    let command = protocol
        .decode_request_exact(bytes)
        .ok()
        .filter(|request| request.command.extra && request.command.kind == kind)
        .map(|request| request.code());
    Some(Request {
        kind,
        register: u16::try_from(register.address).ok()?,
        space: space_of(register),
        wire_register: false,
        index,
        data,
        data_type,
        process: None,
        info: None,
        command,
    })
}

#[cfg(test)]
mod tests {
    use super::examples_re_encode as check;
    use crate::validate::testing::{check_yaml, valid_with, VALID};

    #[test]
    fn the_valid_drives_example_re_encodes() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn a_written_value_re_encodes_through_the_typed_api() {
        let yaml = valid_with(&[
            ("(R0011)\\r", "(W00111F40)\\r"),
            (
                "expect: { command: R, register: 0x0011 } }",
                "expect: { command: W, register: 0x0011, data: 0x1F40 } }",
            ),
            ("(R00111F40)\\r", "(W00111F40)\\r"),
            (
                "command: R, register: 0x0011, data",
                "command: W, register: 0x0011, data",
            ),
        ]);
        let found = check_yaml(check, &yaml);
        assert!(found.is_empty(), "{found:#?}");
    }
}
