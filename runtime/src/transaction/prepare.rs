//! Requests become bytes: [`prepare`] turns what to send ([`Exchange`]) into a
//! [`Prepared`] frame with everything needed to judge its reply, with one command lookup
//! and one encoding, and no I/O. `vfd encode`, the masters and the tests share it.

use super::exchange::{Exchange, ExchangeKind};
use crate::codec;
use crate::error::EncodeError;
use crate::layout::{Encoding, Format, FrameLayout, Role};
use crate::protocol::{CommandSpec, Expectation, Protocol};
use crate::register::Request;

/// Largest frame the master buffers; longer noise is dropped from the front.
pub const MAX_FRAME: usize = 256;

/// The station side of an exchange: who the frame goes to and what the master asks of the
/// drive besides.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Station {
    /// The station addressed (`None`: no address, where the protocol lets it out). For a
    /// broadcast, the station whose reply is awaited.
    pub address: Option<u8>,
    /// The wait the drive is asked to make before replying, in tens of milliseconds, in
    /// requests whose layout carries one ([`Role::ReplyWait`]); 0: none asked.
    pub reply_wait: u8,
}

/// A frame's bytes, held without allocation.
#[derive(Clone, Copy)]
pub struct FrameBytes {
    bytes: [u8; MAX_FRAME],
    len: usize,
}

impl FrameBytes {
    /// No bytes yet.
    pub const EMPTY: FrameBytes = FrameBytes {
        bytes: [0; MAX_FRAME],
        len: 0,
    };

    /// The frame.
    pub fn as_slice(&self) -> &[u8] {
        &self.bytes[..self.len]
    }

    /// Fills the frame with what `encode` writes (returning its length).
    fn fill(
        encode: impl FnOnce(&mut [u8]) -> Result<usize, EncodeError>,
    ) -> Result<FrameBytes, EncodeError> {
        let mut frame = FrameBytes::EMPTY;
        frame.len = encode(&mut frame.bytes)?;
        Ok(frame)
    }
}

impl std::fmt::Debug for FrameBytes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&crate::error::hex(self.as_slice()))
    }
}

/// A frame ready for the line, and what its reply must be.
#[derive(Debug, Clone, Copy)]
pub struct Prepared {
    frame: FrameBytes,
    request: Request,
    command: &'static CommandSpec,
    expectation: Expectation,
    block_size: usize,
    answered: bool,
    shortest_reply: usize,
    shortest_own_reply: usize,
    follow_up: Option<FollowUpFrames>,
}

/// The frames a command's follow-up sends (see [`crate::protocol::FollowUp`]): the
/// acknowledgement of a sound reply, and the request to send the last reply again.
#[derive(Debug, Clone, Copy)]
pub struct FollowUpFrames {
    /// Sent after a sound reply; nothing comes back.
    pub sound: FrameBytes,
    /// Sent in place of the request after a garbled reply: the drive repeats its reply.
    pub again: FrameBytes,
}

impl Prepared {
    /// The frame's bytes.
    pub fn bytes(&self) -> &[u8] {
        self.frame.as_slice()
    }

    /// The request the frame carries.
    pub fn request(&self) -> &Request {
        &self.request
    }

    /// The command that carries it.
    pub fn command(&self) -> &'static CommandSpec {
        self.command
    }

    /// What a reply must say to answer it (station, wire register, index, the value a write
    /// reports, the data size a read asked for).
    pub fn expectation(&self) -> &Expectation {
        &self.expectation
    }

    /// Bytes of data a block read expects (0: not a block read).
    pub fn block_size(&self) -> usize {
        self.block_size
    }

    /// Whether a reply comes: `false` for a command with `reply: none`, a write of a
    /// register with `no_reply: true` and a broadcast no station answers. Such a request is
    /// done once its frame is on the line.
    pub fn answered(&self) -> bool {
        self.answered
    }

    /// Whether the request only reads, so that sending it again after a failed exchange
    /// changes nothing in the drive.
    pub fn repeatable(&self) -> bool {
        self.request.kind.only_reads()
    }

    /// The fewest bytes any answer can have: the command's reply or the protocol's error
    /// reply, whichever can be shorter.
    pub fn shortest_reply(&self) -> usize {
        self.shortest_reply
    }

    /// The fewest bytes the command's own reply can have, with the data the request asked
    /// for (a Modbus 03 reply to a read of one word holds 2).
    pub fn shortest_own_reply(&self) -> usize {
        self.shortest_own_reply
    }

    /// The follow-up frames, where the command has a follow-up.
    pub fn follow_up(&self) -> Option<&FollowUpFrames> {
        self.follow_up.as_ref()
    }

    /// The same frame without a reply to wait for (a broadcast no station answers).
    pub fn unanswered(self) -> Prepared {
        Prepared {
            answered: false,
            ..self
        }
    }
}

