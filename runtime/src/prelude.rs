//! The names most code using a generated drive module needs: `use vfd_runtime::prelude::*;`.
//!
//! It brings the register traits into scope, so every register has `R::read()`,
//! `R::read_at(index)`, `R::write_ram(value)`, `R::write_ram_at(index, value)`,
//! `R::write_persistent(value)` and `R::write_persistent_at(index, value)`, plus the
//! request, error and master types and the unit quantities.

pub use crate::error::{DecodeError, DecodeErrorKind, EncodeError, ValueError};
pub use crate::protocol::Protocol;
pub use crate::register::{Persistable, Register, RegisterValue, Request, Writable};
pub use crate::transaction::{Master, Reading, TransactionError, TransactionErrorKind};
pub use crate::transport::Transport;
pub use crate::units::{Amperes, Hertz, Hours, Kilowatts, Percent, Rpm, Seconds, Volts};
