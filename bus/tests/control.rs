//! One scenario for every drive with control roles, on every protocol it speaks, against
//! its virtual drive: run forward, at speed, reverse, a new speed, stop, a trip shown with
//! its code and refusing a run, reset. The same code for every drive: nothing here knows a
//! command word.

use std::time::Duration;
use vfd_bus::control::{Control, ControlError, Direction, Roles};
use vfd_bus::{Catalogue, Line, Session};
use vfd_runtime::units::raw_to_scaled;
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{DriveInfo, Protocol};

/// The speed `share` of the way up the speed command's range, in its unit, as text.
fn speed(drive: &DriveInfo, roles: &Roles, share: f64) -> String {
    let info = roles.speed;
    let top = raw_to_scaled(u32::try_from(info.raw_max).unwrap_or(u32::MAX), info).min(
        // A span the model ramps over (the maximum frequency), where it is smaller.
        drive
            .behaviour
            .and_then(|b| match b.frequency.span {
                vfd_runtime::behaviour::Amount::Value(v) => Some(v),
                vfd_runtime::behaviour::Amount::Register(_) => None,
            })
            .unwrap_or(f64::MAX),
    );
    let top = top.min(50.0);
    format!("{:.1}", top * share)
}

/// The protocols of `drive` the scenario runs on: those that can write the command and
/// speed registers.
fn protocols(drive: &'static DriveInfo, roles: &Roles) -> Vec<&'static Protocol> {
    drive
        .protocols
        .iter()
        .copied()
        .filter(|p| {
            [roles.command, roles.speed].iter().all(|info| {
                let writes = vfd_bus::storage::writes(p, info);
                writes.ram || writes.persistent
            })
        })
        .collect()
}

fn session(sim: &Simulator, drive: &'static DriveInfo, protocol: &'static Protocol) -> Session {
    let address = protocol.default_address();
    if let Some(address) = address {
        sim.lock().set_address(address);
    }
    Session::over(
        drive,
        protocol,
        Line::Other(Box::new(sim.link(protocol))),
        address,
    )
}

fn scenario(drive: &'static DriveInfo, protocol: &'static Protocol) -> Result<(), String> {
    let at = |what: &str| format!("{} over {}: {what}", drive.id, protocol.id);
    let sim = Simulator::new(drive);
    let mut session = session(&sim, drive, protocol);
    let mut control = Control::new(&mut session).map_err(|e| e.to_string())?;
    let roles = *control.roles();
    let thirty = speed(drive, &roles, 0.6);
    let ramp = Duration::from_secs(120);

    control
        .run(Direction::Forward, &thirty)
        .map_err(|e| at(&format!("run forward at {thirty}: {e}")))?;
    sim.advance(ramp);
    let state = control.state().map_err(|e| at(&e.to_string()))?;
    let wanted: f64 = thirty.parse().unwrap();
    if !state.running || !state.at_speed {
        return Err(at(&format!("after run at {thirty}: {state:?}")));
    }
    if let Some(out) = state.output {
        if (out - wanted).abs() > 0.6 {
            return Err(at(&format!("output {out} after run at {thirty}")));
        }
    }
    if state.direction == Some(Direction::Reverse) {
        return Err(at("runs in reverse after run forward"));
    }

    if roles.can_reverse() {
        control
            .run(Direction::Reverse, &thirty)
            .map_err(|e| at(&format!("run reverse: {e}")))?;
        sim.advance(ramp);
        let state = control.state().map_err(|e| at(&e.to_string()))?;
        if !state.running || state.direction == Some(Direction::Forward) {
            return Err(at(&format!("after run reverse: {state:?}")));
        }
    }

    let faster = speed(drive, &roles, 0.9);
    control
        .set_speed(&faster)
        .map_err(|e| at(&format!("set speed {faster}: {e}")))?;
    sim.advance(ramp);
    let state = control.state().map_err(|e| at(&e.to_string()))?;
    let wanted: f64 = faster.parse().unwrap();
    if let Some(out) = state.output {
        if (out.abs() - wanted).abs() > 0.6 {
            return Err(at(&format!("output {out} after set speed {faster}")));
        }
    }

    control.stop().map_err(|e| at(&format!("stop: {e}")))?;
    sim.advance(ramp);
    let state = control.state().map_err(|e| at(&e.to_string()))?;
    if state.running {
        return Err(at(&format!("still running after stop: {state:?}")));
    }

    if !roles.shows_trips() {
        return Ok(());
    }
    let code = roles
        .trip_code
        .and_then(|info| info.codes)
        .and_then(|codes| codes.values.iter().find(|c| c.value != 0))
        .map_or(1, |c| c.value);
    sim.inject_trip(code);
    let state = control.state().map_err(|e| at(&e.to_string()))?;
    if !state.tripped {
        return Err(at(&format!("trip {code} not shown: {state:?}")));
    }
    if roles.trip_code.is_some() && state.trip.as_ref().map(|t| t.code) != Some(u32::from(code)) {
        return Err(at(&format!("trip code: {:?}, injected {code}", state.trip)));
    }
    match control.run(Direction::Forward, &thirty) {
        Err(ControlError::Tripped(_)) => {}
        other => return Err(at(&format!("run while tripped: {other:?}"))),
    }
    if roles.can_reset() {
        control.reset().map_err(|e| at(&format!("reset: {e}")))?;
        sim.advance(Duration::from_secs(1));
        let state = control.state().map_err(|e| at(&e.to_string()))?;
        if state.tripped {
            return Err(at(&format!("still tripped after reset: {state:?}")));
        }
    }
    Ok(())
}

#[test]
fn every_drive_with_roles_runs_reverses_stops_trips_and_resets_on_every_protocol() {
    let catalogue = Catalogue::new();
    let mut failures = Vec::new();
    let mut ran = Vec::new();
    for &drive in catalogue.builtin() {
        let Ok(roles) = Roles::of(drive) else {
            continue;
        };
        for protocol in protocols(drive, &roles) {
            ran.push(format!("{}/{}", drive.id, protocol.id));
            if let Err(failure) = scenario(drive, protocol) {
                failures.push(failure);
            }
        }
    }
    assert!(
        failures.is_empty(),
        "ran {}:\n{}",
        ran.join(", "),
        failures.join("\n")
    );
    assert!(ran.len() >= 10, "only {ran:?}");
}
