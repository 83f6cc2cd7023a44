//! Check: bit-field words, code tables and value examples name things that exist.

use crate::diagnostics::Diagnostics;
use crate::validate::ranges;
use crate::validate::Context;

/// Bit-field words, code tables and value examples name things that exist.
pub fn references_resolve(drive: &Context, out: &mut Diagnostics) {
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
