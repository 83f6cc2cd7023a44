//! A protocol is a set of frame layouts tied to commands, plus the error-reply layout and
//! the drive's error-code table; this module encodes requests and decodes replies with it.

use crate::codec::{self, DecodeStatus, FrameValues};
use crate::error::{DecodeError, EncodeError, ValueError};
use crate::layout::{FrameLayout, List, Part, Role, Text};
use crate::register::{Persistable, Register, RegisterInfo, RegisterValue, Writable};

/// What a command does, independent of its letter on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CommandKind {
    /// Read one register.
    Read,
    /// Write one register in RAM only (lost at power-off).
    WriteRam,
    /// Write one register in RAM and EEPROM (persistent; EEPROM wears out).
    WritePersistent,
}

impl CommandKind {
    /// Name as written in protocol description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            CommandKind::Read => "read",
            CommandKind::WriteRam => "write_ram",
            CommandKind::WritePersistent => "write_persistent",
        }
    }
}

/// One command of a protocol: its letter and the layouts of its request and reply.
#[derive(Debug, Clone, PartialEq)]
pub struct CommandSpec {
    /// Command letter (`b'R'`).
    pub letter: u8,
    /// What it does.
    pub kind: CommandKind,
    /// Request layout.
    pub request: FrameLayout,
    /// Normal reply layout.
    pub reply: FrameLayout,
}

/// One entry of a drive's error-code table.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorCodeInfo {
    /// The code carried by the error reply.
    pub code: u16,
    /// Identifier (`data_error`).
    pub id: Text,
    /// English name.
    pub name: Text,
    /// The manual's Chinese name.
    pub name_zh: Text,
    /// The manual's explanation.
    pub meaning: Text,
}

/// A protocol as one drive speaks it.
#[derive(Debug, Clone, PartialEq)]
pub struct Protocol {
    /// Identifier within the drive (`ascii`).
    pub id: Text,
    /// Human name.
    pub name: Text,
    /// Commands.
    pub commands: List<CommandSpec>,
    /// Layout of error replies, if the protocol has them.
    pub error_reply: Option<FrameLayout>,
    /// A lower-case command letter in a reply means the drive is tripped.
    pub lowercase_means_tripped: bool,
    /// Longest frame, in bytes, used to size buffers and derive reply timeouts.
    pub max_frame_len: u16,
    /// Lowest and highest station address.
    pub address_range: (u8, u8),
    /// Optional parts (by name) included in requests unless the caller says otherwise.
    pub default_optional_parts: List<Text>,
    /// The drive's error codes.
    pub error_codes: List<ErrorCodeInfo>,
}

/// A request, independent of the protocol that will carry it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Request {
    /// What to do.
    pub kind: CommandKind,
    /// Register address.
    pub register: u16,
    /// Data word (ignored for reads).
    pub data: u16,
    /// The register's metadata, when the request was built from a typed register.
    pub info: Option<&'static RegisterInfo>,
}

impl Request {
    /// Reads register `R`.
    pub fn read<R: Register>() -> Request {
        Request {
            kind: CommandKind::Read,
            register: R::INFO.address,
            data: 0,
            info: Some(R::INFO),
        }
    }

    /// Writes `value` to register `R` in RAM only. Refuses values outside the register's range.
    pub fn write_ram<R: Writable>(value: R::Value) -> Result<Request, ValueError> {
        let data = value.to_raw(R::INFO)?;
        Ok(Request {
            kind: CommandKind::WriteRam,
            register: R::INFO.address,
            data,
            info: Some(R::INFO),
        })
    }

    /// Writes `value` to register `R` in RAM and EEPROM. EEPROM endures a limited number of
    /// writes (the manuals say 1,000 to 10,000): use [`Request::write_ram`] for values that
    /// change often.
    pub fn write_persistent<R: Persistable>(value: R::Value) -> Result<Request, ValueError> {
        let data = value.to_raw(R::INFO)?;
        Ok(Request {
            kind: CommandKind::WritePersistent,
            register: R::INFO.address,
            data,
            info: Some(R::INFO),
        })
    }

    /// A request built from raw numbers, with no range checks.
    pub fn raw(kind: CommandKind, register: u16, data: u16) -> Request {
        Request {
            kind,
            register,
            data,
            info: None,
        }
    }

    /// Describes the request for error messages.
    pub fn describe(&self) -> String {
        let target = match self.info {
            Some(info) => info.label(),
            None => format!("register {:04X}", self.register),
        };
        match self.kind {
            CommandKind::Read => format!("read of {target}"),
            CommandKind::WriteRam => format!("RAM write of {:04X}h to {target}", self.data),
            CommandKind::WritePersistent => {
                format!("persistent write of {:04X}h to {target}", self.data)
            }
        }
    }
}

/// A decoded request (what a drive, or the simulator, receives).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DecodedRequest<'p> {
    /// The command it carries.
    pub command: &'p CommandSpec,
    /// Station address, if the frame carries one.
    pub address: Option<u8>,
    /// Register address.
    pub register: u16,
    /// Data word (0 for reads).
    pub data: u16,
    /// Every part's value, including presentation (digits used, optional parts present).
    pub values: FrameValues,
    /// Frame length in bytes.
    pub len: usize,
}

