//! Check: code values that set the line's character format or choose a protocol
//! (`codes[].values[].line`, `.protocol`) say something possible: 7 or 8 data bits, 1 or 2
//! stop bits, a parity the drive's serial section lists, and a protocol id of the drive.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;

/// Every `line` is a possible character format and every `protocol` a protocol of the drive.
pub fn line_formats_resolve(drive: &Context, out: &mut Diagnostics) {
    let protocols: Vec<&str> = drive
        .model
        .protocols
        .iter()
        .map(|p| p.id.as_str())
        .collect();
    for (t, table) in drive.model.codes.iter().enumerate() {
        for (v, value) in table.values.iter().enumerate() {
            let base = format!("codes[{t}].values[{v}]");
            if let Some(line) = &value.line {
                if !(7..=8).contains(&line.data_bits) {
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("{base}.line.data_bits"),
                                format!("{} data bits", line.data_bits),
                            )
                            .hint("a character carries 7 or 8 data bits"),
                    );
                }
                if !(1..=2).contains(&line.stop_bits) {
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("{base}.line.stop_bits"),
                                format!("{} stop bits", line.stop_bits),
                            )
                            .hint("a character ends with 1 or 2 stop bits"),
                    );
                }
                if !drive.model.serial.parities.contains(&line.parity) {
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("{base}.line.parity"),
                                format!(
                                    "parity `{}` is not among serial.parities",
                                    line.parity.as_str()
                                ),
                            )
                            .hint("list every parity the drive can use under serial.parities"),
                    );
                }
            }
            if let Some(protocol) = &value.protocol {
                if !protocols.contains(&protocol.as_str()) {
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("{base}.protocol"),
                                format!("unknown protocol `{protocol}`"),
                            )
                            .hint(format!(
                                "use one of the drive's protocol ids: {}",
                                protocols.join(", ")
                            )),
                    );
                }
            }
        }
    }
}
