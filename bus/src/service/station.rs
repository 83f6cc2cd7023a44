//! One station as a bus worker drives it: its master (a session the bus lends its line to),
//! its poll schedule and its health, and one round of polling that turns replies into
//! events.

use super::event::{Availability, Event, Reading};
use super::health::{Change, Health, Rules, Turn};
use super::report::Reporter;
use super::schedule::Schedule;
use crate::plant::{Bus, Station};
use crate::record::ValueRecord;
use crate::session::{Session, Value};
use crate::session_error::SessionError;
use crate::trip_flag::trip_flag;
use crate::{Line, OnLine};
use std::time::{Duration, Instant};
use vfd_runtime::transaction::Master;
use vfd_runtime::RegisterInfo;

/// How one round with a station ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Round {
    /// Nothing was due.
    Idle,
    /// Exchanges were made (answered or not).
    Done,
    /// The line itself failed (an unplugged adapter, a lost connection): the worker
    /// reopens the port.
    LineFailed(String),
}

/// A station on an open bus.
pub struct Link {
    /// The plant's station.
    pub station: Station,
    /// The bus's name.
    pub bus: String,
    /// Its master.
    pub session: Session,
    /// When its registers are due.
    pub schedule: Schedule,
    /// Whether it answers.
    pub health: Health,
    /// The registers polled, each in the scale it is read in (a register whose scale
    /// another register chooses is resolved once the station answers).
    registers: Vec<&'static RegisterInfo>,
    /// Whether the scales of the registers were resolved since the station came online.
    scaled: bool,
    /// The retries of a read while the station answers (an offline station is tried with
    /// one exchange).
    retries: u8,
}

impl Link {
    /// `station` on `bus`, its registers all due at `now`; it speaks when the bus lends it
    /// the line ([`crate::Bus::speak`]).
    pub fn new(bus: &Bus, station: &Station, health: Health, now: Instant) -> Link {
        let drive = station.drive;
        let mut timing = drive.serial.timing;
        if let Some(timeout) = bus.timeout {
            timing.processing_allowance = timeout;
        }
        let mut master = Master::for_protocol(Line::Away, station.protocol, bus.settings, timing)
            .with_address(station.address)
            .with_port(station.port)
            .with_retries(bus.retries);
        if let Some(gap) = bus.min_gap {
            master = master.with_min_gap(gap);
        }
        if let Some(latency) = bus.host_latency {
            master = master.with_host_latency(latency);
        }
        let mut session = Session::with_master(
            drive,
            station.protocol,
            bus.settings,
            master,
            station.address,
        );
        session.port = station.port;
        session.drive_name = station.drive_name.clone();
        let intervals: Vec<Duration> = station.polls.iter().map(|p| p.every).collect();
        Link {
            station: station.clone(),
            bus: bus.name.clone(),
            session,
            schedule: Schedule::new(&intervals, now),
            // A station that polls nothing cannot be tried: it is taken as there once
            // its bus is open (a write to it shows whether it answers).
            health: if station.polls.is_empty() {
                Health::new(health.rules())
            } else {
                health
            },
            registers: station.polls.iter().map(|p| p.register).collect(),
            scaled: false,
            retries: bus.retries,
        }
    }

    /// The rules of `bus` for its stations' health.
    pub fn rules(bus: &Bus) -> Rules {
        Rules {
            offline_after: bus.offline_after,
            first: bus.backoff_first,
            cap: bus.backoff_cap,
        }
    }

    /// When the station next needs the line: its next poll, or its next try while
    /// offline (`None`: never).
    pub fn next_turn(&self, now: Instant) -> Option<Instant> {
        if self.registers.is_empty() {
            return None;
        }
        match self.health.turn(now) {
            Turn::Poll => self.schedule.next_due(),
            Turn::Probe => Some(now),
            Turn::WaitUntil(at) => Some(at),
        }
    }

