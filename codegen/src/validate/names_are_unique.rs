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
            "forbidden combination id",
            model
                .forbidden_combinations
                .iter()
                .enumerate()
                .map(|(i, c)| (format!("forbidden_combinations[{i}].id"), c.id.clone()))
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
    aliases_are_unique(drive, out);
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

/// A register alias names one register: it is no register's code or id, nor another
/// alias, ignoring case (a client may write `p.33` for `P.33`), and is not empty.
fn aliases_are_unique(drive: &Context, out: &mut Diagnostics) {
    let model = &drive.model;
    let mut names: HashMap<String, String> = HashMap::new();
    for (i, register) in model.registers.iter().enumerate() {
        for (key, name) in [("code", &register.code), ("id", &register.id)] {
            names
                .entry(name.to_ascii_lowercase())
                .or_insert(format!("registers[{i}].{key}"));
        }
    }
    for (i, register) in model.registers.iter().enumerate() {
        for (j, alias) in register.aliases.iter().enumerate() {
            let path = format!("registers[{i}].aliases[{j}]");
            if alias.trim().is_empty() {
                out.push(
                    drive
                        .source
                        .error(&path, "an empty register alias")
                        .hint("write the manual's other name for the register (`P.33`), or leave the alias out"),
                );
                continue;
            }
            match names.get(&alias.to_ascii_lowercase()) {
                Some(first) => out.push(
                    drive
                        .source
                        .error(
                            &path,
                            format!("register alias `{alias}` is already a register's name (at {first})"),
                        )
                        .hint("an alias must name one register: unique among the codes, ids and aliases, ignoring case"),
                ),
                None => {
                    names.insert(alias.to_ascii_lowercase(), path);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::names_are_unique as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_unique_names() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn reports_the_second_of_two_register_ids_and_codes() {
        let yaml = valid_with(&[("id: upper_limit_frequency", "id: maximum_frequency")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[2].id",
            "duplicate register id `maximum_frequency` (first at registers[1].id)",
            "code: UL,",
        );
        let yaml = valid_with(&[("code: UL,", "code: FH,")]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "registers[2].code",
            "duplicate register code `FH` (first at registers[1].code)",
            "upper_limit_frequency",
        );
        assert_eq!(
            diagnostic.hint.as_deref(),
            Some("each register code must be unique")
        );
    }

    #[test]
    fn reports_duplicates_within_one_bit_field_word_and_one_code_table() {
        let yaml = valid_with(&[
            ("{ bit: 10, id: run,", "{ bit: 10, id: command_enabled,"),
            ("id: even_parity", "id: no_parity"),
        ]);
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 2, "{found:#?}");
        assert_at(
            &found[0],
            &yaml,
            "bitfields[0].fields[2].id",
            "duplicate bit field id `command_enabled` (first at bitfields[0].fields[0].id)",
            "bit: 10,",
        );
        assert_at(
            &found[1],
            &yaml,
            "codes[0].values[1].id",
            "duplicate code id `no_parity` (first at codes[0].values[0].id)",
            "value: 1,",
        );
    }

    #[test]
    fn reports_duplicate_error_code_and_example_ids() {
        let yaml = valid_with(&[("id: data_error", "id: cannot_execute")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "error_codes.codes[1].id",
            "duplicate error code id `cannot_execute` (first at error_codes.codes[0].id)",
            "code: 0x0001",
        );
        let second = "  - id: read_maximum_frequency\n    protocol: ascii\n    source: \"5.1\"\n    description: Again.\n    request: { ascii: \"(R0012)\\r\", expect: { command: R, register: 0x0012 } }\n";
        let yaml = format!("{VALID}{second}");
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_eq!(diagnostic.path, "examples[1].id");
        assert_eq!(
            diagnostic.message,
            "duplicate example id `read_maximum_frequency` (first at examples[0].id)"
        );
    }

    #[test]
    fn kinds_and_words_are_separate_namespaces() {
        // A bit-field word may share its id with a code table and a register; two words
        // may have fields of the same name.
        let yaml = valid_with(&[
            ("- id: command_word", "- id: parity"),
            ("bitfield: command_word", "bitfield: parity"),
            ("id: parity_setting", "id: parity"),
        ]);
        assert!(check_yaml(check, &yaml).is_empty());
        let second = valid_with(&[(
            "\nregisters:",
            "  - id: status_word\n    name: Status word\n    source: \"7.2\"\n    fields:\n      - { bit: 10, id: run, name: Running }\n\nregisters:",
        )]);
        assert!(check_yaml(check, &second).is_empty());
    }
}
