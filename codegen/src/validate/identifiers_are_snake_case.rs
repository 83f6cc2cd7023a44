//! Check: identifiers become Rust names: lower-case snake case.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;

/// Identifiers become Rust names: lower-case snake case.
pub fn identifiers_are_snake_case(drive: &Context, out: &mut Diagnostics) {
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
