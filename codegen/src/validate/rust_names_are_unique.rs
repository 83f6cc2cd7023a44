//! Check: distinct identifiers do not become the same Rust name.
//!
//! `acc_dec_2` and `acc_dec2` are different ids but the same type name `AccDec2`;
//! `names_are_unique` cannot see that. This check builds the names the Rust emitter
//! declares in each scope of the generated module and reports the second id that lands on
//! a name already taken, or on a name the generator itself always declares there.

use crate::diagnostics::Diagnostics;
use crate::naming::{const_name, method_name, type_name};
use crate::validate::Context;
use std::collections::{HashMap, HashSet};

/// One Rust scope of the generated module and the names declared in it.
struct Scope<'m> {
    /// The scope's Rust path inside the drive module (`registers`, `bits::CommandWord`).
    rust_path: String,
    /// What declares the names, for messages (`register id`, `bit field`).
    label: &'static str,
    /// How ids become names here, and what to do.
    hint: &'static str,
    /// Names the generator declares in the scope whatever the description says, and what
    /// they are.
    fixed: &'static [(&'static str, &'static str)],
    /// The names declared for the description's identifiers, in file order.
    items: Vec<Item<'m>>,
}

/// One Rust name declared for an identifier.
struct Item<'m> {
    /// YAML path of the identifier.
    path: String,
    /// The identifier.
    id: &'m str,
    /// The Rust name it becomes.
    rust: String,
    /// What kind of item (`type`, `method`), for messages.
    kind: &'static str,
}

const TYPE_HINT: &str = "type and variant names are the id in CamelCase without underscores (`acc_dec_2` and `acc_dec2` both give `AccDec2`); rename one of the two";

/// Distinct identifiers do not become the same Rust name in one scope.
pub fn rust_names_are_unique(drive: &Context, out: &mut Diagnostics) {
    for scope in scopes(drive) {
        report(drive, &scope, out);
    }
}

/// A scope of type or variant names (`type_name` of each id).
fn types<'m>(
    label: &'static str,
    rust_path: &str,
    kind: &'static str,
    ids: Vec<(String, &'m str)>,
) -> Scope<'m> {
    Scope {
        rust_path: rust_path.to_owned(),
        label,
        hint: TYPE_HINT,
        fixed: &[],
        items: ids
            .into_iter()
            .map(|(path, id)| Item {
                path,
                rust: type_name(id),
                id,
                kind,
            })
            .collect(),
    }
}

