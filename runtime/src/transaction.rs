//! Request/reply exchanges: run any steps a request needs first, encode, send, collect the
//! reply within a timeout derived from the baud rate, check it answers the request, and
//! map error replies to typed errors.

use crate::error::{hex, DecodeError, DecodeErrorKind, EncodeError, ValueError};
use crate::info::ErrorCodeInfo;
use crate::kinds::{CommandKind, DataType, Space};
use crate::layout::Role;
use crate::protocol::{DriveProtocol, Found, PreStep, Protocol, Reply};
use crate::register::{Persistable, Register, RegisterValue, Request, Writable};
use crate::serial::{DriveTiming, SerialSettings};
use crate::transport::Transport;
use std::fmt;
use std::marker::PhantomData;
use std::time::{Duration, Instant};

/// Largest frame the master buffers; longer noise is dropped from the front.
pub const MAX_FRAME: usize = 256;

/// What a successful exchange returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Answer {
    /// Data read, or the value the drive reports written; `None` when the reply carries no
    /// data (the protocol echoes nothing).
    pub data: Option<u32>,
    /// The drive said it is tripped (lower-case command letter in the reply).
    pub tripped: bool,
    /// Process words the reply carried (status word, output value).
    pub process: Option<[u16; 2]>,
    /// Offset and length of text in the reply, for text reads.
    pub text: Option<(usize, usize)>,
}

/// A value read from a drive, with what the reply said about the drive: a tripped drive
/// still answers reads (its monitors hold the values at the trip), so the value comes back
/// and [`Reading::tripped`] says so, without an extra request.
///
/// It dereferences to the value and compares with it (`reading == Hertz(60.0)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reading<V> {
    /// The typed value.
    pub value: V,
    /// The reply said the drive is tripped (in the Toshiba-style protocols, a lower-case
    /// command letter). Protocols whose replies carry no such sign report `false`; the FC
    /// drives report a trip in the status word instead.
    pub tripped: bool,
}

impl<V> Reading<V> {
    /// The value, without the drive state.
    pub fn into_value(self) -> V {
        self.value
    }
}

impl<V> std::ops::Deref for Reading<V> {
    type Target = V;
    fn deref(&self) -> &V {
        &self.value
    }
}

impl<V: PartialEq> PartialEq<V> for Reading<V> {
    fn eq(&self, other: &V) -> bool {
        self.value == *other
    }
}

impl<V: fmt::Display> fmt::Display for Reading<V> {
    /// The value, followed by `(drive tripped)` when the reply said so.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.value.fmt(f)?;
        if self.tripped {
            f.write_str(" (drive tripped)")?;
        }
        Ok(())
    }
}

/// Drive parameter of a [`Master`] built on an untyped [`Protocol`]
/// ([`Master::for_protocol`]): it sends raw requests ([`Master::transact`]) for tools that
/// work with any drive, and no typed register requests.
#[derive(Debug, Clone, Copy)]
pub enum AnyDrive {}

/// A bus master speaking one protocol to one station of drive `D`.
///
/// Typed reads and writes take only registers of `D` (`R: Register<Drive = D>`), so a
/// register of another drive does not compile. Buffers are fixed arrays, so a transaction
/// makes no heap allocation unless it fails.
pub struct Master<T: Transport, D: 'static = AnyDrive> {
    transport: T,
    protocol: &'static Protocol,
    drive: PhantomData<fn() -> D>,
    settings: SerialSettings,
    timing: DriveTiming,
    address: Option<u8>,
    request: [u8; MAX_FRAME],
    reply: [u8; MAX_FRAME],
    reply_len: usize,
    last_activity: Option<Instant>,
}

impl<T: Transport> Master<T, AnyDrive> {
    /// A master for an untyped `protocol` (from a [`crate::DriveInfo`], for tools that work
    /// with any drive): it runs raw requests with [`Master::transact`].
    pub fn for_protocol(
        transport: T,
        protocol: &'static Protocol,
        settings: SerialSettings,
        timing: DriveTiming,
    ) -> Self {
        Master::build(transport, protocol, settings, timing)
    }
}

