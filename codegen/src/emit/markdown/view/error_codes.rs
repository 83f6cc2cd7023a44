//! Error replies: the drive's table and each protocol's own, codes written as the manual
//! prints them or with as many hex digits as the protocol's error field has.

use crate::ir::*;
use serde::Serialize;
use vfd_runtime::Role;

#[derive(Serialize)]
pub(super) struct ErrorCodesView<'a> {
    #[serde(flatten)]
    error_codes: &'a ErrorCodesIr,
    codes: Vec<ErrorCodeView<'a>>,
    /// The protocols it applies to, as `` `fc`, `modbus` ``.
    protocols_display: String,
}

#[derive(Serialize)]
pub(super) struct ProtocolErrorsView<'a> {
    id: &'a str,
    name: &'a str,
    table: ErrorCodesView<'a>,
}

/// The error codes of `table`, each written with `digits` hex digits (the width of the
/// error-code field of the protocols it serves: `01h` for a Modbus byte, `0001h` for a
/// four-digit word).
pub(super) fn error_codes_view(table: &ErrorCodesIr, digits: usize) -> ErrorCodesView<'_> {
    ErrorCodesView {
        error_codes: table,
        codes: table
            .codes
            .iter()
            .map(|code| ErrorCodeView {
                code,
                code_hex: if code.printed.is_empty() {
                    format!("{:0digits$X}h", code.code)
                } else {
                    code.printed.clone()
                },
            })
            .collect(),
        protocols_display: table
            .protocols
            .iter()
            .map(|id| format!("`{id}`"))
            .collect::<Vec<_>>()
            .join(", "),
    }
}

#[derive(Serialize)]
struct ErrorCodeView<'a> {
    #[serde(flatten)]
    code: &'a ErrorCodeIr,
    code_hex: String,
}

/// `code`, an error code of `protocol`, as the manual prints it (its table's `notation`:
/// the DV1's H0C), else in hex with [`error_code_digits`] digits and `h`.
pub(super) fn printed_error(drive: &DriveIr, protocol: &ProtocolIr, code: u16) -> String {
    let table = match &protocol.error_table {
        ErrorTableIr::Drive => &drive.error_codes,
        ErrorTableIr::Protocol(table) => table,
    };
    table
        .codes
        .iter()
        .find(|c| c.code == code && !c.printed.is_empty())
        .map_or_else(
            || format!("{:0w$X}h", code, w = error_code_digits(drive, protocol)),
            |c| c.printed.clone(),
        )
}

/// How many hex digits an error code of `protocol` is written with: two when its error
/// reply carries the code in one byte (or two digits), else four.
pub(super) fn error_code_digits(drive: &DriveIr, protocol: &ProtocolIr) -> usize {
    use vfd_runtime::layout::{Format, Part};
    let layout = protocol.error_reply.as_deref().and_then(|name| {
        drive
            .protocol_files
            .iter()
            .find(|f| f.id == protocol.uses)
            .and_then(|f| f.layouts.iter().find(|l| l.name == name))
    });
    let one_byte = layout.is_some_and(|layout| {
        layout.parts.iter().any(|part| {
            matches!(part, Part::Field(field) if field.role == Role::ErrorCode
                && (matches!(field.format, Format::U8 | Format::Char)
                    || (field.format.is_digits() && field.width <= 2)))
        })
    });
    if one_byte {
        2
    } else {
        4
    }
}

/// The protocols the drive's table does not apply to, with the tables they use.
pub(super) fn protocol_error_tables(drive: &DriveIr) -> Vec<ProtocolErrorsView<'_>> {
    drive
        .protocols
        .iter()
        .filter_map(|p| match &p.error_table {
            ErrorTableIr::Drive => None,
            ErrorTableIr::Protocol(table) => Some(ProtocolErrorsView {
                id: &p.id,
                name: &p.name,
                table: error_codes_view(table, error_code_digits(drive, p)),
            }),
        })
        .collect()
}
