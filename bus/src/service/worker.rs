//! One bus's worker thread: opens the bus's port (again with back-off when it fails), and
//! on the open line, over and over, carries out the write requests first, then polls the
//! stations whose reads are due, then sleeps until the next is due or a request comes. A
//! slow or dead bus holds only its own thread.

use super::event::{Availability, Event, PortState, WriteOutcome, WriteRequest};
use super::health::Health;
use super::report::Reporter;
use super::station::{Link, Round};
use crate::plant::Bus;
use crate::BackOff;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// The stations of an open bus, on its line.
type OnLine = crate::Bus<Link>;

/// The longest a worker sleeps before it looks at the stop flag again.
const STOP_CHECK: Duration = Duration::from_millis(100);

/// Why the worker left an open line.
enum End {
    Stopped,
    LineFailed(String),
}

/// A bus and what its worker needs.
pub struct Worker {
    bus: Bus,
    reporter: Reporter,
    requests: Receiver<WriteRequest>,
    stop: Arc<AtomicBool>,
    /// Whether the write queue still has a sender (else the worker only sleeps).
    inputs: bool,
}

impl Worker {
    /// A worker for `bus`, reporting to `reporter`, taking writes from `requests`, until
    /// `stop` is set.
    pub fn new(
        bus: Bus,
        reporter: Reporter,
        requests: Receiver<WriteRequest>,
        stop: Arc<AtomicBool>,
    ) -> Worker {
        Worker {
            bus,
            reporter,
            requests,
            stop,
            inputs: true,
        }
    }

    /// Runs the worker on its own thread.
    pub fn spawn(self) -> std::io::Result<JoinHandle<()>> {
        std::thread::Builder::new()
            .name(format!("bus {}", self.bus.name))
            .spawn(move || self.run())
    }

    fn stopped(&self) -> bool {
        self.stop.load(Ordering::SeqCst)
    }

    fn run(mut self) {
        let rules = Link::rules(&self.bus);
        let mut healths: Vec<Health> = self
            .bus
            .stations
            .iter()
            .map(|_| Health::new(rules))
            .collect();
        let mut backoff = BackOff::reopening();
        let mut failing = false;
        while !self.stopped() {
            let line = match crate::line::open(&self.bus.port, &self.bus.settings) {
                Ok(line) => line,
                Err(error) => {
                    let why = error.with_hint_text();
                    if !failing {
                        log::warn!(
                            target: super::LOG_TARGET,
                            "{}: {why}; trying again with back-off up to {} s",
                            self.bus.name,
                            backoff.cap().as_secs()
                        );
                        self.port_state(false, Some(why.clone()));
                        failing = true;
                    }
                    self.all_unreachable(&mut healths, &why);
                    self.sleep_serving_refusals(backoff.next_wait(), &why);
                    continue;
                }
            };
            if failing {
                log::info!(target: super::LOG_TARGET, "{}: {} is open again", self.bus.name, self.bus.port);
            }
            backoff.reset();
            self.port_state(true, None);
            let now = Instant::now();
            let links: Vec<Link> = self
                .bus
                .stations
                .iter()
                .zip(healths.drain(..))
                .map(|(station, health)| Link::new(&self.bus, station, health, now))
                .collect();
            let mut on_line = OnLine::new(line, links);
            let end = self.serve(&mut on_line);
            // The line closes here; what the stations know of their health carries on.
            let (_, links) = on_line.into_parts();
            healths = links.into_iter().map(|link| link.health).collect();
            match end {
                End::Stopped => break,
                End::LineFailed(why) => {
                    log::warn!(
                        target: super::LOG_TARGET,
                        "{}: the line failed: {why}; reopening {}",
                        self.bus.name,
                        self.bus.port
                    );
                    self.port_state(false, Some(why.clone()));
                    failing = true;
                    self.all_unreachable(&mut healths, &why);
                    self.sleep_serving_refusals(backoff.next_wait(), &why);
                }
            }
        }
        // Told once, for every station: the service no longer polls them.
        for station in &self.bus.stations {
            self.reporter.event(Event::Availability(Availability {
                bus: self.bus.name.clone(),
                drive: station.name.clone(),
                online: false,
                reason: Some("the service stopped".to_owned()),
                time: crate::record::now().0,
            }));
        }
    }

