//! What an exchange with a virtual drive ended in, for assertions: the error code of a
//! refusal, or silence.

use vfd_runtime::{TransactionError, TransactionErrorKind};

/// The manual's error code of a refused exchange; panics on any other outcome.
#[track_caller]
pub fn refused<T: std::fmt::Debug>(result: Result<T, TransactionError>) -> u16 {
    match result {
        Err(TransactionError {
            kind: TransactionErrorKind::Rejected { code, .. },
            ..
        }) => code,
        other => panic!("expected an error reply, got {other:?}"),
    }
}

/// The exchange timed out: the drive stayed silent; panics on any other outcome.
#[track_caller]
pub fn timed_out<T: std::fmt::Debug>(result: Result<T, TransactionError>) {
    match result {
        Err(TransactionError {
            kind: TransactionErrorKind::Timeout { .. },
            ..
        }) => {}
        other => panic!("expected silence, got {other:?}"),
    }
}
