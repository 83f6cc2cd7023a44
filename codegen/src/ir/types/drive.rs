//! One drive as a whole ([`DriveIr`]), with the rules its writes follow and the manual's
//! mistakes in prose.

use super::behaviour::BehaviourIr;
use super::bitfields::BitfieldIr;
use super::code_tables::CodeTableIr;
use super::conversions::ConversionIr;
use super::error_codes::ErrorCodesIr;
use super::examples::{ExampleIr, ValueExampleIr};
use super::protocol::{ProtocolFileIr, ProtocolIr};
use super::register::RegisterIr;
use super::scaling::ReferenceScalingIr;
use super::sequences::SequenceIr;
use super::serial::{AddressingIr, PortsIr, SerialIr};
use crate::parse::model::WarningModel as WarningIr;
use serde::Serialize;

/// One drive, ready to emit.
#[derive(Debug, Clone, Serialize)]
pub struct DriveIr {
    /// Drive id (`yd1000`), also the file names of its outputs.
    pub id: String,
    /// Rust module name (`yd1000`, `vf_as1`).
    pub module: String,
    /// Vendor.
    pub vendor: String,
    /// Model.
    pub model: String,
    /// English name.
    pub name: String,
    /// The manual's Chinese name.
    pub name_zh: String,
    /// The manual's file name.
    pub manual: String,
    /// The manual's title in English (empty when the description gives none).
    pub manual_title: String,
    /// The manual's title as it prints it.
    pub manual_title_zh: String,
    /// The manual's document number and edition.
    pub manual_document: String,
    /// A note on the copy of the manual (where its title comes from).
    pub manual_note: String,
    /// What the description covers.
    pub description: String,
    /// The drive file's path, as given to the generator (or relative to a display root).
    pub file: String,
    /// Serial line facts.
    pub serial: SerialIr,
    /// Station numbers.
    pub addressing: AddressingIr,
    /// The protocol files this drive's protocols use, each once, with their frame layouts.
    pub protocol_files: Vec<ProtocolFileIr>,
    /// The drive's protocols.
    pub protocols: Vec<ProtocolIr>,
    /// The manual's error codes.
    pub error_codes: ErrorCodesIr,
    /// Code tables.
    pub code_tables: Vec<CodeTableIr>,
    /// Bit-field layouts.
    pub bitfields: Vec<BitfieldIr>,
    /// Registers, in file order.
    pub registers: Vec<RegisterIr>,
    /// Worked value examples (`80 Hz = 1F40h`).
    pub value_examples: Vec<ValueExampleIr>,
    /// Mode-dependent reference scaling, when the drive has one.
    pub reference_scaling: Option<ReferenceScalingIr>,
    /// Mistakes in the manual's prose.
    pub manual_errata: Vec<ManualErratumIr>,
    /// Example exchanges, each frame decoded.
    pub examples: Vec<ExampleIr>,
    /// Multi-step examples: one call and every frame on the line.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sequences: Vec<SequenceIr>,
    /// Safety warnings for the drive as a whole.
    pub warnings: Vec<WarningIr>,
    /// The behaviour model for the virtual drive, when the description declares one.
    pub behaviour: Option<BehaviourIr>,
    /// The serial ports, when the drive has several.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ports: Option<PortsIr>,
    /// The manual's formulas between registers.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub conversions: Vec<ConversionIr>,
    /// The register choosing where parameter writes go, when the drive has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub persistence: Option<PersistenceIr>,
    /// Combinations of register values the manual forbids.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub forbidden_combinations: Vec<ForbiddenCombinationIr>,
}

/// The register choosing where parameter writes over the link go (`persistence:`).
#[derive(Debug, Clone, Serialize)]
pub struct PersistenceIr {
    /// Code of the selector register.
    pub selector: String,
    /// The value for RAM-only writes.
    pub ram: u32,
    /// The value for RAM + EEPROM writes.
    pub persistent: u32,
    /// The governed register numbers (first, last); empty: every parameter.
    pub registers: Vec<(u16, u16)>,
    /// Manual section.
    pub source: String,
    /// Remarks.
    pub note: String,
}

/// Values of several registers the manual forbids together, resolved to codes and raw
/// words.
#[derive(Debug, Clone, Serialize)]
pub struct ForbiddenCombinationIr {
    /// Identifier.
    pub id: String,
    /// The manual's words.
    pub rule: String,
    /// In English.
    pub meaning: String,
    /// Manual section.
    pub source: String,
    /// Each condition: register code and the raw words that fulfil it.
    pub when: Vec<(String, Vec<u32>)>,
}

/// A mistake in the manual's prose.
#[derive(Debug, Clone, Serialize)]
pub struct ManualErratumIr {
    /// Manual section.
    pub source: String,
    /// What it prints.
    pub printed: String,
    /// What it should say.
    pub corrected: String,
    /// Why.
    pub reason: String,
}
