//! `vfd demo`: the whole product against the virtual drive, no hardware needed. The
//! virtual drive answers on a pseudo-terminal served by a thread of this process; the demo
//! opens that terminal as any port, lists the drives, shows a register, writes a frequency,
//! runs the motor, watches the output climb with the status bits, stops, injects a trip and
//! shows it with the trip history, and resets, printing the command behind each step and
//! every frame exchanged (hex and decoded). Everything it uses comes from the drive's
//! description (its `behaviour:` section says which registers and bits do what).

use crate::commands::{describe, watch};
use crate::out::say;
use crate::traced_line::Traced;
use crate::Failure;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use vfd_bus::session::{Session, Value};
use vfd_bus::values;
use vfd_bus::Catalogue;
use vfd_bus::Line;
use vfd_runtime::behaviour::{Amount, Behaviour};
use vfd_runtime::transport::{PseudoTerminal, PtyTransport};
use vfd_runtime::virtual_drive::{serve, Simulator};
use vfd_runtime::{DriveInfo, RegisterInfo};

fn step(text: &str) {
    say!("");
    say!("$ {text}");
}

/// Runs the demo.
pub fn run(catalogue: &Catalogue, drive: Option<&str>, seconds: u64) -> Result<(), Failure> {
    let drive: &'static DriveInfo = match drive {
        Some(id) => catalogue.drive(id)?,
        // The fullest tour: a drive whose model has status bits and a reset, else any
        // drive with a model.
        None => {
            let full = |d: &&'static DriveInfo| {
                d.behaviour.is_some_and(|b| {
                    !b.status.registers.is_empty()
                        && (b.command.reset.is_some() || b.command.reset_by_write.is_some())
                })
            };
            let drives = catalogue.builtin().iter().copied();
            drives
                .clone()
                .find(full)
                .or_else(|| drives.clone().find(|d| d.behaviour.is_some()))
                .ok_or_else(|| {
                    Failure::new("no described drive has a behaviour model to simulate")
                })?
        }
    };
    let behaviour: &'static Behaviour = drive.behaviour.ok_or_else(|| {
        Failure::new(format!(
            "drive {} has no behaviour model to simulate",
            drive.id
        ))
        .hint("choose another with --drive (`vfd list` marks them \"virtual drive\")")
    })?;
    let protocol = demo_protocol(drive, behaviour)?;
    let sim = Simulator::new(drive);
    let station = protocol.address_range.0.max(1);
    sim.lock().set_address(station);
    let address = protocol.default_address();
    // The virtual drive answers on a pseudo-terminal, as `vfd sim` does, served by a
    // thread of this process (its motor follows the wall clock there).
    let pty = PseudoTerminal::open()
        .map_err(|e| Failure::new(format!("cannot open a pseudo-terminal: {e}")))?;
    let port = pty.slave_path().display().to_string();
    let mut served = pty
        .master()
        .map_err(|e| Failure::new(format!("cannot use the pseudo-terminal: {e}")))?;
    let stop = Arc::new(AtomicBool::new(false));
    let server = {
        let (sim, stop) = (sim.clone(), stop.clone());
        let settings = drive.serial.default_for(&protocol.id);
        std::thread::spawn(move || serve(&sim, protocol, &mut served, settings, &stop))
    };
    let line = PtyTransport::open_path(std::path::Path::new(&port))
        .map_err(|e| Failure::new(format!("cannot open {port}: {e}")))?;
    let mut session = Session::over(
        drive,
        protocol,
        Traced::line(Line::Pty(line), drive, protocol),
        address,
    );
    let result = tour(
        catalogue,
        drive,
        behaviour,
        &sim,
        &mut session,
        seconds,
        &port,
    );
    stop.store(true, Ordering::SeqCst);
    match server.join() {
        Ok(Err(e)) if result.is_ok() => {
            return Err(Failure::new(format!("the virtual drive stopped: {e}")))
        }
        _ => {}
    }
    result
}

/// The first protocol that can write both the command word and the frequency command.
fn demo_protocol(
    drive: &'static DriveInfo,
    behaviour: &Behaviour,
) -> Result<&'static vfd_runtime::Protocol, Failure> {
    let command = register(drive, behaviour.command.register)?;
    let frequency = register(drive, behaviour.frequency.command)?;
    drive
        .protocols
        .iter()
        .copied()
        .find(|p| {
            [command, frequency].iter().all(|r| {
                p.command_for(vfd_runtime::CommandKind::WriteRam, r.space, r.data_type)
                    .is_some()
            })
        })
        .ok_or_else(|| {
            Failure::new(format!(
                "no protocol of {} writes both {} and {}",
                drive.id, command.code, frequency.code
            ))
        })
}