/// Turns `exchange` for `station` into the frame to send and the reply it expects: one
/// command lookup, one encoding. Fails, before anything could be sent, when the protocol
/// cannot carry it.
pub fn prepare(
    protocol: &'static Protocol,
    exchange: &Exchange,
    station: &Station,
) -> Result<Prepared, EncodeError> {
    let request = &exchange.request;
    let command = protocol.command_for_request(request)?;
    let address = station.address;
    let frame = match exchange.kind {
        ExchangeKind::Single if station.reply_wait > 0 && command.request.has(Role::ReplyWait) => {
            // The wait the master asks for, in the request's wait field.
            let (layout, mut values) = protocol.request_values_for(command, request, address)?;
            values.set(layout, Role::ReplyWait, u32::from(station.reply_wait));
            FrameBytes::fill(|out| codec::encode(layout, &values, out))?
        }
        ExchangeKind::Single => {
            FrameBytes::fill(|out| protocol.encode_request_for(command, request, address, out))?
        }
        ExchangeKind::BlockRead { words } => {
            // A block read: the request counts the words it asks for.
            let (layout, mut values) = protocol.request_values_for(command, request, address)?;
            values.data_size = block_bytes(words);
            FrameBytes::fill(|out| codec::encode(layout, &values, out))?
        }
        ExchangeKind::BlockWrite(words) => {
            // A block write: the request counts the words it carries; more than two go in
            // its data field as a payload, each in the field's byte order.
            let (layout, mut values) = protocol.request_values_for(command, request, address)?;
            let count = words.as_slice().len();
            values.data_size = (count * 2) as u8;
            let mut payload = [0u8; 2 * codec::MAX_WORDS];
            let little_endian = data_little_endian(&command.request);
            for (word, pair) in words.as_slice().iter().zip(payload.chunks_exact_mut(2)) {
                pair.copy_from_slice(&if little_endian {
                    word.to_le_bytes()
                } else {
                    word.to_be_bytes()
                });
            }
            let payload = if count > 2 {
                &payload[..count * 2]
            } else {
                &[]
            };
            FrameBytes::fill(|out| codec::encode_with_payload(layout, &values, payload, out))?
        }
        ExchangeKind::BlockTransfer { writes, read_count } => {
            // The words to write and the count of words asked back.
            let (layout, mut values) = protocol.request_values_for(command, request, address)?;
            values.set(layout, Role::ReadCount, u32::from(read_count));
            let mut payload = [0u8; 2 * codec::MAX_WORDS];
            let size = writes.write_payload(layout, &mut payload);
            FrameBytes::fill(|out| {
                codec::encode_with_payload(layout, &values, &payload[..size], out)
            })?
        }
        ExchangeKind::Broadcast(to) => {
            let (layout, values) = protocol.broadcast_values_for(command, request, &to)?;
            FrameBytes::fill(|out| codec::encode(layout, &values, out))?
        }
    };
    let follow_up = match &command.follow_up {
        Some(follow_up) => Some(FollowUpFrames {
            sound: FrameBytes::fill(|out| follow_up.encode(true, address, out))?,
            again: FrameBytes::fill(|out| follow_up.encode(false, address, out))?,
        }),
        None => None,
    };
    let expectation = Expectation {
        address,
        wire_register: if request.wire_register {
            Some(request.register)
        } else {
            protocol.to_wire(command, request.register)
        },
        index: request.index,
        data: request.kind.reports_data().then(|| {
            let mask = match request.data_type.size() {
                0 => 0,
                bytes @ 1..=3 => (1u32 << (8 * u32::from(bytes))) - 1,
                _ => u32::MAX,
            };
            (request.data, mask)
        }),
        data_size: match exchange.kind {
            // A block read asks for its words; a block write's reply repeats the count
            // written; a single read asks for its data type's size.
            ExchangeKind::BlockRead { words } => Some(block_bytes(words)),
            ExchangeKind::BlockWrite(words) => Some((words.as_slice().len() * 2) as u8),
            _ => (request.kind.only_reads() && request.data_type.size() > 0)
                .then_some(request.data_type.size()),
        },
    };
    let block_size = match exchange.kind {
        ExchangeKind::BlockRead { words } => usize::from(block_bytes(words)),
        _ => 0,
    };
    let own = shortest_frame_holding(&command.reply, expectation.data_size.map_or(0, usize::from));
    let shortest_reply = protocol
        .error_reply
        .as_ref()
        .map_or(shortest_frame(&command.reply), |error| {
            shortest_frame(&command.reply).min(shortest_frame(error))
        });
    Ok(Prepared {
        frame,
        request: *request,
        command,
        expectation,
        block_size,
        answered: !unanswered(command, request),
        shortest_reply,
        shortest_own_reply: own,
        follow_up,
    })
}

/// The bytes of data `words` registers take, as a request counts them (at most 255).
fn block_bytes(words: u16) -> u8 {
    (words * 2).min(u16::from(u8::MAX)) as u8
}

/// Whether a layout's data field is least significant byte first.
pub(crate) fn data_little_endian(layout: &FrameLayout) -> bool {
    layout
        .field(Role::Data)
        .is_some_and(|field| field.format == Format::UintLe)
}

/// Whether `request` sent by `command` gets no reply: the command is never answered
/// (`reply: none`), or it writes a register whose writes are not (`no_reply: true`).
fn unanswered(command: &CommandSpec, request: &Request) -> bool {
    command.no_reply || (request.kind.is_write() && request.info.is_some_and(|info| info.no_reply))
}

/// The fewest bytes a frame of `layout` can have: its parts of fixed size (a part whose
/// size depends on the frame counts as none), with every byte between the first and last
/// part written as two digits in a hex-pairs layout.
fn shortest_frame(layout: &FrameLayout) -> usize {
    shortest_frame_holding(layout, 0)
}

/// [`shortest_frame`], with a data field whose size depends on the frame counted as
/// `data` bytes.
fn shortest_frame_holding(layout: &FrameLayout, data: usize) -> usize {
    let data_index = layout.index_of(Role::Data);
    let sizes = || {
        layout.parts.iter().enumerate().map(move |(index, part)| {
            part.fixed_size()
                .unwrap_or(if Some(index) == data_index { data } else { 0 })
        })
    };
    let total: usize = sizes().sum();
    match layout.encoding {
        Encoding::HexPairs if layout.parts.len() >= 2 => {
            let ends = sizes().next().unwrap_or(0) + sizes().next_back().unwrap_or(0);
            ends + 2 * (total - ends)
        }
        _ => total,
    }
}
