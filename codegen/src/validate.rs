//! Stage 2: checks a parsed drive description and reports every problem at once.
//!
//! Each check is its own function over the loaded description; [`check`] runs them all.
//! Nothing is generated from a description that has problems.

use crate::diagnostics::Diagnostic;
use crate::load::{LoadedDrive, LoadedProtocol};
use crate::model::{BoundModel, FrameModel};
use crate::ranges::{self, BoundProblem, End};
use std::collections::HashMap;
use vfd_runtime::units::Unit;
use vfd_runtime::{CommandKind, DecodeError, DecodeErrorKind, Role, Space};

/// Runs every check.
pub fn check(drive: &LoadedDrive) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let checks: [fn(&LoadedDrive, &mut Vec<Diagnostic>); 15] = [
        identifiers_are_snake_case,
        register_addresses_are_unique,
        names_are_unique,
        units_are_known,
        scales_are_positive,
        ranges_resolve,
        defaults_are_in_range,
        references_resolve,
        bit_fields_do_not_overlap,
        code_values_are_unique,
        serial_settings_are_consistent,
        examples_decode,
        value_examples_match,
        bit_examples_match,
        reference_scaling_resolves,
    ];
    for check in checks {
        check(drive, &mut out);
    }
    out
}

/// Identifiers become Rust names: lower-case snake case.
pub fn identifiers_are_snake_case(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    let model = &drive.model;
    let mut ids: Vec<(String, &str)> = vec![("drive.id".into(), model.drive.id.as_str())];
    ids.extend(
        model
            .registers
            .iter()
            .enumerate()
            .map(|(i, r)| (format!("registers[{i}].id"), r.id.as_str())),
    );
    ids.extend(
        model
            .bitfields
            .iter()
            .enumerate()
            .map(|(i, b)| (format!("bitfields[{i}].id"), b.id.as_str())),
    );
    for (i, bitfield) in model.bitfields.iter().enumerate() {
        for (j, field) in bitfield.fields.iter().enumerate() {
            if let Some(id) = &field.id {
                ids.push((format!("bitfields[{i}].fields[{j}].id"), id.as_str()));
            } else if !field.reserved {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("bitfields[{i}].fields[{j}]"),
                            "a bit field that is not reserved needs an `id`",
                        )
                        .hint("add `id: some_name`, or `reserved: true` for reserved bits"),
                );
            }
        }
    }
    ids.extend(
        model
            .codes
            .iter()
            .enumerate()
            .map(|(i, c)| (format!("codes[{i}].id"), c.id.as_str())),
    );
    for (i, table) in model.codes.iter().enumerate() {
        ids.extend(
            table
                .values
                .iter()
                .enumerate()
                .map(|(j, v)| (format!("codes[{i}].values[{j}].id"), v.id.as_str())),
        );
    }
    ids.extend(
        model
            .error_codes
            .codes
            .iter()
            .enumerate()
            .map(|(i, c)| (format!("error_codes.codes[{i}].id"), c.id.as_str())),
    );
    ids.extend(
        model
            .examples
            .iter()
            .enumerate()
            .map(|(i, e)| (format!("examples[{i}].id"), e.id.as_str())),
    );
    for (path, id) in ids {
        let valid = id
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_lowercase() || c == '_')
            && id
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
        if !valid {
            out.push(
                drive
                    .source
                    .error(
                        &path,
                        format!("identifier `{id}` is not lower-case snake case"),
                    )
                    .hint(
                        "identifiers become Rust names: use a-z, 0-9 and _ and start with a letter",
                    ),
            );
        }
    }
}

/// No two registers share an address.
pub fn register_addresses_are_unique(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    let mut seen: HashMap<u32, usize> = HashMap::new();
    for (index, register) in drive.model.registers.iter().enumerate() {
        let path = format!("registers[{index}].address");
        if register.address > 0xFFFF {
            out.push(
                drive
                    .source
                    .error(
                        &path,
                        format!("address {:#X} does not fit in 16 bits", register.address),
                    )
                    .hint("communication numbers run from 0x0000 to 0xFFFF"),
            );
        }
        if let Some(first) = seen.insert(register.address, index) {
            let other = &drive.model.registers[first];
            out.push(
                drive
                    .source
                    .error(&path, format!("duplicate register address {:04X}h: `{}` (registers[{first}]) already uses it", register.address, other.id))
                    .hint("each communication number may be described once; check the manual's table for a typo"),
            );
        }
    }
}

