//! Reference scaling: the span each selector value chooses.

use crate::ir::*;
use serde::Serialize;

#[derive(Serialize)]
pub(super) struct ScalingView<'a> {
    #[serde(flatten)]
    scaling: &'a ReferenceScalingIr,
    modes: Vec<ScalingModeView<'a>>,
}

#[derive(Serialize)]
struct ScalingModeView<'a> {
    selector: u32,
    low: String,
    high: String,
    description: &'a str,
}

/// The reference scaling's modes, when the drive has one.
pub(super) fn reference_scaling_view(drive: &DriveIr) -> Option<ScalingView<'_>> {
    drive.reference_scaling.as_ref().map(|scaling| {
        let end = |end: &SpanEndIr| match end {
            SpanEndIr::Number(value) => format!("{value:?}"),
            SpanEndIr::Register(id) => id.clone(),
        };
        ScalingView {
            scaling,
            modes: scaling
                .modes
                .iter()
                .map(|mode| ScalingModeView {
                    selector: mode.selector,
                    low: end(&mode.low),
                    high: end(&mode.high),
                    description: &mode.description,
                })
                .collect(),
        }
    })
}
