//! Check: identifiers become Rust names: lower-case snake case.

use crate::diagnostics::Diagnostics;
use crate::naming::{method_name, module_name};
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
    ids.extend(
        model
            .sequences
            .iter()
            .enumerate()
            .map(|(i, q)| (format!("sequences[{i}].id"), q.id.as_str())),
    );
    for (path, id) in ids {
        // The drive id may be kebab case too (`vf-as1`): its module is `vf_as1`, its files
        // keep the id.
        let is_drive = path == "drive.id";
        // A leading `_` would leave `_1` as the type name `1` and `_` as an empty one.
        let valid = id.chars().next().is_some_and(|c| c.is_ascii_lowercase())
            && id.chars().all(|c| {
                c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_' || (is_drive && c == '-')
            });
        if !valid && is_drive {
            out.push(
                drive
                    .source
                    .error(
                        &path,
                        format!("drive id `{id}` is not lower-case snake or kebab case"),
                    )
                    .hint(
                        "the drive id names the generated module (`-` becomes `_`) and files: use a-z, 0-9, _ and - and start with a letter",
                    ),
            );
        } else if !valid {
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
        } else if is_drive && method_name(&module_name(id)) != module_name(id) {
            out.push(
                drive
                    .source
                    .error(&path, format!("drive id `{id}` is a Rust keyword"))
                    .hint(format!(
                        "the drive id becomes the generated module's name; use e.g. `{id}_drive`"
                    )),
            );
        } else if id == "self" && becomes_type_name(&path) {
            out.push(
                drive
                    .source
                    .error(
                        &path,
                        "identifier `self` becomes the Rust name `Self`, which is a keyword",
                    )
                    .hint("choose another identifier"),
            );
        }
    }
}

/// Whether the identifier at `path` becomes a type or variant name (bit fields become
/// methods, examples and sequences test functions, the drive id the module).
fn becomes_type_name(path: &str) -> bool {
    !(path == "drive.id"
        || path.starts_with("examples[")
        || path.starts_with("sequences[")
        || path.contains(".fields["))
}

#[cfg(test)]
mod tests {
    use super::identifiers_are_snake_case as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_snake_case_identifiers() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn reports_upper_case_and_dashes_wherever_an_identifier_is() {
        let cases = [
            (
                "id: maximum_frequency,",
                "id: MaximumFrequency,",
                "registers[1].id",
                "MaximumFrequency",
                "code: FH,",
            ),
            (
                "- id: command_word",
                "- id: commandWord",
                "bitfields[0].id",
                "commandWord",
                "- id: commandWord",
            ),
            (
                "id: run,",
                "id: Run,",
                "bitfields[0].fields[2].id",
                "Run",
                "bit: 10,",
            ),
            (
                "- id: parity",
                "- id: Parity",
                "codes[0].id",
                "Parity",
                "- id: Parity",
            ),
            (
                "id: even_parity",
                "id: even parity",
                "codes[0].values[1].id",
                "even parity",
                "value: 1,",
            ),
            (
                "id: data_error",
                "id: DataError",
                "error_codes.codes[1].id",
                "DataError",
                "code: 0x0001",
            ),
            (
                "id: read_maximum_frequency",
                "id: read.maximum",
                "examples[0].id",
                "read.maximum",
                "id: read.maximum",
            ),
        ];
        for (from, to, path, id, line) in cases {
            let yaml = valid_with(&[(from, to)]);
            let found = check_yaml(check, &yaml);
            assert_at(
                only(&found),
                &yaml,
                path,
                &format!("identifier `{id}` is not lower-case snake case"),
                line,
            );
        }
    }

    #[test]
    fn accepts_a_kebab_case_drive_id() {
        let yaml = valid_with(&[("id: test_drive", "id: vf-as1")]);
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn reports_a_drive_id_that_is_neither_snake_nor_kebab_case() {
        for id in ["Test-drive", "test.drive", "-test", "test drive"] {
            let yaml = valid_with(&[("id: test_drive", &format!("id: \"{id}\""))]);
            let found = check_yaml(check, &yaml);
            assert_at(
                only(&found),
                &yaml,
                "drive.id",
                &format!("drive id `{id}` is not lower-case snake or kebab case"),
                &format!("id: \"{id}\""),
            );
        }
    }

    #[test]
    fn reports_an_identifier_starting_with_a_digit() {
        let yaml = valid_with(&[("id: no_parity", "id: 0_none")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "codes[0].values[0].id",
            "identifier `0_none` is not lower-case snake case",
            "value: 0,",
        );
    }

    #[test]
    fn reports_an_identifier_starting_with_an_underscore() {
        for id in ["_1st", "_"] {
            let yaml = valid_with(&[("id: acceleration_time", &format!("id: {id}"))]);
            let found = check_yaml(check, &yaml);
            assert_at(
                only(&found),
                &yaml,
                "registers[0].id",
                &format!("identifier `{id}` is not lower-case snake case"),
                "code: Acc,",
            );
        }
    }

    #[test]
    fn reports_a_drive_id_that_is_a_keyword() {
        let yaml = valid_with(&[("id: test_drive", "id: type")]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "drive.id",
            "drive id `type` is a Rust keyword",
            "id: type",
        );
        assert_eq!(
            diagnostic.hint.as_deref(),
            Some("the drive id becomes the generated module's name; use e.g. `type_drive`")
        );
    }

    #[test]
    fn reports_self_where_it_becomes_a_type_name() {
        let cases = [
            (
                "id: acceleration_time",
                "id: self",
                "registers[0].id",
                "code: Acc,",
            ),
            (
                "- id: command_word",
                "- id: self",
                "bitfields[0].id",
                "- id: self",
            ),
            ("- id: parity", "- id: self", "codes[0].id", "- id: self"),
            (
                "id: no_parity",
                "id: self",
                "codes[0].values[0].id",
                "value: 0,",
            ),
            (
                "id: data_error",
                "id: self",
                "error_codes.codes[1].id",
                "code: 0x0001",
            ),
        ];
        for (from, to, path, line) in cases {
            let yaml = valid_with(&[(from, to)]);
            let found = check_yaml(check, &yaml);
            assert_at(
                only(&found),
                &yaml,
                path,
                "identifier `self` becomes the Rust name `Self`, which is a keyword",
                line,
            );
        }
        // Fields become methods (`self_`) and examples test functions (`example_self`).
        let yaml = valid_with(&[
            ("{ bit: 10, id: run,", "{ bit: 10, id: self,"),
            ("id: read_maximum_frequency", "id: self"),
        ]);
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn reports_a_field_that_is_neither_named_nor_reserved() {
        let yaml = valid_with(&[("{ bit: 10, id: run, name: Run }", "{ bit: 10, name: Run }")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "bitfields[0].fields[2]",
            "a bit field that is not reserved needs an `id`",
            "bit: 10,",
        );
    }
}