impl<T: Transport, D: 'static> Master<T, D> {
    /// A master for drive `D`'s `protocol` over `transport`, with the line `settings` and
    /// the drive's `timing` (all from the generated drive module).
    pub fn new(
        transport: T,
        protocol: &'static DriveProtocol<D>,
        settings: SerialSettings,
        timing: DriveTiming,
    ) -> Self {
        Master::build(transport, protocol.protocol(), settings, timing)
    }

    fn build(
        transport: T,
        protocol: &'static Protocol,
        settings: SerialSettings,
        timing: DriveTiming,
    ) -> Self {
        Master {
            transport,
            protocol,
            drive: PhantomData,
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

    /// Reads register `R`: its typed value, and whether the reply said the drive is tripped.
    pub fn read<R: Register<Drive = D>>(&mut self) -> Result<Reading<R::Value>, TransactionError> {
        let request = Request::read::<R>();
        let answer = self.transact(&request)?;
        Self::value_read::<R>(&request, answer)
    }

    /// Reads element `index` of the array register `R`. Refuses indexes beyond the array.
    pub fn read_at<R: Register<Drive = D>>(
        &mut self,
        index: u16,
    ) -> Result<Reading<R::Value>, TransactionError> {
        let request = Request::read::<R>().at_index(index)?;
        let answer = self.transact(&request)?;
        Self::value_read::<R>(&request, answer)
    }

    /// The typed value a read reply carries; a reply without data does not answer a read.
    fn value_read<R: Register>(
        request: &Request,
        answer: Answer,
    ) -> Result<Reading<R::Value>, TransactionError> {
        let data = answer.data.ok_or_else(|| {
            TransactionError::new(
                Some(request),
                TransactionErrorKind::Mismatch {
                    field: ReplyField::Data,
                    expected: 1,
                    found: 0,
                },
            )
        })?;
        Ok(Reading {
            value: R::Value::from_raw(data, R::INFO)?,
            tripped: answer.tripped,
        })
    }

    /// Reads the text register `R` (text parameters such as an ordering number).
    pub fn read_text<R: Register<Drive = D>>(&mut self) -> Result<String, TransactionError> {
        let answer = self.transact(&Request::read::<R>())?;
        let (start, len) = answer.text.unwrap_or((0, 0));
        Ok(String::from_utf8_lossy(&self.reply[start..start + len]).into_owned())
    }

    /// Writes `value` to register `R` in RAM only. Returns the value the drive reports
    /// written (its echo), or `None` when the protocol's reply carries no data.
    pub fn write_ram<R: Writable<Drive = D>>(
        &mut self,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self.transact(&Request::write_ram::<R>(value)?)?;
        self.written::<R>(answer)
    }

    /// Writes `value` to element `index` of the array register `R` in RAM only. Returns
    /// the value the drive reports written, if its reply carries one.
    pub fn write_ram_at<R: Writable<Drive = D>>(
        &mut self,
        index: u16,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self.transact(&Request::write_ram::<R>(value)?.at_index(index)?)?;
        self.written::<R>(answer)
    }

    /// Writes `value` to register `R` in RAM and EEPROM (persistent; EEPROM wears out).
    /// Returns the value the drive reports written, if its reply carries one.
    pub fn write_persistent<R: Persistable<Drive = D>>(
        &mut self,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self.transact(&Request::write_persistent::<R>(value)?)?;
        self.written::<R>(answer)
    }

    /// Writes `value` to element `index` of the array register `R` in RAM and EEPROM
    /// (persistent; EEPROM wears out). Returns the value the drive reports written, if its
    /// reply carries one.
    pub fn write_persistent_at<R: Persistable<Drive = D>>(
        &mut self,
        index: u16,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let request = Request::write_persistent::<R>(value)?.at_index(index)?;
        let answer = self.transact(&request)?;
        self.written::<R>(answer)
    }

    fn written<R: Register>(&self, answer: Answer) -> Result<Option<R::Value>, TransactionError> {
        Ok(answer
            .data
            .map(|data| R::Value::from_raw(data, R::INFO))
            .transpose()?)
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
        answer.process.ok_or_else(|| {
            TransactionError::new(
                Some(&request),
                TransactionErrorKind::Mismatch {
                    field: ReplyField::ProcessWords,
                    expected: 2,
                    found: 0,
                },
            )
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
        // Errors of the main exchange name the caller's request, not the adjusted one.
        self.exchange(&main).map_err(|error| TransactionError {
            request: Some(*request),
            ..error
        })
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
        let fail = |kind| TransactionError::new(Some(request), kind);
        let io = |error| fail(TransactionErrorKind::Io(error));
        let cannot_send = |error| fail(TransactionErrorKind::Encode(error));
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
        self.transport.clear_input().map_err(io)?;
        self.transport.send(&self.request[..len]).map_err(io)?;
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
                .receive(&mut self.reply[filled..], deadline)
                .map_err(io)?;
            self.last_activity = Some(Instant::now());
            if got == 0 {
                return Err(fail(TransactionErrorKind::Timeout {
                    waited: timeout,
                    received: self.reply[..filled.min(64)].to_vec(),
                    received_len: filled,
                    last_error,
                }));
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
                    return Err(fail(TransactionErrorKind::Decode(Box::new(error))));
                }
                Err(error) => last_error = Some(Box::new(error)),
            }
        }
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
        } => Err(TransactionError::new(
            Some(request),
            TransactionErrorKind::Rejected {
                code: error,
                info,
                tripped,
            },
        )),
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
            let mismatch = |field, expected: u32, found: u32| {
                TransactionError::new(
                    Some(request),
                    TransactionErrorKind::Mismatch {
                        field,
                        expected,
                        found,
                    },
                )
            };
            if let (Some(sent), Some(got)) = (address, reply_address) {
                if sent != got {
                    return Err(mismatch(ReplyField::Address, sent.into(), got.into()));
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
                        return Err(mismatch(ReplyField::Register, sent.into(), got.into()));
                    }
                }
            }
            if let (Some(sent), Some(got)) = (request.index, index) {
                if sent != got {
                    return Err(mismatch(ReplyField::Index, sent.into(), got.into()));
                }
            }
            if request.data_type == DataType::Text && text.is_none() {
                return Err(mismatch(ReplyField::Text, 1, 0));
            }
            Ok(Answer {
                data: command.reply.has(Role::Data).then_some(data),
                tripped,
                process,
                text,
            })
        }
    }
}

