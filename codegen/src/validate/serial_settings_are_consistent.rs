//! Check: serial defaults are among the supported settings.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;

/// Serial defaults are among the supported settings.
pub fn serial_settings_are_consistent(drive: &Context, out: &mut Diagnostics) {
    let serial = &drive.model.serial;
    for (index, parity) in serial.parities.iter().enumerate() {
        if !["none", "even", "odd"].contains(&parity.as_str()) {
            out.push(
                drive
                    .source
                    .error(
                        &format!("serial.parities[{index}]"),
                        format!("unknown parity `{parity}`"),
                    )
                    .hint("use none, even or odd"),
            );
        }
    }
    if !serial.baud_rates.contains(&serial.default.baud) {
        out.push(
            drive
                .source
                .error(
                    "serial.default.baud",
                    format!(
                        "default baud rate {} is not in `baud_rates`",
                        serial.default.baud
                    ),
                )
                .hint("add it to baud_rates or fix the default"),
        );
    }
    if !serial.parities.contains(&serial.default.parity) {
        out.push(
            drive
                .source
                .error(
                    "serial.default.parity",
                    format!(
                        "default parity `{}` is not in `parities`",
                        serial.default.parity
                    ),
                )
                .hint("add it to parities or fix the default"),
        );
    }
    if !(1..=2).contains(&serial.default.stop_bits) || !(7..=8).contains(&serial.default.data_bits)
    {
        out.push(
            drive
                .source
                .error(
                    "serial.default",
                    "default needs 7 or 8 data bits and 1 or 2 stop bits",
                )
                .hint("check section 2 of the manual"),
        );
    }
    if drive.model.addressing.min > drive.model.addressing.max {
        out.push(
            drive
                .source
                .error("addressing", "addressing.min is above addressing.max")
                .hint("swap them"),
        );
    }
}
