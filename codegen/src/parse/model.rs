//! The description format as serde types: what a drive file and a protocol file may say.
//!
//! These types mirror the YAML one to one (unknown keys are errors). Meaning is checked
//! later, in [`crate::validate`]; nothing here resolves references.

use schemars::{json_schema, JsonSchema, Schema, SchemaGenerator};
use serde::de::value::MapAccessDeserializer;
use serde::de::{self, MapAccess, Unexpected, Visitor};
use serde::{Deserialize, Serialize};
use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fmt;
use vfd_runtime::serial::{BeforeStart, Parity};
use vfd_runtime::{
    Access, BroadcastAnswer, ChecksumAlgorithm, CommandKind, DataType, DecodeErrorKind, Encoding,
    Format, Role, SizedBy, Space, TakesEffect,
};

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

/// A register of the drive that chooses where parameter writes over the link go
/// (`persistence:`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PersistenceModel {
    /// Code or id of the selector register.
    pub selector: String,
    /// The selector's value with which parameter writes go to RAM only.
    pub ram: u32,
    /// The selector's value with which parameter writes go to RAM and EEPROM.
    pub persistent: u32,
    /// The register numbers (before any address map) whose writes the selector governs;
    /// left out: every parameter. RAM-only registers are never governed.
    #[serde(default)]
    pub registers: Vec<AddressSpanModel>,
    /// Where the manual says it.
    pub source: String,
    /// Remarks.
    #[serde(default)]
    pub note: String,
}

/// Register numbers `from` through `to`.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AddressSpanModel {
    /// The first register number.
    pub from: u16,
    /// The last register number.
    pub to: u16,
}

/// Values of several registers the manual forbids together (`forbidden_combinations:`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ForbiddenCombinationModel {
    /// Unique lower snake case name (`two_stop_bits_with_parity`).
    pub id: String,
    /// The manual's rule, in its words (quoted by the error a forbidden write gets).
    pub rule: String,
    /// What the rule says, in English.
    pub meaning: String,
    /// Where the manual says it.
    pub source: String,
    /// The conditions, all holding at once: at least two, each about another register.
    pub when: Vec<CombinationConditionModel>,
}

/// One condition of a forbidden combination: the register holds one of these values.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CombinationConditionModel {
    /// The register, by code, id or alias.
    pub register: String,
    /// Its values (in its unit, as its range gives them) that fulfil the condition.
    pub values: Vec<f64>,
}

/// The drive's serial ports (`ports:`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PortsModel {
    /// The manual sections describing the ports.
    pub source: String,
    /// Anything the manual says about the ports that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// The ports, the one a client uses when it names none first.
    pub list: Vec<PortModel>,
    /// Registers (codes or ids) that both ports share (parity, station number).
    #[serde(default)]
    pub shared: Vec<String>,
    /// Registers that exist once per port: each entry maps every port id to its copy
    /// (`{ two_wire: FA00, four_wire: FA04 }`); a client that picks a port is pointed
    /// from one copy to its port's.
    #[serde(default)]
    pub registers: Vec<BTreeMap<String, String>>,
}

/// One serial port.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PortModel {
    /// Lower snake case id (`two_wire`): what `--port-kind` and the generated port
    /// constants are named by.
    pub id: String,
    /// The port's name in English.
    pub name: String,
    /// The port's name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// The registers setting this port, by what they set (`{ baud_rate: F800,
    /// protocol: F807 }`); every port names the same settings.
    #[serde(default)]
    pub settings: BTreeMap<String, String>,
}

/// A register's scale chosen by another register's value (`scale_by:`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScaleByModel {
    /// Code or id of the register whose value chooses the scale.
    pub register: String,
    /// One entry per value of that register.
    pub values: Vec<ScaleChoiceModel>,
    /// The scale (and range) for every value `values` does not list (DV1: 00-08 = 0 gives
    /// two decimals, any other value one).
    pub otherwise: Option<ScaleOtherwiseModel>,
}

/// The scale (and range) a register has for the selector values a `scale_by` does not list.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScaleOtherwiseModel {
    /// Engineering value of one raw step with these values.
    pub scale: f64,
    /// The range with these values, in engineering units (left out: the register's).
    pub range: Option<RangeModel>,
}

/// The scale (and range) a register has for one value of its selector.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScaleChoiceModel {
    /// The selector's value.
    pub value: u32,
    /// Engineering value of one raw step with this choice.
    pub scale: f64,
    /// The range with this choice, in engineering units (left out: the register's).
    pub range: Option<RangeModel>,
}

/// A formula of the manual between registers (`conversions:`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConversionModel {
    /// Lower snake case: it names the generated function.
    pub id: String,
    /// What the result is, in English.
    pub name: String,
    /// The manual section giving the formula.
    pub source: String,
    /// The formula with `+ - * /` and parentheses over numbers and the inputs' names
    /// (`"(speed * poles * 10 + 6) / 12"`).
    pub formula: String,
    /// The inputs, in the generated function's argument order.
    pub inputs: Vec<ConversionInputModel>,
    /// The result's unit (`Hz`, `rpm`); left out for plain numbers.
    pub unit: Option<String>,
    /// The register the result goes to or comes from, when it is one (code or id).
    pub result: Option<String>,
    /// `truncate`: the result is cut to a whole number, as the drive's integer arithmetic
    /// does; left out: exact.
    pub rounding: Option<RoundingModel>,
    /// When the formula applies: the selector register (code or id) and its value
    /// (`{ register: F810, value: 0 }`); left out: always.
    pub when: Option<ConversionWhenModel>,
    /// Anything the manual says about the formula that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// The manual's worked numbers; each becomes a test.
    pub examples: Vec<ConversionExampleModel>,
}

/// How a conversion's result is rounded.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, JsonSchema, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum RoundingModel {
    /// Cut towards zero to a whole number.
    Truncate,
}

/// The condition under which a conversion applies.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConversionWhenModel {
    /// Code or id of the register.
    pub register: String,
    /// Its value (`0`), or `nonzero`.
    pub value: ConditionValueModel,
}

/// A selector value a conversion applies for.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema, PartialEq)]
#[serde(untagged)]
pub enum ConditionValueModel {
    /// This value.
    Value(u32),
    /// `nonzero`: any value but 0.
    Word(String),
}

/// One input of a conversion.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConversionInputModel {
    /// The name the formula uses (lower snake case; also the argument's name).
    pub name: String,
    /// The register it comes from (code or id), when it is one: the value is the
    /// register's raw word times its scale (a code table's value as is).
    pub register: Option<String>,
    /// Multiplies the register's value first (F856 counts pole pairs: `times: 2` gives
    /// the poles).
    pub times: Option<f64>,
    /// What the input is, when it is no register (the received percentage).
    #[serde(default)]
    pub description: String,
}

/// A worked example of a conversion: its inputs and result.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConversionExampleModel {
    /// Input values by name (the register's own value, before `times`).
    pub inputs: BTreeMap<String, f64>,
    /// The result the manual gives.
    pub result: f64,
    /// The manual section giving the numbers.
    pub source: String,
}

/// A bit of a bit-field word: its id (`run`), or `{ bit: no_coast, active: 0 }` for a bit
/// that acts when it is 0. A bit held by another register than its role's word is named
/// `register.field` (a field of another bit-field register: the GS2's `P9.28.reverse`), or
/// by the code or id of a coil of its own (a register of `data_type: bit`, on at FF00h).
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(untagged)]
pub enum BitRefModel {
    /// An active-high bit, by its id in the word's bit field, as `register.field` in another
    /// bit-field register, or a coil by its code or id.
    Id(String),
    /// A bit with the level at which it acts.
    Level(BitLevelModel),
}

/// A bit and the level at which it acts.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BitLevelModel {
    /// The bit's id in the word's bit field (or `register.field`, or a coil).
    pub bit: String,
    /// 1 (default): the bit acts when set; 0: it acts when clear (active low).
    #[serde(default = "one")]
    pub active: u8,
}

fn one() -> u8 {
    1
}

impl BitRefModel {
    /// The bit's id.
    pub fn id(&self) -> &str {
        match self {
            BitRefModel::Id(id) => id,
            BitRefModel::Level(level) => &level.bit,
        }
    }

    /// Whether the bit acts when it is 0.
    pub fn active_low(&self) -> bool {
        matches!(self, BitRefModel::Level(level) if level.active == 0)
    }
}

/// The behaviour model of a drive (`behaviour:`), for the virtual drive.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BehaviourModel {
    /// The manual sections the model comes from.
    pub source: String,
    /// What the model assumes where the manual is silent.
    #[serde(default)]
    pub note: String,
    /// The command word: which bits run, stop, reverse, reset and coast the motor.
    pub command: CommandBehaviourModel,
    /// The frequency command, the ramp and the monitors that follow the output.
    pub frequency: FrequencyBehaviourModel,
    /// The output current as a simple function of the output.
    pub current: Option<CurrentBehaviourModel>,
    /// The status-word bits that show the drive's state.
    pub status: StatusBehaviourModel,
    /// Where a trip is recorded.
    #[serde(default)]
    pub trip: TripBehaviourModel,
    /// Which registers the process words of process exchanges carry.
    pub process: Option<ProcessBehaviourModel>,
    /// The error code each protocol (by the drive's protocol id) answers each refused
    /// request with; a refusal left out means the drive stays silent.
    #[serde(default)]
    pub refusals: BTreeMap<String, RefusalsModel>,
}

