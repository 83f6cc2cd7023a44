//! Drives on RS-485 lines, for any Rust program: what the `vfd` tool and its service
//! (`vfd serve`) run on, as a library. Everything about a drive comes from its
//! [`vfd_runtime::DriveInfo`] (compiled in, or compiled from a drive file when the program
//! starts): no drive or protocol is named here.
//!
//! # The design in brief
//!
//! - A **catalogue** ([`Catalogue`]) is the drives a program knows: the ones compiled in,
//!   the drive files of some folders, and drive files named by their path. It is a value
//!   (no process-global state): a drive file is compiled once per catalogue, its run-time
//!   values built once, and found again by its path. Names people write (a drive id, a
//!   register's code, address or name, a protocol, a variant, a port) are found through it
//!   ([`lookup`]) when a command or a plant is set up, and never again after.
//! - A **line** ([`Line`]) is a byte pipe to the drives: a serial port, a TCP connection to
//!   a serial device server, a Unix pseudo-terminal, or any [`vfd_runtime::transport::Transport`]
//!   (an in-memory pair, a traced line).
//! - A **station** is one drive on a line: a master ([`vfd_runtime::transaction::Master`])
//!   made from a drive, a protocol (in its variant), the drive's port and an address,
//!   reading and writing registers by their [`vfd_runtime::RegisterInfo`], found once when
//!   a command or a plant is set up. A station alone holds its line (`vfd read`); on a bus
//!   it holds [`Line::Away`] until its turn ([`OnLine`]).
//! - A **bus** ([`Bus`]) owns one line and the stations on it, and keeps the line's timing
//!   itself: it lends the line to the station that speaks next, telling its master when the
//!   line was last busy, and notes which station spoke last, so the frame gap is kept
//!   across stations and no caller copies timing between masters.
//! - **One write check** ([`mod@write_check`]) says whether a write may be sent: the register's
//!   access and storage (RAM or EEPROM), the port, the value's range and the bounds other
//!   registers set (read from the drive), the manual's forbidden combinations, and a plant's
//!   allow-list. It refuses with a typed [`Refusal`], before anything is sent.
//! - **One error** ([`Error`], [`ErrorKind`]) says how a read or a write ended when it did
//!   not succeed: no reply in time, a damaged reply, the drive's error reply with the
//!   manual's code and meaning, a reply to something else, a failed port, refused before
//!   sending, the station offline. Each kind has a stable snake_case name for JSON.
//! - **One back-off** ([`BackOff`]): the wait before trying again, doubling to a cap, for a
//!   port to reopen, an offline station to try, a broker to reconnect to.
//! - A **session** ([`Session`]) is one station's reads and writes by register: values
//!   scaled as the drive's selector registers say, writes checked first, the manual's
//!   forbidden combinations kept; it ends in a typed [`SessionError`].
//! - A **plant** ([`Plant`], [`mod@plant`]) is the buses, stations, poll lists and write
//!   allow-lists a service runs, read from a plant file with file:line:column diagnostics
//!   and resolved once.
//! - The **service** ([`ServiceCore`], [`mod@service`]) runs a plant: one worker thread per
//!   bus polls its stations, takes stations offline and back, and carries out write
//!   requests; what happens comes out as [`service::event::Event`]s. `vfd serve` is this
//!   with JSON lines and MQTT around it.
//!
//! # Embedding the service
//!
//! ```no_run
//! use std::sync::atomic::AtomicBool;
//! use std::sync::Arc;
//! use vfd_bus::service::event::Event;
//! use vfd_bus::{Catalogue, ServiceCore};
//!
//! let catalogue = Catalogue::new();
//! let plant = vfd_bus::plant::load("plant.yaml".as_ref(), &catalogue)
//!     .map_err(|problems| problems.to_string())?;
//! let (core, events) = ServiceCore::new(&plant);
//! let stop = Arc::new(AtomicBool::new(false));
//! let running = core.start(stop.clone())?;
//! for event in events.iter().take(100) {
//!     if let Event::Reading(reading) = event {
//!         println!("{}/{} {}: {:?} {}", reading.bus, reading.drive, reading.code, reading.value, reading.unit);
//!     }
//! }
//! stop.store(true, std::sync::atomic::Ordering::SeqCst);
//! running.join();
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Library code never prints: what it has to say goes through the `log` facade, or comes
//! back as values (errors with a message and, where one helps, a hint on what to do).

pub mod back_off;
pub mod bus;
pub mod catalogue;
pub mod control;
pub mod error;
pub mod line;
pub mod lookup;
pub mod plant;
pub mod record;
pub mod service;
pub mod session;
pub mod session_error;
pub mod setup_error;
pub mod storage;
pub mod trip_flag;
pub mod values;
pub mod write_check;
pub mod write_value;

pub use back_off::BackOff;
pub use bus::{Bus, OnLine};
pub use catalogue::Catalogue;
pub use error::{Error, ErrorKind};
pub use line::Line;
pub use plant::Plant;
pub use service::ServiceCore;
pub use session::Session;
pub use session_error::SessionError;
pub use setup_error::SetupError;
pub use write_check::{Reason, Refusal};
