//! The reader's serde error: a complaint to report at the node being read, or one already
//! reported.

use serde::de;
use std::fmt;

/// An error while reading: either already reported, or a visitor's complaint to report at
/// the node being read.
#[derive(Debug)]
pub struct Error(pub(super) Complaint);

#[derive(Debug)]
pub(super) enum Complaint {
    Reported,
    Message(String),
    MissingKey(&'static str),
    UnknownKey(String, &'static [&'static str]),
    UnknownValue(String, &'static [&'static str]),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.0 {
            Complaint::Reported => f.write_str("reported"),
            Complaint::Message(message) => f.write_str(message),
            Complaint::MissingKey(key) => write!(f, "missing key `{key}`"),
            Complaint::UnknownKey(key, _) => write!(f, "unknown key `{key}`"),
            Complaint::UnknownValue(value, _) => write!(f, "unknown value `{value}`"),
        }
    }
}

impl std::error::Error for Error {}

impl de::Error for Error {
    fn custom<M: fmt::Display>(message: M) -> Self {
        Error(Complaint::Message(message.to_string()))
    }

    fn missing_field(field: &'static str) -> Self {
        Error(Complaint::MissingKey(field))
    }

    fn unknown_field(field: &str, expected: &'static [&'static str]) -> Self {
        Error(Complaint::UnknownKey(field.to_owned(), expected))
    }

    fn unknown_variant(variant: &str, expected: &'static [&'static str]) -> Self {
        Error(Complaint::UnknownValue(variant.to_owned(), expected))
    }
}

pub(super) const REPORTED: Error = Error(Complaint::Reported);