/// A request/reply exchange that failed: the request it concerns (stored once) and what
/// went wrong.
#[derive(Debug)]
pub struct TransactionError {
    /// The request the error is about: the caller's request for failures of the exchange
    /// itself, or the step's request when a step the protocol needs first failed
    /// (selecting an array index, choosing RAM or EEPROM). `None` when no request was sent:
    /// a value is refused before anything goes on the line, or a value read back does not
    /// convert (the value error names the register).
    pub request: Option<Request>,
    /// What went wrong.
    pub kind: TransactionErrorKind,
}

/// What went wrong in a failed exchange.
#[derive(Debug)]
pub enum TransactionErrorKind {
    /// The transport failed.
    Io(std::io::Error),
    /// The request could not be built.
    Encode(EncodeError),
    /// The value cannot be sent, or the value read back cannot be converted.
    Value(ValueError),
    /// No complete reply arrived in time.
    Timeout {
        /// The timeout that elapsed.
        waited: Duration,
        /// The first bytes received (at most 64).
        received: Vec<u8>,
        /// Number of bytes received.
        received_len: usize,
        /// The last decode error seen while waiting, if any.
        last_error: Option<Box<DecodeError>>,
    },
    /// The reply is not a valid frame.
    Decode(Box<DecodeError>),
    /// The drive answered with an error reply.
    Rejected {
        /// Error code received.
        code: u16,
        /// The manual's entry for the code.
        info: Option<&'static ErrorCodeInfo>,
        /// Whether the reply said the drive is tripped (lower-case command).
        tripped: bool,
    },
    /// The reply does not answer the request (wrong address, register or index).
    Mismatch {
        /// Which part of the reply differs.
        field: ReplyField,
        /// Value expected.
        expected: u32,
        /// Value found.
        found: u32,
    },
}

/// A part of a reply the master checks against its request.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ReplyField {
    /// The station address.
    Address,
    /// The register number on the wire.
    Register,
    /// The array index.
    Index,
    /// The text of a text read (expected 1: present; found 0: absent).
    Text,
    /// The process words (expected 2, found 0: absent).
    ProcessWords,
    /// The data of a read (expected 1: present; found 0: absent).
    Data,
}

impl ReplyField {
    /// Name used in messages (`register`, `process words`).
    pub const fn as_str(self) -> &'static str {
        match self {
            ReplyField::Address => "address",
            ReplyField::Register => "register",
            ReplyField::Index => "index",
            ReplyField::Text => "text",
            ReplyField::ProcessWords => "process words",
            ReplyField::Data => "data",
        }
    }
}

impl TransactionError {
    /// An error about `request` (`None`: no request was sent).
    pub fn new(request: Option<&Request>, kind: TransactionErrorKind) -> TransactionError {
        TransactionError {
            request: request.copied(),
            kind,
        }
    }
}

impl From<std::io::Error> for TransactionError {
    fn from(error: std::io::Error) -> Self {
        TransactionError::new(None, TransactionErrorKind::Io(error))
    }
}

impl From<ValueError> for TransactionError {
    fn from(error: ValueError) -> Self {
        TransactionError::new(None, TransactionErrorKind::Value(error))
    }
}

