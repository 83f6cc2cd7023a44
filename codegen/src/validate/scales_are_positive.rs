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
