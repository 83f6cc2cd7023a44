//! The service wing of `vfd`: `vfd serve` around the library's service core
//! ([`vfd_bus::service`]): its plant check (`plant_check`), its outputs and inputs (JSON
//! lines, MQTT, standard input: `serve`), and its command-line options (`serve_args`).

pub mod plant_check;
pub mod serve;
pub mod serve_args;
