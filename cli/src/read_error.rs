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
