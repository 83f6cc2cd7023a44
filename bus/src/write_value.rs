//! The value a write sends, checked before anything is sent, the same way for `vfd write`
//! and for `vfd serve`'s `set` requests: a percentage of another register where the named
//! command carries one, else the value in the register's unit (in the scale another
//! register chooses now, where one does), within the register's range and the bounds other
//! registers set at run time, by the library's one write check ([`crate::write_check`];
//! writability and the plant's allow-list are asked by the callers, the manual's forbidden
//! combinations by [`Session::write`]).

use crate::session::Session;
use crate::session_error::SessionError;
use crate::write_check;
use crate::SetupError;
use vfd_runtime::RegisterInfo;

/// The register (in the scale it is written in) and the raw word `text` writes to `info`
/// over `session`; reads what the checks need (a scale selector, a bounding register).
/// Nothing is written.
pub fn checked_value(
    session: &mut Session,
    info: &'static RegisterInfo,
    text: &str,
) -> Result<(&'static RegisterInfo, u32), SessionError> {
    let drive_name = session.drive_name.clone();
    let parse = |info: &'static RegisterInfo| write_check::in_range(info, text, &drive_name);
    let percent_of = session.named_command().and_then(|c| c.percent_of.clone());
    // The data is a percentage of another register (50%), or a value in the register's
    // scale; a register whose scale another register chooses is read in the scale it
    // chooses now. Nothing is written before the value is checked.
    let (info, raw) = match (&percent_of, info.scale_by) {
        (Some(percent_of), _) => (info, percentage(percent_of, text)?),
        (None, Some(_)) => {
            let scaled = session.scaled(info)?;
            (scaled, parse(scaled)?)
        }
        (None, None) => (info, parse(info)?),
    };
    if percent_of.is_none() {
        check_run_time_bounds(session, info, raw)?;
    }
    Ok((info, raw))
}

/// The raw word of a percentage written `50%` (or `50`), for a command whose data is a
/// percentage of another register.
pub fn percentage(
    percent_of: &vfd_runtime::protocol::PercentOf,
    text: &str,
) -> Result<u32, SessionError> {
    let number = text.trim().trim_end_matches('%').trim();
    let value: f64 = number.parse().map_err(|_| {
        SessionError::Said(
            SetupError::new(format!("`{text}` is not a percentage")).with_hint(format!(
                "this command carries a percentage of {}: write e.g. 50%",
                percent_of.register
            )),
        )
    })?;
    percent_of.to_raw(value, 100.0).ok_or_else(|| {
        SessionError::Said(
            SetupError::new(format!("{value} % does not fit the command's data word"))
                .with_hint("nothing was sent"),
        )
    })
}

/// Refuses a value beyond a bound another register sets at run time (FH for the frequency
/// command), reading that register first ([`write_check::within_bounds`]). Nothing is
/// written when it refuses.
fn check_run_time_bounds(
    session: &mut Session,
    info: &'static RegisterInfo,
    raw: u32,
) -> Result<(), SessionError> {
    let drive = session.drive;
    write_check::within_bounds(drive, info, raw, |other| session.read_if_readable(other))
        .map_err(SessionError::from)
}
