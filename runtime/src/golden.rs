//! Golden-frame checks as results: what the generated golden tests assert (the
//! `vfd_runtime::testing` module, feature `testing`, panics with these) and what
//! `vfd check` reports before any test runs (the code generator calls them on the
//! protocols it lowers), so the two cannot drift.
//!
//! Each check takes the manual's bytes and what the description says about them, and
//! returns a [`Mismatch`] naming the first difference and, where it can, its cause: the
//! field of the layout whose printed value a re-encode does not give back.

use crate::codec::{self, FrameValues};
use crate::error::hex;
use crate::layout::{FrameLayout, Part, Role};
use crate::meaning::{decode_meaning, Direction, FrameMeaning};
use crate::protocol::{DecodedRequest, NotAnAnswer};
use crate::{DataType, DecodeErrorKind, Protocol, Reply, Request};
use std::fmt;

/// Why a golden check fails: what differs, and the cause when one field explains it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mismatch {
    /// What differs (`the request re-encodes to 45 30 .., not the printed 45 33 ..`).
    pub message: String,
    /// The cause, naming the layout's field (`the printed frame carries 3 in the
    /// reply_wait field `wait`; the example states no value for it, so a re-encode gives
    /// 0`), when the difference is one field's value.
    pub cause: Option<String>,
}

impl Mismatch {
    fn new(message: impl Into<String>) -> Mismatch {
        Mismatch {
            message: message.into(),
            cause: None,
        }
    }
}

impl fmt::Display for Mismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)?;
        if let Some(cause) = &self.cause {
            write!(f, ": {cause}")?;
        }
        Ok(())
    }
}

impl std::error::Error for Mismatch {}

/// What an example states about a request beyond its meaning: values of fields of its
/// layout (`(Role::ReplyWait, 3)`), which a re-encode then uses instead of the protocol's
/// default. Empty: the example states none.
pub type StatedFields<'a> = &'a [(Role, u32)];

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

/// The request an example's meaning describes, as the golden test builds it: the decoded
/// command, register, index, data and process words; nothing else.
pub fn request_from_meaning(decoded: &DecodedRequest<'_>, expect: &FrameMeaning) -> Request {
    let (register, wire_register) = match (expect.register, expect.wire_register) {
        (Some(register), _) => (register, false),
        (None, Some(wire)) => (wire, true),
        (None, None) => (0, false),
    };
    Request {
        kind: decoded.command.kind,
        register,
        space: decoded.command.space,
        wire_register,
        index: expect.index,
        data: expect.data.unwrap_or(0),
        data_type: data_type_of(decoded),
        process: expect.process,
        info: None,
        command: expect.code,
    }
}

/// The request decodes to `expect` (what the generator's decoder read from the manual's
/// bytes), and the same request built from that meaning and the example's `stated` field
/// values encodes to `bytes`.
pub fn request_round_trips(
    protocol: &Protocol,
    bytes: &[u8],
    expect: &FrameMeaning,
    stated: StatedFields<'_>,
) -> Result<(), Mismatch> {
    let meaning = decode_meaning(protocol, Direction::Request, bytes)
        .map_err(|e| Mismatch::new(format!("the request does not decode: {e}")))?;
    if &meaning != expect {
        return Err(Mismatch::new(format!(
            "the request means something else: {meaning:?}, not {expect:?}"
        )));
    }
    let decoded = decoded_request(protocol, bytes)?;
    let request = request_from_meaning(&decoded, expect);
    // A reply-wait digit the meaning states is a stated value like any other.
    let mut stated = stated.to_vec();
    if let Some(wait) = expect.reply_wait {
        if !stated.iter().any(|(role, _)| *role == Role::ReplyWait) {
            stated.push((Role::ReplyWait, wait));
        }
    }
    encodes_like(protocol, &decoded, &request, &stated, bytes)
}

/// A request built through the typed API encodes to the manual's `bytes` (with the
/// manual's command, optional parts, digit counts and process words, and the example's
/// `stated` field values).
pub fn typed_request_encodes(
    protocol: &Protocol,
    request: &Request,
    stated: StatedFields<'_>,
    bytes: &[u8],
) -> Result<(), Mismatch> {
    let decoded = decoded_request(protocol, bytes)?;
    if request.space != decoded.command.space {
        return Err(Mismatch::new(format!(
            "the register is in the {:?} space, the printed command addresses {:?}",
            request.space, decoded.command.space
        )));
    }
    let request = Request {
        process: decoded.process,
        ..*request
    };
    encodes_like(protocol, &decoded, &request, stated, bytes)
}

