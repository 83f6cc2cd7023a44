//! The description format as serde types: what a drive file and a protocol file may say.
//!
//! These types mirror the YAML one to one (unknown keys are errors). Meaning is checked
//! later, in [`crate::validate`]; nothing here resolves references.

use serde::Deserialize;
use std::collections::BTreeMap;

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
    #[serde(default)]
    pub manual_errata: Vec<ManualErratumModel>,
    #[serde(default)]
    pub examples: Vec<ExampleModel>,
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
    pub baud_rates: Vec<u32>,
    pub parities: Vec<String>,
    pub data_bits: u8,
    pub stop_bits_sent: u8,
    pub stop_bits_received: u8,
    pub default: SerialDefaultModel,
    pub timing: TimingModel,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SerialDefaultModel {
    pub baud: u32,
    pub parity: String,
    pub data_bits: u8,
    pub stop_bits: u8,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimingModel {
    pub startup_delay_ms: u64,
    pub frame_abandon_ms: u64,
    pub processing_allowance_ms: u64,
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
#[derive(Debug, Clone, Deserialize, PartialEq)]
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
    pub access: Option<String>,
    #[serde(default)]
    pub ram_only: bool,
    #[serde(default)]
    pub writable_while_running: bool,
    #[serde(default)]
    pub panel_only: bool,
    #[serde(default)]
    pub takes_effect: Option<String>,
    pub bitfield: Option<String>,
    pub code_table: Option<String>,
    pub source: String,
    #[serde(default)]
    pub note: String,
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
    pub printed_rejected_as: Option<String>,
}

#[derive(Debug, Clone, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ExpectModel {
    pub address: Option<u8>,
    pub command: Option<String>,
    pub register: Option<u32>,
    pub data: Option<u32>,
    pub error_code: Option<u32>,
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
}

/// A layout entry: the name of a shared part, or a part written in place.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum PartRefModel {
    Named(String),
    Inline(PartModel),
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartModel {
    pub literal: Option<String>,
    pub literal_hex: Option<String>,
    pub field: Option<String>,
    pub checksum: Option<String>,
    pub format: Option<String>,
    pub width: Option<u8>,
    pub min_width: Option<u8>,
    pub optional: Option<OptionalModel>,
    #[serde(default)]
    pub allowed: Vec<String>,
    #[serde(default)]
    pub fold_case: bool,
    pub marker: Option<String>,
    pub covers_from: Option<String>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum OptionalModel {
    Flag(bool),
    Rule(String),
    ByteAtMost { if_byte_at_most: u8 },
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CommandModel {
    pub letter: String,
    pub kind: String,
    pub request: String,
    pub reply: String,
}