/// Identifiers and codes are unique within their kind.
pub fn names_are_unique(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    let model = &drive.model;
    let mut groups: Vec<(&str, Vec<(String, String)>)> = vec![
        (
            "register id",
            model
                .registers
                .iter()
                .enumerate()
                .map(|(i, r)| (format!("registers[{i}].id"), r.id.clone()))
                .collect(),
        ),
        (
            "register code",
            model
                .registers
                .iter()
                .enumerate()
                .map(|(i, r)| (format!("registers[{i}].code"), r.code.clone()))
                .collect(),
        ),
        (
            "bit-field word id",
            model
                .bitfields
                .iter()
                .enumerate()
                .map(|(i, b)| (format!("bitfields[{i}].id"), b.id.clone()))
                .collect(),
        ),
        (
            "code table id",
            model
                .codes
                .iter()
                .enumerate()
                .map(|(i, c)| (format!("codes[{i}].id"), c.id.clone()))
                .collect(),
        ),
        (
            "example id",
            model
                .examples
                .iter()
                .enumerate()
                .map(|(i, e)| (format!("examples[{i}].id"), e.id.clone()))
                .collect(),
        ),
        (
            "error code id",
            model
                .error_codes
                .codes
                .iter()
                .enumerate()
                .map(|(i, c)| (format!("error_codes.codes[{i}].id"), c.id.clone()))
                .collect(),
        ),
        (
            "protocol id",
            model
                .protocols
                .iter()
                .enumerate()
                .map(|(i, p)| (format!("protocols[{i}].id"), p.id.clone()))
                .collect(),
        ),
    ];
    for (i, bitfield) in model.bitfields.iter().enumerate() {
        let ids = bitfield.fields.iter().enumerate().filter_map(|(j, f)| {
            f.id.clone()
                .map(|id| (format!("bitfields[{i}].fields[{j}].id"), id))
        });
        groups.push(("bit field id", ids.collect()));
    }
    for (i, table) in model.codes.iter().enumerate() {
        groups.push((
            "code id",
            table
                .values
                .iter()
                .enumerate()
                .map(|(j, v)| (format!("codes[{i}].values[{j}].id"), v.id.clone()))
                .collect(),
        ));
    }
    for (what, items) in groups {
        let mut seen: HashMap<&str, &str> = HashMap::new();
        for (path, name) in &items {
            if let Some(first) = seen.insert(name, path) {
                out.push(
                    drive
                        .source
                        .error(
                            path,
                            format!("duplicate {what} `{name}` (first at {first})"),
                        )
                        .hint(format!("each {what} must be unique")),
                );
            }
        }
    }
}

/// Units are ones the runtime has quantity types for.
pub fn units_are_known(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    for (index, register) in drive.model.registers.iter().enumerate() {
        if let Some(unit) = &register.unit {
            if Unit::from_symbol(unit).is_none() {
                let known: Vec<&str> = Unit::ALL
                    .iter()
                    .map(|u| u.symbol())
                    .filter(|s| !s.is_empty())
                    .collect();
                out.push(
                    drive
                        .source
                        .error(
                            &format!("registers[{index}].unit"),
                            format!("unknown unit `{unit}`"),
                        )
                        .hint(format!(
                            "known units: {}; leave `unit` out for plain numbers",
                            known.join(", ")
                        )),
                );
            }
        }
    }
}

/// Scales are positive and finite.
pub fn scales_are_positive(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    for (index, register) in drive.model.registers.iter().enumerate() {
        if let Some(scale) = register.scale {
            if !(scale.is_finite() && scale > 0.0) {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("registers[{index}].scale"),
                            format!("scale {scale} must be a positive number"),
                        )
                        .hint("the scale is the value of one raw step, e.g. 0.01 for 0.01 Hz"),
                );
            }
        }
    }
}

