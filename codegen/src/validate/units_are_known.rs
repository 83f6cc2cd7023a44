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
