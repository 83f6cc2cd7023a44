//! Request/reply exchanges: encode, send, collect the reply within a timeout derived from
//! the baud rate, check it answers the request, and map error replies to typed errors.

use crate::error::{hex, TransactionError};
use crate::protocol::{Found, Protocol, Reply, Request};
use crate::register::{Persistable, Register, RegisterValue, Writable};
use crate::serial::{DriveTiming, SerialSettings};
use crate::transport::Transport;
use std::time::{Duration, Instant};

/// Largest frame the master buffers; protocols with longer frames are refused at construction.
pub const MAX_FRAME: usize = 256;

/// What a successful exchange returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Answer {
    /// Data word read, or actually written.
    pub data: u16,
    /// The drive said it is tripped (lower-case command letter in the reply).
    pub tripped: bool,
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

    /// Reads register `R` and converts the word to its typed value.
    pub fn read<R: Register>(&mut self) -> Result<R::Value, TransactionError> {
        let answer = self.transact(&Request::read::<R>())?;
        Ok(R::Value::from_raw(answer.data, R::INFO)?)
    }

    /// Writes `value` to register `R` in RAM only; returns the value the drive reports written.
    pub fn write_ram<R: Writable>(
        &mut self,
        value: R::Value,
    ) -> Result<R::Value, TransactionError> {
        let answer = self.transact(&Request::write_ram::<R>(value)?)?;
        Ok(R::Value::from_raw(answer.data, R::INFO)?)
    }

    /// Writes `value` to register `R` in RAM and EEPROM (persistent; EEPROM wears out).
    pub fn write_persistent<R: Persistable>(
        &mut self,
        value: R::Value,
    ) -> Result<R::Value, TransactionError> {
        let answer = self.transact(&Request::write_persistent::<R>(value)?)?;
        Ok(R::Value::from_raw(answer.data, R::INFO)?)
    }

    /// Runs one exchange.
    pub fn transact(&mut self, request: &Request) -> Result<Answer, TransactionError> {
        let len = self
            .protocol
            .encode_request(request, self.address, &mut self.request)?;
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
            match self
                .protocol
                .find_reply(Some(request.kind), &self.reply[..filled])
            {
                Ok(Found::Incomplete) => continue,
                Ok(Found::Frame { frame, .. }) => {
                    return check_reply(self.protocol, request, self.address, frame)
                }
                Err(error) if error.kind() == "checksum_mismatch" => {
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

fn check_reply(
    protocol: &'static Protocol,
    request: &Request,
    address: Option<u8>,
    reply: Reply<'static>,
) -> Result<Answer, TransactionError> {
    match reply {
        Reply::Error {
            code,
            info,
            tripped,
            ..
        } => Err(TransactionError::Rejected {
            request: request.describe(),
            code,
            info,
            tripped,
        }),
        Reply::Data {
            command,
            address: reply_address,
            tripped,
            register,
            data,
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
            let expected = protocol
                .command(request.kind)
                .map(|c| c.letter)
                .unwrap_or(0);
            if command.letter != expected {
                return Err(mismatch("command", expected.into(), command.letter.into()));
            }
            if register != request.register {
                return Err(mismatch(
                    "register",
                    request.register.into(),
                    register.into(),
                ));
            }
            Ok(Answer { data, tripped })
        }
    }
}
