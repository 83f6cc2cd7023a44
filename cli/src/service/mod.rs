//! The service wing of `vfd`: `vfd serve`, its plant files (`plant`), the bus workers,
//! their outputs and MQTT (`serve`), and its command-line options (`serve_args`).

pub mod plant;
pub mod serve;
pub mod serve_args;
