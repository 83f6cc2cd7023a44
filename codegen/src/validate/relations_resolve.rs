//! Check: the relations between registers resolve and agree: serial ports (`ports:`),
//! held-at-trip copies (`held_at_trip_of`), scales chosen by another register
//! (`scale_by`, and the `given` values of value examples) and the formulas of
//! `conversions:` (each worked example computes the manual's result).

use crate::diagnostics::Diagnostics;
use crate::parse::model::{ConditionValueModel, RegisterModel};
use crate::validate::ranges::{self, RegisterIndex};
use crate::validate::{formula, Context};
use std::collections::{BTreeSet, HashMap};

/// What a register's value is, for registers that stand for one another (a port's copy, a
/// held copy): unit, scale, sign, width, bit field and code table.
fn shape(register: &RegisterModel) -> String {
    format!(
        "{}|{}|{}|{:?}|{}|{}",
        register.unit.as_deref().unwrap_or(""),
        ranges::scale_of(register),
        register.signed,
        register.data_type,
        register.bitfield.as_deref().unwrap_or(""),
        register.code_table.as_deref().unwrap_or(""),
    )
}

/// Ports, held copies, chosen scales and conversions name registers that exist and agree.
pub fn relations_resolve(drive: &Context, out: &mut Diagnostics) {
    let index = RegisterIndex::new(&drive.model);
    let unknown = |out: &mut Diagnostics, path: &str, name: &str| {
        out.push(
            drive
                .source
                .error(path, format!("register `{name}` is not defined"))
                .hint("name a register by its code or id"),
        );
    };
    ports(drive, &index, out, &unknown);
    persistence(drive, &index, out, &unknown);
    forbidden_combinations(drive, &index, out, &unknown);
    for (i, register) in drive.model.registers.iter().enumerate() {
        if let Some(live) = &register.held_at_trip_of {
            let path = format!("registers[{i}].held_at_trip_of");
            match index.find(live) {
                None => unknown(out, &path, live),
                Some(found) if found.id == register.id => out.push(
                    drive
                        .source
                        .error(&path, format!("`{}` cannot hold its own value", register.code))
                        .hint("name the live register whose value it keeps at a trip; a register that itself stops changing while tripped has `live_except_while_tripped: true`"),
                ),
                Some(found) if shape(found) != shape(register) => out.push(
                    drive
                        .source
                        .error(
                            &path,
                            format!(
                                "`{}` and the live register `{}` it holds differ in unit, scale, sign, width, bit field or code table",
                                register.code, found.code
                            ),
                        )
                        .hint("a held copy reads like its live register: give both the same unit and scale"),
                ),
                Some(_) => {}
            }
        }
        if let Some(scale_by) = &register.scale_by {
            let path = format!("registers[{i}].scale_by");
            if index.find(&scale_by.register).is_none() {
                unknown(out, &format!("{path}.register"), &scale_by.register);
            }
            let mut seen = BTreeSet::new();
            for (j, choice) in scale_by.values.iter().enumerate() {
                if !seen.insert(choice.value) {
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("{path}.values[{j}].value"),
                                format!("selector value {} is given twice", choice.value),
                            )
                            .hint("give each selector value once"),
                    );
                }
                if !(choice.scale.is_finite() && choice.scale > 0.0) {
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("{path}.values[{j}].scale"),
                                format!("scale {} is not a positive number", choice.scale),
                            )
                            .hint("the engineering value of one raw step, e.g. 0.01"),
                    );
                }
            }
            if let Some(other) = &scale_by.otherwise {
                if !(other.scale.is_finite() && other.scale > 0.0) {
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("{path}.otherwise.scale"),
                                format!("scale {} is not a positive number", other.scale),
                            )
                            .hint("the engineering value of one raw step, e.g. 0.1"),
                    );
                }
            }
        }
    }
    for (i, register) in drive.model.registers.iter().enumerate() {
        let (low, high) = ranges::word_limits(register);
        let word_max = if register.signed {
            // Two's complement: every bit pattern of the word is a raw word.
            (high - low) as u64
        } else {
            high as u64
        };
        for (j, special) in register.special_values.iter().enumerate() {
            let path = format!("registers[{i}].special_values[{j}]");
            if u64::from(special.raw) > word_max {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("{path}.raw"),
                            format!("raw {:X}h does not fit the register's word", special.raw),
                        )
                        .hint("the raw word carrying the special value, e.g. 0xFFFF"),
                );
            }
            if !is_snake_case(&special.id) {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("{path}.id"),
                            format!("`{}` is not lower snake case", special.id),
                        )
                        .hint("use lower_snake_case"),
                );
            }
        }
    }
    for (i, example) in drive.model.value_examples.iter().enumerate() {
        for name in example.given.keys() {
            if index.find(name).is_none() {
                unknown(out, &format!("value_examples[{i}].given.{name}"), name);
            }
        }
    }
    conversions(drive, &index, out, &unknown);
}