    /// Reads what is due at `now` (or, while offline and its back-off has passed, one
    /// register to see whether it answers again), reporting readings and changes.
    pub fn poll(&mut self, now: Instant, reporter: &Reporter) -> Round {
        let due = match self.health.turn(now) {
            Turn::WaitUntil(_) => return Round::Idle,
            Turn::Poll => self.schedule.take_due(now),
            Turn::Probe => {
                if self.registers.is_empty() {
                    return Round::Idle;
                }
                vec![0]
            }
        };
        if due.is_empty() {
            return Round::Idle;
        }
        let probing = self.health.is_offline();
        self.session
            .set_retries(if probing { 0 } else { self.retries });
        let registers: Vec<&'static RegisterInfo> =
            due.iter().map(|i| self.registers[*i]).collect();
        let values = self.session.read_many_until_silent(&registers);
        let mut answered = false;
        let mut silent: Option<SessionError> = None;
        for result in &values {
            match result {
                Ok(_) => answered = true,
                Err(failure) => match failure.exchange().map(|e| e.kind()) {
                    Some(kind) if kind.is_io() => return self.line_failed(failure, reporter),
                    // The drive answered, with a refusal: it is there.
                    Some(kind) if kind.answered() => answered = true,
                    _ => silent = Some(failure.clone()),
                },
            }
        }
        let now = Instant::now();
        if answered {
            let change = self.health.answered();
            if change.is_some() && !self.scaled {
                self.resolve_scales();
            }
            self.report_change(change, None, reporter);
            if probing {
                // Back online: everything is due now, not at the old times.
                self.schedule.all_due(now);
                return Round::Done;
            }
        } else if let Some(failure) = &silent {
            let change = self.health.failed(now);
            if change.is_some() {
                // Its scale selectors may be set otherwise when it is back.
                self.scaled = false;
            }
            self.report_change(change, Some(failure), reporter);
        }
        if probing && !answered {
            return Round::Done;
        }
        let tripped = trip_flag(&self.session, &registers, &values);
        for ((index, info), result) in due.iter().zip(&registers).zip(&values) {
            match result {
                Ok(value) => reporter.reading(self.reading(info, value, tripped)),
                Err(failure) => {
                    if answered {
                        log::debug!(
                            target: super::LOG_TARGET,
                            "{}/{}: {} not read: {}",
                            self.bus,
                            self.station.name,
                            self.station.polls[*index].register.code,
                            failure.message()
                        );
                    }
                }
            }
        }
        Round::Done
    }

    /// Reports the station offline because its bus cannot be reached (`why`).
    pub fn unreachable(&mut self, why: &str, reporter: &Reporter) {
        let change = self.health.unreachable();
        if change.is_some() {
            reporter.event(Event::Availability(Availability {
                bus: self.bus.clone(),
                drive: self.station.name.clone(),
                online: false,
                reason: Some(why.to_owned()),
                time: crate::record::now().0,
            }));
        }
    }

    fn line_failed(&mut self, failure: &SessionError, reporter: &Reporter) -> Round {
        let why = failure.message().to_owned();
        self.unreachable(&why, reporter);
        Round::LineFailed(why)
    }

    fn report_change(
        &self,
        change: Option<Change>,
        failure: Option<&SessionError>,
        reporter: &Reporter,
    ) {
        let Some(change) = change else { return };
        let online = change == Change::Online;
        if online {
            log::info!(target: super::LOG_TARGET, "{}/{}: online", self.bus, self.station.name);
        } else {
            log::warn!(
                target: super::LOG_TARGET,
                "{}/{}: offline after {} failed exchanges: {}",
                self.bus,
                self.station.name,
                self.station_rules_offline_after(),
                failure.map_or("", |f| f.message())
            );
        }
        reporter.event(Event::Availability(Availability {
            bus: self.bus.clone(),
            drive: self.station.name.clone(),
            online,
            reason: failure.map(|f| f.message().to_owned()),
            time: crate::record::now().0,
        }));
    }

    fn station_rules_offline_after(&self) -> u32 {
        self.health.rules().offline_after
    }

    /// Resolves the scale of each register whose scale another register chooses, once per
    /// time online (a failure keeps the description's first scale).
    fn resolve_scales(&mut self) {
        self.scaled = true;
        for (index, poll) in self.station.polls.iter().enumerate() {
            if poll.register.scale_by.is_some() {
                if let Ok(chosen) = self.session.scaled(poll.register) {
                    self.registers[index] = chosen;
                }
            }
        }
    }

    /// The reading event of `value` read from `info`.
    fn reading(
        &self,
        info: &'static RegisterInfo,
        value: &Value,
        tripped: Option<bool>,
    ) -> Reading {
        // The reply's own decimals (the Eaton unit digit) choose the scale where they can.
        let info = value
            .decimals
            .and_then(|d| info.scaled_for_decimals(d))
            .unwrap_or(info);
        let record = ValueRecord::new(self.session.drive.id, info, value.raw, value.text.clone());
        let (time, epoch_ms) = crate::record::now();
        Reading {
            bus: self.bus.clone(),
            drive: self.station.name.clone(),
            model: self.session.drive.id.to_owned(),
            code: record.code,
            name: record.name,
            name_zh: record.name_zh,
            value: record.value,
            unit: record.unit,
            raw: record.raw,
            text: record.text,
            time,
            epoch_ms,
            tripped,
        }
    }
}

impl OnLine for Link {
    fn master(&mut self) -> &mut Master<Line> {
        self.session.master()
    }
}
