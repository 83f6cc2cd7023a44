//! The description format as serde types: what a drive file and a protocol file may say.
//!
//! These types mirror the YAML one to one (unknown keys are errors). Meaning is checked
//! later, in [`crate::validate`]; nothing here resolves references. A drive file's types
//! start at [`DriveFile`] (`drive.rs`), a protocol file's at [`ProtocolFile`]
//! (`protocol_file.rs`); each section of the files has a module of its own.

mod behaviour;
mod bitfields;
mod code_tables;
mod commands;
mod conversions;
mod defaults;
mod drive;
mod error_codes;
mod examples;
mod parts;
mod protocol_file;
mod protocol_ref;
mod range;
mod register;
mod scaling;
mod sequences;
mod serial;
mod write_rules;

pub use behaviour::{BehaviourModel, BitRefModel, RefusalsModel};
pub use code_tables::{CodeTableModel, LineFormatModel};
pub use commands::{CodeModel, CommandModel, LowercaseMeans, PreStepKind, PreStepModel};
pub use conversions::ConditionValueModel;
pub use drive::DriveFile;
pub use error_codes::{CodeNotationModel, ErrorCodeModel, ProtocolErrorCodesModel};
pub use examples::{BytesModel, ExampleModel, ExpectModel, FrameModel, PrintedRejection};
pub use parts::{
    BitsModel, BroadcastAddressModel, CountsModel, OptionalModel, PartModel, PartRefModel,
    OR_SCALAR,
};
pub use protocol_file::{ProtocolFile, VariantLiteralModel};
pub use protocol_ref::{BlockModel, PageRangeModel, PagesModel, ProtocolRef};
pub use range::{BoundModel, RangeModel};
pub use register::{InferredFact, RegisterModel, WarningModel, WireNumberModel};
pub use sequences::{Sender, SequenceModel, Shown};
pub use serial::{BitOrder, Duplex, Synchronisation, TimingField, Topology};