fn ports(
    drive: &Context,
    index: &RegisterIndex<'_>,
    out: &mut Diagnostics,
    unknown: &dyn Fn(&mut Diagnostics, &str, &str),
) {
    let Some(ports) = &drive.model.ports else {
        return;
    };
    let ids: Vec<&str> = ports.list.iter().map(|p| p.id.as_str()).collect();
    let mut seen = BTreeSet::new();
    for (i, port) in ports.list.iter().enumerate() {
        if !is_snake_case(&port.id) {
            out.push(
                drive
                    .source
                    .error(
                        &format!("ports.list[{i}].id"),
                        format!("`{}` is not lower snake case", port.id),
                    )
                    .hint(
                        "it names a Rust constant and a command-line choice: use lower_snake_case",
                    ),
            );
        }
        if !seen.insert(port.id.as_str()) {
            out.push(
                drive
                    .source
                    .error(
                        &format!("ports.list[{i}].id"),
                        format!("port `{}` is described twice", port.id),
                    )
                    .hint("give each port its own id"),
            );
        }
        for (setting, name) in &port.settings {
            if index.find(name).is_none() {
                unknown(out, &format!("ports.list[{i}].settings.{setting}"), name);
            }
        }
        if let Some(first) = ports.list.first() {
            let mine: Vec<&String> = port.settings.keys().collect();
            let theirs: Vec<&String> = first.settings.keys().collect();
            if mine != theirs {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("ports.list[{i}].settings"),
                            format!(
                                "port `{}` names other settings than port `{}`",
                                port.id, first.id
                            ),
                        )
                        .hint("every port names the same settings (a setting both share goes under `shared`)"),
                );
            }
        }
    }
    for (i, name) in ports.shared.iter().enumerate() {
        if index.find(name).is_none() {
            unknown(out, &format!("ports.shared[{i}]"), name);
        }
    }
    let mut rows_of: HashMap<String, usize> = HashMap::new();
    for (i, row) in ports.registers.iter().enumerate() {
        let path = format!("ports.registers[{i}]");
        for port in row.keys() {
            if !ids.contains(&port.as_str()) {
                out.push(
                    drive
                        .source
                        .error(&format!("{path}.{port}"), format!("`{port}` is not a port"))
                        .hint(format!(
                            "name a port under `ports.list` ({})",
                            ids.join(", ")
                        )),
                );
            }
        }
        let missing: Vec<&str> = ids
            .iter()
            .copied()
            .filter(|id| !row.contains_key(*id))
            .collect();
        if !missing.is_empty() {
            out.push(
                drive
                    .source
                    .error(
                        &path,
                        format!("the copy on port `{}` is missing", missing.join("`, `")),
                    )
                    .hint("a register that exists once per port names its copy on every port"),
            );
        }
        let mut shapes = BTreeSet::new();
        for (port, name) in row {
            let Some(register) = index.find(name) else {
                unknown(out, &format!("{path}.{port}"), name);
                continue;
            };
            shapes.insert(shape(register));
            if let Some(other) = rows_of.insert(register.id.clone(), i) {
                if other != i {
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("{path}.{port}"),
                                format!(
                                    "`{}` is already a port copy in ports.registers[{other}]",
                                    register.code
                                ),
                            )
                            .hint("a register belongs to one group of port copies"),
                    );
                }
            }
        }
        if shapes.len() > 1 {
            out.push(
                drive
                    .source
                    .error(
                        &path,
                        "the port copies differ in unit, scale, sign, width, bit field or code table",
                    )
                    .hint("the copies of one register on each port read and write alike"),
            );
        }
    }
}

