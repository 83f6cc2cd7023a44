//! A plant as `vfd serve` runs it: buses, the stations on each, what is polled and how
//! often, and which registers may be written. Loaded and checked from a plant file by
//! [`super::load`]; everything here is resolved (drives, protocols, registers, line
//! settings), so the service itself never looks a name up.

use std::path::PathBuf;
use std::time::Duration;
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::{DriveInfo, Port, Protocol, RegisterInfo};

/// A checked plant file.
#[derive(Debug, Clone)]
pub struct Plant {
    /// The file it was loaded from.
    pub path: PathBuf,
    /// The buses, in the file's order; names are unique.
    pub buses: Vec<Bus>,
    /// What the check found valid but probably not meant (a drive that polls nothing),
    /// for the service to print when it starts; `vfd serve --check` prints them too.
    pub warnings: vfd_codegen::Diagnostics,
}

/// One serial line (or serial device server) and the stations on it.
#[derive(Debug, Clone)]
pub struct Bus {
    /// The bus's name as it appears in topics and records (`[a-z0-9_-]+`).
    pub name: String,
    /// A serial device (`/dev/ttyUSB0`, `COM3`, a pseudo-terminal) or `tcp://HOST:PORT`.
    pub port: String,
    /// Line settings: the bus's own where given, else its first station's drive's factory
    /// settings.
    pub settings: SerialSettings,
    /// The drive's processing time in each reply timeout, where the plant overrides the
    /// manuals' (`timeout_ms`).
    pub timeout: Option<Duration>,
    /// Extra silence between frames, for a slow gateway (`gap_ms`).
    pub min_gap: Option<Duration>,
    /// Added to every reply timeout for the adapter and host (`host_latency_ms`).
    pub host_latency: Option<Duration>,
    /// Repeats of a read after a lost or garbled reply (never of a write). Default 0.
    pub retries: u8,
    /// Failed exchanges in a row that mark a station offline. Default 3.
    pub offline_after: u32,
    /// The first wait before an offline station is tried again; doubled after each failed
    /// try. Default 1 s.
    pub backoff_first: Duration,
    /// The longest wait between tries of an offline station. Default 60 s.
    pub backoff_cap: Duration,
    /// The stations, in the file's order; names and station addresses are unique on a bus.
    pub stations: Vec<Station>,
}

/// One drive on a bus.
#[derive(Debug, Clone)]
pub struct Station {
    /// The drive's name in topics and records (`[a-z0-9_-]+`), unique on its bus.
    pub name: String,
    /// The drive model (a built-in id or a drive file).
    pub drive: &'static DriveInfo,
    /// How a command line names the drive model so that it is found again (its id, or the
    /// path of its drive file), for messages.
    pub drive_name: String,
    /// The protocol spoken, in the variant the plant names.
    pub protocol: &'static Protocol,
    /// The station address (`None`: the protocol sends none).
    pub address: Option<u8>,
    /// The drive's port the bus is on, for drives with several.
    pub port: Option<Port>,
    /// What is read, and how often. A register appears once per station.
    pub polls: Vec<Poll>,
    /// What may be written. Writes of anything else are refused before a frame is sent.
    pub writes: Vec<Allowed>,
}

/// A register read at a fixed interval.
#[derive(Debug, Clone)]
pub struct Poll {
    /// The register.
    pub register: &'static RegisterInfo,
    /// How often it is read.
    pub every: Duration,
}

/// A register the plant allows to be written.
#[derive(Debug, Clone)]
pub struct Allowed {
    /// The register (writable, per the manual).
    pub register: &'static RegisterInfo,
    /// Writes go to RAM and EEPROM (`persistent: true` in the plant file); else RAM only.
    pub persistent: bool,
}