/// Every scope in which the emitter (`emit::rust`) declares names made from identifiers.
fn scopes(drive: &Context) -> Vec<Scope<'_>> {
    let model = &drive.model;
    let mut scopes = Vec::new();
    let mut registers = types(
        "register id",
        "registers",
        "type",
        model
            .registers
            .iter()
            .enumerate()
            .map(|(i, r)| (format!("registers[{i}].id"), r.id.as_str()))
            .collect(),
    );
    registers.fixed = &[("ALL", "the list of every register")];
    for (i, register) in model.registers.iter().enumerate() {
        for (j, alias) in register.aliases.iter().enumerate() {
            if let Some(rust) = crate::naming::alias_type_name(alias) {
                registers.items.push(Item {
                    path: format!("registers[{i}].aliases[{j}]"),
                    id: alias,
                    rust,
                    kind: "type alias",
                });
            }
        }
    }
    scopes.push(registers);
    // Bit-field words and code tables live in separate modules (`bits`, `codes`).
    scopes.push(types(
        "bit-field word id",
        "bits",
        "type",
        model
            .bitfields
            .iter()
            .enumerate()
            .map(|(i, b)| (format!("bitfields[{i}].id"), b.id.as_str()))
            .collect(),
    ));
    scopes.push(types(
        "code table id",
        "codes",
        "type",
        model
            .codes
            .iter()
            .enumerate()
            .map(|(i, c)| (format!("codes[{i}].id"), c.id.as_str()))
            .collect(),
    ));
    for (i, table) in model.codes.iter().enumerate() {
        scopes.push(types(
            "code id",
            &format!("codes::{}", type_name(&table.id)),
            "variant",
            table
                .values
                .iter()
                .enumerate()
                .map(|(j, v)| (format!("codes[{i}].values[{j}].id"), v.id.as_str()))
                .collect(),
        ));
    }
    scopes.push(types(
        "error code id",
        "ErrorCode",
        "variant",
        model
            .error_codes
            .codes
            .iter()
            .enumerate()
            .map(|(i, c)| (format!("error_codes.codes[{i}].id"), c.id.as_str()))
            .collect(),
    ));
    for (i, bitfield) in model.bitfields.iter().enumerate() {
        let mut items = Vec::new();
        for (j, field) in bitfield.fields.iter().enumerate() {
            // Reserved fields get no accessors.
            let (Some(id), false) = (field.id.as_deref(), field.reserved) else {
                continue;
            };
            let path = format!("bitfields[{i}].fields[{j}].id");
            for (rust, kind) in [
                (method_name(id), "method"),
                (format!("with_{id}"), "method"),
                (id.to_ascii_uppercase(), "constant"),
            ] {
                items.push(Item {
                    path: path.clone(),
                    id,
                    rust,
                    kind,
                });
            }
        }
        scopes.push(Scope {
            rust_path: format!("bits::{}", type_name(&bitfield.id)),
            label: "bit field",
            hint: "a field `x` becomes the getter `x` (`x_` for a keyword), the setter `with_x` and the mask `X`; rename one of the two",
            fixed: &[
                ("RESERVED", "the mask of reserved bits"),
                ("FIELDS", "the list of named fields"),
                ("new", "the constructor"),
                ("bits", "the raw word's getter"),
                ("has_reserved_bits", "the reserved-bits test"),
            ],
            items,
        });
    }
    let mut items = Vec::new();
    for (i, reference) in model.protocols.iter().enumerate() {
        let prefix = const_name(&reference.id);
        let path = format!("protocols[{i}].id");
        let mut names = vec![prefix.clone(), format!("{prefix}_COMMANDS")];
        if let Some(lowered) = drive.protocols.iter().find(|p| p.id == reference.id) {
            let runtime = &lowered.runtime;
            let layouts = runtime
                .commands
                .iter()
                .flat_map(|command| [&command.request, &command.reply])
                .chain(runtime.error_reply.iter());
            for layout in layouts {
                let name = format!("{prefix}_{}", const_name(&layout.name));
                if !names.contains(&name) {
                    names.push(name);
                }
            }
        }
        items.extend(names.into_iter().map(|rust| Item {
            path: path.clone(),
            id: &reference.id,
            rust,
            kind: "static",
        }));
    }
    scopes.push(Scope {
        rust_path: "protocols".to_owned(),
        label: "protocol id",
        hint: "a protocol `x-y` becomes the statics `X_Y`, `X_Y_COMMANDS` and `X_Y_<LAYOUT>` for each of its layouts; rename one of the two",
        fixed: &[
            ("ALL", "the list of every protocol"),
            ("ERROR_CODES", "the table of error codes"),
        ],
        items,
    });
    scopes
}