/// `lower_snake_case`: a lower-case letter, then lower-case letters, digits and `_`.
/// The persistence selector (`persistence:`) is a writable register, its two values differ
/// and lie in its range, and its register spans run upwards.
fn persistence(
    drive: &Context,
    index: &RegisterIndex<'_>,
    out: &mut Diagnostics,
    unknown: &dyn Fn(&mut Diagnostics, &str, &str),
) {
    let Some(persistence) = &drive.model.persistence else {
        return;
    };
    let error = |out: &mut Diagnostics, path: &str, message: String, hint: &str| {
        out.push(drive.source.error(path, message).hint(hint));
    };
    match index.find(&persistence.selector) {
        None => unknown(out, "persistence.selector", &persistence.selector),
        Some(register) => {
            if register.access == Some(vfd_runtime::Access::ReadOnly) {
                error(
                    out,
                    "persistence.selector",
                    format!(
                        "`{}` is read-only, so the master cannot set it",
                        register.code
                    ),
                    "name the register whose value chooses where parameter writes go",
                );
            }
            if register.range.is_some() {
                let (low, high) = index.raw_range(register);
                for (key, value) in [
                    ("ram", persistence.ram),
                    ("persistent", persistence.persistent),
                ] {
                    if !(low..=high).contains(&i64::from(value)) {
                        error(
                            out,
                            &format!("persistence.{key}"),
                            format!(
                                "{value} is outside `{}`'s raw range {low} to {high}",
                                register.code
                            ),
                            "give the selector's values as the manual lists them",
                        );
                    }
                }
            }
        }
    }
    if persistence.ram == persistence.persistent {
        error(
            out,
            "persistence.persistent",
            format!("`ram` and `persistent` are both {}", persistence.ram),
            "give the selector value for RAM-only writes and the one for RAM + EEPROM writes",
        );
    }
    for (i, span) in persistence.registers.iter().enumerate() {
        if span.from > span.to {
            error(
                out,
                &format!("persistence.registers[{i}].to"),
                format!(
                    "the span ends at {:04X}h, before its start {:04X}h",
                    span.to, span.from
                ),
                "give the first register number in `from` and the last in `to`",
            );
        }
    }
}

fn is_snake_case(name: &str) -> bool {
    name.starts_with(|c: char| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}

fn conversions(
    drive: &Context,
    index: &RegisterIndex<'_>,
    out: &mut Diagnostics,
    unknown: &dyn Fn(&mut Diagnostics, &str, &str),
) {
    for (i, conversion) in drive.model.conversions.iter().enumerate() {
        let path = format!("conversions[{i}]");
        let names = std::iter::once((format!("{path}.id"), conversion.id.as_str())).chain(
            conversion
                .inputs
                .iter()
                .enumerate()
                .map(|(j, input)| (format!("{path}.inputs[{j}].name"), input.name.as_str())),
        );
        for (at, name) in names {
            if !is_snake_case(name) {
                out.push(
                    drive
                        .source
                        .error(&at, format!("`{name}` is not lower snake case"))
                        .hint("it names a Rust function or argument: use lower_snake_case"),
                );
            }
        }
        let names: Vec<&str> = conversion.inputs.iter().map(|x| x.name.as_str()).collect();
        for (j, input) in conversion.inputs.iter().enumerate() {
            if let Some(name) = &input.register {
                if index.find(name).is_none() {
                    unknown(out, &format!("{path}.inputs[{j}].register"), name);
                }
            }
        }
        if let Some(name) = &conversion.result {
            if index.find(name).is_none() {
                unknown(out, &format!("{path}.result"), name);
            }
        }
        if let Some(when) = &conversion.when {
            if index.find(&when.register).is_none() {
                unknown(out, &format!("{path}.when.register"), &when.register);
            }
            if let ConditionValueModel::Word(word) = &when.value {
                if word != "nonzero" {
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("{path}.when.value"),
                                format!("`{word}` is neither a number nor `nonzero`"),
                            )
                            .hint("give the selector's value, or `nonzero` for any value but 0"),
                    );
                }
            }
        }
        let program = match formula::parse(&conversion.formula, &names) {
            Ok(program) => program,
            Err(problem) => {
                out.push(
                    drive
                        .source
                        .error(&format!("{path}.formula"), problem)
                        .hint("write + - * / and parentheses over numbers and the inputs' names"),
                );
                continue;
            }
        };
        let truncate = conversion.rounding.is_some();
        for (j, example) in conversion.examples.iter().enumerate() {
            let mut values = Vec::new();
            for input in &conversion.inputs {
                match example.inputs.get(&input.name) {
                    Some(value) => values.push(value * input.times.unwrap_or(1.0)),
                    None => {
                        out.push(
                            drive
                                .source
                                .error(
                                    &format!("{path}.examples[{j}].inputs"),
                                    format!("input `{}` is not given", input.name),
                                )
                                .hint("give every input of the formula a value"),
                        );
                        values.clear();
                        break;
                    }
                }
            }
            if values.len() != conversion.inputs.len() {
                continue;
            }
            let result =
                vfd_runtime::conversion::run(&program, |k| values.get(usize::from(k)).copied())
                    .map(|v| if truncate { v.trunc() } else { v });
            if result
                .is_none_or(|r| (r - example.result).abs() > 1e-6 * example.result.abs().max(1.0))
            {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("{path}.examples[{j}].result"),
                            format!(
                                "the formula gives {} here, not {}",
                                result.map_or_else(|| "no result".to_owned(), |r| r.to_string()),
                                example.result
                            ),
                        )
                        .hint("check the formula, the inputs' `times` and `rounding`, or record a manual mistake"),
                );
            }
        }
    }
}

