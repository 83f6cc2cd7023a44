//! `vfd backup` and `vfd restore`: every readable parameter into a YAML (or JSON) file that
//! people can read and edit (values in units, codes with their meaning), and back: only
//! writable values that differ from the drive's, after checking every entry, in RAM unless
//! `--persist`.

use crate::emit::{Emitter, Format};
use crate::line_args::LineArgs;
use crate::out::say;
use crate::Failure;
use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};
use std::path::Path;
use vfd_bus::record::ValueRecord;
use vfd_bus::session::{Session, Value};
use vfd_bus::trip_flag::trip_flag;
use vfd_bus::values;
use vfd_bus::{Catalogue, ErrorKind};
use vfd_runtime::{Access, RegisterInfo, Space};

/// A backup file.
#[derive(Debug, Serialize, Deserialize)]
pub struct Backup {
    /// Drive id: a restore refuses another drive's file.
    pub drive: String,
    /// Vendor and model, for people.
    pub model: String,
    /// Protocol the values were read with.
    pub protocol: String,
    /// The values.
    pub parameters: Vec<Entry>,
}

/// One parameter.
#[derive(Debug, Serialize, Deserialize)]
pub struct Entry {
    /// The manual's code.
    pub code: String,
    /// English name, for people.
    #[serde(default)]
    pub name: String,
    /// The value as `vfd write` takes it (`80.00 Hz`, `1`, `C400h`).
    pub value: String,
    /// What a code or bit-field value means, for people.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub meaning: String,
    /// `read-only` for values kept for reference (never written back).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub access: String,
}

/// Whether a register belongs in a backup: a readable parameter that is not a command
/// (RAM-only registers such as command words are left out: restoring one could start a motor).
fn backed_up(session: &Session, info: &RegisterInfo) -> bool {
    info.space == Space::Parameter
        && info.access != Access::WriteOnly
        && !info.ram_only
        && info.array_len == 0
        && session.can_read(info)
}

/// The value as `vfd write` takes it, and what it means.
fn entry_value(info: &RegisterInfo, value: &Value) -> (String, String) {
    match (&value.text, value.raw) {
        (Some(text), _) => (text.clone(), String::new()),
        (None, Some(raw)) => {
            if let Some(bits) = info.bits {
                (
                    values::hex(info, raw),
                    values::set_fields(bits, raw as u16).join(", "),
                )
            } else if let Some(codes) = info.codes {
                (values::scaled(info, raw), values::code_meaning(codes, raw))
            } else {
                (values::scaled(info, raw), String::new())
            }
        }
        (None, None) => (String::new(), String::new()),
    }
}

fn progress(len: usize, what: &str) -> ProgressBar {
    let bar = ProgressBar::new(len as u64);
    if let Ok(style) = ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len}") {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(what.to_owned());
    bar
}

/// Reads every parameter and writes the file.
pub fn backup(
    catalogue: &Catalogue,
    line: &LineArgs,
    to: &Path,
    format: Format,
) -> Result<(), Failure> {
    let mut session = crate::open_session::open_session(line, catalogue)?;
    let registers: Vec<&'static RegisterInfo> = session
        .drive
        .registers
        .iter()
        .copied()
        .filter(|r| backed_up(&session, r))
        .collect();
    let bar = progress(registers.len(), "reading");
    let mut parameters = Vec::new();
    let mut failed = Vec::new();
    // Consecutive registers in one request where the protocol allows it.
    let mut read = Vec::with_capacity(registers.len());
    for chunk in registers.chunks(128) {
        read.extend(session.read_many(chunk));
        bar.inc(chunk.len() as u64);
    }
    let mut listing = Emitter::new(format);
    let mut errors = 0;
    let tripped = trip_flag(&session, &registers, &read);
    for (info, result) in registers.iter().zip(read) {
        // The listing (`--format`): every parameter as `vfd read` gives it.
        match &result {
            Ok(value) => {
                let mut record =
                    ValueRecord::new(session.drive.id, info, value.raw, value.text.clone()).now();
                record.errors = errors;
                record.tripped = tripped;
                listing.record(&record);
            }
            Err(failure) => {
                errors += 1;
                let error = failure.exchange().cloned().unwrap_or_else(|| {
                    vfd_bus::Error::new(ErrorKind::Other, failure.message().to_owned())
                });
                let mut record = ValueRecord::new(session.drive.id, info, None, None)
                    .now()
                    .failed(&error);
                record.errors = errors;
                listing.record(&record);
            }
        }
        match result {
            Ok(value) => {
                let (value, meaning) = entry_value(info, &value);
                parameters.push(Entry {
                    code: info.code.to_owned(),
                    name: info.name.to_owned(),
                    value,
                    meaning,
                    access: if info.access == Access::ReadOnly {
                        "read-only".to_owned()
                    } else {
                        String::new()
                    },
                });
            }
            Err(error) => failed.push(format!(
                "{}: {}",
                info.code,
                error_line(&Failure::from(error))
            )),
        }
    }
    bar.finish_and_clear();
    if parameters.is_empty() {
        return Err(Failure::new(format!(
            "no parameter could be read; first error: {}",
            failed.first().map_or("none", String::as_str)
        ))
        .hint("check the line with `vfd read` first"));
    }
    let drive = session.drive;
    let backup = Backup {
        drive: drive.id.to_owned(),
        model: format!("{} {}", drive.vendor, drive.model),
        protocol: session.protocol.id.to_string(),
        parameters,
    };
    let json = to
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let text = if json {
        serde_json::to_string_pretty(&backup).map_err(|e| Failure::new(e.to_string()))?
    } else {
        format!(
            "# vfd backup of a {} ({}): restore with `vfd restore --drive {} --from FILE`\n{}",
            backup.model,
            drive.id,
            // A drive loaded by its path is named by it: its id alone finds nothing.
            session.drive_name,
            yaml_serde::to_string(&backup).map_err(|e| Failure::new(e.to_string()))?
        )
    };
    std::fs::write(to, text)
        .map_err(|e| Failure::new(format!("cannot write {}: {e}", to.display())))?;
    listing.finish();
    let summary = format!(
        "saved {} parameters of {} to {} ({} read request(s))",
        backup.parameters.len(),
        drive.id,
        to.display(),
        session.requests
    );
    if !format.is_text() {
        // Standard output carries the listing alone.
        eprintln!("{summary}");
        return Ok(());
    }
    say!("{summary}");
    for line in &failed {
        say!("  not read: {line}");
    }
    Ok(())
}