fn decoded_request<'p>(
    protocol: &'p Protocol,
    bytes: &[u8],
) -> Result<DecodedRequest<'p>, Mismatch> {
    protocol
        .decode_request_exact(bytes)
        .map_err(|e| Mismatch::new(format!("the request does not decode: {e}")))
}

fn encodes_like(
    protocol: &Protocol,
    decoded: &DecodedRequest<'_>,
    request: &Request,
    stated: StatedFields<'_>,
    bytes: &[u8],
) -> Result<(), Mismatch> {
    let address = decoded
        .address
        .or(decoded.broadcast.map(|_| protocol.address_range.0));
    let (layout, mut values) = protocol
        .request_values_for(decoded.command, request, address)
        .map_err(|e| Mismatch::new(format!("cannot build the request: {e}")))?;
    adopt_presentation(layout, &mut values, &decoded.values);
    // A block transfer: the count asked back and the words written, as the manual's.
    if let Some(count) = decoded.values.get(layout, Role::ReadCount) {
        values.set(layout, Role::ReadCount, count);
    }
    let payload = decoded.words.payload(layout);
    // A broadcast (a read too: the manual may print one) carries its stations' encoding.
    if let (Some(broadcast), Some(field)) = (decoded.broadcast, layout.field(Role::Address)) {
        values.set(
            layout,
            Role::Address,
            crate::broadcast::field_value(field, &broadcast),
        );
    }
    for (role, value) in stated {
        values.set(layout, *role, *value);
    }
    let mut out = [0u8; 256];
    let len = codec::encode_with_payload(layout, &values, &payload, &mut out)
        .map_err(|e| Mismatch::new(format!("cannot encode the request: {e}")))?;
    if &out[..len] == bytes {
        return Ok(());
    }
    Err(Mismatch {
        message: format!(
            "the request re-encodes to {}, not the printed {}",
            hex(&out[..len]),
            hex(bytes)
        ),
        cause: field_cause(layout, &decoded.values, &values, stated),
    })
}

/// The first field whose printed value differs from the one a re-encode used.
fn field_cause(
    layout: &FrameLayout,
    printed: &FrameValues,
    built: &FrameValues,
    stated: StatedFields<'_>,
) -> Option<String> {
    let mut fields = Vec::new();
    for part in layout.parts.iter() {
        match part {
            Part::Field(field) => fields.push((field.role, field.name.as_ref())),
            Part::Word(word) => {
                fields.extend(word.fields.iter().map(|b| (b.role, b.name.as_ref())))
            }
            _ => {}
        }
    }
    fields.into_iter().find_map(|(role, name)| {
        if matches!(role, Role::Text | Role::Words) {
            return None;
        }
        // A field the built request leaves unset goes out as 0.
        let (was, gives) = (printed.get(layout, role)?, built.get(layout, role).unwrap_or(0));
        if was == gives {
            return None;
        }
        let why = if stated.iter().any(|(r, _)| *r == role) {
            "the example states".to_owned()
        } else {
            "the example states no value for it, so".to_owned()
        };
        Some(format!(
            "the printed frame carries {was} in the {} field `{name}`; {why} a re-encode gives {gives}",
            role.as_str()
        ))
    })
}

/// The reply decodes to `expect` and re-encodes to `bytes`.
pub fn reply_round_trips(
    protocol: &Protocol,
    bytes: &[u8],
    expect: &FrameMeaning,
) -> Result<(), Mismatch> {
    let meaning = decode_meaning(protocol, Direction::Reply, bytes)
        .map_err(|e| Mismatch::new(format!("the reply does not decode: {e}")))?;
    if &meaning != expect {
        return Err(Mismatch::new(format!(
            "the reply means something else: {meaning:?}, not {expect:?}"
        )));
    }
    let reply = protocol
        .decode_reply_exact(None, bytes)
        .map_err(|e| Mismatch::new(format!("the reply does not decode: {e}")))?;
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
            if info.is_none() {
                return Err(Mismatch::new(format!(
                    "error code {error} is not in the drive's table"
                )));
            }
            let layout = protocol
                .error_reply
                .as_ref()
                .ok_or_else(|| Mismatch::new("an error reply needs an error layout"))?;
            (layout, values, &[][..])
        }
    };
    let mut out = [0u8; 256];
    let len = codec::encode_with_payload(layout, &values, payload, &mut out)
        .map_err(|e| Mismatch::new(format!("cannot re-encode the reply: {e}")))?;
    if &out[..len] == bytes {
        return Ok(());
    }
    Err(Mismatch::new(format!(
        "the reply re-encodes to {}, not the printed {}",
        hex(&out[..len]),
        hex(bytes)
    )))
}

