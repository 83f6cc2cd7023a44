//! Check: code-table values and error codes are unique and fit 16 bits, and the error
//! table's notation prints them.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;
use std::collections::HashMap;

/// Code-table values and error codes are unique and fit 16 bits.
pub fn code_values_are_unique(drive: &Context, out: &mut Diagnostics) {
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
    crate::protocols::check_notation(
        drive.model.error_codes.notation.as_ref(),
        "error_codes",
        &drive.source,
        out,
    );
    let mut seen: HashMap<u32, usize> = HashMap::new();
    for (j, code) in drive.model.error_codes.codes.iter().enumerate() {
        if code.code > 0xFFFF {
            out.push(
                drive
                    .source
                    .error(
                        &format!("error_codes.codes[{j}].code"),
                        format!("error code {:#X} does not fit in 16 bits", code.code),
                    )
                    .hint("error codes are the data word of an error reply"),
            );
        }
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

#[cfg(test)]
mod tests {
    use super::code_values_are_unique as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_distinct_codes() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn reports_a_code_used_twice_in_a_table() {
        let yaml = valid_with(&[("{ value: 1, id: even_parity", "{ value: 0, id: even_parity")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "codes[0].values[1].value",
            "code 0 appears twice in `parity` (first at values[0])",
            "id: even_parity",
        );
    }

    #[test]
    fn reports_a_code_beyond_16_bits() {
        let yaml = valid_with(&[(
            "{ value: 1, id: even_parity",
            "{ value: 0x10000, id: even_parity",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "codes[0].values[1].value",
            "code 0x10000 does not fit in 16 bits",
            "id: even_parity",
        );
    }

    #[test]
    fn reports_an_error_code_beyond_16_bits() {
        let yaml = valid_with(&[(
            "code: 0x0001, id: data_error",
            "code: 0x10001, id: data_error",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "error_codes.codes[1].code",
            "error code 0x10001 does not fit in 16 bits",
            "id: data_error",
        );
    }

    #[test]
    fn reports_an_error_code_used_twice() {
        let yaml = valid_with(&[(
            "code: 0x0001, id: data_error",
            "code: 0x0000, id: data_error",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "error_codes.codes[1].code",
            "error code 0000h appears twice (first at error_codes.codes[0])",
            "id: data_error",
        );
    }
}
