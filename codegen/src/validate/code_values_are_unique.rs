//! Check: code-table values are unique and fit 16 bits.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;
use std::collections::HashMap;

/// Code-table values are unique and fit 16 bits.
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
