//! How a read or a write ends when it does not succeed: one typed error for the tool, the
//! service and any program, its kind ([`ErrorKind`], with a stable snake_case name for
//! JSON), a message for people, a hint where one helps, and for the drive's error reply its
//! code and the manual's meaning of it.

use serde::Serialize;
use std::fmt;
use vfd_runtime::{TransactionError, TransactionErrorKind};

/// How a read or write ended, as machine-readable output names it (`error_kind` of a
/// record, docs/output.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorKind {
    /// No reply came in time.
    Timeout,
    /// A reply came, damaged or garbled.
    BadReply,
    /// The drive refused with an error reply (its code and the manual's meaning given).
    ErrorReply,
    /// A reply to something else (another station, another register).
    Mismatch,
    /// The port failed or cannot be opened (an unplugged adapter, a lost connection).
    Io,
    /// Refused before anything was sent: the write check said no ([`crate::Refusal`]).
    Refused,
    /// Not sent: the station is offline (it did not answer the last exchanges).
    Offline,
    /// Anything else: a request the protocol cannot make, a reply without the data asked.
    Other,
}

impl ErrorKind {
    /// The kind's name in JSON and CSV output (`timeout`, `bad_reply`, `error_reply`,
    /// `mismatch`, `io`, `refused`, `offline`, `other`).
    pub const fn name(self) -> &'static str {
        match self {
            ErrorKind::Timeout => "timeout",
            ErrorKind::BadReply => "bad_reply",
            ErrorKind::ErrorReply => "error_reply",
            ErrorKind::Mismatch => "mismatch",
            ErrorKind::Io => "io",
            ErrorKind::Refused => "refused",
            ErrorKind::Offline => "offline",
            ErrorKind::Other => "other",
        }
    }

    /// Whether the request's frame went out on the line: the exchange itself failed (no
    /// reply, a bad one, a refusal, a failed port), as opposed to a request refused or not
    /// made before sending. A write that went out may have been carried out.
    pub const fn sent(self) -> bool {
        matches!(
            self,
            ErrorKind::Timeout
                | ErrorKind::BadReply
                | ErrorKind::ErrorReply
                | ErrorKind::Mismatch
                | ErrorKind::Io
        )
    }

    /// Whether the line itself failed (reopen the port).
    pub const fn is_io(self) -> bool {
        matches!(self, ErrorKind::Io)
    }

    /// Whether the drive answered, with a refusal: it is there.
    pub const fn answered(self) -> bool {
        matches!(self, ErrorKind::ErrorReply)
    }

    /// Whether a request of a block the drive did not read is worth making one register at a
    /// time: the drive refused it (an error reply), or the protocol could not make it. No
    /// answer, a damaged one or a failed line would only cost as long again per register.
    pub const fn worth_splitting(self) -> bool {
        matches!(self, ErrorKind::ErrorReply | ErrorKind::Other)
    }
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// How a read or write ended when it did not succeed (two words: the kind and its details
/// boxed, so that a `Result` carrying it stays small).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Error {
    kind: ErrorKind,
    details: Box<Details>,
}

/// What an [`Error`] says beyond its kind.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Details {
    message: String,
    hint: Option<String>,
    code: Option<u16>,
    meaning: Option<String>,
}

