//! What the virtual drive built from the description does: its behaviour model in words
//! and each protocol's answers to refused requests.

use super::error_codes::printed_error;
use super::trimmed;
use crate::ir::*;
use serde::Serialize;

#[derive(Serialize)]
pub(super) struct VirtualDriveView<'a> {
    /// The description's behaviour model, when it has one.
    behaviour: Option<&'a BehaviourIr>,
    /// Lines on what drives the simulated motor (command word, frequency, ramps).
    model_lines: Vec<String>,
    /// The refusals the model tells apart, as column titles.
    refusal_names: Vec<&'static str>,
    /// Per protocol: its id and the answer to each refusal, in the columns' order.
    refusals: Vec<(String, Vec<String>)>,
}

/// The command and status roles whose bits are held by a register of their own (a field of
/// another bit-field register, or a coil), with those bits, in the model's order.
fn held_elsewhere(behaviour: &BehaviourIr) -> Vec<(&'static str, &BitRefIr)> {
    let status = &behaviour.status;
    let mut roles: Vec<(&'static str, &BitRefIr)> = Vec::new();
    for (role, bit) in [
        ("run", &behaviour.run),
        ("reverse run", &behaviour.run_reverse),
        ("reverse", &behaviour.reverse),
        ("reset", &behaviour.reset),
        ("coast", &behaviour.coast),
    ] {
        roles.extend(bit.iter().map(|bit| (role, bit)));
    }
    let lists: [(&'static str, &Vec<BitRefIr>); 11] = [
        ("command required", &behaviour.command_require),
        ("frequency required", &behaviour.frequency_require),
        ("running", &status.running),
        ("reversing", &status.reverse),
        ("running forward", &status.forward),
        ("at the frequency command", &status.at_reference),
        ("tripped", &status.tripped),
        ("overload", &status.overload),
        ("frequency detected", &status.frequency_detected),
        ("enabled", &status.enabled),
        ("always", &status.always),
    ];
    for (role, bits) in lists {
        roles.extend(bits.iter().map(|bit| (role, bit)));
    }
    roles.retain(|(_, bit)| bit.register.is_some());
    roles
}

/// What the virtual drive built from the description does: its behaviour model's parts in
/// words and each protocol's answers to refused requests.
pub(super) fn virtual_drive_view(drive: &DriveIr) -> VirtualDriveView<'_> {
    let Some(behaviour) = &drive.behaviour else {
        return VirtualDriveView {
            behaviour: None,
            model_lines: Vec::new(),
            refusal_names: Vec::new(),
            refusals: Vec::new(),
        };
    };
    let code = |id: &str| {
        drive
            .register(id)
            .map_or_else(|| id.to_owned(), |r| r.code.clone())
    };
    let codes = |ids: &[String]| ids.iter().map(|id| code(id)).collect::<Vec<_>>().join(", ");
    let amount = |a: &AmountIr, unit: &str| match a {
        AmountIr::Number(n) => format!("{} {unit}", trimmed(*n)),
        AmountIr::Register(id) => code(id),
    };
    let mut model_lines = vec![format!(
        "Commands: the command word is {}{}; the frequency command is {}.",
        code(&behaviour.command_register),
        match &behaviour.require_mode {
            Some((register, values)) => format!(
                ", taken only while {} = {}",
                code(register),
                values
                    .iter()
                    .map(|v| v.to_string())
                    .collect::<Vec<_>>()
                    .join(" or ")
            ),
            None => String::new(),
        },
        match &behaviour.frequency_percent_of {
            Some(full) => format!(
                "{}, a percentage of {}",
                code(&behaviour.frequency_command),
                amount(full, "Hz")
            ),
            None => code(&behaviour.frequency_command),
        }
    )];
    if let Some(c) = &behaviour.command_codes {
        let named = [
            ("run forward", &c.run),
            ("run in reverse", &c.run_reverse),
            ("stop", &c.stop),
            ("coast to a stop", &c.coast),
            ("reset a trip", &c.reset),
        ];
        let parts: Vec<String> = named
            .iter()
            .filter(|(_, values)| !values.is_empty())
            .map(|(what, values)| {
                let values: Vec<String> = values.iter().map(|v| format!("{v:04X}h")).collect();
                format!("{} {what}", values.join(" or "))
            })
            .collect();
        model_lines.push(format!(
            "Command codes: the command word holds a code, not bits: {}; any other value \
             changes nothing.",
            parts.join(", ")
        ));
    }
    if let Some(s) = &behaviour.status_state {
        model_lines.push(format!(
            "State register: {} holds {:04X}h while stopped, {:04X}h running forward, \
             {:04X}h running in reverse, {:04X}h tripped.",
            code(&s.register),
            s.stopped,
            s.forward,
            s.reverse,
            s.tripped
        ));
    }
    model_lines.push(format!(
        "Ramps: acceleration {}, deceleration {}, each for a change of {}.",
        amount(&behaviour.acceleration, "s"),
        amount(&behaviour.deceleration, "s"),
        amount(&behaviour.span, "Hz")
    ));
    if !behaviour.output.is_empty() {
        model_lines.push(format!(
            "Monitors following the output: {}.",
            codes(&behaviour.output)
        ));
    }
    if !behaviour.status_registers.is_empty() {
        model_lines.push(format!(
            "Status words: {}.",
            codes(&behaviour.status_registers)
        ));
    }
    let held = held_elsewhere(behaviour)
        .into_iter()
        .map(|(role, bit)| {
            let register = bit.register.as_deref().unwrap_or_default();
            let coil = drive
                .register(register)
                .is_some_and(|r| r.data_type == vfd_runtime::DataType::Bit);
            match bit.id.rsplit_once('.') {
                Some((_, field)) if !coil => format!("{role}: {} (`{field}`)", code(register)),
                _ => format!("{role}: coil {}", code(register)),
            }
        })
        .collect::<Vec<_>>();
    if !held.is_empty() {
        model_lines.push(format!(
            "Bits held by registers of their own: {}.",
            held.join("; ")
        ));
    }
    let mut levels = Vec::new();
    if let Some(level) = &behaviour.current_overload {
        levels.push(format!(
            "overload while the output current is at or above {}",
            amount(level, "").trim_end()
        ));
    }
    if let Some(level) = &behaviour.frequency_detection {
        levels.push(format!(
            "frequency detected while running at or above {}",
            amount(level, "Hz")
        ));
    }
    if !levels.is_empty() {
        model_lines.push(format!("Status levels: {}.", levels.join("; ")));
    }
    let answer = |protocol: &ProtocolIr, code: Option<u16>| match code {
        Some(code) => printed_error(drive, protocol, code),
        None => "no reply".to_owned(),
    };
    // The refusals every model tells apart, then those only some models give.
    type Cell = fn(&RefusalsIr) -> Option<u16>;
    let mut columns: Vec<(&'static str, Cell)> = vec![
        ("Unknown register", |r| r.unknown_register),
        ("Read-only register", |r| r.read_only),
        ("Out of range", |r| r.out_of_range),
        ("While running", |r| r.while_running),
        ("Bad checksum", |r| r.bad_checksum),
    ];
    if behaviour.require_mode.is_some() {
        columns.push(("Outside the required mode", |r| r.wrong_mode));
    }
    let optional: [(&'static str, Cell); 3] = [
        ("Bad character", |r| r.bad_character),
        ("Malformed frame", |r| r.malformed),
        ("Retries exceeded", |r| {
            r.retries_exceeded.as_ref().map(|(code, _)| *code)
        }),
    ];
    for (name, cell) in optional {
        if behaviour.refusals.iter().any(|r| cell(r).is_some()) {
            columns.push((name, cell));
        }
    }
    let refusal_names = columns.iter().map(|(name, _)| *name).collect();
    let refusals = drive
        .protocols
        .iter()
        .map(|protocol| {
            let entry = behaviour
                .refusals
                .iter()
                .find(|r| r.protocol == protocol.id);
            let cells: Vec<String> = columns
                .iter()
                .map(|(_, cell)| answer(protocol, entry.and_then(cell)))
                .collect();
            (protocol.id.clone(), cells)
        })
        .collect();
    for rule in &behaviour.refusals {
        if let Some((code, after)) = &rule.retries_exceeded {
            model_lines.push(format!(
                "Over `{}`, once more than {} unreadable frames (bad characters, malformed frames, bad checksums) came in a row, the next is answered {code:X}h.",
                rule.protocol,
                amount(after, "").trim_end()
            ));
        }
    }
    VirtualDriveView {
        behaviour: Some(behaviour),
        model_lines,
        refusal_names,
        refusals,
    }
}
