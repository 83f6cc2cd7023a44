//! Check: bit-field words, code tables, value examples, the error table and registers' own
//! wire numbers name things that exist.

use crate::diagnostics::Diagnostics;
use crate::validate::ranges;
use crate::validate::Context;

/// Bit-field words, code tables, value examples and the protocols the error table applies
/// to name things that exist.
pub fn references_resolve(drive: &Context, out: &mut Diagnostics) {
    let model = &drive.model;
    for (index, id) in model.error_codes.protocols.iter().flatten().enumerate() {
        if !model.protocols.iter().any(|protocol| &protocol.id == id) {
            let ids: Vec<&str> = model.protocols.iter().map(|p| p.id.as_str()).collect();
            out.push(
                drive
                    .source
                    .error(
                        &format!("error_codes.protocols[{index}]"),
                        format!("protocol `{id}` is not one of the drive's protocols"),
                    )
                    .hint(format!(
                        "name an id under `protocols:` ({})",
                        ids.join(", ")
                    )),
            );
        }
    }
    let ids: Vec<&str> = model.protocols.iter().map(|p| p.id.as_str()).collect();
    for (index, register) in model.registers.iter().enumerate() {
        for id in register.wire_numbers.keys() {
            if !ids.contains(&id.as_str()) {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("registers[{index}].wire_numbers.{id}"),
                            format!("protocol `{id}` is not one of the drive's protocols"),
                        )
                        .hint(format!(
                            "name an id under `protocols:` ({})",
                            ids.join(", ")
                        )),
                );
            }
        }
    }
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
    }
    let registers = ranges::RegisterIndex::new(model);
    for (index, example) in model.value_examples.iter().enumerate() {
        if registers.find(&example.register).is_none() {
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

#[cfg(test)]
mod tests {
    use super::references_resolve as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_references_to_defined_things() {
        assert!(check_yaml(check, VALID).is_empty());
        let yaml = valid_with(&[
            (
                "ram_only: true,",
                "ram_only: true, access: write-only, takes_effect: after_reset,",
            ),
            ("register: FH, value", "register: maximum_frequency, value"),
        ]);
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn reports_an_undefined_bit_field_word_and_code_table() {
        let yaml = valid_with(&[
            ("bitfield: command_word", "bitfield: status_word"),
            ("code_table: parity", "code_table: baud_rate"),
        ]);
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 2, "{found:#?}");
        assert_at(
            &found[0],
            &yaml,
            "registers[3].code_table",
            "code table `baud_rate` is not defined",
            "code: F601,",
        );
        assert_at(
            &found[1],
            &yaml,
            "registers[4].bitfield",
            "bit-field word `status_word` is not defined",
            "code: FA00,",
        );
    }

    #[test]
    fn reports_a_bit_field_register_with_a_unit_scale_or_code_table() {
        let yaml = valid_with(&[(
            "bitfield: command_word,",
            "bitfield: command_word, unit: Hz,",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[4].unit",
            "a bit-field register cannot also have `unit`",
            "code: FA00,",
        );
        let yaml = valid_with(&[(
            "bitfield: command_word,",
            "bitfield: command_word, code_table: parity, scale: 0.1,",
        )]);
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 2, "{found:#?}");
        assert_at(
            &found[0],
            &yaml,
            "registers[4].code_table",
            "a bit-field register cannot also have `code_table` or `scale`",
            "code: FA00,",
        );
        assert_at(
            &found[1],
            &yaml,
            "registers[4].code_table",
            "a code-table register cannot also have a unit or a scale",
            "code: FA00,",
        );
    }

    #[test]
    fn reports_a_value_example_naming_no_register() {
        let yaml = valid_with(&[("register: FH, value", "register: XY, value")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "value_examples[0].register",
            "register `XY` is not defined",
            "register: XY",
        );
    }

    #[test]
    fn reports_a_bit_field_naming_an_undefined_code_table() {
        let yaml = valid_with(&[(
            r#"{ bits: "14:11", reserved: true }"#,
            r#"{ bits: "14:11", id: mode, code_table: modes }"#,
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "bitfields[0].fields[1].code_table",
            "code table `modes` is not defined",
            "id: mode,",
        );
    }
}
