//! Where a write of a register goes, as the description says it: which of the drive's
//! protocols write it to RAM and which persistently (their commands, a persistence selector
//! or pre-step), and what a persistent write stores (some drives keep it in RAM). `vfd info`,
//! `vfd write`, `vfd restore` and their hints all say it from here, so they agree.

use vfd_runtime::protocol::PreStep;
use vfd_runtime::{CommandKind, DataType, DriveInfo, Protocol, RegisterInfo, Space};

/// The writes a protocol can send of a register.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Writes {
    /// A RAM write.
    pub ram: bool,
    /// A persistent (RAM and EEPROM) write.
    pub persistent: bool,
}

/// The writes `protocol` can send of `info`: a command of the kind for its space and data
/// type that reaches its number, or, for a persistent write, a RAM write the protocol's
/// persistence selector or pre-step makes persistent. A RAM-only register has no
/// persistent write.
pub fn writes(protocol: &Protocol, info: &RegisterInfo) -> Writes {
    let can = |kind| {
        protocol
            .command_for_register(kind, info.space, info.data_type, info.address)
            .is_some_and(|command| protocol.to_wire(command, info.address).is_some())
    };
    let ram = can(CommandKind::WriteRam);
    let selector = protocol
        .persistence
        .as_ref()
        .is_some_and(|s| s.governs(info.space, info.address, info.ram_only));
    let pre_step = info.space == Space::Parameter
        && protocol
            .pre_steps
            .iter()
            .any(|s| matches!(s, PreStep::Persistence { .. }));
    Writes {
        ram,
        persistent: !info.ram_only
            && (can(CommandKind::WritePersistent) || (ram && (selector || pre_step))),
    }
}

/// Where a write of `info` goes, for the line that reports it: `RAM and EEPROM`, `RAM`, or,
/// for a register the drive keeps in RAM whatever the command, that.
pub fn target(info: &RegisterInfo, persist: bool) -> &'static str {
    match (persist, info.persistent_write_to_ram) {
        (true, true) => "RAM only: the drive keeps a persistent write of it in RAM",
        (true, false) => "RAM and EEPROM",
        (false, _) => "RAM",
    }
}

/// `vfd info`'s storage line: what the drive's protocols can do with `info`.
pub fn storage_line(drive: &DriveInfo, info: &RegisterInfo) -> String {
    if info.ram_only {
        return "RAM only (no persistent write)".to_owned();
    }
    if info.persistent_write_to_ram {
        return "RAM only (a persistent write is accepted, kept in RAM)".to_owned();
    }
    if info.access == vfd_runtime::Access::ReadOnly {
        return "—".to_owned();
    }
    let all: Vec<Writes> = drive.protocols.iter().map(|p| writes(p, info)).collect();
    let ram = all.iter().any(|w| w.ram);
    let persistent = all.iter().any(|w| w.persistent);
    match (ram, persistent) {
        (true, true) => "RAM, or RAM and EEPROM with --persist".to_owned(),
        (false, true) => {
            "RAM and EEPROM: its protocols write it only persistently (give --persist)".to_owned()
        }
        (true, false) => "RAM (its protocols have no persistent write of it)".to_owned(),
        (false, false) => "— (no write command of its protocols carries it)".to_owned(),
    }
}

/// A hint for a write of `kind` (`space`, `data_type`) that `protocol` has no command for:
/// the other kind where the protocol has it (`--persist`, or leaving it out), else the
/// drive's protocols that carry it, else that none does (no `--protocol` to suggest).
pub fn missing_write_hint(
    drive: &DriveInfo,
    protocol: &Protocol,
    kind: CommandKind,
    space: Space,
    data_type: DataType,
) -> Option<String> {
    let other = match kind {
        CommandKind::WriteRam => CommandKind::WritePersistent,
        CommandKind::WritePersistent => CommandKind::WriteRam,
        _ => return None,
    };
    if protocol.command_for(other, space, data_type).is_some() {
        return Some(match kind {
            CommandKind::WriteRam => format!(
                "protocol {} writes it only persistently (RAM and EEPROM): give --persist",
                protocol.id
            ),
            _ => format!(
                "protocol {} writes it to RAM only: leave out --persist",
                protocol.id
            ),
        });
    }
    let others: Vec<&str> = drive
        .protocols
        .iter()
        .filter(|p| p.id != protocol.id && p.command_for(kind, space, data_type).is_some())
        .map(|p| p.id.as_ref())
        .collect();
    Some(if others.is_empty() {
        format!(
            "none of drive {}'s protocols can send this write (`vfd info` shows how each register is stored)",
            drive.id
        )
    } else {
        format!("try --protocol {}", others.join(" or "))
    })
}
