//! Runtime support for drive APIs generated from YAML descriptions: frame layouts
//! interpreted as data, checksums, typed register values, transactions and transports.
//!
//! Nothing here names a drive. A generated drive module supplies `static` data (frame
//! layouts, register tables, error tables) and this crate does the work:
//!
//! * [`kinds`] holds the enumerations descriptions name (access, command kinds, data types,
//!   address spaces, units) and [`info`] the register and error-code table entries;
//! * [`layout`] describes a frame as a list of parts (literals, fields, checksums);
//! * [`codec`] encodes and decodes any such layout without heap allocation;
//! * [`protocol`] ties layouts to commands (read, RAM write, persistent write) and error replies;
//! * [`register`] holds the traits that make register access typed (each register gets
//!   `R::read()`, `R::write_ram(value)`, ... from them) and the protocol-independent
//!   [`Request`]; [`units`] the quantities and value conversions (scaling, ranges);
//! * [`transaction`] runs request/reply exchanges with timeouts derived from the baud rate;
//! * [`transport`] moves bytes: serial ports, pseudo-terminals and in-memory pipes.
//!
//! `use vfd_runtime::prelude::*` brings the register traits and the common types into scope.
//!
//! Modules only use modules below them (a test in the workspace keeps it so): `layout`,
//! `kinds`, `serial` and `scaling` use nothing; `info` the first two; then `error`, `codec`,
//! `register`, `units`, `protocol`, `drive`, `transport`, `transaction` and `prelude`.
//! Types are re-exported where they used to live (`protocol::DataType`,
//! `protocol::Request`, `register::RegisterInfo`, `units::Unit`) and at the crate root.
//!
//! # Features
//!
//! * `serial` (default): `transport::SerialTransport`, over the `serialport` crate.
//! * `pty` (default, Unix only): `transport::PseudoTerminal` and `transport::PtyTransport`,
//!   over the `nix` crate.
//! * `serde`: `Serialize` and `Deserialize` for the enumerations description files name,
//!   spelled as in those files, and `Serialize` for layout and protocol data.
//!
//! Without default features the crate is portable and needs no operating-system crate:
//! the code generator uses it that way.
#![warn(missing_docs)]

pub mod checksum;
pub mod codec;
pub mod drive;
pub mod error;
pub mod info;
pub mod kinds;
pub mod layout;
pub mod prelude;
pub mod protocol;
pub mod register;
pub mod scaling;
#[cfg(all(test, feature = "serde"))]
mod serde_names;
pub mod serial;
pub mod transaction;
pub mod transport;
pub mod units;

pub use codec::{FieldValue, FrameValues, Roles};
pub use drive::DriveInfo;
pub use error::{DecodeError, DecodeErrorKind, EncodeError, ValueError};
pub use info::{ErrorCodeInfo, RegisterInfo};
pub use kinds::{Access, CommandKind, DataType, Space};
pub use layout::{
    BitsSpec, ChecksumAlgorithm, ChecksumSpec, Counts, FieldSpec, Format, FrameLayout, LengthSpec,
    Part, Presence, Role, SizedBy, WordSpec,
};
pub use protocol::{AddressMap, CommandSpec, PreStep, Protocol, Reply};
pub use register::{Persistable, Register, RegisterValue, Request, Writable};
pub use transaction::{TransactionError, TransactionErrorKind};