    /// Polls and writes on the open line until the service stops or the line fails.
    fn serve(&mut self, on_line: &mut OnLine) -> End {
        loop {
            if self.stopped() {
                return End::Stopped;
            }
            if let Some(why) = self.writes(on_line) {
                return End::LineFailed(why);
            }
            let now = Instant::now();
            for index in 0..on_line.stations().len() {
                let reporter = &self.reporter;
                match on_line.speak(index, |link| link.poll(now, reporter)) {
                    Round::Idle | Round::Done => {}
                    Round::LineFailed(why) => return End::LineFailed(why),
                }
                // A write waits for one station's round at most.
                if let Some(why) = self.writes(on_line) {
                    return End::LineFailed(why);
                }
                if self.stopped() {
                    return End::Stopped;
                }
            }
            let now = Instant::now();
            let next = on_line
                .stations()
                .iter()
                .filter_map(|link| link.next_turn(now))
                .min();
            let wait = next
                .map_or(STOP_CHECK, |at| at.saturating_duration_since(now))
                .min(STOP_CHECK);
            if wait.is_zero() {
                continue;
            }
            match self.next_request(wait) {
                Some(request) => {
                    if let Some(why) = self.write(on_line, &request) {
                        return End::LineFailed(why);
                    }
                }
                None => continue,
            }
        }
    }

    /// Waits up to `wait` for a write request.
    fn next_request(&mut self, wait: Duration) -> Option<WriteRequest> {
        if !self.inputs {
            std::thread::sleep(wait);
            return None;
        }
        match self.requests.recv_timeout(wait) {
            Ok(request) => Some(request),
            Err(RecvTimeoutError::Timeout) => None,
            Err(RecvTimeoutError::Disconnected) => {
                self.inputs = false;
                None
            }
        }
    }

    /// Carries out the write requests waiting; the line's failure, if one failed it.
    fn writes(&mut self, on_line: &mut OnLine) -> Option<String> {
        while let Ok(request) = self.requests.try_recv() {
            if let Some(why) = self.write(on_line, &request) {
                return Some(why);
            }
        }
        None
    }

    fn write(&self, on_line: &mut OnLine, request: &WriteRequest) -> Option<String> {
        // The router resolved the station's name when it took the request.
        let Some(index) = request.target.and_then(|target| target.station) else {
            self.refuse(
                request,
                format!(
                    "there is no drive `{}` on bus {} (the plant file names {}); nothing was sent",
                    request.drive,
                    self.bus.name,
                    self.bus
                        .stations
                        .iter()
                        .map(|s| s.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            );
            return None;
        };
        let (outcome, line_failed) =
            on_line.speak(index, |link| super::write::write(link, request));
        if outcome.ok {
            log::info!(
                target: super::LOG_TARGET,
                "{}/{}: wrote {} = {}",
                self.bus.name,
                request.drive,
                outcome.code,
                outcome.request
            );
        } else {
            log::warn!(
                target: super::LOG_TARGET,
                "{}/{}: write of {} = {} refused or failed: {}",
                self.bus.name,
                request.drive,
                outcome.code,
                outcome.request,
                outcome.error.as_deref().unwrap_or("")
            );
        }
        self.reporter.event(Event::Written(outcome));
        line_failed
    }

    /// Sleeps `wait` (in steps, so a stop is seen), refusing the write requests that come
    /// meanwhile: the port is not open.
    fn sleep_serving_refusals(&mut self, wait: Duration, why: &str) {
        let until = Instant::now() + wait;
        while !self.stopped() {
            let now = Instant::now();
            if now >= until {
                break;
            }
            if let Some(request) = self.next_request((until - now).min(STOP_CHECK)) {
                self.refuse(
                    &request,
                    format!(
                        "bus {}'s port is not open ({why}); nothing was sent",
                        self.bus.name
                    ),
                );
            }
        }
    }

    fn refuse(&self, request: &WriteRequest, error: String) {
        self.reporter
            .event(Event::Written(WriteOutcome::refused(request, error)));
    }

    fn port_state(&self, open: bool, error: Option<String>) {
        self.reporter.event(Event::Port(PortState {
            bus: self.bus.name.clone(),
            port: self.bus.port.clone(),
            open,
            error,
            time: crate::record::now().0,
        }));
    }

    fn all_unreachable(&self, healths: &mut [Health], why: &str) {
        for (station, health) in self.bus.stations.iter().zip(healths.iter_mut()) {
            if health.unreachable().is_some() {
                self.reporter.event(Event::Availability(Availability {
                    bus: self.bus.name.clone(),
                    drive: station.name.clone(),
                    online: false,
                    reason: Some(why.to_owned()),
                    time: crate::record::now().0,
                }));
            }
        }
    }
}
