//! The character formats a setting offers each protocol: a code table whose values set the
//! line and choose a protocol (`codes[].values[].line`, `.protocol`; the DV1's 07-07), with
//! the one its register's factory value chooses marked. Only a value that sets the whole
//! format (data bits, parity and stop bits) gives one.

use super::types::ProtocolLineIr;
use crate::parse::model::DriveFile;

/// Every format a code table offers a protocol, in the table's order, `factory` on the one
/// the selecting register's factory value chooses (none, when that value chooses another
/// protocol: a master then starts from the first).
pub(super) fn protocol_lines(model: &DriveFile) -> Vec<ProtocolLineIr> {
    let mut lines = Vec::new();
    for table in &model.codes {
        let Some(selector) = model
            .registers
            .iter()
            .find(|r| r.code_table.as_deref() == Some(table.id.as_str()))
        else {
            continue;
        };
        for value in &table.values {
            let (Some(line), Some(protocol)) = (value.line, &value.protocol) else {
                continue;
            };
            // A protocol's format is a value that sets the whole of it.
            let (Some(data_bits), Some(parity), Some(stop_bits)) =
                (line.data_bits, line.parity, line.stop_bits)
            else {
                continue;
            };
            lines.push(ProtocolLineIr {
                protocol: protocol.clone(),
                data_bits,
                parity,
                stop_bits,
                selector: selector.code.clone(),
                value: value.value as u16,
                factory: selector
                    .default
                    .is_some_and(|d| d == f64::from(value.value)),
            });
        }
    }
    lines
}
