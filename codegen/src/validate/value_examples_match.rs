//! Check: value examples agree with the register's scale.

use crate::diagnostics::Diagnostics;
use crate::validate::ranges;
use crate::validate::with_unit;
use crate::validate::Context;

/// Value examples (`80 Hz = 1F40h`) agree with the register's scale.
pub fn value_examples_match(drive: &Context, out: &mut Diagnostics) {
    for (index, example) in drive.model.value_examples.iter().enumerate() {
        let Some(register) = ranges::find_register(&drive.model, &example.register) else {
            continue;
        };
        // The runtime rounds to the nearest step, so the example must round to its raw value.
        let steps = example.value / ranges::scale_of(register);
        if !steps.is_finite() || steps.round() as i64 != i64::from(example.raw) {
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
                            with_unit(register, ranges::scale_of(register).to_string())
                        ),
                    )
                    .hint("check the register's scale, or record a manual mistake"),
            );
        }
    }
}
