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
    /// The register a request's page offset reaches on the page its example names
    /// (`examples[].page`); the decoder alone leaves a paged offset unnamed.
    pub page_register: Option<u16>,
    /// A request whose register field is an offset on a page (`None`: not one, or not a
    /// request): the page its example names, if any. Which register the offset is depends
    /// on it: without a page that is one of the protocol's, the frame names none.
    pub paged: Option<Option<u16>>,
}

impl DecodedFrame {
    /// The meaning, when the frame decoded.
    pub fn decoded(&self) -> Option<&FrameMeaning> {
        self.meaning.as_ref().and_then(|m| m.as_ref().ok())
    }

    /// The meaning as the example states it: a paged offset named as the register it
    /// reaches on the example's page. The golden checks compare the decoder's own
    /// meaning ([`DecodedFrame::decoded`]).
    ///
    /// Whether the register it names follows from a page that is missing or names no
    /// register there ([`DecodedFrame::paged`]): then `paged_examples_name_their_place`
    /// reports the page, and the register is no further mistake.
    pub fn register_unknown_for_its_page(&self) -> bool {
        self.paged.is_some() && self.page_register.is_none()
    }

    pub fn as_stated(&self) -> Option<std::borrow::Cow<'_, FrameMeaning>> {
        self.decoded()?;
        let meaning = self.decoded()?;
        Some(match self.page_register {
            Some(register) if meaning.register.is_none() => std::borrow::Cow::Owned(FrameMeaning {
                register: Some(register),
                ..meaning.clone()
            }),
            _ => std::borrow::Cow::Borrowed(meaning),
        })
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
                page_register: None,
                paged: None,
            }
        })
    };
    let mut request = frame(Direction::Request, &example.request);
    let reply = frame(Direction::Reply, &example.reply);
    // On the page the example names, the request's offset is a register.
    if let (Some(page), Some(runtime), Some(request)) = (example.page, runtime, request.as_mut()) {
        if let Ok(bytes) = &request.bytes {
            request.page_register = register_on_page(runtime, bytes, page);
        }
    }
    if let (Some(runtime), Some(request)) = (runtime, request.as_mut()) {
        if let Ok(bytes) = &request.bytes {
            request.paged = page_offset(runtime, bytes).map(|_| example.page);
        }
    }
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

/// The register a request reaches on `page` of its protocol's pages: its register field,
/// the command's address map undone, as an offset on the page ([`page_offset`]). `None`
/// when it is no offset, or no range lays a register there.
pub(crate) fn register_on_page(
    protocol: &vfd_runtime::Protocol,
    request: &[u8],
    page: u16,
) -> Option<u16> {
    let offset = page_offset(protocol, request)?;
    protocol.paging.as_ref()?.register(page, offset)
}

/// The offset on a page a request's register field carries (the command's address map
/// undone): `None` when the protocol has no pages, the request does not decode, or its
/// field is a register's own number (`wire_numbers`) or the page register's.
pub(crate) fn page_offset(protocol: &vfd_runtime::Protocol, request: &[u8]) -> Option<u16> {
    let paging = protocol.paging.as_ref()?;
    let decoded = protocol.decode_request_exact(request).ok()?;
    if decoded.register.is_some() {
        return None; // a register's own number
    }
    let wire = decoded.wire_register?;
    let command = decoded.command;
    let select = if command.kind.is_write() {
        Some(paging.select_write)
    } else {
        paging.select_read
    };
    if select == Some(wire) {
        return None;
    }
    command.address_map.from_wire(wire)
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