fn register(drive: &DriveInfo, id: &str) -> Result<&'static RegisterInfo, Failure> {
    drive.register(id).ok_or_else(|| {
        Failure::new(format!(
            "{}: the behaviour names `{id}`, which is not a register",
            drive.id
        ))
    })
}

fn tour(
    catalogue: &Catalogue,
    drive: &'static DriveInfo,
    behaviour: &'static Behaviour,
    sim: &Simulator,
    session: &mut Session,
    seconds: u64,
    port: &str,
) -> Result<(), Failure> {
    let line = format!(
        "--drive {} --protocol {} --port {port}",
        drive.id, session.protocol.id
    );
    say!(
        "vfd demo: a virtual {} {} ({}), generated from its YAML description, answering {} on the pseudo-terminal {port}.",
        drive.vendor, drive.model, drive.id, session.protocol.name
    );
    say!("Each frame is shown as it goes: -> request, <- reply, in hex with what it says. Against a real drive, give --port /dev/ttyUSB0; `vfd sim` serves the same virtual drive on its own.");

    step("vfd list");
    describe::list(catalogue, crate::emit::Format::Text)?;

    let frequency = register(drive, behaviour.frequency.command)?;
    step(&format!("vfd info {} {}", drive.id, frequency.code));
    describe::info(
        catalogue,
        drive.id,
        &[frequency.code.to_owned()],
        crate::emit::Format::Text,
    )?;

    if let Amount::Register(id) = behaviour.frequency.acceleration {
        let acc = register(drive, id)?;
        if let Ok(raw) = values::parse(acc, "3") {
            step(&format!(
                "vfd write {line} {} 3   # a quicker ramp for the demo",
                acc.code
            ));
            write(session, acc, raw)?;
        }
    }
    let target = target_frequency(drive, behaviour, frequency);
    let raw = values::parse(frequency, &target).map_err(Failure::new)?;
    step(&format!("vfd write {line} {} {target}", frequency.code));
    write(session, frequency, raw)?;

    let command = register(drive, behaviour.command.register)?;
    let enabled = behaviour
        .command
        .require
        .iter()
        .chain(behaviour.frequency.require)
        .fold(0u32, |word, bit| bit.apply(word, true));
    // A coast stop must not act (on drives where it is active low, its bit is set).
    let enabled = behaviour
        .command
        .coast
        .map_or(enabled, |coast| coast.apply(enabled, false));
    let run_word = behaviour.command.run_word(enabled);
    let stop_word = behaviour.command.stop_word(enabled);
    step(&format!(
        "vfd write {line} {} {}   # run",
        command.code,
        word_text(command, run_word)
    ));
    write(session, command, run_word)?;

    let mut watched: Vec<&'static RegisterInfo> = Vec::new();
    if let Some(output) = behaviour.frequency.output.first() {
        watched.push(register(drive, output)?);
    }
    if let Some(current) = behaviour.current.as_ref().and_then(|c| c.registers.first()) {
        watched.push(register(drive, current)?);
    }
    if let Some(status) = behaviour.status.registers.first() {
        watched.push(register(drive, status)?);
    }
    let codes: Vec<&str> = watched.iter().map(|r| r.code).collect();
    step(&format!(
        "vfd watch {line} {}   # Ctrl-C stops; here {seconds} s",
        codes.join(" ")
    ));
    let never = AtomicBool::new(false);
    watch::watch_loop(
        session,
        &watched,
        Duration::from_millis(500),
        None,
        &never,
        Some(Instant::now() + Duration::from_secs(seconds)),
    )?;

    step(&format!(
        "vfd write {line} {} {}   # stop",
        command.code,
        word_text(command, stop_word)
    ));
    write(session, command, stop_word)?;

    let trip_register = behaviour
        .trip
        .code
        .first()
        .and_then(|id| drive.register(id));
    let trip_code = trip_register
        .and_then(|r| r.codes)
        .and_then(|c| c.values.first())
        .map_or(1, |c| c.value);
    step(&format!(
        "# the virtual drive trips (code {trip_code}), as `vfd sim --trip {trip_code}` would"
    ));
    sim.inject_trip(trip_code);
    let mut shown: Vec<&'static RegisterInfo> = Vec::new();
    if let Some(r) = trip_register {
        shown.push(r);
    }
    if let Some(status) = behaviour.status.registers.first() {
        shown.push(register(drive, status)?);
    }
    if !shown.is_empty() {
        let codes: Vec<&str> = shown.iter().map(|r| r.code).collect();
        step(&format!("vfd read {line} {}", codes.join(" ")));
        read(session, behaviour, &shown)?;
    }

    let mut history: Vec<&'static RegisterInfo> = behaviour
        .trip
        .history
        .iter()
        .filter_map(|slot| drive.register(slot.register))
        .filter(|r| session.can_read(r))
        .collect();
    // Slots that are fields of one register read it once.
    history.dedup_by_key(|r| r.id);
    if !history.is_empty() {
        let codes: Vec<&str> = history.iter().map(|r| r.code).collect();
        step(&format!(
            "vfd read {line} {}   # trip history",
            codes.join(" ")
        ));
        read(session, behaviour, &history)?;
    }

    if let Some(reset) = behaviour.command.reset {
        let reset_word = reset.apply(stop_word, true);
        step(&format!(
            "vfd write {line} {} {}   # fault reset",
            command.code,
            word_text(command, reset_word)
        ));
        write(session, command, reset_word)?;
        write(session, command, stop_word)?;
        if !shown.is_empty() {
            let codes: Vec<&str> = shown.iter().map(|r| r.code).collect();
            step(&format!("vfd read {line} {}", codes.join(" ")));
            read(session, behaviour, &shown)?;
        }
    }
    if let Some(reset) = behaviour.command.reset_by_write {
        let target = register(drive, reset.register)?;
        // The value by its code's name where the register has a code table.
        let value = target
            .codes
            .and_then(|codes| codes.find(reset.value as u16))
            .map_or_else(
                || format!("0x{:04X}", reset.value),
                |code| code.id.to_owned(),
            );
        step(&format!(
            "vfd write {line} {} {value}   # reset (never answered)",
            target.code
        ));
        write(session, target, reset.value)?;
        if !shown.is_empty() {
            let codes: Vec<&str> = shown.iter().map(|r| r.code).collect();
            step(&format!("vfd read {line} {}", codes.join(" ")));
            read(session, behaviour, &shown)?;
        }
    }
    say!("");
    say!("Done. Next: `vfd info {}` for every register, `vfd decode --help` for captured frames, `vfd sim --help` for a virtual drive on a pseudo-terminal.", drive.id);
    Ok(())
}

