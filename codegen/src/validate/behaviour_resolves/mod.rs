//! Check: the behaviour model names registers, bits and protocols that exist: the
//! command and status words are bit-field registers, every bit is a field of their bit
//! field, and every protocol with refusal codes is one of the drive's.

use crate::diagnostics::Diagnostics;
use crate::parse::model::{BehaviourModel, BitRefModel, BoundModel, DriveFile};
use crate::validate::ranges::RegisterIndex;
use crate::validate::Context;

/// The behaviour model names registers, bits and protocols that exist.
pub fn behaviour_resolves(drive: &Context, out: &mut Diagnostics) {
    let model = &drive.model;
    let Some(behaviour) = &model.behaviour else {
        return;
    };
    let index = RegisterIndex::new(model);
    let mut problem = |path: String, message: String, hint: &str| {
        out.push(drive.source.error(&path, message).hint(hint));
    };
    let mut register = |path: String, name: &str| {
        if index.find(name).is_none() {
            problem(
                path,
                format!("register `{name}` is not defined"),
                "name a register by its code or id",
            );
        }
    };
    for (path, name) in registers_named(behaviour) {
        register(path, name);
    }
    let written = [
        (
            "behaviour.command.reset_by_write",
            &behaviour.command.reset_by_write,
            "reset",
        ),
        (
            "behaviour.trip.clear_by_write",
            &behaviour.trip.clear_by_write,
            "clear the trip history",
        ),
    ];
    for (path, value, what) in written {
        let Some(value) = value else { continue };
        let Some(target) = index.find(&value.register) else {
            continue;
        };
        if target.access == Some(vfd_runtime::Access::ReadOnly) {
            problem(
                format!("{path}.register"),
                format!(
                    "register `{}` is read-only: no value can be written to it",
                    value.register
                ),
                &format!("name the register the manual writes the value to {what}"),
            );
        } else if let Some(table) = target
            .code_table
            .as_deref()
            .and_then(|id| model.codes.iter().find(|t| t.id == id))
        {
            if !table.values.iter().any(|v| v.value == value.value) {
                problem(
                    format!("{path}.value"),
                    format!(
                        "{:#06X} is not a value of `{}`'s code table `{}`",
                        value.value, value.register, table.id
                    ),
                    &format!(
                        "give the raw value the manual writes to {what}, one of the register's codes"
                    ),
                );
            }
        } else if value.value > 0xFFFF {
            problem(
                format!("{path}.value"),
                format!("{:#X} does not fit a 16-bit word", value.value),
                &format!("give the raw value the manual writes to {what}, 0x0000-0xFFFF"),
            );
        }
    }
    // A status role set by a level needs the level.
    let levels = [
        (
            "overload",
            behaviour.status.overload.is_empty(),
            behaviour.current.as_ref().and_then(|c| c.overload.as_ref()).is_some(),
            "give `current: { registers, at_zero, at_span, overload }`: the output current at and above which the drive reports an overload",
        ),
        (
            "frequency_detected",
            behaviour.status.frequency_detected.is_empty(),
            behaviour.frequency.detection.is_some(),
            "give `frequency.detection`: the output frequency (a number or a register) at and above which the drive reports it",
        ),
    ];
    percent_command(&index, behaviour, &mut problem);
    for (key, empty, level, hint) in levels {
        if !empty && !level {
            problem(
                format!("behaviour.status.{key}"),
                format!("`{key}` bits are set by a level the model does not give"),
                hint,
            );
        }
    }
    if let Some(mode) = &behaviour.command.require_mode {
        let path = "behaviour.command.require_mode.values";
        if mode.values.is_empty() {
            problem(
                path.to_owned(),
                "no value is given: the drive would take no command in any mode".to_owned(),
                "list the raw values of the mode register in which the drive takes commands",
            );
        }
        let table = index
            .find(&mode.register)
            .and_then(|r| r.code_table.as_deref())
            .and_then(|id| model.codes.iter().find(|t| t.id == id));
        if let Some(table) = table {
            for (i, value) in mode.values.iter().enumerate() {
                if !table.values.iter().any(|v| v.value == *value) {
                    problem(
                        format!("{path}[{i}]"),
                        format!(
                            "{value:#06X} is not a value of `{}`'s code table `{}`",
                            mode.register, table.id
                        ),
                        "give a mode as the register's code table lists it",
                    );
                }
            }
        }
    }
    for (i, name) in behaviour.trip.history.iter().enumerate() {
        if index.find(name).is_some() {
            continue;
        }
        let path = format!("behaviour.trip.history[{i}]");
        let field = name
            .rsplit_once('.')
            .and_then(|(register, field)| index.find(register).map(|r| (r, field)));
        match field {
            None => problem(
                path,
                format!("register `{name}` is not defined"),
                "name a register by its code or id, or a field of a bit-field register as `register.field`",
            ),
            Some((register, field)) => {
                let bitfield = register
                    .bitfield
                    .as_deref()
                    .and_then(|id| model.bitfields.iter().find(|b| b.id == id));
                match bitfield {
                    None => problem(
                        path,
                        format!("register `{}` is not a bit-field word, so `{name}` names no field", register.id),
                        "name the whole register, or a field of a register with `bitfield:`",
                    ),
                    Some(b) if !b.fields.iter().any(|f| f.id.as_deref() == Some(field)) => problem(
                        path,
                        format!("`{field}` is not a field of `{}`", b.id),
                        "name a field by its id in the register's bit field",
                    ),
                    Some(_) => {}
                }
            }
        }
    }
    let bitfield_of = |name: &str| {
        index
            .find(name)
            .and_then(|r| r.bitfield.as_deref())
            .and_then(|id| model.bitfields.iter().find(|b| b.id == id))
    };
    let words = [
        (
            "behaviour.command.register",
            behaviour.command.register.as_str(),
            command_bits(behaviour),
        ),
        (
            "behaviour.status.registers[0]",
            behaviour
                .status
                .registers
                .first()
                .map_or("", String::as_str),
            status_bits(behaviour),
        ),
    ];
    for (path, word, bits) in words {
        let register = index.find(word).filter(|_| !word.is_empty());
        if !word.is_empty() && register.is_none() {
            continue;
        }
        // A register of command codes needs no bit field (`codes_and_states` checks it).
        if path == "behaviour.command.register" && behaviour.command.codes.is_some() {
            continue;
        }
        // A `bitfield:` naming no bit field is `references_resolve`'s to report, once.
        let undefined = register
            .and_then(|r| r.bitfield.as_deref())
            .is_some_and(|id| !model.bitfields.iter().any(|b| b.id == id));
        if undefined {
            continue;
        }
        let bitfield = bitfield_of(word);
        let coil = register.is_some_and(|r| r.data_type == Some(vfd_runtime::DataType::Bit));
        if register.is_some() && bitfield.is_none() && !coil {
            problem(
                path.to_owned(),
                format!("register `{word}` is not a bit-field word"),
                "name a register with `bitfield:`",
            );
            continue;
        }
        for (bit_path, bit) in bits {
            let name = bit.id();
            if bitfield.is_some_and(|b| b.fields.iter().any(|f| f.id.as_deref() == Some(name))) {
                continue;
            }
            match elsewhere(model, &index, name) {
                Elsewhere::Held => continue,
                Elsewhere::Wrong(message, hint) => {
                    problem(bit_path, message, hint);
                    continue;
                }
                Elsewhere::Nothing => {}
            }
            if let Some((register, _)) = name.rsplit_once('.') {
                problem(
                    bit_path,
                    format!("register `{register}` is not defined, so `{name}` names no bit"),
                    "name a field of another bit-field register as `register.field`, the register by its code or id",
                );
                continue;
            }
            match bitfield {
                Some(bitfield) => problem(
                    bit_path,
                    format!("bit `{name}` is not a field of `{}`", bitfield.id),
                    "name a bit by its id in the word's bit field",
                ),
                None => problem(
                    bit_path,
                    format!("`{name}` names no bit: the role has no bit-field word, and it is neither `register.field` nor a coil"),
                    "name a field of a bit-field register as `register.field`, or a coil (a register of `data_type: bit`) by its code or id",
                ),
            }
        }
    }
    for protocol in behaviour.refusals.keys() {
        if !model.protocols.iter().any(|p| &p.id == protocol) {
            problem(
                format!("behaviour.refusals.{protocol}"),
                format!("protocol `{protocol}` is not one of the drive's"),
                &protocol_hint(model),
            );
        }
    }
    // A protocol without refusals would leave the virtual drive silent on every refused
    // request over it: say so explicitly (`{}`) where the manual gives no error replies.
    if !behaviour.refusals.is_empty() {
        for protocol in &model.protocols {
            if !behaviour.refusals.contains_key(&protocol.id) {
                problem(
                    "behaviour.refusals".to_owned(),
                    format!("protocol `{}` has no refusals: the virtual drive would not answer a refused request over it", protocol.id),
                    "give its error codes (unknown_register, read_only, out_of_range, while_running, bad_checksum, wrong_mode, bad_character, malformed, retries_exceeded) as the manual lists them, or `{}` where it gives none",
                );
            }
        }
    }
    codes_and_states(drive, behaviour, &index, out);
}

