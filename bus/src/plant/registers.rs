//! A drive's poll list and write allow-list, resolved to its registers: each name found as
//! `vfd read` and `vfd write` find it, and refused where the register cannot do what the
//! list asks (a write-only register polled, a read-only one allowed to be written,
//! `persistent` on a RAM-only register or on one the bus's protocol cannot write
//! persistently), or where a register is listed twice.

use super::file::{PollFile, WriteEntry};
use super::interval;
use super::model::{Allowed, Poll};
use super::problems::Problems;
use super::station::Head;
use crate::write_check::{self, Reason};
use vfd_runtime::transaction::{script, Exchange, Station};
use vfd_runtime::{Access, CommandKind, DriveInfo, Protocol, RegisterInfo, Request};

/// The poll list of the drive entry at `path`.
pub fn polls(
    drive: &'static DriveInfo,
    groups: &[PollFile],
    path: &str,
    problems: &mut Problems<'_>,
) -> Vec<Poll> {
    let mut polls = Vec::new();
    // Each register polled so far, and where.
    let mut seen: Vec<(&'static RegisterInfo, String)> = Vec::new();
    if groups.is_empty() {
        problems.warning(
            path,
            format!("drive {} polls nothing", drive.id),
            "add `poll:` with the registers to read and how often; without it nothing is published for this drive, and it is found offline only when a write fails",
        );
    }
    for (g, group) in groups.iter().enumerate() {
        let group_path = format!("{path}.poll[{g}]");
        let every = match interval::parse(&group.every) {
            Ok(every) => Some(every),
            Err((message, hint)) => {
                problems.error(&format!("{group_path}.every"), message, hint);
                None
            }
        };
        if group.registers.is_empty() {
            problems.warning(
                &format!("{group_path}.registers"),
                "this poll group lists no registers",
                "list the registers to read at this interval, or remove the group",
            );
        }
        for (r, name) in group.registers.iter().enumerate() {
            let at = format!("{group_path}.registers[{r}]");
            let register = match problems.catalogue.register_for(drive, name, false) {
                Ok(register) => register,
                Err(failure) => {
                    problems.failure(&at, failure);
                    continue;
                }
            };
            if register.access == Access::WriteOnly {
                problems.error(
                    &at,
                    format!("{} is write-only: it cannot be polled", register.label()),
                    "the manual lists it as write-only; allow it under `write:` instead",
                );
                continue;
            }
            if let Some((_, first)) = seen.iter().find(|(seen, _)| std::ptr::eq(*seen, register)) {
                problems.error(
                    &at,
                    format!(
                        "{} is polled twice (first at line {})",
                        register.label(),
                        problems.line(first)
                    ),
                    "list each register once, in the group with the interval it needs",
                );
                continue;
            }
            seen.push((register, at));
            if let Some(every) = every {
                polls.push(Poll { register, every });
            }
        }
    }
    polls
}

/// The write allow-list of the drive entry at `path`, resolved to `head`.
pub fn writes(
    head: &Head,
    entries: &[WriteEntry],
    path: &str,
    problems: &mut Problems<'_>,
) -> Vec<Allowed> {
    let drive = head.drive;
    let mut writes: Vec<Allowed> = Vec::new();
    let mut seen: Vec<(&'static RegisterInfo, String)> = Vec::new();
    for (w, entry) in entries.iter().enumerate() {
        let at = format!("{path}.write[{w}]");
        let register = match problems
            .catalogue
            .register_for(drive, &entry.register, true)
        {
            Ok(register) => register,
            Err(failure) => {
                problems.failure(&format!("{at}.register"), failure);
                continue;
            }
        };
        // The library's one write check, asked once here: the worker does not ask again
        // for an allowed register (the session asks just before sending).
        let writable = write_check::writable(register, entry.persistent).map_err(|r| r.reason());
        if writable == Err(Reason::ReadOnly) {
            problems.error(
                &format!("{at}.register"),
                format!("{} is read-only: it cannot be written", register.label()),
                "the manual lists it as read-only; poll it under `poll:` instead",
            );
            continue;
        }
        if let Some((_, first)) = seen.iter().find(|(seen, _)| std::ptr::eq(*seen, register)) {
            problems.error(
                &format!("{at}.register"),
                format!(
                    "{} is allowed twice (first at line {})",
                    register.label(),
                    problems.line(first)
                ),
                "list each register once (with `persistent: true` where writes should reach EEPROM)",
            );
            continue;
        }
        seen.push((register, format!("{at}.register")));
        if writable == Err(Reason::RamOnly) {
            problems.error(
                &format!("{at}.persistent"),
                format!(
                    "{} is RAM-only: it cannot be written persistently",
                    register.label()
                ),
                "leave `persistent` out: its writes go to RAM",
            );
            continue;
        }
        if entry.persistent && !writes_persistently(head.protocol, head, register) {
            let others: Vec<&str> = drive
                .protocols
                .iter()
                .filter(|other| writes_persistently(other, head, register))
                .map(|other| other.id.as_ref())
                .collect();
            problems.error(
                &format!("{at}.persistent"),
                format!(
                    "{} cannot be written persistently over protocol `{}`: it has no persistent write for it{}",
                    register.label(),
                    head.protocol.id,
                    if head.protocol.persistence.is_some() {
                        ", and the drive's persistence selector does not govern it"
                    } else {
                        ""
                    }
                ),
                if others.is_empty() {
                    format!(
                        "leave `persistent` out: a write goes where the drive's description says (`vfd info {} {}`)",
                        drive.id, register.code
                    )
                } else {
                    format!(
                        "leave `persistent` out, or put the drive on a protocol that writes it persistently: {}",
                        others.join(", ")
                    )
                },
            );
            continue;
        }
        if entry.persistent && register.persistent_write_to_ram {
            problems.warning(
                &format!("{at}.persistent"),
                format!(
                    "{}: the drive accepts a persistent write but keeps the value in RAM only (lost at power-off)",
                    register.label()
                ),
                "leave `persistent` out, or set the value from the drive's panel where it must survive a power cycle",
            );
        }
        if register.panel_only {
            problems.warning(
                &at,
                format!(
                    "{} takes effect only when set from the operator panel",
                    register.label()
                ),
                "a write over the bus is accepted but changes nothing; remove it from `write:`",
            );
        }
        writes.push(Allowed {
            register,
            persistent: entry.persistent,
        });
    }
    writes
}

/// Whether `protocol` carries a persistent write of `register` (on `head`'s port, to its
/// station): a persistent command the runtime can encode for it, or a plain write the
/// drive's persistence selector governs (DV1 07-11).
fn writes_persistently(
    protocol: &'static Protocol,
    head: &Head,
    register: &'static RegisterInfo,
) -> bool {
    let register = head.port.map_or(register, |port| port.register(register));
    let request = Request::for_register(CommandKind::WritePersistent, register, 0);
    if protocol
        .persistence
        .as_ref()
        .is_some_and(|selector| selector.governs_request(&request))
    {
        return true;
    }
    let station = Station {
        address: head.address.or(protocol.default_address()),
        reply_wait: 0,
    };
    script(protocol, &Exchange::single(request), &station, None).is_ok()
}
