//! The description format as serde types: what a drive file and a protocol file may say.
//!
//! These types mirror the YAML one to one (unknown keys are errors). Meaning is checked
//! later, in [`crate::validate`]; nothing here resolves references.

use serde::de::value::MapAccessDeserializer;
use serde::de::{self, MapAccess, Unexpected, Visitor};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use vfd_runtime::serial::Parity;
use vfd_runtime::{
    Access, ChecksumAlgorithm, CommandKind, DataType, DecodeErrorKind, Format, Role, SizedBy,
    Space, TakesEffect,
};

/// A drive file (`drives/<id>.yaml`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriveFile {
    pub drive: DriveMeta,
    pub serial: SerialModel,
    pub addressing: AddressingModel,
    pub protocols: Vec<ProtocolRef>,
    pub error_codes: ErrorCodesModel,
    #[serde(default)]
    pub codes: Vec<CodeTableModel>,
    #[serde(default)]
    pub bitfields: Vec<BitfieldModel>,
    pub registers: Vec<RegisterModel>,
    #[serde(default)]
    pub value_examples: Vec<ValueExampleModel>,
    pub reference_scaling: Option<ReferenceScalingModel>,
    #[serde(default)]
    pub manual_errata: Vec<ManualErratumModel>,
    #[serde(default)]
    pub examples: Vec<ExampleModel>,
    /// Safety warnings the manual gives (or that follow from its examples) for the drive as
    /// a whole, shown prominently on the reference page.
    #[serde(default)]
    pub warnings: Vec<WarningModel>,
}

/// A safety warning: what can go wrong, and where the manual says so.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WarningModel {
    /// The warning, in English (the manual's Chinese may follow in brackets).
    pub text: String,
    /// The manual section it comes from; empty when it follows from the description only.
    #[serde(default)]
    pub source: String,
}

/// The line-level facts of the serial link (the manual's specification table).
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct LineModel {
    /// Manual section these facts come from.
    #[serde(default)]
    pub source: String,
    /// `half` or `full` duplex (传输方式).
    pub duplex: Option<Duplex>,
    /// Who controls the line (连接控制): `master_slave` (one master polls the drives).
    pub topology: Option<Topology>,
    /// `asynchronous` or `synchronous` transmission (同步性).
    pub synchronisation: Option<Synchronisation>,
    /// Order of the bits within a character (位发送次序): `lsb_first` or `msb_first`.
    pub bit_order: Option<BitOrder>,
}

/// Half or full duplex.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Duplex {
    /// One direction at a time (two-wire RS-485).
    Half,
    /// Both directions at once (four-wire).
    Full,
}

/// Who controls the line.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Topology {
    /// Centralised control (集中控制): one master sends, the addressed drive answers.
    MasterSlave,
    /// Any station may start an exchange.
    MultiMaster,
}

/// Character synchronisation.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Synchronisation {
    /// Start and stop bits frame each character.
    Asynchronous,
    /// A shared clock frames the characters.
    Synchronous,
}

/// Bit order within a character.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BitOrder {
    /// Least significant bit first (the UART convention).
    LsbFirst,
    /// Most significant bit first.
    MsbFirst,
}

/// A timing value that can be marked as assumed (not from the manual).
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum TimingField {
    /// `startup_delay_ms`.
    StartupDelayMs,
    /// `frame_abandon_ms`.
    FrameAbandonMs,
    /// `processing_allowance_ms`.
    ProcessingAllowanceMs,
}

