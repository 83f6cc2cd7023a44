//! What a failed exchange reports: the request it concerns and what went wrong (the
//! transport, a frame that cannot be built, a value, a timeout, a garbled or foreign reply,
//! or the drive's refusal with the manual's meaning of its code).

use crate::error::{hex, DecodeError, EncodeError, ValueError};
use crate::info::ErrorCodeInfo;
use crate::register::Request;
use std::fmt;
use std::time::Duration;

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
    /// The reply does not answer the request (wrong address, register or index, or a
    /// write reply reporting another value).
    Mismatch {
        /// Which part of the reply differs.
        field: ReplyField,
        /// Value expected.
        expected: u32,
        /// Value found.
        found: u32,
    },
}

impl TransactionErrorKind {
    /// Whether something came back that was not a sound frame: a reply that does not
    /// decode, or bytes that never made one before the timeout.
    pub fn garbled_reply(&self) -> bool {
        match self {
            TransactionErrorKind::Decode(_) => true,
            TransactionErrorKind::Timeout { received_len, .. } => *received_len > 0,
            _ => false,
        }
    }

    /// Whether sending the request again may succeed: no reply in time, a garbled reply or
    /// a reply to something else. A refusal by the drive, a request that cannot be built
    /// and a failing transport would fail again.
    pub fn worth_repeating(&self) -> bool {
        matches!(
            self,
            TransactionErrorKind::Timeout { .. }
                | TransactionErrorKind::Decode(_)
                | TransactionErrorKind::Mismatch { .. }
        )
    }
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
    /// The value a write's reply reports written (expected: the value sent). A reply
    /// reporting another value answers an earlier write.
    Written,
    /// The number of data bytes a read's reply carries (expected: the size asked for). A
    /// reply of another size answers another read.
    DataSize,
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
            ReplyField::Written => "value written",
            ReplyField::DataSize => "data size",
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
                // The code in the manual's notation (the DV1's H0C) where the table states
                // it, else as a number and in hex.
                match info {
                    Some(info) => write!(
                        f,
                        "drive rejected {}: error {} {} ({}): {}",
                        request(),
                        info.shown(),
                        info.name,
                        info.name_zh,
                        info.meaning
                    )?,
                    None => write!(
                        f,
                        "drive rejected {}: error {code} ({code:04X}h) (code not in the manual's table)",
                        request()
                    )?,
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
                // A block read's data is counted in bytes.
                ReplyField::Data if (*expected, *found) != (1, 0) => write!(
                    f,
                    "reply to {} carries {found} byte(s) of data, expected {expected}",
                    request()
                ),
                // Parts whose presence is what is checked: say what is missing.
                ReplyField::Text | ReplyField::ProcessWords | ReplyField::Data => {
                    write!(f, "reply to {} carries no {}", request(), field.as_str())
                }
                ReplyField::Address
                | ReplyField::Register
                | ReplyField::Index
                | ReplyField::Written
                | ReplyField::DataSize => write!(
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
    use crate::kinds::CommandKind;
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
