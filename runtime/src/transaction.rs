//! Request/reply exchanges: run any steps a request needs first, encode, send, collect the
//! reply within a timeout derived from the baud rate, check it answers the request, and
//! map error replies to typed errors.

use crate::error::{hex, DecodeErrorKind, TransactionError};
use crate::kinds::{CommandKind, DataType, Space};
use crate::protocol::{Found, PreStep, Protocol, Reply, Request};
use crate::register::{Persistable, Register, RegisterValue, Writable};
use crate::serial::{DriveTiming, SerialSettings};
use crate::transport::Transport;
use std::time::{Duration, Instant};

/// Largest frame the master buffers; longer noise is dropped from the front.
pub const MAX_FRAME: usize = 256;

/// What a successful exchange returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Answer {
    /// Data read, or actually written (0 when the reply carries none).
    pub data: u32,
    /// The drive said it is tripped (lower-case command letter in the reply).
    pub tripped: bool,
    /// Process words the reply carried (status word, output value).
    pub process: Option<[u16; 2]>,
    /// Offset and length of text in the reply, for text reads.
    pub text: Option<(usize, usize)>,
}

/// A bus master speaking one protocol to one station.
///
/// Buffers are fixed arrays, so a transaction makes no heap allocation unless it fails.
pub struct Master<T: Transport> {
    transport: T,
    protocol: &'static Protocol,
    settings: SerialSettings,
    timing: DriveTiming,
    address: Option<u8>,
    request: [u8; MAX_FRAME],
    reply: [u8; MAX_FRAME],
    reply_len: usize,
    last_activity: Option<Instant>,
}

impl<T: Transport> Master<T> {
    /// A master for `protocol` over `transport`, with the line `settings` and the drive's
    /// `timing` (from the generated drive module).
    pub fn new(
        transport: T,
        protocol: &'static Protocol,
        settings: SerialSettings,
        timing: DriveTiming,
    ) -> Self {
        Master {
            transport,
            protocol,
            settings,
            timing,
            address: None,
            request: [0; MAX_FRAME],
            reply: [0; MAX_FRAME],
            reply_len: 0,
            last_activity: None,
        }
    }

    /// Addresses requests to station `address` (`None`: send no address, which the
    /// Toshiba-style protocols accept when one drive is on the line).
    pub fn with_address(mut self, address: Option<u8>) -> Self {
        self.address = address;
        self
    }

    /// The transport, e.g. to close it.
    pub fn into_transport(self) -> T {
        self.transport
    }

    /// The reply timeout for a request of `request_len` bytes.
    pub fn reply_timeout(&self, request_len: usize) -> Duration {
        self.timing.reply_timeout(
            &self.settings,
            request_len,
            usize::from(self.protocol.max_frame_len),
        )
    }

    /// The silence kept between frames (Modbus RTU: 3.5 character times).
    pub fn frame_gap(&self) -> Duration {
        self.settings
            .char_time()
            .mul_f32(self.protocol.frame_gap_chars)
    }

    /// Reads register `R` and converts the value to its typed form.
    pub fn read<R: Register>(&mut self) -> Result<R::Value, TransactionError> {
        let answer = self.transact(&Request::read::<R>())?;
        Ok(R::Value::from_raw(answer.data, R::INFO)?)
    }

    /// Reads element `index` of the array register `R`.
    pub fn read_indexed<R: Register>(&mut self, index: u16) -> Result<R::Value, TransactionError> {
        let answer = self.transact(&Request::read::<R>().at_index(index)?)?;
        Ok(R::Value::from_raw(answer.data, R::INFO)?)
    }

    /// Reads the text register `R` (text parameters such as an ordering number).
    pub fn read_text<R: Register>(&mut self) -> Result<String, TransactionError> {
        let answer = self.transact(&Request::read::<R>())?;
        let (start, len) = answer.text.unwrap_or((0, 0));
        Ok(String::from_utf8_lossy(&self.reply[start..start + len]).into_owned())
    }