/// A command register holding codes (`command.codes`) instead of a run bit, and a status
/// register holding the state as a code (`status.state`): one of `run` and `codes`, no
/// command bits beside codes, each code once, and codes the register's table lists.
fn codes_and_states(
    drive: &Context,
    behaviour: &BehaviourModel,
    index: &RegisterIndex<'_>,
    out: &mut Diagnostics,
) {
    let model = &drive.model;
    let mut problem = |path: String, message: String, hint: &str| {
        out.push(drive.source.error(&path, message).hint(hint));
    };
    let command = &behaviour.command;
    match (&command.run, &command.codes) {
        (None, None) => problem(
            "behaviour.command".to_owned(),
            "the command register has neither a run bit (`run`) nor command codes (`codes`)"
                .to_owned(),
            "give `run: <bit>` for a command word, or `codes: { run: [..], stop: [..] }` for a register the manual writes codes to",
        ),
        (Some(_), Some(_)) => problem(
            "behaviour.command.codes".to_owned(),
            "`codes` and a run bit (`run`) are both given".to_owned(),
            "a command register holds either bits or codes: leave out `run` where the manual writes codes",
        ),
        _ => {}
    }
    let table_of = |name: &str| {
        index
            .find(name)
            .and_then(|r| r.code_table.as_deref())
            .and_then(|id| model.codes.iter().find(|t| t.id == id))
    };
    // Checks one raw value against the register's code table, or a 16-bit word.
    let value_problem =
        |path: String, register: &str, value: u32| -> Option<(String, String, String)> {
            match table_of(register) {
                Some(table) if !table.values.iter().any(|v| v.value == value) => Some((
                    path,
                    format!(
                        "{value:#06X} is not a value of `{register}`'s code table `{}`",
                        table.id
                    ),
                    "give the raw value as the register's code table lists it".to_owned(),
                )),
                None if value > 0xFFFF => Some((
                    path,
                    format!("{value:#X} does not fit a 16-bit word"),
                    "give the raw value the manual gives, 0x0000-0xFFFF".to_owned(),
                )),
                _ => None,
            }
        };
    let mut found = Vec::new();
    if let Some(codes) = &command.codes {
        if command.run.is_none() {
            let bits = [
                ("require", !command.require.is_empty()),
                ("run_reverse", command.run_reverse.is_some()),
                ("reverse", command.reverse.is_some()),
                ("reset", command.reset.is_some()),
                ("coast", command.coast.is_some()),
            ];
            for (key, given) in bits {
                if given {
                    found.push((
                        format!("behaviour.command.{key}"),
                        format!("`{key}` is a bit of a command word, but the command register holds codes"),
                        "say what each code does in `codes` (run, run_reverse, stop, coast, reset)".to_owned(),
                    ));
                }
            }
            if !behaviour.frequency.require.is_empty() {
                found.push((
                    "behaviour.frequency.require".to_owned(),
                    "`require` names command-word bits, but the command register holds codes"
                        .to_owned(),
                    "leave it out: the frequency command is in effect whatever code was written"
                        .to_owned(),
                ));
            }
        }
        let lists = [
            ("run", &codes.run),
            ("run_reverse", &codes.run_reverse),
            ("stop", &codes.stop),
            ("coast", &codes.coast),
            ("reset", &codes.reset),
        ];
        let mut seen: Vec<(u32, &str)> = Vec::new();
        for (key, list) in lists {
            for (i, &value) in list.iter().enumerate() {
                let path = format!("behaviour.command.codes.{key}[{i}]");
                if let Some((_, other)) = seen.iter().find(|(v, _)| *v == value) {
                    found.push((
                        path,
                        format!("code {value:#06X} is listed under `{other}` already"),
                        "each code does one thing: list it once".to_owned(),
                    ));
                    continue;
                }
                seen.push((value, key));
                found.extend(value_problem(path, &command.register, value));
            }
        }
    }
    if let Some(state) = &behaviour.status.state {
        let values = [
            ("stopped", Some(state.stopped)),
            ("forward", Some(state.forward)),
            ("reverse", state.reverse),
            ("tripped", state.tripped),
        ];
        for (key, value) in values {
            if let Some(value) = value {
                let path = format!("behaviour.status.state.{key}");
                found.extend(value_problem(path, &state.register, value));
            }
        }
    }
    for (path, message, hint) in found {
        problem(path, message, &hint);
    }
}