/// How the command word drives the motor.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CommandBehaviourModel {
    /// Id of the command-word register (a bit-field register; with `codes`, a register
    /// holding a command code).
    pub register: String,
    /// Bits that must all act for the word to act at all.
    #[serde(default)]
    pub require: Vec<BitRefModel>,
    /// The run/stop bit (with `run_reverse`: the forward-run bit). Left out when the
    /// register holds command codes (`codes`).
    pub run: Option<BitRefModel>,
    /// The command is a code, not bits: each value written to the register acts as the
    /// list it is in says (`{ run: [1], run_reverse: [2], stop: [6], coast: [5], reset:
    /// [7] }`). Instead of `run`; the command bits (`require`, `run_reverse`, `reverse`,
    /// `reset`, `coast`, `frequency.require`) are then left out.
    pub codes: Option<CommandCodesModel>,
    /// A second run bit that runs the motor in reverse (STR beside STF): the motor runs
    /// while either run bit acts, in reverse when only this one does, and stops while
    /// both act.
    pub run_reverse: Option<BitRefModel>,
    /// The reverse bit.
    pub reverse: Option<BitRefModel>,
    /// The fault-reset bit (acts on its rising edge).
    pub reset: Option<BitRefModel>,
    /// A fault reset by a value written to a register of its own, not by a command-word
    /// bit: `{ register: inverter_reset, value: 0x9696 }`.
    pub reset_by_write: Option<WrittenValueModel>,
    /// The coast-stop bit.
    pub coast: Option<BitRefModel>,
    /// The mode in which the command word and the frequency command are taken:
    /// `{ register: operation_mode, values: [0] }`. A write to either in another mode is
    /// refused as `wrong_mode`.
    pub require_mode: Option<ModeRequirementModel>,
}

/// Command codes: the raw values written to the command register, by what they do.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CommandCodesModel {
    /// Values that run the motor forward.
    pub run: Vec<u32>,
    /// Values that run the motor in reverse.
    #[serde(default)]
    pub run_reverse: Vec<u32>,
    /// Values that stop it (the output ramps down).
    #[serde(default)]
    pub stop: Vec<u32>,
    /// Values that coast it to a stop (the output drops to zero at once).
    #[serde(default)]
    pub coast: Vec<u32>,
    /// Values that reset a trip (each write acts; the motor stays stopped).
    #[serde(default)]
    pub reset: Vec<u32>,
}

/// A register whose value must be one of `values` for commands to be taken.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModeRequirementModel {
    /// Code or id of the mode register.
    pub register: String,
    /// The raw values in which commands are taken (one of its codes, if it has a table).
    pub values: Vec<u32>,
}

/// A raw value written to a register that makes the drive act.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WrittenValueModel {
    /// Code or id of the register written (writable, not the command word).
    pub register: String,
    /// The raw value that acts (`0x9696`).
    pub value: u32,
}

/// A number, or the id or code of a register whose value gives it.
pub type AmountModel = BoundModel;

/// How the output follows the frequency command.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FrequencyBehaviourModel {
    /// Id of the frequency-command register.
    pub command: String,
    /// Command-word bits that make the frequency command effective.
    #[serde(default)]
    pub require: Vec<BitRefModel>,
    /// Seconds the output takes to rise by `span`: a number or a register.
    pub acceleration: AmountModel,
    /// Seconds the output takes to fall by `span`: a number or a register.
    pub deceleration: AmountModel,
    /// The change the ramp times refer to, in the command's units: a number or a register.
    pub span: AmountModel,
    /// Ids of the monitors that show the output (in the command's units).
    #[serde(default)]
    pub output: Vec<String>,
    /// Ids of the monitors that show the frequency command in use.
    #[serde(default)]
    pub reference: Vec<String>,
    /// The output frequency at and above which the drive reports the frequency detected
    /// (`status.frequency_detected`; an output-frequency detection setting): a number in
    /// the command's units or a register.
    pub detection: Option<AmountModel>,
    /// The frequency the command register's 100 % stands for, where the command is a
    /// percentage (a unit of `%`) and the output a frequency (Huanyang GT 2000H: a
    /// percentage of the maximum frequency P0.03): a number or a register. The model runs
    /// at command x `percent_of` / 100; `span`, `detection` and the output and reference
    /// monitors are then in `percent_of`'s units.
    pub percent_of: Option<AmountModel>,
}

/// Output current: `at_zero + (at_span - at_zero) x |output| / span` while running, 0 when stopped.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurrentBehaviourModel {
    /// Ids of the monitors that show it.
    pub registers: Vec<String>,
    /// Value at zero output while running, in the monitors' units.
    pub at_zero: f64,
    /// Value at an output of `span`.
    pub at_span: f64,
    /// The current at and above which the drive reports an overload (`status.overload`):
    /// a number in the monitors' units or a register.
    pub overload: Option<AmountModel>,
}

/// The status-word bits; each entry lists bits of the status word's bit field.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StatusBehaviourModel {
    /// Ids of the status-word registers (bit-field registers sharing one bit field).
    pub registers: Vec<String>,
    /// Set while the motor runs.
    #[serde(default)]
    pub running: Vec<BitRefModel>,
    /// Set while the direction is reverse.
    #[serde(default)]
    pub reverse: Vec<BitRefModel>,
    /// Set while the motor runs in the forward direction.
    #[serde(default)]
    pub forward: Vec<BitRefModel>,
    /// Set while running at the frequency command.
    #[serde(default)]
    pub at_reference: Vec<BitRefModel>,
    /// Set while tripped.
    #[serde(default)]
    pub tripped: Vec<BitRefModel>,
    /// Set while the output current is at or above `current.overload` (an overload
    /// alarm).
    #[serde(default)]
    pub overload: Vec<BitRefModel>,
    /// Set while running with the output frequency at or above `frequency.detection`
    /// (frequency detected).
    #[serde(default)]
    pub frequency_detected: Vec<BitRefModel>,
    /// Set unless a coast stop is commanded.
    #[serde(default)]
    pub enabled: Vec<BitRefModel>,
    /// Always set (ready bits).
    #[serde(default)]
    pub always: Vec<BitRefModel>,
    /// A register showing the drive's state as a code, not bits:
    /// `{ register: inverter_state, stopped: 3, forward: 1, reverse: 2, tripped: 4 }`.
    pub state: Option<StatusStateModel>,
}

/// A state register: the code it holds in each state of the drive.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StatusStateModel {
    /// Code or id of the register.
    pub register: String,
    /// Its value while stopped (and not tripped).
    pub stopped: u32,
    /// Its value while the motor runs forward.
    pub forward: u32,
    /// Its value while the motor runs in reverse (left out: `forward`'s).
    pub reverse: Option<u32>,
    /// Its value while tripped (left out: `stopped`'s).
    pub tripped: Option<u32>,
}

/// Where a trip is recorded.
#[derive(Debug, Clone, Default, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TripBehaviourModel {
    /// Ids of the registers showing the present trip code (0 after a reset).
    #[serde(default)]
    pub code: Vec<String>,
    /// The trip history, newest first: registers (codes or ids), or fields of bit-field
    /// registers as `register.field` (`fault_codes_1_2.latest`).
    #[serde(default)]
    pub history: Vec<String>,
    /// A value written to a register that clears the trip history:
    /// `{ register: parameter_clear_1102, value: 0xA5A5 }`.
    pub clear_by_write: Option<WrittenValueModel>,
}

/// Which registers the process words carry.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProcessBehaviourModel {
    /// Id of the register the first request word writes (control word).
    pub control: String,
    /// Id of the register the second request word writes (reference).
    pub reference: String,
    /// Id of the register the first reply word reads (status word).
    pub status: String,
    /// Id of the register the second reply word reads (output).
    pub output: String,
}

/// Error codes one protocol answers refused requests with; a code left out: silence.
#[derive(Debug, Clone, Default, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RefusalsModel {
    /// No register at that number.
    pub unknown_register: Option<u16>,
    /// A write to a read-only register.
    pub read_only: Option<u16>,
    /// A value outside the range (bounds named after other registers included).
    pub out_of_range: Option<u16>,
    /// A write to a register that cannot change while the motor runs.
    pub while_running: Option<u16>,
    /// A frame whose checksum does not match.
    pub bad_checksum: Option<u16>,
    /// A write to the command word or the frequency command outside the mode
    /// `command.require_mode` names.
    pub wrong_mode: Option<u16>,
    /// A frame holding a character its protocol's frames never carry (in a text framing, a
    /// character other than the digits, letters and control codes of its layouts: the
    /// computer link's character error).
    pub bad_character: Option<u16>,
    /// A frame the drive cannot read otherwise (a missing or wrong fixed character, a field
    /// of the wrong length: the computer link's protocol error), whose station it can read.
    pub malformed: Option<u16>,
    /// After more consecutive unreadable frames (bad characters, malformed frames, bad
    /// checksums) than the drive allows, the code it answers the next with instead (the
    /// computer link's NAK error): `{ code: 0x00, after: retries }`.
    pub retries_exceeded: Option<RetriesExceededModel>,
}

/// The error after too many consecutive unreadable frames (`refusals.<p>.retries_exceeded`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RetriesExceededModel {
    /// The error code.
    pub code: u16,
    /// How many consecutive unreadable frames the drive answers with their own errors: a
    /// number or the register setting it (the allowed number of retries); the next gets
    /// `code`.
    pub after: AmountModel,
}

/// A safety warning: what can go wrong, and where the manual says so.
#[derive(Debug, Clone, Deserialize, JsonSchema, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WarningModel {
    /// The warning, in English (the manual's Chinese may follow in brackets).
    pub text: String,
    /// The manual section it comes from; empty when it follows from the description only.
    #[serde(default)]
    pub source: String,
}

/// The line-level facts of the serial link (the manual's specification table).
#[derive(Debug, Clone, Deserialize, JsonSchema, Default)]
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
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Duplex {
    /// One direction at a time (two-wire RS-485).
    Half,
    /// Both directions at once (four-wire).
    Full,
}

/// Who controls the line.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Topology {
    /// Centralised control (集中控制): one master sends, the addressed drive answers.
    MasterSlave,
    /// Any station may start an exchange.
    MultiMaster,
}

