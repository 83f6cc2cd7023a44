//! What `vfd serve` reports and what it is asked to do: the events its bus workers produce
//! (readings, a station going on- or offline, the outcome of a write, a port opening or
//! failing), which every output (`--jsonl`, MQTT) turns into its own form, and the write
//! requests an input (an MQTT `set` topic) hands to a bus worker.

pub use super::directory::{Directory, Target};
use crate::plant::Plant;
use serde::Serialize;
use std::sync::mpsc::{Receiver, Sender};
use std::sync::Arc;

/// One thing the service reports. As a JSON line it is an object whose `event` field names
/// the kind (`reading`, `availability`, `written`, `port`).
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum Event {
    /// A polled register was read.
    Reading(Reading),
    /// A station went online or offline.
    Availability(Availability),
    /// A requested write was carried out or refused.
    Written(WriteOutcome),
    /// A bus's port was opened, or failed.
    Port(PortState),
}

/// A polled register's value.
#[derive(Debug, Clone, Serialize)]
pub struct Reading {
    /// The bus's name in the plant file.
    pub bus: String,
    /// The station's name in the plant file.
    pub drive: String,
    /// The drive model's id (`vfd list`).
    pub model: String,
    /// The register's code as the manual writes it (`FA01`, `3-03`).
    pub code: String,
    /// The register's English name.
    pub name: String,
    /// The manual's Chinese name (empty when it gives none).
    pub name_zh: String,
    /// The value in the register's unit; `null` for text parameters.
    pub value: Option<f64>,
    /// The unit symbol (`Hz`, `s`); empty for plain numbers.
    pub unit: String,
    /// The raw word on the line; `null` for text parameters.
    pub raw: Option<u32>,
    /// The value as text (`50.00 Hz`, a code's meaning, set bit fields, a text parameter).
    pub text: Option<String>,
    /// When it was read: RFC 3339, UTC, milliseconds.
    pub time: String,
    /// The same instant in milliseconds since 1970-01-01 UTC.
    pub epoch_ms: u64,
    /// The drive's trip flag as the reply states it; `null` where the reply carries none.
    pub tripped: Option<bool>,
}

/// A station's availability changed.
#[derive(Debug, Clone, Serialize)]
pub struct Availability {
    /// The bus's name.
    pub bus: String,
    /// The station's name.
    pub drive: String,
    /// `true`: it answers; `false`: it failed `offline_after` exchanges in a row (or its
    /// bus's port is not open, or the service stopped).
    pub online: bool,
    /// Why it is offline (the last error), `null` when online.
    pub reason: Option<String>,
    /// When: RFC 3339, UTC, milliseconds.
    pub time: String,
}

/// The outcome of a write request.
#[derive(Debug, Clone, Serialize)]
pub struct WriteOutcome {
    /// The bus's name.
    pub bus: String,
    /// The station's name.
    pub drive: String,
    /// The register as the request named it (its code where it was found).
    pub code: String,
    /// The request's value as received (`50`, `50 Hz`, a code name, bit fields), cut to
    /// its first characters and its size when long ([`super::request_text::echo`]).
    pub request: String,
    /// The request's number in this run, for the input to answer it; written `RUN-N`
    /// ([`super::run_id`]), unique across restarts.
    #[serde(serialize_with = "super::run_id::serialize")]
    pub id: u64,
    /// The write was carried out (and its reply accepted).
    pub ok: bool,
    /// Whether a write frame was sent (a refusal before sending: `false`).
    pub sent: bool,
    /// The value written, in the register's unit.
    pub value: Option<f64>,
    /// The unit symbol.
    pub unit: String,
    /// The raw word written.
    pub raw: Option<u32>,
    /// Why it was refused or failed (the register, the value, the rule).
    pub error: Option<String>,
    /// The drive's error code, when it refused the write with one.
    pub error_code: Option<u16>,
    /// The manual's meaning of that code.
    pub error_meaning: Option<String>,
    /// When the outcome was decided: RFC 3339, UTC, milliseconds.
    pub time: String,
}

impl WriteOutcome {
    /// The outcome of `request` not yet decided: not carried out, nothing sent, stamped
    /// now.
    pub fn pending(request: &WriteRequest) -> WriteOutcome {
        WriteOutcome {
            bus: request.bus.clone(),
            drive: request.drive.clone(),
            code: request.register.clone(),
            request: super::request_text::echo_text(&request.value),
            id: request.id,
            ok: false,
            sent: false,
            value: None,
            unit: String::new(),
            raw: None,
            error: None,
            error_code: None,
            error_meaning: None,
            time: crate::record::now().0,
        }
    }

