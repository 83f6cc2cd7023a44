//! `vfd serve`: a plant's buses polled by one worker each, their events handed to the
//! outputs (`--jsonl`, MQTT). (Placeholder on the `mqtt` branch: the lead's core replaces
//! this file; only the modules are declared here.)

#[allow(dead_code)] // until the service core uses it
pub mod event;
#[allow(dead_code, unused_imports)] // used by the service core, wired in by the lead
pub mod mqtt;