/// Range bounds name known registers, are whole steps, fit the word and are in order.
pub fn ranges_resolve(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    for (index, register) in drive.model.registers.iter().enumerate() {
        let Some(range) = &register.range else {
            continue;
        };
        let mut resolved = [None, None];
        for (slot, (end, bound, key)) in
            [(End::Min, &range.min, "min"), (End::Max, &range.max, "max")]
                .into_iter()
                .enumerate()
        {
            let path = format!("registers[{index}].range.{key}");
            match ranges::resolve_bound(&drive.model, bound, end) {
                Ok(value) => {
                    let (word_min, word_max) = ranges::word_limits(register);
                    match ranges::to_raw(register, value) {
                        None => out.push(drive.source.error(&path, format!("bound {} is not a whole number of {} steps", with_unit(register, value.to_string()), with_unit(register, ranges::scale_of(register).to_string()))).hint("check the scale, or the bound's decimals")),
                        Some(raw) if raw < word_min || raw > word_max => out.push(
                            drive
                                .source
                                .error(&path, format!("bound {value} is raw {raw}, outside the 16-bit word ({word_min}..={word_max})"))
                                .hint("check the scale and `signed`"),
                        ),
                        Some(_) => resolved[slot] = Some(value),
                    }
                }
                Err(BoundProblem::Unknown(name)) => out.push(
                    drive
                        .source
                        .error(&path, format!("range bound `{name}` names no register"))
                        .hint("a named bound is the `code` (e.g. FH) or `id` of another register in this file"),
                ),
                Err(BoundProblem::Unbounded(name)) => out.push(
                    drive
                        .source
                        .error(&path, format!("range bound `{name}` names a register that has no range"))
                        .hint(format!("give `{name}` a range so a static bound can be taken from it")),
                ),
                Err(BoundProblem::Cycle(name)) => out.push(drive.source.error(&path, format!("range bounds through `{name}` refer to each other in a circle")).hint("one of the registers needs numeric bounds")),
            }
        }
        if let [Some(min), Some(max)] = resolved {
            if min > max {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("registers[{index}].range"),
                            format!("range minimum {min} is above its maximum {max}"),
                        )
                        .hint("swap the bounds, or check the manual"),
                );
            }
        }
    }
}

/// Decimal places a scale implies (0.01 -> 2).
fn decimals(scale: f64) -> usize {
    usize::from(vfd_runtime::units::decimals_of(scale))
}

/// `12.50 Hz` for a raw count of a register, without float noise.
fn show_raw(register: &crate::model::RegisterModel, raw: i64) -> String {
    let scale = ranges::scale_of(register);
    with_unit(
        register,
        format!("{:.*}", decimals(scale), raw as f64 * scale),
    )
}

fn with_unit(register: &crate::model::RegisterModel, number: String) -> String {
    match register.unit.as_deref() {
        Some(unit) if !unit.is_empty() => format!("{number} {unit}"),
        _ => number,
    }
}

/// Defaults lie within their (static) range.
pub fn defaults_are_in_range(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    for (index, register) in drive.model.registers.iter().enumerate() {
        let Some(default) = register.default else {
            continue;
        };
        let (raw_min, raw_max, _, _) = ranges::raw_range(&drive.model, register);
        let scale = ranges::scale_of(register);
        let path = format!("registers[{index}].default");
        match ranges::to_raw(register, default) {
            None => out.push(
                drive
                    .source
                    .error(
                        &path,
                        format!(
                            "default {} is not a whole number of {} steps",
                            with_unit(register, default.to_string()),
                            with_unit(register, scale.to_string())
                        ),
                    )
                    .hint("check the default's decimals against the scale"),
            ),
            Some(raw) if raw < raw_min || raw > raw_max => out.push(
                drive
                    .source
                    .error(
                        &path,
                        format!(
                            "default {} is outside the range {} to {}",
                            with_unit(register, default.to_string()),
                            show_raw(register, raw_min),
                            show_raw(register, raw_max)
                        ),
                    )
                    .hint("check the default and the range against the manual's table"),
            ),
            Some(_) => {}
        }
    }
}

