//! Stage 3: decodes every example frame of a drive exactly once, with the runtime's own
//! decoder ([`vfd_runtime::meaning::decode_meaning`]).
//!
//! Validation checks these results against what the description says (`expect:`,
//! `printed_rejected_as:`); the IR reads the same results. Nothing decodes a frame again.

use crate::parse::model::{BytesModel, DriveFile, ExampleModel, FrameModel, RegisterModel};
use crate::protocols::LoweredProtocol;
use vfd_runtime::layout::Role;
use vfd_runtime::meaning::{decode_meaning, Direction, FrameMeaning};
use vfd_runtime::protocol::NotAnAnswer;
use vfd_runtime::{DecodeError, Space};

/// One example's frames, decoded.
#[derive(Debug, Clone)]
pub(crate) struct DecodedExample {
    /// Index of the example's protocol among the drive's lowered protocols; `None` when the
    /// protocol is unknown or failed to lower (both reported elsewhere).
    pub protocol: Option<usize>,
    /// The request frame, when the example has one.
    pub request: Option<DecodedFrame>,
    /// The reply frame, when the example has one.
    pub reply: Option<DecodedFrame>,
    /// Whether the reply answers the request, as the master judges it; `None` unless both
    /// frames have bytes and the protocol is known.
    pub answers: Option<Result<(), NotAnAnswer>>,
    /// The same for the manual's misprinted reply, when the example records one.
    pub printed_answers: Option<Result<(), NotAnAnswer>>,
    /// A request the drive does not answer (`unanswered_request`), decoded.
    pub unanswered: Option<PrintedFrame>,
    /// Values the example states for fields of its request's layout beyond its meaning
    /// (see [`stated_fields`]): the golden checks re-encode the request with them.
    pub stated: Vec<(Role, u32)>,
}

impl DecodedExample {
    /// The frames that are present, reply first (the value an example states belongs to the
    /// reply's data when the reply carries data).
    pub fn reply_then_request(&self) -> impl Iterator<Item = &DecodedFrame> {
        self.reply.iter().chain(self.request.iter())
    }
}

/// One frame: its bytes and what they decode to.
#[derive(Debug, Clone)]
pub(crate) struct DecodedFrame {
    /// The bytes, or why the description gives none.
    pub bytes: Result<Vec<u8>, String>,
    /// What the bytes mean; `None` when there are no bytes or no protocol to decode with.
    pub meaning: Option<Result<FrameMeaning, DecodeError>>,
    /// The manual's misprinted bytes, when the description records an erratum.
    pub printed: Option<PrintedFrame>,
}

impl DecodedFrame {
    /// The meaning, when the frame decoded.
    pub fn decoded(&self) -> Option<&FrameMeaning> {
        self.meaning.as_ref().and_then(|m| m.as_ref().ok())
    }
}

/// The bytes a manual printed for a frame it got wrong, and how the decoder takes them.
#[derive(Debug, Clone)]
pub(crate) struct PrintedFrame {
    /// The printed bytes, or why the description gives none.
    pub bytes: Result<Vec<u8>, String>,
    /// What the decoder says about them; `None` when there are no bytes or no protocol.
    pub meaning: Option<Result<FrameMeaning, DecodeError>>,
}

/// Decodes every example frame of `drive` once.
pub(crate) fn decode_examples(
    drive: &DriveFile,
    protocols: &[LoweredProtocol],
) -> Vec<DecodedExample> {
    drive
        .examples
        .iter()
        .map(|example| decode_example(example, protocols))
        .collect()
}

fn decode_example(example: &ExampleModel, protocols: &[LoweredProtocol]) -> DecodedExample {
    let protocol = protocols.iter().position(|p| p.id == example.protocol);
    // In a named variant, the frames decode in that variant's bytes; an unknown variant
    // leaves nothing to decode with (reported by validation).
    let in_variant = match (protocol, &example.variant) {
        (Some(index), Some(variant)) => Some(in_variant(&protocols[index].runtime, variant)),
        _ => None,
    };
    let runtime = match &in_variant {
        Some(found) => found.as_ref(),
        None => protocol.map(|index| &protocols[index].runtime),
    };
    let frame = |direction: Direction, model: &Option<FrameModel>| {
        model.as_ref().map(|model| {
            let bytes = frame_bytes(&model.ascii, &model.hex);
            let decode = |bytes: &Result<Vec<u8>, String>| match (bytes, runtime) {
                (Ok(bytes), Some(runtime)) => Some(decode_meaning(runtime, direction, bytes)),
                _ => None,
            };
            let printed = model.printed.as_ref().map(|BytesModel { ascii, hex }| {
                let bytes = frame_bytes(ascii, hex);
                PrintedFrame {
                    meaning: decode(&bytes),
                    bytes,
                }
            });
            DecodedFrame {
                meaning: decode(&bytes),
                bytes,
                printed,
            }
        })
    };
    let request = frame(Direction::Request, &example.request);
    let reply = frame(Direction::Reply, &example.reply);
    let request_bytes = request.as_ref().and_then(|r| r.bytes.as_ref().ok());
    let answer = |reply: Option<&Result<Vec<u8>, String>>| match (runtime, request_bytes, reply) {
        (Some(runtime), Some(request), Some(Ok(reply))) => {
            Some(runtime.check_answer(request, reply))
        }
        _ => None,
    };
    let unanswered = example.unanswered_request.as_ref().map(|model| {
        let bytes = frame_bytes(&model.ascii, &model.hex);
        PrintedFrame {
            meaning: match (&bytes, runtime) {
                (Ok(bytes), Some(runtime)) => {
                    Some(decode_meaning(runtime, Direction::Request, bytes))
                }
                _ => None,
            },
            bytes,
        }
    });
    DecodedExample {
        protocol,
        unanswered,
        answers: answer(reply.as_ref().map(|r| &r.bytes)),
        printed_answers: answer(
            reply
                .as_ref()
                .and_then(|r| r.printed.as_ref())
                .map(|p| &p.bytes),
        ),
        stated: stated_fields(request.as_ref().and_then(DecodedFrame::decoded)),
        request,
        reply,
    }
}