    /// `request` refused before anything was sent, for `error`.
    pub fn refused(request: &WriteRequest, error: String) -> WriteOutcome {
        WriteOutcome {
            error: Some(error),
            ..WriteOutcome::pending(request)
        }
    }
}

/// A bus's port was opened, or could not be opened or failed.
#[derive(Debug, Clone, Serialize)]
pub struct PortState {
    /// The bus's name.
    pub bus: String,
    /// The port (`/dev/ttyUSB0`, `tcp://HOST:PORT`).
    pub port: String,
    /// `true`: open; `false`: failed (then tried again with back-off).
    pub open: bool,
    /// Why it failed.
    pub error: Option<String>,
    /// When: RFC 3339, UTC, milliseconds.
    pub time: String,
}

/// A write asked of the service (from an MQTT `set` topic): checked by the bus worker as
/// `vfd write` checks it, and against the plant file's allow-list, before anything is sent.
/// Its outcome comes back as [`Event::Written`] with the same `id`.
#[derive(Debug, Clone)]
pub struct WriteRequest {
    /// The bus's name.
    pub bus: String,
    /// The station's name.
    pub drive: String,
    /// The register as named in the topic (a code, id or name).
    pub register: String,
    /// The value (`50`, `50 Hz`, a code name, bit fields such as
    /// `command_enabled,frequency_enabled,run`).
    pub value: String,
    /// The request's number in this run ([`super::run_id::next`]), echoed in the outcome.
    pub id: u64,
    /// Where it goes, resolved from the names once ([`WriteRouter::send`] resolves a
    /// request that comes without it).
    pub target: Option<Target>,
}

impl WriteRequest {
    /// A request to write `value` to `register` of `drive` on `bus`, numbered `id`.
    pub fn new(
        bus: impl Into<String>,
        drive: impl Into<String>,
        register: impl Into<String>,
        value: impl Into<String>,
        id: u64,
    ) -> WriteRequest {
        WriteRequest {
            bus: bus.into(),
            drive: drive.into(),
            register: register.into(),
            value: value.into(),
            id,
            target: None,
        }
    }
}

/// Why a write request could not be handed to a bus worker.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Unroutable {
    /// The plant has no bus of that name; its buses' names, sorted.
    NoBus(Vec<String>),
    /// The bus's worker has stopped.
    Stopped,
}

/// A write request that could not be handed to a bus worker, and why.
#[derive(Debug)]
pub struct NotSent {
    /// Why.
    pub why: Unroutable,
    /// The request, with its target where it was resolved.
    pub request: Box<WriteRequest>,
}

/// Where write requests go: each bus worker's queue, by the bus's index in the plant,
/// and the plant's names resolved ([`Directory`]).
#[derive(Debug, Clone, Default)]
pub struct WriteRouter {
    /// The workers' queues, in the plant's order.
    queues: Vec<Sender<WriteRequest>>,
    /// The plant's names.
    directory: Arc<Directory>,
}

impl WriteRouter {
    /// The router of `plant`, its names resolved, and the workers' ends of its queues (one
    /// per bus, in the plant's order).
    pub fn new(plant: &Plant) -> (WriteRouter, Vec<Receiver<WriteRequest>>) {
        let (queues, receivers) = plant
            .buses
            .iter()
            .map(|_| std::sync::mpsc::channel())
            .unzip();
        let router = WriteRouter {
            queues,
            directory: Arc::new(Directory::new(plant)),
        };
        (router, receivers)
    }

    /// The plant's names, resolved.
    pub fn directory(&self) -> &Directory {
        &self.directory
    }

    /// Hands `request` to its bus's worker, resolving its names first unless it comes
    /// with its [`Target`].
    pub fn send(&self, mut request: WriteRequest) -> Result<(), NotSent> {
        let target = match request.target {
            Some(target) => target,
            None => {
                match self
                    .directory
                    .target(&request.bus, &request.drive, &request.register)
                {
                    Some(target) => target,
                    None => {
                        let known = self.directory.bus_names();
                        return Err(NotSent {
                            why: Unroutable::NoBus(known.into_iter().map(str::to_owned).collect()),
                            request: Box::new(request),
                        });
                    }
                }
            }
        };
        request.target = Some(target);
        let Some(queue) = self.queues.get(target.bus) else {
            return Err(NotSent {
                why: Unroutable::Stopped,
                request: Box::new(request),
            });
        };
        queue.send(request).map_err(|error| NotSent {
            why: Unroutable::Stopped,
            request: Box::new(error.0),
        })
    }
}
