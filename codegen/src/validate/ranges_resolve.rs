//! Check: range bounds name known registers, are whole steps, fit the word and are in order.

use crate::diagnostics::Diagnostics;
use crate::validate::ranges;
use crate::validate::ranges::{BoundProblem, End};
use crate::validate::with_unit;
use crate::validate::Context;

/// Range bounds name known registers, are whole steps, fit the word and are in order.
pub fn ranges_resolve(drive: &Context, out: &mut Diagnostics) {
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
            match ranges::resolve_bound(&drive.model, bound, end) {
                Ok(value) => {
                    let (word_min, word_max) = ranges::word_limits(register);
                    match ranges::to_raw(register, value) {
                        None => out.push(drive.source.error(&path, format!("bound {} is not a whole number of {} steps", with_unit(register, value.to_string()), with_unit(register, ranges::scale_of(register).to_string()))).hint("check the scale, or the bound's decimals")),
                        Some(raw) if raw < word_min || raw > word_max => out.push(
                            drive
                                .source
                                .error(&path, format!("bound {value} is raw {raw}, outside the 16-bit word ({word_min}..={word_max})"))
                                .hint("check the scale and `signed`"),
                        ),
                        Some(_) => resolved[slot] = Some(value),
                    }
                }
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