/// Each forbidden combination has at least two conditions, each about another register
/// that exists, with values the register can hold (whole raw words within its range).
fn forbidden_combinations(
    drive: &Context,
    index: &RegisterIndex<'_>,
    out: &mut Diagnostics,
    unknown: &dyn Fn(&mut Diagnostics, &str, &str),
) {
    for (i, combination) in drive.model.forbidden_combinations.iter().enumerate() {
        let path = format!("forbidden_combinations[{i}]");
        if !is_snake_case(&combination.id) {
            out.push(
                drive
                    .source
                    .error(
                        &format!("{path}.id"),
                        format!("id `{}` is not lower snake case", combination.id),
                    )
                    .hint("write it like `two_stop_bits_with_parity`"),
            );
        }
        if combination.when.len() < 2 {
            out.push(
                drive
                    .source
                    .error(
                        &format!("{path}.when"),
                        "a forbidden combination needs at least two conditions",
                    )
                    .hint("one condition alone is a range: narrow the register's `range` instead"),
            );
        }
        let mut seen: Vec<&str> = Vec::new();
        for (j, condition) in combination.when.iter().enumerate() {
            let at = format!("{path}.when[{j}]");
            let Some(register) = index.find(&condition.register) else {
                unknown(out, &format!("{at}.register"), &condition.register);
                continue;
            };
            if seen.contains(&register.code.as_str()) {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("{at}.register"),
                            format!(
                                "register `{}` has two conditions in one combination",
                                register.code
                            ),
                        )
                        .hint("list all its values in one condition's `values`"),
                );
            }
            seen.push(&register.code);
            if condition.values.is_empty() {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("{at}.values"),
                            "a condition needs at least one value",
                        )
                        .hint("the register's values, in its unit, that fulfil the condition"),
                );
            }
            let scale = ranges::scale_of(register);
            let (low, high) = index.raw_range(register);
            // A scale that is not positive or a range in the wrong order is reported once,
            // as itself, not again for each value it makes unholdable.
            if !ranges::has_sound_scale(register) || low > high {
                continue;
            }
            for (k, value) in condition.values.iter().enumerate() {
                let raw = value / scale;
                if (raw - raw.round()).abs() > 1e-6
                    || (raw.round() as i64) < low
                    || (raw.round() as i64) > high
                {
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("{at}.values[{k}]"),
                                format!(
                                    "{value} is not a value `{}` can hold (a whole step of {scale} within its range)",
                                    register.code
                                ),
                            )
                            .hint("give the register's values in its unit, as its range does"),
                    );
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::relations_resolve as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    const PORTS: &str = "ports:
  source: \"1\"
  list:
    - { id: left, name: Left port, settings: { baud_rate: Acc } }
    - { id: right, name: Right port, settings: { baud_rate: UL } }
  shared: [F601]
  registers:
    - { left: FH, right: UL }
