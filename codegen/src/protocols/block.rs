//! Block transfers: a drive's `protocols[].block` lowered into the runtime's [`BlockSpec`].
//! Selector registers name their choices through their code tables (each value's
//! `register`); modes name fixed registers. Every name must resolve to a described
//! parameter, and the protocol file must have a `kind: block` command.

use super::lowered_command::LoweredCommand;
use super::Input;
use crate::diagnostics::Diagnostics;
use crate::parse::model::RegisterModel;
use std::borrow::Cow;
use vfd_runtime::{BlockChoice, BlockMode, BlockSelector, BlockSpec, CommandKind};

/// The drive's block selection, `None` when it has none or it has problems (reported).
pub(super) fn lower_block(
    input: &Input<'_>,
    commands: &[LoweredCommand],
    out: &mut Diagnostics,
) -> Option<BlockSpec> {
    let block = input.reference.block.as_ref()?;
    let base = format!("{}.block", input.reference_path);
    let before = out.items.len();
    if !commands.iter().any(|c| c.spec.kind == CommandKind::Block) {
        out.push(
            input
                .drive_source
                .error(
                    &base,
                    format!(
                        "protocol `{}` (file `{}`) carries no block command (`kind: block`)",
                        input.reference.id, input.reference.uses
                    ),
                )
                .hint("describe the block-transfer frames in the protocol file (and list the command under `commands`, if given), or drop `block`"),
        );
    }
    let write = selectors(input, &block.write, &format!("{base}.write"), out);
    let read = selectors(input, &block.read, &format!("{base}.read"), out);
    let write_choices = choices(input, &block.write, &format!("{base}.write"), out);
    let read_choices = choices(input, &block.read, &format!("{base}.read"), out);
    let mut modes = Vec::new();
    for (index, mode) in block.modes.iter().enumerate() {
        let path = format!("{base}.modes[{index}]");
        let register = resolve(input, &mode.register, &format!("{path}.register"), out);
        let write = registers(input, &mode.write, &format!("{path}.write"), out);
        let read = registers(input, &mode.read, &format!("{path}.read"), out);
        if let (Some(register), Some(write), Some(read)) = (register, write, read) {
            modes.push(BlockMode {
                register: register.address as u16,
                value: mode.value as u16,
                default: default_of(register),
                write: Cow::Owned(write),
                read: Cow::Owned(read),
            });
        }
    }
    if let Some(status) = &block.status {
        if !input.drive.bitfields.iter().any(|b| &b.id == status) {
            out.push(
                input
                    .drive_source
                    .error(
                        &format!("{base}.status"),
                        format!("no bit field `{status}`"),
                    )
                    .hint("name a bit field under `bitfields:` (bit n: word n not written)"),
            );
        }
    }
    if out.items.len() > before {
        return None;
    }
    Some(BlockSpec {
        write: Cow::Owned(write?),
        read: Cow::Owned(read?),
        write_choices: Cow::Owned(write_choices?),
        read_choices: Cow::Owned(read_choices?),
        modes: Cow::Owned(modes),
    })
}

/// The described parameter a name (code or id) names.
fn resolve<'d>(
    input: &Input<'d>,
    name: &str,
    path: &str,
    out: &mut Diagnostics,
) -> Option<&'d RegisterModel> {
    let found =
        input.drive.registers.iter().find(|r| {
            r.is_named(name) && r.space.is_none_or(|s| s == vfd_runtime::Space::Parameter)
        });
    if found.is_none() {
        out.push(
            input
                .drive_source
                .error(path, format!("no parameter `{name}`"))
                .hint("name a register of this drive by its code or id"),
        );
    }
    found
}

fn default_of(register: &RegisterModel) -> u16 {
    register.default.map_or(0, |value| {
        (value / register.scale.unwrap_or(1.0)).round() as u16
    })
}

/// Registers named in a list, in order.
fn registers(
    input: &Input<'_>,
    names: &[String],
    path: &str,
    out: &mut Diagnostics,
) -> Option<Vec<u16>> {
    let resolved: Vec<Option<u16>> = names
        .iter()
        .enumerate()
        .map(|(i, name)| {
            resolve(input, name, &format!("{path}[{i}]"), out).map(|r| r.address as u16)
        })
        .collect();
    resolved.into_iter().collect()
}

