//! Golden-frame checks for generated tests (cargo feature `testing`, off by default).
//!
//! `vfd-codegen` turns every example frame of a drive description into a `#[test]` that
//! calls these functions: a manual's bytes decode to what the manual says, re-encode to the
//! same bytes, and a misprinted frame is rejected for the stated reason. A crate that runs
//! generated golden tests enables the feature for its tests only:
//!
//! ```toml
//! [dev-dependencies]
//! vfd-runtime = { version = "0.1", features = ["testing"] }
//! ```
//!
//! The functions panic with a message naming the mismatch, like `assert_eq!`.

use crate::codec::{self, FrameValues};
use crate::layout::{FrameLayout, Part, Role};
use crate::meaning::{decode_meaning, Direction, FrameMeaning};
use crate::protocol::DecodedRequest;
use crate::{DataType, DecodeErrorKind, Protocol, Reply, Request};

/// Copies presentation choices (optional parts present, digits and bytes used) from a
/// decoded frame onto values built from meaning, so both can be compared byte for byte.
fn adopt_presentation(layout: &FrameLayout, built: &mut FrameValues, decoded: &FrameValues) {
    for (index, part) in layout.parts.iter().enumerate() {
        let optional = match part {
            Part::Literal { optional, .. } => *optional,
            Part::Field(field) => field.optional.is_some(),
            Part::Checksum(spec) => spec.optional,
            Part::Word(_) | Part::Length(_) => false,
        };
        if optional {
            built.parts[index].present = decoded.parts[index].present;
        }
        built.parts[index].width = decoded.parts[index].width;
    }
    built.data_size = decoded.data_size;
}

fn data_type_of(decoded: &DecodedRequest<'_>) -> DataType {
    match (decoded.command.data_types.first(), decoded.values.data_size) {
        (_, 4) => DataType::DoubleWord,
        (Some(data_type), _) if decoded.command.data_types.len() == 1 => *data_type,
        _ => DataType::Word,
    }
}

/// The request decodes to `expect` (what the generator's decoder read from the manual's
/// bytes), and the same request built from that meaning encodes to `bytes`.
#[track_caller]
pub fn request_round_trips(protocol: &'static Protocol, bytes: &[u8], expect: &FrameMeaning) {
    let meaning = decode_meaning(protocol, Direction::Request, bytes)
        .unwrap_or_else(|e| panic!("request does not decode: {e}"));
    assert_eq!(&meaning, expect, "the request means something else");
    let decoded = protocol
        .decode_request_exact(bytes)
        .unwrap_or_else(|e| panic!("request does not decode: {e}"));
    let command = decoded.command;
    let (register, wire_register) = match (expect.register, expect.wire_register) {
        (Some(register), _) => (register, false),
        (None, Some(wire)) => (wire, true),
        (None, None) => (0, false),
    };
    let request = Request {
        kind: command.kind,
        register,
        space: command.space,
        wire_register,
        index: expect.index,
        data: expect.data.unwrap_or(0),
        data_type: data_type_of(&decoded),
        process: expect.process,
        info: None,
        command: expect.code,
    };
    encodes_like(protocol, &decoded, &request, expect.reply_wait, bytes);
}

/// A request built through the typed API encodes to the manual's `bytes` (with the
/// manual's command, optional parts, digit counts and process words).
#[track_caller]
pub fn typed_request_encodes(protocol: &'static Protocol, request: &Request, bytes: &[u8]) {
    let decoded = protocol
        .decode_request_exact(bytes)
        .unwrap_or_else(|e| panic!("request does not decode: {e}"));
    assert_eq!(request.space, decoded.command.space, "address space");
    let request = Request {
        process: decoded.process,
        ..*request
    };
    let reply_wait = decoded
        .values
        .get(&decoded.command.request, Role::ReplyWait);
    encodes_like(protocol, &decoded, &request, reply_wait, bytes);
}

