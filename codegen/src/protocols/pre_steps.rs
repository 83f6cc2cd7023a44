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

#[cfg(test)]
mod tests {
    use super::super::test_support::{at, drive_with, lower_both, problems_of, protocol_with};
    use super::*;

    #[test]
    fn the_protocol_file_steps_come_first_then_the_drive_steps_with_defaults() {
        let yaml = protocol_with(&[(
            "  default_optional_parts: [sum]\n",
            "  default_optional_parts: [sum]\n  pre_steps:\n    - { step: index, register: 8 }\n",
        )]);
        let drive = drive_with("    pre_steps:\n      - { step: persistence, register: 65, ram: 0, persistent: 0xFF00 }\n      - { step: persistence, space: coil, data_type: bit, register: 3, ram: 0, persistent: 1 }");
        let protocol = lower_both(&drive, &yaml).unwrap();
        assert_eq!(
            protocol.pre_steps.as_ref(),
            [
                PreStep::Index { register: 8 },
                PreStep::Persistence {
                    space: Space::Parameter,
                    register: 65,
                    data_type: DataType::Word,
                    ram: 0,
                    persistent: 0xFF00,
                },
                PreStep::Persistence {
                    space: Space::Coil,
                    register: 3,
                    data_type: DataType::Bit,
                    ram: 0,
                    persistent: 1,
                },
            ]
        );
    }

    #[test]
    fn a_persistence_step_without_its_values_is_reported_in_the_drive_file() {
        let drive =
            drive_with("    pre_steps:\n      - { step: persistence, register: 65, ram: 0 }");
        assert_eq!(
            problems_of(lower_both(&drive, &protocol_with(&[]))),
            [format!(
                "{} protocols[0].pre_steps[0]: the persistence step lacks `persistent`",
                at(&drive, "step: persistence")
            )]
        );
    }

    #[test]
    fn an_unknown_step_is_reported_in_the_drive_file() {
        let drive = drive_with("    pre_steps:\n      - { step: reboot, register: 1 }");
        assert_eq!(
            problems_of(lower_both(&drive, &protocol_with(&[]))),
            [format!(
                "{} protocols[0].pre_steps[0].step: unknown value `reboot`",
                at(&drive, "reboot")
            )]
        );
    }
}
