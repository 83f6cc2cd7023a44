//! The service (what `vfd serve` runs), embeddable in any program: a plant in
//! ([`crate::plant::Plant`]), events and write results out. One worker thread per bus
//! polls its stations and carries out writes (`worker`); its events go through a bounded
//! queue ([`report`]) to whoever reads them ([`ServiceCore::new`] gives the receiving end).
//! The outputs (JSON lines, MQTT) and inputs (MQTT `set`, standard input) are the tool's.

mod directory;
pub mod event;
mod health;
pub mod report;
pub mod request_text;
pub mod run_id;
mod schedule;
pub mod service_core;
mod station;
#[cfg(test)]
mod tests;
mod worker;
mod write;

pub use service_core::{Running, ServiceCore, StartError};

/// The `log` target of the service's own records.
pub const LOG_TARGET: &str = "vfd::serve";