/// Character synchronisation.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Synchronisation {
    /// Start and stop bits frame each character.
    Asynchronous,
    /// A shared clock frames the characters.
    Synchronous,
}

/// Bit order within a character.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BitOrder {
    /// Least significant bit first (the UART convention).
    LsbFirst,
    /// Most significant bit first.
    MsbFirst,
}

/// A timing value that can be marked as assumed (not from the manual).
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum TimingField {
    /// `startup_delay_ms`.
    StartupDelayMs,
    /// `frame_abandon_ms`.
    FrameAbandonMs,
    /// `processing_allowance_ms`.
    ProcessingAllowanceMs,
}

/// Whether a register may be written while the motor runs, as the manual gives it: `true`,
/// `false`, or `unknown` where its table has no such column (the VF-AS1's section 7 table).
#[derive(Debug, Clone, Copy, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(untagged)]
pub enum WhileRunning {
    /// Stated by the manual (or inferred, and then listed in `inferred`).
    Known(bool),
    /// `unknown`: the manual does not say. A master attempts the write and reports the
    /// drive's refusal; the virtual drive accepts it.
    Unknown(UnknownWord),
}

impl Default for WhileRunning {
    fn default() -> Self {
        WhileRunning::Known(false)
    }
}

impl WhileRunning {
    /// Known to be writable while running.
    pub fn writable(self) -> bool {
        self == WhileRunning::Known(true)
    }

    /// The manual does not say.
    pub fn is_unknown(self) -> bool {
        matches!(self, WhileRunning::Unknown(_))
    }
}

impl<'de> Deserialize<'de> for WhileRunning {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = WhileRunning;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("true, false or unknown")
            }
            fn visit_bool<E: serde::de::Error>(self, value: bool) -> Result<WhileRunning, E> {
                Ok(WhileRunning::Known(value))
            }
            fn visit_str<E: serde::de::Error>(self, value: &str) -> Result<WhileRunning, E> {
                match value {
                    "unknown" => Ok(WhileRunning::Unknown(UnknownWord::Unknown)),
                    other => Err(E::invalid_value(
                        serde::de::Unexpected::Str(other),
                        &"true, false or unknown",
                    )),
                }
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// The word `unknown`: a fact the manual leaves open.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum UnknownWord {
    /// `unknown`.
    Unknown,
}

/// A register fact that can be marked as inferred (the description's reading, not the
/// manual's statement).
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
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
    /// The address: derived by a rule of the manual, not printed for this register (DV1
    /// 00-08 at 2718h by the group-mode rule 10000 + group number).
    Address,
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
pub struct SerialModel {
    /// The manual section these settings come from.
    pub source: String,
    /// Anything the manual says about the serial line that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// Every baud rate the drive can be set to.
    pub baud_rates: Vec<u32>,
    /// Every parity the drive can be set to.
    pub parities: Vec<Parity>,
    /// Data bits per character (`8`), or the data bits the drive can be set to (`[7, 8]`:
    /// a setting chooses, the factory setting being `default.data_bits`).
    pub data_bits: DataBitsModel,
    /// Stop bits the drive sends, when fixed; left out with `stop_bits`.
    pub stop_bits_sent: Option<u8>,
    /// Stop bits the drive needs to receive, when fixed; left out with `stop_bits`.
    pub stop_bits_received: Option<u8>,
    /// The stop bits the drive can be set to (`[1, 2]`: "1 or 2", the drive's choice, a
    /// setting): it then sends and needs the stop bits it is set to, the factory setting
    /// being `default.stop_bits`. Give this or both `stop_bits_sent` and
    /// `stop_bits_received`.
    #[serde(default)]
    pub stop_bits: Vec<u8>,
    /// The factory setting.
    pub default: SerialDefaultModel,
    /// How long the drive takes to be ready, to give up a frame and to answer.
    pub timing: TimingModel,
    /// Line-level facts from the manual's specification table (duplex, topology,
    /// synchronisation, bit order); each may be left out.
    pub line: Option<LineModel>,
}

/// Data bits per character: fixed, or the drive's choice.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum DataBitsModel {
    /// Every character carries this many data bits.
    Fixed(u8),
    /// The drive can be set to any of these (`[7, 8]`).
    Choice(Vec<u8>),
}

impl DataBitsModel {
    /// The data bits the drive can use, in the file's order.
    pub fn choices(&self) -> Vec<u8> {
        match self {
            DataBitsModel::Fixed(bits) => vec![*bits],
            DataBitsModel::Choice(bits) => bits.clone(),
        }
    }
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SerialDefaultModel {
    /// Factory baud rate.
    pub baud: u32,
    /// Factory parity.
    pub parity: Parity,
    /// Factory data bits.
    pub data_bits: u8,
    /// Factory stop bits.
    pub stop_bits: u8,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TimingModel {
    /// No answer this long after power-on (milliseconds).
    pub startup_delay_ms: u64,
    /// The drive drops an unfinished frame after this long (milliseconds).
    pub frame_abandon_ms: u64,
    /// Added to the wire time of request and longest reply to give the reply timeout (milliseconds).
    pub processing_allowance_ms: u64,
    /// Timings that are placeholders or our own assumption rather than the manual's
    /// statement: `[startup_delay_ms, frame_abandon_ms, processing_allowance_ms]`.
    #[serde(default)]
    pub assumed: Vec<TimingField>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AddressingModel {
    /// Lowest station number.
    pub min: u8,
    /// Highest station number.
    pub max: u8,
    /// What the manual says about addressing (broadcast, panel setting).
    #[serde(default)]
    pub note: String,
    /// Code or id of the register holding the drive's station number (DV1 07-01): the
    /// virtual drive answers at the station it holds (the value in effect: after a reset
    /// for a register that takes effect then), and a write to it moves the station.
    pub register: Option<String>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProtocolRef {
    /// The name this drive file uses for the protocol (in `examples[].protocol`).
    pub id: String,
    /// The protocol file it is: `protocols/<uses>.yaml`.
    pub uses: String,
    /// The manual section describing the protocol.
    pub source: String,
    /// How this drive numbers registers on the wire, per address space (overrides the
    /// protocol file): `{ parameter: { multiply: 10, offset: -1 }, coil: { multiply: 1, offset: -1 } }`.
    #[serde(default)]
    pub address_maps: BTreeMap<String, AddressMapModel>,
    /// Steps this drive needs before some requests (added to the protocol file's).
    #[serde(default)]
    pub pre_steps: Vec<PreStepModel>,
    /// The station numbers this protocol reaches, where narrower than the drive's
    /// `addressing` (a two-digit ASCII station: 0-99; Modbus: 1-247).
    pub addressing: Option<StationRangeModel>,
    /// The codes of the protocol file's commands this drive carries out, where it
    /// implements only some (`[0x03, 0x06]`); left out: all of them.
    pub commands: Option<Vec<CodeModel>>,
    /// The data types this drive carries over the protocol, where fewer than the protocol
    /// file's commands allow (`[word]`: one register per Modbus request); left out: all.
    pub data_types: Option<Vec<DataType>>,
    /// The most registers this drive returns to one read, where fewer than the protocol
    /// file's `max_words_per_read` (`12`; `1`: one register per read); left out: the
    /// protocol file's.
    pub max_words_per_read: Option<u16>,
    /// The most registers one write of several carries on this drive, where fewer than the
    /// protocol file's `max_words_per_write` (DV1: `12`); left out: the protocol file's.
    pub max_words_per_write: Option<u16>,
    /// The longest frame on the wire in bytes, where the drive's manual makes it shorter
    /// than the protocol file's `max_frame_len` (DV1 Modbus RTU: `33`, a write of its 12
    /// registers); it sizes buffers and reply timeouts. At least the longest frame the
    /// drive's commands make at its word limits; left out: the protocol file's.
    pub max_frame_len: Option<u16>,
    /// A read or write of several registers is carried out for the registers that can be,
    /// and refused only when none can (DV1 l. 473: 若有 1 个及以上可以操作就不视为错误): a
    /// register that does not exist reads as 0, one that does not exist or refuses its
    /// value is left as it is. Left out (false): one such register refuses the request.
    #[serde(default)]
    pub partial_blocks: bool,
    /// The codes this protocol's error replies carry as the manual gives them for this
    /// drive (its own Modbus exception table, whose numbers mean something else than the
    /// drive's `error_codes`): they name this protocol's error replies in place of the
    /// drive's table and of the protocol file's own.
    pub error_codes: Option<ProtocolErrorCodesModel>,
    /// Per command (by code): the registers it may address on this drive, and what its data
    /// is when not a value in the register's own unit
    /// (`[{ code: S, registers: [FA01, FA05], percent_of: FH, step: 0.01 }]`).
    #[serde(default)]
    pub command_registers: Vec<CommandRegistersModel>,
    /// What the protocol's block-transfer command (`kind: block`) writes and reads on this
    /// drive; left out, the drive has no block transfer and the command is dropped.
    pub block: Option<BlockModel>,
    /// Silence between frames in character times, where this drive's manual states its own
    /// (overrides the protocol file's `frame_gap_chars`; VF-AS1 Toshiba protocol: 3.5).
    pub frame_gap_chars: Option<f32>,
    /// The shortest silence between frames in milliseconds, whatever the baud rate: the gap
    /// is the longer of this and `frame_gap_chars` (DV1 Modbus RTU: 10; VF-AS1: 2).
    pub frame_gap_ms: Option<f32>,
    /// The longest silence between two bytes of one frame, in character times; the drive
    /// drops a frame with a longer one (VF-AS1: 1.5). Left out: no limit but
    /// `serial.timing.frame_abandon_ms`.
    pub max_inner_gap_chars: Option<f32>,
    /// What the drive makes of bytes before a frame's start sequence: `skip` (the default:
    /// the frame begins at its start) or `reject` (the frame is not answered; VF-AS1).
    pub before_start: Option<BeforeStart>,
    /// Registers whose value delays every reply (VF-AS1 F805 / F825): the master adds the
    /// wait to its reply timeout, the virtual drive waits that long.
    pub reply_delay: Option<ReplyDelayModel>,
    /// Which commands the drive carries out when broadcast over this protocol (the address
    /// part's `broadcast:` encodings in the protocol file) and which station answers. Left
    /// out: the drive takes no broadcasts over this protocol.
    pub broadcast: Option<BroadcastRuleModel>,
    /// Parameters this protocol reaches through pages: a request carries a parameter's
    /// offset in its page, after the page register has been set (DV1 Eaton protocol: HFF).
    pub pages: Option<PagesModel>,
    /// Which of the protocol file's `variants` the drive speaks: the register that selects
    /// it (its code table's value ids are variant ids) and the error the drive answers a
    /// frame in another variant's form with (`{ register: 07-06, mismatch_error:
    /// protocol_error }`). Left out: the drive speaks the first variant.
    pub variant: Option<VariantRuleModel>,
    /// What the drive answers to a well-formed request with a function (command code) it
    /// does not carry out, where its manual says (`{ error_code: 0x01, source: "..." }`:
    /// the error reply with exception 01). Left out: the manual does not say, and the
    /// virtual drive stays silent, so a master waits for its time-out.
    pub unsupported_function: Option<UnsupportedFunctionModel>,
}

/// What a drive answers to a function it lacks (`protocols[].unsupported_function`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UnsupportedFunctionModel {
    /// The error code its error reply carries: one of the protocol's error codes (the
    /// reply's function code is the request's, marked as the commands' error codes are:
    /// Modbus function + 80h).
    pub error_code: u16,
    /// Where the manual says so.
    pub source: String,
}

/// A protocol's parameter pages (`protocols[].pages`): which register numbers lie on which
/// page, and the register that switches pages.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PagesModel {
    /// The manual section describing the pages.
    pub source: String,
    /// The page register's numbers on the wire: `{ read: 0x7F, write: 0xFF }` (`read` may
    /// be left out when it cannot be read back).
    pub select: WireNumberModel,
    /// The page register's data type: `byte` where the page switch carries a narrower data
    /// field than a word's (two hex digits where words take four), so that it goes out with
    /// the protocol's write command that carries bytes, in that command's own layout.
    /// Default `word`.
    pub data_type: Option<DataType>,
    /// The ranges of register numbers laid out on pages.
    pub ranges: Vec<PageRangeModel>,
    /// Codes or ids of registers whose write resets the drive's page (an inverter reset):
    /// the master selects the page again before the next paged access.
    #[serde(default)]
    pub forgotten_after: Vec<String>,
    /// The page a drive is on after power-on or a reset (what the virtual drive starts on);
    /// default 0.
    #[serde(default)]
    pub initial: u16,
    /// What the manual does not say and the description assumes (`[initial]`).
    #[serde(default)]
    pub assumed: Vec<String>,
    /// Notes for people; nothing is generated from them.
    #[serde(default)]
    pub note: String,
}

/// Register numbers `registers[0]..=registers[1]`, laid out `size` to a page from
/// `first_page` on (`protocols[].pages.ranges[]`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PageRangeModel {
    /// What the range is (`P mode`, `group mode`).
    pub name: String,
    /// The lowest and the highest register number of the range.
    pub registers: [u32; 2],
    /// Registers per page.
    pub size: u16,
    /// The page of the range's first register.
    pub first_page: u16,
    /// Pages the range skips (no register lies on them).
    #[serde(default)]
    pub missing_pages: Vec<u16>,
}

/// How a drive selects the variant of a protocol it speaks (`protocols[].variant`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VariantRuleModel {
    /// The register (code or id) whose value selects the variant: a parameter with a
    /// `code_table` whose values' ids are the protocol file's variant ids (DV1 07-06:
    /// `1: cr`, `2: cr_lf`). Every variant must be selected by some value.
    pub register: String,
    /// The id of the error code (in the table naming this protocol's error replies) the
    /// drive answers a frame in another variant's form with (DV1: `protocol_error`, H03);
    /// left out: the drive does not answer such a frame.
    pub mismatch_error: Option<String>,
}

