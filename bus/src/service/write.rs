//! A write asked of the service (an MQTT `set` message), carried out by the bus worker of
//! the station's bus: refused before anything is sent unless the plant file allows the
//! register, the manual allows writing it (in the storage the plant names), the value is
//! in range and within the bounds other registers set now, and no forbidden combination
//! results — the checks `vfd write` makes, in the same code. It is sent once: a write
//! whose reply was lost is reported as such, never repeated.

use super::event::{WriteOutcome, WriteRequest};
use super::station::Link;
use crate::session_error::SessionError;
use crate::values;
use crate::write_value::checked_value;
use crate::ErrorKind;
use std::time::Instant;

/// Carries out `request` on `link` and says how it went, and, when the line itself failed
/// on the way (an unplugged adapter), why. A written register that is polled is made due,
/// so its new value is read back at once.
pub fn write(link: &mut Link, request: &WriteRequest) -> (WriteOutcome, Option<String>) {
    let mut outcome = WriteOutcome::pending(request);
    let mut line_failed = None;
    match attempt(link, request, &mut outcome) {
        Ok(()) => outcome.ok = true,
        Err((failure, sent)) => {
            if failure.exchange().is_some_and(|e| e.kind().is_io()) {
                line_failed = Some(failure.message().to_owned());
            }
            outcome.sent = sent;
            if let Some(error) = failure.exchange() {
                outcome.error_code = error.code();
                if error.kind() == ErrorKind::ErrorReply {
                    outcome.error_meaning = Some(error.meaning().to_owned());
                }
            }
            outcome.error = Some(match failure.hint() {
                Some(hint) => format!("{} ({hint})", failure.message()),
                None => failure.message().to_owned(),
            });
        }
    }
    if outcome.ok {
        outcome.sent = true;
    }
    outcome.time = crate::record::now().0;
    (outcome, line_failed)
}

/// The checks and the write; the error says whether the write's frame was sent.
fn attempt(
    link: &mut Link,
    request: &WriteRequest,
    outcome: &mut WriteOutcome,
) -> Result<(), (SessionError, bool)> {
    let not_sent = |failure: SessionError| (failure, false);
    let station = &link.station;
    let drive = station.drive;
    let (info, index) = match request.target.and_then(|target| target.allowed) {
        // Resolved when the plant was set up: one of the allowed registers.
        Some(index) => (station.writes[index].register, index),
        // A name that is none of the allowed registers' own: what it means, refused unless
        // it is one of them after all (another spelling).
        None => {
            let info =
                crate::lookup::register_for(drive, &request.register, true, &station.drive_name)
                    .map_err(|error| not_sent(error.into()))?;
            let allow: Vec<&'static vfd_runtime::RegisterInfo> =
                station.writes.iter().map(|a| a.register).collect();
            let place = format!("{}/{}", link.bus, station.name);
            let index = crate::write_check::allowed(&allow, info, &place)
                .map_err(|refusal| not_sent(refusal.into()))?;
            (info, index)
        }
    };
    outcome.code = info.code.to_owned();
    outcome.unit = info.unit_symbol().to_owned();
    let persistent = station.writes[index].persistent;
    // Writable in the storage the plant names: checked when the plant was set up, and
    // by the session just before it sends.
    let info = link.session.on_port(info);
    if link.health.is_offline() {
        return Err(not_sent(SessionError::Exchange(
            crate::Error::new(
                ErrorKind::Offline,
                format!(
                    "{}/{} is offline (it did not answer the last exchanges); nothing was sent",
                    link.bus, station.name
                ),
            )
            .with_hint("the write is not queued: send it again once the drive is online"),
        )));
    }
    let (info, raw) = checked_value(&mut link.session, info, &request.value).map_err(not_sent)?;
    let record = crate::record::ValueRecord::new(drive.id, info, Some(raw), None);
    outcome.raw = Some(raw);
    outcome.value = record.value;
    let result = link.session.write(info, raw, persistent);
    match result {
        Ok((echo, _tripped)) => {
            if let Some(echo) = echo.filter(|echo| *echo != raw) {
                log::info!(
                    target: super::LOG_TARGET,
                    "{}/{}: wrote {} = {}; the drive reports {}",
                    link.bus,
                    station.name,
                    info.code,
                    values::short(info, raw),
                    values::short(info, echo)
                );
            }
            if let Some(poll) = station
                .polls
                .iter()
                .position(|p| crate::write_check::same_register(p.register, info))
            {
                link.schedule.due_now(poll, Instant::now());
            }
            Ok(())
        }
        Err(failure) => {
            // A failure with a line error came from the exchange: the frame went out
            // (a lost reply leaves the outcome unknown). One without came from a check.
            let sent = failure.exchange().is_some_and(|e| e.kind().sent());
            let failure = match failure {
                SessionError::Exchange(error) if error.kind() == ErrorKind::Timeout => {
                    let message = format!(
                        "{}; the write may have been carried out and is not repeated",
                        error.message()
                    );
                    SessionError::Exchange(error.with_message(message).with_hint(format!(
                        "read {} back to see whether it took effect",
                        info.code
                    )))
                }
                failure => failure,
            };
            Err((failure, sent))
        }
    }
}
