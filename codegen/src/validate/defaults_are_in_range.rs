//! Check: defaults lie within their (static) range.

use crate::diagnostics::Diagnostics;
use crate::validate::ranges;
use crate::validate::Context;
use crate::validate::{show_raw, with_unit};

/// Defaults lie within their (static) range.
pub fn defaults_are_in_range(drive: &Context, out: &mut Diagnostics) {
    let registers = ranges::RegisterIndex::new(&drive.model);
    for (index, register) in drive.model.registers.iter().enumerate() {
        let Some(default) = register.default else {
            continue;
        };
        // A value the register takes besides its range (99999) may be its default.
        if register.special_values.iter().any(|s| s.value == default) {
            continue;
        }
        let (raw_min, raw_max) = registers.raw_range(register);
        // A scale that is not positive (`scales_are_positive`) or a range whose minimum
        // lies above its maximum (`ranges_resolve`) is reported once, as itself.
        if !ranges::has_sound_scale(register) || raw_min > raw_max {
            continue;
        }
        let scale = ranges::scale_of(register);
        let path = format!("registers[{index}].default");
        match ranges::to_raw(register, default) {
            None => out.push(
                drive
                    .source
                    .error(
                        &path,
                        format!(
                            "default {} is not a whole number of {} steps",
                            with_unit(register, default.to_string()),
                            with_unit(register, scale.to_string())
                        ),
                    )
                    .hint("check the default's decimals against the scale"),
            ),
            Some(raw) if raw < raw_min || raw > raw_max => out.push(
                drive
                    .source
                    .error(
                        &path,
                        format!(
                            "default {} is outside the range {} to {}",
                            with_unit(register, default.to_string()),
                            show_raw(register, raw_min),
                            show_raw(register, raw_max)
                        ),
                    )
                    .hint("check the default and the range against the manual's table"),
            ),
            Some(_) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::defaults_are_in_range as check;
    use crate::validate::testing::{assert_at, assert_column, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_defaults_within_their_ranges() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn reports_a_default_outside_a_numeric_range() {
        let yaml = valid_with(&[(
            "max: 320.0 }, default: 80.0",
            "max: 320.0 }, default: 400.0",
        )]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "registers[1].default",
            "default 400 Hz is outside the range 30.00 Hz to 320.00 Hz",
            "code: FH,",
        );
        assert_column(diagnostic, &yaml, "400.0");
    }

    #[test]
    fn takes_a_named_bound_at_its_widest() {
        let yaml = valid_with(&[("max: FH }, default: 80.0", "max: FH }, default: 320.0")]);
        assert!(check_yaml(check, &yaml).is_empty());
        let yaml = valid_with(&[("max: FH }, default: 80.0", "max: FH }, default: 320.01")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[2].default",
            "default 320.01 Hz is outside the range 0.50 Hz to 320.00 Hz",
            "code: UL,",
        );
    }

    #[test]
    fn checks_a_register_without_a_range_against_its_code_table() {
        let yaml = valid_with(&[(
            "code_table: parity, default: 1",
            "code_table: parity, default: 70000",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[3].default",
            "default 70000 is outside the range 0 to 1",
            "code: F601,",
        );
    }

    #[test]
    fn reports_a_default_that_is_not_a_whole_number_of_steps() {
        let yaml = valid_with(&[("default: 10.0", "default: 10.05")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[0].default",
            "default 10.05 s is not a whole number of 0.1 s steps",
            "code: Acc,",
        );
    }
}
