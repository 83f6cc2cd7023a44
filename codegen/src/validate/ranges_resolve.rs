//! Check: range bounds name known registers, are whole steps, fit the word and are in order.

use crate::diagnostics::Diagnostics;
use crate::validate::ranges;
use crate::validate::ranges::{BoundProblem, End};
use crate::validate::with_unit;
use crate::validate::Context;

/// Range bounds name known registers, are whole steps, fit the word and are in order.
pub fn ranges_resolve(drive: &Context, out: &mut Diagnostics) {
    let registers = ranges::RegisterIndex::new(&drive.model);
    for (index, register) in drive.model.registers.iter().enumerate() {
        let Some(range) = &register.range else {
            continue;
        };
        let mut resolved = [None, None];
        for (slot, (end, bound, key)) in
            [(End::Min, &range.min, "min"), (End::Max, &range.max, "max")]
                .into_iter()
                .enumerate()
        {
            let path = format!("registers[{index}].range.{key}");
            match registers.resolve_bound(bound, end) {
                // Bounds in steps of a scale that is not positive: `scales_are_positive`
                // reports the scale, once.
                Ok(_) if !ranges::has_sound_scale(register) => {}
                Ok(value) => {
                    let (word_min, word_max) = ranges::word_limits(register);
                    let word = match register.data_type {
                        Some(vfd_runtime::DataType::DoubleWord) => "32-bit double word",
                        Some(vfd_runtime::DataType::Byte) => "8-bit byte",
                        _ => "16-bit word",
                    };
                    match ranges::to_raw(register, value) {
                        None => out.push(drive.source.error(&path, format!("bound {} is not a whole number of {} steps", with_unit(register, value.to_string()), with_unit(register, ranges::scale_of(register).to_string()))).hint("check the scale, or the bound's decimals")),
                        Some(raw) if raw < word_min || raw > word_max => out.push(
                            drive
                                .source
                                .error(&path, format!("bound {value} is raw {raw}, outside the {word} ({word_min}..={word_max})"))
                                .hint("check the scale and `signed`"),
                        ),
                        Some(_) => resolved[slot] = Some(value),
                    }
                }
                // A problem further along the chain (the register named here has a bound
                // naming no register, or no range) is reported once, where it is written.
                Err(BoundProblem::Unknown(name) | BoundProblem::Unbounded(name))
                    if !names(bound, &name) => {}
                Err(BoundProblem::Unknown(name)) => out.push(
                    drive
                        .source
                        .error(&path, format!("range bound `{name}` names no register"))
                        .hint("a named bound is the `code` (e.g. FH) or `id` of another register in this file"),
                ),
                Err(BoundProblem::Unbounded(name)) => out.push(
                    drive
                        .source
                        .error(&path, format!("range bound `{name}` names a register that has no range"))
                        .hint(format!("give `{name}` a range so a static bound can be taken from it")),
                ),
                Err(BoundProblem::Cycle(name)) => out.push(drive.source.error(&path, format!("range bounds through `{name}` refer to each other in a circle")).hint("one of the registers needs numeric bounds")),
            }
        }
        if let [Some(min), Some(max)] = resolved {
            if min > max {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("registers[{index}].range"),
                            format!("range minimum {min} is above its maximum {max}"),
                        )
                        .hint("swap the bounds, or check the manual"),
                );
            }
        }
    }
}

/// Whether `bound` is written as the name `name`.
fn names(bound: &crate::parse::model::BoundModel, name: &str) -> bool {
    matches!(bound, crate::parse::model::BoundModel::Register(written) if written == name)
}