fn error_line(failure: &Failure) -> String {
    failure.message.clone()
}

/// What restore will do with one entry.
enum Plan {
    Write(&'static RegisterInfo, u32, u32),
    Same,
    ReadOnly,
}

/// Checks every entry, then writes the changed writable values.
pub fn restore(
    catalogue: &Catalogue,
    line: &LineArgs,
    from: &Path,
    dry_run: bool,
    persist: bool,
    stop_first: bool,
) -> Result<(), Failure> {
    let text = std::fs::read_to_string(from)
        .map_err(|e| Failure::new(format!("cannot read {}: {e}", from.display())))?;
    let backup: Backup = if from
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        serde_json::from_str(&text).map_err(|e| Failure::new(format!("{}: {e}", from.display())))?
    } else {
        yaml_serde::from_str(&text).map_err(|e| Failure::new(format!("{}: {e}", from.display())))?
    };
    let drive = catalogue.drive(&line.drive)?;
    if !backup.drive.eq_ignore_ascii_case(drive.id) {
        return Err(Failure::new(format!(
            "{} is a backup of a {} ({}), not of a {}: nothing written",
            from.display(),
            backup.model,
            backup.drive,
            drive.id
        ))
        .hint(format!(
            "restore it onto a {} with --drive {} (or the path of its drive file); a backup of this {} is made with `vfd backup --drive {}`",
            backup.drive,
            backup.drive,
            drive.id,
            catalogue.name_for(drive)
        )));
    }
    // Every entry is checked before anything is sent.
    let mut refused = Vec::new();
    let mut wanted = Vec::new();
    for entry in &backup.parameters {
        let info = match catalogue.register(drive, &entry.code) {
            Ok(info) => info,
            Err(failure) => {
                refused.push(format!("{}: {}", entry.code, failure.message()));
                continue;
            }
        };
        if info.access == Access::ReadOnly || entry.access == "read-only" {
            wanted.push((info, None));
            continue;
        }
        if info.ram_only || info.data_type == vfd_runtime::DataType::Text {
            refused.push(format!("{}: {} cannot be restored", entry.code, info.name));
            continue;
        }
        match values::parse(info, &entry.value) {
            Ok(raw) => wanted.push((info, Some(raw))),
            Err(message) => refused.push(message),
        }
    }
    if !refused.is_empty() {
        for line in &refused {
            say!("refused: {line}");
        }
        return Err(Failure::new(format!(
            "{} entr{} of {} cannot be restored: nothing written",
            refused.len(),
            if refused.len() == 1 { "y" } else { "ies" },
            from.display()
        ))
        .hint("correct or remove those entries, then restore again"));
    }
    let mut session = crate::open_session::open_session(line, catalogue)?;
    let bar = progress(wanted.len(), "comparing");
    let mut plans = Vec::new();
    for (info, raw) in wanted {
        bar.inc(1);
        let Some(raw) = raw else {
            plans.push(Plan::ReadOnly);
            continue;
        };
        let current = session.read(info)?;
        match current.raw {
            Some(now) if now == raw => plans.push(Plan::Same),
            Some(now) => plans.push(Plan::Write(info, now, raw)),
            None => plans.push(Plan::Write(info, raw, raw)),
        }
    }
    bar.finish_and_clear();
    let same = plans.iter().filter(|p| matches!(p, Plan::Same)).count();
    let read_only = plans.iter().filter(|p| matches!(p, Plan::ReadOnly)).count();
    let writes: Vec<(&'static RegisterInfo, u32, u32)> = plans
        .iter()
        .filter_map(|p| match p {
            Plan::Write(info, now, raw) => Some((*info, *now, *raw)),
            _ => None,
        })
        .collect();
    let target = if persist { "RAM and EEPROM" } else { "RAM" };
    // Writes the protocol cannot send as asked are refused before anything is sent, with
    // the way they can be sent.
    check_sendable(&session, &writes, persist)?;
    // Registers the drive keeps in RAM whatever the command (`persistent_write_to_ram`).
    let kept_in_ram: Vec<&'static RegisterInfo> = writes
        .iter()
        .map(|(info, _, _)| *info)
        .filter(|info| persist && info.persistent_write_to_ram)
        .collect();
    let kept_note = (!kept_in_ram.is_empty()).then(|| {
        format!(
            "the drive keeps {} in RAM only, whatever the command (`vfd info` says so)",
            list(&kept_in_ram)
        )
    });
    if dry_run {
        for (info, now, raw) in &writes {
            say!(
                "would write {:<7} {}: {} -> {}",
                info.code,
                info.name,
                values::short(info, *now),
                values::short(info, *raw)
            );
        }
        say!(
            "dry run: {} to write ({target}), {same} unchanged, {read_only} read-only kept for reference; nothing written",
            writes.len()
        );
        return Ok(());
    }
    let blocked: Vec<&'static RegisterInfo> = writes
        .iter()
        .map(|(info, _, _)| *info)
        // `unknown` registers are attempted: a refusal is reported with the other failures.
        .filter(|info| !info.writable_while_running && !info.while_running_unknown)
        .collect();
    if !blocked.is_empty() && is_running(&mut session)? {
        if !stop_first {
            return Err(Failure::new(format!(
                "the drive is running: {} value(s) cannot be written while it runs ({}); nothing written",
                blocked.len(),
                list(&blocked)
            ))
            .hint("stop the drive first, or restore with --stop-first (stops it, then writes)"));
        }
        stop_drive(&mut session)?;
    }
    // One value at a time, each read back: a restore cut short leaves every value either
    // old or new, and running it again writes only what still differs.
    let bar = progress(writes.len(), "writing");
    let mut failed = Vec::new();
    // Whether every failure is the drive's refusal, which running again does not change.
    let mut only_refusals = true;
    let mut written = 0usize;
    for (info, now, raw) in &writes {
        bar.inc(1);
        let outcome = session
            .write(info, *raw, persist)
            .and_then(|_| session.read(info));
        match outcome {
            Ok(back) if back.raw == Some(*raw) => {
                written += 1;
                bar.suspend(|| {
                    say!(
                        "wrote {:<7} {}: {} -> {} (read back)",
                        info.code,
                        info.name,
                        values::short(info, *now),
                        values::short(info, *raw)
                    )
                });
            }
            Ok(back) => failed.push(format!(
                "{}: wrote {}, reads back {}",
                info.code,
                values::short(info, *raw),
                back.raw
                    .map_or_else(|| "no data".to_owned(), |b| values::short(info, b))
            )),
            Err(failure) => {
                only_refusals &= failure
                    .exchange()
                    .is_some_and(|e| e.kind() == ErrorKind::ErrorReply);
                failed.push(format!("{}: {}", info.code, failure.message()))
            }
        }
    }
    bar.finish_and_clear();
    say!(
        "restored {written} value(s) to {target}, each read back; {same} unchanged, {read_only} read-only kept for reference"
    );
    if let Some(note) = kept_note.filter(|_| written > 0) {
        say!("{note}");
    }
    let persistable = writes.iter().any(|(info, _, _)| {
        !info.persistent_write_to_ram && vfd_bus::storage::writes(session.protocol, info).persistent
    });
    if !persist && written > 0 && persistable {
        say!("RAM only: the restored values are lost at power-off (restore with --persist to keep them in EEPROM)");
    }
    if failed.is_empty() {
        Ok(())
    } else {
        for line in &failed {
            say!("failed: {line}");
        }
        Err(Failure::new(format!(
            "{} of {} write(s) failed",
            failed.len(),
            writes.len()
        ))
        .hint(if only_refusals {
            "the drive refused them (the reasons above): correct those entries of the file, then restore again"
        } else {
            "run the same restore again: it writes only the values that still differ"
        }))
    }
}

/// Refuses a restore whose writes the session's protocol cannot send as asked (RAM, or
/// with `--persist` persistent), naming the way they can be sent: the other storage, or
/// another protocol of the drive.
fn check_sendable(
    session: &Session,
    writes: &[(&'static RegisterInfo, u32, u32)],
    persist: bool,
) -> Result<(), Failure> {
    let sendable = |protocol: &vfd_runtime::Protocol, info: &RegisterInfo| {
        let can = vfd_bus::storage::writes(protocol, info);
        if persist {
            can.persistent
        } else {
            can.ram
        }
    };
    let stuck: Vec<&'static RegisterInfo> = writes
        .iter()
        .map(|(info, _, _)| *info)
        .filter(|info| !sendable(session.protocol, info))
        .collect();
    if stuck.is_empty() {
        return Ok(());
    }
    let other_storage = stuck.iter().all(|info| {
        let can = vfd_bus::storage::writes(session.protocol, info);
        if persist {
            can.ram
        } else {
            can.persistent
        }
    });
    let others: Vec<&str> = session
        .drive
        .protocols
        .iter()
        .filter(|p| p.id != session.protocol.id && stuck.iter().all(|info| sendable(p, info)))
        .map(|p| p.id.as_ref())
        .collect();
    let hint = match (other_storage, persist, others.is_empty()) {
        (true, false, _) => format!(
            "protocol {} writes them only persistently: restore with --persist",
            session.protocol.id
        ),
        (true, true, _) => format!(
            "protocol {} writes them to RAM only: restore without --persist",
            session.protocol.id
        ),
        (false, _, false) => format!("restore over --protocol {}", others.join(" or ")),
        (false, _, true) => "remove those entries from the file, then restore again".to_owned(),
    };
    Err(Failure::new(format!(
        "{} value(s) cannot be written {} over protocol {} ({}): nothing written",
        stuck.len(),
        if persist { "persistently" } else { "to RAM" },
        session.protocol.id,
        list(&stuck)
    ))
    .hint(hint))
}

/// `FH, UL, ...` (at most eight, then `...`).
fn list(registers: &[&'static RegisterInfo]) -> String {
    let mut codes: Vec<&str> = registers.iter().take(8).map(|r| r.code).collect();
    if registers.len() > 8 {
        codes.push("...");
    }
    codes.join(", ")
}

/// Whether the drive's status word says it runs, where its description says which bits
/// show it; `false` when it does not (the drive then refuses what it cannot take).
fn is_running(session: &mut Session) -> Result<bool, Failure> {
    let Some(behaviour) = session.drive.behaviour else {
        return Ok(false);
    };
    if let Some(state) = behaviour.status.state {
        if let Some(info) = session.drive.register(state.register) {
            if session.can_read(info) {
                let raw = session.read(info)?.raw.unwrap_or(0);
                return Ok(state.shows_running(raw));
            }
        }
    }
    for id in behaviour.status.registers {
        let Some(info) = session.drive.register(id) else {
            continue;
        };
        if !session.can_read(info) {
            continue;
        }
        let raw = session.read(info)?.raw.unwrap_or(0);
        return Ok(behaviour
            .status
            .running
            .iter()
            .any(|bit| bit.is_active(raw)));
    }
    Ok(false)
}

/// Clears the run bit of the command word and waits (at most a minute) for the status word
/// to say the motor stopped.
fn stop_drive(session: &mut Session) -> Result<(), Failure> {
    let behaviour = session
        .drive
        .behaviour
        .ok_or_else(|| Failure::new("the description does not say how to stop this drive"))?;
    let command = session
        .drive
        .register(behaviour.command.register)
        .ok_or_else(|| Failure::new("the description names no command word"))?;
    let word = if session.can_read(command) {
        session.read(command)?.raw.unwrap_or(0)
    } else {
        behaviour
            .command
            .require
            .iter()
            .fold(0, |word, bit| bit.apply(word, true))
    };
    let stop = behaviour.command.stop_word(word);
    session.write(command, stop, false)?;
    say!(
        "stopping: wrote {} {} = {}",
        command.code,
        command.name,
        values::short(command, stop)
    );
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while is_running(session)? {
        if std::time::Instant::now() > deadline {
            return Err(Failure::new(
                "the drive still runs a minute after the stop command; nothing restored",
            )
            .hint("stop it at the panel and restore again"));
        }
        std::thread::sleep(std::time::Duration::from_millis(200));
    }
    say!("the drive has stopped");
    Ok(())
}
