//! `vfd read`, `vfd write` and `vfd watch`: registers by name, values in engineering units,
//! bit-field words field by field, code tables with their meaning, and the drive's trip.

use crate::commands::poll::{self, Poll};
use crate::emit::{Emitter, Format};
use crate::line_args::LineArgs;
use crate::out::say;
use crate::Failure;
use std::sync::atomic::AtomicBool;
use std::time::Duration;
use vfd_bus::record::ValueRecord;
use vfd_bus::session::{Session, Value};
use vfd_bus::trip_flag::trip_flag;
use vfd_bus::values;
use vfd_bus::write_value::checked_value;
use vfd_bus::Catalogue;
use vfd_runtime::RegisterInfo;

/// Reads each register and prints it, in `format`.
pub fn read(
    catalogue: &Catalogue,
    line: &LineArgs,
    command: Option<&str>,
    names: &[String],
    format: Format,
) -> Result<(), Failure> {
    let mut session = crate::open_session::open_session(line, catalogue)?;
    session.command = command.map(command_code).transpose()?;
    let registers = resolve(catalogue, &session, names)?;
    let mut read = Vec::new();
    for info in &registers {
        let value = session.read(info)?;
        // A register whose scale another register chooses is shown in that scale: the one
        // the reply's decimals give (the Eaton unit digit), else the selector's.
        let shown = match value.decimals.and_then(|d| info.scaled_for_decimals(d)) {
            Some(chosen) => chosen,
            None => session.scaled(info)?,
        };
        read.push((shown, value));
    }
    let values: Vec<Result<Value, ()>> = read.iter().map(|(_, v)| Ok(v.clone())).collect();
    let tripped = trip_flag(&session, &registers, &values);
    if !format.is_text() {
        let mut emitter = Emitter::new(format);
        for (info, value) in &read {
            let mut record =
                ValueRecord::new(session.drive.id, info, value.raw, value.text.clone()).now();
            record.tripped = tripped;
            emitter.record(&record);
        }
        emitter.finish();
        return Ok(());
    }
    let mut any_tripped = false;
    for (info, value) in &read {
        any_tripped |= value.tripped;
        print_value(info, value);
    }
    if any_tripped {
        show_trip(&mut session);
    }
    Ok(())
}

/// The registers `names` name for reading, in order.
pub fn resolve(
    catalogue: &Catalogue,
    session: &Session,
    names: &[String],
) -> Result<Vec<&'static RegisterInfo>, Failure> {
    names
        .iter()
        .map(|name| {
            catalogue
                .register_for(session.drive, name, false)
                .map(|info| session.on_port(info))
                .map_err(Failure::from)
        })
        .collect()
}

/// One register's value: a line, and the fields of a bit-field word under it.
pub fn print_value(info: &'static RegisterInfo, value: &Value) {
    let shown = match (&value.text, value.raw) {
        (Some(text), _) => format!("{text:?}"),
        (None, Some(raw)) => values::short(info, raw),
        (None, None) => "(no data)".to_owned(),
    };
    // The Chinese name in brackets, where the manual gives one.
    let zh = if info.name_zh.is_empty() {
        String::new()
    } else {
        format!(" ({})", info.name_zh)
    };
    say!(
        "{:<7} {}{zh} = {shown}{}",
        info.code,
        info.name,
        if value.tripped {
            "  [drive tripped]"
        } else {
            ""
        }
    );
    if let (Some(bits), Some(raw)) = (info.bits, value.raw) {
        for line in values::field_lines(bits, raw as u16) {
            say!("          {line}");
        }
    }
}

/// Says the drive is tripped and shows its trip code, where the description says which
/// register holds it.
pub fn show_trip(session: &mut Session) {
    let codes = session
        .drive
        .behaviour
        .map(|b| b.trip.code)
        .unwrap_or_default();
    let mut shown = false;
    for id in codes {
        if let Some(info) = session.drive.register(id) {
            if let Ok(Value { raw: Some(raw), .. }) = session.read(info) {
                say!("TRIPPED: {} = {}", info.code, values::short(info, raw));
                shown = true;
            }
        }
    }
    if !shown {
        say!("TRIPPED: the drive reports a trip");
    }
}

/// Writes one value, refused before anything is sent when out of range.
pub fn write(
    catalogue: &Catalogue,
    line: &LineArgs,
    command: Option<&str>,
    name: &str,
    text: &str,
    persist: bool,
) -> Result<(), Failure> {
    let drive = catalogue.drive(&line.drive)?;
    let info = catalogue.register_for(drive, name, true)?;
    let info = match vfd_bus::lookup::port(drive, line.port_kind.as_deref())? {
        Some(port) => port.register(info),
        None => info,
    };
    vfd_bus::write_check::writable(info, persist)?;
    let code = command.map(command_code).transpose()?;
    let mut session = crate::open_session::open_session(line, catalogue)?;
    session.command = code;
    let percent_of = session.named_command().and_then(|c| c.percent_of.clone());
    let (info, raw) = checked_value(&mut session, info, text)?;
    let (echo, tripped) = session.write(info, raw, persist)?;
    let target = vfd_bus::storage::target(info, persist);
    let echo = match echo {
        Some(echo) if echo != raw => format!("; the drive reports {}", values::short(info, echo)),
        Some(_) => "; the drive confirms it".to_owned(),
        None if info.no_reply || session.named_command().is_some_and(|c| c.no_reply) => {
            "; sent (the drive never answers it)".to_owned()
        }
        None => String::new(),
    };
    let shown = match &percent_of {
        Some(percent_of) => format!(
            "{:.2} % of {} ({raw:04X}h)",
            percent_of.from_raw(raw, 100.0),
            percent_of.register
        ),
        None => values::short(info, raw),
    };
    say!(
        "wrote {} {} = {shown} ({target}){echo}",
        info.code,
        info.name
    );
    if let Some(note) = session.selector_note(info).filter(|_| !persist) {
        say!("{note}");
    }
    if tripped {
        show_trip(&mut session);
    }
    Ok(())
}

