//! Check: a byte-wide register (`data_type: byte`) has, in each of the drive's protocols,
//! a command that carries bytes (`data_types: [byte]`): its frames' data is narrower than
//! a word's, so a word command would send it with the wrong width.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;
use vfd_runtime::{Access, DataType};

/// Every byte-wide register can be read (unless write-only) and written (unless read-only)
/// by a command of each protocol that lists `byte` among its data types.
pub fn byte_registers_have_commands(drive: &Context, out: &mut Diagnostics) {
    for (index, register) in drive.model.registers.iter().enumerate() {
        if register.data_type != Some(DataType::Byte) {
            continue;
        }
        let access = register.access.unwrap_or(Access::ReadWrite);
        for protocol in &drive.protocols {
            let carried = |write: bool| {
                protocol.runtime.commands.iter().any(|c| {
                    c.kind.is_write() == write
                        && c.data_types.contains(&DataType::Byte)
                        && c.space == register.space.unwrap_or(vfd_runtime::Space::Parameter)
                })
            };
            let missing: Vec<&str> = [
                ("read", access != Access::WriteOnly && !carried(false)),
                ("write", access != Access::ReadOnly && !carried(true)),
            ]
            .into_iter()
            .filter_map(|(what, missing)| missing.then_some(what))
            .collect();
            if missing.is_empty() {
                continue;
            }
            out.push(
                drive
                    .source
                    .error(
                        &format!("registers[{index}].data_type"),
                        format!(
                            "register {} is a byte, and protocol `{}` has no command that carries bytes to {} it",
                            register.code,
                            protocol.id,
                            missing.join(" or ")
                        ),
                    )
                    .hint("list `byte` in the `data_types` of the protocol file's commands whose frames carry the narrower data (their own layouts), or describe the register as a `word`"),
            );
        }
    }
}
