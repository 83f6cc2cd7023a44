//! The tool's error for people, at the CLI's edge: one line saying what went wrong and,
//! where one helps, a hint on what to do, printed by `main` as `vfd: error: …` / `hint: …`.
//! The library's typed errors ([`vfd_bus::SetupError`], [`vfd_bus::Refusal`],
//! [`vfd_bus::Error`]) become one here; the library itself never sees this type.

use vfd_bus::SetupError;

/// A failure for people: one line, and a hint when one helps.
#[derive(Debug, Clone)]
pub struct Failure {
    /// What went wrong, in one line.
    pub message: String,
    /// What to do about it.
    pub hint: Option<String>,
    /// How the read or write failed, when one did (for `watch`).
    pub error: Option<vfd_bus::Error>,
}

impl Failure {
    /// A failure with this message.
    pub fn new(message: impl Into<String>) -> Failure {
        Failure {
            message: message.into(),
            hint: None,
            error: None,
        }
    }

    /// With a hint on what to do.
    pub fn hint(mut self, hint: impl Into<String>) -> Failure {
        self.hint = Some(hint.into());
        self
    }
}

impl From<String> for Failure {
    fn from(message: String) -> Failure {
        Failure::new(message)
    }
}

impl From<SetupError> for Failure {
    fn from(error: SetupError) -> Failure {
        let (message, hint) = error.into_parts();
        Failure {
            message,
            hint,
            error: None,
        }
    }
}

impl From<vfd_bus::Refusal> for Failure {
    fn from(refusal: vfd_bus::Refusal) -> Failure {
        let (message, hint) = refusal.into_parts();
        Failure {
            message,
            hint,
            error: None,
        }
    }
}

impl From<vfd_bus::Error> for Failure {
    fn from(error: vfd_bus::Error) -> Failure {
        Failure {
            message: error.message().to_owned(),
            hint: error.hint().map(str::to_owned),
            error: Some(error),
        }
    }
}

impl From<vfd_bus::session_error::SessionError> for Failure {
    fn from(error: vfd_bus::session_error::SessionError) -> Failure {
        use vfd_bus::session_error::SessionError;
        match error {
            SessionError::Exchange(error) => error.into(),
            SessionError::Refused(refusal) => refusal.into(),
            SessionError::Said(said) => said.into(),
        }
    }
}
