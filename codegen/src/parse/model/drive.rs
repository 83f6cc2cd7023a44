//! The drive file as a whole (`drives/<id>.yaml`): its sections, who the drive is and
//! the manual's mistakes in prose.

use super::behaviour::BehaviourModel;
use super::bitfields::BitfieldModel;
use super::code_tables::CodeTableModel;
use super::conversions::ConversionModel;
use super::error_codes::ErrorCodesModel;
use super::examples::{ExampleModel, ValueExampleModel};
use super::protocol_ref::ProtocolRef;
use super::register::{RegisterModel, WarningModel};
use super::scaling::ReferenceScalingModel;
use super::sequences::SequenceModel;
use super::serial::{AddressingModel, PortsModel, SerialModel};
use super::write_rules::{ForbiddenCombinationModel, PersistenceModel};
use schemars::JsonSchema;
use serde::Deserialize;

/// A drive file (`drives/<id>.yaml`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DriveFile {
    /// Who the drive is: id, vendor, model, names and the manual.
    pub drive: DriveMeta,
    /// The serial line settings the manual gives.
    pub serial: SerialModel,
    /// The range of station numbers (inverter addresses).
    pub addressing: AddressingModel,
    /// The protocols the drive speaks: each names a file in `protocols/` and may adapt it to the drive's numbering.
    pub protocols: Vec<ProtocolRef>,
    /// Codes carried by error replies, and when the drive does not answer at all.
    pub error_codes: ErrorCodesModel,
    /// Code tables (registers whose value is a code), each becoming a Rust enum.
    #[serde(default)]
    pub codes: Vec<CodeTableModel>,
    /// Bit-field words, each becoming a Rust type with accessors and builders.
    #[serde(default)]
    pub bitfields: Vec<BitfieldModel>,
    /// The registers (parameters, monitors, commands) the drive has over the serial link.
    pub registers: Vec<RegisterModel>,
    /// The manual's worked conversions between an engineering value and a raw word; each becomes a test.
    #[serde(default)]
    pub value_examples: Vec<ValueExampleModel>,
    /// A reference word that is a percentage of a span chosen by a selector register.
    pub reference_scaling: Option<ReferenceScalingModel>,
    /// Mistakes in the manual's prose (mistakes in example frames go on the frame).
    #[serde(default)]
    pub manual_errata: Vec<ManualErratumModel>,
    /// The manual's example frames; each becomes a golden test.
    #[serde(default)]
    pub examples: Vec<ExampleModel>,
    /// The manual's multi-step examples (a page switch, its acknowledgement, a read, the
    /// reply, the master's follow-up): each becomes a test that makes one call and
    /// compares every frame on the line with the manual's, in order.
    #[serde(default)]
    pub sequences: Vec<SequenceModel>,
    /// Safety warnings the manual gives (or that follow from its examples) for the drive as
    /// a whole, shown prominently on the reference page.
    #[serde(default)]
    pub warnings: Vec<WarningModel>,
    /// How the drive behaves, for the virtual drive (simulator): which command bits run,
    /// stop, reverse, reset and coast it, how the output follows the frequency command,
    /// which status bits show its state, where trips are recorded and which error code
    /// answers each refused request.
    pub behaviour: Option<BehaviourModel>,
    /// The drive's serial ports, where it has more than one (a 2-wire and a 4-wire
    /// RS-485 port): each port's own setting registers, the registers both ports share,
    /// and the registers that exist once per port.
    pub ports: Option<PortsModel>,
    /// The manual's formulas between registers (a speed from a frequency and the motor's
    /// poles), each becoming a typed function tested with the manual's numbers.
    #[serde(default)]
    pub conversions: Vec<ConversionModel>,
    /// Where parameter writes over the link go, when a register of the drive chooses it
    /// (DV1 07-11: 0 RAM and EEPROM, 1 RAM only): the master sets that register so that a
    /// RAM write stays out of the EEPROM and a persistent write reaches it.
    pub persistence: Option<PersistenceModel>,
    /// Combinations of register values the manual forbids (the DV1's two stop bits with
    /// parity): the virtual drive refuses a write that would make one, `vfd write` checks
    /// a write against the values it reads first.
    #[serde(default)]
    pub forbidden_combinations: Vec<ForbiddenCombinationModel>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DriveMeta {
    /// Lower snake or kebab case: the file name, the name on the command line and, with `-`
    /// as `_`, the Rust module name (`vf-as1` -> `vf_as1`).
    pub id: String,
    /// The maker, as the manual names it.
    pub vendor: String,
    /// The model or series designation.
    pub model: String,
    /// The drive's name in English.
    pub name: String,
    /// The drive's name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// The manual's file name (in the manuals folder) every `source` refers to.
    pub manual: String,
    /// The manual's title in English, as the pages and the generated docs name it (the
    /// file name is shown beside it); a translation of `manual_title_zh`, or a title of
    /// the description's own when the copy has none (say so in `manual_note`).
    #[serde(default)]
    pub manual_title: String,
    /// The manual's title as it prints it (in Chinese).
    #[serde(default)]
    pub manual_title_zh: String,
    /// The manual's document number and edition as it prints them (`E6581315`,
    /// `IL550-0501001, September 2017`), when it has one.
    #[serde(default)]
    pub manual_document: String,
    /// Anything to say about the copy of the manual: where its title comes from when it
    /// prints none.
    #[serde(default)]
    pub manual_note: String,
    /// Prose for the top of the reference page.
    #[serde(default)]
    pub description: String,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ManualErratumModel {
    /// The manual section with the mistake.
    pub source: String,
    /// What the manual prints.
    pub printed: String,
    /// What it should say.
    pub corrected: String,
    /// Why the printed text is wrong.
    pub reason: String,
}
