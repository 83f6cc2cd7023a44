//! Code tables: each value in hex with what it sets on the line, and links to a table.

use crate::ir::*;
use serde::Serialize;

#[derive(Serialize)]
pub(super) struct CodeTableView<'a> {
    #[serde(flatten)]
    table: &'a CodeTableIr,
    values: Vec<CodeValueView<'a>>,
}

#[derive(Serialize)]
struct CodeValueView<'a> {
    #[serde(flatten)]
    value: &'a CodeValueIr,
    value_hex: String,
    /// What it sets on the line and which protocol it chooses, where it says.
    sets: String,
}

/// A link to the code table `id` on the page (`[Trip codes](#code-table-trip_code)`), when
/// the drive has it.
pub(super) fn code_table_link(drive: &DriveIr, id: Option<&str>) -> Option<String> {
    let table = drive
        .code_tables
        .iter()
        .find(|t| Some(t.id.as_str()) == id)?;
    Some(format!("[{}](#code-table-{})", table.name, table.id))
}

/// What a code value sets on the line and which protocol it chooses (` — line 7 data
/// bits, no parity, 2 stop bits; protocol `modbus_ascii``), empty when it says neither.
fn code_value_sets(value: &CodeValueIr) -> String {
    let mut parts = Vec::new();
    if let Some(line) = value.line {
        let mut sets = Vec::new();
        if let Some(baud) = line.baud {
            sets.push(format!("{baud} bps"));
        }
        if let Some(data_bits) = line.data_bits {
            sets.push(format!("{data_bits} data bits"));
        }
        if let Some(parity) = line.parity {
            sets.push(
                match parity {
                    vfd_runtime::serial::Parity::None => "no parity",
                    vfd_runtime::serial::Parity::Even => "even parity",
                    vfd_runtime::serial::Parity::Odd => "odd parity",
                }
                .to_owned(),
            );
        }
        if let Some(stop_bits) = line.stop_bits {
            let stops = if stop_bits == 1 {
                "stop bit"
            } else {
                "stop bits"
            };
            sets.push(format!("{stop_bits} {stops}"));
        }
        parts.push(format!("line: {}", sets.join(", ")));
    }
    if let Some(protocol) = &value.protocol {
        parts.push(format!("protocol `{protocol}`"));
    }
    if parts.is_empty() {
        String::new()
    } else {
        format!(" — {}", parts.join("; "))
    }
}

/// Every code table, each value in hex with what it sets.
pub(super) fn code_table_views(drive: &DriveIr) -> Vec<CodeTableView<'_>> {
    drive
        .code_tables
        .iter()
        .map(|table| CodeTableView {
            table,
            values: table
                .values
                .iter()
                .map(|value| CodeValueView {
                    value,
                    value_hex: format!("{:04X}h", value.value),
                    sets: code_value_sets(value),
                })
                .collect(),
        })
        .collect()
}
