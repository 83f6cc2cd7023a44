//! Check: value examples agree with the register's scale.

use crate::diagnostics::Diagnostics;
use crate::validate::ranges;
use crate::validate::with_unit;
use crate::validate::Context;

/// Value examples (`80 Hz = 1F40h`) agree with the register's scale.
pub fn value_examples_match(drive: &Context, out: &mut Diagnostics) {
    let registers = ranges::RegisterIndex::new(&drive.model);
    for (index, example) in drive.model.value_examples.iter().enumerate() {
        // An unknown register is `references_resolve`'s to report, a scale that is not
        // positive `scales_are_positive`'s.
        let Some(register) = registers
            .find(&example.register)
            .filter(|r| ranges::has_sound_scale(r))
        else {
            continue;
        };
        // The runtime rounds to the nearest step, so the example must round to its raw value.
        // A signed register's negative values are two's complement in its word.
        if let Some(special) = register
            .special_values
            .iter()
            .find(|s| s.value == example.value)
        {
            if special.raw != example.raw {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("value_examples[{index}].raw"),
                            format!(
                                "{} in `{}` is the special value `{}`, raw {:04X}h, not {:04X}h",
                                example.value, register.code, special.id, special.raw, example.raw
                            ),
                        )
                        .hint("check the special value's raw word, or the example"),
                );
            }
            continue;
        }
        let scale = given_scale(&registers, register, &example.given);
        let steps = example.value / scale;
        let bits = 8 * register
            .data_type
            .unwrap_or(vfd_runtime::DataType::Word)
            .size() as u32;
        let mask = (1i64 << bits.clamp(8, 32)) - 1;
        let raw = match steps.round() as i64 {
            negative if negative < 0 && register.signed => negative & mask,
            raw => raw,
        };
        if !steps.is_finite() || raw != i64::from(example.raw) {
            out.push(
                drive
                    .source
                    .error(
                        &format!("value_examples[{index}].raw"),
                        format!(
                            "{} in `{}` is not raw {:04X}h with a step of {}",
                            with_unit(register, example.value.to_string()),
                            register.code,
                            example.raw,
                            with_unit(register, scale.to_string())
                        ),
                    )
                    .hint("check the register's scale, or record a manual mistake"),
            );
        }
    }
}

/// The register's scale with the selector values an example assumes (`given`): the
/// `scale_by` choice for the selector's value, else the register's own scale.
pub(crate) fn given_scale(
    registers: &ranges::RegisterIndex<'_>,
    register: &crate::parse::model::RegisterModel,
    given: &std::collections::BTreeMap<String, u32>,
) -> f64 {
    let Some(scale_by) = &register.scale_by else {
        return ranges::scale_of(register);
    };
    let selector = registers.find(&scale_by.register);
    given
        .iter()
        .find(|(name, _)| {
            registers
                .find(name)
                .zip(selector)
                .is_some_and(|(a, b)| a.id == b.id)
        })
        .and_then(|(_, value)| {
            scale_by
                .values
                .iter()
                .find(|c| c.value == *value)
                .map(|choice| choice.scale)
                .or(scale_by.otherwise.as_ref().map(|other| other.scale))
        })
        .unwrap_or_else(|| ranges::scale_of(register))
}

#[cfg(test)]
mod tests {
    use super::value_examples_match as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_an_example_that_matches_the_scale() {
        assert!(check_yaml(check, VALID).is_empty());
        // The register may be named by id, and the value needs only round to the raw count.
        let yaml = valid_with(&[(
            "register: FH, value: 80.0",
            "register: maximum_frequency, value: 80.004",
        )]);
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn an_example_given_a_scale_selector_uses_the_chosen_scale() {
        let scaled = valid_with(&[
            (
                "default: 10.0, source: \"11.1\" }",
                "default: 10.0, source: \"11.1\", scale_by: { register: F601, values: [{ value: 0, scale: 0.01 }, { value: 1, scale: 0.1 }] } }",
            ),
            (
                "register: FH, value: 80.0, raw: 0x1F40",
                "register: Acc, given: { F601: 0 }, value: 10.0, raw: 0x03E8",
            ),
        ]);
        assert!(
            check_yaml(check, &scaled).is_empty(),
            "{:?}",
            check_yaml(check, &scaled)
        );
        let other = scaled.replace("given: { F601: 0 }", "given: { F601: 1 }");
        let found = check_yaml(check, &other);
        assert_eq!(
            only(&found).message,
            "10 s in `Acc` is not raw 03E8h with a step of 0.1 s"
        );
    }

    #[test]
    fn a_special_value_is_its_own_raw_word() {
        let special = valid_with(&[
            (
                "default: 80.0, source: \"11.1\" }\n  - { address: 0x0012",
                "default: 99999, special_values: [{ value: 99999, raw: 0xFFFF, id: no_limit, name: No limit }], source: \"11.1\" }\n  - { address: 0x0012",
            ),
            (
                "register: FH, value: 80.0, raw: 0x1F40",
                "register: FH, value: 99999, raw: 0xFFFF",
            ),
        ]);
        assert!(
            check_yaml(check, &special).is_empty(),
            "{:?}",
            check_yaml(check, &special)
        );
        let wrong = special.replace(
            "value: 99999, raw: 0xFFFF, source",
            "value: 99999, raw: 0xFFFE, source",
        );
        let found = check_yaml(check, &wrong);
        assert_eq!(
            only(&found).message,
            "99999 in `FH` is the special value `no_limit`, raw FFFFh, not FFFEh"
        );
        // The special value may be the default, though it lies outside the range.
        let defaults = super::super::defaults_are_in_range::defaults_are_in_range;
        assert!(check_yaml(defaults, &special).is_empty());
    }

    #[test]
    fn a_signed_register_gives_negative_values_in_twos_complement() {
        let yaml = valid_with(&[
            (
                "code: F601, name: Parity,",
                "code: F601, name: Parity, signed: true, scale: 0.01,",
            ),
            (
                "register: FH, value: 80.0, raw: 0x1F40",
                "register: F601, value: -100.0, raw: 0xD8F0",
            ),
        ]);
        assert!(
            check_yaml(check, &yaml).is_empty(),
            "{:?}",
            check_yaml(check, &yaml)
        );
        let yaml = yaml.replace("raw: 0xD8F0", "raw: 0xD8F1");
        assert_eq!(check_yaml(check, &yaml).len(), 1);
    }

    #[test]
    fn reports_a_raw_value_the_scale_does_not_give() {
        let yaml = valid_with(&[("raw: 0x1F40", "raw: 0x1F41")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "value_examples[0].raw",
            "80 Hz in `FH` is not raw 1F41h with a step of 0.01 Hz",
            "raw: 0x1F41",
        );
    }

    #[test]
    fn leaves_unknown_registers_to_references_resolve() {
        let yaml = valid_with(&[("register: FH, value", "register: XY, value")]);
        assert!(check_yaml(check, &yaml).is_empty());
    }
}
