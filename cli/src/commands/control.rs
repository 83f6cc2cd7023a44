//! `vfd run`, `vfd stop`, `vfd reset` and `vfd state`: the control profile
//! ([`vfd_bus::control`]) for any drive whose description has control roles, by id or by
//! path. A drive without them gets one line naming the roles it lacks.

use crate::emit::{Emitter, Format};
use crate::line_args::LineArgs;
use crate::out::say;
use crate::Failure;
use std::time::Duration;
use vfd_bus::control::{Control, ControlError, Direction, DriveState, Roles};
use vfd_bus::{Catalogue, Session};

impl From<ControlError> for Failure {
    fn from(error: ControlError) -> Failure {
        let failure = Failure::new(error.message());
        match error.hint() {
            Some(hint) => failure.hint(hint),
            None => failure,
        }
    }
}

/// The session the options name, with the drive's roles checked first (nothing is opened
/// for a drive without them).
fn open(catalogue: &Catalogue, line: &LineArgs) -> Result<Session, Failure> {
    let drive = catalogue.drive(&line.drive)?;
    Roles::of(drive).map_err(|missing| {
        Failure::new(missing.to_string()).hint(format!(
            "`vfd read` and `vfd write` still reach its registers (`vfd info {}` lists them)",
            line.drive
        ))
    })?;
    crate::open_session::open_session(line, catalogue)
}

fn control(session: &mut Session) -> Result<Control<'_>, Failure> {
    Control::new(session).map_err(|missing| Failure::new(missing.to_string()))
}

/// `vfd run SPEED [--reverse]`.
pub fn run(
    catalogue: &Catalogue,
    line: &LineArgs,
    speed: &str,
    reverse: bool,
) -> Result<(), Failure> {
    let mut session = open(catalogue, line)?;
    let mut control = control(&mut session)?;
    let direction = if reverse {
        Direction::Reverse
    } else {
        Direction::Forward
    };
    control.run(direction, speed)?;
    say!(
        "{}: running {} at {speed} ({} write(s))",
        line.drive,
        match direction {
            Direction::Forward => "forward",
            Direction::Reverse => "in reverse",
        },
        control.writes
    );
    Ok(())
}

/// `vfd stop [--coast]`.
pub fn stop(catalogue: &Catalogue, line: &LineArgs, coast: bool) -> Result<(), Failure> {
    let mut session = open(catalogue, line)?;
    let mut control = control(&mut session)?;
    if coast {
        control.coast()?;
        say!("{}: coasting to a stop", line.drive);
    } else {
        control.stop()?;
        say!("{}: stopping", line.drive);
    }
    Ok(())
}

/// `vfd reset`.
pub fn reset(catalogue: &Catalogue, line: &LineArgs) -> Result<(), Failure> {
    let mut session = open(catalogue, line)?;
    let mut control = control(&mut session)?;
    control.reset()?;
    say!("{}: trip reset sent", line.drive);
    Ok(())
}

/// `vfd state [--watch SECONDS] [--count N]`: with `--watch`, a failed read is reported and
/// tried again; the command fails only when no state was ever read.
pub fn state(
    catalogue: &Catalogue,
    line: &LineArgs,
    format: Format,
    watch: Option<f64>,
    count: Option<u64>,
) -> Result<(), Failure> {
    if format == Format::Csv {
        return Err(Failure::new("`vfd state` prints text, json or jsonl")
            .hint("a state has a nested trip: use --format jsonl for one object per line"));
    }
    let interval = match watch {
        Some(seconds) if !seconds.is_finite() || seconds <= 0.0 || seconds > 86_400.0 => {
            return Err(Failure::new(format!(
                "--watch {seconds}: the interval must be a number of seconds above 0 and at most 86400"
            ))
            .hint("e.g. --watch 1 (every second) or --watch 0.2"));
        }
        Some(seconds) => Some(Duration::from_secs_f64(seconds.max(0.05))),
        None => None,
    };
    let mut session = open(catalogue, line)?;
    let mut control = control(&mut session)?;
    let mut emitter = Emitter::new(format);
    let (mut tries, mut shown) = (0u64, 0u64);
    let mut last_error = None;
    loop {
        tries += 1;
        match control.state() {
            Ok(state) => {
                shown += 1;
                if format.is_text() {
                    say!("{}", text(&state));
                } else {
                    emitter.record(&state);
                }
            }
            // A watch outlives a failed read (a timeout, a damaged reply): it says so and
            // tries again at the next interval.
            Err(error) if interval.is_some() => {
                eprintln!("vfd: {}", error.message());
                last_error = Some(error);
            }
            Err(error) => return Err(error.into()),
        }
        let (Some(interval), true) = (interval, count.is_none_or(|n| tries < n)) else {
            break;
        };
        std::thread::sleep(interval);
    }
    emitter.finish();
    match (shown, last_error) {
        (0, Some(error)) => Err(error.into()),
        _ => Ok(()),
    }
}

/// A state on one line.
fn text(state: &DriveState) -> String {
    let number = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{v:.2}"));
    let mut parts = vec![if state.tripped {
        "TRIPPED".to_owned()
    } else if state.running {
        match state.direction {
            Some(Direction::Reverse) => "running in reverse".to_owned(),
            Some(Direction::Forward) => "running forward".to_owned(),
            None => "running".to_owned(),
        }
    } else {
        "stopped".to_owned()
    }];
    parts.push(format!(
        "output {} {}, set point {} {}",
        number(state.output),
        state.unit,
        number(state.set_point),
        state.unit
    ));
    if state.at_speed {
        parts.push("at speed".to_owned());
    }
    if let Some(current) = state.current {
        parts.push(format!("current {current:.2} {}", state.current_unit));
    }
    if let Some(trip) = &state.trip {
        parts.push(format!("trip {}: {}", trip.code, trip.name));
    }
    format!("{}: {}", state.drive, parts.join(", "))
}