/// Reports each identifier whose Rust name is taken in its scope, once.
fn report(drive: &Context, scope: &Scope<'_>, out: &mut Diagnostics) {
    let mut taken: HashMap<&str, &Item<'_>> = HashMap::new();
    let mut reported: HashSet<&str> = HashSet::new();
    for item in &scope.items {
        let rust = format!("{}::{}", scope.rust_path, item.rust);
        let label = if item.kind == "type alias" {
            "register alias"
        } else {
            scope.label
        };
        let problem = if let Some((_, what)) = scope.fixed.iter().find(|(n, _)| *n == item.rust) {
            Some((
                format!(
                    "{} `{}` becomes the Rust {} `{rust}`, which the generator already declares as {what}",
                    label, item.id, item.kind
                ),
                "rename it: the generated code needs that name",
            ))
        } else {
            match taken.get(item.rust.as_str()) {
                // The same name twice, also in another case (`P.9` and `p.9`), is
                // `names_are_unique`'s (or, for ids, `identifiers_are_snake_case`'s) to
                // report: the Rust names follow from it.
                Some(first) if !first.id.eq_ignore_ascii_case(item.id) => Some((
                    format!(
                        "{} `{}` becomes the Rust {} `{rust}`, like `{}` at {}",
                        label, item.id, item.kind, first.id, first.path
                    ),
                    scope.hint,
                )),
                Some(_) => None,
                None => {
                    taken.insert(&item.rust, item);
                    None
                }
            }
        };
        if let Some((message, hint)) = problem {
            if reported.insert(&item.path) {
                out.push(drive.source.error(&item.path, message).hint(hint));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::rust_names_are_unique as check;
    use crate::validate::testing::{assert_at, assert_column, check_yaml, only, valid_with, VALID};

    const RESERVED_LINE: &str = r#"      - { bits: "14:11", reserved: true }"#;

    /// The test drive with one more field in `command_word`, at bit 14 (fields[1]).
    fn with_field(id: &str) -> String {
        valid_with(&[(
            RESERVED_LINE,
            &format!("      - {{ bit: 14, id: {id}, name: Extra }}\n      - {{ bits: \"13:11\", reserved: true }}"),
        )])
    }

    #[test]
    fn accepts_distinct_names_and_equal_names_in_different_scopes() {
        assert!(check_yaml(check, VALID).is_empty());
        // A register, a bit-field word and a code table are types of three modules; two
        // words have separate methods; two tables separate variants.
        let yaml = valid_with(&[
            ("- id: command_word", "- id: parity"),
            ("bitfield: command_word", "bitfield: parity"),
            ("id: parity_setting", "id: parity"),
            ("id: data_error", "id: no_parity"),
            (
                "\nregisters:",
                "  - id: status_word\n    name: Status word\n    source: \"7.2\"\n    fields:\n      - { bit: 10, id: run, name: Running }\n\nregisters:",
            ),
        ]);
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn reports_register_ids_that_give_one_type_name() {
        let yaml = valid_with(&[
            ("id: maximum_frequency,", "id: frequency_2,"),
            ("id: upper_limit_frequency,", "id: frequency2,"),
        ]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "registers[2].id",
            "register id `frequency2` becomes the Rust type `registers::Frequency2`, like `frequency_2` at registers[1].id",
            "code: UL,",
        );
        assert_column(diagnostic, &yaml, "frequency2");
        assert!(diagnostic
            .hint
            .as_deref()
            .is_some_and(|hint| hint.contains("CamelCase")));
    }

    #[test]
    fn leaves_an_id_used_twice_to_names_are_unique() {
        let yaml = valid_with(&[("id: upper_limit_frequency,", "id: maximum_frequency,")]);
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn reports_a_register_named_like_the_list_of_registers() {
        let yaml = valid_with(&[("id: acceleration_time,", "id: a_l_l,")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[0].id",
            "register id `a_l_l` becomes the Rust type `registers::ALL`, which the generator already declares as the list of every register",
            "code: Acc,",
        );
    }

    #[test]
    fn reports_bit_field_words_that_give_one_type_name() {
        let yaml = valid_with(&[(
            "\nregisters:",
            "  - id: command__word\n    name: Second word\n    source: \"7.2\"\n    fields:\n      - { bit: 10, id: run, name: Running }\n\nregisters:",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "bitfields[1].id",
            "bit-field word id `command__word` becomes the Rust type `bits::CommandWord`, like `command_word` at bitfields[0].id",
            "- id: command__word",
        );
    }

    #[test]
    fn reports_codes_and_error_codes_that_give_one_variant() {
        let yaml = valid_with(&[
            ("id: even_parity", "id: no_parity_"),
            ("id: data_error", "id: cannot__execute"),
        ]);
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 2, "{found:#?}");
        assert_at(
            &found[0],
            &yaml,
            "codes[0].values[1].id",
            "code id `no_parity_` becomes the Rust variant `codes::Parity::NoParity`, like `no_parity` at codes[0].values[0].id",
            "value: 1,",
        );
        assert_at(
            &found[1],
            &yaml,
            "error_codes.codes[1].id",
            "error code id `cannot__execute` becomes the Rust variant `ErrorCode::CannotExecute`, like `cannot_execute` at error_codes.codes[0].id",
            "code: 0x0001",
        );
    }

    #[test]
    fn reports_a_setter_that_is_another_fields_getter() {
        let yaml = with_field("with_run");
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "bitfields[0].fields[3].id",
            "bit field `run` becomes the Rust method `bits::CommandWord::with_run`, like `with_run` at bitfields[0].fields[1].id",
            "bit: 10,",
        );
        assert!(diagnostic
            .hint
            .as_deref()
            .is_some_and(|hint| hint.contains("the setter `with_x`")));
    }

    #[test]
    fn reports_a_getter_that_is_a_keywords_getter() {
        let yaml = valid_with(&[
            ("id: command_enabled,", "id: type,"),
            ("id: run,", "id: type_,"),
            ("set: [command_enabled, run]", "set: [type, type_]"),
        ]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "bitfields[0].fields[2].id",
            "bit field `type_` becomes the Rust method `bits::CommandWord::type_`, like `type` at bitfields[0].fields[0].id",
            "bit: 10,",
        );
    }

    #[test]
    fn reports_fields_named_like_the_generated_members() {
        for (id, rust, what) in [
            (
                "reserved",
                "constant `bits::CommandWord::RESERVED`",
                "the mask of reserved bits",
            ),
            (
                "fields",
                "constant `bits::CommandWord::FIELDS`",
                "the list of named fields",
            ),
            (
                "bits",
                "method `bits::CommandWord::bits`",
                "the raw word's getter",
            ),
            ("new", "method `bits::CommandWord::new`", "the constructor"),
        ] {
            let yaml = with_field(id);
            let found = check_yaml(check, &yaml);
            assert_at(
                only(&found),
                &yaml,
                "bitfields[0].fields[1].id",
                &format!("bit field `{id}` becomes the Rust {rust}, which the generator already declares as {what}"),
                "bit: 14,",
            );
        }
    }

    #[test]
    fn reports_protocol_ids_that_give_one_static() {
        let protocol = r#"  - { id: ascii, uses: toshiba-ascii, source: "4.1" }"#;
        let cases = [
            // Each protocol also declares its command table and one static per layout.
            ("ascii_commands", "protocol id `ascii_commands` becomes the Rust static `protocols::ASCII_COMMANDS`, like `ascii` at protocols[0].id"),
            ("ascii_read_request", "protocol id `ascii_read_request` becomes the Rust static `protocols::ASCII_READ_REQUEST`, like `ascii` at protocols[0].id"),
            ("error_codes", "protocol id `error_codes` becomes the Rust static `protocols::ERROR_CODES`, which the generator already declares as the table of error codes"),
        ];
        for (id, message) in cases {
            let yaml = valid_with(&[(
                protocol,
                &format!("{protocol}\n  - {{ id: {id}, uses: toshiba-ascii, source: \"4.1\" }}"),
            )]);
            let found = check_yaml(check, &yaml);
            assert_at(
                only(&found),
                &yaml,
                "protocols[1].id",
                message,
                &format!("id: {id},"),
            );
        }
        // `ASCII` is `ascii` in another case: `identifiers_are_snake_case` reports it, and
        // the clash of their statics follows from it.
        let yaml = valid_with(&[(
            protocol,
            &format!("{protocol}\n  - {{ id: ASCII, uses: toshiba-ascii, source: \"4.1\" }}"),
        )]);
        assert!(check_yaml(check, &yaml).is_empty());
    }
}