";

    fn with_ports(ports: &str) -> String {
        format!("{VALID}{ports}")
    }

    #[test]
    fn accepts_ports_held_copies_scales_and_conversions_that_resolve() {
        assert!(check_yaml(check, VALID).is_empty());
        let yaml = with_ports(PORTS);
        assert!(
            check_yaml(check, &yaml).is_empty(),
            "{:#?}",
            check_yaml(check, &yaml)
        );
        let yaml = valid_with(&[(
            "default: 80.0, source: \"11.1\" }\n  - { address: 0x0012",
            "default: 80.0, source: \"11.1\", scale_by: { register: F601, values: [{ value: 0, scale: 0.01 }, { value: 1, scale: 0.1 }] } }\n  - { address: 0x0012",
        ), ("range: { min: 0.5, max: FH }, default: 80.0,", "range: { min: 0.5, max: FH }, default: 80.0, held_at_trip_of: FH,")]);
        assert!(
            check_yaml(check, &yaml).is_empty(),
            "{:#?}",
            check_yaml(check, &yaml)
        );
    }

    #[test]
    fn reports_a_port_copy_missing_unknown_or_of_another_shape() {
        let yaml = with_ports(&PORTS.replace(
            "{ left: FH, right: UL }",
            "{ left: FH }\n    - { left: Acc, right: XX }\n    - { left: UL, right: Acc }",
        ));
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 4, "{found:#?}");
        assert_at(
            &found[0],
            &yaml,
            "ports.registers[0]",
            "the copy on port `right` is missing",
            "{ left: FH }",
        );
        assert_at(
            &found[1],
            &yaml,
            "ports.registers[1].right",
            "register `XX` is not defined",
            "right: XX",
        );
        assert_at(
            &found[2],
            &yaml,
            "ports.registers[2].right",
            "`Acc` is already a port copy in ports.registers[1]",
            "{ left: UL, right: Acc }",
        );
        assert_eq!(
            found[3].message,
            "the port copies differ in unit, scale, sign, width, bit field or code table"
        );
    }

    #[test]
    fn reports_ports_naming_different_settings() {
        let yaml =
            with_ports(&PORTS.replace("settings: { baud_rate: UL }", "settings: { baud: UL }"));
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "ports.list[1].settings",
            "port `right` names other settings than port `left`",
            "Right port",
        );
    }

    #[test]
    fn reports_a_held_copy_of_itself_or_of_another_shape() {
        let yaml = valid_with(&[(
            "range: { min: 0.5, max: FH }, default: 80.0,",
            "range: { min: 0.5, max: FH }, default: 80.0, held_at_trip_of: UL,",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[2].held_at_trip_of",
            "`UL` cannot hold its own value",
            "code: UL,",
        );
        let yaml = valid_with(&[(
            "range: { min: 0.5, max: FH }, default: 80.0,",
            "range: { min: 0.5, max: FH }, default: 80.0, held_at_trip_of: Acc,",
        )]);
        let found = check_yaml(check, &yaml);
        assert_eq!(only(&found).message, "`UL` and the live register `Acc` it holds differ in unit, scale, sign, width, bit field or code table");
    }

    #[test]
    fn reports_a_scale_selector_given_twice_or_unknown() {
        let yaml = valid_with(&[(
            "default: 10.0, source: \"11.1\" }",
            "default: 10.0, source: \"11.1\", scale_by: { register: XY, values: [{ value: 0, scale: 0.01 }, { value: 0, scale: 0.1 }] } }",
        )]);
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 2, "{found:#?}");
        assert_eq!(found[0].message, "register `XY` is not defined");
        assert_eq!(found[0].path, "registers[0].scale_by.register");
        assert_eq!(found[1].message, "selector value 0 is given twice");
    }

    #[test]
    fn reports_a_special_value_beyond_the_word() {
        let yaml = valid_with(&[(
            "default: 10.0, source: \"11.1\" }",
            "default: 10.0, source: \"11.1\", special_values: [{ value: 99999, raw: 0x1FFFF, id: No_check, name: No check }] }",
        )]);
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 2, "{found:#?}");
        assert_eq!(
            found[0].message,
            "raw 1FFFFh does not fit the register's word"
        );
        assert_eq!(found[0].path, "registers[0].special_values[0].raw");
        assert_eq!(found[1].message, "`No_check` is not lower snake case");
    }

    #[test]
    fn conversions_are_checked_against_their_examples() {
        let conversion = "conversions:
  - id: double_it
    name: Twice the value
    source: \"1\"
    formula: \"(x * 2 + 1) / 2\"
    rounding: truncate
    inputs: [{ name: x, register: FH }]
    examples: [{ inputs: { x: 3 }, result: 3, source: \"1\" }]
";
        let yaml = format!("{VALID}{conversion}");
        assert!(
            check_yaml(check, &yaml).is_empty(),
            "{:#?}",
            check_yaml(check, &yaml)
        );
        let wrong = format!("{VALID}{}", conversion.replace("result: 3,", "result: 4,"));
        let found = check_yaml(check, &wrong);
        assert_at(
            only(&found),
            &wrong,
            "conversions[0].examples[0].result",
            "the formula gives 3 here, not 4",
            "result: 4",
        );
        let bad = format!("{VALID}{}", conversion.replace("(x * 2 + 1) / 2", "(y * 2"));
        let found = check_yaml(check, &bad);
        assert_at(
            only(&found),
            &bad,
            "conversions[0].formula",
            "`y` is not an input (inputs: x)",
            "formula:",
        );
    }
}
