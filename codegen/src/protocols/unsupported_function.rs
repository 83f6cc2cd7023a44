//! What a drive answers to a function it lacks (`protocols[].unsupported_function`): the
//! error code is one of the protocol's error codes, and the protocol must be able to build
//! the reply for any function, which it can when its error replies mark the function one
//! way for every command (Modbus: function + 80h).

use super::Input;
use crate::diagnostics::Diagnostics;
use vfd_runtime::{ErrorCodeInfo, Protocol};

/// The error code the drive answers a function it lacks with; `None` when the entry
/// leaves it out or is wrong (reported to `out`).
pub(super) fn unsupported_function(
    input: &Input<'_>,
    protocol: &Protocol,
    table: &[ErrorCodeInfo],
    out: &mut Diagnostics,
) -> Option<u16> {
    let entry = input.reference.unsupported_function.as_ref()?;
    let path = format!("{}.unsupported_function", input.reference_path);
    let code = entry.error_code;
    let marked = protocol
        .commands
        .first()
        .and_then(|command| protocol.error_code_of_function(command.code));
    if protocol.error_reply.is_none() || marked.is_none() {
        out.push(
            input
                .drive_source
                .error(
                    &format!("{path}.error_code"),
                    format!(
                        "protocol `{}` cannot answer a function it lacks: its commands' error codes do not mark the function one way (Modbus: function + 80h)",
                        input.reference.uses
                    ),
                )
                .hint("leave `unsupported_function` out: the drive then stays silent, as for a frame it cannot read"),
        );
        return None;
    }
    if !table.iter().any(|known| known.code == code) {
        let codes: Vec<String> = table.iter().map(|c| format!("{:02X}h", c.code)).collect();
        out.push(
            input
                .drive_source
                .error(
                    &format!("{path}.error_code"),
                    format!(
                        "error code {code:02X}h is not one of protocol `{}`'s error codes ({})",
                        input.reference.id,
                        codes.join(", ")
                    ),
                )
                .hint("the code the manual's error table gives for a function the drive does not carry out (Modbus: 01h, illegal function)"),
        );
        return None;
    }
    Some(code)
}
