//! Check: identifiers and codes are unique within their kind.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;
use std::collections::HashMap;

/// Identifiers and codes are unique within their kind.
pub fn names_are_unique(drive: &Context, out: &mut Diagnostics) {
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
