//! Error tables: which one names a protocol's error replies (the drive's protocol entry's
//! own, else the drive's for the protocols it applies to, else the protocol file's), and the
//! checks on a protocol's own table (each code and id once).

use super::Input;
use crate::diagnostics::Diagnostics;
use crate::parse::model::{CodeNotationModel, DriveFile, ErrorCodeModel, ProtocolErrorCodesModel};
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

/// The error codes the protocol's error replies are named with, as the runtime holds them:
/// the drive's protocol entry's own table, else the drive's (where it applies), else the
/// protocol file's.
pub(super) fn error_table(input: &Input<'_>) -> Vec<ErrorCodeInfo> {
    let (codes, notation): (&[ErrorCodeModel], _) =
        if let Some(table) = &input.reference.error_codes {
            (&table.codes, table.notation.as_ref())
        } else if drive_table_applies(input.drive, &input.reference.id) {
            (
                &input.drive.error_codes.codes,
                input.drive.error_codes.notation.as_ref(),
            )
        } else {
            input
                .file
                .error_codes
                .as_ref()
                .map_or((&[], None), |table| (&table.codes, table.notation.as_ref()))
        };
    codes
        .iter()
        .map(|code| runtime_entry(code, notation))
        .collect()
}

fn runtime_entry(code: &ErrorCodeModel, notation: Option<&CodeNotationModel>) -> ErrorCodeInfo {
    ErrorCodeInfo {
        code: code.code as u16,
        id: Cow::Owned(code.id.clone()),
        name: Cow::Owned(code.name.clone()),
        name_zh: Cow::Owned(code.name_zh.clone()),
        meaning: Cow::Owned(code.meaning.clone()),
        printed_as: Cow::Owned(notation.map_or_else(String::new, |n| n.print(code.code))),
    }
}

/// A protocol's own tables (the protocol file's, and the drive's protocol entry's) describe
/// each code and each id once, and their codes fit the 16 bits an error reply carries. A
/// drive's protocol entry with a table of its own is not also named by the drive's table.
pub(super) fn check_error_codes(input: &Input<'_>, out: &mut Diagnostics) {
    if let Some(table) = &input.file.error_codes {
        check_table(table, "error_codes", input.source, out);
    }
    let Some(table) = &input.reference.error_codes else {
        return;
    };
    let at = format!("{}.error_codes", input.reference_path);
    check_table(table, &at, input.drive_source, out);
    let listed = input.drive.error_codes.protocols.as_ref();
    if listed.is_some_and(|ids| ids.contains(&input.reference.id)) {
        out.push(
            input
                .drive_source
                .error(
                    &at,
                    format!(
                        "protocol `{}` has an error table of its own, and the drive's `error_codes.protocols` lists it too",
                        input.reference.id
                    ),
                )
                .hint("name each protocol's error replies from one table: drop it from error_codes.protocols"),
        );
    }
}

/// A table's `notation` prints at least one digit and at most eight (a code has 16 bits).
pub(crate) fn check_notation(
    notation: Option<&CodeNotationModel>,
    at: &str,
    source: &SourceFile,
    out: &mut Diagnostics,
) {
    if let Some(digits) = notation.map(|n| n.digits).filter(|d| !(1..=8).contains(d)) {
        out.push(
            source
                .error(
                    &format!("{at}.notation.digits"),
                    format!("{digits} digits: a code is printed with 1 to 8"),
                )
                .hint("give the fewest digits the manual prints (H0C: `{ prefix: H, digits: 2 }`)"),
        );
    }
}

fn check_table(
    table: &ProtocolErrorCodesModel,
    at: &str,
    source: &SourceFile,
    out: &mut Diagnostics,
) {
    check_notation(table.notation.as_ref(), at, source, out);
    for (j, code) in table.codes.iter().enumerate() {
        let path = |key: &str| format!("{at}.codes[{j}].{key}");
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
                            "error code {:02X}h appears twice (first at {at}.codes[{i}])",
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
                            "duplicate error code id `{}` (first at {at}.codes[{i}].id)",
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
    use super::super::test_support::{
        at, drive_with, lower_both, problems, problems_of, protocol_with,
    };

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

    #[test]
    fn a_drive_protocol_entry_may_bring_its_own_table() {
        let drive = drive_with("    error_codes: { source: \"5.3\", codes: [{ code: 3, id: data_range, name: Data range error, meaning: Out of range. }] }");
        let protocol = lower_both(&drive, &with_table(TABLE)).unwrap();
        assert_eq!(names(&protocol), [(3, "Data range error".to_owned())]);
        let listed = drive.replace(
            "error_codes:\n  source: \"3.2\"\n",
            "error_codes:\n  source: \"3.2\"\n  protocols: [ascii]\n",
        );
        let problems = problems_of(lower_both(&listed, &with_table(TABLE)));
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(
            problems[0].contains(
                "protocols[0].error_codes: protocol `ascii` has an error table of its own"
            ),
            "{problems:?}"
        );
    }
}
