//! Check: units are ones the runtime has quantity types for.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;
use vfd_runtime::units::Unit;

/// Units are ones the runtime has quantity types for.
pub fn units_are_known(drive: &Context, out: &mut Diagnostics) {
    for (index, register) in drive.model.registers.iter().enumerate() {
        if let Some(unit) = &register.unit {
            if Unit::from_symbol(unit).is_none() {
                let known: Vec<&str> = Unit::ALL
                    .iter()
                    .map(|u| u.symbol())
                    .filter(|s| !s.is_empty())
                    .collect();
                out.push(
                    drive
                        .source
                        .error(
                            &format!("registers[{index}].unit"),
                            format!("unknown unit `{unit}`"),
                        )
                        .hint(format!(
                            "known units: {}; leave `unit` out for plain numbers",
                            known.join(", ")
                        )),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::units_are_known as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_the_runtime_units() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn reports_an_unknown_unit_and_lists_the_known_ones() {
        let yaml = valid_with(&[(
            "code: FH, name: Maximum frequency, unit: Hz",
            "code: FH, name: Maximum frequency, unit: Hertz",
        )]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "registers[1].unit",
            "unknown unit `Hertz`",
            "code: FH,",
        );
        let hint = diagnostic.hint.as_deref().unwrap_or_default();
        assert!(hint.starts_with("known units: Hz, s, %"), "{hint}");
    }

    #[test]
    fn unit_symbols_are_case_sensitive() {
        let yaml = valid_with(&[(
            "code: Acc, name: Acceleration time, unit: s",
            "code: Acc, name: Acceleration time, unit: S",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "registers[0].unit",
            "unknown unit `S`",
            "code: Acc,",
        );
    }
}