impl fmt::Display for TransactionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let request = || {
            self.request
                .as_ref()
                .map_or_else(|| "the request".to_owned(), Request::describe)
        };
        match &self.kind {
            TransactionErrorKind::Io(error) if self.request.is_some() => {
                write!(f, "transport error during {}: {error}", request())
            }
            TransactionErrorKind::Io(error) => write!(f, "transport error: {error}"),
            TransactionErrorKind::Encode(error) => write!(f, "cannot send {}: {error}", request()),
            TransactionErrorKind::Value(error) => write!(f, "{error}"),
            TransactionErrorKind::Timeout {
                waited,
                received,
                received_len,
                last_error,
            } => {
                let waited = for_people(*waited);
                if *received_len == 0 {
                    write!(f, "no reply to {} within {waited}", request())?;
                } else {
                    write!(
                        f,
                        "no complete reply to {} within {waited}; received {received_len} byte(s): {}",
                        request(),
                        hex(received)
                    )?;
                    if *received_len > received.len() {
                        f.write_str(" ...")?;
                    }
                }
                if let Some(error) = last_error {
                    write!(f, "; last decode error: {error}")?;
                }
                Ok(())
            }
            TransactionErrorKind::Decode(error) => {
                write!(f, "invalid reply to {}: {error}", request())
            }
            TransactionErrorKind::Rejected {
                code,
                info,
                tripped,
            } => {
                write!(
                    f,
                    "drive rejected {}: error {code} ({code:04X}h) ",
                    request()
                )?;
                match info {
                    Some(info) => write!(f, "{} ({}): {}", info.name, info.name_zh, info.meaning)?,
                    None => f.write_str("(code not in the manual's table)")?,
                }
                if *tripped {
                    f.write_str("; the drive reports it is tripped")?;
                }
                Ok(())
            }
            TransactionErrorKind::Mismatch {
                field,
                expected,
                found,
            } => match field {
                // Parts whose presence is what is checked: say what is missing.
                ReplyField::Text | ReplyField::ProcessWords | ReplyField::Data => {
                    write!(f, "reply to {} carries no {}", request(), field.as_str())
                }
                ReplyField::Address | ReplyField::Register | ReplyField::Index => write!(
                    f,
                    "reply to {} does not match: {} is {found:#X}, expected {expected:#X}",
                    request(),
                    field.as_str()
                ),
            },
        }
    }
}

impl std::error::Error for TransactionError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            TransactionErrorKind::Io(error) => Some(error),
            TransactionErrorKind::Encode(error) => Some(error),
            TransactionErrorKind::Decode(error) => Some(error.as_ref()),
            // The message is the value error's own, so it is not repeated as a source.
            TransactionErrorKind::Value(error) => error.source(),
            TransactionErrorKind::Timeout { .. }
            | TransactionErrorKind::Rejected { .. }
            | TransactionErrorKind::Mismatch { .. } => None,
        }
    }
}

/// A duration as people read it: `850 µs`, `120 ms`, `12.5 s`.
fn for_people(duration: Duration) -> String {
    let micros = duration.as_micros();
    if micros < 1_000 {
        format!("{micros} µs")
    } else if micros < 10_000_000 {
        format!("{} ms", (micros + 500) / 1_000)
    } else {
        format!("{:.1} s", duration.as_secs_f64())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error as _;

    #[test]
    fn durations_read_as_people_write_them() {
        assert_eq!(for_people(Duration::from_micros(850)), "850 µs");
        assert_eq!(for_people(Duration::from_micros(120_400)), "120 ms");
        assert_eq!(for_people(Duration::from_micros(1_999_600)), "2000 ms");
        assert_eq!(for_people(Duration::from_millis(12_500)), "12.5 s");
    }

    #[test]
    fn a_silent_timeout_says_so_without_a_dangling_colon() {
        let request = Request::raw(CommandKind::Read, 0xFD00, 0);
        let error = TransactionError::new(
            Some(&request),
            TransactionErrorKind::Timeout {
                waited: Duration::from_micros(120_300),
                received: Vec::new(),
                received_len: 0,
                last_error: None,
            },
        );
        assert_eq!(
            error.to_string(),
            "no reply to read of register FD00 within 120 ms"
        );
        let error = TransactionError {
            kind: TransactionErrorKind::Timeout {
                waited: Duration::from_millis(40),
                received: b"garbage".to_vec(),
                received_len: 70,
                last_error: None,
            },
            ..error
        };
        assert_eq!(
            error.to_string(),
            "no complete reply to read of register FD00 within 40 ms; \
             received 70 byte(s): 67 61 72 62 61 67 65 ..."
        );
    }

    #[test]
    fn the_source_is_the_underlying_error() {
        let io = std::io::Error::new(std::io::ErrorKind::BrokenPipe, "gone");
        let error = TransactionError::from(io);
        assert_eq!(error.to_string(), "transport error: gone");
        assert_eq!(error.source().unwrap().to_string(), "gone");
        let request = Request::raw(CommandKind::Read, 1, 0);
        let decode = DecodeError::Truncated {
            layout: "reply".into(),
            len: 2,
        };
        let error = TransactionError::new(
            Some(&request),
            TransactionErrorKind::Decode(Box::new(decode.clone())),
        );
        assert_eq!(error.source().unwrap().to_string(), decode.to_string());
        assert!(error
            .to_string()
            .starts_with("invalid reply to read of register 0001: "));
    }
}