/// What one command of a protocol may address on this drive, and what its data means.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CommandRegistersModel {
    /// The command's code in the protocol file (`S`, `0x06`).
    pub code: CodeModel,
    /// Codes or ids of the registers it may address; any other is refused before sending.
    pub registers: Vec<String>,
    /// Code or id of the register whose value is 100 %: the data is a percentage of it,
    /// not a value in the addressed register's unit (the unit must be the same).
    pub percent_of: Option<String>,
    /// With `percent_of`: the percentage one raw step stands for (default 0.01).
    pub step: Option<f64>,
    /// With `percent_of`: the conversions (ids under `conversions:`) a receiving drive
    /// turns the raw percentage into its register's value with, the first whose `when`
    /// holds (VF-AS1: frequency points when F810 is not 0, else the plain ratio). Left out:
    /// the plain proportion of the 100 % register.
    #[serde(default)]
    pub received_by: Vec<String>,
}

/// A drive's block transfer: which registers the words of a block-transfer request are
/// written to and which registers its reply reads, position by position.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BlockModel {
    /// The manual section describing it.
    pub source: String,
    /// The selector registers (codes or ids) of the words written, in word order (`[F870,
    /// F871]`). Each has a `code_table` whose values say which `register` they select.
    pub write: Vec<String>,
    /// The selector registers of the words read, in word order (`[F875, ..., F879]`).
    pub read: Vec<String>,
    /// Selections that replace the selectors' while a register holds a value.
    #[serde(default)]
    pub modes: Vec<BlockModeModel>,
    /// The bit field naming the reply's write-status bits (bit `n`: word `n` not written).
    pub status: Option<String>,
    /// What the manual leaves open.
    #[serde(default)]
    pub note: String,
}

/// A block-transfer mode: while `register` holds `value`, the words go to and come from
/// fixed registers.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BlockModeModel {
    /// The register (code or id) that turns the mode on (`FA80`).
    pub register: String,
    /// The value that turns it on.
    pub value: u32,
    /// The registers written, in word order.
    pub write: Vec<String>,
    /// The registers read, in word order.
    pub read: Vec<String>,
    /// The manual section describing it.
    pub source: String,
}

/// Registers that set a wait before every reply (`protocols[].reply_delay`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReplyDelayModel {
    /// The registers (code or id), each with a unit of time (`s` or `ms`) and a range. With
    /// several (one per port), the longest value applies: the master cannot tell which port
    /// it is on.
    pub registers: Vec<String>,
}

/// A drive's broadcast rule for one protocol (`protocols[].broadcast`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BroadcastRuleModel {
    /// The command codes the drive carries out when broadcast: writes only (`[W, P]`,
    /// `[0x06, 0x10]`); a broadcast read is refused before anything is sent.
    pub commands: Vec<CodeModel>,
    /// Which station answers: `none` (Modbus) or `lowest_matching` (the lowest station the
    /// broadcast addresses: 00 for every station, 09 for the group `*9`).
    pub answered_by: BroadcastAnswer,
}

