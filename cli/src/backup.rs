//! `vfd backup` and `vfd restore`: every readable parameter into a YAML (or JSON) file that
//! people can read and edit (values in units, codes with their meaning), and back: only
//! writable values that differ from the drive's, after checking every entry, in RAM unless
//! `--persist`.

use crate::bus::{LineArgs, Session, Value};
use crate::out::say;
use crate::{lookup, values, Failure};
use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};
use std::path::Path;
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
pub fn backup(line: &LineArgs, to: &Path) -> Result<(), Failure> {
    let mut session = Session::open(line)?;
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
    for (info, result) in registers.iter().zip(read) {
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
            Err(error) => failed.push(format!("{}: {}", info.code, error_line(&error))),
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
            drive.id,
            serde_yaml::to_string(&backup).map_err(|e| Failure::new(e.to_string()))?
        )
    };
    std::fs::write(to, text)
        .map_err(|e| Failure::new(format!("cannot write {}: {e}", to.display())))?;
    say!(
        "saved {} parameters of {} to {} ({} read request(s))",
        backup.parameters.len(),
        drive.id,
        to.display(),
        session.requests
    );
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
pub fn restore(line: &LineArgs, from: &Path, dry_run: bool, persist: bool) -> Result<(), Failure> {
    let text = std::fs::read_to_string(from)
        .map_err(|e| Failure::new(format!("cannot read {}: {e}", from.display())))?;
    let backup: Backup = if from
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        serde_json::from_str(&text).map_err(|e| Failure::new(format!("{}: {e}", from.display())))?
    } else {
        serde_yaml::from_str(&text).map_err(|e| Failure::new(format!("{}: {e}", from.display())))?
    };
    let drive = lookup::drive(&line.drive)?;
    if !backup.drive.eq_ignore_ascii_case(drive.id) {
        return Err(Failure::new(format!(
            "{} is a backup of a {} ({}), not of a {}: nothing written",
            from.display(),
            backup.model,
            backup.drive,
            drive.id
        ))
        .hint("restore a backup onto the model it was taken from"));
    }
    // Every entry is checked before anything is sent.
    let mut refused = Vec::new();
    let mut wanted = Vec::new();
    for entry in &backup.parameters {
        let info = match lookup::register(drive, &entry.code) {
            Ok(info) => info,
            Err(failure) => {
                refused.push(format!("{}: {}", entry.code, failure.message));
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
    let mut session = Session::open(line)?;
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
    for (info, now, raw) in &writes {
        say!(
            "{} {:<7} {}: {} -> {}",
            if dry_run { "would write" } else { "write" },
            info.code,
            info.name,
            values::short(info, *now),
            values::short(info, *raw)
        );
    }
    if dry_run {
        say!(
            "dry run: {} to write ({target}), {same} unchanged, {read_only} read-only kept for reference; nothing written",
            writes.len()
        );
        return Ok(());
    }
    let bar = progress(writes.len(), "writing");
    let mut failed = Vec::new();
    for (info, _, raw) in &writes {
        bar.inc(1);
        if let Err(failure) = session.write(info, *raw, persist) {
            failed.push(format!("{}: {}", info.code, failure.message));
        }
    }
    bar.finish_and_clear();
    say!(
        "restored {} value(s) to {target}, {same} unchanged, {read_only} read-only kept for reference",
        writes.len() - failed.len()
    );
    if failed.is_empty() {
        Ok(())
    } else {
        for line in &failed {
            say!("failed: {line}");
        }
        Err(Failure::new(format!("{} write(s) failed", failed.len())))
    }
}
