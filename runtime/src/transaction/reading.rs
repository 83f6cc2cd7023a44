//! A typed value read from a drive ([`Reading`]), and the conversions between an
//! [`Answer`] and the typed values of reads and writes.

use super::answer::{for_decimals, Answer};
use super::error::{ReplyField, TransactionError, TransactionErrorKind};
use crate::register::{Register, RegisterValue, Request};
use std::fmt;

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

/// The typed value of register `R` a read's answer carries; an answer without data does not
/// answer a read.
pub(crate) fn value_read<R: Register>(
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
    // A reply stating its decimals (checked against the register's scales) picks the scale
    // of a register whose scale another register chooses.
    let info = match answer.decimals {
        Some(decimals) => for_decimals(R::INFO, decimals)?,
        None => R::INFO,
    };
    Ok(Reading {
        value: R::Value::from_raw(data, info)?,
        tripped: answer.tripped,
    })
}

/// The typed value a write's answer reports written, if it carries one.
pub(crate) fn value_written<R: Register>(
    answer: Answer,
) -> Result<Option<R::Value>, TransactionError> {
    Ok(answer
        .data
        .map(|data| R::Value::from_raw(data, R::INFO))
        .transpose()?)
}