/// A command code as given on the command line: one letter (`G`, `s`) or a number
/// (`0x03`, `3`).
pub fn command_code(text: &str) -> Result<u32, Failure> {
    let number = match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u32::from_str_radix(hex, 16).ok(),
        None => text.parse::<u32>().ok(),
    };
    match (number, text.as_bytes()) {
        (Some(number), _) => Ok(number),
        (None, [letter]) if letter.is_ascii_alphabetic() => Ok(u32::from(*letter)),
        _ => Err(
            Failure::new(format!("`{text}` is not a command code")).hint(
                "give one letter (G, S, s) or a number (0x03); the drive page lists the commands",
            ),
        ),
    }
}

/// `vfd write --broadcast`: one write to every station (or a group), where the drive's
/// description allows it; waits for the station `reply_from` names, else returns once the
/// frame is on the line. Nothing is sent when the value, the register or the broadcast is
/// refused.
pub fn broadcast_write(
    catalogue: &Catalogue,
    line: &LineArgs,
    name: &str,
    text: &str,
    persist: bool,
    stations: &str,
    reply_from: Option<u8>,
) -> Result<(), Failure> {
    let drive = catalogue.drive(&line.drive)?;
    let info = catalogue.register_for(drive, name, true)?;
    vfd_bus::write_check::writable(info, persist)?;
    let to: vfd_runtime::Broadcast = stations
        .parse()
        .map_err(|e: vfd_runtime::broadcast::GroupParseError| Failure::new(e.to_string()))?;
    let raw = vfd_bus::write_check::in_range(info, text, &catalogue.name_for(drive))?;
    let mut session = crate::open_session::open_session(line, catalogue)?;
    let (echo, responder) = session.broadcast_write(info, raw, persist, to, reply_from)?;
    let target = vfd_bus::storage::target(info, persist);
    let answered = match (reply_from, echo) {
        (Some(station), Some(echo)) if echo != raw => {
            format!("; station {station} reports {}", values::short(info, echo))
        }
        (Some(station), _) => format!("; station {station} confirms it"),
        (None, _) => match responder {
            Some(station) => format!(
                "; no answer awaited (station {station} would answer where it exists: --reply-from {station})"
            ),
            None => "; no station answers a broadcast".to_owned(),
        },
    };
    say!(
        "broadcast {} {} = {} to {} ({target}){answered}",
        info.code,
        info.name,
        values::short(info, raw),
        match to {
            vfd_runtime::Broadcast::All => "every station".to_owned(),
            vfd_runtime::Broadcast::Group(group) => format!("the stations {group}"),
        }
    );
    Ok(())
}

/// Polls the registers and shows them until Ctrl-C (or `count` samples), in `format`;
/// reopens the port after an I/O error (see [`crate::commands::poll`]).
pub fn watch(
    catalogue: &Catalogue,
    line: &LineArgs,
    names: &[String],
    interval: u64,
    count: Option<u64>,
    format: Format,
) -> Result<(), Failure> {
    let mut session = crate::open_session::open_session(line, catalogue)?;
    // Registers whose scale another register chooses are shown in the scale it chooses
    // when the watch starts (unscaled when that register cannot be read now).
    let registers = resolve(catalogue, &session, names)?
        .into_iter()
        .map(|info| match session.scaled(info) {
            Ok(scaled) => scaled,
            Err(failure) => {
                eprintln!(
                    "vfd: {}; {} is shown unscaled",
                    failure.message(),
                    info.code
                );
                info
            }
        })
        .collect::<Vec<_>>();
    let stop = crate::stop_flag::stop_flag()?;
    poll::run(
        &mut session,
        &Poll {
            registers: &registers,
            interval: Duration::from_millis(interval),
            count,
            stop: &stop,
            deadline: None,
            format,
            reopen: Some((line, catalogue)),
        },
    )
}

/// The demo's watch: text, until `deadline`, never reopening the line.
#[cfg(feature = "pty")]
pub fn watch_loop(
    session: &mut Session,
    registers: &[&'static RegisterInfo],
    interval: Duration,
    count: Option<u64>,
    stop: &AtomicBool,
    deadline: Option<std::time::Instant>,
) -> Result<(), Failure> {
    poll::run(
        session,
        &Poll {
            registers,
            interval,
            count,
            stop,
            deadline,
            format: Format::Text,
            reopen: None,
        },
    )
}
