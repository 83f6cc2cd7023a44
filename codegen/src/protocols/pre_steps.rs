//! Pre-steps: register writes some requests need first (a Modbus array index, a persistence
//! switch), from the protocol file's `protocol.pre_steps` followed by the drive's own.

use super::commands::{data_type, space};
use super::Input;
use crate::diagnostics::Diagnostics;
use crate::parse::model::PreStepModel;
use crate::parse::SourceFile;
use vfd_runtime::{DataType, PreStep};

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
    match step.step.as_str() {
        "index" => Some(PreStep::Index {
            register: step.register,
        }),
        "persistence" => persistence(step, source, path, out),
        other => {
            out.push(
                source
                    .error(&format!("{path}.step"), format!("unknown step `{other}`"))
                    .hint("use index or persistence"),
            );
            None
        }
    }
}

/// A persistence switch: which value of a register selects RAM only and which RAM + EEPROM.
fn persistence(
    step: &PreStepModel,
    source: &SourceFile,
    path: &str,
    out: &mut Diagnostics,
) -> Option<PreStep> {
    let space = space(step.space.as_deref(), source, &format!("{path}.space"), out);
    let data_type = match step.data_type.as_deref() {
        None => Some(DataType::Word),
        Some(name) => data_type(name, source, &format!("{path}.data_type"), out),
    };
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
        space: space?,
        register: step.register,
        data_type: data_type?,
        ram: step.ram?,
        persistent: step.persistent?,
    })
}