/// A range of station numbers.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StationRangeModel {
    /// Lowest station number.
    pub min: u8,
    /// Highest station number.
    pub max: u8,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ErrorCodesModel {
    /// The manual section listing the codes.
    pub source: String,
    /// The drive's protocols (their ids under `protocols`) whose error replies carry these
    /// codes; left out: every one of them. A protocol not listed names its error codes
    /// from its protocol file's own `error_codes`.
    pub protocols: Option<Vec<String>>,
    /// How the manual prints the codes (`{ prefix: H, digits: 2 }`: H0C); left out:
    /// two hex digits and `h` (0Ch).
    pub notation: Option<CodeNotationModel>,
    /// The codes an error reply may carry.
    pub codes: Vec<ErrorCodeModel>,
    /// Conditions in which the drive does not answer at all (documentation only).
    #[serde(default)]
    pub silent: Vec<String>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ErrorCodeModel {
    /// The code carried by the error reply.
    pub code: u32,
    /// Lower snake case name for the code in Rust.
    pub id: String,
    /// Short English name.
    pub name: String,
    /// The name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// What the code means and what to do about it.
    pub meaning: String,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CodeTableModel {
    /// Lower snake case: registers and bit fields name the table by it; it becomes a Rust enum.
    pub id: String,
    /// The table's name in English.
    pub name: String,
    /// The table's name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// The manual section the values come from.
    pub source: String,
    /// Whether the values listed are all there are (default true): a register using an exhaustive table and giving no `range` accepts writes from its lowest to its highest value only. False: registers using the table read as plain numbers.
    #[serde(default = "yes")]
    pub exhaustive: bool,
    /// Anything the manual says about the table that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// The codes and their meanings.
    pub values: Vec<CodeValueModel>,
}

fn yes() -> bool {
    true
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CodeValueModel {
    /// The raw value.
    pub value: u32,
    /// Lower snake case name of the value (a Rust enum variant).
    pub id: String,
    /// What the value means, in English.
    pub name: String,
    /// What the value means, as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// The register (code or id) this value selects, in a code table of selector registers
    /// (a block transfer's: F870 = 1 selects FA00).
    pub register: Option<String>,
    /// What this value sets on the line, in a code table of a line setting: the whole
    /// character format (DV1 07-07 = 0: `{ data_bits: 7, parity: none, stop_bits: 2 }`) or
    /// the part one register sets (a baud-rate register's `{ baud: 9600 }`, a parity
    /// register's `{ parity: even }`).
    pub line: Option<LineFormatModel>,
    /// The id of the drive's protocol this value chooses (DV1 07-07 = 0-2: `modbus_ascii`).
    pub protocol: Option<String>,
}

/// What a code value sets on the line (`codes[].values[].line`): any of the baud rate and
/// the character format's data bits, parity and stop bits, at least one.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LineFormatModel {
    /// The baud rate (one of `serial.baud_rates`).
    pub baud: Option<u32>,
    /// Data bits per character (7 or 8).
    pub data_bits: Option<u8>,
    /// `none`, `even` or `odd`.
    pub parity: Option<Parity>,
    /// Stop bits (1 or 2).
    pub stop_bits: Option<u8>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BitfieldModel {
    /// Lower snake case: registers name the word by it; it becomes a Rust type.
    pub id: String,
    /// The word's name in English.
    pub name: String,
    /// The word's name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// The manual section describing the word.
    pub source: String,
    /// Anything the manual says about the word that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// The word's bits and bit groups.
    pub fields: Vec<BitModel>,
    /// The manual's worked values of the word; each becomes a test.
    #[serde(default)]
    pub examples: Vec<BitExampleModel>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BitModel {
    /// A one-bit field.
    pub bit: Option<u8>,
    /// A multi-bit field as `"msb:lsb"`.
    pub bits: Option<String>,
    /// Lower snake case name of the field (an accessor in Rust); required unless `reserved`.
    pub id: Option<String>,
    /// The bits carry nothing (no accessor is generated).
    #[serde(default)]
    pub reserved: bool,
    /// What the field means, in English.
    #[serde(default)]
    pub name: String,
    /// What the field means, as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// What a one-bit field's 0 means.
    #[serde(default)]
    pub zero: String,
    /// What a one-bit field's 1 means.
    #[serde(default)]
    pub one: String,
    /// What a one-bit field's 0 means, in Chinese.
    #[serde(default)]
    pub zero_zh: String,
    /// What a one-bit field's 1 means, in Chinese.
    #[serde(default)]
    pub one_zh: String,
    /// Code table giving the meanings of a multi-bit field's values.
    pub code_table: Option<String>,
    /// Anything the manual says about the field that fits nowhere else.
    #[serde(default)]
    pub note: String,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BitExampleModel {
    /// The word's raw value.
    pub value: u32,
    /// The ids of the one-bit fields that are 1 in it.
    pub set: Vec<String>,
    /// The values of multi-bit fields in it, by field id (`{ character: 0x30 }`); fields
    /// left out are 0.
    #[serde(default)]
    pub fields: BTreeMap<String, u32>,
    /// What the manual says the value does.
    pub description: String,
    /// The manual section giving the example.
    pub source: String,
}

/// A range bound: a number in engineering units, or the code of another register.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq, JsonSchema)]
#[serde(untagged)]
pub enum BoundModel {
    Number(f64),
    Register(String),
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RangeModel {
    /// Lowest value in engineering units, or the code or id of a register giving it.
    pub min: BoundModel,
    /// Highest value in engineering units, or the code or id of a register giving it.
    pub max: BoundModel,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RegisterModel {
    /// Communication number, 0x0000-0xFFFF, unique within its space. Left out for a
    /// register the manual gives no number of its own: one its protocols reach by its own
    /// numbers on the wire (`wire_numbers`, an instruction code such as H7A) or by its place
    /// on a page (`on_page`).
    #[serde(rename = "address")]
    pub given_address: Option<u32>,
    /// The register's number in the description: `address` as given, else the number its
    /// place on a page gives (`on_page`), else a number of its own that no frame carries
    /// (a register known by its wire numbers only). Set when the file is loaded
    /// (`load::register_numbers`).
    #[serde(skip)]
    pub address: u32,
    /// Unique lower snake case name; it becomes a Rust type (`upper_limit_frequency` -> `UpperLimitFrequency`).
    pub id: String,
    /// The manual's code or mnemonic for the register, unique.
    pub code: String,
    /// Other names the manual gives the register (the DV1's P numbers: `[P.33]` for 07-00),
    /// each unique among the codes, ids and aliases: usable wherever a register is named
    /// (ranges, relations, the command line, `DriveInfo::register`) and shown on the page;
    /// one that makes a Rust name becomes a type alias (`pub type P33 = Protocol;`).
    #[serde(default)]
    pub aliases: Vec<String>,
    /// The register's name in English.
    pub name: String,
    /// The register's name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// Prose for the reference page.
    #[serde(default)]
    pub description: String,
    /// Unit of the engineering value (`Hz`, `s`, `%`, `A`, `V`, `h`, `kW`, `rpm`); left out for plain numbers.
    #[serde(default)]
    pub unit: Option<String>,
    /// Engineering value of one raw step (default 1).
    #[serde(default)]
    pub scale: Option<f64>,
    /// The word is two's complement (default false).
    #[serde(default)]
    pub signed: bool,
    /// Allowed values in engineering units; a bound may name another register.
    pub range: Option<RangeModel>,
    /// Factory value in engineering units; must lie in the range.
    pub default: Option<f64>,
    /// `read-only`, `read-write` (default) or `write-only`.
    #[serde(default)]
    pub access: Option<Access>,
    /// No persistent (EEPROM) write is generated: the drive refuses the persistent command.
    #[serde(default)]
    pub ram_only: bool,
    /// The drive accepts the persistent (EEPROM) command for this register but keeps the
    /// value in RAM only (lost at power-off), as a manual's own example shows it accepted;
    /// unlike `ram_only`, which refuses it. Not with `ram_only`.
    #[serde(default)]
    pub persistent_write_to_ram: bool,
    /// May be written while the motor runs: `true`, `false` (default) or `unknown` (the
    /// manual's table has no such column).
    #[serde(default)]
    pub writable_while_running: WhileRunning,
    /// Only effective when set from the panel.
    #[serde(default)]
    pub panel_only: bool,
    /// `immediately` (default) or `after_reset`.
    #[serde(default)]
    pub takes_effect: Option<TakesEffect>,
    /// Id of the bit-field word the value is (no unit or scale then).
    pub bitfield: Option<String>,
    /// Id of the code table the value is a code of (no unit or scale then).
    pub code_table: Option<String>,
    /// `word` (default), `double_word`, `bit` or `text`.
    pub data_type: Option<DataType>,
    /// `parameter` (default) or `coil`.
    pub space: Option<Space>,
    /// Number of elements of an array (indexed) parameter.
    pub array: Option<u8>,
    /// The manual section describing the register.
    pub source: String,
    /// Anything the manual says that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// Facts of this register that are inferred rather than stated by the manual:
    /// `[unit, scale, writable_while_running, ...]`; the page marks them.
    #[serde(default)]
    pub inferred: Vec<InferredFact>,
    /// Safety warnings about writing or using this register.
    #[serde(default)]
    pub warnings: Vec<WarningModel>,
    /// Writes to it are never answered (an inverter reset): a master returns once the
    /// frame is sent (its wire time and the frame gap) instead of waiting for a reply, and
    /// the virtual drive stays silent.
    #[serde(default)]
    pub no_reply: bool,
    /// Its own numbers on the wire in some of the drive's protocols (by protocol id), for
    /// reading and for writing, where its command's address map does not give them (the
    /// DV1's 1002h is read as Eaton code 6Dh and written as EDh); a direction left out
    /// cannot be used over that protocol.
    #[serde(default)]
    pub wire_numbers: BTreeMap<String, WireNumberModel>,
    /// Its place on a page, per protocol with pages (`protocols[].pages`), where the manual
    /// gives the register by page and number only (`{ eaton: { page: 1, offset: 0x5F } }`):
    /// without an `address`, the register's number is the one the page ranges lay there;
    /// with one, the two must agree.
    #[serde(default)]
    pub on_page: BTreeMap<String, PagePlaceModel>,
    /// The live register (code or id) whose value this register holds from the moment of
    /// the last trip (`FD00` for FE00): the virtual drive copies it when it trips.
    pub held_at_trip_of: Option<String>,
    /// The register shows the live value but keeps the value it had while the drive is
    /// tripped.
    #[serde(default)]
    pub live_except_while_tripped: bool,
    /// The scale (and range) is chosen by another register's value:
    /// `{ register: FA09, values: [{ value: 0, scale: 0.01 }, { value: 1, scale: 0.1 }] }`.
    /// `scale` and `range` remain the register's when the selector is not known.
    pub scale_by: Option<ScaleByModel>,
    /// Values outside the range that the register also takes, each carried by its own raw
    /// word (`{ value: 99999, raw: 0xFFFF, id: no_check, name: No time-out check }`); a
    /// special value may be the default.
    #[serde(default)]
    pub special_values: Vec<SpecialValueModel>,
}

impl RegisterModel {
    /// Whether `name` is its code, id or one of its aliases (as written).
    pub fn is_named(&self, name: &str) -> bool {
        self.code == name || self.id == name || self.aliases.iter().any(|a| a == name)
    }
}

/// A value a register takes besides its range, with its own raw word.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpecialValueModel {
    /// The value as the manual writes it (`99999`), in the register's engineering terms.
    pub value: f64,
    /// The raw word carrying it (`0xFFFF`).
    pub raw: u32,
    /// Lower snake case name of the value.
    pub id: String,
    /// What it means, in English.
    pub name: String,
    /// What it means, as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
}

/// A reference word that is a percentage of a span chosen by a selector register.
#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReferenceScalingModel {
    /// The manual section describing the scaling.
    pub source: String,
    /// The raw value meaning 100 %.
    pub full_scale_raw: u32,
    /// Ids of the registers scaled this way.
    pub applies_to: Vec<String>,
    /// Id of the register choosing the mode.
    pub selector: String,
    /// Anything the manual says about the scaling that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// The spans, one per selector value: value = percent x (high - low).
    pub modes: Vec<ScalingModeModel>,
}

#[derive(Debug, Clone, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScalingModeModel {
    /// The selector register's value choosing this mode.
    pub selector: u32,
    /// The span's low end: a number or a register id.
    pub low: BoundModel,
    /// The span's high end: a number or a register id.
    pub high: BoundModel,
    /// What the mode means.
    pub description: String,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ValueExampleModel {
    /// Code or id of the register.
    pub register: String,
    /// The engineering value; it must round to `raw`.
    pub value: f64,
    /// The raw word on the wire.
    pub raw: u32,
    /// The manual section giving the example.
    pub source: String,
    /// What the manual says.
    pub description: String,
    /// The values of other registers the example assumes, by code or id (`{ FA09: 0 }`
    /// for a register whose `scale_by` names FA09).
    #[serde(default)]
    pub given: BTreeMap<String, u32>,
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

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExampleModel {
    /// Unique lower snake case name; it names the golden test.
    pub id: String,
    /// A protocol id of this drive (`protocols[].id`).
    pub protocol: String,
    /// The protocol file's variant the frames are in (`cr_lf`: the terminator is CR LF);
    /// left out: the first variant, the one the layouts are written in.
    pub variant: Option<String>,
    /// On a protocol with pages (`protocols[].pages`), the page the drive is on for these
    /// frames: the request's register field is an offset on it, and `expect.register`
    /// names the register it reaches there (checked); the virtual drive is put on the page
    /// before the example is played to it.
    pub page: Option<u16>,
    /// The manual section with the frame.
    pub source: String,
    /// What the exchange does, in English.
    pub description: String,
    /// What the exchange does, as the manual says it in Chinese.
    #[serde(default)]
    pub description_zh: String,
    /// The request frame, if the manual gives one.
    pub request: Option<FrameModel>,
    /// The reply frame, if the manual gives one.
    pub reply: Option<FrameModel>,
    /// The manual prints the request and says nothing comes back (a broadcast no station
    /// answers, a command never answered): the example gives no `reply`, and `vfd check`
    /// plays the request to the virtual drive, which must stay silent.
    #[serde(default)]
    pub no_reply: bool,
    /// A request the manual prints as one the drive does not answer (a format error): the
    /// decoder refuses it and the virtual drive stays silent.
    pub unanswered_request: Option<UnansweredModel>,
    /// The data word's value in the register's engineering unit.
    pub value: Option<f64>,
    /// The drive settings the frames assume, where the frames depend on more than their
    /// bytes (a block transfer's selectors): register (code or id) -> value, in the
    /// register's unit (a code for code tables), as `default` is written; the virtual drive
    /// built from the description holds them as set before power-on when `vfd check` plays
    /// the example to it.
    #[serde(default)]
    pub settings: BTreeMap<String, f64>,
    /// Why the virtual drive built from this description cannot give the example's reply
    /// to its request (a state its behaviour model does not reach, such as a trip). Without
    /// it, `vfd check` plays the request to the virtual drive, under `settings`, and requires
    /// the example's reply byte for byte.
    pub not_simulated: Option<String>,
}

/// A register's place on a page of one protocol (`registers[].on_page`).
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PagePlaceModel {
    /// The page.
    pub page: u16,
    /// Its number on the page, before the command's address map (the read code: P.195 is
    /// 5Fh on page 1).
    pub offset: u16,
}

/// A register's own numbers on the wire in one protocol (`registers[].wire_numbers`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WireNumberModel {
    /// Its number in read requests.
    pub read: Option<u32>,
    /// Its number in write requests.
    pub write: Option<u32>,
}

/// A request the drive does not answer, as the manual prints it.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UnansweredModel {
    /// The frame as text (text protocols).
    pub ascii: Option<String>,
    /// The frame as hex byte pairs (binary protocols).
    pub hex: Option<String>,
    /// The decoder's reason for refusing it.
    pub rejected_as: DecodeErrorKind,
    /// Why the drive does not answer it, as the manual says.
    pub reason: String,
}

/// Frame bytes, written as text (`ascii`) or as hex pairs (`hex`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BytesModel {
    /// The frame as text (text protocols); `\r` and other escapes as in YAML double quotes.
    pub ascii: Option<String>,
    /// The frame as hex byte pairs separated by spaces (binary protocols).
    pub hex: Option<String>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FrameModel {
    /// The corrected frame as text (text protocols).
    pub ascii: Option<String>,
    /// The corrected frame as hex byte pairs (binary protocols).
    pub hex: Option<String>,
    /// What the frame must decode to.
    pub expect: ExpectModel,
    /// What the manual prints, when it differs from the bytes above (an erratum).
    pub printed: Option<BytesModel>,
    /// Why the printed bytes are wrong; required with `printed`.
    pub erratum: Option<String>,
    /// The decoder's reason for refusing the printed bytes, or, for a printed frame that
    /// is valid on its own, why it is still wrong (`does_not_answer_request`,
    /// `contradicts_expect`).
    pub printed_rejected_as: Option<PrintedRejection>,
}

/// A multi-step example (`sequences[]`): one call of the master, and every frame on the
/// line it makes, in order.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SequenceModel {
    /// Identifier (snake case; names the generated test).
    pub id: String,
    /// Id of the protocol (within this drive file).
    pub protocol: String,
    /// The protocol file's variant the frames are in (`cr_lf`); left out: the first.
    pub variant: Option<String>,
    /// The value of the reply-wait field in the master's requests (the wait digit of the
    /// computer-link family, tens of milliseconds: `3` asks for 30 ms), as the frames
    /// print it; the test's master asks for that wait (`Master::with_reply_wait`).
    /// Left out: 0.
    pub reply_wait: Option<u8>,
    /// The manual section (and lines) the steps come from.
    pub source: String,
    /// What the sequence does, in the manual's words.
    pub description: String,
    /// The manual's Chinese words.
    #[serde(default)]
    pub description_zh: String,
    /// The station the manual's frames address.
    pub address: Option<u8>,
    /// The one call: `{ read: 02-15 }`, `{ write: 02-15, value: 50.0 }` (through the typed
    /// API, range checked) or `{ write: 02-15, raw: 0xC350 }` (sent as given).
    pub call: SequenceCallModel,
    /// What the master is told before the call, by register code or id: the raw value of
    /// the drive's persistence selector (`{ 07-11: 0 }`: the factory setting, so a
    /// persistent write goes out alone).
    #[serde(default)]
    pub given: BTreeMap<String, u32>,
    /// What the call returns: `{ value: 60.0 }`, `{ written: true }` or `{ error: ID }` (an
    /// error code's id, the drive's or the protocol's).
    pub result: SequenceResultModel,
    /// The frames on the line, in order.
    pub steps: Vec<SequenceStepModel>,
}

/// The call a sequence makes.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SequenceCallModel {
    /// Code or id of the register read.
    pub read: Option<String>,
    /// Code or id of the register written (RAM).
    pub write: Option<String>,
    /// The value written, in the register's unit.
    pub value: Option<f64>,
    /// The raw word written, without a range check (to show a refusal).
    pub raw: Option<u32>,
    /// The write goes to RAM and EEPROM (`write_persistent`); default false (RAM).
    #[serde(default)]
    pub persistent: bool,
}

/// What a sequence's call returns.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SequenceResultModel {
    /// The value read, in the register's unit.
    pub value: Option<f64>,
    /// The write succeeded.
    #[serde(default)]
    pub written: bool,
    /// The id of the error code the drive answers with.
    pub error: Option<String>,
}

/// Who sends a sequence's frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Sender {
    /// The master (a request, a page switch, a follow-up).
    Master,
    /// The drive (a reply).
    Drive,
}

