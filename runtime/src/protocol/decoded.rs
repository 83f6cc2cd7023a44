//! What decoding finds: a request ([`DecodedRequest`]), a reply ([`Reply`]), or more bytes
//! needed ([`Found`]).

use super::command::CommandSpec;
use crate::broadcast::Broadcast;
use crate::codec::{FrameValues, Words};
use crate::info::ErrorCodeInfo;
use crate::layout::Role;

/// A decoded request (what a drive, or the simulator, receives).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DecodedRequest<'p> {
    /// The command it carries.
    pub command: &'p CommandSpec,
    /// Station address, if the frame carries one (`None` for a broadcast).
    pub address: Option<u8>,
    /// The stations a broadcast addresses, when the station field holds a broadcast
    /// encoding (`**`, `*9`, FFh, Modbus 0) rather than one station.
    pub broadcast: Option<Broadcast>,
    /// Register number on the wire.
    pub wire_register: Option<u16>,
    /// Register number after undoing the command's address map, when it maps back.
    pub register: Option<u16>,
    /// Array index, if the frame carries one.
    pub index: Option<u16>,
    /// Data (0 for reads).
    pub data: u32,
    /// Process words, if the frame carries them.
    pub process: Option<[u16; 2]>,
    /// The words of its words field (a block transfer's words to write); empty if none.
    pub words: Words,
    /// The registers its data field carries when it carries more than 4 bytes (a Modbus
    /// 10h write of three registers or more), each in the field's byte order; empty
    /// otherwise (the data is then the number in `data`).
    pub data_words: Words,
    /// Every part's value, including presentation (digits used, optional parts present).
    pub values: FrameValues,
    /// Frame length in bytes.
    pub len: usize,
}

impl DecodedRequest<'_> {
    /// The command code as on the wire (the letter in its case); the command's own code
    /// when the layout carries none.
    pub fn code(&self) -> u32 {
        self.values
            .get(&self.command.request, Role::Command)
            .unwrap_or(self.command.code)
    }

    /// The request says its sender has tripped (a lower-case code of a command whose lower
    /// case means so: the Toshiba drive-to-drive `s`).
    pub fn sender_tripped(&self) -> bool {
        self.command.lowercase_means_sender_tripped
            && u8::try_from(self.code()).is_ok_and(|b| b.is_ascii_lowercase())
    }
}

/// A decoded reply.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reply<'p> {
    /// A normal reply.
    Data {
        /// The command it answers.
        command: &'p CommandSpec,
        /// The code it carries (the AK response, the letter in its case).
        code: u32,
        /// Station address, if the frame carries one.
        address: Option<u8>,
        /// The command letter was lower case: the drive is tripped.
        tripped: bool,
        /// Register number on the wire, if the reply carries one.
        wire_register: Option<u16>,
        /// Array index, if the reply carries one.
        index: Option<u16>,
        /// Data read, or actually written (0 when the reply carries none).
        data: u32,
        /// Process words (status word, output value), if the reply carries them.
        process: Option<[u16; 2]>,
        /// Offset and length of the text in the frame, for text replies.
        text: Option<(usize, usize)>,
        /// Every part's value.
        values: FrameValues,
        /// Frame length in bytes.
        len: usize,
    },
    /// An error reply.
    Error {
        /// Station address, if the frame carries one.
        address: Option<u8>,
        /// The command letter was lower case: the drive is tripped.
        tripped: bool,
        /// The code the reply carries (`N`, AK 7, function | 80h).
        code: u32,
        /// Error code.
        error: u16,
        /// The manual's entry for the error code, when the table has it.
        info: Option<&'p ErrorCodeInfo>,
        /// Every part's value.
        values: FrameValues,
        /// Frame length in bytes.
        len: usize,
    },
}

impl Reply<'_> {
    /// Frame length in bytes.
    pub fn len(&self) -> usize {
        match self {
            Reply::Data { len, .. } | Reply::Error { len, .. } => *len,
        }
    }

    /// Whether the frame is empty (never true for a decoded reply).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Outcome of looking for one frame in received bytes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Found<T> {
    /// A frame, found after skipping `skipped` bytes of noise.
    Frame {
        /// The decoded frame.
        frame: T,
        /// Bytes skipped before its start.
        skipped: usize,
    },
    /// The bytes so far may still become a frame.
    Incomplete,
}
