//! How a read or a write of a one-drive session ([`crate::session::Session`]) ended when
//! it did not succeed, typed: an exchange that failed (the library's [`crate::Error`],
//! with the session's hint on what to check), a write refused before anything was sent
//! ([`crate::Refusal`]), or something else said with a message and a hint. The service
//! core decides on these by their type and kind; the commands turn them into the tool's
//! human error at their edge (`crate::failure`).

use crate::{Refusal, SetupError};

/// How a session's read or write ended, when it did not succeed.
#[derive(Debug, Clone)]
pub enum SessionError {
    /// An exchange failed (timeout, damaged reply, error reply, I/O), or was not made
    /// because the station is offline: how, with a hint.
    Exchange(crate::Error),
    /// The write check refused the write: nothing was sent.
    Refused(Refusal),
    /// Anything else, said with a message and a hint: a step sent before a write that
    /// failed, a reply without data, a value that does not fit, a register not read.
    Said(SetupError),
}

impl SessionError {
    /// A message (and no hint) for what is neither an exchange nor a refusal.
    pub fn said(message: impl Into<String>) -> SessionError {
        SessionError::Said(SetupError::new(message))
    }

    /// With `hint` on what to do, in place of the one it had.
    pub fn with_hint(self, hint: impl Into<String>) -> SessionError {
        match self {
            SessionError::Exchange(error) => SessionError::Exchange(error.with_hint(hint)),
            SessionError::Refused(refusal) => {
                SessionError::Said(SetupError::new(refusal.message()).with_hint(hint))
            }
            SessionError::Said(said) => {
                SessionError::Said(SetupError::new(said.message()).with_hint(hint))
            }
        }
    }

    /// What went wrong, in one line.
    pub fn message(&self) -> &str {
        match self {
            SessionError::Exchange(error) => error.message(),
            SessionError::Refused(refusal) => refusal.message(),
            SessionError::Said(said) => said.message(),
        }
    }

    /// What to do about it.
    pub fn hint(&self) -> Option<&str> {
        match self {
            SessionError::Exchange(error) => error.hint(),
            SessionError::Refused(refusal) => refusal.hint(),
            SessionError::Said(said) => said.hint(),
        }
    }

    /// How the exchange failed, when one did.
    pub fn exchange(&self) -> Option<&crate::Error> {
        match self {
            SessionError::Exchange(error) => Some(error),
            _ => None,
        }
    }
}

impl From<crate::Error> for SessionError {
    fn from(error: crate::Error) -> SessionError {
        SessionError::Exchange(error)
    }
}

impl From<Refusal> for SessionError {
    fn from(refusal: Refusal) -> SessionError {
        SessionError::Refused(refusal)
    }
}

impl From<SetupError> for SessionError {
    fn from(said: SetupError) -> SessionError {
        SessionError::Said(said)
    }
}

impl std::fmt::Display for SessionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.message())
    }
}

impl std::error::Error for SessionError {}
