//! Pre-steps: register writes some requests need first (a Modbus array index, a persistence
//! switch), from the protocol file's `protocol.pre_steps` followed by the drive's own.

use super::Input;
use crate::diagnostics::Diagnostics;
use crate::parse::model::{PreStepKind, PreStepModel};
use crate::parse::SourceFile;
use vfd_runtime::{DataType, PreStep, Space};

/// Lowers the protocol file's pre-steps, then the drive's; those with problems are reported
/// and left out.
pub(super) fn lower_pre_steps(input: &Input<'_>, out: &mut Diagnostics) -> Vec<PreStep> {
    let from_file = input
        .file
        .protocol
        .pre_steps
        .iter()
        .enumerate()
        .map(|(index, step)| (input.source, format!("protocol.pre_steps[{index}]"), step));
    let from_drive = input
        .reference
        .pre_steps
        .iter()
        .enumerate()
        .map(|(index, step)| {
            let path = format!("{}.pre_steps[{index}]", input.reference_path);
            (input.drive_source, path, step)
        });
    from_file
        .chain(from_drive)
        .filter_map(|(source, path, step)| lower_pre_step(step, source, &path, out))
        .collect()
}

/// Lowers one pre-step written at `path` of `source`.
fn lower_pre_step(
    step: &PreStepModel,
    source: &SourceFile,
    path: &str,
    out: &mut Diagnostics,
) -> Option<PreStep> {
    match step.step {
        PreStepKind::Index => Some(PreStep::Index {
            register: step.register,
        }),
        PreStepKind::Persistence => persistence(step, source, path, out),
    }
}

/// A persistence switch: which value of a register selects RAM only and which RAM + EEPROM.
fn persistence(
    step: &PreStepModel,
    source: &SourceFile,
    path: &str,
    out: &mut Diagnostics,
) -> Option<PreStep> {
    let missing: Vec<&str> = [
        ("ram", step.ram.is_none()),
        ("persistent", step.persistent.is_none()),
    ]
    .into_iter()
    .filter_map(|(key, absent)| absent.then_some(key))
    .collect();
    if !missing.is_empty() {
        out.push(
            source
                .error(path, format!("the persistence step lacks `{}`", missing.join("` and `")))
                .hint("give the values that select RAM only and RAM + EEPROM, e.g. ram: 0x0000, persistent: 0xFF00"),
        );
    }
    Some(PreStep::Persistence {
        space: step.space.unwrap_or(Space::Parameter),
        register: step.register,
        data_type: step.data_type.unwrap_or(DataType::Word),
        ram: step.ram?,
        persistent: step.persistent?,
    })
}
