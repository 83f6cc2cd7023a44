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
