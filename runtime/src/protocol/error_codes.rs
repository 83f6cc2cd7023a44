//! The drive's error codes: the table entry for a code, the code an error reply carries,
//! and the error reply to a function the drive lacks.

use super::Protocol;
use crate::info::ErrorCodeInfo;
use crate::layout::{FrameLayout, Part, Role};
use std::borrow::Cow;

impl Protocol {
    /// The error-code table entry for `code`.
    pub fn error_code(&self, code: u16) -> Option<&ErrorCodeInfo> {
        self.error_codes.iter().find(|entry| entry.code == code)
    }

    /// The code an error reply carries for a request with the function `code`, when every
    /// command's error code is its own code moved by one offset (Modbus: function + 80h),
    /// which then holds for any function; `None` when the commands have no error codes or
    /// no common offset.
    pub fn error_code_of_function(&self, code: u32) -> Option<u32> {
        let mut offsets = self.commands.iter().map(|command| {
            command
                .error_code
                .map(|error| error.wrapping_sub(command.code))
        });
        let first = offsets.next()??;
        offsets
            .all(|offset| offset == Some(first))
            .then(|| code.wrapping_add(first))
    }

    /// The error-reply layout as the drive sends it to a function it lacks
    /// ([`Protocol::unsupported_function`]): its function field takes any function (the
    /// request's, marked as [`Protocol::error_code_of_function`] marks it), not only the
    /// codes the protocol file lists. `None` when the drive gives no such reply.
    pub fn lacking_function_reply(&self) -> Option<FrameLayout> {
        self.unsupported_function?;
        let error = self.error_reply.as_ref()?;
        let function_at = error.index_of(Role::Command)?;
        let mut parts: Vec<Part> = error.parts.to_vec();
        if let Part::Field(field) = &mut parts[function_at] {
            field.allowed = Cow::Borrowed(&[]);
        }
        Some(FrameLayout {
            parts: Cow::Owned(parts),
            plan: None,
            ..error.clone()
        })
    }

    /// Whether an error reply with the function field `code` and the error code `error` is
    /// the drive's answer to a function it lacks: `error` is
    /// [`Protocol::unsupported_function`]'s and `code` marks a function that none of the
    /// drive's commands has (Modbus: 81h with exception 01 from a drive without 01).
    pub fn is_lacking_function_reply(&self, code: u32, error: u32) -> bool {
        let Some(unsupported) = self.unsupported_function else {
            return false;
        };
        let Some(offset) = self.error_code_of_function(0) else {
            return false;
        };
        let Some(function) = code.checked_sub(offset) else {
            return false;
        };
        error == u32::from(unsupported)
            && self.error_code_of_function(function) == Some(code)
            && !self.commands.iter().any(|c| c.answers_to(function))
    }
}