/// What `name` names as a bit held by another register than its role's word.
enum Elsewhere {
    /// A field of another bit-field register (`register.field`), or a coil.
    Held,
    /// A register, but no such bit: the message and the hint.
    Wrong(String, &'static str),
    /// No register.
    Nothing,
}

/// Whether `name` names a bit held by another register than its role's word
/// (`register.field` whose register exists, or a register by code or id), and what is
/// wrong with it: the register is no bit-field word, the field is not one of its bit
/// field's, or a register named whole is not a coil.
fn elsewhere(model: &DriveFile, index: &RegisterIndex<'_>, name: &str) -> Elsewhere {
    let bitfield_of = |register: &crate::parse::model::RegisterModel| {
        register
            .bitfield
            .as_deref()
            .and_then(|id| model.bitfields.iter().find(|b| b.id == id))
    };
    if let Some(register) = index.find(name) {
        if register.data_type == Some(vfd_runtime::DataType::Bit) {
            return Elsewhere::Held;
        }
        return Elsewhere::Wrong(
            format!("register `{}` is not a coil, so `{name}` names no bit of its own", register.id),
            "a register named as a bit must be a coil (`data_type: bit`); name a field of a bit-field register as `register.field`",
        );
    }
    let Some((register, field)) = name
        .rsplit_once('.')
        .and_then(|(register, field)| index.find(register).map(|r| (r, field)))
    else {
        return Elsewhere::Nothing;
    };
    match bitfield_of(register) {
        None => Elsewhere::Wrong(
            format!(
                "register `{}` is not a bit-field word, so `{name}` names no field",
                register.id
            ),
            "name a field of a register with `bitfield:` as `register.field`",
        ),
        Some(b) if !b.fields.iter().any(|f| f.id.as_deref() == Some(field)) => Elsewhere::Wrong(
            format!("`{field}` is not a field of `{}`", b.id),
            "name a field by its id in the register's bit field",
        ),
        Some(_) => Elsewhere::Held,
    }
}

/// `frequency.percent_of` reads the frequency command as a percentage: its register must
/// be in `%`, and the frequency its 100 % stands for must not be one.
fn percent_command(
    index: &RegisterIndex,
    behaviour: &BehaviourModel,
    problem: &mut impl FnMut(String, String, &str),
) {
    let Some(full) = &behaviour.frequency.percent_of else {
        return;
    };
    let unit = |name: &str| index.find(name).map(|r| r.unit.as_deref().unwrap_or(""));
    if let Some(unit) = unit(&behaviour.frequency.command) {
        if unit != "%" {
            let shown = if unit.is_empty() { "no unit" } else { unit };
            problem(
                "behaviour.frequency.percent_of".to_owned(),
                format!(
                    "`percent_of` reads the frequency command `{}` as a percentage, but it is in {shown}",
                    behaviour.frequency.command
                ),
                "leave `percent_of` out where the command register holds a frequency; give it where the register's unit is `%`",
            );
        }
    }
    if let BoundModel::Register(name) = full {
        if unit(name) == Some("%") {
            problem(
                "behaviour.frequency.percent_of".to_owned(),
                format!("`{name}` is a percentage itself, not the frequency 100 % stands for"),
                "name the register holding the frequency the command's 100 % stands for (a maximum frequency)",
            );
        }
    }
}

fn protocol_hint(model: &DriveFile) -> String {
    let ids: Vec<&str> = model.protocols.iter().map(|p| p.id.as_str()).collect();
    format!("the drive's protocols are: {}", ids.join(", "))
}

/// Every register the model names, with its path.
fn registers_named(b: &BehaviourModel) -> Vec<(String, &str)> {
    let mut named = vec![
        (
            "behaviour.command.register".to_owned(),
            b.command.register.as_str(),
        ),
        (
            "behaviour.frequency.command".to_owned(),
            b.frequency.command.as_str(),
        ),
    ];
    for (key, amount) in [
        ("frequency.acceleration", Some(&b.frequency.acceleration)),
        ("frequency.deceleration", Some(&b.frequency.deceleration)),
        ("frequency.span", Some(&b.frequency.span)),
        ("frequency.detection", b.frequency.detection.as_ref()),
        ("frequency.percent_of", b.frequency.percent_of.as_ref()),
        (
            "current.overload",
            b.current.as_ref().and_then(|c| c.overload.as_ref()),
        ),
    ] {
        if let Some(BoundModel::Register(name)) = amount {
            named.push((format!("behaviour.{key}"), name));
        }
    }
    let lists: [(&str, &[String]); 5] = [
        ("frequency.output", &b.frequency.output),
        ("frequency.reference", &b.frequency.reference),
        ("status.registers", &b.status.registers),
        ("trip.code", &b.trip.code),
        (
            "current.registers",
            b.current.as_ref().map_or(&[][..], |c| &c.registers),
        ),
    ];
    for (key, list) in lists {
        for (i, name) in list.iter().enumerate() {
            named.push((format!("behaviour.{key}[{i}]"), name));
        }
    }
    if let Some(state) = &b.status.state {
        named.push((
            "behaviour.status.state.register".to_owned(),
            state.register.as_str(),
        ));
    }
    if let Some(mode) = &b.command.require_mode {
        named.push((
            "behaviour.command.require_mode.register".to_owned(),
            mode.register.as_str(),
        ));
    }
    for (key, written) in [
        ("command.reset_by_write", &b.command.reset_by_write),
        ("trip.clear_by_write", &b.trip.clear_by_write),
    ] {
        if let Some(written) = written {
            named.push((
                format!("behaviour.{key}.register"),
                written.register.as_str(),
            ));
        }
    }
    if let Some(p) = &b.process {
        for (key, name) in [
            ("control", &p.control),
            ("reference", &p.reference),
            ("status", &p.status),
            ("output", &p.output),
        ] {
            named.push((format!("behaviour.process.{key}"), name));
        }
    }
    named
}

/// The command word's bits, with their paths.
fn command_bits(b: &BehaviourModel) -> Vec<(String, &BitRefModel)> {
    let c = &b.command;
    let mut bits = Vec::new();
    if let Some(run) = &c.run {
        bits.push(("behaviour.command.run".to_owned(), run));
    }
    for (key, bit) in [
        ("run_reverse", &c.run_reverse),
        ("reverse", &c.reverse),
        ("reset", &c.reset),
        ("coast", &c.coast),
    ] {
        if let Some(bit) = bit {
            bits.push((format!("behaviour.command.{key}"), bit));
        }
    }
    for (key, list) in [
        ("command.require", &c.require),
        ("frequency.require", &b.frequency.require),
    ] {
        for (i, bit) in list.iter().enumerate() {
            bits.push((format!("behaviour.{key}[{i}]"), bit));
        }
    }
    bits
}

/// The status word's bits, with their paths.
fn status_bits(b: &BehaviourModel) -> Vec<(String, &BitRefModel)> {
    let s = &b.status;
    let lists: [(&str, &Vec<BitRefModel>); 9] = [
        ("running", &s.running),
        ("reverse", &s.reverse),
        ("forward", &s.forward),
        ("at_reference", &s.at_reference),
        ("tripped", &s.tripped),
        ("overload", &s.overload),
        ("frequency_detected", &s.frequency_detected),
        ("enabled", &s.enabled),
        ("always", &s.always),
    ];
    let mut bits = Vec::new();
    for (key, list) in lists {
        for (i, bit) in list.iter().enumerate() {
            bits.push((format!("behaviour.status.{key}[{i}]"), bit));
        }
    }
    bits
}

#[cfg(test)]
mod tests;