#[cfg(test)]
mod tests {
    use super::ranges_resolve as check;
    use crate::validate::testing::{assert_at, assert_column, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_numeric_and_named_bounds() {
        assert!(check_yaml(check, VALID).is_empty());
        // A bound may name a register by id as well as by code.
        let yaml = valid_with(&[("max: FH }", "max: maximum_frequency }")]);
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn reports_a_bound_naming_no_register() {
        let yaml = valid_with(&[("max: FH }", "max: XX }")]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "registers[2].range.max",
            "range bound `XX` names no register",
            "code: UL,",
        );
        assert_column(diagnostic, &yaml, "XX");
    }

    #[test]
    fn a_bad_bound_is_reported_once_where_it_is_written() {
        // FH's own bound names no register; UL is bounded by FH and gets no second message.
        let yaml = valid_with(&[("max: 320.0 }", "max: HF }")]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "registers[1].range.max",
            "range bound `HF` names no register",
            "code: FH,",
        );
    }

    #[test]
    fn reports_a_bound_naming_a_register_without_a_range() {
        let yaml = valid_with(&[("max: FH }", "max: F601 }")]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "registers[2].range.max",
            "range bound `F601` names a register that has no range",
            "code: UL,",
        );
        assert_eq!(
            diagnostic.hint.as_deref(),
            Some("give `F601` a range so a static bound can be taken from it")
        );
    }

    #[test]
    fn reports_bounds_that_refer_to_each_other() {
        let yaml = valid_with(&[("min: 30.0, max: 320.0", "min: 30.0, max: UL")]);
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 2, "{found:#?}");
        assert_at(
            &found[0],
            &yaml,
            "registers[1].range.max",
            "range bounds through `FH` refer to each other in a circle",
            "code: FH,",
        );
        assert_at(
            &found[1],
            &yaml,
            "registers[2].range.max",
            "range bounds through `UL` refer to each other in a circle",
            "code: UL,",
        );
        // A register bounded by itself.
        let yaml = valid_with(&[("max: FH }", "max: UL }")]);
        let found = check_yaml(check, &yaml);
        assert_eq!(only(&found).path, "registers[2].range.max");
    }

    #[test]
    fn reports_a_bound_that_is_not_a_whole_number_of_steps() {
        let yaml = valid_with(&[("min: 0.1, max: 3600", "min: 0.15, max: 3600")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[0].range.min",
            "bound 0.15 s is not a whole number of 0.1 s steps",
            "code: Acc,",
        );
    }

    #[test]
    fn reports_a_bound_outside_the_word() {
        let yaml = valid_with(&[("min: 30.0, max: 320.0", "min: 30.0, max: 700.0")]);
        let found = check_yaml(check, &yaml);
        // Reported at FH's own bound, and again at UL's `max: FH`, which takes it over.
        assert_eq!(found.len(), 2, "{found:#?}");
        assert_at(
            &found[0],
            &yaml,
            "registers[1].range.max",
            "bound 700 is raw 70000, outside the 16-bit word (0..=65535)",
            "code: FH,",
        );
        assert_at(
            &found[1],
            &yaml,
            "registers[2].range.max",
            "bound 700 is raw 70000, outside the 16-bit word (0..=65535)",
            "code: UL,",
        );
        let yaml = valid_with(&[("min: 0.1, max: 3600", "min: -0.1, max: 3600")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[0].range.min",
            "bound -0.1 is raw -1, outside the 16-bit word (0..=65535)",
            "code: Acc,",
        );
        let yaml = valid_with(&[(
            "min: 30.0, max: 320.0 }",
            "min: 30.0, max: 50000000.0 }, data_type: double_word",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            &found[0],
            &yaml,
            "registers[1].range.max",
            "bound 50000000 is raw 5000000000, outside the 32-bit double word (0..=4294967295)",
            "code: FH,",
        );
        // Signed registers take negative bounds (and a signed word ends at raw 32767).
        let yaml = valid_with(&[(
            "min: 0.1, max: 3600 }",
            "min: -0.1, max: 3000 }, signed: true",
        )]);
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn reports_a_minimum_above_the_maximum() {
        let yaml = valid_with(&[("min: 0.1, max: 3600", "min: 3600, max: 0.1")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[0].range",
            "range minimum 3600 is above its maximum 0.1",
            "code: Acc,",
        );
    }
}
