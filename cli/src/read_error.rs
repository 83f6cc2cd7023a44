//! A failed exchange as the machine-readable records name it ([`ReadError`]): its kind
//! (`timeout`, `bad_reply`, `error_reply`, `mismatch`, `io`, `other`), the error reply's code
//! and the manual's meaning of it.

use crate::record::ReadError;
use vfd_runtime::{TransactionError, TransactionErrorKind};

/// The kind, code and meaning of `error`.
pub fn read_error(error: &TransactionError) -> ReadError {
    let (kind, code, meaning) = match &error.kind {
        TransactionErrorKind::Timeout { .. } if error.kind.garbled_reply() => {
            ("bad_reply", None, error.to_string())
        }
        TransactionErrorKind::Timeout { .. } => ("timeout", None, error.to_string()),
        TransactionErrorKind::Decode(_) => ("bad_reply", None, error.to_string()),
        TransactionErrorKind::Rejected { code, info, .. } => (
            "error_reply",
            Some(*code),
            match info {
                Some(info) if info.name_zh.is_empty() => {
                    format!("{}: {}", info.name, info.meaning)
                }
                Some(info) => format!("{} ({}): {}", info.name, info.name_zh, info.meaning),
                None => error.to_string(),
            },
        ),
        TransactionErrorKind::Mismatch { .. } => ("mismatch", None, error.to_string()),
        TransactionErrorKind::Io(_) => ("io", None, error.to_string()),
        _ => ("other", None, error.to_string()),
    };
    ReadError {
        kind,
        code,
        meaning,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;
    use vfd_runtime::info::ErrorCodeInfo;

    fn kind_of(kind: TransactionErrorKind) -> ReadError {
        read_error(&TransactionError::new(None, kind))
    }

    #[test]
    fn each_failure_has_its_kind() {
        let silent = kind_of(TransactionErrorKind::Timeout {
            waited: Duration::from_millis(100),
            received: Vec::new(),
            received_len: 0,
            last_error: None,
        });
        assert_eq!(silent.kind, "timeout");
        let garbled = kind_of(TransactionErrorKind::Timeout {
            waited: Duration::from_millis(100),
            received: vec![0xFF],
            received_len: 1,
            last_error: None,
        });
        assert_eq!(garbled.kind, "bad_reply");
        let unplugged = kind_of(TransactionErrorKind::Io(std::io::Error::from_raw_os_error(
            5,
        )));
        assert_eq!(unplugged.kind, "io");
        assert!(unplugged.is_io());
        assert!(!silent.is_io());
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
        assert_eq!(refused.kind, "error_reply");
        assert_eq!(refused.code, Some(6));
        assert_eq!(refused.meaning, "Busy (忙): The drive is busy.");
    }
}