    /// Writes `value` to register `R` in RAM only; returns the value the drive reports written.
    pub fn write_ram<R: Writable>(
        &mut self,
        value: R::Value,
    ) -> Result<R::Value, TransactionError> {
        let answer = self.transact(&Request::write_ram::<R>(value)?)?;
        self.written::<R>(answer)
    }

    /// Writes `value` to element `index` of the array register `R` in RAM only.
    pub fn write_ram_indexed<R: Writable>(
        &mut self,
        index: u16,
        value: R::Value,
    ) -> Result<R::Value, TransactionError> {
        let answer = self.transact(&Request::write_ram::<R>(value)?.at_index(index)?)?;
        self.written::<R>(answer)
    }

    /// Writes `value` to register `R` in RAM and EEPROM (persistent; EEPROM wears out).
    pub fn write_persistent<R: Persistable>(
        &mut self,
        value: R::Value,
    ) -> Result<R::Value, TransactionError> {
        let answer = self.transact(&Request::write_persistent::<R>(value)?)?;
        self.written::<R>(answer)
    }

    fn written<R: Register>(&self, answer: Answer) -> Result<R::Value, TransactionError> {
        Ok(R::Value::from_raw(answer.data, R::INFO)?)
    }

    /// Sends process words (control word, reference) and returns those the drive answers
    /// with (status word, output value).
    pub fn exchange_process(
        &mut self,
        control: u16,
        reference: u16,
    ) -> Result<[u16; 2], TransactionError> {
        let request = Request::process(control, reference);
        let answer = self.transact(&request)?;
        answer.process.ok_or_else(|| TransactionError::Mismatch {
            request: request.describe(),
            field: "process words",
            expected: 2,
            found: 0,
        })
    }

    /// Runs one request, with any steps the protocol needs first (selecting an array
    /// index, choosing RAM or EEPROM).
    pub fn transact(&mut self, request: &Request) -> Result<Answer, TransactionError> {
        for step in self.protocol.pre_steps.iter() {
            match *step {
                PreStep::Index { register } => {
                    if let Some(index) = request.index {
                        let select = Request {
                            wire_register: true,
                            index: None,
                            info: None,
                            ..Request::raw(CommandKind::WriteRam, register, u32::from(index))
                        };
                        self.exchange(&select)?;
                    }
                }
                PreStep::Persistence {
                    space,
                    register,
                    data_type,
                    ram,
                    persistent,
                } => {
                    // Coil writes (process data) are not parameter writes: no selector for them.
                    if request.kind.is_write() && request.space == Space::Parameter {
                        let value = if request.kind == CommandKind::WritePersistent {
                            persistent
                        } else {
                            ram
                        };
                        let select = Request::raw(CommandKind::WriteRam, register, value)
                            .in_space(space)
                            .with_data_type(data_type);
                        self.exchange(&select)?;
                    }
                }
            }
        }
        // With the protocol's steps done, the selector is set: send the request itself.
        let main = if self.has_index_step() {
            Request {
                index: None,
                ..*request
            }
        } else {
            *request
        };
        let main = if self.has_persistence_step()
            && request.kind == CommandKind::WritePersistent
            && request.space == Space::Parameter
        {
            Request {
                kind: CommandKind::WriteRam,
                ..main
            }
        } else {
            main
        };
        let answer = self.exchange(&main);
        answer.map_err(|error| rename(error, request))
    }

    fn has_index_step(&self) -> bool {
        self.protocol
            .pre_steps
            .iter()
            .any(|s| matches!(s, PreStep::Index { .. }))
    }

    fn has_persistence_step(&self) -> bool {
        self.protocol
            .pre_steps
            .iter()
            .any(|s| matches!(s, PreStep::Persistence { .. }))
    }