/// A register fact that can be marked as inferred (the description's reading, not the
/// manual's statement).
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum InferredFact {
    /// The English name.
    Name,
    /// The unit.
    Unit,
    /// The step (`scale`).
    Scale,
    /// The range.
    Range,
    /// The default.
    Default,
    /// The access (read-only, read-write, write-only).
    Access,
    /// The data type (word, double word, ...).
    DataType,
    /// `ram_only`.
    RamOnly,
    /// `writable_while_running`.
    WritableWhileRunning,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriveMeta {
    pub id: String,
    pub vendor: String,
    pub model: String,
    pub name: String,
    #[serde(default)]
    pub name_zh: String,
    pub manual: String,
    #[serde(default)]
    pub description: String,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SerialModel {
    pub source: String,
    #[serde(default)]
    pub note: String,
    pub baud_rates: Vec<u32>,
    pub parities: Vec<Parity>,
    pub data_bits: u8,
    pub stop_bits_sent: u8,
    pub stop_bits_received: u8,
    pub default: SerialDefaultModel,
    pub timing: TimingModel,
    /// Line-level facts from the manual's specification table (duplex, topology,
    /// synchronisation, bit order); each may be left out.
    pub line: Option<LineModel>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SerialDefaultModel {
    pub baud: u32,
    pub parity: Parity,
    pub data_bits: u8,
    pub stop_bits: u8,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimingModel {
    pub startup_delay_ms: u64,
    pub frame_abandon_ms: u64,
    pub processing_allowance_ms: u64,
    /// Timings that are placeholders or our own assumption rather than the manual's
    /// statement: `[startup_delay_ms, frame_abandon_ms, processing_allowance_ms]`.
    #[serde(default)]
    pub assumed: Vec<TimingField>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AddressingModel {
    pub min: u8,
    pub max: u8,
    #[serde(default)]
    pub note: String,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProtocolRef {
    pub id: String,
    pub uses: String,
    pub source: String,
    /// How this drive numbers registers on the wire, per address space (overrides the
    /// protocol file): `{ parameter: { multiply: 10, offset: -1 }, coil: { multiply: 1, offset: -1 } }`.
    #[serde(default)]
    pub address_maps: BTreeMap<String, AddressMapModel>,
    /// Steps this drive needs before some requests (added to the protocol file's).
    #[serde(default)]
    pub pre_steps: Vec<PreStepModel>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErrorCodesModel {
    pub source: String,
    pub codes: Vec<ErrorCodeModel>,
    #[serde(default)]
    pub silent: Vec<String>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErrorCodeModel {
    pub code: u32,
    pub id: String,
    pub name: String,
    #[serde(default)]
    pub name_zh: String,
    pub meaning: String,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CodeTableModel {
    pub id: String,
    pub name: String,
    #[serde(default)]
    pub name_zh: String,
    pub source: String,
    #[serde(default = "yes")]
    pub exhaustive: bool,
    #[serde(default)]
    pub note: String,
    pub values: Vec<CodeValueModel>,
}

fn yes() -> bool {
    true
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CodeValueModel {
    pub value: u32,
    pub id: String,
    pub name: String,
    #[serde(default)]
    pub name_zh: String,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BitfieldModel {
    pub id: String,
    pub name: String,
    #[serde(default)]
    pub name_zh: String,
    pub source: String,
    #[serde(default)]
    pub note: String,
    pub fields: Vec<BitModel>,
    #[serde(default)]
    pub examples: Vec<BitExampleModel>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BitModel {
    /// A one-bit field.
    pub bit: Option<u8>,
    /// A multi-bit field as `"msb:lsb"`.
    pub bits: Option<String>,
    pub id: Option<String>,
    #[serde(default)]
    pub reserved: bool,
    #[serde(default)]
    pub name: String,
    #[serde(default)]
    pub name_zh: String,
    #[serde(default)]
    pub zero: String,
    #[serde(default)]
    pub one: String,
    #[serde(default)]
    pub zero_zh: String,
    #[serde(default)]
    pub one_zh: String,
    /// Code table giving the meanings of a multi-bit field's values.
    pub code_table: Option<String>,
    #[serde(default)]
    pub note: String,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BitExampleModel {
    pub value: u32,
    pub set: Vec<String>,
    pub description: String,
    pub source: String,
}

/// A range bound: a number in engineering units, or the code of another register.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum BoundModel {
    Number(f64),
    Register(String),
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RangeModel {
    pub min: BoundModel,
    pub max: BoundModel,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegisterModel {
    pub address: u32,
    pub id: String,
    pub code: String,
    pub name: String,
    #[serde(default)]
    pub name_zh: String,
    #[serde(default)]
    pub description: String,
    #[serde(default)]
    pub unit: Option<String>,
    #[serde(default)]
    pub scale: Option<f64>,
    #[serde(default)]
    pub signed: bool,
    pub range: Option<RangeModel>,
    pub default: Option<f64>,
    #[serde(default)]
    pub access: Option<Access>,
    #[serde(default)]
    pub ram_only: bool,
    #[serde(default)]
    pub writable_while_running: bool,
    #[serde(default)]
    pub panel_only: bool,
    #[serde(default)]
    pub takes_effect: Option<TakesEffect>,
    pub bitfield: Option<String>,
    pub code_table: Option<String>,
    /// `word` (default), `double_word`, `bit` or `text`.
    pub data_type: Option<DataType>,
    /// `parameter` (default) or `coil`.
    pub space: Option<Space>,
    /// Number of elements of an array (indexed) parameter.
    pub array: Option<u8>,
    pub source: String,
    #[serde(default)]
    pub note: String,
    /// Facts of this register that are inferred rather than stated by the manual:
    /// `[unit, scale, writable_while_running, ...]`; the page marks them.
    #[serde(default)]
    pub inferred: Vec<InferredFact>,
    /// Safety warnings about writing or using this register.
    #[serde(default)]
    pub warnings: Vec<WarningModel>,
}

/// A reference word that is a percentage of a span chosen by a selector register.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceScalingModel {
    pub source: String,
    pub full_scale_raw: u32,
    pub applies_to: Vec<String>,
    pub selector: String,
    #[serde(default)]
    pub note: String,
    pub modes: Vec<ScalingModeModel>,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ScalingModeModel {
    pub selector: u32,
    pub low: BoundModel,
    pub high: BoundModel,
    pub description: String,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ValueExampleModel {
    pub register: String,
    pub value: f64,
    pub raw: u32,
    pub source: String,
    pub description: String,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ManualErratumModel {
    pub source: String,
    pub printed: String,
    pub corrected: String,
    pub reason: String,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExampleModel {
    pub id: String,
    pub protocol: String,
    pub source: String,
    pub description: String,
    #[serde(default)]
    pub description_zh: String,
    pub request: Option<FrameModel>,
    pub reply: Option<FrameModel>,
    /// The data word's value in the register's engineering unit.
    pub value: Option<f64>,
}

/// Frame bytes, written as text (`ascii`) or as hex pairs (`hex`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BytesModel {
    pub ascii: Option<String>,
    pub hex: Option<String>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameModel {
    pub ascii: Option<String>,
    pub hex: Option<String>,
    pub expect: ExpectModel,
    /// What the manual prints, when it differs from the bytes above (an erratum).
    pub printed: Option<BytesModel>,
    pub erratum: Option<String>,
    pub printed_rejected_as: Option<DecodeErrorKind>,
}

#[derive(Debug, Clone, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ExpectModel {
    pub address: Option<u8>,
    pub command: Option<CodeModel>,
    /// Register number as the drive file numbers it (before the protocol's address map).
    pub register: Option<u32>,
    /// Register number on the wire, for frames addressing no described register (the FC
    /// Modbus index register 0008h).
    pub wire_register: Option<u32>,
    pub index: Option<u32>,
    pub data: Option<u32>,
    pub error_code: Option<u32>,
    /// Process words (control word and reference, or status word and output value).
    pub process: Option<[u32; 2]>,
    pub text: Option<String>,
    #[serde(default)]
    pub tripped: bool,
}

/// A shared protocol file (`drives/protocols/<id>.yaml`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProtocolFile {
    pub protocol: ProtocolMeta,
    #[serde(default)]
    pub parts: BTreeMap<String, PartModel>,
    pub layouts: BTreeMap<String, Vec<PartRefModel>>,
    pub commands: Vec<CommandModel>,
    pub error_reply: Option<String>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProtocolMeta {
    pub id: String,
    pub name: String,
    #[serde(default)]
    pub name_zh: String,
    #[serde(default)]
    pub description: String,
    pub text: bool,
    pub max_frame_len: u16,
    #[serde(default)]
    pub lowercase_means_tripped: bool,
    #[serde(default)]
    pub default_optional_parts: Vec<String>,
    /// Steps some requests need first.
    #[serde(default)]
    pub pre_steps: Vec<PreStepModel>,
    /// Process words sent when the caller gives none.
    pub default_process: Option<[u16; 2]>,
    /// Silence between frames in character times.
    #[serde(default)]
    pub frame_gap_chars: f32,
}

/// A layout entry: the name of a shared part, or a part written in place.
#[derive(Debug, Clone)]
pub enum PartRefModel {
    Named(String),
    Inline(Box<PartModel>),
}

impl<'de> Deserialize<'de> for PartRefModel {
    /// Written by hand so that a mistake inside an inline part is reported as itself
    /// ("unknown field `fromat`") rather than as "no variant matched", with the path and
    /// position of the key at fault.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct EntryVisitor;
        impl<'de> Visitor<'de> for EntryVisitor {
            type Value = PartRefModel;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("the name of a part or a part written as `{ ... }`")
            }
            fn visit_str<E: de::Error>(self, name: &str) -> Result<PartRefModel, E> {
                Ok(PartRefModel::Named(name.to_owned()))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<PartRefModel, A::Error> {
                PartModel::deserialize(MapAccessDeserializer::new(map))
                    .map(|part| PartRefModel::Inline(Box::new(part)))
            }
        }
        deserializer.deserialize_any(EntryVisitor)
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartModel {
    pub literal: Option<String>,
    pub literal_hex: Option<String>,
    /// A value field: its role.
    pub field: Option<Role>,
    pub checksum: Option<ChecksumAlgorithm>,
    /// A word made of bit fields: its format (`u16be`).
    pub word: Option<Format>,
    /// A computed length: its format (`u8`).
    pub length: Option<Format>,
    /// Name for error messages and docs (defaults to the role or the part's key).
    pub name: Option<String>,
    pub format: Option<Format>,
    pub width: Option<u8>,
    pub min_width: Option<u8>,
    /// `rest` (up to the fixed parts before the frame end) or `length` (a length part covers
    /// it); left out, the format sizes the field.
    pub size: Option<SizedBy>,
    pub optional: Option<OptionalModel>,
    #[serde(default)]
    pub allowed: Vec<CodeModel>,
    #[serde(default)]
    pub fold_case: bool,
    pub marker: Option<String>,
    pub covers_from: Option<String>,
    /// Bit fields of a `word`.
    #[serde(default)]
    pub fields: Vec<BitsModel>,
    /// What a `length` counts.
    pub counts: Option<CountsModel>,
    pub times: Option<u8>,
    pub per: Option<u8>,
}

/// A command code or allowed value: one character (`R`) or a number (`0x03`).
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum CodeModel {
    Number(u32),
    Text(String),
}

impl CodeModel {
    /// The code's value: a character's byte, or the number.
    pub fn value(&self) -> Option<u32> {
        match self {
            CodeModel::Number(n) => Some(*n),
            CodeModel::Text(text) => match text.as_bytes() {
                [byte] => Some(u32::from(*byte)),
                _ => None,
            },
        }
    }

    /// As written.
    pub fn shown(&self) -> String {
        match self {
            CodeModel::Number(n) => format!("{n:#X}"),
            CodeModel::Text(text) => text.clone(),
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BitsModel {
    pub field: Role,
    pub name: Option<String>,
    /// `"msb:lsb"` or a single bit number.
    pub bits: String,
    #[serde(default)]
    pub allowed: Vec<CodeModel>,
}

/// What a length counts: `{ from: part, through: part }` or `data_size`.
#[derive(Debug, Clone, PartialEq)]
pub enum CountsModel {
    Parts { from: String, through: String },
    DataSize,
}

impl<'de> Deserialize<'de> for CountsModel {
    /// By hand, so that a mistake names the value or the key at fault.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Parts {
            from: String,
            through: String,
        }
        struct CountsVisitor;
        impl<'de> Visitor<'de> for CountsVisitor {
            type Value = CountsModel;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("`data_size` or `{ from: part, through: part }`")
            }
            fn visit_str<E: de::Error>(self, value: &str) -> Result<CountsModel, E> {
                match value {
                    "data_size" => Ok(CountsModel::DataSize),
                    _ => Err(E::invalid_value(Unexpected::Str(value), &self)),
                }
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<CountsModel, A::Error> {
                let Parts { from, through } = Parts::deserialize(MapAccessDeserializer::new(map))?;
                Ok(CountsModel::Parts { from, through })
            }
        }
        deserializer.deserialize_any(CountsVisitor)
    }
}

/// Whether a part may be left out: `true`/`false`, or for fields a presence rule
/// (`if_format_matches`, `{ if_byte_at_most: 0x3F }`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OptionalModel {
    Flag(bool),
    IfFormatMatches,
    IfByteAtMost(u8),
}

impl<'de> Deserialize<'de> for OptionalModel {
    /// By hand, so that a mistake names the value at fault.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(deny_unknown_fields)]
        struct ByteAtMost {
            if_byte_at_most: u8,
        }
        struct OptionalVisitor;
        impl<'de> Visitor<'de> for OptionalVisitor {
            type Value = OptionalModel;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("true, false, `if_format_matches` or `{ if_byte_at_most: N }`")
            }
            fn visit_bool<E: de::Error>(self, flag: bool) -> Result<OptionalModel, E> {
                Ok(OptionalModel::Flag(flag))
            }
            fn visit_str<E: de::Error>(self, value: &str) -> Result<OptionalModel, E> {
                match value {
                    "if_format_matches" => Ok(OptionalModel::IfFormatMatches),
                    _ => Err(E::invalid_value(Unexpected::Str(value), &self)),
                }
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<OptionalModel, A::Error> {
                let rule = ByteAtMost::deserialize(MapAccessDeserializer::new(map))?;
                Ok(OptionalModel::IfByteAtMost(rule.if_byte_at_most))
            }
        }
        deserializer.deserialize_any(OptionalVisitor)
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CommandModel {
    /// The code on the wire; absent for layouts without a command field.
    pub code: Option<CodeModel>,
    pub kind: CommandKind,
    pub request: String,
    pub reply: String,
    /// Data types carried (`word`, `double_word`, `bit`, `text`); empty: any.
    #[serde(default)]
    pub data_types: Vec<DataType>,
    /// `parameter` (default) or `coil`.
    pub space: Option<Space>,
    pub address_map: Option<AddressMapModel>,
    /// Codes a normal reply may carry; empty: the request's code.
    #[serde(default)]
    pub reply_codes: Vec<CodeModel>,
    /// Notes for people reading the protocol file; nothing is generated from them.
    #[serde(default)]
    #[allow(dead_code)]
    pub description: String,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AddressMapModel {
    pub multiply: u16,
    pub offset: i32,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PreStepModel {
    pub step: PreStepKind,
    pub register: u16,
    /// `parameter` (default) or `coil`.
    pub space: Option<Space>,
    /// `word` (default), `double_word`, `bit` or `text`.
    pub data_type: Option<DataType>,
    pub ram: Option<u32>,
    pub persistent: Option<u32>,
    /// Notes for people reading the protocol file; nothing is generated from them.
    #[serde(default)]
    #[allow(dead_code)]
    pub description: String,
}

/// What a pre-step does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PreStepKind {
    /// Write the array index of an indexed parameter.
    Index,
    /// Switch between writing RAM only and RAM + EEPROM.
    Persistence,
}