impl Error {
    /// An error of `kind` saying `message`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error {
            kind,
            details: Box::new(Details {
                message: message.into(),
                hint: None,
                code: None,
                meaning: None,
            }),
        }
    }

    /// With a hint on what to do (replacing one it had).
    pub fn with_hint(mut self, hint: impl Into<String>) -> Error {
        self.details.hint = Some(hint.into());
        self
    }

    /// With `hint`, or without one.
    pub fn with_hint_or_none(mut self, hint: Option<String>) -> Error {
        self.details.hint = hint;
        self
    }

    /// With another message, keeping the kind, the code and the meaning.
    pub fn with_message(mut self, message: impl Into<String>) -> Error {
        self.details.message = message.into();
        self
    }

    /// The error of a failed exchange: its kind, its message, and for an error reply the
    /// code and the manual's meaning of it. Without a hint: the station that made the
    /// exchange knows what to suggest (the tool adds its own).
    pub fn from_transaction(error: &TransactionError) -> Error {
        let (kind, code, meaning) = match &error.kind {
            TransactionErrorKind::Timeout { .. } if error.kind.garbled_reply() => {
                (ErrorKind::BadReply, None, None)
            }
            TransactionErrorKind::Timeout { .. } => (ErrorKind::Timeout, None, None),
            TransactionErrorKind::Decode(_) => (ErrorKind::BadReply, None, None),
            TransactionErrorKind::Rejected { code, info, .. } => (
                ErrorKind::ErrorReply,
                Some(*code),
                info.map(|info| {
                    if info.name_zh.is_empty() {
                        format!("{}: {}", info.name, info.meaning)
                    } else {
                        format!("{} ({}): {}", info.name, info.name_zh, info.meaning)
                    }
                }),
            ),
            TransactionErrorKind::Mismatch { .. } => (ErrorKind::Mismatch, None, None),
            TransactionErrorKind::Io(_) => (ErrorKind::Io, None, None),
            _ => (ErrorKind::Other, None, None),
        };
        Error {
            kind,
            details: Box::new(Details {
                message: error.to_string(),
                hint: None,
                code,
                meaning,
            }),
        }
    }

    /// How it ended.
    pub fn kind(&self) -> ErrorKind {
        self.kind
    }

    /// What went wrong, for people (one line, without the hint).
    pub fn message(&self) -> &str {
        &self.details.message
    }

    /// What to do about it, where something helps.
    pub fn hint(&self) -> Option<&str> {
        self.details.hint.as_deref()
    }

    /// The drive's error code, when it refused with an error reply.
    pub fn code(&self) -> Option<u16> {
        self.details.code
    }

    /// The manual's meaning of the error code (`Busy (忙): The drive is busy.`), else the
    /// message.
    pub fn meaning(&self) -> &str {
        self.details
            .meaning
            .as_deref()
            .unwrap_or(&self.details.message)
    }

    /// The message with its hint in brackets, as one line (`… (check the wiring)`).
    pub fn with_hint_text(&self) -> String {
        match &self.details.hint {
            Some(hint) => format!("{} ({hint})", self.details.message),
            None => self.details.message.clone(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.details.message)
    }
}

impl std::error::Error for Error {}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;
    use vfd_runtime::info::ErrorCodeInfo;

    fn kind_of(kind: TransactionErrorKind) -> Error {
        Error::from_transaction(&TransactionError::new(None, kind))
    }

    #[test]
    fn each_failure_has_its_kind() {
        let silent = kind_of(TransactionErrorKind::Timeout {
            waited: Duration::from_millis(100),
            received: Vec::new(),
            received_len: 0,
            last_error: None,
        });
        assert_eq!(silent.kind(), ErrorKind::Timeout);
        assert_eq!(silent.kind().name(), "timeout");
        let garbled = kind_of(TransactionErrorKind::Timeout {
            waited: Duration::from_millis(100),
            received: vec![0xFF],
            received_len: 1,
            last_error: None,
        });
        assert_eq!(garbled.kind().name(), "bad_reply");
        let unplugged = kind_of(TransactionErrorKind::Io(std::io::Error::from_raw_os_error(
            5,
        )));
        assert_eq!(unplugged.kind().name(), "io");
        assert!(unplugged.kind().is_io());
        assert!(!silent.kind().is_io());
        assert_eq!(silent.meaning(), silent.message());
    }

    #[test]
    fn an_error_reply_carries_its_code_and_the_manuals_meaning() {
        static BUSY: ErrorCodeInfo = ErrorCodeInfo {
            code: 6,
            id: std::borrow::Cow::Borrowed("busy"),
            name: std::borrow::Cow::Borrowed("Busy"),
            name_zh: std::borrow::Cow::Borrowed("忙"),
            meaning: std::borrow::Cow::Borrowed("The drive is busy."),
            printed_as: std::borrow::Cow::Borrowed(""),
        };
        let refused = kind_of(TransactionErrorKind::Rejected {
            code: 6,
            info: Some(&BUSY),
            tripped: false,
        });
        assert_eq!(refused.kind().name(), "error_reply");
        assert_eq!(refused.code(), Some(6));
        assert_eq!(refused.meaning(), "Busy (忙): The drive is busy.");
        assert!(refused.kind().sent() && refused.kind().answered());
    }

    #[test]
    fn kinds_serialize_with_their_names() {
        for kind in [
            ErrorKind::Timeout,
            ErrorKind::BadReply,
            ErrorKind::ErrorReply,
            ErrorKind::Mismatch,
            ErrorKind::Io,
            ErrorKind::Refused,
            ErrorKind::Offline,
            ErrorKind::Other,
        ] {
            assert_eq!(
                serde_json::to_string(&kind).unwrap(),
                format!("\"{}\"", kind.name())
            );
        }
    }
}