/// Bit-field words, code tables and value examples name things that exist.
pub fn references_resolve(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    let model = &drive.model;
    for (index, register) in model.registers.iter().enumerate() {
        let extras: Vec<&str> = [
            ("code_table", register.code_table.is_some()),
            ("unit", register.unit.is_some()),
            ("scale", register.scale.is_some()),
        ]
        .into_iter()
        .filter_map(|(key, present)| present.then_some(key))
        .collect();
        if register.bitfield.is_some() && !extras.is_empty() {
            out.push(
                drive
                    .source
                    .error(
                        &format!("registers[{index}].{}", extras[0]),
                        format!("a bit-field register cannot also have `{}`", extras.join("` or `")),
                    )
                    .hint("a bit-field word has no unit, scale or code table: remove them, or remove `bitfield`"),
            );
        }
        if register.code_table.is_some() && (register.unit.is_some() || register.scale.is_some()) {
            out.push(
                drive
                    .source
                    .error(
                        &format!("registers[{index}].code_table"),
                        "a code-table register cannot also have a unit or a scale",
                    )
                    .hint("keep one of them"),
            );
        }
        if let Some(name) = &register.bitfield {
            if !model.bitfields.iter().any(|b| &b.id == name) {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("registers[{index}].bitfield"),
                            format!("bit-field word `{name}` is not defined"),
                        )
                        .hint("define it under `bitfields:`"),
                );
            }
        }
        if let Some(name) = &register.code_table {
            if !model.codes.iter().any(|c| &c.id == name) {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("registers[{index}].code_table"),
                            format!("code table `{name}` is not defined"),
                        )
                        .hint("define it under `codes:`"),
                );
            }
        }
        if let Some(access) = &register.access {
            if !["read-only", "read-write", "write-only"].contains(&access.as_str()) {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("registers[{index}].access"),
                            format!("unknown access `{access}`"),
                        )
                        .hint("use read-only, read-write or write-only (default read-write)"),
                );
            }
        }
        if let Some(when) = &register.takes_effect {
            if !["immediately", "after_reset"].contains(&when.as_str()) {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("registers[{index}].takes_effect"),
                            format!("unknown takes_effect `{when}`"),
                        )
                        .hint("use immediately or after_reset"),
                );
            }
        }
    }
    for (index, example) in model.value_examples.iter().enumerate() {
        if ranges::find_register(model, &example.register).is_none() {
            out.push(
                drive
                    .source
                    .error(
                        &format!("value_examples[{index}].register"),
                        format!("register `{}` is not defined", example.register),
                    )
                    .hint("name a register by its code or id"),
            );
        }
    }
    for (i, bitfield) in model.bitfields.iter().enumerate() {
        for (j, field) in bitfield.fields.iter().enumerate() {
            if let Some(table) = &field.code_table {
                if !model.codes.iter().any(|c| &c.id == table) {
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("bitfields[{i}].fields[{j}].code_table"),
                                format!("code table `{table}` is not defined"),
                            )
                            .hint("define it under `codes:`"),
                    );
                }
            }
        }
    }
}

/// Parses `bit: N` or `bits: "msb:lsb"` into (lsb, width).
pub fn bit_span(bit: Option<u8>, bits: Option<&str>) -> Result<(u8, u8), String> {
    match (bit, bits) {
        (Some(bit), None) if bit < 16 => Ok((bit, 1)),
        (Some(bit), None) => Err(format!("bit {bit} is outside a 16-bit word")),
        (None, Some(text)) => {
            let (msb, lsb) = text
                .split_once(':')
                .ok_or_else(|| format!("`bits: {text}` is not \"msb:lsb\""))?;
            let msb: u8 = msb
                .trim()
                .parse()
                .map_err(|_| format!("`{msb}` is not a bit number"))?;
            let lsb: u8 = lsb
                .trim()
                .parse()
                .map_err(|_| format!("`{lsb}` is not a bit number"))?;
            if msb < lsb || msb > 15 {
                return Err(format!("`bits: {text}` needs 15 >= msb >= lsb"));
            }
            Ok((lsb, msb - lsb + 1))
        }
        _ => Err("give exactly one of `bit` and `bits`".to_owned()),
    }
}

/// Bit fields fit the word and do not overlap.
pub fn bit_fields_do_not_overlap(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    for (i, bitfield) in drive.model.bitfields.iter().enumerate() {
        let mut owner: [Option<usize>; 16] = [None; 16];
        for (j, field) in bitfield.fields.iter().enumerate() {
            let path = format!("bitfields[{i}].fields[{j}]");
            match bit_span(field.bit, field.bits.as_deref()) {
                Err(message) => out.push(
                    drive
                        .source
                        .error(&path, message)
                        .hint("write `bit: 15` for one bit or `bits: \"13:12\"` for several"),
                ),
                Ok((lsb, width)) => {
                    for bit in lsb..lsb + width {
                        if let Some(first) = owner[usize::from(bit)] {
                            let other = bitfield.fields[first].id.as_deref().unwrap_or("reserved");
                            out.push(
                                drive
                                    .source
                                    .error(&path, format!("bit {bit} of `{}` is already used by `{other}` (fields[{first}])", bitfield.id))
                                    .hint("bit fields of one word must not overlap; check the manual's bit table"),
                            );
                            break;
                        }
                        owner[usize::from(bit)] = Some(j);
                    }
                }
            }
        }
    }
}

