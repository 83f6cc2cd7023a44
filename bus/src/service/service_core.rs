//! The service itself, embedded in-process: a plant in, events and write results out.
//! [`ServiceCore::new`] sets a plant up (its names resolved once, a write queue per bus)
//! and gives the events' receiving end; [`ServiceCore::writes`] takes write requests,
//! whose outcomes come back as [`Event::Written`] events with their ids;
//! [`ServiceCore::start`] runs one worker thread per bus until the stop flag is set.
//! `vfd serve` is this with its outputs (JSON lines, MQTT) and inputs (MQTT `set`,
//! `--stdin-writes`) around it; nothing here prints or knows the command line, and its
//! errors are typed ([`StartError`]).

use super::event::{Event, WriteRequest, WriteRouter};
use super::report::Reporter;
use super::worker::Worker;
use crate::plant::{Bus, Plant};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Receiver;
use std::sync::Arc;
use std::thread::JoinHandle;

/// A plant set up to run: its buses, their write queues, the event queue's sending end.
pub struct ServiceCore {
    buses: Vec<Bus>,
    reporter: Reporter,
    router: WriteRouter,
    queues: Vec<Receiver<WriteRequest>>,
}

/// A bus's worker could not be started.
#[derive(Debug)]
pub struct StartError {
    /// The bus's name.
    pub bus: String,
    /// Why its thread could not be made.
    pub error: std::io::Error,
}

impl std::fmt::Display for StartError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "cannot start the worker of bus {}: {}",
            self.bus, self.error
        )
    }
}

impl std::error::Error for StartError {}

/// The workers of a started service.
pub struct Running {
    workers: Vec<JoinHandle<()>>,
}

impl Running {
    /// Waits until every worker has ended (after the stop flag was set): each has
    /// reported its stations offline.
    pub fn join(self) {
        for worker in self.workers {
            let _ = worker.join();
        }
    }
}

impl ServiceCore {
    /// `plant` set up to run, and the receiving end of its events (readings, stations
    /// going on- or offline, write outcomes, ports opening or failing). The queue is
    /// bounded: a reading that finds it full is dropped, other events wait for room.
    pub fn new(plant: &Plant) -> (ServiceCore, Receiver<Event>) {
        let (reporter, events) = Reporter::queue();
        let (router, queues) = WriteRouter::new(plant);
        let core = ServiceCore {
            buses: plant.buses.clone(),
            reporter,
            router,
            queues,
        };
        (core, events)
    }

    /// Where write requests go (clone it for each input).
    pub fn writes(&self) -> WriteRouter {
        self.router.clone()
    }

    /// The event queue's sending end, for an input that answers a request it cannot route
    /// with a [`Event::Written`] event of its own.
    pub fn reporter(&self) -> Reporter {
        self.reporter.clone()
    }

    /// Starts a worker per bus, running until `stop` is set. When one cannot be started,
    /// `stop` is set (the ones started end) and the error says which.
    pub fn start(self, stop: Arc<AtomicBool>) -> Result<Running, StartError> {
        let mut workers = Vec::new();
        for (bus, requests) in self.buses.into_iter().zip(self.queues) {
            let name = bus.name.clone();
            let worker = Worker::new(bus, self.reporter.clone(), requests, stop.clone());
            match worker.spawn() {
                Ok(handle) => workers.push(handle),
                Err(error) => {
                    stop.store(true, Ordering::SeqCst);
                    return Err(StartError { bus: name, error });
                }
            }
        }
        Ok(Running { workers })
    }
}