/// How the manual shows a sequence's frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Shown {
    /// Printed byte for byte.
    #[default]
    Printed,
    /// Left out by the manual as the same as an earlier example's ("略").
    Elided,
    /// Not printed: it follows from the manual's format tables.
    Derived,
}

/// One frame of a sequence.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SequenceStepModel {
    /// `master` or `drive`.
    pub from: Sender,
    /// The frame as text.
    pub ascii: Option<String>,
    /// The frame as hex byte pairs.
    pub hex: Option<String>,
    /// `printed` (default), `elided` or `derived`.
    #[serde(default)]
    pub shown: Shown,
    /// What the step is, for people (`page switch`, `the master's C`).
    #[serde(default)]
    pub note: String,
}

/// Why the bytes a manual prints for a frame are wrong, as the library shows it: the
/// decoder refuses them (a [`DecodeErrorKind`]), or they decode but are wrong in their
/// exchange.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PrintedRejection {
    /// A byte where the layout has a fixed one.
    UnexpectedByte,
    /// A value the layout does not allow.
    NotAllowed,
    /// The checksum does not match the bytes.
    ChecksumMismatch,
    /// A length field disagrees with the frame.
    LengthMismatch,
    /// The frame ends early.
    Truncated,
    /// Bytes follow the frame.
    TrailingBytes,
    /// A reply that decodes, but carries another station, register, index or written value
    /// than its request: the master passes it over as the answer to something else.
    DoesNotAnswerRequest,
    /// A frame that decodes, but to something other than `expect` (the manual's stated
    /// meaning): a letter case that contradicts the stated state, for example.
    ContradictsExpect,
}

impl PrintedRejection {
    /// The name written in drive files.
    pub fn as_str(self) -> &'static str {
        match self.decode_kind() {
            Some(kind) => kind.as_str(),
            None if self == PrintedRejection::DoesNotAnswerRequest => "does_not_answer_request",
            None => "contradicts_expect",
        }
    }

    /// The decoder's error kind, for a rejection the decoder itself makes.
    pub fn decode_kind(self) -> Option<DecodeErrorKind> {
        Some(match self {
            PrintedRejection::UnexpectedByte => DecodeErrorKind::UnexpectedByte,
            PrintedRejection::NotAllowed => DecodeErrorKind::NotAllowed,
            PrintedRejection::ChecksumMismatch => DecodeErrorKind::ChecksumMismatch,
            PrintedRejection::LengthMismatch => DecodeErrorKind::LengthMismatch,
            PrintedRejection::Truncated => DecodeErrorKind::Truncated,
            PrintedRejection::TrailingBytes => DecodeErrorKind::TrailingBytes,
            PrintedRejection::DoesNotAnswerRequest | PrintedRejection::ContradictsExpect => {
                return None
            }
        })
    }
}

