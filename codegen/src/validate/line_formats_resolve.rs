//! Check: code values that set the line or choose a protocol (`codes[].values[].line`,
//! `.protocol`) say something possible: a baud rate the drive's serial section lists, 7 or
//! 8 data bits, 1 or 2 stop bits, a parity the serial section lists, at least one of them,
//! and a protocol id of the drive; and a line-setting register's factory value sets what
//! the serial section gives as the factory setting (`serial.default`).

use crate::diagnostics::Diagnostics;
use crate::parse::model::LineFormatModel;
use crate::validate::Context;

/// Every `line` is possible, agrees with the factory setting where its register's default
/// selects it, and every `protocol` is a protocol of the drive.
pub fn line_formats_resolve(drive: &Context, out: &mut Diagnostics) {
    let protocols: Vec<&str> = drive
        .model
        .protocols
        .iter()
        .map(|p| p.id.as_str())
        .collect();
    let serial = &drive.model.serial;
    for (t, table) in drive.model.codes.iter().enumerate() {
        for (v, value) in table.values.iter().enumerate() {
            let base = format!("codes[{t}].values[{v}]");
            let mut problem = |key: &str, message: String, hint: &str| {
                out.push(
                    drive
                        .source
                        .error(&format!("{base}.line{key}"), message)
                        .hint(hint),
                );
            };
            if let Some(line) = &value.line {
                let LineFormatModel {
                    baud,
                    data_bits,
                    parity,
                    stop_bits,
                } = *line;
                if baud.is_none() && data_bits.is_none() && parity.is_none() && stop_bits.is_none()
                {
                    problem(
                        "",
                        "the value sets nothing on the line".to_owned(),
                        "give what it sets: `baud`, `data_bits`, `parity`, `stop_bits` (any of them)",
                    );
                }
                if let Some(baud) = baud.filter(|b| !serial.baud_rates.contains(b)) {
                    problem(
                        ".baud",
                        format!("{baud} bps is not among serial.baud_rates"),
                        "list every baud rate the drive can use under serial.baud_rates",
                    );
                }
                if let Some(bits) = data_bits.filter(|b| !(7..=8).contains(b)) {
                    problem(
                        ".data_bits",
                        format!("{bits} data bits"),
                        "a character carries 7 or 8 data bits",
                    );
                }
                if let Some(bits) = stop_bits.filter(|b| !(1..=2).contains(b)) {
                    problem(
                        ".stop_bits",
                        format!("{bits} stop bits"),
                        "a character ends with 1 or 2 stop bits",
                    );
                }
                if let Some(parity) = parity.filter(|p| !serial.parities.contains(p)) {
                    problem(
                        ".parity",
                        format!("parity `{}` is not among serial.parities", parity.as_str()),
                        "list every parity the drive can use under serial.parities",
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
    factory_settings_agree(drive, out);
}

/// A register whose code table sets the line (and chooses no protocol) is a setting of the
/// line the drive starts with: its factory value must set what `serial.default` says.
fn factory_settings_agree(drive: &Context, out: &mut Diagnostics) {
    let factory = &drive.model.serial.default;
    for (index, register) in drive.model.registers.iter().enumerate() {
        let (Some(table), Some(default)) = (&register.code_table, register.default) else {
            continue;
        };
        let Some(value) = drive
            .model
            .codes
            .iter()
            .find(|t| &t.id == table)
            .and_then(|t| t.values.iter().find(|v| f64::from(v.value) == default))
        else {
            continue;
        };
        let (Some(line), None) = (&value.line, &value.protocol) else {
            continue;
        };
        // What the value sets and what serial.default gives instead, part by part.
        let mut differ: Vec<(String, String)> = Vec::new();
        if let Some(baud) = line.baud.filter(|b| *b != factory.baud) {
            differ.push((format!("{baud} bps"), format!("{} bps", factory.baud)));
        }
        if let Some(bits) = line.data_bits.filter(|b| *b != factory.data_bits) {
            differ.push((
                format!("{bits} data bits"),
                format!("{} data bits", factory.data_bits),
            ));
        }
        if let Some(parity) = line.parity.filter(|p| *p != factory.parity) {
            differ.push((
                format!("parity `{}`", parity.as_str()),
                format!("parity `{}`", factory.parity.as_str()),
            ));
        }
        if let Some(bits) = line.stop_bits.filter(|b| *b != factory.stop_bits) {
            differ.push((
                format!("{bits} stop bits"),
                format!("{} stop bits", factory.stop_bits),
            ));
        }
        if !differ.is_empty() {
            out.push(
                drive
                    .source
                    .error(
                        &format!("registers[{index}].default"),
                        format!(
                            "{}'s factory value {} (`{}`) sets {}, but the factory setting in serial.default is {}",
                            register.code,
                            value.value,
                            value.id,
                            differ.iter().map(|(sets, _)| sets.as_str()).collect::<Vec<_>>().join(", "),
                            differ.iter().map(|(_, given)| given.as_str()).collect::<Vec<_>>().join(", ")
                        ),
                    )
                    .hint("the register's default and serial.default are one factory setting: check both against the manual"),
            );
        }
    }
}
