//! Check: the reference scaling names registers that exist.

use crate::diagnostics::Diagnostics;
use crate::parse::model::BoundModel;
use crate::validate::Context;

/// The reference scaling names registers that exist.
pub fn reference_scaling_resolves(drive: &Context, out: &mut Diagnostics) {
    let Some(scaling) = &drive.model.reference_scaling else {
        return;
    };
    let known = |id: &str| drive.model.registers.iter().any(|r| r.id == id);
    let mut names: Vec<(String, &str)> = vec![(
        "reference_scaling.selector".to_owned(),
        scaling.selector.as_str(),
    )];
    names.extend(
        scaling
            .applies_to
            .iter()
            .enumerate()
            .map(|(i, id)| (format!("reference_scaling.applies_to[{i}]"), id.as_str())),
    );
    for (i, mode) in scaling.modes.iter().enumerate() {
        for (key, bound) in [("low", &mode.low), ("high", &mode.high)] {
            if let BoundModel::Register(id) = bound {
                names.push((format!("reference_scaling.modes[{i}].{key}"), id.as_str()));
            }
        }
    }
    for (path, id) in names {
        if !known(id) {
            out.push(
                drive
                    .source
                    .error(&path, format!("`{id}` is not the id of a register"))
                    .hint("name registers by their `id` here"),
            );
        }
    }
    if scaling.full_scale_raw == 0 {
        out.push(
            drive
                .source
                .error(
                    "reference_scaling.full_scale_raw",
                    "full scale must be above 0",
                )
                .hint("the raw value meaning 100 %, e.g. 0x4000"),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::reference_scaling_resolves as check;
    use crate::validate::testing::{assert_at, assert_column, check_yaml, only, valid_with, VALID};

    const SCALING: &str = "reference_scaling:
  source: \"7.1\"
  full_scale_raw: 0x4000
  applies_to: [upper_limit_frequency]
  selector: parity_setting
  modes:
    - { selector: 0, low: 0, high: maximum_frequency, description: Percent of FH }

value_examples:";

    fn with_scaling(edits: &[(&str, &str)]) -> String {
        let mut yaml = valid_with(&[("value_examples:", SCALING)]);
        for (from, to) in edits {
            assert_eq!(yaml.matches(from).count(), 1, "{from}");
            yaml = yaml.replacen(from, to, 1);
        }
        yaml
    }

    #[test]
    fn accepts_no_scaling_and_a_scaling_naming_registers() {
        assert!(check_yaml(check, VALID).is_empty());
        assert!(check_yaml(check, &with_scaling(&[])).is_empty());
    }

    #[test]
    fn reports_every_name_that_is_not_a_register_id() {
        let yaml = with_scaling(&[
            ("selector: parity_setting", "selector: F601"),
            (
                "applies_to: [upper_limit_frequency]",
                "applies_to: [upper_limit_frequency, speed]",
            ),
            ("low: 0,", "low: minimum_frequency,"),
        ]);
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 3, "{found:#?}");
        assert_at(
            &found[0],
            &yaml,
            "reference_scaling.selector",
            "`F601` is not the id of a register",
            "selector: F601",
        );
        assert_at(
            &found[1],
            &yaml,
            "reference_scaling.applies_to[1]",
            "`speed` is not the id of a register",
            "applies_to:",
        );
        assert_column(&found[1], &yaml, "speed");
        assert_at(
            &found[2],
            &yaml,
            "reference_scaling.modes[0].low",
            "`minimum_frequency` is not the id of a register",
            "low: minimum_frequency",
        );
    }

    #[test]
    fn reports_a_zero_full_scale() {
        let yaml = with_scaling(&[("full_scale_raw: 0x4000", "full_scale_raw: 0")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "reference_scaling.full_scale_raw",
            "full scale must be above 0",
            "full_scale_raw",
        );
    }
}