#[derive(Debug, Clone, Default, Deserialize, PartialEq, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExpectModel {
    /// Station number.
    pub address: Option<u8>,
    /// The stations a broadcast request addresses: `all`, or a group written with `*` for
    /// each open digit (`"*9"`, `"1*"`).
    pub broadcast: Option<String>,
    /// The command code: a letter (`R`) or a number (`0x03`).
    pub command: Option<CodeModel>,
    /// Register number as the drive file numbers it (before the protocol's address map).
    pub register: Option<u32>,
    /// Register number on the wire, for frames addressing no described register (the FC
    /// Modbus index register 0008h).
    pub wire_register: Option<u32>,
    /// Array index (indexed parameters).
    pub index: Option<u32>,
    /// The data word, raw.
    pub data: Option<u32>,
    /// The code of an error reply.
    pub error_code: Option<u32>,
    /// Process words (control word and reference, or status word and output value).
    pub process: Option<[u32; 2]>,
    /// Text carried by the frame.
    pub text: Option<String>,
    /// The words of a block transfer (written by the request, read by the reply).
    pub words: Option<Vec<u32>>,
    /// How many words a block-transfer request asks back.
    pub read_count: Option<u32>,
    /// A block-transfer reply's write status.
    pub write_status: Option<u32>,
    /// A request's reply-wait field (the wait digit of the computer-link family: tens of
    /// milliseconds before the drive answers), as printed; the golden test encodes with it.
    /// Left out: not checked, and the frame's digit is used.
    pub reply_wait: Option<u32>,
    /// The reply says the drive has tripped.
    #[serde(default)]
    pub tripped: bool,
}

/// A shared protocol file (`drives/protocols/<id>.yaml`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProtocolFile {
    /// Who the protocol is and its frame-wide settings.
    pub protocol: ProtocolMeta,
    /// Reusable frame parts by name; layouts list them.
    #[serde(default)]
    pub parts: BTreeMap<String, PartModel>,
    /// Another protocol file whose parts, layouts, commands, error reply and error codes
    /// this one takes, with the changes said here (Modbus ASCII: Modbus RTU's frames with
    /// another start, checksum and end). What this file gives itself replaces the base's.
    pub based_on: Option<BasedOnModel>,
    /// Frame layouts by name: the parts of a frame in order, each the name of a part or a part written in place.
    /// Required unless the file is `based_on` another.
    #[serde(default)]
    pub layouts: BTreeMap<String, Vec<PartRefModel>>,
    /// The commands: which layouts a request and its reply use. Required unless the file
    /// is `based_on` another.
    #[serde(default)]
    pub commands: Vec<CommandModel>,
    /// Name of the layout of an error reply.
    pub error_reply: Option<String>,
    /// The codes the protocol's error replies carry, as the protocol itself defines them
    /// (Modbus exception codes): used for a drive whose own `error_codes` do not apply to
    /// this protocol.
    pub error_codes: Option<ProtocolErrorCodesModel>,
    /// Variants of the protocol: other bytes for some literal parts (a terminator that is
    /// CR or CR LF as a drive setting chooses). The first is the protocol as its `parts`
    /// are written; a drive's `protocols[].variant` says which register selects one.
    #[serde(default)]
    pub variants: Vec<VariantModel>,
}

/// A variant of a protocol (`variants[]`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VariantModel {
    /// Lower snake case identifier (`cr_lf`): the value id that selects it in a drive's
    /// code table, and the name masters and tools are told (`--variant cr_lf`).
    pub id: String,
    /// The variant's name in English.
    pub name: String,
    /// The variant's name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// Shared literal parts (keys under `parts:`) with other bytes in this variant, each
    /// `{ literal: ... }` or `{ literal_hex: ... }`; none in the first variant.
    #[serde(default)]
    pub literals: BTreeMap<String, VariantLiteralModel>,
}

/// The bytes of a literal part in a variant: exactly one of the keys.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VariantLiteralModel {
    /// The bytes, as text.
    pub literal: Option<String>,
    /// The bytes, as hex pairs.
    pub literal_hex: Option<String>,
}

/// A protocol file built on another (`based_on:`): the base's layouts, each changed the
/// same way.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BasedOnModel {
    /// The base protocol file's id (its file name without `.yaml`), in the same folder. A
    /// base may not itself be based on another.
    pub protocol: String,
    /// Parts put before the first part of every layout of the base (a start literal).
    #[serde(default)]
    pub prepend: Vec<String>,
    /// Parts put after the last part of every layout of the base (an end literal).
    #[serde(default)]
    pub append: Vec<String>,
    /// Parts of the base's layouts replaced, wherever a layout names them: base part name
    /// -> the name of the part used instead (`{ crc: lrc }`).
    #[serde(default)]
    pub replace: BTreeMap<String, String>,
}

/// A protocol's own error codes.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProtocolErrorCodesModel {
    /// Where the codes are defined (a specification, or the manuals that print them).
    pub source: String,
    /// How the manual or specification prints the codes (`{ digits: 2 }`: 01); left out:
    /// two hex digits and `h` (01h).
    pub notation: Option<CodeNotationModel>,
    /// The codes an error reply may carry.
    pub codes: Vec<ErrorCodeModel>,
}

/// How a manual prints a table's codes: in hex (`H0C`, `000Ch`, `01`) or decimal (`17`),
/// at least `digits` digits, between a prefix and a suffix.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CodeNotationModel {
    /// `hex` (the default) or `decimal`.
    #[serde(default)]
    pub base: CodeBase,
    /// The fewest digits printed (leading zeros); default 1.
    #[serde(default = "one")]
    pub digits: u8,
    /// Text before the digits (`H` for H0C).
    #[serde(default)]
    pub prefix: String,
    /// Text after the digits (`h` for 000Ch).
    #[serde(default)]
    pub suffix: String,
}

impl CodeNotationModel {
    /// `code` as the manual prints it.
    pub fn print(&self, code: u32) -> String {
        let width = usize::from(self.digits);
        let digits = match self.base {
            CodeBase::Hex => format!("{code:0width$X}"),
            CodeBase::Decimal => format!("{code:0width$}"),
        };
        format!("{}{digits}{}", self.prefix, self.suffix)
    }
}

/// The base a manual prints codes in.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum CodeBase {
    /// Hexadecimal digits, upper case.
    #[default]
    Hex,
    /// Decimal digits.
    Decimal,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProtocolMeta {
    /// The file's name without `.yaml`; drive files name it in `protocols[].uses`.
    pub id: String,
    /// The protocol's name in English.
    pub name: String,
    /// The protocol's name as the manuals print it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// Prose for the reference pages.
    #[serde(default)]
    pub description: String,
    /// Frames are printable text.
    pub text: bool,
    /// The longest frame in bytes: sizes buffers and reply timeouts.
    pub max_frame_len: u16,
    /// A reply with a lower-case command letter says the drive has tripped.
    #[serde(default)]
    pub lowercase_means_tripped: bool,
    /// Optional parts included in the requests the library builds.
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
    /// How frames go on the wire: `binary` (the default: as the parts give them) or
    /// `hex_pairs` (Modbus ASCII: a literal first and last part as they are, every byte in
    /// between as two hex digits; lengths and checksums over the bytes, not the digits).
    #[serde(default)]
    pub encoding: Encoding,
    /// The most 16-bit registers one read request may carry (Modbus 03: 125), when the
    /// protocol's read command counts its data (a length part with `counts: data_size`);
    /// left out: 1, one register per read.
    pub max_words_per_read: Option<u16>,
    /// The most 16-bit registers one write request may carry (Modbus 10h: 123), when a
    /// RAM write command's data field is sized by a length part; left out: 1, one register
    /// (of its own width) per write.
    pub max_words_per_write: Option<u16>,
}

/// The suffix of a struct name asking the reader for "a mapping with these keys, or a
/// scalar": a scalar goes to the visitor as itself, a mapping is checked key by key (unknown
/// keys reported and skipped, missing required keys reported) before the visitor sees it.
pub const OR_SCALAR: &str = "|or_scalar";

/// `"Name|or_scalar"`, as a `&'static str`.
macro_rules! const_str_or_scalar {
    ($name:literal) => {
        concat!($name, "|or_scalar")
    };
}

/// The keys of [`PartModel`], for the reader (checked against the schema in a test).
pub const PART_FIELDS: &[&str] = &[
    "literal",
    "literal_hex",
    "field",
    "checksum",
    "word",
    "length",
    "name",
    "format",
    "width",
    "min_width",
    "size",
    "optional",
    "allowed",
    "fold_case",
    "marker",
    "covers_from",
    "covers_through",
    "fields",
    "counts",
    "times",
    "per",
    "broadcast",
];

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
        // Asked for as a struct that may also be a scalar (see `OR_SCALAR`), so that the
        // reader checks the keys of a part written in place as it does any struct's.
        deserializer.deserialize_struct(
            const_str_or_scalar!("PartModel"),
            PART_FIELDS,
            EntryVisitor,
        )
    }
}