/// The bytes as printed in the manual are rejected, for the reason the erratum states.
pub fn printed_is_rejected(
    protocol: &Protocol,
    direction: Direction,
    bytes: &[u8],
    reason: DecodeErrorKind,
) -> Result<(), Mismatch> {
    let error = match direction {
        Direction::Request => protocol.decode_request_exact(bytes).err(),
        Direction::Reply => protocol.decode_reply_exact(None, bytes).err(),
    };
    let error = error.ok_or_else(|| {
        Mismatch::new(format!(
            "the misprinted frame {} decodes without error",
            hex(bytes)
        ))
    })?;
    if error.kind() != reason {
        return Err(Mismatch::new(format!(
            "rejected for another reason: {error}"
        )));
    }
    Ok(())
}

/// The reply answers the request, as the master judges a reply it receives
/// ([`Protocol::check_answer`]).
pub fn reply_answers(protocol: &Protocol, request: &[u8], reply: &[u8]) -> Result<(), Mismatch> {
    protocol.check_answer(request, reply).map_err(|why| {
        Mismatch::new(format!(
            "{} does not answer {}: {why}",
            hex(reply),
            hex(request)
        ))
    })
}

/// The reply as printed in the manual decodes on its own, but the master passes it over:
/// it does not answer its request.
pub fn printed_does_not_answer(
    protocol: &Protocol,
    request: &[u8],
    printed: &[u8],
) -> Result<(), Mismatch> {
    if let Err(error) = protocol.decode_reply_exact(None, printed) {
        return Err(Mismatch::new(format!(
            "the misprinted reply does not even decode: {error}"
        )));
    }
    match protocol.check_answer(request, printed) {
        Err(NotAnAnswer::Differs(_)) => Ok(()),
        Err(other) => Err(Mismatch::new(format!(
            "the misprinted reply is refused for another reason: {other}"
        ))),
        Ok(()) => Err(Mismatch::new(format!(
            "the misprinted reply {} answers its request",
            hex(printed)
        ))),
    }
}

/// The frame as printed in the manual decodes, but to something other than what the
/// manual says it means (`expect`).
pub fn printed_means_otherwise(
    protocol: &Protocol,
    direction: Direction,
    printed: &[u8],
    expect: &FrameMeaning,
) -> Result<(), Mismatch> {
    let meaning = decode_meaning(protocol, direction, printed)
        .map_err(|e| Mismatch::new(format!("the misprinted frame does not even decode: {e}")))?;
    if &meaning == expect {
        return Err(Mismatch::new(
            "the misprinted frame means what the manual says",
        ));
    }
    Ok(())
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
        if let Err(mismatch) = self.followed() {
            panic!("{mismatch}");
        }
    }

    /// Whether the master sent exactly the manual's frames, in order, and received all of
    /// the drive's; the first difference if not.
    pub fn followed(&self) -> Result<(), Mismatch> {
        let expected: Vec<String> = self
            .steps
            .iter()
            .filter(|(master, _)| *master)
            .map(|(_, bytes)| hex(bytes))
            .collect();
        let sent: Vec<String> = self.sent.iter().map(|b| hex(b)).collect();
        if sent != expected {
            return Err(Mismatch::new(format!(
                "the master's frames differ from the manual's: it sent [{}], the manual shows [{}]",
                sent.join("], ["),
                expected.join("], [")
            )));
        }
        if self.at != self.steps.len() || !self.pending.is_empty() {
            return Err(Mismatch::new(format!(
                "the drive's frames from step {} on were never asked for",
                self.at + 1
            )));
        }
        Ok(())
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
