//! `vfd serve` as a library: the plant benchmarks run the service core (`vfd_bus`'s
//! [`ServiceCore`]) in their own process as well as the binary, counting its events as
//! [`crate::service::Service`] counts the binary's JSON lines, and timing the service's
//! own threads (the bus workers and the thread taking the events) from `/proc` (Linux).

use crate::service::{Measured, Tally};
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use vfd_bus::service::event::{Event, WriteRequest, WriteRouter};
use vfd_bus::service::Running;
use vfd_bus::{Catalogue, ServiceCore};

/// The name of the thread taking the service's events here.
const EVENTS_THREAD: &str = "events";

/// The service core running in this process.
pub struct InProcess {
    /// What it reported so far.
    pub tally: Arc<Mutex<Tally>>,
    router: WriteRouter,
    stop: Arc<AtomicBool>,
    running: Option<Running>,
    events: Option<JoinHandle<()>>,
    next_id: AtomicU64,
}

impl InProcess {
    /// Loads the plant file at `plant` (drives compiled in) and starts its workers.
    pub fn start(plant: &Path) -> Result<InProcess, String> {
        let catalogue = Catalogue::new();
        let plant = vfd_bus::plant::load(plant, &catalogue).map_err(|p| p.to_string())?;
        let (core, events) = ServiceCore::new(&plant);
        let router = core.writes();
        let tally = Arc::new(Mutex::new(Tally::default()));
        let sink = Arc::clone(&tally);
        let events = std::thread::Builder::new()
            .name(EVENTS_THREAD.to_owned())
            .spawn(move || {
                for event in events {
                    let now = Instant::now();
                    let mut tally = sink.lock().unwrap_or_else(|p| p.into_inner());
                    match event {
                        Event::Reading(r) => {
                            *tally.readings.entry((r.bus, r.drive)).or_default() += 1
                        }
                        Event::Availability(a) => {
                            tally.availability.push((now, a.bus, a.drive, a.online))
                        }
                        Event::Written(w) => {
                            tally.written.insert(w.id, (now, w.ok));
                        }
                        Event::Port(_) => {}
                    }
                }
            })
            .map_err(|e| e.to_string())?;
        let stop = Arc::new(AtomicBool::new(false));
        let running = core.start(Arc::clone(&stop)).map_err(|e| e.to_string())?;
        Ok(InProcess {
            tally,
            router,
            stop,
            running: Some(running),
            events: Some(events),
            next_id: AtomicU64::new(1),
        })
    }

    /// Asks for a write, as a JSON line on `--stdin-writes` would.
    pub fn write(&self, bus: &str, drive: &str, register: &str, value: &str) -> Result<(), String> {
        let id = self.next_id.fetch_add(1, Ordering::Relaxed);
        self.router
            .send(WriteRequest::new(bus, drive, register, value, id))
            .map_err(|not_sent| format!("not routed: {:?}", not_sent.why))
    }

    /// CPU time (user + system) of the service's threads so far: the bus workers and the
    /// thread taking their events (not the benchmark's virtual drives and paced lines).
    pub fn cpu_time(&self) -> Option<Duration> {
        let mut ticks = 0u64;
        for task in std::fs::read_dir("/proc/self/task").ok()? {
            let Ok(task) = task else { continue };
            let Ok(stat) = std::fs::read_to_string(task.path().join("stat")) else {
                continue;
            };
            let (Some(open), Some(close)) = (stat.find('('), stat.rfind(')')) else {
                continue;
            };
            let name = &stat[open + 1..close];
            // Thread names are cut to 15 bytes: "bus line12" fits.
            if !(name.starts_with("bus ") || name == EVENTS_THREAD) {
                continue;
            }
            let fields: Vec<&str> = stat[close + 2..].split_whitespace().collect();
            let utime: u64 = fields.get(11)?.parse().ok()?;
            let stime: u64 = fields.get(12)?.parse().ok()?;
            ticks += utime + stime;
        }
        Some(Duration::from_secs_f64(
            ticks as f64 / crate::service::clock_ticks() as f64,
        ))
    }

    /// This process's resident memory now and its peak, in KiB (the benchmark's virtual
    /// drives and lines included).
    pub fn memory_kib(&self) -> Option<(u64, u64)> {
        crate::service::memory_kib(std::process::id())
    }

    /// Stops the workers (every station reported offline) and the events' thread.
    pub fn stop(mut self) {
        self.shut_down();
    }

    fn shut_down(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(running) = self.running.take() {
            running.join();
        }
        // The workers' ends of the event queue are gone: the events' thread ends.
        self.router = WriteRouter::default();
        if let Some(events) = self.events.take() {
            let _ = events.join();
        }
    }
}

impl Drop for InProcess {
    fn drop(&mut self) {
        self.shut_down();
    }
}

impl Measured for InProcess {
    fn tally(&self) -> &Mutex<Tally> {
        &self.tally
    }
    fn cpu_time(&self) -> Option<Duration> {
        InProcess::cpu_time(self)
    }
    fn memory_kib(&self) -> Option<(u64, u64)> {
        InProcess::memory_kib(self)
    }
    fn write(&mut self, bus: &str, drive: &str, register: &str, value: &str) -> Result<(), String> {
        InProcess::write(self, bus, drive, register, value)
    }
}
