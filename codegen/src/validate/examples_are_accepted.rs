//! Warning: an example shows the drive accepting a write that the virtual drive built from
//! the same file refuses for the register's access or storage (a write to a read-only
//! register, a persistent write to a RAM-only one).

use crate::diagnostics::Diagnostics;
use crate::frames::{register_of, space_of, DecodedFrame};
use crate::parse::model::RegisterModel;
use crate::validate::Context;
use vfd_runtime::{Access, CommandKind, DataType, Space};

/// An example whose request writes a register the way the virtual drive refuses
/// (`VirtualDrive::check_write`: read-only or text registers, persistent writes of RAM-only
/// parameters), and whose reply is not the drive's error reply.
pub fn examples_are_accepted(drive: &Context, out: &mut Diagnostics) {
    for (index, decoded) in drive.frames.iter().enumerate() {
        let Some(request) = decoded.request.as_ref().and_then(DecodedFrame::decoded) else {
            continue;
        };
        let refused_reply = decoded
            .reply
            .as_ref()
            .and_then(DecodedFrame::decoded)
            .is_some_and(|reply| reply.error_code.is_some());
        let Some(kind) = request.kind.filter(|kind| kind.is_write()) else {
            continue;
        };
        if refused_reply {
            continue;
        }
        let Some(register) = register_of(&drive.model, request) else {
            continue;
        };
        if let Some((why, hint)) = refusal(register, kind) {
            out.push(
                drive
                    .source
                    .warning(
                        &format!("examples[{index}].request"),
                        format!(
                            "the virtual drive built from this file refuses this request: {why}"
                        ),
                    )
                    .hint(hint),
            );
        }
    }
}

/// Why the virtual drive refuses a `kind` write of `register`, and what to check.
fn refusal(register: &RegisterModel, kind: CommandKind) -> Option<(String, String)> {
    let code = &register.code;
    if register.access == Some(Access::ReadOnly) {
        return Some((
            format!("{code} is read-only (`access: read-only`)"),
            "the example shows the drive taking the write; check `access` against the manual, or give the drive's error reply".to_owned(),
        ));
    }
    if register.data_type == Some(DataType::Text) {
        return Some((
            format!("{code} is text, which is only read"),
            "check `data_type` against the manual, or give the drive's error reply".to_owned(),
        ));
    }
    if kind == CommandKind::WritePersistent
        && register.ram_only
        && space_of(register) == Space::Parameter
    {
        return Some((
            format!("the write is persistent (RAM and EEPROM) and {code} is `ram_only: true`"),
            "the virtual drive answers a persistent write of a RAM-only parameter with its read-only refusal; if the manual shows the drive accepting it (and keeping the value in RAM only), `ram_only: true` says more than the manual: check it, or give the drive's error reply".to_owned(),
        ));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::examples_are_accepted as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    /// The valid drive with its example writing FA00 (RAM only) with `command`.
    fn writing_command_word(command: &str) -> String {
        valid_with(&[
            ("(R0011)\\r", &format!("({command}FA008400)\\r")),
            (
                "expect: { command: R, register: 0x0011 } }",
                &format!("expect: {{ command: {command}, register: 0xFA00, data: 0x8400 }} }}"),
            ),
            ("(R00111F40)\\r", &format!("({command}FA008400)\\r")),
            (
                "command: R, register: 0x0011, data: 0x1F40",
                &format!("command: {command}, register: 0xFA00, data: 0x8400"),
            ),
            ("    value: 80.0\n", ""),
        ])
    }

    #[test]
    fn a_persistent_write_of_a_ram_only_register_is_warned_about() {
        let yaml = writing_command_word("W");
        let found = check_yaml(check, &yaml);
        let warning = only(&found);
        assert!(warning.is_warning());
        assert_at(
            warning,
            &yaml,
            "examples[0].request",
            "the virtual drive built from this file refuses this request: the write is persistent (RAM and EEPROM) and FA00 is `ram_only: true`",
            "request:",
        );
    }

    #[test]
    fn a_ram_write_of_a_ram_only_register_and_reads_are_accepted() {
        assert!(check_yaml(check, &writing_command_word("P")).is_empty());
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn a_write_to_a_read_only_register_is_warned_about() {
        let yaml = writing_command_word("P").replace(
            "bitfield: command_word, ram_only: true",
            "bitfield: command_word, access: read-only",
        );
        let found = check_yaml(check, &yaml);
        assert_eq!(
            only(&found).message,
            "the virtual drive built from this file refuses this request: FA00 is read-only (`access: read-only`)"
        );
    }
}