/// Code-table values are unique and fit 16 bits.
pub fn code_values_are_unique(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    for (i, table) in drive.model.codes.iter().enumerate() {
        let mut seen: HashMap<u32, usize> = HashMap::new();
        for (j, value) in table.values.iter().enumerate() {
            let path = format!("codes[{i}].values[{j}].value");
            if value.value > 0xFFFF {
                out.push(
                    drive
                        .source
                        .error(
                            &path,
                            format!("code {:#X} does not fit in 16 bits", value.value),
                        )
                        .hint("codes are register values"),
                );
            }
            if let Some(first) = seen.insert(value.value, j) {
                out.push(
                    drive
                        .source
                        .error(
                            &path,
                            format!(
                                "code {} appears twice in `{}` (first at values[{first}])",
                                value.value, table.id
                            ),
                        )
                        .hint("each code has one meaning"),
                );
            }
        }
    }
    let mut seen: HashMap<u32, usize> = HashMap::new();
    for (j, code) in drive.model.error_codes.codes.iter().enumerate() {
        if let Some(first) = seen.insert(code.code, j) {
            out.push(
                drive
                    .source
                    .error(
                        &format!("error_codes.codes[{j}].code"),
                        format!(
                            "error code {:04X}h appears twice (first at error_codes.codes[{first}])",
                            code.code
                        ),
                    )
                    .hint("each error code has one meaning"),
            );
        }
    }
}

/// Serial defaults are among the supported settings.
pub fn serial_settings_are_consistent(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
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

/// The bytes a frame model holds, or a message saying why there are none.
pub fn frame_bytes(ascii: &Option<String>, hex: &Option<String>) -> Result<Vec<u8>, String> {
    match (ascii, hex) {
        (Some(text), None) => Ok(text.as_bytes().to_vec()),
        (None, Some(hex)) => crate::protocols::parse_hex(hex),
        _ => Err("give exactly one of `ascii` and `hex`".to_owned()),
    }
}

/// Whether a frame is a request or a reply.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Master to drive.
    Request,
    /// Drive to master.
    Reply,
}

/// What a frame decoded to, in the terms `expect:` uses.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Decoded {
    /// Station address.
    pub address: Option<u8>,
    /// Command code as received (letter in its case, AK nibble, function code).
    pub command: Option<u32>,
    /// Kind of the command the frame belongs to.
    pub kind: Option<CommandKind>,
    /// Address space of the command.
    pub space: Option<Space>,
    /// Register number after undoing the address map.
    pub register: Option<u32>,
    /// Register number on the wire.
    pub wire_register: Option<u32>,
    /// Array index.
    pub index: Option<u32>,
    /// Data.
    pub data: Option<u32>,
    /// Error code.
    pub error_code: Option<u32>,
    /// Process words.
    pub process: Option<[u32; 2]>,
    /// Text.
    pub text: Option<String>,
    /// Lower-case command.
    pub tripped: bool,
}

/// Decodes a whole frame with `protocol`.
pub fn decode_frame(
    protocol: &LoadedProtocol,
    direction: Direction,
    bytes: &[u8],
) -> Result<Decoded, DecodeError> {
    let protocol = &protocol.runtime;
    let process = |p: Option<[u16; 2]>| p.map(|[a, b]| [u32::from(a), u32::from(b)]);
    match direction {
        Direction::Request => {
            let request = protocol.decode_request_exact(bytes)?;
            let command = request.command;
            Ok(Decoded {
                address: request.address,
                command: command.request.has(Role::Command).then_some(command.code),
                kind: Some(command.kind),
                space: Some(command.space),
                register: request.register.map(u32::from),
                wire_register: request.wire_register.map(u32::from),
                index: request.index.map(u32::from),
                data: command.request.has(Role::Data).then_some(request.data),
                error_code: None,
                process: process(request.process),
                text: None,
                tripped: false,
            })
        }
        Direction::Reply => match protocol.decode_reply_exact(None, bytes)? {
            vfd_runtime::Reply::Data {
                command,
                code,
                address,
                tripped,
                wire_register,
                index,
                data,
                process: words,
                text,
                ..
            } => Ok(Decoded {
                address,
                command: command.reply.has(Role::Command).then_some(code),
                kind: Some(command.kind),
                space: Some(command.space),
                register: wire_register
                    .and_then(|w| command.address_map.from_wire(w))
                    .map(u32::from),
                wire_register: wire_register.map(u32::from),
                index: index.map(u32::from),
                data: command.reply.has(Role::Data).then_some(data),
                error_code: None,
                process: process(words),
                text: text.map(|(start, len)| {
                    String::from_utf8_lossy(&bytes[start..start + len]).into_owned()
                }),
                tripped,
            }),
            vfd_runtime::Reply::Error {
                address,
                tripped,
                code,
                error,
                ..
            } => Ok(Decoded {
                address,
                command: Some(code),
                error_code: Some(u32::from(error)),
                tripped,
                ..Decoded::default()
            }),
        },
    }
}