impl JsonSchema for PartRefModel {
    fn schema_name() -> Cow<'static, str> {
        "PartRefModel".into()
    }

    /// As the hand-written `Deserialize` reads it: a string or a part.
    fn json_schema(generator: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "The name of a part under `parts`, or a part written in place as `{ ... }`.",
            "oneOf": [
                { "type": "string", "description": "The name of a part under `parts`." },
                generator.subschema_for::<PartModel>(),
            ],
        })
    }
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PartModel {
    /// Fixed bytes, as text; the first literal of a layout is its start sequence.
    pub literal: Option<String>,
    /// Fixed bytes, as hex pairs.
    pub literal_hex: Option<String>,
    /// A value field: its role.
    pub field: Option<Role>,
    /// A checksum: its algorithm.
    pub checksum: Option<ChecksumAlgorithm>,
    /// A word made of bit fields: its format (`u16be`).
    pub word: Option<Format>,
    /// A computed length: its format (`u8`).
    pub length: Option<Format>,
    /// Name for error messages and docs (defaults to the role or the part's key).
    pub name: Option<String>,
    /// How the value is written on the wire.
    pub format: Option<Format>,
    /// Digit formats: the number of digits encoded; byte formats: the number of bytes.
    pub width: Option<u8>,
    /// Digit formats: the fewest digits accepted on decode.
    pub min_width: Option<u8>,
    /// `rest` (up to the fixed parts before the frame end) or `length` (a length part covers
    /// it); left out, the format sizes the field.
    pub size: Option<SizedBy>,
    /// Whether the part may be left out, and how a decoder tells it is there.
    pub optional: Option<OptionalModel>,
    /// Values accepted on decode (letters or numbers).
    #[serde(default)]
    pub allowed: Vec<CodeModel>,
    /// Accept lower case too on decode.
    #[serde(default)]
    pub fold_case: bool,
    /// Bytes announcing an optional checksum; the checksum covers them.
    pub marker: Option<String>,
    /// Name of the first part a checksum covers.
    pub covers_from: Option<String>,
    /// Name of the last part a checksum covers, where it stops before the checksum (an ETX
    /// in between is left out); left out: up to the checksum.
    pub covers_through: Option<String>,
    /// Bit fields of a `word`.
    #[serde(default)]
    pub fields: Vec<BitsModel>,
    /// What a `length` counts.
    pub counts: Option<CountsModel>,
    /// A length: the count is multiplied by this.
    pub times: Option<u8>,
    /// A length: the count is divided by this.
    pub per: Option<u8>,
    /// A station address field: how one frame addresses every station, or a group
    /// (`{ literal: "**", wildcard: "*" }`, `{ value: 0xFF }`, Modbus `{ value: 0 }`).
    pub broadcast: Option<BroadcastAddressModel>,
}

/// The broadcast encodings of a station address part.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BroadcastAddressModel {
    /// Text written instead of the station number to address every station (`"**"`).
    pub literal: Option<String>,
    /// The station value that addresses every station (`0xFF`; Modbus `0`).
    pub value: Option<u32>,
    /// One character that stands for any digit of a digit-format station number: group
    /// addressing (`"*"`: `*9` is every station whose last digit is 9, `1*` every station
    /// whose first digit is 1).
    pub wildcard: Option<String>,
}

/// A command code or allowed value: one character (`R`) or a number (`0x03`).
#[derive(Debug, Clone, Deserialize, PartialEq, JsonSchema)]
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

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BitsModel {
    /// The value's role for the transaction engine.
    pub field: Role,
    /// Name for error messages and docs (defaults to the role).
    pub name: Option<String>,
    /// `"msb:lsb"` or a single bit number.
    pub bits: String,
    /// Values accepted on decode.
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
        deserializer.deserialize_struct(
            const_str_or_scalar!("Parts"),
            &["from", "through"],
            CountsVisitor,
        )
    }
}

impl JsonSchema for CountsModel {
    fn schema_name() -> Cow<'static, str> {
        "CountsModel".into()
    }

    /// As the hand-written `Deserialize` reads it.
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "What a length counts: `{ from: part, through: part }` or `data_size`.",
            "oneOf": [
                { "const": "data_size", "description": "The bytes of the data the frame carries." },
                {
                    "type": "object",
                    "description": "The bytes from one part through another, both included.",
                    "properties": {
                        "from": { "type": "string", "description": "Name of the first part counted." },
                        "through": { "type": "string", "description": "Name of the last part counted." },
                    },
                    "required": ["from", "through"],
                    "additionalProperties": false,
                },
            ],
        })
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
        deserializer.deserialize_struct(
            const_str_or_scalar!("ByteAtMost"),
            &["if_byte_at_most"],
            OptionalVisitor,
        )
    }
}

impl JsonSchema for OptionalModel {
    fn schema_name() -> Cow<'static, str> {
        "OptionalModel".into()
    }

    /// As the hand-written `Deserialize` reads it.
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "Whether a part may be left out: `true`/`false`, or for fields a presence rule (`if_format_matches`, `{ if_byte_at_most: 0x3F }`).",
            "oneOf": [
                { "type": "boolean", "description": "Always there (`false`) or perhaps left out (`true`)." },
                { "const": "if_format_matches", "description": "There when the bytes at its place match its format." },
                {
                    "type": "object",
                    "description": "There when the byte at its place is at most this value.",
                    "properties": {
                        "if_byte_at_most": { "type": "integer", "minimum": 0, "maximum": 255 },
                    },
                    "required": ["if_byte_at_most"],
                    "additionalProperties": false,
                },
            ],
        })
    }
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CommandModel {
    /// The code on the wire; absent for layouts without a command field.
    pub code: Option<CodeModel>,
    /// What the command does: `read`, `write_ram`, `write_persistent`, `read_text` or `process`.
    pub kind: CommandKind,
    /// Name of the request's layout.
    pub request: String,
    /// Name of the normal reply's layout, or `none` for a command that is never answered
    /// (a master returns once the frame is sent; the virtual drive stays silent).
    pub reply: String,
    /// An extra command (default false): a drive gets it only by listing its code in
    /// `protocols[].commands`, and a request uses it only by naming its code (a second read
    /// command that some drives have).
    #[serde(default)]
    pub extra: bool,
    /// What a lower-case code means for this command: `sender_tripped` (a request whose
    /// letter is lower case says its sender, a master inverter, has tripped). Left out: as
    /// the protocol's `lowercase_means_tripped` says of replies.
    pub lowercase_means: Option<LowercaseMeans>,
    /// Data types carried (`word`, `double_word`, `bit`, `text`); empty: any.
    #[serde(default)]
    pub data_types: Vec<DataType>,
    /// `parameter` (default) or `coil`.
    pub space: Option<Space>,
    /// How register numbers become wire addresses (a default a drive file may override).
    pub address_map: Option<AddressMapModel>,
    /// Codes a normal reply may carry; empty: the request's code.
    #[serde(default)]
    pub reply_codes: Vec<CodeModel>,
    /// The code an error reply to this command carries, where the `error_reply` layout
    /// allows several (a Modbus exception to function 0x03 carries 0x83); left out: the one
    /// code the error layout allows.
    pub error_code: Option<CodeModel>,
    /// `by_instruction`: a plain write (`kind: write_ram`) whose storage is the
    /// instruction's, that is the register's: the protocol writes RAM and EEPROM with
    /// instructions of their own (a frequency written to RAM with one code and to EEPROM
    /// with another), so a RAM-only register's write goes to RAM and any other's to RAM
    /// and EEPROM. Said once here, not per register. Left out: the kind's storage.
    pub storage: Option<WriteStorage>,
    /// What the master sends after this command's reply: `{ ok: LAYOUT, again: LAYOUT }`,
    /// the acknowledgement of a sound reply and the request to send a garbled one again
    /// (Eaton: C and F after a read's E). Neither is answered by a frame of its own.
    pub follow_up: Option<FollowUpModel>,
    /// Notes for people reading the protocol file; nothing is generated from them.
    #[serde(default)]
    #[allow(dead_code)]
    pub description: String,
}

/// Where a write command's writes go (`commands[].storage`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum WriteStorage {
    /// Where the instruction (the register it addresses) stores: RAM for a RAM-only
    /// register, RAM and EEPROM for any other.
    ByInstruction,
}

/// The master's answer to a command's reply (`commands[].follow_up`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FollowUpModel {
    /// The layout sent after a sound reply (the drive does nothing more).
    pub ok: String,
    /// The layout sent after a garbled reply: the drive sends the same reply again.
    pub again: String,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AddressMapModel {
    /// Wire address = number x multiply + offset: the factor.
    pub multiply: u16,
    /// Wire address = number x multiply + offset: the offset.
    pub offset: i32,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PreStepModel {
    /// What the step does: `index` or `persistence`.
    pub step: PreStepKind,
    /// The register the step writes.
    pub register: u16,
    /// `parameter` (default) or `coil`.
    pub space: Option<Space>,
    /// `word` (default), `double_word`, `bit` or `text`.
    pub data_type: Option<DataType>,
    /// Persistence: the value selecting RAM-only writes.
    pub ram: Option<u32>,
    /// Persistence: the value selecting RAM + EEPROM writes.
    pub persistent: Option<u32>,
    /// Notes for people reading the protocol file; nothing is generated from them.
    #[serde(default)]
    #[allow(dead_code)]
    pub description: String,
}

/// What a lower-case command letter means for one command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum LowercaseMeans {
    /// A request with the lower-case letter says its sender has tripped.
    SenderTripped,
}

/// What a pre-step does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PreStepKind {
    /// Write the array index of an indexed parameter.
    Index,
    /// Switch between writing RAM only and RAM + EEPROM.
    Persistence,
}

#[cfg(test)]
mod part_fields_tests {
    use super::{PartModel, PART_FIELDS};

    #[test]
    fn the_reader_knows_every_key_of_a_part() {
        let schema = schemars::SchemaGenerator::default().into_root_schema_for::<PartModel>();
        let value = schema.to_value();
        let mut keys: Vec<&str> = value["properties"]
            .as_object()
            .expect("properties")
            .keys()
            .map(String::as_str)
            .collect();
        let mut listed = PART_FIELDS.to_vec();
        keys.sort_unstable();
        listed.sort_unstable();
        assert_eq!(keys, listed, "PART_FIELDS must list PartModel's keys");
    }
}