    /// One request frame, one reply frame.
    fn exchange(&mut self, request: &Request) -> Result<Answer, TransactionError> {
        let protocol = self.protocol;
        let cannot_send = |source| TransactionError::Encode {
            request: request.describe(),
            source,
        };
        let command = protocol.command_for_request(request).map_err(cannot_send)?;
        let len = protocol
            .encode_request(request, self.address, &mut self.request)
            .map_err(cannot_send)?;
        if let Some(last) = self.last_activity {
            let gap = self.frame_gap();
            let since = last.elapsed();
            if since < gap {
                std::thread::sleep(gap - since);
            }
        }
        self.transport.clear_input()?;
        self.transport.send(&self.request[..len])?;
        let timeout = self.reply_timeout(len);
        let deadline = Instant::now() + timeout;
        let mut filled = 0usize;
        let mut last_error = None;
        loop {
            if filled == self.reply.len() {
                // Only noise could fill the buffer: keep the last half and go on looking.
                self.reply.copy_within(MAX_FRAME / 2.., 0);
                filled = MAX_FRAME - MAX_FRAME / 2;
            }
            let got = self
                .transport
                .receive(&mut self.reply[filled..], deadline)?;
            self.last_activity = Some(Instant::now());
            if got == 0 {
                return Err(TransactionError::Timeout {
                    request: request.describe(),
                    waited: timeout,
                    received: hex(&self.reply[..filled.min(64)]),
                    received_len: filled,
                    last_error,
                });
            }
            filled += got;
            match protocol.find_reply(Some(command), &self.reply[..filled]) {
                Ok(Found::Incomplete) => continue,
                Ok(Found::Frame { frame, skipped }) => {
                    self.reply_len = filled;
                    let answer = check_reply(request, self.address, frame)?;
                    return Ok(Answer {
                        text: answer.text.map(|(start, len)| (start + skipped, len)),
                        ..answer
                    });
                }
                Err(error) if error.kind() == DecodeErrorKind::ChecksumMismatch => {
                    return Err(TransactionError::Decode {
                        request: request.describe(),
                        source: Box::new(error),
                    });
                }
                Err(error) => last_error = Some(Box::new(error)),
            }
        }
    }
}

/// Names the caller's request (not the internal step) in errors about the main exchange.
fn rename(error: TransactionError, request: &Request) -> TransactionError {
    let name = request.describe();
    match error {
        TransactionError::Timeout {
            waited,
            received,
            received_len,
            last_error,
            ..
        } => TransactionError::Timeout {
            request: name,
            waited,
            received,
            received_len,
            last_error,
        },
        TransactionError::Decode { source, .. } => TransactionError::Decode {
            request: name,
            source,
        },
        TransactionError::Rejected {
            code,
            info,
            tripped,
            ..
        } => TransactionError::Rejected {
            request: name,
            code,
            info,
            tripped,
        },
        TransactionError::Encode { source, .. } => TransactionError::Encode {
            request: name,
            source,
        },
        TransactionError::Mismatch {
            field,
            expected,
            found,
            ..
        } => TransactionError::Mismatch {
            request: name,
            field,
            expected,
            found,
        },
        other => other,
    }
}

fn check_reply(
    request: &Request,
    address: Option<u8>,
    reply: Reply<'static>,
) -> Result<Answer, TransactionError> {
    match reply {
        Reply::Error {
            error,
            info,
            tripped,
            ..
        } => Err(TransactionError::Rejected {
            request: request.describe(),
            code: error,
            info,
            tripped,
        }),
        Reply::Data {
            command,
            address: reply_address,
            tripped,
            wire_register,
            index,
            data,
            process,
            text,
            ..
        } => {
            let mismatch = |field, expected: u32, found: u32| TransactionError::Mismatch {
                request: request.describe(),
                field,
                expected,
                found,
            };
            if let (Some(sent), Some(got)) = (address, reply_address) {
                if sent != got {
                    return Err(mismatch("address", sent.into(), got.into()));
                }
            }
            if let Some(got) = wire_register {
                let sent = if request.wire_register {
                    Some(request.register)
                } else {
                    command.address_map.to_wire(request.register)
                };
                if let Some(sent) = sent {
                    if sent != got {
                        return Err(mismatch("register", sent.into(), got.into()));
                    }
                }
            }
            if let (Some(sent), Some(got)) = (request.index, index) {
                if sent != got {
                    return Err(mismatch("index", sent.into(), got.into()));
                }
            }
            if request.data_type == DataType::Text && text.is_none() {
                return Err(mismatch("text", 1, 0));
            }
            Ok(Answer {
                data,
                tripped,
                process,
                text,
            })
        }
    }
}
