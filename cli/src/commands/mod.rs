//! The commands wing of `vfd`: one module per command or family of commands, each taking
//! its arguments and the catalogue and printing what it has to say (`read`, `write`,
//! `watch`, `block`, `backup`, `restore`, `list`, `info`, `encode`, `decode`, `ports`,
//! `generate`, `check`, and the control profile's `run`, `stop`, `reset`, `state`). The drives, lines, write check and errors they use are the
//! library's (`vfd_bus`).

pub mod backup;
pub mod block;
pub mod control;
pub mod decode;
pub mod describe;
pub mod encode;
pub mod generate;
pub mod poll;
pub mod ports;
pub mod watch;