#[track_caller]
fn encodes_like(
    protocol: &'static Protocol,
    decoded: &DecodedRequest<'_>,
    request: &Request,
    reply_wait: Option<u32>,
    bytes: &[u8],
) {
    let address = decoded
        .address
        .or(decoded.broadcast.map(|_| protocol.address_range.0));
    let (layout, mut values) = protocol
        .request_values_for(decoded.command, request, address)
        .unwrap_or_else(|e| panic!("cannot build the request: {e}"));
    adopt_presentation(layout, &mut values, &decoded.values);
    // The reply-wait field as the example states it (a master sets it with
    // `Master::with_reply_wait`; the encoder's default is 0).
    if let Some(wait) = reply_wait {
        values.set(layout, Role::ReplyWait, wait);
    }
    // A block transfer: the count asked back and the words written, as the manual's.
    if let Some(count) = decoded.values.get(layout, Role::ReadCount) {
        values.set(layout, Role::ReadCount, count);
    }
    let payload = decoded.words.payload(layout);
    // A broadcast (a read too: the manual may print one) carries its stations' encoding.
    if let (Some(broadcast), Some(field)) = (decoded.broadcast, layout.field(crate::Role::Address))
    {
        values.set(
            layout,
            crate::Role::Address,
            crate::broadcast::field_value(field, &broadcast),
        );
    }
    let mut out = [0u8; 256];
    let len = codec::encode_with_payload(layout, &values, &payload, &mut out)
        .unwrap_or_else(|e| panic!("cannot encode: {e}"));
    assert_eq!(
        crate::error::hex(&out[..len]),
        crate::error::hex(bytes),
        "encoded request differs from the manual"
    );
}

/// The reply decodes to `expect` and re-encodes to `bytes`.
#[track_caller]
pub fn reply_round_trips(protocol: &'static Protocol, bytes: &[u8], expect: &FrameMeaning) {
    let meaning = decode_meaning(protocol, Direction::Reply, bytes)
        .unwrap_or_else(|e| panic!("reply does not decode: {e}"));
    assert_eq!(&meaning, expect, "the reply means something else");
    let reply = protocol
        .decode_reply_exact(None, bytes)
        .unwrap_or_else(|e| panic!("reply does not decode: {e}"));
    let (layout, values, payload) = match reply {
        Reply::Data {
            command,
            text,
            values,
            ..
        } => {
            let text_bytes = text.map(|(start, len)| &bytes[start..start + len]);
            let words = values.bytes(&command.reply, Role::Words, bytes);
            (&command.reply, values, text_bytes.or(words).unwrap_or(&[]))
        }
        Reply::Error {
            error,
            info,
            values,
            ..
        } => {
            assert!(
                info.is_some(),
                "error code {error} is not in the drive's table"
            );
            let layout = protocol
                .error_reply
                .as_ref()
                .expect("an error reply needs an error layout");
            (layout, values, &[][..])
        }
    };
    let mut out = [0u8; 256];
    let len = codec::encode_with_payload(layout, &values, payload, &mut out)
        .unwrap_or_else(|e| panic!("cannot re-encode: {e}"));
    assert_eq!(
        crate::error::hex(&out[..len]),
        crate::error::hex(bytes),
        "re-encoded reply differs"
    );
}

/// The bytes as printed in the manual are rejected, for the reason the erratum states.
#[track_caller]
pub fn printed_is_rejected(
    protocol: &'static Protocol,
    direction: Direction,
    bytes: &[u8],
    reason: DecodeErrorKind,
) {
    let error = match direction {
        Direction::Request => protocol.decode_request_exact(bytes).err(),
        Direction::Reply => protocol.decode_reply_exact(None, bytes).err(),
    };
    let error = error.unwrap_or_else(|| {
        panic!(
            "the misprinted frame {} decodes without error",
            crate::error::hex(bytes)
        )
    });
    assert_eq!(error.kind(), reason, "rejected for another reason: {error}");
}

/// The reply answers the request, as the master judges a reply it receives
/// ([`Protocol::check_answer`]).
#[track_caller]
pub fn reply_answers(protocol: &'static Protocol, request: &[u8], reply: &[u8]) {
    if let Err(why) = protocol.check_answer(request, reply) {
        panic!(
            "{} does not answer {}: {why}",
            crate::error::hex(reply),
            crate::error::hex(request)
        );
    }
}

/// The reply as printed in the manual decodes on its own, but the master passes it over:
/// it does not answer its request.
#[track_caller]
pub fn printed_does_not_answer(protocol: &'static Protocol, request: &[u8], printed: &[u8]) {
    if let Err(error) = protocol.decode_reply_exact(None, printed) {
        panic!("the misprinted reply does not even decode: {error}");
    }
    match protocol.check_answer(request, printed) {
        Err(crate::protocol::NotAnAnswer::Differs(_)) => {}
        Err(other) => panic!("the misprinted reply is refused for another reason: {other}"),
        Ok(()) => panic!(
            "the misprinted reply {} answers its request",
            crate::error::hex(printed)
        ),
    }
}

