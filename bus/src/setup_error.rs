//! Why something cannot be set up, before any line is used: a drive, protocol, register or
//! port that is not there, line settings a drive cannot take, a port that does not open. A
//! message for people and, where one helps, a hint on what to do.

use std::fmt;

/// A setup that cannot be made, and what to do about it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SetupError {
    message: String,
    hint: Option<String>,
}

impl SetupError {
    /// A problem saying `message`.
    pub fn new(message: impl Into<String>) -> SetupError {
        SetupError {
            message: message.into(),
            hint: None,
        }
    }

    /// With a hint on what to do (replacing one it had).
    pub fn with_hint(mut self, hint: impl Into<String>) -> SetupError {
        self.hint = Some(hint.into());
        self
    }

    /// What is wrong, for people (one line, without the hint).
    pub fn message(&self) -> &str {
        &self.message
    }

    /// What to do about it, where something helps.
    pub fn hint(&self) -> Option<&str> {
        self.hint.as_deref()
    }

    /// The message and the hint.
    pub fn into_parts(self) -> (String, Option<String>) {
        (self.message, self.hint)
    }

    /// The message with its hint in brackets, as one line.
    pub fn with_hint_text(&self) -> String {
        match &self.hint {
            Some(hint) => format!("{} ({hint})", self.message),
            None => self.message.clone(),
        }
    }
}

impl fmt::Display for SetupError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for SetupError {}
