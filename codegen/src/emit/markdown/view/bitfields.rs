//! Bit fields: each field's bits and meaning, and the manual's worked values.

use super::code_tables::code_table_link;
use crate::ir::*;
use serde::Serialize;

#[derive(Serialize)]
pub(super) struct BitfieldView<'a> {
    #[serde(flatten)]
    bitfield: &'a BitfieldIr,
    fields: Vec<BitView<'a>>,
    examples: Vec<BitExampleView<'a>>,
}

#[derive(Serialize)]
struct BitView<'a> {
    #[serde(flatten)]
    field: &'a BitIr,
    bits_label: String,
    name: &'a str,
    /// For a multi-bit field, the link to the code table naming its values (empty: none).
    values: String,
}

#[derive(Serialize)]
struct BitExampleView<'a> {
    #[serde(flatten)]
    example: &'a BitExampleIr,
    value_hex: String,
    /// The one-bit fields set and the multi-bit fields' values (`character = 30h`).
    fields_display: String,
}

/// Every bit field, with each field's bits and the worked values.
pub(super) fn bitfield_views(drive: &DriveIr) -> Vec<BitfieldView<'_>> {
    drive
        .bitfields
        .iter()
        .map(|bitfield| BitfieldView {
            bitfield,
            fields: bitfield
                .fields
                .iter()
                .map(|field| BitView {
                    field,
                    bits_label: if field.width == 1 {
                        field.lsb.to_string()
                    } else {
                        format!("{}:{}", field.lsb + field.width - 1, field.lsb)
                    },
                    name: if field.reserved && field.name.is_empty() {
                        "Reserved"
                    } else {
                        &field.name
                    },
                    values: if field.width > 1 {
                        code_table_link(drive, field.code_table.as_deref())
                            .map_or_else(String::new, |link| format!("values: {link}"))
                    } else {
                        String::new()
                    },
                })
                .collect(),
            examples: bitfield
                .examples
                .iter()
                .map(|example| BitExampleView {
                    example,
                    value_hex: format!("{:04X}h", example.value),
                    fields_display: example
                        .set
                        .iter()
                        .cloned()
                        .chain(
                            example
                                .fields
                                .iter()
                                .map(|(id, v)| format!("{id} = {v:X}h")),
                        )
                        .collect::<Vec<_>>()
                        .join(", "),
                })
                .collect(),
        })
        .collect()
}