/// A decoded reply.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reply<'p> {
    /// A normal reply.
    Data {
        /// The command it answers.
        command: &'p CommandSpec,
        /// Station address, if the frame carries one.
        address: Option<u8>,
        /// The command letter was lower case: the drive is tripped.
        tripped: bool,
        /// Register address.
        register: u16,
        /// Data word read, or actually written.
        data: u16,
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
        /// Error code.
        code: u16,
        /// The manual's entry for the code, when the table has it.
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

impl Protocol {
    /// The command of the given kind.
    pub fn command(&self, kind: CommandKind) -> Option<&CommandSpec> {
        self.commands.iter().find(|command| command.kind == kind)
    }

    /// The command with this letter (either case when lower case means "tripped").
    pub fn command_by_letter(&self, letter: u8) -> Option<&CommandSpec> {
        self.commands.iter().find(|command| {
            command.letter == letter
                || (self.lowercase_means_tripped && command.letter == letter.to_ascii_uppercase())
        })
    }

    /// The error-code table entry for `code`.
    pub fn error_code(&self, code: u16) -> Option<&ErrorCodeInfo> {
        self.error_codes.iter().find(|entry| entry.code == code)
    }

    /// Builds the request's frame values: its layout and the values to encode, with the
    /// protocol's default optional parts included. Callers may adjust presentation (digits,
    /// optional parts) before calling [`codec::encode`].
    pub fn request_values(
        &self,
        request: &Request,
        address: Option<u8>,
    ) -> Result<(&FrameLayout, FrameValues), EncodeError> {
        let command =
            self.command(request.kind)
                .ok_or_else(|| EncodeError::UnsupportedCommand {
                    protocol: self.id.clone(),
                    kind: request.kind.as_str(),
                })?;
        let layout = &command.request;
        let mut values = FrameValues::default();
        for name in self.default_optional_parts.iter() {
            values.include(layout, &[name]);
        }
        values.set(layout, Role::Command, u32::from(command.letter));
        values.set(layout, Role::Register, u32::from(request.register));
        values.set(layout, Role::Data, u32::from(request.data));
        if let Some(address) = address {
            let (min, max) = self.address_range;
            if address < min || address > max {
                return Err(EncodeError::AddressOutOfRange {
                    protocol: self.id.clone(),
                    address,
                    min,
                    max,
                });
            }
            values.set(layout, Role::Address, u32::from(address));
        }
        Ok((layout, values))
    }

    /// Encodes `request` for the station `address` (or for whichever drive listens, when
    /// `None` and the protocol lets the address out) into `out`; returns the frame length.
    pub fn encode_request(
        &self,
        request: &Request,
        address: Option<u8>,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let (layout, values) = self.request_values(request, address)?;
        codec::encode(layout, &values, out)
    }

    /// Decodes a request frame starting at `bytes[0]`.
    pub fn decode_request(&self, bytes: &[u8]) -> Result<Found<DecodedRequest<'_>>, DecodeError> {
        let mut best: Option<DecodeError> = None;
        let mut incomplete = false;
        for command in self.commands.iter() {
            match codec::decode(&command.request, bytes) {
                Ok(DecodeStatus::Complete { values, len }) => {
                    let layout = &command.request;
                    // Commands may share a layout (W and P): the letter decides.
                    if values
                        .get(layout, Role::Command)
                        .is_some_and(|letter| letter != u32::from(command.letter))
                    {
                        continue;
                    }
                    return Ok(Found::Frame {
                        frame: DecodedRequest {
                            command,
                            address: values.get(layout, Role::Address).map(|a| a as u8),
                            register: values.get(layout, Role::Register).unwrap_or(0) as u16,
                            data: values.get(layout, Role::Data).unwrap_or(0) as u16,
                            values,
                            len,
                        },
                        skipped: 0,
                    });
                }
                Ok(DecodeStatus::Incomplete) => incomplete = true,
                Err(error) => best = Some(furthest(best, error)),
            }
        }
        if incomplete {
            return Ok(Found::Incomplete);
        }
        Err(self.no_match("request", best))
    }

    /// Decodes a reply frame starting at `bytes[0]`. With `expected`, only that command's
    /// reply layout (and the error reply) is tried.
    pub fn decode_reply(
        &self,
        expected: Option<CommandKind>,
        bytes: &[u8],
    ) -> Result<Found<Reply<'_>>, DecodeError> {
        let mut best: Option<DecodeError> = None;
        let mut incomplete = false;
        if let Some(layout) = &self.error_reply {
            match codec::decode(layout, bytes) {
                Ok(DecodeStatus::Complete { values, len }) => {
                    let letter = values.get(layout, Role::Command).unwrap_or(0) as u8;
                    let code = values.get(layout, Role::ErrorCode).unwrap_or(0) as u16;
                    return Ok(Found::Frame {
                        frame: Reply::Error {
                            address: values.get(layout, Role::Address).map(|a| a as u8),
                            tripped: self.lowercase_means_tripped && letter.is_ascii_lowercase(),
                            code,
                            info: self.error_code(code),
                            values,
                            len,
                        },
                        skipped: 0,
                    });
                }
                Ok(DecodeStatus::Incomplete) => incomplete = true,
                Err(error) => best = Some(furthest(best, error)),
            }
        }
        for command in self
            .commands
            .iter()
            .filter(|c| expected.is_none_or(|kind| c.kind == kind))
        {
            let layout = &command.reply;
            match codec::decode(layout, bytes) {
                Ok(DecodeStatus::Complete { values, len }) => {
                    let letter = values.get(layout, Role::Command).unwrap_or(0) as u8;
                    let same = letter == command.letter
                        || (self.lowercase_means_tripped
                            && letter.to_ascii_uppercase() == command.letter);
                    if !same {
                        continue;
                    }
                    return Ok(Found::Frame {
                        frame: Reply::Data {
                            command,
                            address: values.get(layout, Role::Address).map(|a| a as u8),
                            tripped: self.lowercase_means_tripped && letter.is_ascii_lowercase(),
                            register: values.get(layout, Role::Register).unwrap_or(0) as u16,
                            data: values.get(layout, Role::Data).unwrap_or(0) as u16,
                            values,
                            len,
                        },
                        skipped: 0,
                    });
                }
                Ok(DecodeStatus::Incomplete) => incomplete = true,
                Err(error) => best = Some(furthest(best, error)),
            }
        }
        if incomplete {
            return Ok(Found::Incomplete);
        }
        Err(self.no_match("reply", best))
    }

    /// Decodes exactly one request frame: `bytes` must hold the whole frame and nothing else.
    pub fn decode_request_exact(&self, bytes: &[u8]) -> Result<DecodedRequest<'_>, DecodeError> {
        match self.decode_request(bytes)? {
            Found::Frame { frame, .. } => self.exact(frame.len, bytes.len()).map(|()| frame),
            Found::Incomplete => Err(DecodeError::Truncated {
                layout: self.id.clone(),
                len: bytes.len(),
            }),
        }
    }

    /// Decodes exactly one reply frame: `bytes` must hold the whole frame and nothing else.
    pub fn decode_reply_exact(
        &self,
        expected: Option<CommandKind>,
        bytes: &[u8],
    ) -> Result<Reply<'_>, DecodeError> {
        match self.decode_reply(expected, bytes)? {
            Found::Frame { frame, .. } => self.exact(frame.len(), bytes.len()).map(|()| frame),
            Found::Incomplete => Err(DecodeError::Truncated {
                layout: self.id.clone(),
                len: bytes.len(),
            }),
        }
    }

    fn exact(&self, len: usize, available: usize) -> Result<(), DecodeError> {
        if len == available {
            Ok(())
        } else {
            Err(DecodeError::TrailingBytes {
                layout: self.id.clone(),
                len,
                extra: available - len,
            })
        }
    }

    /// Looks for a reply in `bytes`, skipping noise before a start sequence: each
    /// occurrence of a layout's start bytes is tried in turn.
    pub fn find_reply(
        &self,
        expected: Option<CommandKind>,
        bytes: &[u8],
    ) -> Result<Found<Reply<'_>>, DecodeError> {
        let start = self.start_bytes();
        let mut last_error = None;
        let mut incomplete = false;
        for offset in 0..bytes.len() {
            if !start.is_empty() && !bytes[offset..].starts_with(start) {
                continue;
            }
            match self.decode_reply(expected, &bytes[offset..]) {
                Ok(Found::Frame { frame, .. }) => {
                    return Ok(Found::Frame {
                        frame,
                        skipped: offset,
                    })
                }
                Ok(Found::Incomplete) => incomplete = true,
                Err(error) => last_error = Some(error),
            }
            if start.is_empty() {
                break;
            }
        }
        match (incomplete, last_error) {
            (false, Some(error)) => Err(error),
            _ => Ok(Found::Incomplete),
        }
    }

    /// The start bytes shared by the protocol's layouts (empty if there are none).
    pub fn start_bytes(&self) -> &[u8] {
        self.commands
            .first()
            .and_then(|c| c.reply.start_bytes())
            .unwrap_or(&[])
    }

    fn no_match(&self, what: &'static str, best: Option<DecodeError>) -> DecodeError {
        let closest = best.unwrap_or(DecodeError::Truncated {
            layout: self.id.clone(),
            len: 0,
        });
        DecodeError::NoLayoutMatches {
            protocol: self.id.clone(),
            what,
            closest: Box::new(closest),
        }
    }

    /// Whether any layout of the protocol has a part with this name.
    pub fn has_part(&self, name: &str) -> bool {
        self.commands
            .iter()
            .flat_map(|c| [&c.request, &c.reply])
            .chain(self.error_reply.as_ref())
            .any(|layout| layout.parts.iter().any(|part: &Part| part.name() == name))
    }
}

/// Keeps the error that got further into the frame: it names the most telling problem.
fn furthest(best: Option<DecodeError>, error: DecodeError) -> DecodeError {
    match best {
        Some(best) if best.offset() >= error.offset() => best,
        _ => error,
    }
}
