//! Check: bit-field examples agree with the bit positions.

use crate::diagnostics::Diagnostics;
use crate::validate::bit_span;
use crate::validate::Context;

/// Bit-field examples (`8400h = command_enabled + run`) agree with the bit positions.
pub fn bit_examples_match(drive: &Context, out: &mut Diagnostics) {
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
            for (name, field_value) in &example.fields {
                let path = format!("bitfields[{i}].examples[{j}].fields.{name}");
                let field = bitfield
                    .fields
                    .iter()
                    .find(|f| f.id.as_deref() == Some(name.as_str()));
                let span = field.and_then(|f| bit_span(f.bit, f.bits.as_deref()).ok());
                match span {
                    None => out.push(
                        drive
                            .source
                            .error(
                                &path,
                                format!("`{name}` is not a field of `{}`", bitfield.id),
                            )
                            .hint("name fields by id"),
                    ),
                    Some((_, width)) if u64::from(*field_value) >= 1u64 << width => out.push(
                        drive
                            .source
                            .error(
                                &path,
                                format!(
                                    "{field_value:X}h does not fit the {width} bit(s) of `{name}`"
                                ),
                            )
                            .hint("give the field's own value, shifted down to bit 0"),
                    ),
                    Some((lsb, _)) => value |= field_value << lsb,
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

#[cfg(test)]
mod tests {
    use super::bit_examples_match as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_an_example_that_matches_the_bits() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn multi_bit_fields_add_their_values_at_their_bits() {
        let yaml = valid_with(&[
            (
                r#"{ bits: "14:11", reserved: true }"#,
                r#"{ bits: "14:11", id: mode, name: Mode }"#,
            ),
            (
                "{ value: 0x8400, set: [command_enabled, run],",
                "{ value: 0x9C00, set: [command_enabled, run], fields: { mode: 3 },",
            ),
        ]);
        assert!(
            check_yaml(check, &yaml).is_empty(),
            "{:?}",
            check_yaml(check, &yaml)
        );
        let wide = yaml.replace("fields: { mode: 3 }", "fields: { mode: 16 }");
        let found = check_yaml(check, &wide);
        assert_eq!(found[0].message, "10h does not fit the 4 bit(s) of `mode`");
        assert_eq!(found[0].path, "bitfields[0].examples[0].fields.mode");
        let unknown = yaml.replace("fields: { mode: 3 }", "fields: { speed: 3 }");
        let found = check_yaml(check, &unknown);
        assert_eq!(found[0].message, "`speed` is not a field of `command_word`");
    }

    #[test]
    fn reports_a_value_the_fields_do_not_give() {
        let yaml = valid_with(&[("value: 0x8400, set", "value: 0x8000, set")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "bitfields[0].examples[0].value",
            "the fields set give 8400h, not 8000h",
            "Forward run",
        );
    }

    #[test]
    fn reports_a_name_that_is_not_a_field() {
        let yaml = valid_with(&[(
            "set: [command_enabled, run]",
            "set: [command_enabled, run, jog]",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "bitfields[0].examples[0].set",
            "`jog` is not a field of `command_word`",
            "Forward run",
        );
    }
}
