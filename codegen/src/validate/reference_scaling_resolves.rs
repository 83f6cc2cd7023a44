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
