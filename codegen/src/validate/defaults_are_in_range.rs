//! Check: defaults lie within their (static) range.

use crate::diagnostics::Diagnostics;
use crate::validate::ranges;
use crate::validate::Context;
use crate::validate::{show_raw, with_unit};

/// Defaults lie within their (static) range.
pub fn defaults_are_in_range(drive: &Context, out: &mut Diagnostics) {
    for (index, register) in drive.model.registers.iter().enumerate() {
        let Some(default) = register.default else {
            continue;
        };
        let (raw_min, raw_max, _, _) = ranges::raw_range(&drive.model, register);
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
