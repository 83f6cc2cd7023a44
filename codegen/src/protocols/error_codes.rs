//! Error tables: which one names a protocol's error replies (the drive's, for the protocols
//! it applies to; otherwise the protocol file's own), and the checks on a protocol file's
//! own table (each code and id once).

use super::Input;
use crate::diagnostics::Diagnostics;
use crate::parse::model::{DriveFile, ErrorCodeModel, ProtocolFile};
use crate::parse::SourceFile;
use std::borrow::Cow;
use vfd_runtime::ErrorCodeInfo;

/// Whether the drive's own error table names the error replies of its protocol `id`: it
/// does for the protocols its `error_codes.protocols` lists, or for all when that is left out.
pub(crate) fn drive_table_applies(drive: &DriveFile, id: &str) -> bool {
    drive
        .error_codes
        .protocols
        .as_ref()
        .is_none_or(|ids| ids.iter().any(|listed| listed == id))
}

/// The error codes the protocol's error replies are named with, as the runtime holds them.
pub(super) fn error_table(input: &Input<'_>) -> Vec<ErrorCodeInfo> {
    let codes: &[ErrorCodeModel] = if drive_table_applies(input.drive, &input.reference.id) {
        &input.drive.error_codes.codes
    } else {
        input
            .file
            .error_codes
            .as_ref()
            .map_or(&[], |table| &table.codes)
    };
    codes.iter().map(runtime_entry).collect()
}

fn runtime_entry(code: &ErrorCodeModel) -> ErrorCodeInfo {
    ErrorCodeInfo {
        code: code.code as u16,
        id: Cow::Owned(code.id.clone()),
        name: Cow::Owned(code.name.clone()),
        name_zh: Cow::Owned(code.name_zh.clone()),
        meaning: Cow::Owned(code.meaning.clone()),
    }
}

/// A protocol file's own table describes each code and each id once, and its codes fit
/// the 16 bits an error reply carries.
pub(super) fn check_error_codes(file: &ProtocolFile, source: &SourceFile, out: &mut Diagnostics) {
    let Some(table) = &file.error_codes else {
        return;
    };
    for (j, code) in table.codes.iter().enumerate() {
        let path = |key: &str| format!("error_codes.codes[{j}].{key}");
        if code.code > u32::from(u16::MAX) {
            out.push(
                source
                    .error(
                        &path("code"),
                        format!("error code {:#X} does not fit 16 bits", code.code),
                    )
                    .hint("error replies carry codes up to FFFFh"),
            );
        }
        if let Some(i) = table.codes[..j].iter().position(|c| c.code == code.code) {
            out.push(
                source
                    .error(
                        &path("code"),
                        format!(
                            "error code {:02X}h appears twice (first at error_codes.codes[{i}])",
                            code.code
                        ),
                    )
                    .hint("describe each code once"),
            );
        }
        if let Some(i) = table.codes[..j].iter().position(|c| c.id == code.id) {
            out.push(
                source
                    .error(
                        &path("id"),
                        format!(
                            "duplicate error code id `{}` (first at error_codes.codes[{i}].id)",
                            code.id
                        ),
                    )
                    .hint("give each code its own id"),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{at, drive_with, lower_both, problems, protocol_with};

    const TABLE: &str = "error_codes:\n  source: spec\n  codes:\n    - { code: 1, id: bad_function, name: Bad function, meaning: Unknown function. }\n    - { code: 2, id: bad_address, name: Bad address, meaning: Unknown register. }\n";

    fn with_table(table: &str) -> String {
        protocol_with(&[(
            "error_reply: error_reply\n",
            &format!("error_reply: error_reply\n{table}"),
        )])
    }

    fn names(protocol: &vfd_runtime::Protocol) -> Vec<(u16, String)> {
        protocol
            .error_codes
            .iter()
            .map(|c| (c.code, c.name.to_string()))
            .collect()
    }

    #[test]
    fn the_drive_table_names_the_errors_of_the_protocols_it_applies_to() {
        // Left out, `protocols` means every protocol of the drive.
        let protocol = lower_both(&drive_with(""), &with_table(TABLE)).unwrap();
        assert_eq!(names(&protocol), [(1, "Data error".to_owned())]);
        let listed = drive_with("").replace(
            "error_codes:\n  source: \"3.2\"\n",
            "error_codes:\n  source: \"3.2\"\n  protocols: [ascii]\n",
        );
        let protocol = lower_both(&listed, &with_table(TABLE)).unwrap();
        assert_eq!(names(&protocol), [(1, "Data error".to_owned())]);
    }

    #[test]
    fn other_protocols_take_their_own_table() {
        let unlisted = drive_with("").replace(
            "error_codes:\n  source: \"3.2\"\n",
            "error_codes:\n  source: \"3.2\"\n  protocols: []\n",
        );
        let protocol = lower_both(&unlisted, &with_table(TABLE)).unwrap();
        assert_eq!(
            names(&protocol),
            [
                (1, "Bad function".to_owned()),
                (2, "Bad address".to_owned())
            ]
        );
        assert_eq!(
            protocol.error_code(2).map(|c| c.name.as_ref()),
            Some("Bad address")
        );
        // No table of its own: its error replies are shown by number only.
        let protocol = lower_both(&unlisted, &protocol_with(&[])).unwrap();
        assert!(protocol.error_codes.is_empty());
    }

    #[test]
    fn a_protocol_table_describes_each_code_and_id_once() {
        let yaml = with_table(&format!(
            "{TABLE}    - {{ code: 0x01, id: bad_address, name: Twice, meaning: Again. }}\n"
        ));
        assert_eq!(
            problems(&yaml),
            [
                format!(
                    "{} error_codes.codes[2].code: error code 01h appears twice (first at error_codes.codes[0])",
                    at(&yaml, "0x01")
                ),
                format!(
                    "{} error_codes.codes[2].id: duplicate error code id `bad_address` (first at error_codes.codes[1].id)",
                    at(&yaml, "bad_address, name: Twice")
                ),
            ]
        );
    }
}
