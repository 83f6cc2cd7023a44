//! Check: bit fields fit the word and do not overlap.

use crate::diagnostics::Diagnostics;
use crate::validate::bit_span;
use crate::validate::Context;

/// Bit fields fit the word and do not overlap.
pub fn bit_fields_do_not_overlap(drive: &Context, out: &mut Diagnostics) {
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

#[cfg(test)]
mod tests {
    use super::bit_fields_do_not_overlap as check;
    use crate::validate::testing::{assert_at, assert_column, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_fields_that_tile_the_word() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn reports_the_later_of_two_overlapping_fields() {
        let yaml = valid_with(&[(
            r#"{ bits: "9:0", reserved: true }"#,
            r#"{ bits: "10:0", reserved: true }"#,
        )]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "bitfields[0].fields[3]",
            "bit 10 of `command_word` is already used by `run` (fields[2])",
            r#"bits: "10:0""#,
        );
        assert_column(diagnostic, &yaml, r#"bits: "10:0""#);
    }

    #[test]
    fn names_a_reserved_owner_as_reserved() {
        let yaml = valid_with(&[("{ bit: 10, id: run,", "{ bit: 12, id: run,")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "bitfields[0].fields[2]",
            "bit 12 of `command_word` is already used by `reserved` (fields[1])",
            "bit: 12,",
        );
    }

    #[test]
    fn reports_spans_that_do_not_fit_or_are_malformed() {
        let cases = [
            ("{ bit: 16, id: run,", "bit 16 is outside a 16-bit word"),
            (r#"{ bits: "10", id: run,"#, "`bits: 10` is not \"msb:lsb\""),
            (
                r#"{ bits: "9:10", id: run,"#,
                "`bits: 9:10` needs 15 >= msb >= lsb",
            ),
            (
                r#"{ bit: 10, bits: "10:10", id: run,"#,
                "give exactly one of `bit` and `bits`",
            ),
        ];
        for (to, message) in cases {
            let yaml = valid_with(&[("{ bit: 10, id: run,", to)]);
            let found = check_yaml(check, &yaml);
            assert_at(
                only(&found),
                &yaml,
                "bitfields[0].fields[2]",
                message,
                "id: run,",
            );
        }
    }
}