/// The register a decoded frame's data belongs to.
pub fn register_of<'d>(
    drive: &'d LoadedDrive,
    decoded: &Decoded,
) -> Option<&'d crate::model::RegisterModel> {
    let address = decoded.register?;
    let space = decoded.space.unwrap_or(Space::Parameter);
    drive
        .model
        .registers
        .iter()
        .find(|r| r.address == address && space_of(r) == space)
}

/// A register's address space.
pub fn space_of(register: &crate::model::RegisterModel) -> Space {
    register
        .space
        .as_deref()
        .and_then(crate::protocols::space_from_name)
        .unwrap_or(Space::Parameter)
}

/// Every example frame decodes to what it says; printed errata are rejected for the stated reason.
pub fn examples_decode(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    for (index, example) in drive.model.examples.iter().enumerate() {
        let base = format!("examples[{index}]");
        let Some(protocol) = drive.protocols.iter().find(|p| p.id == example.protocol) else {
            if drive
                .model
                .protocols
                .iter()
                .any(|p| p.id == example.protocol)
            {
                continue; // The protocol is declared but failed to load; that is reported already.
            }
            let known: Vec<&str> = drive
                .model
                .protocols
                .iter()
                .map(|p| p.id.as_str())
                .collect();
            out.push(
                drive
                    .source
                    .error(
                        &format!("{base}.protocol"),
                        format!("unknown protocol `{}`", example.protocol),
                    )
                    .hint(format!(
                        "use one of the drive's protocols: {}",
                        known.join(", ")
                    )),
            );
            continue;
        };
        if example.request.is_none() && example.reply.is_none() {
            out.push(
                drive
                    .source
                    .error(&base, "an example needs a `request`, a `reply` or both")
                    .hint("copy the frames from the manual"),
            );
        }
        for (direction, key, frame) in [
            (Direction::Request, "request", &example.request),
            (Direction::Reply, "reply", &example.reply),
        ] {
            if let Some(frame) = frame {
                check_frame(
                    drive,
                    protocol,
                    direction,
                    &format!("{base}.{key}"),
                    frame,
                    out,
                );
            }
        }
        if let Some(value) = example.value {
            let frames = [
                (Direction::Request, example.request.as_ref()),
                (Direction::Reply, example.reply.as_ref()),
            ];
            check_example_value(drive, protocol, &base, value, frames, out);
        }
    }
}