/// Selector registers: each must have a code table.
fn selectors(
    input: &Input<'_>,
    names: &[String],
    path: &str,
    out: &mut Diagnostics,
) -> Option<Vec<BlockSelector>> {
    let mut selectors = Vec::new();
    for (index, name) in names.iter().enumerate() {
        let path = format!("{path}[{index}]");
        let register = resolve(input, name, &path, out)?;
        if register.code_table.is_none() {
            out.push(
                input
                    .drive_source
                    .error(
                        &path,
                        format!("`{name}` has no code table to select registers with"),
                    )
                    .hint("a selector's `code_table` values say which `register` each selects"),
            );
            return None;
        }
        selectors.push(BlockSelector {
            register: register.address as u16,
            default: default_of(register),
        });
    }
    Some(selectors)
}

/// The selectors' shared code table, as choices: each value with the register it selects.
fn choices(
    input: &Input<'_>,
    names: &[String],
    path: &str,
    out: &mut Diagnostics,
) -> Option<Vec<BlockChoice>> {
    let drive = input.drive;
    let tables: Vec<&str> = names
        .iter()
        .filter_map(|name| drive.registers.iter().find(|r| r.is_named(name)))
        .filter_map(|r| r.code_table.as_deref())
        .collect();
    let first = *tables.first()?;
    if tables.iter().any(|t| *t != first) {
        out.push(
            input
                .drive_source
                .error(
                    path,
                    format!(
                        "the selectors use different code tables ({})",
                        tables.join(", ")
                    ),
                )
                .hint("the selectors of one direction share one code table"),
        );
        return None;
    }
    let (table_index, table) = drive
        .codes
        .iter()
        .enumerate()
        .find(|(_, t)| t.id == first)?;
    let mut choices = Vec::new();
    for (index, value) in table.values.iter().enumerate() {
        let register = match &value.register {
            None => None,
            Some(name) => Some(
                resolve(
                    input,
                    name,
                    &format!("codes[{table_index}].values[{index}].register"),
                    out,
                )?
                .address as u16,
            ),
        };
        choices.push(BlockChoice {
            value: value.value as u16,
            register,
        });
    }
    if choices.iter().all(|c| c.register.is_none()) {
        out.push(
            input
                .drive_source
                .error(
                    &format!("codes[{table_index}]"),
                    format!("code table `{first}` selects no register"),
                )
                .hint("give each value that selects a register `register: CODE`"),
        );
        return None;
    }
    Some(choices)
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{drive_with, lower_both, problems_of, PROTOCOL};

    /// The test drive with a block selection on its ASCII protocol, and the registers and
    /// code table it names.
    fn drive_with_block(block: &str) -> String {
        drive_with(&format!("    block:\n{block}"))
            .replace(
                "registers: []",
                "codes:\n  - id: selection\n    name: Selection\n    source: \"1\"\n    values:\n      - { value: 0, id: none, name: None }\n      - { value: 1, id: frequency, name: Frequency, register: FA01 }\n\nregisters:\n  - { address: 0x0870, id: selector, code: F870, name: Selector, code_table: selection, default: 0, source: \"1\" }\n  - { address: 0xFA01, id: frequency, code: FA01, name: Frequency, source: \"1\" }\n",
            )
    }

    #[test]
    fn a_block_needs_a_block_command_in_the_protocol() {
        let drive =
            drive_with_block("      source: \"1\"\n      write: [F870]\n      read: [F870]\n");
        let problems = problems_of(lower_both(&drive, PROTOCOL));
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(
            problems[0].contains(
                "protocols[0].block: protocol `ascii` (file `test`) carries no block command"
            ),
            "{problems:?}"
        );
    }

    #[test]
    fn every_name_of_a_block_must_resolve() {
        let drive = drive_with_block(
            "      source: \"1\"\n      write: [F870, F871]\n      read: [FA01]\n      modes:\n        - { register: FA80, value: 1, write: [FA01], read: [FA02], source: \"1\" }\n",
        );
        let problems = problems_of(lower_both(&drive, PROTOCOL));
        let wanted = [
            "protocols[0].block.write[1]: no parameter `F871`",
            "protocols[0].block.read[0]: `FA01` has no code table",
            "protocols[0].block.modes[0].register: no parameter `FA80`",
            "protocols[0].block.modes[0].read[0]: no parameter `FA02`",
        ];
        for wanted in wanted {
            assert!(
                problems.iter().any(|p| p.contains(wanted)),
                "missing `{wanted}` in {problems:?}"
            );
        }
    }
}