/// The values an example states for fields of its request's layout beyond its meaning
/// (a reply-wait digit): the re-encode of `vfd check` takes them from here, and the golden
/// tests (`emit/tests.rs`) state the same value, the reply wait of the request's meaning.
pub(crate) fn stated_fields(
    request: Option<&vfd_runtime::meaning::FrameMeaning>,
) -> Vec<(Role, u32)> {
    request
        .and_then(|meaning| meaning.reply_wait)
        .map(|wait| vec![(Role::ReplyWait, wait)])
        .unwrap_or_default()
}

/// The command a golden test builds through a register's typed API for an example's
/// request of `kind` (`None`: it builds none): a RAM write of a writable register, a
/// persistent write of a persistable one, a read. `vfd check` (validate) and the emitted
/// golden tests both decide with this.
pub(crate) fn typed_request_kind(
    kind: Option<vfd_runtime::CommandKind>,
    writable: bool,
    persistable: bool,
) -> Option<vfd_runtime::CommandKind> {
    use vfd_runtime::CommandKind;
    match kind? {
        CommandKind::WriteRam if writable => Some(CommandKind::WriteRam),
        CommandKind::WritePersistent if persistable => Some(CommandKind::WritePersistent),
        CommandKind::Read => Some(CommandKind::Read),
        _ => None,
    }
}

/// `protocol` in its variant called `id`, if it has one.
pub(crate) fn in_variant(
    protocol: &vfd_runtime::Protocol,
    id: &str,
) -> Option<vfd_runtime::Protocol> {
    let index = protocol.variants.as_ref()?.index_of(id)?;
    protocol.in_variant(index)
}

/// The ids of the variants `protocol` has, other than the one it is in, in which `bytes`
/// decode going in `direction`.
pub(crate) fn other_variants_decoding(
    protocol: &vfd_runtime::Protocol,
    direction: Direction,
    bytes: &[u8],
) -> Vec<String> {
    other_variants_where(protocol, |other| {
        decode_meaning(other, direction, bytes).is_ok()
    })
}

/// The ids of the variants `protocol` has, other than the one it is in, for which
/// `accepts` holds.
pub(crate) fn other_variants_where(
    protocol: &vfd_runtime::Protocol,
    accepts: impl Fn(&vfd_runtime::Protocol) -> bool,
) -> Vec<String> {
    let Some(variants) = protocol.variants.as_ref() else {
        return Vec::new();
    };
    (0..variants.choices.len())
        .filter(|index| *index != usize::from(variants.current))
        .filter_map(|index| protocol.in_variant(index))
        .filter(|other| accepts(other))
        .filter_map(|other| other.variants.as_ref()?.current().map(|v| v.id.to_string()))
        .collect()
}

/// The bytes a frame holds (`ascii:` text or `hex:` pairs), or a message saying why there
/// are none.
pub(crate) fn frame_bytes(ascii: &Option<String>, hex: &Option<String>) -> Result<Vec<u8>, String> {
    match (ascii, hex) {
        (Some(text), None) => Ok(text.as_bytes().to_vec()),
        (None, Some(hex)) => crate::protocols::parse_hex(hex),
        _ => Err("give exactly one of `ascii` and `hex`".to_owned()),
    }
}

/// The described register a frame's data belongs to: of two sharing the address (one
/// read-only, one write-only), the one the frame's direction reaches.
pub(crate) fn register_of<'d>(
    drive: &'d DriveFile,
    meaning: &FrameMeaning,
) -> Option<&'d RegisterModel> {
    let address = u32::from(meaning.register?);
    let space = meaning.space.unwrap_or(Space::Parameter);
    let blocked = match meaning.kind {
        Some(kind) if kind.is_write() => Some(vfd_runtime::Access::ReadOnly),
        Some(_) => Some(vfd_runtime::Access::WriteOnly),
        None => None,
    };
    let at = |r: &&RegisterModel| r.address == address && space_of(r) == space;
    drive
        .registers
        .iter()
        .filter(at)
        .find(|r| blocked.is_none() || r.access != blocked)
        .or_else(|| drive.registers.iter().find(at))
}

/// A register's address space.
pub(crate) fn space_of(register: &RegisterModel) -> Space {
    register.space.unwrap_or(Space::Parameter)
}