fn check_frame(
    drive: &LoadedDrive,
    protocol: &LoadedProtocol,
    direction: Direction,
    path: &str,
    frame: &FrameModel,
    out: &mut Vec<Diagnostic>,
) {
    let bytes = match frame_bytes(&frame.ascii, &frame.hex) {
        Ok(bytes) => bytes,
        Err(message) => {
            out.push(drive.source.error(path, message).hint("write text frames as ascii: \"(R0501)\\r\" and binary ones as hex: \"2F 52 05 01 87\""));
            return;
        }
    };
    let expect = &frame.expect;
    let expected_code = match &expect.command {
        Some(code) => match code.value() {
            Some(value) => Some(value),
            None => {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("{path}.expect.command"),
                            format!("`{}` is not one character or a number", code.shown()),
                        )
                        .hint("e.g. command: R, or command: 0x03"),
                );
                None
            }
        },
        None => None,
    };
    match decode_frame(protocol, direction, &bytes) {
        Err(error) => out.push(
            drive
                .source
                .error(path, format!("the frame does not decode: {error}"))
                .hint(match error.kind() {
                    DecodeErrorKind::ChecksumMismatch => "if the manual prints a wrong checksum, put the corrected bytes here and the printed ones under `printed:` with an `erratum:`",
                    _ => "check the bytes against the manual; record a manual mistake as `printed:` + `erratum:`",
                }),
        ),
        Ok(decoded) => {
            let mut mismatches = Vec::new();
            let show = |v: Option<u32>| v.map_or("absent".to_owned(), |v| format!("{v:04X}h"));
            if expected_code != decoded.command {
                let label = |c: Option<u32>| c.map_or("absent".to_owned(), vfd_runtime::protocol::code_label);
                mismatches.push(format!("command is {}, expected {}", label(decoded.command), label(expected_code)));
            }
            for (name, wanted, got) in [
                ("register", expect.register, decoded.register),
                ("wire_register", expect.wire_register, if expect.wire_register.is_some() { decoded.wire_register } else { None }),
                ("index", expect.index, decoded.index),
                ("data", expect.data, decoded.data),
                ("error_code", expect.error_code, decoded.error_code),
                ("address", expect.address.map(u32::from), decoded.address.map(u32::from)),
            ] {
                if wanted != got {
                    mismatches.push(format!("{name} is {}, expected {}", show(got), show(wanted)));
                }
            }
            if expect.process != decoded.process {
                mismatches.push(format!("process words are {:X?}, expected {:X?}", decoded.process, expect.process));
            }
            if expect.text != decoded.text {
                mismatches.push(format!("text is {:?}, expected {:?}", decoded.text, expect.text));
            }
            if expect.tripped != decoded.tripped {
                mismatches.push(format!("tripped is {}, expected {}", decoded.tripped, expect.tripped));
            }
            if !mismatches.is_empty() {
                out.push(drive.source.error(&format!("{path}.expect"), format!("the frame decodes differently: {}", mismatches.join("; "))).hint("`expect` states what the manual says the frame means (register numbers before the protocol's address map)"));
            }
        }
    }
    match (&frame.printed, &frame.erratum, &frame.printed_rejected_as) {
        (None, None, None) => {}
        (Some(printed), Some(_), Some(reason)) => match frame_bytes(&printed.ascii, &printed.hex) {
            Err(message) => out.push(drive.source.error(&format!("{path}.printed"), message).hint("give the bytes exactly as printed")),
            Ok(printed) => match decode_frame(protocol, direction, &printed) {
                Ok(_) => out.push(
                    drive
                        .source
                        .error(&format!("{path}.printed"), "the printed frame decodes without error, so the decoder cannot tell it is wrong")
                        .hint("an erratum records bytes the decoder rejects; describe meaning-only mistakes under manual_errata"),
                ),
                Err(error) if DecodeErrorKind::from_name(reason) != Some(error.kind()) => out.push(
                    drive
                        .source
                        .error(&format!("{path}.printed_rejected_as"), format!("the printed frame is rejected as {}, not {reason}: {error}", error.kind()))
                        .hint("state the reason the decoder gives"),
                ),
                Err(_) => {}
            },
        },
        _ => out.push(
            drive
                .source
                .error(path, "an erratum needs `printed`, `erratum` and `printed_rejected_as` together")
                .hint("printed: the manual's bytes; erratum: why they are wrong; printed_rejected_as: the decoder's reason (checksum_mismatch, length_mismatch, not_allowed, unexpected_byte, truncated, trailing_bytes)"),
        ),
    }
}

fn check_example_value(
    drive: &LoadedDrive,
    protocol: &LoadedProtocol,
    base: &str,
    value: f64,
    frames: [(Direction, Option<&FrameModel>); 2],
    out: &mut Vec<Diagnostic>,
) {
    let path = format!("{base}.value");
    // The value belongs to the data of the reply, else of the request.
    let mut register = None;
    let mut data = None;
    for (direction, frame) in frames.iter().rev() {
        let Some(frame) = frame else { continue };
        let Ok(bytes) = frame_bytes(&frame.ascii, &frame.hex) else {
            continue;
        };
        let Ok(decoded) = decode_frame(protocol, *direction, &bytes) else {
            continue;
        };
        if register.is_none() {
            register = register_of(drive, &decoded);
        }
        if data.is_none() {
            data = decoded.data;
        }
    }
    let Some(register) = register else {
        out.push(
            drive
                .source
                .error(&path, "`value` needs a frame naming a described register")
                .hint("describe the register, or drop `value`"),
        );
        return;
    };
    let Some(data) = data else {
        out.push(
            drive
                .source
                .error(&path, "`value` needs a frame carrying data")
                .hint("the value is the data in engineering units"),
        );
        return;
    };
    let scale = ranges::scale_of(register);
    let data_type = register
        .data_type
        .as_deref()
        .and_then(crate::protocols::data_type_from_name)
        .unwrap_or(vfd_runtime::DataType::Word);
    let raw = vfd_runtime::units::raw_to_number(data, register.signed, data_type);
    if (raw * scale - value).abs() > scale / 2.0 {
        out.push(
            drive
                .source
                .error(
                    &path,
                    format!(
                        "data {data:04X}h is {} in `{}`, not {}",
                        with_unit(register, format!("{:.*}", decimals(scale), raw * scale)),
                        register.code,
                        with_unit(register, value.to_string())
                    ),
                )
                .hint("check the register's scale and the example"),
        );
    }
}

