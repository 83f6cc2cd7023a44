//! The IR's types: one drive, resolved, ordered and typed, as plain serialisable data.
//!
//! Every emitter reads only these types. They hold facts (numbers, names, enums, the
//! runtime's own layout and frame-meaning values), never prose built for people: the
//! Markdown emitter words ranges, meanings and layouts itself. A drive starts at
//! [`DriveIr`] (`drive.rs`); each part of it has a module of its own.

mod behaviour;
mod bitfields;
mod code_tables;
mod conversions;
mod drive;
mod error_codes;
mod examples;
mod protocol;
mod register;
mod scaling;
mod sequences;
mod serial;

pub use crate::parse::model::PrintedRejection;
pub use crate::parse::model::{
    BitOrder, Duplex, InferredFact, Synchronisation, TimingField, Topology,
    WarningModel as WarningIr,
};
pub use behaviour::{
    AmountIr, BehaviourIr, BitRefIr, CommandCodesIr, RefusalsIr, StatusBitsIr, StatusStateIr,
    TripSlotIr,
};
pub use bitfields::{BitExampleIr, BitIr, BitfieldIr};
pub use code_tables::{CodeTableIr, CodeValueIr, LineSettingIr};
pub use conversions::{ConversionInputIr, ConversionIr};
pub use drive::{DriveIr, ForbiddenCombinationIr, ManualErratumIr, PersistenceIr};
pub use error_codes::{ErrorCodeIr, ErrorCodesIr};
pub use examples::{ExampleIr, FrameIr, PrintedIr, UnansweredIr, ValueExampleIr};
pub use protocol::{
    CommandIr, ErrorTableIr, PagesDocIr, ProtocolFileIr, ProtocolIr, UnsupportedFunctionIr,
};
pub use register::{BoundIr, RegisterIr, SpecialValueIr, ValueKind};
pub use scaling::{ReferenceScalingIr, ScaleByIr, ScaleChoiceIr, ScalingModeIr, SpanEndIr};
pub use sequences::{SequenceCallIr, SequenceIr, SequenceResultIr, SequenceStepIr};
pub use serial::{AddressingIr, LineIr, PortIr, PortsIr, ProtocolLineIr, SerialIr};
