//! The drive's error codes: the table entry for a code, the code an error reply carries.

use super::Protocol;
use crate::info::ErrorCodeInfo;

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
}