/// Value examples (`80 Hz = 1F40h`) agree with the register's scale.
pub fn value_examples_match(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    for (index, example) in drive.model.value_examples.iter().enumerate() {
        let Some(register) = ranges::find_register(&drive.model, &example.register) else {
            continue;
        };
        // The runtime rounds to the nearest step, so the example must round to its raw value.
        let steps = example.value / ranges::scale_of(register);
        if !steps.is_finite() || steps.round() as i64 != i64::from(example.raw) {
            out.push(
                drive
                    .source
                    .error(
                        &format!("value_examples[{index}].raw"),
                        format!(
                            "{} in `{}` is not raw {:04X}h with a step of {}",
                            with_unit(register, example.value.to_string()),
                            register.code,
                            example.raw,
                            with_unit(register, ranges::scale_of(register).to_string())
                        ),
                    )
                    .hint("check the register's scale, or record a manual mistake"),
            );
        }
    }
}

/// Bit-field examples (`8400h = command_enabled + run`) agree with the bit positions.
pub fn bit_examples_match(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    for (i, bitfield) in drive.model.bitfields.iter().enumerate() {
        for (j, example) in bitfield.examples.iter().enumerate() {
            let mut value = 0u32;
            for name in &example.set {
                match bitfield
                    .fields
                    .iter()
                    .find(|f| f.id.as_deref() == Some(name.as_str()))
                {
                    Some(field) => {
                        if let Ok((lsb, _)) = bit_span(field.bit, field.bits.as_deref()) {
                            value |= 1 << lsb;
                        }
                    }
                    None => out.push(
                        drive
                            .source
                            .error(
                                &format!("bitfields[{i}].examples[{j}].set"),
                                format!("`{name}` is not a field of `{}`", bitfield.id),
                            )
                            .hint("name fields by id"),
                    ),
                }
            }
            if value != example.value {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("bitfields[{i}].examples[{j}].value"),
                            format!(
                                "the fields set give {value:04X}h, not {:04X}h",
                                example.value
                            ),
                        )
                        .hint("check the example against the bit table"),
                );
            }
        }
    }
}

/// A diagnostic for a bound's value kind, used by the IR for display.
pub fn bound_label(bound: &BoundModel) -> String {
    match bound {
        BoundModel::Number(value) => format!("{value}"),
        BoundModel::Register(name) => name.clone(),
    }
}

/// The reference scaling names registers that exist.
pub fn reference_scaling_resolves(drive: &LoadedDrive, out: &mut Vec<Diagnostic>) {
    let Some(scaling) = &drive.model.reference_scaling else {
        return;
    };
    let known = |id: &str| drive.model.registers.iter().any(|r| r.id == id);
    let mut names: Vec<(String, &str)> = vec![(
        "reference_scaling.selector".to_owned(),
        scaling.selector.as_str(),
    )];
    names.extend(
        scaling
            .applies_to
            .iter()
            .enumerate()
            .map(|(i, id)| (format!("reference_scaling.applies_to[{i}]"), id.as_str())),
    );
    for (i, mode) in scaling.modes.iter().enumerate() {
        for (key, bound) in [("low", &mode.low), ("high", &mode.high)] {
            if let BoundModel::Register(id) = bound {
                names.push((format!("reference_scaling.modes[{i}].{key}"), id.as_str()));
            }
        }
    }
    for (path, id) in names {
        if !known(id) {
            out.push(
                drive
                    .source
                    .error(&path, format!("`{id}` is not the id of a register"))
                    .hint("name registers by their `id` here"),
            );
        }
    }
    if scaling.full_scale_raw == 0 {
        out.push(
            drive
                .source
                .error(
                    "reference_scaling.full_scale_raw",
                    "full scale must be above 0",
                )
                .hint("the raw value meaning 100 %, e.g. 0x4000"),
        );
    }
}
