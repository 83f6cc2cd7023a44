//! Check: serial defaults are among the supported settings.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;

/// Serial defaults are among the supported settings.
pub fn serial_settings_are_consistent(drive: &Context, out: &mut Diagnostics) {
    let serial = &drive.model.serial;
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
                        serial.default.parity.as_str()
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
    stop_bits(drive, out);
    data_bits(drive, out);
    if drive.model.addressing.min > drive.model.addressing.max {
        out.push(
            drive
                .source
                .error("addressing", "addressing.min is above addressing.max")
                .hint("swap them"),
        );
    }
}

/// Stop bits are fixed (`stop_bits_sent` and `stop_bits_received`) or the drive's choice
/// (`stop_bits: [1, 2]`, which holds the factory setting), not both.
fn stop_bits(drive: &Context, out: &mut Diagnostics) {
    let serial = &drive.model.serial;
    let fixed = [
        ("stop_bits_sent", serial.stop_bits_sent),
        ("stop_bits_received", serial.stop_bits_received),
    ];
    if serial.stop_bits.is_empty() {
        for (key, value) in fixed {
            if value.is_none() {
                out.push(
                    drive
                        .source
                        .error("serial", format!("`{key}` is missing"))
                        .hint("give the stop bits the drive sends and needs (`stop_bits_sent: 1`, `stop_bits_received: 1`), or, when they are a setting of the drive, the ones it can be set to: `stop_bits: [1, 2]`"),
                );
            }
        }
        return;
    }
    for (key, value) in fixed {
        if value.is_some() {
            out.push(
                drive
                    .source
                    .error(&format!("serial.{key}"), format!("`{key}` with `stop_bits`"))
                    .hint("with `stop_bits: [1, 2]` the drive sends and needs the stop bits it is set to: leave the fixed values out"),
            );
        }
    }
    if let Some(bad) = serial.stop_bits.iter().find(|b| !(1..=2).contains(*b)) {
        out.push(
            drive
                .source
                .error("serial.stop_bits", format!("{bad} stop bits"))
                .hint("a character has 1 or 2 stop bits"),
        );
    }
    if !serial.stop_bits.contains(&serial.default.stop_bits) {
        out.push(
            drive
                .source
                .error(
                    "serial.default.stop_bits",
                    format!(
                        "default stop bits {} are not in `stop_bits`",
                        serial.default.stop_bits
                    ),
                )
                .hint("the factory setting is one of the stop bits the drive can be set to"),
        );
    }
}

/// Data bits are 7 or 8, and the factory setting is one the drive can use.
fn data_bits(drive: &Context, out: &mut Diagnostics) {
    let serial = &drive.model.serial;
    let choices = serial.data_bits.choices();
    if let Some(bad) = choices.iter().find(|b| !(7..=8).contains(*b)) {
        out.push(
            drive
                .source
                .error("serial.data_bits", format!("{bad} data bits"))
                .hint("a character carries 7 or 8 data bits"),
        );
    }
    if choices.is_empty() {
        out.push(
            drive
                .source
                .error("serial.data_bits", "no data bits listed")
                .hint("give the data bits (`data_bits: 8`), or those the drive can be set to (`data_bits: [7, 8]`)"),
        );
    } else if (7..=8).contains(&serial.default.data_bits)
        && !choices.contains(&serial.default.data_bits)
    {
        out.push(
            drive
                .source
                .error(
                    "serial.default.data_bits",
                    format!(
                        "default data bits {} are not in `data_bits`",
                        serial.default.data_bits
                    ),
                )
                .hint("the factory setting is one of the data bits the drive can use"),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::serial_settings_are_consistent as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_consistent_settings() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn reports_defaults_missing_from_the_lists() {
        let yaml = valid_with(&[
            ("baud_rates: [4800, 9600]", "baud_rates: [4800, 19200]"),
            ("parities: [even, odd]", "parities: [odd]"),
        ]);
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 2, "{found:#?}");
        assert_at(
            &found[0],
            &yaml,
            "serial.default.baud",
            "default baud rate 9600 is not in `baud_rates`",
            "default: { baud",
        );
        assert_at(
            &found[1],
            &yaml,
            "serial.default.parity",
            "default parity `even` is not in `parities`",
            "default: { baud",
        );
    }

    #[test]
    fn reports_impossible_data_or_stop_bits() {
        for (data, stop) in [(9, 1), (8, 3), (6, 1)] {
            let yaml = valid_with(&[(
                "data_bits: 8, stop_bits: 1",
                &format!("data_bits: {data}, stop_bits: {stop}"),
            )]);
            let found = check_yaml(check, &yaml);
            assert_at(
                only(&found),
                &yaml,
                "serial.default",
                "default needs 7 or 8 data bits and 1 or 2 stop bits",
                "default: { baud",
            );
        }
    }

    #[test]
    fn reports_station_numbers_in_the_wrong_order() {
        let yaml = valid_with(&[("min: 0\n  max: 31", "min: 32\n  max: 31")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "addressing",
            "addressing.min is above addressing.max",
            "addressing:",
        );
    }
}
