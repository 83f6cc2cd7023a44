//! What a whole frame means, in protocol-neutral terms: the one record that the generator's
//! example checks, the golden-frame tests and the command-line decoder all compare.
//!
//! [`decode_meaning`] runs the protocol's own decoder ([`Protocol::decode_request_exact`] or
//! [`Protocol::decode_reply_exact`]) and keeps only what a manual states about a frame:
//! station, command code, register, index, data, error code, process words, text and the
//! tripped flag. Fields a frame does not carry are `None`.

use crate::error::DecodeError;
use crate::kinds::{CommandKind, Space};
use crate::layout::Role;
use crate::protocol::{Protocol, Reply};

/// Whether a frame goes from master to drive or back.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Direction {
    /// Master to drive.
    Request,
    /// Drive to master.
    Reply,
}

impl Direction {
    /// `request` or `reply`, as description files and messages write it.
    pub const fn as_str(self) -> &'static str {
        match self {
            Direction::Request => "request",
            Direction::Reply => "reply",
        }
    }
}

/// What a frame says, field by field (`None`: the frame does not carry it).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FrameMeaning {
    /// Station address.
    pub address: Option<u8>,
    /// The stations a broadcast request addresses (`all`, or a group such as `*9`).
    #[cfg_attr(
        feature = "serde",
        serde(skip_serializing_if = "Option::is_none", serialize_with = "shown")
    )]
    pub broadcast: Option<crate::broadcast::Broadcast>,
    /// Command code as on the wire (the letter in its case, the AK nibble, the function code).
    pub code: Option<u32>,
    /// Kind of the command the frame belongs to (absent for error replies).
    pub kind: Option<CommandKind>,
    /// Address space of that command.
    pub space: Option<Space>,
    /// Register number after undoing the command's address map.
    pub register: Option<u16>,
    /// Register number on the wire.
    pub wire_register: Option<u16>,
    /// Array index.
    pub index: Option<u16>,
    /// Data word or double word.
    pub data: Option<u32>,
    /// Error code of an error reply.
    pub error_code: Option<u16>,
    /// Process words (control word and reference out; status word and output value back).
    pub process: Option<[u16; 2]>,
    /// Text carried by a text reply.
    pub text: Option<String>,
    /// The words of a words field (a block transfer's words written or read).
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub words: Option<Vec<u16>>,
    /// How many words a block-transfer request asks back.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub read_count: Option<u32>,
    /// A block-transfer reply's write status (bit `n`: word `n` not written).
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub write_status: Option<u32>,
    /// The value of a request's reply-wait field (the Eaton-style wait digit: tens of
    /// milliseconds the drive waits before it answers), where its layout has one.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub reply_wait: Option<u32>,
    /// The drive answered with a lower-case command: it is tripped. In a request: the
    /// sender says it has tripped (a command whose lower case means so, see
    /// [`crate::protocol::CommandSpec::lowercase_means_sender_tripped`]).
    pub tripped: bool,
}

/// Decodes exactly one whole frame going in `direction` and says what it means.
pub fn decode_meaning(
    protocol: &Protocol,
    direction: Direction,
    bytes: &[u8],
) -> Result<FrameMeaning, DecodeError> {
    match direction {
        Direction::Request => {
            let request = protocol.decode_request_exact(bytes)?;
            let command = request.command;
            Ok(FrameMeaning {
                address: request.address,
                broadcast: request.broadcast,
                code: command.request.has(Role::Command).then(|| request.code()),
                kind: Some(command.kind),
                space: Some(command.space),
                register: request.register,
                wire_register: request.wire_register,
                index: request.index,
                data: command.request.has(Role::Data).then_some(request.data),
                error_code: None,
                process: request.process,
                text: None,
                words: command
                    .request
                    .has(Role::Words)
                    .then(|| request.words.as_slice().to_vec()),
                read_count: request.values.get(&command.request, Role::ReadCount),
                write_status: None,
                reply_wait: request.values.get(&command.request, Role::ReplyWait),
                tripped: request.sender_tripped(),
            })
        }
        Direction::Reply => match protocol.decode_reply_exact(None, bytes)? {
            Reply::Data {
                command,
                code,
                address,
                tripped,
                wire_register,
                index,
                data,
                process,
                text,
                values,
                ..
            } => Ok(FrameMeaning {
                address,
                broadcast: None,
                code: command.reply.has(Role::Command).then_some(code),
                kind: Some(command.kind),
                space: Some(command.space),
                register: wire_register
                    .and_then(|wire| protocol.from_wire(command, wire, Some(data))),
                wire_register,
                index,
                data: command.reply.has(Role::Data).then_some(data),
                error_code: None,
                process,
                text: text.map(|(start, len)| {
                    String::from_utf8_lossy(&bytes[start..start + len]).into_owned()
                }),
                words: command
                    .reply
                    .has(Role::Words)
                    .then(|| values.words(&command.reply, bytes).as_slice().to_vec()),
                read_count: values.get(&command.reply, Role::ReadCount),
                write_status: values.get(&command.reply, Role::WriteStatus),
                reply_wait: None,
                tripped,
            }),
            Reply::Error {
                address,
                tripped,
                code,
                error,
                ..
            } => Ok(FrameMeaning {
                address,
                code: Some(code),
                error_code: Some(error),
                tripped,
                ..FrameMeaning::default()
            }),
        },
    }
}

/// A broadcast as written (`all`, `*9`).
#[cfg(feature = "serde")]
fn shown<S: serde::Serializer>(
    broadcast: &Option<crate::broadcast::Broadcast>,
    serializer: S,
) -> Result<S::Ok, S::Error> {
    match broadcast {
        Some(broadcast) => serializer.serialize_some(&broadcast.to_string()),
        None => serializer.serialize_none(),
    }
}