/// Three quarters of the frequency command's upper bound (or of the register its
/// maximum names), rounded to whole units.
fn target_frequency(drive: &DriveInfo, behaviour: &Behaviour, frequency: &RegisterInfo) -> String {
    let span = match behaviour.frequency.span {
        Amount::Value(v) => v,
        Amount::Register(id) => drive
            .register(id)
            .and_then(|r| {
                r.default_raw
                    .map(|raw| vfd_runtime::units::raw_to_scaled(raw, r))
            })
            .unwrap_or(frequency.raw_max as f64 * frequency.scale),
    };
    let max = (frequency.raw_max as f64 * frequency.scale).min(span);
    let target = (max * 0.75).round().max(1.0);
    format!("{target}{}", frequency.unit_symbol())
}

/// A word as field names (bit-field registers) or hex.
fn word_text(info: &RegisterInfo, raw: u32) -> String {
    match info.bits {
        // A word with no field set (a stop) is written as its raw word, which `vfd write`
        // takes as it stands: the printed line must run when pasted.
        Some(bits) if raw != 0 => values::set_fields(bits, raw as u16).join(","),
        _ => values::hex(info, raw),
    }
}

fn write(session: &mut Session, info: &'static RegisterInfo, raw: u32) -> Result<(), Failure> {
    let (_, tripped) = session.write(info, raw, false)?;
    let how = if info.no_reply {
        "sent; the drive never answers it"
    } else {
        "RAM"
    };
    say!(
        "wrote {} {} = {} ({how})",
        info.code,
        info.name,
        values::short(info, raw)
    );
    if tripped {
        watch::show_trip(session);
    }
    Ok(())
}

fn read(
    session: &mut Session,
    behaviour: &Behaviour,
    registers: &[&'static RegisterInfo],
) -> Result<(), Failure> {
    let mut tripped = false;
    for info in registers {
        let value: Value = session.read(info)?;
        tripped |= value.tripped;
        watch::print_value(info, &value);
        // Drives whose replies carry no trip flag show it in their status word.
        if let Some(raw) = value.raw {
            let status = behaviour.status.registers.contains(&info.id);
            if status
                && behaviour
                    .status
                    .tripped
                    .iter()
                    .any(|bit| bit.is_active(raw))
            {
                say!("TRIPPED: {} says so", info.code);
            }
        }
    }
    if tripped {
        watch::show_trip(session);
    }
    Ok(())
}
