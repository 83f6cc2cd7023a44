//! Check: scales are positive and finite.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;

/// Scales are positive and finite.
pub fn scales_are_positive(drive: &Context, out: &mut Diagnostics) {
    for (index, register) in drive.model.registers.iter().enumerate() {
        if let Some(scale) = register.scale {
            if !(scale.is_finite() && scale > 0.0) {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("registers[{index}].scale"),
                            format!("scale {scale} must be a positive number"),
                        )
                        .hint("the scale is the value of one raw step, e.g. 0.01 for 0.01 Hz"),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::scales_are_positive as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    #[test]
    fn accepts_positive_scales() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn reports_zero_negative_and_non_finite_scales() {
        for (scale, shown) in [
            ("0", "0"),
            ("-0.1", "-0.1"),
            (".nan", "NaN"),
            (".inf", "inf"),
        ] {
            let yaml = valid_with(&[("unit: s, scale: 0.1", &format!("unit: s, scale: {scale}"))]);
            let found = check_yaml(check, &yaml);
            assert_at(
                only(&found),
                &yaml,
                "registers[0].scale",
                &format!("scale {shown} must be a positive number"),
                "code: Acc,",
            );
        }
    }
}