/// The frame as printed in the manual decodes, but to something other than what the
/// manual says it means (`expect`): a letter case that contradicts the stated state, for
/// example.
#[track_caller]
pub fn printed_means_otherwise(
    protocol: &'static Protocol,
    direction: Direction,
    printed: &[u8],
    expect: &FrameMeaning,
) {
    let meaning = decode_meaning(protocol, direction, printed)
        .unwrap_or_else(|e| panic!("the misprinted frame does not even decode: {e}"));
    assert_ne!(
        &meaning, expect,
        "the misprinted frame means what the manual says"
    );
}

/// A request the manual prints as one the drive does not answer: the decoder refuses it
/// for `reason`, and the drive's virtual drive stays silent.
#[track_caller]
pub fn drive_ignores(
    drive: &'static crate::DriveInfo,
    protocol: &'static Protocol,
    bytes: &[u8],
    reason: DecodeErrorKind,
) {
    printed_is_rejected(protocol, Direction::Request, bytes, reason);
    let mut virtual_drive = crate::virtual_drive::VirtualDrive::new(drive);
    let outcome = virtual_drive.respond(protocol, bytes);
    assert!(
        matches!(outcome, crate::virtual_drive::Outcome::Silent(_)),
        "the virtual drive answers {}: {outcome:?}",
        crate::error::hex(bytes)
    );
}

/// The drive's side of a manual's multi-step example, as a transport: every frame the
/// master sends moves the script past the master's step, and the drive's frames that
/// follow it are then received. [`Script::assert_followed`] compares what the master sent
/// with the manual's frames.
#[derive(Debug)]
pub struct Script {
    /// The manual's frames in order: `true` for the master's, `false` for the drive's.
    steps: Vec<(bool, Vec<u8>)>,
    /// The next step.
    at: usize,
    /// The drive's bytes not yet received.
    pending: std::collections::VecDeque<u8>,
    /// What the master sent, frame by frame.
    sent: Vec<Vec<u8>>,
}

impl Script {
    /// A script of `steps`: `(true, bytes)` for the master's frames, `(false, bytes)` for
    /// the drive's, in the manual's order.
    pub fn new(steps: &[(bool, &[u8])]) -> Script {
        Script {
            steps: steps
                .iter()
                .map(|(master, bytes)| (*master, bytes.to_vec()))
                .collect(),
            at: 0,
            pending: std::collections::VecDeque::new(),
            sent: Vec::new(),
        }
    }

    /// Panics unless the master sent exactly the manual's frames, in order, and received
    /// all of the drive's.
    #[track_caller]
    pub fn assert_followed(&self) {
        let expected: Vec<String> = self
            .steps
            .iter()
            .filter(|(master, _)| *master)
            .map(|(_, bytes)| crate::error::hex(bytes))
            .collect();
        let sent: Vec<String> = self.sent.iter().map(|b| crate::error::hex(b)).collect();
        assert_eq!(
            sent, expected,
            "the master's frames differ from the manual's"
        );
        assert!(
            self.at == self.steps.len() && self.pending.is_empty(),
            "the drive's frames from step {} on were never asked for",
            self.at + 1
        );
    }
}

impl crate::transport::Transport for Script {
    fn send(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.sent.push(bytes.to_vec());
        if self.steps.get(self.at).is_some_and(|(master, _)| *master) {
            self.at += 1;
        }
        while let Some((false, reply)) = self.steps.get(self.at) {
            self.pending.extend(reply);
            self.at += 1;
        }
        Ok(())
    }

    fn receive(&mut self, buf: &mut [u8], _deadline: std::time::Instant) -> std::io::Result<usize> {
        let n = buf.len().min(self.pending.len());
        for (slot, byte) in buf.iter_mut().zip(self.pending.drain(..n)) {
            *slot = byte;
        }
        Ok(n)
    }
}

/// Panics unless `error` is the drive's refusal with error code `code`.
#[track_caller]
pub fn refused_with(error: &crate::TransactionError, code: u16) {
    match &error.kind {
        crate::TransactionErrorKind::Rejected { code: got, .. } => {
            assert_eq!(*got, code, "refused with another code: {error}")
        }
        _ => panic!("expected the drive's refusal {code:02X}h, got: {error}"),
    }
}
