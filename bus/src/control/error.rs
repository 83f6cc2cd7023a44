//! How a control operation ends when it does not succeed: the drive lacks the role, it is
//! tripped (run refused, with the trip), or the read or write failed or was refused.

use super::state::Trip;
use crate::session_error::SessionError;

/// A control operation that did not succeed.
#[derive(Debug, Clone)]
pub enum ControlError {
    /// The drive cannot do this on command (no coast, no reset, no reverse).
    Unsupported {
        /// The drive's id.
        drive: &'static str,
        /// The role it lacks.
        role: &'static str,
    },
    /// Running was refused: the drive is tripped (reset it first).
    Tripped(Option<Trip>),
    /// A read or write failed, or the write check refused it (nothing sent).
    Session(SessionError),
}

impl ControlError {
    /// What went wrong, in one line.
    pub fn message(&self) -> String {
        match self {
            ControlError::Unsupported { drive, role } => {
                format!("drive {drive} has no {role} command in its description")
            }
            ControlError::Tripped(Some(trip)) => format!(
                "the drive is tripped ({}: {}); nothing was sent",
                trip.code, trip.name
            ),
            ControlError::Tripped(None) => "the drive is tripped; nothing was sent".to_owned(),
            ControlError::Session(error) => error.message().to_owned(),
        }
    }

    /// What to do about it.
    pub fn hint(&self) -> Option<String> {
        match self {
            ControlError::Unsupported { .. } => None,
            ControlError::Tripped(_) => {
                Some("clear the cause, then reset the trip (`vfd reset`)".to_owned())
            }
            ControlError::Session(error) => error.hint().map(str::to_owned),
        }
    }
}

impl std::fmt::Display for ControlError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message())
    }
}

impl std::error::Error for ControlError {}

impl From<SessionError> for ControlError {
    fn from(error: SessionError) -> ControlError {
        ControlError::Session(error)
    }
}
